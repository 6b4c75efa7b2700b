//! ihbm's side of the peer comparison (`benches/peers/run.sh`): the Duffing frequency
//! sweep `x'' + c x' + k x + k3 x^3 = F cos Ωt` with the `duffing` defaults, timed.
//!
//! ```text
//! cargo run --release --example peer_duffing -- [--harmonics 5] [--from 0.5] [--to 3.0] [--repeats 20]
//! ```
//!
//! Runs the sweep `repeats` times in two configurations and prints one JSON line each:
//! `"ihbm"` without stability (the work the Python peers do: points of the curve, no
//! Floquet/Hill analysis) and `"ihbm+stability"` with Hill's method at every point (the
//! default of `ihbm sweep`). `seconds_per_curve` is the median wall time of one whole
//! curve (`continuation::sweep`: continuation, fold location and jumps; not process
//! start), `best_seconds_per_curve` the fastest of the repeats.
//! The line also carries the point count, the peak amplitudes and the folds, so the
//! script can check that every tool computed the same curve.

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::fourier::sample_count;
use ihbm::models::Duffing;
use ihbm::results::Curve;
use ihbm::Model;
use std::time::Instant;

/// Command-line settings.
struct Args {
    harmonics: usize,
    from: f64,
    to: f64,
    repeats: usize,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args { harmonics: 5, from: 0.5, to: 3.0, repeats: 20 };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let bad = |what: &str| format!("{flag} {value:?}: expected {what}");
        match flag.as_str() {
            "--harmonics" => args.harmonics = value.parse().map_err(|_| bad("a count >= 1"))?,
            "--from" => args.from = value.parse().map_err(|_| bad("a frequency in rad/s"))?,
            "--to" => args.to = value.parse().map_err(|_| bad("a frequency in rad/s"))?,
            "--repeats" => args.repeats = value.parse().map_err(|_| bad("a count >= 1"))?,
            _ => {
                return Err(format!(
                    "unknown option {flag:?} (use --harmonics, --from, --to, --repeats)"
                ))
            }
        }
    }
    if args.harmonics == 0 || args.repeats == 0 {
        return Err("--harmonics and --repeats must be at least 1".into());
    }
    Ok(args)
}

/// Times `repeats` sweeps; returns the last curve and the median and the best seconds
/// per curve.
fn timed(model: &Duffing, args: &Args, opts: &SweepOptions) -> ihbm::Result<(Curve, f64, f64)> {
    let mut times = Vec::with_capacity(args.repeats);
    let mut curve = sweep(model, args.from, args.to, opts)?; // warm-up (page faults, caches)
    for _ in 0..args.repeats {
        let start = Instant::now();
        curve = sweep(model, args.from, args.to, opts)?;
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok((curve, times[times.len() / 2], times[0]))
}

fn json_line(tool: &str, args: &Args, samples: usize, curve: &Curve, times: (f64, f64)) -> String {
    let peak = |f: fn(&ihbm::results::PointOutput) -> f64| {
        curve.points.iter().map(|p| f(&p.outputs[0])).fold(0.0, f64::max)
    };
    let folds: Vec<String> = curve.folds.iter().map(|f| format!("{:.6}", f.omega)).collect();
    let ends: Vec<String> = curve.segments.iter().map(|s| format!("\"{}\"", s.ended)).collect();
    format!(
        "{{\"tool\":\"{tool}\",\"version\":\"{}\",\"harmonics\":{},\"samples\":{samples},\
         \"from\":{},\"to\":{},\"points\":{},\"steps\":{},\"newton_iterations\":{},\"chord_steps\":{},\
         \"seconds_per_curve\":{:.9e},\"best_seconds_per_curve\":{:.9e},\"repeats\":{},\"peak_max_abs\":{:.6},\
         \"peak_amp1\":{:.6},\"folds\":[{}],\"segments\":[{}]}}",
        env!("CARGO_PKG_VERSION"),
        args.harmonics,
        args.from,
        args.to,
        curve.points.len(),
        curve.stats.steps,
        curve.stats.corrector_iterations,
        curve.stats.chord_steps,
        times.0,
        times.1,
        args.repeats,
        peak(|o| o.max_abs),
        peak(|o| o.amp1),
        folds.join(","),
        ends.join(","),
    )
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let model = Duffing::default(); // m = 1, c = 0.1, k = 1, k3 = 1, F = 0.5
    let samples = sample_count(model.degree(), args.harmonics, model.max_forcing_harmonic());
    let plain = SweepOptions { harmonics: args.harmonics, stability: None, ..Default::default() };
    let with_stability = SweepOptions { harmonics: args.harmonics, ..Default::default() };
    for (tool, opts) in [("ihbm", &plain), ("ihbm+stability", &with_stability)] {
        let (curve, median, best) = timed(&model, &args, opts).map_err(|e| e.to_string())?;
        println!("{}", json_line(tool, &args, samples, &curve, (median, best)));
    }
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("peer_duffing: {e}");
        std::process::exit(1);
    }
}
