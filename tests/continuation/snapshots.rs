//! Snapshots of reference curves and solver statistics (floats rounded). Added after
//! the independent checks in duffing.rs, quarter_car.rs (beside this file) and
//! tests/stability/ passed; they guard against silent changes, they prove nothing.

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{Duffing, QuarterCar};
use ihbm::results::Curve;
use serde_json::{json, Value};

fn r(x: f64, digits: i32) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

fn summary(c: &Curve) -> Value {
    json!({
        "points": c.points.len(),
        "stats": c.stats,
        "segments": c.segments.iter().map(|s| json!({
            "from": r(s.from, 8), "to": r(s.to, 8), "ended": s.ended.to_string()
        })).collect::<Vec<_>>(),
        "folds": c.folds.iter().map(|f| json!({
            "omega": r(f.omega, 8),
            "max_abs": f.outputs.iter().map(|o| r(o.max_abs, 6)).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "bifurcations": c.all_bifurcations().iter().map(|b| json!({
            "kind": b.kind, "omega": r(b.omega, 6)
        })).collect::<Vec<_>>(),
        "jumps": c.jumps.iter().map(|j| json!({
            "direction": j.direction, "output": j.output, "omega": r(j.at, 8),
            "from": r(j.from, 5), "to": r(j.to, 3)
        })).collect::<Vec<_>>(),
        "unstable_points": c.points.iter().filter(|p| !p.stability.is_stable()).count(),
        "located_peaks": c.peaks.iter().map(|p| json!({
            "output": c.output_names[p.output], "omega": r(p.omega, 8), "value": r(p.value, 6),
            "located": p.located
        })).collect::<Vec<_>>(),
        "peak": c.output_names.iter().enumerate().map(|(k, n)| json!({
            n.as_str(): r(c.points.iter().map(|p| p.outputs[k].max_abs).fold(0.0, f64::max), 5)
        })).collect::<Vec<_>>(),
    })
}

#[test]
fn duffing_one_harmonic_reference_curve() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let c = sweep(&model, 0.5, 2.5, &SweepOptions { harmonics: 1, ..Default::default() }).unwrap();
    insta::assert_json_snapshot!(summary(&c));
}

#[test]
fn quarter_car_table_1_reference_curve() {
    let c = sweep(&QuarterCar::default(), 1.0, 100.0, &SweepOptions::default()).unwrap();
    insta::assert_json_snapshot!(summary(&c));
}

#[test]
fn quarter_car_multivalued_reference_curve() {
    let car = QuarterCar { F: 0.03, k3: 5e6, ..Default::default() };
    let c = sweep(&car, 1.0, 100.0, &SweepOptions::default()).unwrap();
    insta::assert_json_snapshot!(summary(&c));
}

#[test]
fn quarter_car_runaway_reference_curve() {
    let car = QuarterCar { F: 0.05, k3: 5e6, ..Default::default() };
    let c = sweep(&car, 1.0, 100.0, &SweepOptions::default()).unwrap();
    insta::assert_json_snapshot!(summary(&c));
}
