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
use crate::continuation::path::Extended;
use crate::continuation::tracer::LOCATE_ITER;
use crate::continuation::{Control, Observer};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::model::{DynModel, WithParams};
use crate::outputs::OutputEval;
use crate::results::{End, PointOutput, Stability, Stall, Unknown};

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
    pub ended: End,
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
pub fn cycles(model: &dyn DynModel, opts: &FamilyOptions) -> Result<CycleFamily> {
    cycles_with(model, opts, &mut ())
}

/// [`cycles`], reporting every point to `observer`, which may stop the run (what is
/// traced is returned, ended [`End::Stopped`], with the Hopf point in the
/// range covered).
pub fn cycles_with(
    model: &dyn DynModel,
    opts: &FamilyOptions,
    observer: &mut dyn Observer<FamilyEvent, CycleFamily>,
) -> Result<CycleFamily> {
    Ok(CycleContinuation::new(model, opts)?.run(observer))
}

/// What [`CycleContinuation::step`] produced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FamilyEvent {
    /// A cycle was accepted: `points[i]` (the first is the cycle at `from`).
    Point(usize),
    /// Nothing more to trace: `ended` says why, and
    /// [`finish`](CycleContinuation::finish) gives the family with its Hopf point.
    /// Every later `step` returns `Finished` again.
    Finished,
}

/// A family of limit cycles driven step by step, as
/// [`Continuation`](crate::continuation::Continuation) drives a sweep:
/// [`new`](Self::new) finds the first cycle, each [`step`](Self::step) takes one
/// pseudo-arclength step in the parameter, and [`finish`](Self::finish) locates the
/// Hopf point in the range covered and gives the family, ended
/// [`End::Stopped`] if it was not done.
///
/// ```
/// use ihbm::backbone::{CycleContinuation, FamilyEvent, FamilyOptions};
/// use ihbm::models::VanDerPol;
///
/// let opts = FamilyOptions {
///     param: "mu".into(), from: 0.5, to: -0.5, omega: 1.0, harmonics: 9,
///     ..Default::default()
/// };
/// let model = VanDerPol::default();
/// let mut run = CycleContinuation::new(&model, &opts).unwrap();
/// // five cycles, then stop: they are kept, and the Hopf point is looked for in
/// // the rest of the range too
/// while let FamilyEvent::Point(i) = run.step() {
///     if i == 4 {
///         break;
///     }
/// }
/// let f = run.finish();
/// assert_eq!((f.points.len(), f.ended.to_string().as_str()), (5, "stopped"));
/// assert!(f.hopf.unwrap().value.abs() < 1e-8); // the equilibrium turns at mu = 0
/// ```
pub struct CycleContinuation<'m> {
    model: &'m dyn DynModel,
    opts: FamilyOptions,
    index: usize,
    tracer: Tracer<'m>,
    /// The last accepted point and its tangent.
    y: Vec<f64>,
    t: Vec<f64>,
    /// The row that fixes the parameter (landing on `to`).
    ep: Vec<f64>,
    /// The first cycle's size, for [`FamilyOptions::collapse`].
    first_size: f64,
    res: CycleFamily,
    told: usize,
    done: bool,
}

impl<'m> CycleContinuation<'m> {
    /// Check the options and find the first cycle; errors as [`cycles`].
    pub fn new(model: &'m dyn DynModel, opts: &FamilyOptions) -> Result<Self> {
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
        let m0 = WithParams::with(model, index, from);
        let co = super::CycleOptions {
            omega: opts.omega,
            harmonics: opts.harmonics,
            ..Default::default()
        };
        let first = super::cycle(&m0, &co).map_err(|e| Error::NoCycleToContinue {
            parameter: opts.param.clone(),
            value: from,
            cause: Some(Box::new(e)),
        })?;
        let start = first.branch.points.last().ok_or_else(|| Error::NoCycleToContinue {
            parameter: opts.param.clone(),
            value: from,
            cause: None,
        })?;
        let (mut sys, _, _) =
            system(model, &m0, Some((index, from)), first.mode, opts.harmonics, opts.tol)?;
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
        if t[n + 1] * (to - from) < 0.0 {
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
        let tracer = Tracer {
            sys,
            eval: OutputEval::new(&m0, opts.harmonics, 1),
            h: opts.initial_step,
            opts: bo,
            goal: Goal::Amplitude(f64::INFINITY),
            others: Vec::new(),
            // every cycle's verdict comes from its own parameter value (`cycle_at`)
            stability: None,
        };
        let res = CycleFamily {
            model: model.name().to_string(),
            harmonics: opts.harmonics,
            parameter: opts.param.clone(),
            range: (from, to),
            param_index: index,
            mode: first.mode,
            output_names: m0.outputs().iter().map(|o| o.name.to_string()).collect(),
            points: Vec::new(),
            hopf: None,
            ended: End::Stopped,
            iterations: 0,
            steps: 0,
        };
        let mut run = CycleContinuation {
            model,
            opts: opts.clone(),
            index,
            tracer,
            y,
            t,
            ep,
            first_size: f64::NAN,
            res,
            told: 0,
            done: false,
        };
        let first = run.cycle_at(&run.y.clone());
        run.first_size = size(&first);
        run.res.points.push(first);
        run.res.iterations = run.tracer.sys.iterations;
        Ok(run)
    }

    /// Everything traced so far (the Hopf point is located by
    /// [`finish`](Self::finish)).
    pub fn traced(&self) -> &CycleFamily {
        &self.res
    }

    /// Report the last accepted cycle, or take the next step.
    pub fn step(&mut self) -> FamilyEvent {
        loop {
            if self.told < self.res.points.len() {
                self.told += 1;
                return FamilyEvent::Point(self.told - 1);
            }
            if self.done {
                return FamilyEvent::Finished;
            }
            if let Some(end) = self.advance() {
                self.res.ended = end;
                self.done = true;
            }
            self.res.iterations = self.tracer.sys.iterations;
        }
    }

    /// Step until the family is done or `observer` stops it; the family.
    pub fn run(mut self, observer: &mut dyn Observer<FamilyEvent, CycleFamily>) -> CycleFamily {
        loop {
            let e = self.step();
            if e == FamilyEvent::Finished || observer.observe(&e, &self.res) == Control::Stop {
                return self.finish();
            }
        }
    }

    /// The family traced, ended [`End::Stopped`] unless it was done, with the
    /// Hopf point in the range it covers (to the end of the range when it ended
    /// before).
    pub fn finish(mut self) -> CycleFamily {
        if !self.done {
            self.res.ended = End::Stopped;
        }
        let f = &mut self.res;
        let mut values: Vec<f64> = f.points.iter().map(|p| p.value).collect();
        if f.ended != End::ReachedEnd {
            values.push(f.range.1);
        }
        f.hopf = hopf::locate(self.model, self.index, f.mode, &values);
        self.res
    }

    /// One pseudo-arclength step: the cycle accepted (pushed), or the family's end.
    fn advance(&mut self) -> Option<End> {
        let (to, max_steps) = (self.opts.to, self.opts.max_steps);
        if self.res.points.len() >= max_steps {
            return Some(End::Stalled(Stall::StepLimit { steps: max_steps }));
        }
        let (step, point, tangent) = match self.tracer.advance(&self.y, &self.t) {
            Ok(x) => x,
            Err(why) => return Some(End::Stalled(why)),
        };
        let z = &point;
        let dir = (to - self.opts.from).signum();
        if (self.tracer.sys.param(z) - to) * dir >= 0.0 {
            // land on P = to between y and z
            let (pa, pb) = (self.tracer.sys.param(&self.y), self.tracer.sys.param(z));
            let f = (to - pa) / (pb - pa);
            let mut w: Vec<f64> = self.y.iter().zip(z).map(|(a, b)| a + f * (b - a)).collect();
            let scale = (to - self.opts.from).abs();
            return Some(
                match self.tracer.sys.correct(&mut w, &self.ep, to / scale, LOCATE_ITER) {
                    Ok(_) => {
                        let p = self.cycle_at(&w);
                        self.res.points.push(p);
                        self.res.steps += 1;
                        End::ReachedEnd
                    }
                    Err(why) => End::Stalled(Stall::LandParameter {
                        parameter: self.opts.param.clone(),
                        value: to,
                        cause: Box::new(why),
                    }),
                },
            );
        }
        let p = self.cycle_at(z);
        let collapsed = size(&p) < self.opts.collapse * self.first_size;
        self.res.points.push(p);
        self.res.steps += 1;
        if collapsed {
            return Some(End::Collapsed);
        }
        self.tracer.adapt(&step);
        (self.y, self.t) = (point, tangent);
        None
    }

    /// The cycle at `y`, with its verdict at its own parameter value.
    fn cycle_at(&mut self, y: &[f64]) -> CyclePoint {
        let p = self.tracer.point(y);
        let value = self.tracer.sys.param(y);
        let mp = WithParams::with(self.model, self.index, value);
        let stability = match autonomous_stability(&mp, self.opts.harmonics, &p.coeffs, p.omega) {
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
    }
}

/// A cycle's size: the first output's `max |x(t)|` (the modal amplitude without one).
fn size(p: &CyclePoint) -> f64 {
    p.outputs.first().map_or(p.amplitude, |o| o.max_abs)
}
