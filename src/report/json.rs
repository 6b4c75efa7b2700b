//! The JSON documents of CONTRACT section 2, field for field and in that order.

use crate::results::{Curve, PointOutput, SimRecord, SolveRecord};
use serde_json::{json, Map, Value};

fn point_outputs(names: &[String], outs: &[PointOutput]) -> Value {
    let mut m = Map::new();
    for (name, o) in names.iter().zip(outs) {
        m.insert(name.clone(), json!({ "max_abs": o.max_abs, "mean": o.mean, "amp1": o.amp1 }));
    }
    Value::Object(m)
}

/// The JSON of `solve`: `{model, omega, harmonics, converged, iterations,
/// residual_norm, stable, outputs: {name: {max_abs, mean, amp1, cos, sin}}}`.
pub fn solve_json(r: &SolveRecord) -> Value {
    let mut outs = Map::new();
    for o in &r.outputs {
        outs.insert(
            o.name.clone(),
            json!({ "max_abs": o.max_abs, "mean": o.mean, "amp1": o.amp1,
                    "cos": o.cos, "sin": o.sin }),
        );
    }
    json!({
        "model": r.model, "omega": r.omega, "harmonics": r.harmonics,
        "converged": r.converged, "iterations": r.iterations,
        "residual_norm": r.residual_norm, "stable": r.stability.verdict(),
        "outputs": Value::Object(outs),
    })
}

/// The JSON of `sweep`: `{model, harmonics, points, folds, jumps, segments}` plus
/// `parameter`, `stats`, `bifurcations` and `stability_checked` (`false` when the
/// sweep skipped stability, so that no point's `"stable": true` is taken for a
/// verdict; extensions, after the contract's fields; the objects inside the contract's
/// arrays keep exactly the contract's keys),
/// and `convergence` when a harmonic-convergence study was run. For a parameter
/// sweep (`parameter` not `"omega"`) every point and fold also carries `param`, the
/// parameter's value (`omega` stays the fixed frequency); jumps' `omega` and
/// segments' `from_omega`/`to_omega` are then parameter values.
pub fn sweep_json(c: &Curve) -> Value {
    let by_param = !c.parameter.is_omega();
    let points: Vec<Value> = c
        .points
        .iter()
        .map(|p| {
            let mut v = json!({ "omega": p.omega, "stable": p.stability.verdict(),
                    "outputs": point_outputs(&c.output_names, &p.outputs) });
            if by_param {
                v["param"] = json!(p.param);
            }
            v
        })
        .collect();
    let folds: Vec<Value> = c
        .folds
        .iter()
        .map(|f| {
            let mut m = Map::new();
            for (name, o) in c.output_names.iter().zip(&f.outputs) {
                m.insert(name.clone(), json!({ "max_abs": o.max_abs }));
            }
            let mut v = json!({ "omega": f.omega, "outputs": Value::Object(m) });
            if by_param {
                v["param"] = json!(f.param);
            }
            v
        })
        .collect();
    let jumps: Vec<Value> = c
        .jumps
        .iter()
        .map(|j| {
            json!({ "direction": j.direction, "omega": j.at, "output": j.output,
                    "from": j.from, "to": j.to })
        })
        .collect();
    let segments: Vec<Value> = c
        .segments
        .iter()
        .map(|s| {
            json!({ "from_omega": s.from, "to_omega": s.to,
                    "ended": s.ended.to_string() })
        })
        .collect();
    let mut v = json!({
        "model": c.model, "harmonics": c.harmonics, "points": points,
        "folds": folds, "jumps": jumps, "segments": segments,
        "parameter": c.parameter.name(), "stats": c.stats,
        "bifurcations": c.all_bifurcations(),
        "stability_checked": c.stability_checked,
    });
    if let Some(conv) = &c.convergence {
        v["convergence"] = json!(conv);
    }
    v
}

/// The JSON of `simulate`: `{model, omega, dt, periods, scheme, outputs: {name:
/// {max_abs, mean}}}`, each output with `drift` and `steady` added (whether the
/// last two blocks of 10 periods agree to 1 %: a drifting run has no steady value).
pub fn simulate_json(r: &SimRecord) -> Value {
    let mut outs = Map::new();
    for o in &r.outputs {
        outs.insert(
            o.name.clone(),
            json!({ "max_abs": o.max_abs, "mean": o.mean, "drift": o.drift, "steady": o.steady() }),
        );
    }
    json!({
        "model": r.model, "omega": r.omega, "dt": r.dt, "periods": r.periods,
        "scheme": r.scheme, "outputs": Value::Object(outs),
    })
}
