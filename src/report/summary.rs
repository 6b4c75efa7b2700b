//! Facts read off a curve for `summary.md`: peak amplitude and frequency, folds.

use crate::results::{Curve, HarmonicConvergence};

/// What `summary.md` reports about one output of one curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveFacts {
    /// Largest `max_abs` over the points considered.
    pub peak: f64,
    /// Ω (rad/s) where it occurs.
    pub peak_omega: f64,
    /// Ω (rad/s) of every fold of the curve, in arc-length order.
    pub folds: Vec<f64>,
    /// Number of points marked unstable.
    pub unstable_points: usize,
}

/// Peak and folds of output `output` over the points with Ω in `band` (all points
/// when `None`); `None` when the output is unknown or no point lies in the band.
///
/// ```
/// use ihbm::results::{Curve, CurvePoint, CurveStats, PointOutput};
/// let pt = |w: f64, a: f64| CurvePoint { omega: w, param: w, coeffs: vec![], stable: true,
///     outputs: vec![PointOutput { max_abs: a, mean: 0.0, amp1: a }], segment: 0 };
/// let curve = Curve { model: "m".into(), harmonics: 1, parameter: "omega".into(),
///     output_names: vec!["x".into()], points: vec![pt(1.0, 1.0), pt(2.0, 3.0), pt(9.0, 5.0)],
///     folds: vec![], jumps: vec![], segments: vec![], stats: CurveStats::default(),
///     bifurcations: vec![], convergence: None };
/// let all = ihbm::report::curve_facts(&curve, "x", None).unwrap();
/// assert_eq!((all.peak, all.peak_omega), (5.0, 9.0));
/// let low = ihbm::report::curve_facts(&curve, "x", Some((0.0, 5.0))).unwrap();
/// assert_eq!((low.peak, low.peak_omega), (3.0, 2.0));
/// ```
pub fn curve_facts(curve: &Curve, output: &str, band: Option<(f64, f64)>) -> Option<CurveFacts> {
    let idx = curve.output_names.iter().position(|n| n == output)?;
    let in_band = |w: f64| band.is_none_or(|(lo, hi)| w >= lo && w <= hi);
    let mut best: Option<(f64, f64)> = None;
    let mut unstable = 0;
    for p in curve.points.iter().filter(|p| in_band(p.omega)) {
        let Some(o) = p.outputs.get(idx) else { continue };
        if !p.stable {
            unstable += 1;
        }
        if o.max_abs.is_finite() && best.is_none_or(|(a, _)| o.max_abs > a) {
            best = Some((o.max_abs, p.omega));
        }
    }
    let (peak, peak_omega) = best?;
    Some(CurveFacts {
        peak,
        peak_omega,
        folds: curve.folds.iter().filter(|f| in_band(f.omega)).map(|f| f.omega).collect(),
        unstable_points: unstable,
    })
}

/// One line on a harmonic-convergence study: the levels run and the error estimate.
///
/// ```
/// use ihbm::results::{HarmonicConvergence, HarmonicLevel};
/// let level = |n| HarmonicLevel { harmonics: n, peaks: vec![], folds: vec![], change: 0.0 };
/// let c = HarmonicConvergence { levels: vec![level(5), level(7)], tol: 1e-3,
///                               converged: true, estimate: 4.1e-5 };
/// assert_eq!(ihbm::report::convergence_line(&c),
///     "harmonic convergence (N = 5, 7): estimated relative error 4.100e-5, converged (tol 1e-3)");
/// ```
pub fn convergence_line(c: &HarmonicConvergence) -> String {
    let ns: Vec<String> = c.levels.iter().map(|l| l.harmonics.to_string()).collect();
    format!(
        "harmonic convergence (N = {}): estimated relative error {:.3e}, {} (tol {:e})",
        ns.join(", "),
        c.estimate,
        if c.converged { "converged" } else { "NOT converged" },
        c.tol
    )
}
