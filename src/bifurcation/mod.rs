//! Two-parameter bifurcation analysis: the folds of an amplitude–frequency curve
//! continued as curves in the plane of Ω and a model parameter `P`, and the cusps
//! where two folds meet — where jumps begin.
//!
//! [`fold_curves`] sweeps Ω at both ends of the parameter range, then traces every
//! fold it found across the range ([`fold_system`] is the extended system,
//! [`fold_curve`] the continuation). A fold curve that turns back in `P` does so at a
//! cusp: beyond it that pair of folds, and the jumps between them, no longer exist.
//! A curve that comes back to the end it started from is traced once. With
//! [`Boundary::PeriodDoubling`] or [`Boundary::Torus`] the same machinery follows the
//! period-doubling or torus points of the sweeps instead (the test matrix is then the
//! odd-harmonic block of the period-2 balance, or Hill's operator `T(iω)` with the
//! torus frequency ω as one more unknown: [`torus`]).
//!
//! ```
//! use ihbm::bifurcation::{fold_curves, FoldCurveOptions};
//! use ihbm::models::Duffing;
//! use ihbm::Model;
//! // The one-harmonic Duffing oscillator with its defaults: folds above some forcing.
//! let model = Duffing::default();
//! let f = model.param_index("F").unwrap();
//! let mut opts = FoldCurveOptions::default();
//! opts.sweep.harmonics = 1;
//! opts.omega = (0.5, 3.0);
//! let curves = fold_curves(&model, f, 0.01, 0.3, &opts).unwrap();
//! // Both folds of the curve at F = 0.3 meet at one cusp, at the least forcing with a jump.
//! assert_eq!(curves.cusps.len(), 1);
//! assert!(curves.cusps[0].value > 0.01 && curves.cusps[0].value < 0.3);
//! ```

mod fold_curve;
mod fold_system;
mod period_two;
mod torus;

pub use period_two::{break_symmetry, embed, period_two, PeriodDoubled, SymmetryBroken};

use crate::balance::Balance;
use crate::continuation::{sweep, Control, Observer, SweepOptions};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::model::{DynModel, WithParams};
pub use crate::results::End;
use crate::results::{BifurcationKind, PointOutput, Stall};
use fold_curve::{FoldCurveTracer, Step};
use fold_system::{FoldSystem, OddBlock, ParamScale};

/// One point of a fold curve: a fold of the amplitude–frequency curve at `value`.
#[derive(Debug, Clone, PartialEq)]
pub struct FoldPoint {
    /// Forcing frequency of the fold.
    pub omega: f64,
    /// The parameter's value.
    pub value: f64,
    /// On a torus curve: the torus frequency ω (the critical Floquet exponents are
    /// `±iω`, the second frequency of the quasi-periodic response born there).
    pub torus_frequency: Option<f64>,
    /// Fourier coefficients at the fold.
    pub coeffs: Vec<f64>,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
}

/// How two folds meet where the parameter turns back along a fold curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TurnKind {
    /// A cusp (hysteresis point): the two folds of one hysteresis merge and the jump
    /// between them disappears. The curve's projection on the (Ω, P) plane has a cusp
    /// (Ω turns together with P).
    Cusp,
    /// An isola point: a fold of the curve meets a fold of a detached branch where
    /// the two join (the projection passes smoothly, Ω does not turn).
    Isola,
    /// A turning point of the parameter on a period-doubling curve (the extreme
    /// value at which the period-1 solution doubles its period in the range).
    Turn,
}

impl std::fmt::Display for TurnKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TurnKind::Cusp => "cusp",
            TurnKind::Isola => "isola",
            TurnKind::Turn => "turning point",
        })
    }
}

/// Where two folds meet: the parameter turns back along the fold curve, at a cusp or
/// where a detached branch joins ([`TurnKind`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Cusp {
    /// Which of the two.
    pub kind: TurnKind,
    /// Forcing frequency at the cusp.
    pub omega: f64,
    /// The parameter's value at the cusp: past it (on the side without the curve)
    /// this pair of folds, and the jumps between them, do not exist.
    pub value: f64,
    /// Fourier coefficients at the cusp.
    pub coeffs: Vec<f64>,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
    /// The fold curve it lies on (`curves[curve]`).
    pub curve: usize,
    /// It lies between `points[after]` and `points[after + 1]` of that curve.
    pub after: usize,
    /// Whether the location converged (the parameter component of the tangent below
    /// 1e-13 or the bracket below 1e-14 of the step); `false`: the last converged
    /// estimate inside the step, not located to 1e-8.
    pub located: bool,
}

/// Which end of the parameter range a fold curve started from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RangeEnd {
    /// The first value (`from`).
    From,
    /// The last value (`to`).
    To,
}

/// One fold curve, in arc-length order from the fold it started at.
#[derive(Debug, Clone, PartialEq)]
pub struct FoldCurve {
    /// The end of the parameter range whose sweep found its first fold.
    pub start: RangeEnd,
    /// Which fold of that sweep, in its arc-length order: folds `2k` and `2k + 1`
    /// bound one hysteresis (between them the curve had three solutions).
    pub start_fold: usize,
    /// Its points.
    pub points: Vec<FoldPoint>,
    /// Why it ended.
    pub ended: End,
}

/// The fold curves of a model in the (Ω, parameter) plane and their cusps.
#[derive(Debug, Clone, PartialEq)]
pub struct FoldCurves {
    /// What the curves follow.
    pub boundary: Boundary,
    /// The model's name (set by the caller that knows it, e.g. the command line).
    pub model: String,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The parameter's index in the model.
    pub param: usize,
    /// The parameter's name.
    pub parameter: String,
    /// Output names, in model order.
    pub output_names: Vec<String>,
    /// The parameter range.
    pub range: (f64, f64),
    /// The frequency range.
    pub omega: (f64, f64),
    /// Folds of the sweeps at the two ends of the range (`from`, `to`).
    pub start_folds: (usize, usize),
    /// The fold curves.
    pub curves: Vec<FoldCurve>,
    /// The cusps, in the order found.
    pub cusps: Vec<Cusp>,
    /// Newton iterations of the fold curves (the sweeps not counted).
    pub iterations: usize,
    /// Accepted and rejected steps of the fold curves.
    pub steps: (usize, usize),
}

/// What [`FoldContinuation::step`] produced (and [`fold_curves_with`] reports as it
/// goes). Indices point into the [`FoldCurves`] traced so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoldEvent {
    /// A sweep at an end of the range found this many folds to start from.
    Swept(RangeEnd, usize),
    /// A fold curve began: `curves[i]`.
    CurveStart(usize),
    /// A point was accepted: `curves[curve].points[index]`.
    Point {
        /// The curve.
        curve: usize,
        /// The point.
        index: usize,
    },
    /// A cusp was located: `cusps[i]`.
    Cusp(usize),
    /// `curves[i]` ended; its `ended` says why.
    CurveEnd(usize),
    /// Nothing more to trace; [`FoldContinuation::finish`] gives the result. Every
    /// later `step` returns `Finished` again.
    Finished,
}

/// What a two-parameter curve follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Boundary {
    /// Folds of the amplitude–frequency curve (jumps).
    #[default]
    Fold,
    /// Period-doubling points of it (a Floquet multiplier −1), found by the period-1
    /// sweeps' stability analysis at the ends of the range.
    PeriodDoubling,
    /// Neimark–Sacker (torus) points of it (a pair of multipliers leaves the unit
    /// circle away from ±1: a quasi-periodic response is born), found likewise.
    Torus,
}

impl From<Boundary> for BifurcationKind {
    fn from(b: Boundary) -> Self {
        match b {
            Boundary::Fold => BifurcationKind::Fold,
            Boundary::PeriodDoubling => BifurcationKind::PeriodDoubling,
            Boundary::Torus => BifurcationKind::Torus,
        }
    }
}

/// The kind's one spelling ([`BifurcationKind`]'s: `fold`, `period-doubling`,
/// `torus`), the same a study file, the command line and Python take.
impl std::fmt::Display for Boundary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        BifurcationKind::from(*self).fmt(f)
    }
}

/// A point to start a curve at: a located fold, or a located period doubling solved
/// for its coefficients from the nearest point of the curve.
fn start_points(
    model: &dyn DynModel,
    curve: &crate::results::Curve,
    boundary: Boundary,
    harmonics: usize,
) -> Vec<crate::results::Fold> {
    match boundary {
        Boundary::Fold => curve.folds.iter().filter(|f| f.located).cloned().collect(),
        Boundary::PeriodDoubling | Boundary::Torus => {
            use crate::results::BifurcationKind;
            let kind = match boundary {
                Boundary::Torus => BifurcationKind::Torus,
                _ => BifurcationKind::PeriodDoubling,
            };
            let so = crate::corrector::SolveOptions { harmonics, ..Default::default() };
            curve
                .bifurcations
                .iter()
                .filter(|b| b.kind == kind && b.located)
                .filter_map(|b| {
                    let near = curve.points.get(b.after)?;
                    let sol =
                        crate::corrector::solve(model, b.omega, &so, Some(&near.coeffs)).ok()?;
                    Some(crate::results::Fold {
                        omega: b.omega,
                        param: b.param,
                        coeffs: sol.coeffs,
                        outputs: b.outputs.clone(),
                        after: b.after,
                        located: true,
                    })
                })
                .collect()
        }
    }
}

/// Options of [`fold_curves`].
#[derive(Debug, Clone, PartialEq)]
pub struct FoldCurveOptions {
    /// What the curves follow: folds (default) or period doubling.
    pub boundary: Boundary,
    /// Harmonics, tolerances and step control, of the sweeps that find the folds to
    /// start from and of the fold curves (the sweeps skip their stability analysis:
    /// folds do not depend on it).
    pub sweep: SweepOptions,
    /// The frequency range of those sweeps, and the range the fold curves stay in.
    pub omega: (f64, f64),
}

impl Default for FoldCurveOptions {
    fn default() -> Self {
        FoldCurveOptions {
            boundary: Boundary::Fold,
            sweep: SweepOptions::default(),
            omega: (1.0, 100.0),
        }
    }
}

/// The fold curves of `model` for parameter `param` from `from` to `to`; see the
/// module documentation.
///
/// Errors for bad input (an unknown parameter index, an empty or non-finite range,
/// a range outside the parameter's domain, a bad frequency range) and when neither
/// end of the range has a fold. Numerical trouble ends a curve, with the reason in
/// [`FoldCurve::ended`]; what was traced is kept.
pub fn fold_curves(
    model: &dyn DynModel,
    param: usize,
    from: f64,
    to: f64,
    opts: &FoldCurveOptions,
) -> Result<FoldCurves> {
    fold_curves_with(model, param, from, to, opts, &mut ())
}

/// [`fold_curves`], reporting every event to `observer`, which may stop the run
/// (what is traced is returned, the curve being traced ends as `Stopped`).
pub fn fold_curves_with(
    model: &dyn DynModel,
    param: usize,
    from: f64,
    to: f64,
    opts: &FoldCurveOptions,
    observer: &mut dyn Observer<FoldEvent, FoldCurves>,
) -> Result<FoldCurves> {
    let mut run = FoldContinuation::new(model, param, from, to, opts)?;
    loop {
        let e = run.step()?;
        if e == FoldEvent::Finished || observer.observe(&e, run.traced()) == Control::Stop {
            return Ok(run.finish());
        }
    }
}

/// A fold (period-doubling, torus) analysis driven step by step, as
/// [`Continuation`](crate::continuation::Continuation) drives a sweep: each
/// [`step`](FoldContinuation::step) does one piece of work — the sweep at one end of
/// the parameter range, the start of a curve, one step along it — and says what it
/// produced; [`finish`](FoldContinuation::finish) gives what is traced, the curve
/// being traced (if any) ended `Stopped`.
///
/// ```
/// use ihbm::bifurcation::{FoldContinuation, FoldCurveOptions, FoldEvent};
/// use ihbm::models::Duffing;
/// use ihbm::Model;
///
/// let model = Duffing::default();
/// let mut opts = FoldCurveOptions::default();
/// opts.sweep.harmonics = 1;
/// opts.omega = (0.5, 3.0);
/// let f = model.param_index("F").unwrap();
/// let mut run = FoldContinuation::new(&model, f, 0.01, 0.3, &opts).unwrap();
/// // Two sweeps, then the first curve starts.
/// assert_eq!(run.step().unwrap(), FoldEvent::Swept(ihbm::bifurcation::RangeEnd::From, 0));
/// assert_eq!(run.step().unwrap(), FoldEvent::Swept(ihbm::bifurcation::RangeEnd::To, 2));
/// assert_eq!(run.step().unwrap(), FoldEvent::CurveStart(0));
/// while run.step().unwrap() != FoldEvent::Finished {}
/// assert_eq!(run.finish().cusps.len(), 1);
/// ```
pub struct FoldContinuation<'m> {
    model: &'m dyn DynModel,
    param: usize,
    range: (f64, f64),
    boundary: Boundary,
    sweep_opts: SweepOptions,
    scale: ParamScale,
    res: FoldCurves,
    /// The folds found by the end sweeps that curves start from.
    starts: std::collections::VecDeque<(RangeEnd, f64, usize, crate::results::Fold)>,
    phase: Phase<'m>,
    /// Events already produced, not yet returned (a cusp comes with its point).
    queue: std::collections::VecDeque<FoldEvent>,
}

/// Where a [`FoldContinuation`] stands.
enum Phase<'m> {
    /// The sweep at this end of the range comes next.
    Sweep(RangeEnd),
    /// The next curve starts (from the next start point not yet traced).
    Start,
    /// Curve `ci` is being traced.
    Walk { ci: usize, tracer: Box<FoldCurveTracer<'m>> },
    /// Neither end sweep found a start: the next step says so.
    NoFolds,
    /// Everything is traced.
    Finished,
}

impl<'m> FoldContinuation<'m> {
    /// Check the input and set up the analysis; nothing is computed yet. Errors for
    /// bad input (an unknown parameter index, an empty or non-finite range, a range
    /// outside the parameter's domain, a bad frequency range).
    pub fn new(
        model: &'m dyn DynModel,
        param: usize,
        from: f64,
        to: f64,
        opts: &FoldCurveOptions,
    ) -> Result<Self> {
        let info = model.params_info();
        let Some(pinfo) = info.get(param) else {
            return Err(Error::InvalidValue {
                what: "parameter index".into(),
                value: param.to_string(),
                expected: format!(
                    "one of the model's {} parameters (0..{})",
                    info.len(),
                    info.len()
                ),
            });
        };
        let name = pinfo.name.to_string();
        if !(from.is_finite() && to.is_finite()) || from == to {
            return Err(Error::InvalidValue {
                what: format!("range of {name}"),
                value: format!("{from} to {to}"),
                expected: "two different finite values".into(),
            });
        }
        let (w0, w1) = opts.omega;
        if !(w0.is_finite() && w1.is_finite() && w0 > 0.0 && w1 > w0) {
            return Err(Error::InvalidValue {
                what: "frequency range".into(),
                value: format!("{w0} to {w1}"),
                expected: "finite values with 0 < from < to".into(),
            });
        }
        let (lo, hi) = (from.min(to), from.max(to));
        // The domain is an interval: with both ends in it, so is the whole range.
        for v in [from, to] {
            crate::model::check_domain(
                model.name(),
                pinfo,
                &format!("end of the range of {name}"),
                v,
            )?;
        }
        for v in [from, to] {
            let m = WithParams::with(model, param, v);
            m.validate()?;
        }
        let mut sweep_opts = opts.sweep.clone();
        sweep_opts.convergence = None;
        // Only the folds (or stability changes) of these sweeps are used.
        sweep_opts.peaks = false;
        sweep_opts.stability = match opts.boundary {
            // folds do not depend on stability; period doubling is a change of it
            Boundary::Fold => None,
            Boundary::PeriodDoubling | Boundary::Torus => {
                Some(sweep_opts.stability.unwrap_or_default())
            }
        };
        let scale = if lo > 0.0 && hi / lo >= 10.0 { ParamScale::Log } else { ParamScale::Linear };
        let res = FoldCurves {
            boundary: opts.boundary,
            model: model.name().to_string(),
            harmonics: sweep_opts.harmonics,
            param,
            parameter: name.clone(),
            output_names: model.outputs().iter().map(|o| o.name.to_string()).collect(),
            range: (from, to),
            omega: (w0, w1),
            start_folds: (0, 0),
            curves: Vec::new(),
            cusps: Vec::new(),
            iterations: 0,
            steps: (0, 0),
        };
        Ok(FoldContinuation {
            model,
            param,
            range: (from, to),
            boundary: opts.boundary,
            sweep_opts,
            scale,
            res,
            starts: Default::default(),
            phase: Phase::Sweep(RangeEnd::From),
            queue: Default::default(),
        })
    }

    /// Everything traced so far.
    pub fn traced(&self) -> &FoldCurves {
        &self.res
    }

    /// Do the next piece of work and say what it produced. Errors where the analysis
    /// cannot go on at all: a sweep at an end of the range fails, neither end has a
    /// fold to start from ([`Error::NoFolds`]), or a model that cannot be set up;
    /// numerical trouble on a curve ends that curve instead, with the reason.
    pub fn step(&mut self) -> Result<FoldEvent> {
        if let Some(e) = self.queue.pop_front() {
            return Ok(e);
        }
        let r = match std::mem::replace(&mut self.phase, Phase::Finished) {
            Phase::Sweep(end) => self.sweep_end(end),
            Phase::Start => self.start_curve(),
            Phase::Walk { ci, tracer } => Ok(self.walk(ci, tracer)),
            Phase::NoFolds => Err(self.no_folds()),
            Phase::Finished => Ok(FoldEvent::Finished),
        };
        // An error ends the analysis: the phase stays Finished.
        r
    }

    /// What is traced: the curve being traced (if any) ends `Stopped`, with its
    /// statistics counted.
    pub fn finish(mut self) -> FoldCurves {
        if let Phase::Walk { tracer, .. } = std::mem::replace(&mut self.phase, Phase::Finished) {
            self.count(&tracer);
        }
        self.res
    }

    fn count(&mut self, tracer: &FoldCurveTracer<'m>) {
        self.res.iterations += tracer.sys.iterations;
        self.res.steps.0 += tracer.steps;
        self.res.steps.1 += tracer.rejected;
    }

    /// The sweep at `end` of the range and the folds it offers as starts.
    fn sweep_end(&mut self, end: RangeEnd) -> Result<FoldEvent> {
        let (from, to) = self.range;
        let v = if end == RangeEnd::From { from } else { to };
        let m = WithParams::with(self.model, self.param, v);
        let (w0, w1) = self.res.omega;
        let curve = sweep(&m, w0, w1, &self.sweep_opts)?;
        let folds = start_points(&m, &curve, self.boundary, self.sweep_opts.harmonics);
        let n = folds.len();
        match end {
            RangeEnd::From => self.res.start_folds.0 = n,
            RangeEnd::To => self.res.start_folds.1 = n,
        }
        self.starts.extend(folds.into_iter().enumerate().map(|(k, f)| (end, v, k, f)));
        self.phase = match end {
            RangeEnd::From => Phase::Sweep(RangeEnd::To),
            RangeEnd::To if self.starts.is_empty() => Phase::NoFolds,
            RangeEnd::To => Phase::Start,
        };
        Ok(FoldEvent::Swept(end, n))
    }

    /// Start the next curve from the next start point that no curve has passed
    /// through: its first event, or `Finished` when none is left.
    fn start_curve(&mut self) -> Result<FoldEvent> {
        let (model, param, harmonics) = (self.model, self.param, self.sweep_opts.harmonics);
        let (from, to) = self.range;
        let (lo, hi) = (from.min(to), from.max(to));
        let (w0, w1) = self.res.omega;
        let Some((end, v, start_fold, fold)) = self.next_start() else {
            return Ok(FoldEvent::Finished);
        };
        let m = WithParams::with(model, param, v);
        let bal = Balance::new(model, harmonics)?;
        let sys = FoldSystem::new(bal, param, self.scale, self.sweep_opts.tol);
        let ci = self.res.curves.len();
        let sys = match self.boundary {
            Boundary::Fold => Ok(sys),
            Boundary::PeriodDoubling => {
                let ndof = model.dofs().len();
                Ok(sys.period_doubling(OddBlock::new(model, ndof, harmonics)?))
            }
            Boundary::Torus => torus_frequency(&m, harmonics, &fold)
                .and_then(|w| sys.torus(w).map_err(Stall::from)),
        };
        let up = (end == RangeEnd::From) == (to > from);
        let sr = reference_force(&m, harmonics, fold.omega)?;
        let scale = self.scale;
        let tracer = sys.and_then(|mut sys| {
            sys.sa = fold.coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs())).max(f64::MIN_POSITIVE);
            sys.so = w1 - w0;
            sys.sp = (scale.forward(hi) - scale.forward(lo)).abs();
            sys.sr = sr;
            sys.omega_range = (w0, w1);
            sys.param_range = (lo, hi);
            FoldCurveTracer::new(sys, model, &self.sweep_opts, (&fold.coeffs, fold.omega, v), up)
        });
        self.phase = Phase::Start;
        match tracer {
            Ok(tracer) => {
                self.res.curves.push(FoldCurve {
                    start: end,
                    start_fold,
                    points: tracer.points.clone(),
                    ended: End::Stopped,
                });
                self.phase = Phase::Walk { ci, tracer: Box::new(tracer) };
                Ok(FoldEvent::CurveStart(ci))
            }
            Err(why) => {
                self.res.curves.push(FoldCurve {
                    start: end,
                    start_fold,
                    points: Vec::new(),
                    ended: End::Stalled(why),
                });
                Ok(FoldEvent::CurveEnd(ci))
            }
        }
    }

    /// The next start point no curve traced so far passes through.
    fn next_start(&mut self) -> Option<(RangeEnd, f64, usize, crate::results::Fold)> {
        while let Some(start) = self.starts.pop_front() {
            if !traced_already(&self.res, start.1, start.3.omega, &start.3.coeffs) {
                return Some(start);
            }
        }
        None
    }

    /// One step along curve `ci`: its point (after the cusp it passed, if any), or
    /// its end.
    fn walk(&mut self, ci: usize, mut tracer: Box<FoldCurveTracer<'m>>) -> FoldEvent {
        match tracer.step() {
            Step::Point(cusp) => {
                let k = tracer.points.len() - 1;
                self.res.curves[ci].points.push(tracer.points[k].clone());
                self.phase = Phase::Walk { ci, tracer };
                let point = FoldEvent::Point { curve: ci, index: k };
                match cusp {
                    Some(mut c) => {
                        c.curve = ci;
                        if self.boundary != Boundary::Fold {
                            c.kind = TurnKind::Turn;
                        }
                        self.res.cusps.push(c);
                        self.queue.push_back(point);
                        FoldEvent::Cusp(self.res.cusps.len() - 1)
                    }
                    None => point,
                }
            }
            Step::Ended(e) => {
                // a landing adds its point
                let have = self.res.curves[ci].points.len();
                self.res.curves[ci].points.extend(tracer.points[have..].iter().cloned());
                self.res.curves[ci].ended = e;
                self.count(&tracer);
                self.phase = Phase::Start;
                FoldEvent::CurveEnd(ci)
            }
        }
    }

    /// Neither end of the range has a fold to start from.
    fn no_folds(&self) -> Error {
        let (from, to) = self.range;
        Error::NoFolds {
            what: BifurcationKind::from(self.boundary).noun().to_string(),
            parameter: self.res.parameter.clone(),
            from,
            to,
            omega_from: self.res.omega.0,
            omega_to: self.res.omega.1,
        }
    }
}

/// The torus frequency at a located torus point: the imaginary part of the central
/// exponent nearest the imaginary axis away from 0 and ±Ω/2, by a full Hill analysis.
fn torus_frequency(
    model: &dyn DynModel,
    harmonics: usize,
    at: &crate::results::Fold,
) -> std::result::Result<f64, Stall> {
    let failed = |e: Error| Stall::TorusExponents { cause: Box::new(e.into()) };
    let mut bal = Balance::new(model, harmonics).map_err(failed)?;
    let mut hill = crate::stability::Hill::new(model, harmonics).map_err(failed)?;
    let omega = at.omega;
    let f = hill.analyse(&mut bal, &at.coeffs, omega, &Default::default()).map_err(failed)?;
    f.exponents
        .iter()
        .filter(|l| l.im.abs() > 1e-6 * omega && (l.im.abs() - 0.5 * omega).abs() > 1e-6 * omega)
        .min_by(|a, b| a.re.abs().total_cmp(&b.re.abs()))
        .map(|l| l.im.abs())
        .ok_or(Stall::NoComplexPair { omega })
}

/// The residual max-norm at zero response (the forcing) at Ω: the reference force.
fn reference_force(model: &dyn DynModel, harmonics: usize, omega: f64) -> Result<f64> {
    let mut bal = Balance::new(model, harmonics)?;
    let a = vec![0.0; bal.len()];
    let mut r = vec![0.0; bal.len()];
    bal.residual(&a, omega, &mut r);
    let f = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    Ok(if f > 0.0 && f.is_finite() { f } else { 1.0 })
}

/// Whether a traced curve already ended at this fold (`value`, Ω, coefficients): a
/// curve that turned at a cusp and came back to the end it started from.
fn traced_already(res: &FoldCurves, value: f64, omega: f64, coeffs: &[f64]) -> bool {
    let scale = coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs())).max(f64::MIN_POSITIVE);
    res.curves.iter().any(|c| {
        c.ended == End::ReachedEnd
            && c.points.last().is_some_and(|p| {
                (p.value - value).abs() <= 1e-9 * value.abs().max(f64::MIN_POSITIVE)
                    && (p.omega - omega).abs() <= 1e-6 * omega
                    && p.coeffs.iter().zip(coeffs).all(|(a, b)| (a - b).abs() <= 1e-4 * scale)
            })
    })
}
