//! One CSV per curve: `omega,stable,<out>_max_abs,<out>_mean,<out>_amp1,...` (for a
//! parameter sweep the first column is the parameter, named as in the model).

use crate::backbone::{Backbone, CycleFamily};
use crate::bifurcation::FoldCurves;
use crate::results::Curve;
use std::fmt::Write;

/// The CSV of a curve: a header, then one row per point in arc-length order
/// (the book's output reference). Numbers use Rust's shortest round-trip form. A parameter
/// sweep's first column is the parameter (`curve.parameter`) and its values.
///
/// ```
/// use ihbm::results::{Curve, CurvePoint, CurveStats, Parameter, PointOutput, Stability};
/// let curve = Curve {
///     model: "m".into(), harmonics: 1, parameter: Parameter::Omega,
///     output_names: vec!["x".into()],
///     points: vec![CurvePoint { omega: 2.0, param: 2.0, coeffs: vec![], stability: Stability::Stable,
///         outputs: vec![PointOutput { max_abs: 0.5, mean: 0.0, amp1: 0.5 }], segment: 0 }],
///     stability_checked: true, folds: vec![], jumps: vec![], segments: vec![], stats: CurveStats::default(),
///     bifurcations: vec![], convergence: None };
/// assert_eq!(ihbm::report::curve_csv(&curve),
///            "omega,stable,x_max_abs,x_mean,x_amp1\n2,true,0.5,0,0.5\n");
/// ```
pub fn curve_csv(curve: &Curve) -> String {
    let by_param = !curve.parameter.is_omega();
    let mut s = format!("{},stable", curve.parameter);
    for name in &curve.output_names {
        // Writing to a String cannot fail.
        let _ = write!(s, ",{name}_max_abs,{name}_mean,{name}_amp1");
    }
    s.push('\n');
    for p in &curve.points {
        let x = if by_param { p.param } else { p.omega };
        let stable = p.stability.verdict().map_or(String::new(), |v| v.to_string());
        let _ = write!(s, "{x},{stable}");
        for o in &p.outputs {
            let _ = write!(s, ",{},{},{}", o.max_abs, o.mean, o.amp1);
        }
        s.push('\n');
    }
    s
}

/// The CSV of fold curves: `curve,omega,<parameter>,<out>_max_abs,...`, one row per
/// point, curve after curve (each in arc-length order); the cusps are in the JSON. A
/// torus curve has a `torus_frequency` column after the parameter's.
pub fn folds_csv(f: &FoldCurves) -> String {
    let torus = f.boundary == crate::bifurcation::Boundary::Torus;
    let mut s = format!("curve,omega,{}", f.parameter);
    if torus {
        s.push_str(",torus_frequency");
    }
    for name in &f.output_names {
        let _ = write!(s, ",{name}_max_abs");
    }
    s.push('\n');
    for (i, c) in f.curves.iter().enumerate() {
        for p in &c.points {
            let _ = write!(s, "{i},{},{}", p.omega, p.value);
            if torus {
                let _ =
                    write!(s, ",{}", p.torus_frequency.map_or(String::new(), |w| w.to_string()));
            }
            for o in &p.outputs {
                let _ = write!(s, ",{}", o.max_abs);
            }
            s.push('\n');
        }
    }
    s
}

/// The CSV of a backbone: `omega,damping,xi,amplitude,<out>_max_abs,<out>_mean,
/// <out>_amp1,...`, one row per point in arc-length order.
pub fn backbone_csv(b: &Backbone) -> String {
    let mut s = String::from("omega,damping,xi,amplitude");
    for name in &b.output_names {
        let _ = write!(s, ",{name}_max_abs,{name}_mean,{name}_amp1");
    }
    s.push('\n');
    for p in &b.points {
        let _ = write!(s, "{},{},{},{}", p.omega, p.damping, p.xi, p.amplitude);
        for o in &p.outputs {
            let _ = write!(s, ",{},{},{}", o.max_abs, o.mean, o.amp1);
        }
        s.push('\n');
    }
    s
}

/// The CSV of a family of limit cycles: `<P>,omega,period,stable,<out>_max_abs,
/// <out>_mean,<out>_amp1,...`, one row per point in arc-length order (`stable` empty
/// where there is no verdict).
pub fn cycles_csv(f: &CycleFamily) -> String {
    let mut s = format!("{},omega,period,stable", f.parameter);
    for name in &f.output_names {
        let _ = write!(s, ",{name}_max_abs,{name}_mean,{name}_amp1");
    }
    s.push('\n');
    for p in &f.points {
        let stable = p.stability.verdict().map_or(String::new(), |b| b.to_string());
        let _ = write!(s, "{},{},{},{stable}", p.value, p.omega, p.period);
        for o in &p.outputs {
            let _ = write!(s, ",{},{},{}", o.max_abs, o.mean, o.amp1);
        }
        s.push('\n');
    }
    s
}
