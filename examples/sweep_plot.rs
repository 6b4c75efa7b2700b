//! A frequency sweep with a plot: the fractional Duffing oscillator through its folds,
//! written as CSV, JSON and an SVG figure (stable solid, unstable dashed, folds and
//! jumps marked).
//!
//! ```sh
//! cargo run --release --example sweep_plot -- out/sweep
//! ```

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::FractionalDuffing;
use ihbm::report::plot::{figure_svg, Figure, Panel, Series};
use ihbm::report::{csv::curve_csv, json::sweep_json, write_file, FreqUnit};
use std::path::Path;

/// Trace the curve and write `sweep.csv`, `sweep.json` and `sweep.svg` into `dir`.
/// Returns the fold frequencies.
pub fn run(dir: &Path) -> Result<Vec<f64>, ihbm::Error> {
    let model = FractionalDuffing::default(); // m x'' + c x' + k x + k3 x^3 + h D^0.5 x = F cos Ωt
    let curve = sweep(&model, 0.5, 3.0, &SweepOptions::default())?;
    std::fs::create_dir_all(dir)
        .map_err(|source| ihbm::Error::Io { path: dir.display().to_string(), source })?;
    write_file(&dir.join("sweep.csv"), &curve_csv(&curve))?;
    write_file(&dir.join("sweep.json"), &sweep_json(&curve).to_string())?;
    let figure = Figure {
        title: "Fractional Duffing, h = 0.1, p = 0.5".into(),
        unit: FreqUnit::RadPerSec,
        panels: vec![Panel { output: "x".into(), label: "max|x| (m)".into() }],
        series: vec![Series { label: "F = 0.5 N".into(), curve: &curve }],
        markers: vec![],
    };
    write_file(&dir.join("sweep.svg"), &figure_svg(&figure)?)?;
    for jump in &curve.jumps {
        println!(
            "slow sweep {:?}: jump at Ω = {:.6} from {:.4} to {:.4}",
            jump.direction, jump.at, jump.from, jump.to
        );
    }
    Ok(curve.folds.iter().map(|f| f.omega).collect())
}

#[allow(dead_code)]
fn main() -> Result<(), ihbm::Error> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "out/sweep".into());
    let folds = run(Path::new(&dir))?;
    println!("folds at Ω = {folds:.6?}; files in {dir}/");
    Ok(())
}
