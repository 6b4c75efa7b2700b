//! A limit cycle continued in a model parameter, with the Hopf point it is born at.
//!
//! The family starts at the cycle of [`super::cycle`] at the first value of the
//! parameter P and follows it by pseudo-arclength in `(â, ω, P, ln q)`: the extended
//! system of [`super::epmc`] with the artificial damping held at 0 and P among the
//! unknowns instead. Writing the coefficients as `q â` keeps the system regular as the
//! cycle shrinks towards the equilibrium (`q → 0`, the Hopf point), where a family
//! written in the coefficients themselves would meet the trivial solution. The
//! family ends at the other value of P, when the cycle collapses to the equilibrium
//! (its amplitude falls below [`FamilyOptions::collapse`] of the first cycle's), or
//! when the corrector fails at the smallest step; the points traced are kept either
//! way. Every point's stability is Hill's method on the autonomous problem, with the
//! one exponent at 0 (the phase: a shift in time is no perturbation) left out.
//!
//! The Hopf point is located from the equilibrium's linearisation ([`super::hopf`]):
//! the pair of eigenvalues of `Z(λ) φ = 0` that belongs to the cycle's mode, followed
//! along the family's values of P, and the value where its real part changes sign.

use super::cycle::autonomous_stability;
use super::epmc::Free;
use super::{hopf, system, BackboneOptions, Goal, Tracer};
use crate::continuation::tracer::LOCATE_ITER;
use crate::continuation::Control;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::outputs::OutputEval;
use crate::results::{PointOutput, Stability, Stall, Unknown};

/// Settings of [`cycles`]; `param`, `from`, `to` and `omega` must be set.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyOptions {
    /// The parameter continued (its name).
    pub param: String,
    /// The parameter's first value (the family starts at the cycle there) and last.
    pub from: f64,
    /// See `from`.
    pub to: f64,
    /// The frequency guess of the first cycle, rad/s ([`super::CycleOptions::omega`]).
    pub omega: f64,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The family has collapsed to the equilibrium when the first output's
    /// `max |x(t)|` falls below this fraction of the first cycle's.
    pub collapse: f64,
    /// Newton tolerance (max-norm of the scaled update).
    pub tol: f64,
    /// First step, and its bounds, in the scaled unknowns (P over the length of its
    /// range, ω over the linear mode's frequency, the log of the modal amplitude).
    pub initial_step: f64,
    /// Smallest step before the family is given up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Points at most.
    pub max_steps: usize,
}

impl Default for FamilyOptions {
    fn default() -> Self {
        let b = BackboneOptions::default();
        FamilyOptions {
            param: String::new(),
            from: f64::NAN,
            to: f64::NAN,
            omega: f64::NAN,
            harmonics: crate::fourier::DEFAULT_HARMONICS,
            collapse: 1e-3,
            tol: b.tol,
            initial_step: 0.02,
            min_step: b.min_step,
            max_step: 0.05,
            max_steps: 2000,
        }
    }
}

/// One limit cycle of a family.
#[derive(Debug, Clone, PartialEq)]
pub struct CyclePoint {
    /// The parameter's value.
    pub value: f64,
    /// Angular frequency ω, rad/s, and the period 2π/ω.
    pub omega: f64,
    /// See `omega`.
    pub period: f64,
    /// The modal amplitude q (first harmonic, mass-weighted).
    pub amplitude: f64,
    /// Fourier coefficients (harmonics of ω).
    pub coeffs: Vec<f64>,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
    /// Hill's verdict without the zero exponent of the phase.
    pub stability: Stability,
}

/// Where the equilibrium loses (or gains) stability through a pair of eigenvalues
/// crossing the imaginary axis: the cycle's birth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hopf {
    /// The parameter's value P_H.
    pub value: f64,
    /// The crossing pair's frequency ω_H = Im λ, rad/s.
    pub omega: f64,
}

/// Why a family ended.
#[derive(Debug, Clone, PartialEq)]
pub enum FamilyEnd {
    /// The parameter reached the end of its range (the last point is there).
    Reached,
    /// The cycle shrank to the equilibrium (the last point is the smallest traced).
    Collapsed,
    /// The corrector failed at the smallest step, or the step limit; the reason.
    Stalled(Stall),
    /// An observer stopped it.
    Stopped,
}

impl std::fmt::Display for FamilyEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FamilyEnd::Reached => write!(f, "reached the end of the range"),
            FamilyEnd::Collapsed => write!(f, "collapsed to the equilibrium"),
            FamilyEnd::Stalled(why) => write!(f, "stalled: {why}"),
            FamilyEnd::Stopped => write!(f, "stopped"),
        }
    }
}

/// A family of limit cycles in a parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleFamily {
    /// The model's name (set by the caller that knows it).
    pub model: String,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The parameter's name and the range asked for (`from`, `to`).
    pub parameter: String,
    /// See `parameter`.
    pub range: (f64, f64),
    /// The parameter's index in the model's parameters.
    pub param_index: usize,
    /// The linearised mode the first cycle was found from (1-based).
    pub mode: usize,
    /// Output names, in model order.
    pub output_names: Vec<String>,
    /// Points, by increasing arc length from the first cycle.
    pub points: Vec<CyclePoint>,
    /// The Hopf point of the cycle's mode in the range covered (from the first value
    /// to the last point's, or to the end of the range when the family collapsed or
    /// stalled), if the equilibrium's pair crosses the imaginary axis there.
    pub hopf: Option<Hopf>,
    /// Why it ended.
    pub ended: FamilyEnd,
    /// Newton iterations and accepted steps.
    pub iterations: usize,
    /// See `iterations`.
    pub steps: usize,
}

/// The family of limit cycles of `model` as parameter `opts.param` goes from
/// `opts.from` to `opts.to`; see the module documentation.
///
/// Errors for bad input (an unknown parameter, an empty or non-finite range, a range
/// outside the parameter's domain, a frequency guess that is not positive) and when there is no cycle at `opts.from`
/// near the guess, or it is the equilibrium itself. A family that ends before `to`
/// is not an error: it says why ([`CycleFamily::ended`]) and keeps its points.
pub fn cycles<M: Model + Clone>(model: &M, opts: &FamilyOptions) -> Result<CycleFamily> {
    cycles_with(model, opts, &mut |_: &CycleFamily| Control::Continue)
}

/// [`cycles`], calling `observer` after every accepted point (it may stop the run).
pub fn cycles_with<M: Model + Clone>(
    model: &M,
    opts: &FamilyOptions,
    observer: &mut dyn FnMut(&CycleFamily) -> Control,
) -> Result<CycleFamily> {
    let index = model.param_index(&opts.param)?;
    let (from, to) = (opts.from, opts.to);
    if !(from.is_finite() && to.is_finite() && from != to) {
        return Err(Error::InvalidValue {
            what: format!("range of {}", opts.param),
            value: format!("{from} to {to}"),
            expected: "two different finite values".into(),
        });
    }
    // The domain is an interval: with both ends in it, so is the whole range.
    let info = &model.params_info()[index];
    for v in [from, to] {
        let what = format!("end of the range of {}", opts.param);
        crate::model::check_domain(model.name(), info, &what, v)?;
    }
    let mut m0 = model.clone();
    m0.set_param_value(index, from);
    let co =
        super::CycleOptions { omega: opts.omega, harmonics: opts.harmonics, ..Default::default() };
    let first = super::cycle(&m0, &co).map_err(|e| {
        Error::Other(format!("no limit cycle to continue at {} = {from}: {e}", opts.param))
    })?;
    let start = first.branch.points.last().ok_or_else(|| {
        Error::Other(format!("no limit cycle to continue at {} = {from}", opts.param))
    })?;
    let (mut sys, _, _) = system(&m0, first.mode, opts.harmonics, opts.tol)?;
    let scale = (to - from).abs();
    sys.free = Free::Param { index, scale };
    let n = sys.n;
    let q = start.amplitude;
    let mut y: Vec<f64> = start.coeffs.iter().map(|c| c / q).collect();
    y.extend([start.omega / sys.so, from / scale, q.ln()]);
    let mut ep = vec![0.0; n + 3];
    ep[n + 1] = 1.0;
    sys.correct(&mut y, &ep, from / scale, LOCATE_ITER).map_err(|why| Stall::CycleStart {
        parameter: opts.param.clone(),
        value: from,
        cause: Box::new(why),
    })?;
    let mut t = sys.tangent();
    let dir = (to - from).signum();
    if t[n + 1] * dir < 0.0 {
        t.iter_mut().for_each(|v| *v = -*v);
    }
    let bo = BackboneOptions {
        tol: opts.tol,
        initial_step: opts.initial_step,
        min_step: opts.min_step,
        max_step: opts.max_step,
        max_steps: opts.max_steps,
        harmonics: opts.harmonics,
        to: f64::INFINITY,
        ..Default::default()
    };
    let eval = OutputEval::new(&m0, opts.harmonics);
    let mut tracer = Tracer {
        sys,
        eval,
        h: opts.initial_step,
        opts: bo,
        goal: Goal::Amplitude(f64::INFINITY),
        others: Vec::new(),
        // every cycle's verdict comes from its own parameter value, below
        stability: None,
    };
    let mut fam = CycleFamily {
        model: model.name().to_string(),
        harmonics: opts.harmonics,
        parameter: opts.param.clone(),
        range: (from, to),
        param_index: index,
        mode: first.mode,
        output_names: m0.outputs().iter().map(|o| o.name.to_string()).collect(),
        points: Vec::new(),
        hopf: None,
        ended: FamilyEnd::Stopped,
        iterations: 0,
        steps: 0,
    };
    let at = |tracer: &mut Tracer<'_, M>, y: &[f64]| {
        let p = tracer.point(y);
        let value = tracer.sys.param(y);
        let mut mp = model.clone();
        mp.set_param_value(index, value);
        let stability = match autonomous_stability(&mp, opts.harmonics, &p.coeffs, p.omega) {
            Ok((s, _)) => s,
            Err(e) => Stability::Unknown(Unknown::Failed(e.to_string())),
        };
        CyclePoint {
            value,
            omega: p.omega,
            period: 2.0 * std::f64::consts::PI / p.omega,
            amplitude: p.amplitude,
            coeffs: p.coeffs,
            outputs: p.outputs,
            stability,
        }
    };
    fam.points.push(at(&mut tracer, &y));
    let size = |p: &CyclePoint| p.outputs.first().map_or(p.amplitude, |o| o.max_abs);
    let first_size = size(&fam.points[0]);
    fam.ended = if observer(&fam) == Control::Stop {
        FamilyEnd::Stopped
    } else {
        loop {
            if fam.points.len() >= opts.max_steps {
                break FamilyEnd::Stalled(Stall::StepLimit { steps: opts.max_steps });
            }
            let step = match tracer.advance(&y, &t) {
                Ok(x) => x,
                Err(why) => break FamilyEnd::Stalled(why),
            };
            let z = &step.point;
            if (tracer.sys.param(z) - to) * dir >= 0.0 {
                // land on P = to between y and z
                let (pa, pb) = (tracer.sys.param(&y), tracer.sys.param(z));
                let f = (to - pa) / (pb - pa);
                let mut w: Vec<f64> = y.iter().zip(z).map(|(a, b)| a + f * (b - a)).collect();
                break match tracer.sys.correct(&mut w, &ep, to / scale, LOCATE_ITER) {
                    Ok(_) => {
                        fam.points.push(at(&mut tracer, &w));
                        fam.steps += 1;
                        FamilyEnd::Reached
                    }
                    Err(why) => FamilyEnd::Stalled(Stall::LandParameter {
                        parameter: opts.param.clone(),
                        value: to,
                        cause: Box::new(why),
                    }),
                };
            }
            let p = at(&mut tracer, z);
            let collapsed = size(&p) < opts.collapse * first_size;
            fam.points.push(p);
            fam.steps += 1;
            if collapsed {
                break FamilyEnd::Collapsed;
            }
            tracer.adapt(&step);
            (y, t) = (step.point, step.tangent);
            if observer(&fam) == Control::Stop {
                break FamilyEnd::Stopped;
            }
        }
    };
    fam.iterations = tracer.sys.iterations;
    // the values of P the family covered, in order, and the rest of the range when
    // it ended before
    let mut values: Vec<f64> = fam.points.iter().map(|p| p.value).collect();
    if fam.ended != FamilyEnd::Reached {
        values.push(to);
    }
    fam.hopf = hopf::locate(model, index, first.mode, &values);
    Ok(fam)
}
