//! The stability of a backbone point, where it means something.
//!
//! A point of a nonlinear mode is a periodic motion of `r(x) - ξ M ẋ = 0`. Where
//! ξ = 0 (a conservative model, whose whole backbone has ξ = 0) that is the model
//! itself, an autonomous system: Hill's method applies, and one exponent is always
//! zero (a shift in time is no perturbation), which is left out as for a limit cycle.
//! In a conservative system the zero exponent is double: the neighbouring orbit of
//! another energy drifts in phase but does not grow (a Jordan block), and Hill's
//! method resolves it as one exponent or as two split apart (a perturbed Jordan
//! block splits by the square root of the perturbation: up to 1e-4 ω seen, on either
//! axis). Both are left out: the two exponents nearest 0 if within [`TRIVIAL`]` · ω`.
//!
//! A conservative system's exponents come in pairs ±λ (and ±λ̄), so it can at best be
//! neutrally stable: the verdict is stable only when every other exponent lies on the
//! imaginary axis to the tolerance (`|Re λ| ≤ 1e-7 ω`, the forced problem's), unstable
//! when one has a positive real part.
//!
//! Where ξ ≠ 0 the point is a periodic motion of the model *with the artificial
//! damping added*, not of the model: a damped model has no periodic free motion at
//! all (it decays), so there is nothing whose stability could be asked, and the
//! verdict is [`Unknown::NotAMotion`] (the JSON's `"stable": null`).

use crate::balance::Balance;
use crate::error::Result;
use crate::model::DynModel;
use crate::results::{Stability, Unknown};
use crate::stability::{Hill, StabilityOptions};
use num_complex::Complex64;

/// `|ξ| ≤ XI_ZERO · ω` counts as ξ = 0: the point is a motion of the model. A
/// conservative model's ξ is zero to rounding (about 1e-15 ω).
const XI_ZERO: f64 = 1e-10;

/// The two exponents nearest 0, if within `TRIVIAL · ω` of it, are the double zero of
/// the phase and the energy (see the module documentation), left out of the verdict.
pub(crate) const TRIVIAL: f64 = 1e-2;

/// Hill's method for the points of one backbone (the analysis is set up once).
pub(crate) struct ModeStability {
    hill: Hill,
}

impl ModeStability {
    pub fn new(model: &dyn DynModel, harmonics: usize) -> Result<ModeStability> {
        Ok(ModeStability { hill: Hill::new(model, harmonics)? })
    }

    /// The verdict at the point `coeffs` with frequency `omega` and artificial
    /// damping `xi`, and the exponents other than the phase's (empty without a
    /// verdict).
    pub fn at(
        &mut self,
        bal: &mut Balance<'_>,
        coeffs: &[f64],
        omega: f64,
        xi: f64,
    ) -> (Stability, Vec<Complex64>) {
        // (a NaN ξ is no motion either)
        if xi.abs().is_nan() || xi.abs() > XI_ZERO * omega {
            return (Stability::Unknown(Unknown::NotAMotion), Vec::new());
        }
        let f = match self.hill.analyse(bal, coeffs, omega, &StabilityOptions::default()) {
            Ok(f) => f,
            Err(e) => return (Stability::Unknown(Unknown::Failed(e.to_string())), Vec::new()),
        };
        let mut exps = f.exponents;
        for _ in 0..2 {
            let near = (0..exps.len())
                .filter(|&i| exps[i].norm() <= TRIVIAL * omega)
                .min_by(|&a, &b| exps[a].norm().total_cmp(&exps[b].norm()));
            if let Some(i) = near {
                exps.remove(i);
            }
        }
        (conservative_verdict(&exps, omega), exps)
    }
}

/// `exps` without the one nearest 0 (the phase's).
pub(crate) fn without_phase(mut exps: Vec<Complex64>) -> Vec<Complex64> {
    if let Some(i) = (0..exps.len()).min_by(|&a, &b| exps[a].norm().total_cmp(&exps[b].norm())) {
        exps.remove(i);
    }
    exps
}

/// Stable when every exponent is on the imaginary axis (`|Re λ| ≤ tol · ω`),
/// unstable when one has `Re λ > tol · ω`; otherwise (decaying exponents
/// without growing partners: not a conservative spectrum) no verdict, with the
/// reason.
fn conservative_verdict(exps: &[Complex64], omega: f64) -> Stability {
    let tol = StabilityOptions::default().tol * omega;
    if exps.iter().any(|l| l.re > tol) {
        Stability::Unstable
    } else if exps.iter().all(|l| l.re.abs() <= tol) {
        Stability::Stable
    } else {
        let least = exps.iter().map(|l| l.re).fold(f64::INFINITY, f64::min);
        Stability::Unknown(Unknown::Failed(format!(
            "an exponent decays (Re λ = {least:.3e}) without a growing partner: not a \
             conservative system's spectrum"
        )))
    }
}
