//! One CSV per curve: `omega,stable,<out>_max_abs,<out>_mean,<out>_amp1,<out>_rms,
//! <out>_min,<out>_max,...` (for a parameter sweep the first column is the parameter,
//! named as in the model). Every output's columns are those of [`STATS`].

use crate::backbone::{Backbone, CycleFamily};
use crate::bifurcation::FoldCurves;
use crate::results::Curve;
use crate::results::PointOutput;
use std::fmt::Write;

/// A number as a CSV cell: the fewest digits that read back to the same `f64`, in
/// plain decimal notation or with an exponent, whichever is shorter (`0.5`, `1e-30`,
/// `-1.5071692156825925e-18`, not thirty zeros); a number that is not finite as
/// `NaN`, `inf` or `-inf`.
///
/// ```
/// use ihbm::report::Num;
/// assert_eq!(Num(0.5).to_string(), "0.5");
/// assert_eq!(Num(-6.073200494128545e-17).to_string(), "-6.073200494128545e-17");
/// assert_eq!(Num(1e21).to_string(), "1e21");
/// assert_eq!(Num(120.0).to_string(), "120");
/// assert_eq!("1e-30".parse::<f64>(), Ok(1e-30));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plain = self.0.to_string();
        let exp = format!("{:e}", self.0);
        f.write_str(if exp.len() < plain.len() { &exp } else { &plain })
    }
}

/// The statistics of an output, in the order of its CSV columns (`<out>_max_abs`, ...).
pub const STATS: [&str; 6] = ["max_abs", "mean", "amp1", "rms", "min", "max"];

/// The header columns of every output's statistics.
fn stats_header(s: &mut String, names: &[String]) {
    for name in names {
        for stat in STATS {
            // Writing to a String cannot fail.
            let _ = write!(s, ",{name}_{stat}");
        }
    }
}

/// One row's statistics of every output, in the order of [`STATS`].
fn stats_row(s: &mut String, outs: &[PointOutput]) {
    for o in outs {
        for v in [o.max_abs, o.mean, o.amp1, o.rms, o.min, o.max] {
            let _ = write!(s, ",{}", Num(v));
        }
    }
}

/// The CSV of a curve: a header, then one row per point in arc-length order
/// (the book's output reference). Numbers are written as [`Num`] writes them. A parameter
/// sweep's first column is the parameter (`curve.parameter`) and its values.
///
/// ```
/// use ihbm::results::{Curve, CurvePoint, CurveStats, Parameter, PointOutput, Stability};
/// let curve = Curve {
///     model: "m".into(), harmonics: 1, parameter: Parameter::Omega,
///     output_names: vec!["x".into()],
///     points: vec![CurvePoint { omega: 2.0, param: 2.0, coeffs: vec![], stability: Stability::Stable,
///         outputs: vec![PointOutput::harmonic(0.0, 0.5)], segment: 0 }],
///     stability_checked: true, folds: vec![], jumps: vec![], peaks: vec![], segments: vec![], stats: CurveStats::default(),
///     bifurcations: vec![], convergence: None };
/// assert_eq!(ihbm::report::curve_csv(&curve),
///            format!("omega,stable,x_max_abs,x_mean,x_amp1,x_rms,x_min,x_max\n\
///                     2,true,0.5,0,0.5,{},-0.5,0.5\n", 0.125f64.sqrt()));
/// ```
pub fn curve_csv(curve: &Curve) -> String {
    let by_param = !curve.parameter.is_omega();
    let mut s = format!("{},stable", curve.parameter);
    stats_header(&mut s, &curve.output_names);
    s.push('\n');
    for p in &curve.points {
        let x = if by_param { p.param } else { p.omega };
        let stable = p.stability.verdict().map_or(String::new(), |v| v.to_string());
        let _ = write!(s, "{},{stable}", Num(x));
        stats_row(&mut s, &p.outputs);
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
            let _ = write!(s, "{i},{},{}", Num(p.omega), Num(p.value));
            if torus {
                let _ = write!(
                    s,
                    ",{}",
                    p.torus_frequency.map_or(String::new(), |w| Num(w).to_string())
                );
            }
            for o in &p.outputs {
                let _ = write!(s, ",{}", Num(o.max_abs));
            }
            s.push('\n');
        }
    }
    s
}

/// The CSV of a backbone: `omega,damping,xi,amplitude,<out>_max_abs,<out>_mean,
/// <out>_amp1,<out>_rms,<out>_min,<out>_max,...`, one row per point in arc-length order.
pub fn backbone_csv(b: &Backbone) -> String {
    let mut s = String::from("omega,damping,xi,amplitude");
    stats_header(&mut s, &b.output_names);
    s.push('\n');
    for p in &b.points {
        let _ = write!(s, "{},{},{},{}", Num(p.omega), Num(p.damping), Num(p.xi), Num(p.amplitude));
        stats_row(&mut s, &p.outputs);
        s.push('\n');
    }
    s
}

/// The CSV of a family of limit cycles: `<P>,omega,period,stable,<out>_max_abs,
/// <out>_mean,<out>_amp1,<out>_rms,<out>_min,<out>_max,...`, one row per point in
/// arc-length order (`stable` empty where there is no verdict).
pub fn cycles_csv(f: &CycleFamily) -> String {
    let mut s = format!("{},omega,period,stable", f.parameter);
    stats_header(&mut s, &f.output_names);
    s.push('\n');
    for p in &f.points {
        let stable = p.stability.verdict().map_or(String::new(), |b| b.to_string());
        let _ = write!(s, "{},{},{},{stable}", Num(p.value), Num(p.omega), Num(p.period));
        stats_row(&mut s, &p.outputs);
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::Num;

    /// Every finite `f64` reads back exactly, and is never written longer than Rust's
    /// plain form; over bit patterns spread across the whole range (subnormals, both
    /// signs, every exponent).
    #[test]
    fn numbers_round_trip_and_are_never_longer_than_plain() {
        let mut bits = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..200_000 {
            // xorshift64: a cheap spread over all bit patterns
            bits ^= bits << 13;
            bits ^= bits >> 7;
            bits ^= bits << 17;
            let x = f64::from_bits(bits);
            if !x.is_finite() {
                continue;
            }
            let s = Num(x).to_string();
            assert_eq!(s.parse::<f64>().map(f64::to_bits), Ok(x.to_bits()), "{x:e} -> {s}");
            assert!(s.len() <= x.to_string().len(), "{s}");
        }
        for (x, s) in [(0.0, "0"), (-0.0, "-0"), (1e-300, "1e-300"), (123456.0, "123456")] {
            assert_eq!(Num(x).to_string(), s);
        }
    }
}
