//! The JSON documents of the commands, field for field and in the order the book's
//! chapter "Output reference" lists them.

use crate::backbone::{Backbone, Cycle, CycleFamily, EventKind};
use crate::bifurcation::{FoldCurves, FoldPoint};
use crate::results::{Curve, OutputSummary, PointOutput, SimRecord, SolveRecord};
use serde_json::{json, Map, Value};

/// One output's statistics: `{max_abs, mean, amp1, rms, min, max}`.
fn stats(o: &PointOutput) -> Value {
    json!({ "max_abs": o.max_abs, "mean": o.mean, "amp1": o.amp1,
            "rms": o.rms, "min": o.min, "max": o.max })
}

/// Every output's statistics, by name.
fn point_outputs(names: &[String], outs: &[PointOutput]) -> Value {
    let mut m = Map::new();
    for (name, o) in names.iter().zip(outs) {
        m.insert(name.clone(), stats(o));
    }
    Value::Object(m)
}

/// Every output's statistics and harmonics (`cos`, `sin`), by name.
fn summaries(outs: &[OutputSummary]) -> Value {
    let mut m = Map::new();
    for o in outs {
        let mut v = stats(&o.stats());
        v["cos"] = json!(o.cos);
        v["sin"] = json!(o.sin);
        m.insert(o.name.clone(), v);
    }
    Value::Object(m)
}

/// The JSON of `solve`: `{model, omega, harmonics, converged, iterations,
/// residual_norm, stable, outputs: {name: {max_abs, mean, amp1, rms, min, max, cos,
/// sin}}}`, and `failure` ([`SolveRecord::failure`]) when Newton could not start.
pub fn solve_json(r: &SolveRecord) -> Value {
    let mut v = json!({
        "model": r.model, "omega": r.omega, "harmonics": r.harmonics,
        "converged": r.converged, "iterations": r.iterations,
        "residual_norm": r.residual_norm, "stable": r.stability.verdict(),
        "outputs": summaries(&r.outputs),
    });
    // Each output's sensitivities, by parameter, where any was asked for.
    for (param, rates) in &r.sensitivities {
        for (o, rate) in r.outputs.iter().zip(rates) {
            v["outputs"][&o.name]["sensitivities"][param] = json!(rate);
        }
    }
    // The extension: why Newton could not start (absent when it could).
    if let (Some(why), Some(m)) = (&r.failure, v.as_object_mut()) {
        m.insert("failure".into(), json!(why));
    }
    v
}

/// The JSON of `sweep`: `{model, harmonics, points, folds, jumps, segments}` plus
/// `parameter`, `stats`, `bifurcations`, `peaks` (`[{omega, output, value, located}]`,
/// the local maxima of each output's `max_abs` along the curve) and
/// `stability_checked` (`false` when the
/// sweep skipped stability, so that no point's `"stable": true` is taken for a
/// verdict; these follow the first six, and the objects inside the arrays keep
/// exactly the keys listed here),
/// and `convergence` when a harmonic-convergence study was run. For a parameter
/// sweep (`parameter` not `"omega"`) every point, fold and peak also carries `param`, the
/// parameter's value (`omega` stays the fixed frequency); so do jumps (`param` where
/// they happen) and segments (`from_param`/`to_param`, while `from_omega`/`to_omega`
/// are the fixed frequency).
pub fn sweep_json(c: &Curve) -> Value {
    let by_param = !c.parameter.is_omega();
    // The fixed frequency of a parameter sweep (every point has it).
    let fixed_omega = c.points.first().map(|p| p.omega);
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
            let outputs = point_outputs(&c.output_names, &f.outputs);
            let mut v = json!({ "omega": f.omega, "outputs": outputs });
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
            let mut v = json!({ "direction": j.direction, "omega": j.at, "output": j.output,
                    "from": j.from, "to": j.to });
            if by_param {
                v["omega"] = json!(fixed_omega);
                v["param"] = json!(j.at);
            }
            v
        })
        .collect();
    let segments: Vec<Value> = c
        .segments
        .iter()
        .map(|s| {
            let mut v = json!({ "from_omega": s.from, "to_omega": s.to,
                    "ended": s.ended.to_string() });
            if by_param {
                v["from_omega"] = json!(fixed_omega);
                v["to_omega"] = json!(fixed_omega);
                v["from_param"] = json!(s.from);
                v["to_param"] = json!(s.to);
            }
            v
        })
        .collect();
    let peaks: Vec<Value> = c
        .peaks
        .iter()
        .map(|k| {
            let mut v = json!({ "omega": k.omega, "output": c.output_names.get(k.output),
                    "value": k.value, "located": k.located });
            if by_param {
                v["param"] = json!(k.param);
            }
            v
        })
        .collect();
    let mut v = json!({
        "model": c.model, "harmonics": c.harmonics, "points": points,
        "folds": folds, "jumps": jumps, "segments": segments,
        "parameter": c.parameter.name(), "stats": c.stats,
        "bifurcations": c.all_bifurcations(),
        "peaks": peaks,
        "stability_checked": c.stability_checked,
    });
    if let Some(conv) = &c.convergence {
        v["convergence"] = json!(conv);
    }
    v
}

/// The JSON of `simulate`: `{model, omega, dt, periods, scheme, outputs: {name:
/// {max_abs, mean, amp1, rms, min, max}}}` (over the last 10 periods), each output
/// with `drift` and `steady` added (whether the last two blocks of 10 periods agree
/// to 1 %: a drifting run has no steady value), and `start_up_left`
/// ([`crate::timedomain::StartUp::left`]).
pub fn simulate_json(r: &SimRecord) -> Value {
    let mut outs = Map::new();
    for o in &r.outputs {
        outs.insert(
            o.name.clone(),
            json!({ "max_abs": o.max_abs, "mean": o.mean, "amp1": o.amp1, "rms": o.rms,
                    "min": o.min, "max": o.max, "drift": o.drift, "steady": o.steady() }),
        );
    }
    let mut v = json!({
        "model": r.model, "omega": r.omega, "dt": r.dt, "periods": r.periods,
        "scheme": r.scheme, "outputs": Value::Object(outs),
    });
    // The extension: the slowest free mode's start-up transient left (absent, not
    // null, for a model without an oscillatory mode at rest).
    if let (Some(s), Some(m)) = (r.start_up, v.as_object_mut()) {
        m.insert("start_up_left".into(), json!(s.left));
    }
    v
}

/// The JSON of `folds`: `{model, harmonics, parameter, curves:
/// [{points: [{omega, value, outputs: {name: {max_abs, mean, amp1, rms, min, max}}}],
/// ended}], cusps: [{omega, value, outputs}]}`, then `range`, `omega_range`, `start_folds`
/// (folds found by the sweeps at the two ends of the range), `boundary` (`"fold"` or
/// `"period-doubling"`: what the curves follow) and `stats`; each curve
/// adds `start` (`"from"` or `"to"`: the end its first fold was found at), each cusp
/// `kind` (`"cusp"`, or `"isola"` where a detached branch joins), `curve` (its
/// index) and `located`.
pub fn folds_json(f: &FoldCurves) -> Value {
    let outputs = |outs: &[PointOutput]| point_outputs(&f.output_names, outs);
    let point = |p: &FoldPoint| {
        let mut v = json!({ "omega": p.omega, "value": p.value, "outputs": outputs(&p.outputs) });
        if let (Some(w), Some(m)) = (p.torus_frequency, v.as_object_mut()) {
            m.insert("torus_frequency".into(), json!(w));
        }
        v
    };
    let curves: Vec<Value> = f
        .curves
        .iter()
        .map(|c| {
            json!({ "points": c.points.iter().map(point).collect::<Vec<_>>(),
                    "ended": c.ended.to_string(),
                    "start": match c.start { crate::bifurcation::RangeEnd::From => "from", crate::bifurcation::RangeEnd::To => "to" } })
        })
        .collect();
    let cusps: Vec<Value> = f
        .cusps
        .iter()
        .map(|c| {
            json!({ "omega": c.omega, "value": c.value, "outputs": outputs(&c.outputs),
                    "kind": c.kind.to_string(), "curve": c.curve, "located": c.located })
        })
        .collect();
    json!({
        "model": f.model, "harmonics": f.harmonics, "parameter": f.parameter,
        "curves": curves, "cusps": cusps,
        "range": [f.range.0, f.range.1], "omega_range": [f.omega.0, f.omega.1],
        "start_folds": [f.start_folds.0, f.start_folds.1],
        "boundary": f.boundary.to_string(),
        "stats": { "iterations": f.iterations, "steps": f.steps.0, "rejected_steps": f.steps.1 },
    })
}

/// The JSON of `backbone`: `{model, harmonics, mode, points:
/// [{omega, damping, stable, outputs: {name: {max_abs, mean, amp1, rms, min, max}}}]}`, each point
/// also with `xi` (the artificial damping of `-ξ M ẋ`) and `amplitude` (the modal
/// amplitude), and `output`, `to`, `linear` (the start's `omega` and `damping`),
/// `events` (`[{kind: "turn" | "internal-resonance", omega, amplitude, ratio: "k:1"
/// or null, mode: the other mode or null, after}]`) and `ended`. `stable` is Hill's
/// verdict where ξ = 0 (a conservative model) and `null` where ξ ≠ 0, where the point
/// is not a motion of the model ([`crate::backbone::ModePoint::stability`]).
pub fn backbone_json(b: &Backbone) -> Value {
    let points: Vec<Value> = b
        .points
        .iter()
        .map(|p| {
            json!({ "omega": p.omega, "damping": p.damping, "stable": p.stability.verdict(),
                    "xi": p.xi, "amplitude": p.amplitude,
                    "outputs": point_outputs(&b.output_names, &p.outputs) })
        })
        .collect();
    let events: Vec<Value> = b
        .events
        .iter()
        .map(|e| {
            let (ratio, mode) = match e.kind {
                EventKind::InternalResonance { mode, ratio } => {
                    (Value::from(format!("{ratio}:1")), Value::from(mode))
                }
                EventKind::Turn => (Value::Null, Value::Null),
            };
            json!({ "kind": e.kind.name(), "omega": e.omega, "amplitude": e.amplitude,
                    "ratio": ratio, "mode": mode, "after": e.after })
        })
        .collect();
    json!({
        "model": b.model, "harmonics": b.harmonics, "mode": b.mode,
        "points": points,
        "output": b.output_names.get(b.output), "to": b.to,
        "linear": { "omega": b.linear.0, "damping": b.linear.1 },
        "events": events,
        "ended": b.ended.to_string(),
        "stats": { "iterations": b.iterations, "steps": b.steps },
    })
}

/// The JSON of `cycle`: `{model, harmonics, converged, omega,
/// period, stable, outputs: {name: {max_abs, mean, amp1, rms, min, max, cos, sin}}}`,
/// and `mode` (the linearised mode it was followed from).
pub fn cycle_json(c: &Cycle) -> Value {
    json!({
        "model": c.model, "harmonics": c.harmonics, "converged": true,
        "omega": c.omega, "period": c.period, "stable": c.stability.verdict(),
        "outputs": summaries(&c.outputs), "mode": c.mode,
    })
}

/// The JSON of a family of limit cycles (`cycle --param`): `{model, harmonics,
/// parameter, mode, points: [{value, omega, period, stable, outputs: {name: {max_abs,
/// mean, amp1, rms, min, max}}}], hopf: {value, omega} or null, ended, range, stats}`.
pub fn cycles_json(f: &CycleFamily) -> Value {
    let points: Vec<Value> = f
        .points
        .iter()
        .map(|p| {
            json!({ "value": p.value, "omega": p.omega, "period": p.period,
                    "stable": p.stability.verdict(),
                    "outputs": point_outputs(&f.output_names, &p.outputs) })
        })
        .collect();
    json!({
        "model": f.model, "harmonics": f.harmonics, "parameter": f.parameter,
        "mode": f.mode, "points": points,
        "hopf": f.hopf.map(|h| json!({ "value": h.value, "omega": h.omega })),
        "ended": f.ended.to_string(),
        "range": [f.range.0, f.range.1],
        "stats": { "iterations": f.iterations, "steps": f.steps },
    })
}
