//! Harmonic balance against time integration from rest at a few frequencies: the
//! reference paper's Fig. 6 check, made quantitative.
//!
//! The quarter car with a strong cubic spring (k3 = 5e6 N/m^3, F = 2 cm). For each Ω,
//! `max_abs` of the harmonic-balance solution (N = 9) is compared with the steady
//! `max_abs` over the last 10 periods of a run from rest, with the paper's first-order
//! Grünwald–Letnikov rule at its step T/200 and with the second-order rule at T/400.
//!
//! Run: `cargo run --release --example compare_td`

use ihbm::corrector::SolveOptions;
use ihbm::models::QuarterCar;
use ihbm::timedomain::{compare, Scheme, SimOptions};
use std::f64::consts::TAU;

fn main() -> Result<(), ihbm::Error> {
    run()
}

/// Print the comparison table.
pub fn run() -> Result<(), ihbm::Error> {
    let car = QuarterCar { k3: 5e6, F: 0.02, ..Default::default() };
    let omegas = [4.0, 8.0, 12.0, 24.0, 60.0];
    let hb = SolveOptions { harmonics: 9, tol: 1e-12, ..Default::default() };
    println!("quarter car, k3 = {} N/m^3, F = {} m; HB with N = {}", car.k3, car.F, hb.harmonics);
    println!(
        "{:>6} {:>4} {:>14} {:>14} {:>10} {:>14} {:>10}",
        "Ω", "out", "HB max|x|", "GL T/200", "rel", "BDF2 T/400", "rel"
    );
    for &omega in &omegas {
        // At least 20 s and 40 periods, so that the transient from rest has decayed.
        let periods = ((20.0 * omega / TAU).ceil() as usize).max(40);
        let gl = SimOptions {
            scheme: Scheme::Gl,
            dt: Some(TAU / omega / 200.0),
            periods,
            ..Default::default()
        };
        let bdf2 = SimOptions {
            scheme: Scheme::Bdf2,
            dt: Some(TAU / omega / 400.0),
            periods,
            ..Default::default()
        };
        let a = compare(&car, &[omega], &gl, &hb)?.remove(0);
        let b = compare(&car, &[omega], &bdf2, &hb)?.remove(0);
        if let Some(why) = a.failure.as_ref().or(b.failure.as_ref()) {
            println!("{omega:6.1}: {why}");
            continue;
        }
        for (x, y) in a.outputs.iter().zip(&b.outputs) {
            println!(
                "{omega:6.1} {:>4} {:14.8e} {:14.8e} {:10.2e} {:14.8e} {:10.2e}",
                x.name, x.hb_max_abs, x.td_max_abs, x.rel_diff, y.td_max_abs, y.rel_diff
            );
        }
    }
    Ok(())
}
