//! Time-domain verification: integrate a model from rest and read its steady state.
//!
//! The integer-order part is stepped by Newmark's average-acceleration rule; every
//! fractional signal `D^q (Σ c x_d)` is a convolution quadrature on its displacement
//! history ([`Scheme::Gl`], the paper's first-order Grünwald–Letnikov rule, or
//! [`Scheme::Bdf2`], Lubich's second-order rule); each step is implicit (Newton with
//! the dual-number Jacobian of [`Model::residual`]). History sums use the FFT-based
//! fast convolution ([`Memory::Fast`], `O(n log² n)`) or the direct sum
//! ([`Memory::Naive`], `O(n²)`).
//!
//! The run starts from rest at `t = 0` with the Caputo derivative from 0, which for
//! zero initial displacement and velocity equals the Riemann–Liouville derivative, so
//! the plain quadrature needs no starting correction (see [`newmark`]).
//!
//! # Accuracy (measured by the tests in `tests/timedomain/`)
//!
//! - Observed orders over a fixed horizon from rest: GL 0.9–1.2, BDF2 2.00 on the
//!   fractional Duffing (p = 0.5 and 1.5) and the quarter car. Newmark is second
//!   order, so GL limits the whole scheme to first order.
//! - For a linear model the discrete scheme has an exact periodic response (trapezoid
//!   symbol `(2/dt) i tan(Ω dt/2)` for derivatives, `(δ(e^{-iΩdt})/dt)^q` for `D^q`);
//!   the simulated `max_abs` matches it to ~2e-9, and its distance to the exact
//!   response at the default T/400 is 3e-6..9e-5 (BDF2) and 4e-4..5e-3 (GL).
//! - Quarter car, k3 = 5e6, F = 0.01/0.02, Ω = 8 and 60 rad/s, BDF2, T/400, 20 s:
//!   `max_abs` within 4e-5 of harmonic balance (N = 9) for every output; halving dt
//!   divides the gap by 4, doubling the time changes it by < 2e-7.
//!
//! # The transient from rest is algebraic
//!
//! The fractional memory makes the approach to the periodic state a power law in
//! `t`, not an exponential: on a linear oscillator (p = 0.3) the gap to the periodic
//! response falls by a steady factor ~6.5 per doubling of `t` (≈ t^-2.7); on the
//! quarter car's body motion at 60 rad/s it is 1.3e-7 at 20 s, 4e-8 at 40 s.
//! [`simulate`] reports `drift` (relative change of `max_abs` between the last two
//! blocks of 10 periods) so a user can see whether a run was long enough. Starting
//! from the harmonic-balance state alone would not help: the Caputo history before
//! `t = 0` would be missing and leave a slower `t^-p` tail. With that history added
//! ([`Stepper::on_periodic`], [`PeriodicPast`]) a run starts on the periodic state
//! with no transient: the way to watch a perturbation of a branch grow or decay.
//!
//! # Choosing dt and periods
//!
//! The default `dt = T/400` gives ~1e-5 relative with BDF2. Steps coarser than
//! [`MIN_STEPS_PER_PERIOD`] per period of the highest forcing harmonic are refused.
//! The default 200 periods is 20 s at Ω ≈ 63 rad/s; at higher Ω, or for lightly
//! damped models, check `drift`. With the fast memory a run costs about 0.65 µs per
//! step for the quarter car (1e5 steps in ~65 ms; the direct sum would take ~5 s).
//!
//! ```
//! use ihbm::models::QuarterCar;
//! use ihbm::timedomain::{simulate, SimOptions};
//! let sim = simulate(&QuarterCar::default(), 8.0, &SimOptions { periods: 40, ..Default::default() }).unwrap();
//! let z1 = &sim.outputs[0];
//! assert_eq!(z1.name, "z1");
//! // The linear closed form gives |Z1/F| = 2.2973 at 8 rad/s; k3 is weak here.
//! assert!((z1.max_abs / 0.01 - 2.2973).abs() < 0.01);
//! ```

pub mod budget;
pub mod compare;
pub mod growth;
pub mod memory;
pub mod newmark;
pub mod past;
pub mod settling;
pub mod steady;
pub mod weights;

pub use compare::{compare, compare_at, CompareOutput, CompareRow};
pub use growth::{growth, Growth};
pub use memory::{FastHistory, History, Memory, NaiveHistory};
pub use newmark::{PeriodicStart, Stepper, StepperOptions};
pub use past::PeriodicPast;
pub use settling::StartUp;
pub use steady::SteadyOutput;
pub use weights::Scheme;

use crate::balance::size::{largest_fitting, readable_bytes};
use crate::balance::MEMORY_LIMIT;
use crate::error::Error;
use crate::model::{DynModel, Model};
use serde::Serialize;
use std::f64::consts::TAU;

/// Fewest steps per period of the highest forcing harmonic that [`simulate`] accepts.
///
/// Average-acceleration Newmark has a period error of about `(Ω dt)²/12`: at 20 steps
/// per period that is 0.8 % — already a poor verification, and below it the forcing
/// itself is no longer resolved (the default is 400 steps per period).
pub const MIN_STEPS_PER_PERIOD: f64 = 20.0;

/// Fewest periods [`simulate`] accepts: the steady statistics use the last 10, the
/// drift compares them with the 10 before.
pub const MIN_PERIODS: usize = 20;

/// Most steps of one run (at 2 cores about 20 s for the quarter car); the fractional
/// memory keeps `O(steps)` values, 100–180 bytes per step and fractional signal
/// ([`estimate_bytes`] counts them and [`simulate`] refuses more than
/// [`MEMORY_LIMIT`]).
pub const MAX_STEPS: usize = 20_000_000;

/// Options of [`simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Time step in s; `None` means `T/400` with `T = 2π/Ω`.
    pub dt: Option<f64>,
    /// Number of forcing periods to integrate (at least [`MIN_PERIODS`]).
    pub periods: usize,
    /// Convolution-quadrature rule for fractional derivatives.
    pub scheme: Scheme,
    /// History evaluation (fast FFT-based or naive).
    pub memory: Memory,
    /// Keep every step's outputs in [`Simulation::trajectory`].
    pub record: bool,
    /// Newton tolerance per step (relative to the acceleration scale).
    pub newton_tol: f64,
    /// Newton iterations allowed per step.
    pub max_newton: usize,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            dt: None,
            periods: 200,
            scheme: Scheme::Bdf2,
            memory: Memory::Fast,
            record: false,
            newton_tol: 1e-12,
            max_newton: 30,
        }
    }
}

/// Every step's outputs (with [`SimOptions::record`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trajectory {
    /// Output names, in model order.
    pub names: Vec<String>,
    /// Times `0, dt, 2 dt, ...`, s.
    pub time: Vec<f64>,
    /// `outputs[i][k]`: output `i` at `time[k]`.
    pub outputs: Vec<Vec<f64>>,
}

/// The result of [`simulate`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Simulation {
    /// Model name.
    pub model: String,
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Time step used, s.
    pub dt: f64,
    /// Forcing periods integrated.
    pub periods: usize,
    /// Steps taken.
    pub steps: usize,
    /// Simulated time, s.
    pub duration: f64,
    /// Convolution-quadrature rule.
    pub scheme: Scheme,
    /// History evaluation.
    pub memory: Memory,
    /// Steady statistics per output (model order), over the last 10 periods.
    pub outputs: Vec<SteadyOutput>,
    /// Newton iterations in all steps, and the most in one step.
    pub newton_iterations: usize,
    /// The most Newton iterations one step needed.
    pub newton_max: usize,
    /// Every step's outputs, if requested.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<Trajectory>,
    /// The start-up transient of the slowest-decaying free mode that can be left at
    /// the end ([`settling::start_up`]; `None` without an oscillatory mode at rest).
    pub start_up: Option<StartUp>,
}

fn invalid(what: &str, value: impl ToString, expected: impl Into<String>) -> Error {
    Error::InvalidValue { what: what.into(), value: value.to_string(), expected: expected.into() }
}

/// The memory [`simulate`] takes for `steps` steps of `steps_per_period`, in bytes,
/// estimated before anything is allocated: each fractional signal's history
/// ([`History::bytes`]), the last 20 periods of every output, and the whole
/// trajectory when it is recorded.
pub fn estimate_bytes(
    model: &dyn DynModel,
    steps: usize,
    steps_per_period: f64,
    opts: &SimOptions,
) -> f64 {
    let fractional =
        model.signals().iter().filter(|s| matches!(s.order, crate::model::Order::Param(_))).count();
    let outputs = model.outputs().len() as f64;
    let cap = steps.saturating_add(1);
    let tail = (20.0 * steps_per_period).min(cap as f64);
    let record = if opts.record { (1.0 + outputs) * cap as f64 } else { 0.0 };
    fractional as f64 * History::bytes(opts.memory, cap) + 8.0 * (outputs * tail + record)
}

/// The stepper's settings for a run of `steps` steps of `dt` under `opts`.
fn stepper_options(opts: &SimOptions, dt: f64, steps: usize) -> StepperOptions {
    StepperOptions {
        dt,
        steps,
        scheme: opts.scheme,
        memory: opts.memory,
        newton_tol: opts.newton_tol,
        max_newton: opts.max_newton,
    }
}

/// What a run of [`SimOptions::periods`] periods at `omega` takes, checked (see
/// [`simulate`]'s errors): the period, the step, the steps and the memory of `runs`
/// such runs at once.
struct RunPlan {
    period: f64,
    dt: f64,
    steps: usize,
    bytes: f64,
}

fn plan(model: &dyn DynModel, omega: f64, opts: &SimOptions, runs: f64) -> Result<RunPlan, Error> {
    if !(omega.is_finite() && omega > 0.0) {
        return Err(invalid("omega", omega, "a finite frequency > 0 in rad/s"));
    }
    let period = TAU / omega;
    let dt = opts.dt.unwrap_or(period / 400.0);
    if !(dt.is_finite() && dt > 0.0) {
        return Err(invalid("time step dt", dt, "a finite number > 0 (s)"));
    }
    if opts.periods < MIN_PERIODS {
        return Err(invalid(
            "number of periods",
            opts.periods,
            format!(
                "at least {MIN_PERIODS}: the steady statistics use the last 10 periods and \
                 the drift compares them with the 10 before"
            ),
        ));
    }
    let kmax = model.max_forcing_harmonic().max(1) as f64;
    let per_period = period / (kmax * dt);
    if per_period < MIN_STEPS_PER_PERIOD {
        return Err(invalid(
            "time step dt",
            dt,
            format!(
                "at most {:.6e} s: {per_period:.1} steps per period of forcing harmonic {kmax} \
                 cannot resolve it (at least {MIN_STEPS_PER_PERIOD} needed; default T/400)",
                period / (kmax * MIN_STEPS_PER_PERIOD)
            ),
        ));
    }
    let steps_f = (opts.periods as f64 * period / dt - 1e-9).ceil();
    if steps_f > MAX_STEPS as f64 {
        return Err(invalid(
            "number of steps (periods · T / dt)",
            steps_f,
            format!("at most {MAX_STEPS}: use a larger dt or fewer periods"),
        ));
    }
    let steps = steps_f as usize;
    let bytes = runs * estimate_bytes(model, steps, period / dt, opts);
    if bytes > MEMORY_LIMIT {
        // The most periods whose estimate fits (the estimate grows with the steps).
        let steps_of = |p: usize| (p as f64 * period / dt - 1e-9).ceil() as usize;
        let lo = largest_fitting(opts.periods, |p| {
            runs * estimate_bytes(model, steps_of(p), period / dt, opts) <= MEMORY_LIMIT
        });
        return Err(invalid(
            "time integration",
            format!(
                "{steps} steps needing about {} for the fractional memory",
                readable_bytes(bytes)
            ),
            format!(
                "at most {} (the limit for integrations): at most {lo} periods at this dt, \
                 or a larger dt",
                readable_bytes(MEMORY_LIMIT)
            ),
        ));
    }
    Ok(RunPlan { period, dt, steps, bytes })
}

/// Integrate `model` from rest at forcing frequency `omega` (rad/s) and report the
/// steady statistics of every output over the last 10 periods.
///
/// Errors: `omega <= 0` or not finite, `dt <= 0` or not finite, fewer than
/// [`MIN_PERIODS`] periods, fewer than [`MIN_STEPS_PER_PERIOD`] steps per period of
/// the highest forcing harmonic, more than [`MAX_STEPS`] steps or memory estimated
/// beyond [`MEMORY_LIMIT`] ([`estimate_bytes`]; with integrations running in other
/// threads it waits for its share, see [`budget`]), an invalid model
/// (see [`Model::validate`]); [`Error::Diverged`] with the time if the state stops
/// being finite or a step's Newton iteration fails.
pub fn simulate(model: &dyn DynModel, omega: f64, opts: &SimOptions) -> Result<Simulation, Error> {
    let RunPlan { period, dt, steps, bytes } = plan(model, omega, opts, 1.0)?;
    // Parallel integrations (a study's parts) share one budget: wait, not abort.
    let _held = budget::reserve(bytes);
    let window = (10.0 * period / dt).round() as usize;
    let record_from = steps.saturating_sub(2 * window);
    let step_opts = stepper_options(opts, dt, steps);
    let outs = model.outputs();
    let mut tail: Vec<Vec<f64>> =
        outs.iter().map(|_| Vec::with_capacity(steps - record_from + 1)).collect();
    let mut traj = opts.record.then(|| Trajectory {
        names: outs.iter().map(|o| o.name.to_string()).collect(),
        time: Vec::with_capacity(steps + 1),
        outputs: outs.iter().map(|_| Vec::with_capacity(steps + 1)).collect(),
    });
    let mut stepper = Stepper::new(model, omega, &step_opts)?;
    for m in 0..=steps {
        if m > 0 {
            stepper.step()?;
        }
        if m >= record_from {
            for (i, t) in tail.iter_mut().enumerate() {
                t.push(stepper.output(i));
            }
        }
        if let Some(tr) = traj.as_mut() {
            tr.time.push(stepper.time());
            for (i, o) in tr.outputs.iter_mut().enumerate() {
                o.push(stepper.output(i));
            }
        }
    }
    let (newton_iterations, newton_max) = stepper.newton_iterations();
    // The record's first sample is step `record_from`, at t = record_from · dt.
    let phase = steady::Phase { start: omega * dt * record_from as f64, turn: omega * dt };
    Ok(Simulation {
        model: model.name().to_string(),
        omega,
        dt,
        periods: opts.periods,
        steps,
        duration: steps as f64 * dt,
        scheme: opts.scheme,
        memory: opts.memory,
        outputs: outs
            .iter()
            .zip(&tail)
            .map(|(o, s)| steady::summarize(&o.name, s, window, phase))
            .collect(),
        newton_iterations,
        newton_max,
        trajectory: traj,
        start_up: settling::start_up(model, steps as f64 * dt),
    })
}
