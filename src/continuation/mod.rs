//! Continuation: whole amplitude–frequency (or amplitude–parameter) curves, with
//! folds, jumps, runaway branches and the stability of every point.
//!
//! # Method
//!
//! Pseudo-arc-length continuation of `R(a, λ) = 0` (the harmonic balance residual;
//! `λ` is Ω, or a model parameter at fixed Ω) in scaled variables
//! `y = [a / s_a, λ / s_λ]` (`s_a` the largest Fourier coefficient of the linearised
//! response over the range, `s_λ` the length of the range), so that micrometre
//! amplitudes and 100 rad/s frequencies weigh alike in the arc length.
//!
//! - *Predictor*: along the unit tangent (default) or the secant of the last two points.
//! - *Corrector*: Newton on `R = 0` bordered by the hyperplane through the predicted
//!   point orthogonal to the predictor direction; one LU of the `(n+1)×(n+1)` bordered
//!   matrix per iteration. The same LU gives the new tangent.
//! - *Step control*: the step grows when the corrector needs few iterations and the
//!   tangent turns little, shrinks otherwise; halved on failure down to
//!   [`SweepOptions::min_step`], where the segment ends `"stalled: <reason>"`.
//! - *Folds*: the λ-component of the tangent changes sign; the fold is then located
//!   by regula falsi (Illinois) on that component along the arc, to `|t_λ| < 1e-13`,
//!   i.e. far below 1e-8 relative in λ (λ is quadratic in the arc near a fold).
//! - *Runaway branches*: a point beyond the amplitude bound ends the segment
//!   ("amplitude bound"); the sweep then restarts from the other end of the range,
//!   going backwards. A stalled segment does the same. Both pieces are returned and
//!   nothing computed is discarded.
//! - *Stability*: Hill's method at every point ([`crate::stability`]), the exponents
//!   tracked from point to point with a full eigensolve as fallback; a change of
//!   stability that is not a fold is located along the arc and reported as a
//!   bifurcation (period doubling, torus, branch point).
//! - *Jumps*: slow up and down sweeps are simulated on the traced curve: follow the
//!   stable branch until it folds back, then drop to the other stable branch at the
//!   same λ ([`Jump`](crate::results::Jump), one per output).
//!
//! ```
//! use ihbm::continuation::{sweep, SweepOptions};
//! use ihbm::models::Duffing;
//!
//! // A hardening Duffing oscillator: two folds, a jump in each direction.
//! let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
//! let opts = SweepOptions { harmonics: 1, ..Default::default() };
//! let curve = sweep(&model, 0.5, 2.5, &opts).unwrap();
//! assert_eq!(curve.folds.len(), 2);
//! assert!(curve.jumps.iter().any(|j| j.direction == ihbm::results::Direction::Up));
//! ```

mod convergence;
mod events;
mod jumps;
mod locate;
pub(crate) mod path;
mod step_size;
mod stepper;
pub(crate) mod tracer;

use crate::error::{Error, Result};
use crate::model::{DynModel, Model, Order};
use crate::results::Curve;
use crate::stability::StabilityOptions;
use convergence::with_convergence;
use tracer::Axis;

pub use events::{Control, Event, Observer, Trace};
pub use step_size::StepSize;
pub use stepper::{Continuation, LOG_RANGE};

/// Predictor direction (`tangent`, `secant` on the command line and in study files).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Predictor {
    /// The unit tangent at the last point (exact, one extra solve per step).
    Tangent,
    /// The secant through the last two points (the tangent at the first).
    Secant,
}

/// When a branch counts as running away. Written `rel:F`, `abs:A`, `none`, or a plain
/// number (`abs:`), on the command line and in study files.
///
/// ```
/// use ihbm::continuation::AmplitudeBound;
/// assert_eq!("rel:1e3".parse::<AmplitudeBound>(), Ok(AmplitudeBound::Relative(1e3)));
/// assert_eq!(AmplitudeBound::Absolute(0.5).to_string(), "abs:0.5");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AmplitudeBound {
    /// This many times the largest Fourier coefficient of the linearised response
    /// over the range (sampled at 17 values of λ).
    Relative(f64),
    /// Any output's `max_abs` above this value (in the model's units).
    Absolute(f64),
    /// No bound.
    None,
}

/// What a valid amplitude bound looks like (for error messages).
pub const BOUND_SYNTAX: &str =
    "rel:F, abs:A or none, with F and A finite numbers > 0 (e.g. rel:1e3, abs:0.5)";

/// A text that is not an amplitude bound: what one looks like ([`BOUND_SYNTAX`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("expected {}", BOUND_SYNTAX)]
pub struct InvalidBound;

impl std::str::FromStr for AmplitudeBound {
    type Err = InvalidBound;
    fn from_str(s: &str) -> std::result::Result<Self, InvalidBound> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("none") {
            return Ok(AmplitudeBound::None);
        }
        let (kind, num) = match t.split_once(':') {
            Some((k, v)) => (k.trim().to_ascii_lowercase(), v.trim()),
            None => ("abs".to_string(), t),
        };
        let x = match num.parse::<f64>() {
            Ok(x) if x.is_finite() && x > 0.0 => x,
            _ => return Err(InvalidBound),
        };
        match kind.as_str() {
            "rel" => Ok(AmplitudeBound::Relative(x)),
            "abs" => Ok(AmplitudeBound::Absolute(x)),
            _ => Err(InvalidBound),
        }
    }
}

impl std::fmt::Display for AmplitudeBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AmplitudeBound::Relative(x) => write!(f, "rel:{x}"),
            AmplitudeBound::Absolute(x) => write!(f, "abs:{x}"),
            AmplitudeBound::None => write!(f, "none"),
        }
    }
}

impl serde::Serialize for AmplitudeBound {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> serde::Deserialize<'de> for AmplitudeBound {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = AmplitudeBound;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "{BOUND_SYNTAX}, or a number (abs:)")
            }
            fn visit_str<E: serde::de::Error>(
                self,
                v: &str,
            ) -> std::result::Result<Self::Value, E> {
                v.parse()
                    .map_err(|m: InvalidBound| E::custom(format!("amplitude_bound '{v}': {m}")))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Self::Value, E> {
                self.visit_str(&v.to_string())
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Self::Value, E> {
                self.visit_str(&v.to_string())
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Self::Value, E> {
                self.visit_str(&v.to_string())
            }
        }
        d.deserialize_any(V)
    }
}

/// Rerun a curve with more harmonics until it stops changing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergenceOptions {
    /// Tolerance on the relative change of peak amplitudes and fold parameters.
    pub tol: f64,
    /// Harmonics added per level (2 keeps odd-only responses comparable).
    pub increment: usize,
    /// Give up above this many harmonics.
    pub max_harmonics: usize,
}

impl Default for ConvergenceOptions {
    fn default() -> Self {
        ConvergenceOptions { tol: 1e-3, increment: 2, max_harmonics: 25 }
    }
}

/// Settings of a sweep. Steps are in scaled units (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepOptions {
    /// Number of harmonics N.
    pub harmonics: usize,
    /// First step.
    pub initial_step: f64,
    /// Smallest step before a segment is declared stalled.
    pub min_step: f64,
    /// Largest step (scaled by the response where it exceeds the reference amplitude,
    /// so that a branch climbing an asymptote is followed in relative steps).
    pub max_step: f64,
    /// Largest turn of the tangent per step, radians (steps shrink to respect it).
    pub max_turn: f64,
    /// Predictor direction.
    pub predictor: Predictor,
    /// Newton tolerance on the scaled step (max-norm).
    pub tol: f64,
    /// Newton iterations per corrector call of a step (a failure halves the step).
    /// The solves that locate a point rather than step to it (the first point, folds,
    /// the end of the range, stability changes, jump landings) get at least 30.
    pub max_iter: usize,
    /// Accepted steps per sweep before giving up ("stalled: step limit").
    pub max_steps: usize,
    /// When a branch runs away.
    pub amplitude_bound: AmplitudeBound,
    /// Stability of every point; `None` skips it: all points are then reported stable
    /// (and [`Curve::stability_checked`] is `false`), no stability changes are found,
    /// and jumps may land on unstable branches.
    pub stability: Option<StabilityOptions>,
    /// Harmonic convergence study; `None` runs once with `harmonics`.
    pub convergence: Option<ConvergenceOptions>,
    /// Solutions that repeat every `period` forcing periods (1: the usual; 2: a
    /// period-doubled branch). With `period` > 1 the continuation runs in `ω = Ω/period`
    /// and the harmonics of `ω` ([`Balance::with_period`](crate::balance::Balance::with_period)).
    pub period: usize,
    /// Locate the resonance peaks ([`Curve::peaks`]: every local maximum of an
    /// output's `max_abs` along the curve). Each costs about six corrector
    /// iterations; `false` skips them (the fold analyses' sweeps, which need folds
    /// only). The command line, studies and Python always locate them.
    pub peaks: bool,
}

impl SweepOptions {
    /// The step-size rule of a path with these options, whose corrector counts
    /// `easy` iterations as no effort ([`StepSize::easy`]).
    pub fn step_size(&self, easy: usize) -> StepSize {
        StepSize { min: self.min_step, max: self.max_step, max_turn: self.max_turn, easy }
    }
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            harmonics: crate::fourier::DEFAULT_HARMONICS,
            initial_step: 0.01,
            min_step: 1e-6,
            max_step: 0.1,
            max_turn: 0.12,
            predictor: Predictor::Tangent,
            tol: 1e-10,
            max_iter: 8,
            max_steps: 20_000,
            amplitude_bound: AmplitudeBound::Relative(1e3),
            stability: Some(StabilityOptions::default()),
            convergence: None,
            period: 1,
            peaks: true,
        }
    }
}

/// Trace the branch that leaves the solution `a0` at Ω = `omega0` along the coefficient
/// direction `v` (branch switching: [`crate::bifurcation::period_two`]), for Ω in
/// `[from, to]`. The first point is a step of `step` (relative to the largest
/// coefficient of `a0`) along `v`; the branch is traced one way, until it leaves the
/// range or crosses back through the solutions it left (its component along `v` in
/// the coefficients of `mask`, which those solutions lack, changes sign).
#[allow(clippy::too_many_arguments)]
pub fn sweep_branch(
    model: &dyn DynModel,
    from: f64,
    to: f64,
    opts: &SweepOptions,
    a0: &[f64],
    omega0: f64,
    v: &[f64],
    mask: &[bool],
    step: f64,
) -> Result<Curve> {
    check_sweep(model, from, to, opts)?;
    let mask = mask.to_vec();
    let branch =
        stepper::Branch { a0: a0.to_vec(), omega0, v: v.to_vec(), step, mask, start_size: 0.0 };
    let c = Continuation::new(model, tracer::Axis::Omega, from, to, opts)?.with_branch(branch);
    Ok(c.run(&mut ()))
}

/// Trace the amplitude–frequency curve of `model` for Ω from `from` to `to` (rad/s).
///
/// Errors only for bad input (`from >= to`, non-finite or non-positive frequencies,
/// N = 0, invalid model parameters). Numerical trouble ends a segment and is reported
/// in [`Curve::segments`]; the curve is returned with everything computed.
pub fn sweep(model: &dyn DynModel, from: f64, to: f64, opts: &SweepOptions) -> Result<Curve> {
    sweep_with(model, from, to, opts, &mut ())
}

/// [`sweep`] watched by `observer`, which sees every [`Event`] and may stop the run
/// (the curve then holds what was traced: one step's events all come after the step,
/// so a stop at a fold keeps the point after it too). With a harmonic-convergence study, each
/// level is one run, ending with [`Event::Finished`]; a stop ends the study there.
///
/// ```
/// use ihbm::continuation::{sweep_with, Control, Event, SweepOptions, Trace};
/// use ihbm::models::Duffing;
///
/// let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
/// let opts = SweepOptions { harmonics: 1, ..Default::default() };
/// let mut traced = 0;
/// let mut stop_at_fold = |e: &Event, t: &Trace| match e {
///     Event::Fold(_) => {
///         traced = t.points.len();
///         Control::Stop
///     }
///     _ => Control::Continue,
/// };
/// let curve = sweep_with(&model, 0.5, 2.5, &opts, &mut stop_at_fold)?;
/// // Everything traced when it stopped is kept: the fold and the step that found it.
/// assert_eq!((curve.folds.len(), curve.points.len()), (1, traced));
/// # Ok::<(), ihbm::Error>(())
/// ```
pub fn sweep_with(
    model: &dyn DynModel,
    from: f64,
    to: f64,
    opts: &SweepOptions,
    observer: &mut dyn Observer,
) -> Result<Curve> {
    check_sweep(model, from, to, opts)?;
    with_convergence(opts, |o| run(Continuation::new(model, Axis::Omega, from, to, o)?, observer))
}

/// Trace the response of `model` at fixed frequency `omega` as parameter `param`
/// goes from `from` to `to`. The parameter derivative comes from the dual-number
/// residual ([`Balance::d_param`](crate::balance::Balance::d_param)). A range with an
/// end outside the parameter's [`Domain`](crate::model::Domain) is refused before
/// anything is computed.
pub fn sweep_param(
    model: &dyn DynModel,
    param: &str,
    from: f64,
    to: f64,
    omega: f64,
    opts: &SweepOptions,
) -> Result<Curve> {
    sweep_param_with(model, param, from, to, omega, opts, &mut ())
}

/// [`sweep_param`] watched by `observer` (as in [`sweep_with`]).
pub fn sweep_param_with(
    model: &dyn DynModel,
    param: &str,
    from: f64,
    to: f64,
    omega: f64,
    opts: &SweepOptions,
    observer: &mut dyn Observer,
) -> Result<Curve> {
    let index = check_sweep_param(model, param, from, to, omega, opts)?;
    let axis = Axis::Param { index, omega };
    with_convergence(opts, |o| run(Continuation::new(model, axis, from, to, o)?, observer))
}

/// Run to the end or to the observer's stop: the curve, and whether it was stopped.
fn run(mut c: Continuation<'_>, observer: &mut dyn Observer) -> Result<(Curve, bool)> {
    let stopped = c.drive(observer);
    Ok((c.finish(), stopped))
}

/// The checks of a frequency sweep.
fn check_sweep(model: &dyn DynModel, from: f64, to: f64, opts: &SweepOptions) -> Result<()> {
    check_range("frequency", from, to)?;
    if from <= 0.0 {
        return Err(invalid("start frequency", from, "a positive frequency in rad/s"));
    }
    check_options(opts)?;
    model.validate()
}

/// The checks of a parameter sweep; the parameter's index.
fn check_sweep_param(
    model: &dyn DynModel,
    param: &str,
    from: f64,
    to: f64,
    omega: f64,
    opts: &SweepOptions,
) -> Result<usize> {
    let index = model.param_index(param)?;
    check_range(&format!("range of {param}"), from, to)?;
    if !(omega.is_finite() && omega > 0.0) {
        return Err(invalid("frequency", omega, "a positive frequency in rad/s"));
    }
    if model.signals().iter().any(|s| s.order == Order::Param(index)) && !(0.0 <= from && to <= 2.0)
    {
        return Err(invalid(
            &format!("range of fractional order {param}"),
            if from < 0.0 { from } else { to },
            "a range inside [0, 2]",
        ));
    }
    // The domain is an interval: with both ends in it, no step leaves it.
    let info = &model.params_info()[index];
    for v in [from, to] {
        crate::model::check_domain(model.name(), info, &format!("end of the range of {param}"), v)?;
    }
    check_options(opts)?;
    model.validate()?;
    Ok(index)
}

/// Frequency sweeps of a family of models that differ in `param`, run in parallel
/// (rayon, one curve per task; feature `parallel`). One result per value, in order.
#[cfg(feature = "parallel")]
pub fn sweep_family(
    model: &dyn DynModel,
    param: &str,
    values: &[f64],
    from: f64,
    to: f64,
    opts: &SweepOptions,
) -> Vec<Result<Curve>> {
    use rayon::prelude::*;
    values
        .par_iter()
        .map(|&v| {
            let mut m = crate::model::WithParams::new(model);
            m.set_param(param, v)?;
            sweep(&m, from, to, opts)
        })
        .collect()
}

fn invalid(what: &str, value: f64, expected: &str) -> Error {
    Error::InvalidValue { what: what.into(), value: value.to_string(), expected: expected.into() }
}

fn check_range(what: &str, from: f64, to: f64) -> Result<()> {
    if !from.is_finite() {
        return Err(invalid(&format!("{what} start"), from, "a finite number"));
    }
    if !to.is_finite() {
        return Err(invalid(&format!("{what} end"), to, "a finite number"));
    }
    if from >= to {
        return Err(Error::InvalidValue {
            what: what.into(),
            value: format!("{from} .. {to}"),
            expected: "from < to".into(),
        });
    }
    if to - from <= MIN_RELATIVE_WIDTH * from.abs().max(to.abs()) {
        return Err(Error::InvalidValue {
            what: what.into(),
            value: format!("{from} .. {to}"),
            expected: format!(
                "a range wider than {MIN_RELATIVE_WIDTH:e} of its ends (events are located to 1e-8 relative; a narrower range holds nothing the continuation can resolve)"
            ),
        });
    }
    Ok(())
}

/// The narrowest range a continuation accepts, relative to the larger of its ends: a
/// range a few rounding units wide made the step controller pile its whole step
/// budget (20 000 points) on it.
pub const MIN_RELATIVE_WIDTH: f64 = 1e-9;

fn check_options(o: &SweepOptions) -> Result<()> {
    crate::fourier::check_harmonics(o.harmonics)?;
    let steps_ok = o.min_step > 0.0 && o.min_step <= o.initial_step && o.initial_step <= o.max_step;
    if !steps_ok || !o.max_step.is_finite() {
        return Err(Error::InvalidValue {
            what: "continuation steps".into(),
            value: format!("min {} initial {} max {}", o.min_step, o.initial_step, o.max_step),
            expected: "0 < min <= initial <= max, finite".into(),
        });
    }
    let positive = |x: f64| x > 0.0;
    if !positive(o.tol) || o.max_iter == 0 || !positive(o.max_turn) {
        return Err(Error::InvalidValue {
            what: "corrector settings".into(),
            value: format!("tol {} max_iter {} max_turn {}", o.tol, o.max_iter, o.max_turn),
            expected: "positive values".into(),
        });
    }
    Ok(())
}
