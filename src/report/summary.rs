//! Facts read off a curve for `summary.md`: peak amplitude and frequency, folds.

use crate::results::{Curve, HarmonicConvergence};

/// What `summary.md` reports about one output of one curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveFacts {
    /// Largest `max_abs` over the points considered; at an interior maximum, the
    /// vertex of the parabola through it and its two neighbours (error `O(h²)` in the
    /// point spacing `h`, instead of `O(h)` for the largest point itself).
    pub peak: f64,
    /// Ω (rad/s) where it occurs (the parabola's vertex, likewise).
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
/// use ihbm::results::{Curve, CurvePoint, CurveStats, Parameter, PointOutput, Stability};
/// let pt = |w: f64, a: f64| CurvePoint { omega: w, param: w, coeffs: vec![], stability: Stability::Stable,
///     outputs: vec![PointOutput::harmonic(0.0, a)], segment: 0 };
/// let curve = Curve { model: "m".into(), harmonics: 1, parameter: Parameter::Omega,
///     output_names: vec!["x".into()], points: vec![pt(1.0, 1.0), pt(2.0, 3.0), pt(9.0, 5.0)],
///     stability_checked: true, folds: vec![], jumps: vec![], peaks: vec![], segments: vec![], stats: CurveStats::default(),
///     bifurcations: vec![], convergence: None };
/// let all = ihbm::report::curve_facts(&curve, "x", None).unwrap();
/// assert_eq!((all.peak, all.peak_omega), (5.0, 9.0));
/// let low = ihbm::report::curve_facts(&curve, "x", Some((0.0, 5.0))).unwrap();
/// assert_eq!((low.peak, low.peak_omega), (3.0, 2.0));
/// // an interior peak of 4 - (Ω - 2.3)², sampled at 1, 2, 3: the parabola's vertex
/// let f = |w: f64| 4.0 - (w - 2.3) * (w - 2.3);
/// let curve = Curve { points: vec![pt(1.0, f(1.0)), pt(2.0, f(2.0)), pt(3.0, f(3.0))], ..curve };
/// let top = ihbm::report::curve_facts(&curve, "x", None).unwrap();
/// assert!((top.peak_omega - 2.3).abs() < 1e-12 && (top.peak - 4.0).abs() < 1e-12);
/// ```
pub fn curve_facts(curve: &Curve, output: &str, band: Option<(f64, f64)>) -> Option<CurveFacts> {
    let idx = curve.output_names.iter().position(|n| n == output)?;
    let in_band = |w: f64| band.is_none_or(|(lo, hi)| w >= lo && w <= hi);
    let mut best: Option<(f64, usize)> = None;
    let mut unstable = 0;
    for (i, p) in curve.points.iter().enumerate().filter(|(_, p)| in_band(p.omega)) {
        let Some(o) = p.outputs.get(idx) else { continue };
        if p.stability.is_unstable() {
            unstable += 1;
        }
        if o.max_abs.is_finite() && best.is_none_or(|(a, _)| o.max_abs > a) {
            best = Some((o.max_abs, i));
        }
    }
    let (peak, i) = best?;
    let (peak, peak_omega) =
        refine_peak(curve, idx, i, &in_band).unwrap_or((peak, curve.points[i].omega));
    Some(CurveFacts {
        peak,
        peak_omega,
        folds: curve.folds.iter().filter(|f| in_band(f.omega)).map(|f| f.omega).collect(),
        unstable_points: unstable,
    })
}

/// The vertex of the parabola in Ω through points `i - 1`, `i`, `i + 1` (same
/// segment, in the band, Ω strictly monotone), if it lies between the neighbours.
fn refine_peak(
    curve: &Curve,
    idx: usize,
    i: usize,
    in_band: &dyn Fn(f64) -> bool,
) -> Option<(f64, f64)> {
    let pts = curve.points.get(i.checked_sub(1)?..=i + 1)?;
    if pts.iter().any(|p| p.segment != pts[1].segment || !in_band(p.omega)) {
        return None;
    }
    let (x0, x1, x2) = (pts[0].omega, pts[1].omega, pts[2].omega);
    let y = |k: usize| pts[k].outputs.get(idx).map(|o| o.max_abs);
    let (y0, y1, y2) = (y(0)?, y(1)?, y(2)?);
    if !((x0 < x1 && x1 < x2) || (x0 > x1 && x1 > x2)) {
        return None;
    }
    // Newton's divided differences: y = y1 + d1 (x - x1) + d2 (x - x1)(x - x0)
    let (f01, f12) = ((y1 - y0) / (x1 - x0), (y2 - y1) / (x2 - x1));
    let d2 = (f12 - f01) / (x2 - x0);
    if d2 >= 0.0 {
        return None;
    }
    // y'(x) = f01 + d2 (2x - x0 - x1) = 0
    let xv = 0.5 * (x0 + x1) - f01 / (2.0 * d2);
    if !(xv - x0.min(x2) > 0.0 && x0.max(x2) - xv > 0.0) {
        return None;
    }
    let yv = y0 + f01 * (xv - x0) + d2 * (xv - x0) * (xv - x1);
    (yv >= y1 && yv.is_finite()).then_some((yv, xv))
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
