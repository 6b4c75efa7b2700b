//! Self-excited periodic motions (limit cycles) of a model without forcing.
//!
//! A limit cycle is the periodic motion of the model itself: the point of a nonlinear
//! mode (traced as in [`super::backbone`], from the linear mode nearest the frequency
//! guess) where the artificial damping ξ vanishes. At small amplitude ξ is the
//! equilibrium's own damping with its sign reversed; a mode that is self-excited there
//! (ξ < 0: the equilibrium is unstable, as past a Hopf point) gains damping with
//! amplitude until ξ = 0 at the cycle, which is then located by Newton's method on
//! the row `ξ = 0`. Its stability is Hill's method on the autonomous problem, where
//! one exponent is always zero (shifting the cycle in time is no perturbation): it
//! is left out of the verdict.

use super::{Backbone, BackboneContinuation, BackboneOptions, End, Goal};
use crate::balance::Balance;
use crate::error::{Error, Result};
use crate::model::{DynModel, Model};
use crate::outputs::{At, OutputEval};
use crate::results::{OutputSummary, Stability, Unknown};
use crate::stability::{Hill, StabilityOptions};

/// Settings of [`cycle`]; `omega` must be set.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleOptions {
    /// The frequency guess, rad/s: the linearised mode nearest it is followed.
    pub omega: f64,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// Output amplitudes searched: from `start` up to `max` (max |x(t)| of the first
    /// output).
    pub start: f64,
    /// See `start`.
    pub max: f64,
}

impl Default for CycleOptions {
    fn default() -> Self {
        CycleOptions {
            omega: f64::NAN,
            harmonics: crate::fourier::DEFAULT_HARMONICS,
            start: 1e-4,
            max: 1e4,
        }
    }
}

/// A limit cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Cycle {
    /// The model's name (set by the caller that knows it).
    pub model: String,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The linearised mode it was found from (1-based).
    pub mode: usize,
    /// Angular frequency ω, rad/s, and the period 2π/ω.
    pub omega: f64,
    /// See `omega`.
    pub period: f64,
    /// Fourier coefficients (harmonics of ω).
    pub coeffs: Vec<f64>,
    /// Every output with its harmonics.
    pub outputs: Vec<OutputSummary>,
    /// Hill's verdict without the zero exponent of the phase.
    pub stability: Stability,
    /// The exponents other than the phase's (central, by decreasing real part).
    pub exponents: Vec<num_complex::Complex64>,
    /// The nonlinear mode traced from the equilibrium to the cycle.
    pub branch: Backbone,
}

/// The limit cycle of `model` near the frequency `opts.omega`; see the module
/// documentation.
///
/// Errors for bad input (a guess that is not a positive frequency, a model whose
/// modes are not oscillatory), and when no cycle is found: the mode's artificial
/// damping keeps its sign up to the largest amplitude searched (no self-excitation),
/// or the branch fails before (the reason, and where).
pub fn cycle(model: &dyn DynModel, opts: &CycleOptions) -> Result<Cycle> {
    if !(opts.omega > 0.0 && opts.omega.is_finite()) {
        return Err(Error::InvalidValue {
            what: "frequency guess".into(),
            value: opts.omega.to_string(),
            expected: "a finite frequency > 0 rad/s".into(),
        });
    }
    let ndof = model.dofs().len();
    let mut best: Option<(usize, f64)> = None;
    for k in 1..=ndof {
        let m = super::linear_mode(model, k)?;
        let d = (m.omega - opts.omega).abs();
        if best.is_none_or(|(_, b)| d < b) {
            best = Some((k, d));
        }
    }
    let mode = best.map_or(1, |b| b.0);
    let bo =
        BackboneOptions { mode, harmonics: opts.harmonics, max_steps: 500, ..Default::default() };
    let branch = BackboneContinuation::start(model, &bo, Goal::ZeroDamping(opts.max), opts.start)?
        .run(&mut ());
    let Some(last) = branch.points.last().filter(|_| branch.ended == End::ReachedAmplitude) else {
        return Err(Error::NoLimitCycle { omega: opts.omega, mode, ended: branch.ended.clone() });
    };
    let omega = last.omega;
    if last.outputs.iter().all(|o| o.max_abs <= 10.0 * opts.start) {
        return Err(Error::CycleCollapses {
            omega,
            amplitude: last.outputs.first().map_or(0.0, |o| o.max_abs),
        });
    }
    let coeffs = last.coeffs.clone();
    let params = model.param_values();
    let at = At::model(model, &params, omega);
    let outputs = OutputEval::new(model, opts.harmonics, 1).summaries(&at, &coeffs);
    let (stability, exponents) = match autonomous_stability(model, opts.harmonics, &coeffs, omega) {
        Ok(x) => x,
        Err(e) => (Stability::Unknown(Unknown::Failed(e.to_string())), Vec::new()),
    };
    Ok(Cycle {
        model: model.name().to_string(),
        harmonics: opts.harmonics,
        mode,
        omega,
        period: 2.0 * std::f64::consts::PI / omega,
        coeffs,
        outputs,
        stability,
        exponents,
        branch,
    })
}

/// Hill's method at the cycle, with the exponent nearest 0 (the phase) left out.
pub(super) fn autonomous_stability(
    model: &dyn DynModel,
    harmonics: usize,
    coeffs: &[f64],
    omega: f64,
) -> Result<(Stability, Vec<num_complex::Complex64>)> {
    let mut bal = Balance::new(model, harmonics)?;
    let mut hill = Hill::new(model, harmonics)?;
    let opts = StabilityOptions::default();
    let f = hill.analyse(&mut bal, coeffs, omega, &opts)?;
    let exps = super::stability::without_phase(f.exponents);
    let stable = exps.iter().all(|l| l.re <= opts.tol * omega);
    Ok((if stable { Stability::Stable } else { Stability::Unstable }, exps))
}
