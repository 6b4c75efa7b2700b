//! Harmonic convergence: rerun a curve with N, N + increment, ... harmonics until its
//! peaks and folds stop changing by more than a relative tolerance.

use super::SweepOptions;
use crate::error::Result;
use crate::results::{Curve, HarmonicConvergence, HarmonicLevel};

/// Run once (no study requested), or rerun with more harmonics until the curve
/// converges; `run` traces one curve at the options' harmonic count and says whether
/// it was stopped early (then no further level is run).
pub(super) fn with_convergence(
    opts: &SweepOptions,
    mut run: impl FnMut(&SweepOptions) -> Result<(Curve, bool)>,
) -> Result<Curve> {
    let Some(conv) = opts.convergence else {
        return run(opts).map(|(c, _)| c);
    };
    let mut o = opts.clone();
    o.convergence = None;
    let mut levels: Vec<HarmonicLevel> = Vec::new();
    let mut prev: Option<(Vec<f64>, Vec<f64>)> = None;
    loop {
        let (mut curve, stopped) = run(&o)?;
        let peaks: Vec<f64> = (0..curve.output_names.len())
            .map(|k| curve.points.iter().map(|p| p.outputs[k].max_abs).fold(0.0, f64::max))
            .collect();
        let folds: Vec<f64> = curve.folds.iter().map(|f| f.param).collect();
        let change = match &prev {
            Some((pp, pf)) if pf.len() == folds.len() => {
                let rel =
                    |a: f64, b: f64| (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
                let c1 = peaks.iter().zip(pp).map(|(&a, &b)| rel(a, b)).fold(0.0, f64::max);
                let c2 = folds.iter().zip(pf).map(|(&a, &b)| rel(a, b)).fold(0.0, f64::max);
                c1.max(c2)
            }
            _ => f64::INFINITY,
        };
        levels.push(HarmonicLevel {
            harmonics: o.harmonics,
            peaks: peaks.clone(),
            folds: folds.clone(),
            change,
        });
        let converged = change < conv.tol;
        if stopped || converged || o.harmonics + conv.increment.max(1) > conv.max_harmonics {
            curve.convergence =
                Some(HarmonicConvergence { levels, tol: conv.tol, converged, estimate: change });
            return Ok(curve);
        }
        prev = Some((peaks, folds));
        o.harmonics += conv.increment.max(1);
    }
}
