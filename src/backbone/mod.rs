//! Nonlinear modes: backbones by the extended periodic motion concept (EPMC).
//!
//! A backbone is how the free-vibration frequency of a mode changes with its
//! amplitude: where the forced peaks lean and fold. [`backbone`] starts at mode `K` of
//! the linearised model at a small amplitude and continues it (pseudo-arclength in
//! the coefficients, ω, ξ and the log of the modal amplitude) until the chosen
//! output's `max |x(t)|` reaches the requested amplitude. Every forcing term is left
//! out; damping, integer or fractional, stays in and is balanced by the artificial
//! damping `-ξ M ẋ` ([`epmc`]), which gives the modal damping ratio `D = ξ / (2ω)`
//! (exactly 0 for a conservative model). A backbone is followed through the turns in
//! amplitude and the internal resonances it meets (harmonic k of its frequency
//! crossing another mode's linear frequency), which are reported
//! ([`Backbone::events`]).
//!
//! Without damping to balance, the same system gives self-excited periodic motions:
//! [`cycle`] finds one (where the artificial damping of a mode vanishes), and
//! [`cycles`] continues it in a model parameter with every point's stability and the
//! Hopf point where it is born from the equilibrium, located from the linearisation's
//! eigenvalues. The book's chapter *Nonlinear modes* has the method and the checks
//! against closed forms.
//!
//! ```
//! use ihbm::backbone::{backbone, BackboneOptions};
//! use ihbm::models::Duffing;
//! // The undamped Duffing oscillator x'' + x + x³ = 0 stiffens: ω grows with amplitude.
//! let mut model = Duffing::default();
//! model.c = 0.0;
//! let opts = BackboneOptions { to: 1.0, harmonics: 7, ..Default::default() };
//! let b = backbone(&model, &opts).unwrap();
//! let last = b.points.last().unwrap();
//! assert!((last.outputs[0].max_abs - 1.0).abs() < 1e-9);
//! assert!(last.omega > 1.3 && last.omega < 1.4);
//! assert!(last.damping.abs() < 1e-12);
//! ```

mod cycle;
mod epmc;
mod family;
mod hopf;
mod stability;

use crate::balance::Balance;
use crate::continuation::path::{self, Advance, Extended, Orientation, Stepped};
use crate::continuation::tracer::LOCATE_ITER;
use crate::continuation::{Control, Observer, StepSize};
use crate::error::{Error, Result};
pub(crate) use crate::linearisation::{linear_mode, Linearisation};
use crate::model::{DynModel, Model};
use crate::outputs::{At, OutputEval};
pub use crate::results::End;
use crate::results::{PointOutput, Stability, Stall, Unknown};
pub use cycle::{cycle, Cycle, CycleOptions};
use epmc::Epmc;
pub use family::{
    cycles, cycles_with, CycleContinuation, CycleFamily, CyclePoint, FamilyEvent, FamilyOptions,
    Hopf,
};

/// Where a trace stops.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Goal {
    /// The output's `max |x(t)|` reaches this (a backbone).
    Amplitude(f64),
    /// The artificial damping vanishes: a periodic motion of the model itself (a
    /// limit cycle), searched up to this output amplitude.
    ZeroDamping(f64),
}

/// Settings of [`backbone`]; `to` must be set.
#[derive(Debug, Clone, PartialEq)]
pub struct BackboneOptions {
    /// The mode, 1-based, in the order of the linearised natural frequencies.
    pub mode: usize,
    /// The output whose `max |x(t)|` is continued to `to` (index; default the first).
    pub output: usize,
    /// The amplitude to reach.
    pub to: f64,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// Newton tolerance (max-norm of the scaled update).
    pub tol: f64,
    /// Newton iterations per point.
    pub max_iter: usize,
    /// First step, and its bounds, in the scaled unknowns (the log of the modal
    /// amplitude among them).
    pub initial_step: f64,
    /// Smallest step before the curve is given up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Largest turn of the tangent per step, radians: the next step shrinks to
    /// respect it, and a step that turns by more than twice as much is halved.
    pub max_turn: f64,
    /// Points at most.
    pub max_steps: usize,
    /// The start's amplitude relative to `to` (small: the linear limit).
    pub start: f64,
}

impl Default for BackboneOptions {
    fn default() -> Self {
        BackboneOptions {
            mode: 1,
            output: 0,
            to: f64::NAN,
            harmonics: crate::fourier::DEFAULT_HARMONICS,
            tol: 1e-10,
            max_iter: 12,
            initial_step: 0.05,
            min_step: 1e-6,
            max_step: 0.25,
            max_turn: 0.15,
            max_steps: 2000,
            start: 1e-4,
        }
    }
}

/// One point of a backbone.
#[derive(Debug, Clone, PartialEq)]
pub struct ModePoint {
    /// The mode's angular frequency ω, rad/s.
    pub omega: f64,
    /// The artificial damping ξ of `-ξ M ẋ` (1/s).
    pub xi: f64,
    /// The modal damping ratio `D = ξ / (2ω)`.
    pub damping: f64,
    /// The modal amplitude q (first harmonic, mass-weighted).
    pub amplitude: f64,
    /// Fourier coefficients.
    pub coeffs: Vec<f64>,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
    /// Where ξ = 0 (a conservative model) the point is a periodic motion of the
    /// model: Hill's verdict, stable only when every exponent but the trivial zero
    /// ones is on the imaginary axis. Where ξ ≠ 0 it is not a motion of the model, and the
    /// verdict is [`Unknown::NotAMotion`].
    pub stability: Stability,
    /// The Floquet exponents other than the double zero of the phase and the energy
    /// (central, by decreasing real part), where there is a verdict; empty otherwise.
    pub exponents: Vec<num_complex::Complex64>,
}

/// What happens at a [`ModeEvent`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// The continued output's amplitude has an extremum along the branch: the
    /// backbone turns back in amplitude (and is followed on).
    Turn,
    /// Harmonic `ratio` of the mode's frequency crosses the linear natural frequency
    /// of mode `mode`: a `ratio:1` internal resonance (only for harmonics present in
    /// the motion).
    InternalResonance {
        /// The other mode (1-based).
        mode: usize,
        /// The harmonic k of `k ω = ω_mode`.
        ratio: usize,
    },
}

impl EventKind {
    /// `"turn"` or `"internal-resonance"` (the JSON's `kind`).
    pub fn name(&self) -> &'static str {
        match self {
            EventKind::Turn => "turn",
            EventKind::InternalResonance { .. } => "internal-resonance",
        }
    }
}

/// A turn or an internal resonance met by a backbone.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeEvent {
    /// What happens.
    pub kind: EventKind,
    /// Where: the mode's frequency (for an internal resonance exactly `ω_j / k`) and
    /// the continued output's `max |x(t)|` there, interpolated between the points
    /// around it (a turn: the vertex of the parabola through the three points at it;
    /// an internal resonance: linear in ω between the two points around it).
    pub omega: f64,
    /// See `omega`.
    pub amplitude: f64,
    /// The index of the point after which it happens.
    pub after: usize,
}

/// A backbone: the linear mode it starts from and the traced points.
#[derive(Debug, Clone, PartialEq)]
pub struct Backbone {
    /// The model's name (set by the caller that knows it).
    pub model: String,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The mode (1-based).
    pub mode: usize,
    /// Output names, in model order.
    pub output_names: Vec<String>,
    /// The output continued to `to`, and `to`.
    pub output: usize,
    /// See `output`.
    pub to: f64,
    /// The start's frequency and damping ratio: the linearised mode's, to the
    /// start's relative amplitude squared ([`BackboneOptions::start`]).
    pub linear: (f64, f64),
    /// Points, by increasing arc length from the start.
    pub points: Vec<ModePoint>,
    /// The turns and internal resonances met on the way, in order.
    pub events: Vec<ModeEvent>,
    /// Why it ended.
    pub ended: End,
    /// Newton iterations and accepted steps.
    pub iterations: usize,
    /// See `iterations`.
    pub steps: usize,
}

/// The backbone of `model`; see the module documentation.
///
/// Errors for bad input (a mode beyond the DOFs, an unknown output, a target
/// amplitude that is not positive, a mode that is not oscillatory at rest) and when
/// the start does not converge. A backbone that cannot reach the amplitude (it turns
/// back or runs away) ends [`End::Stalled`] with what was traced.
pub fn backbone(model: &dyn DynModel, opts: &BackboneOptions) -> Result<Backbone> {
    backbone_with(model, opts, &mut ())
}

/// [`backbone`], reporting every event to `observer`, which may stop the run (what is
/// traced is returned, ended [`End::Stopped`]).
pub fn backbone_with(
    model: &dyn DynModel,
    opts: &BackboneOptions,
    observer: &mut dyn Observer<BackboneEvent, Backbone>,
) -> Result<Backbone> {
    Ok(BackboneContinuation::new(model, opts)?.run(observer))
}

/// What [`BackboneContinuation::step`] produced. Indices point into the
/// [`Backbone`] traced so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BackboneEvent {
    /// A point was accepted: `points[i]` (the first is the start).
    Point(usize),
    /// A turn in amplitude or an internal resonance: `events[i]` (reported before
    /// the point after it).
    Event(usize),
    /// Nothing more to trace: `ended` says why, and
    /// [`finish`](BackboneContinuation::finish) gives the backbone. Every later `step`
    /// returns `Finished` again.
    Finished,
}

/// A backbone driven step by step, as [`Continuation`](crate::continuation::Continuation)
/// drives a sweep: [`new`](Self::new) converges the start, each
/// [`step`](Self::step) takes one pseudo-arclength step (or reports what the last
/// one found), and [`finish`](Self::finish) gives what is traced, ended
/// [`End::Stopped`] if the backbone was not done.
///
/// ```
/// use ihbm::backbone::{BackboneContinuation, BackboneEvent, BackboneOptions};
/// use ihbm::models::Duffing;
///
/// let mut model = Duffing::default();
/// model.c = 0.0;
/// let opts = BackboneOptions { to: 1.0, harmonics: 5, ..Default::default() };
/// let mut run = BackboneContinuation::new(&model, &opts).unwrap();
/// // stop once the frequency has grown by 10 %: the points so far are kept
/// while let BackboneEvent::Point(i) | BackboneEvent::Event(i) = run.step() {
///     if run.traced().points.last().is_some_and(|p| p.omega > 1.1) {
///         break;
///     }
/// }
/// let b = run.finish();
/// assert_eq!(b.ended.to_string(), "stopped");
/// assert!(b.points.last().unwrap().omega > 1.1);
/// ```
pub struct BackboneContinuation<'m> {
    tracer: Tracer<'m>,
    /// The last accepted point and its tangent.
    y: Vec<f64>,
    t: Vec<f64>,
    res: Backbone,
    /// Points and events reported so far.
    told: (usize, usize),
    done: bool,
}

impl<'m> BackboneContinuation<'m> {
    /// Check the options and converge the start (the linear mode at
    /// [`BackboneOptions::start`] of the amplitude); errors as [`backbone`].
    pub fn new(model: &'m dyn DynModel, opts: &BackboneOptions) -> Result<Self> {
        if !(opts.to > 0.0 && opts.to.is_finite()) {
            return Err(Error::InvalidValue {
                what: "backbone amplitude".into(),
                value: opts.to.to_string(),
                expected: "a positive, finite max |x(t)| to reach".into(),
            });
        }
        Self::start(model, opts, Goal::Amplitude(opts.to), opts.start * opts.to)
    }

    /// Continue mode `opts.mode` from the output amplitude `start` until `goal`.
    fn start(
        model: &'m dyn DynModel,
        opts: &BackboneOptions,
        goal: Goal,
        start: f64,
    ) -> Result<Self> {
        model.validate()?;
        let outputs = model.outputs();
        if opts.output >= outputs.len() {
            return Err(Error::InvalidValue {
                what: "output index".into(),
                value: opts.output.to_string(),
                expected: format!("one of the model's {} outputs", outputs.len()),
            });
        }
        let (mut sys, lm, mass) = system(model, model, None, opts.mode, opts.harmonics, opts.tol)?;
        let n = sys.n;
        let nh = opts.harmonics;
        let len = 2 * nh + 1;
        let ndof = model.dofs().len();
        // the start: the linear mode, mass-normalised, at a small amplitude
        let mnorm: f64 = (0..ndof)
            .flat_map(|i| (0..ndof).map(move |j| (i, j)))
            .map(|(i, j)| lm.shape[i] * mass[i * ndof + j] * lm.shape[j])
            .sum();
        if !(mnorm > 0.0 && mnorm.is_finite()) {
            return Err(Error::InvalidValue {
                what: format!("mode {}", opts.mode),
                value: format!("modal mass {mnorm:e}"),
                expected: "a positive modal mass".into(),
            });
        }
        let shape: Vec<f64> = lm.shape.iter().map(|v| v / mnorm.sqrt()).collect();
        // The output's first harmonic on the mode shape (its cosine part), whatever the
        // output is.
        let mut mode = vec![0.0; ndof * len];
        for (d, v) in shape.iter().enumerate() {
            mode[d * len + 1] = *v;
        }
        let params = model.param_values();
        let at = At::model(model, &params, lm.omega);
        let first = OutputEval::new(model, nh, 1).coeffs(&at, &mode, opts.output).to_vec();
        let out_amp = first[1].hypot(first[nh + 1]);
        let scale = if out_amp > 1e-12 * shape.iter().fold(0.0f64, |m, v| m.max(v.abs())) {
            out_amp
        } else {
            shape.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        };
        let q0 = start / scale;
        let mut y = vec![0.0; n + 3];
        for d in 0..ndof {
            y[d * len + 1] = shape[d];
        }
        y[n] = 1.0;
        y[n + 1] = lm.xi / sys.so;
        y[n + 2] = q0.ln();
        let mut res = Backbone {
            model: model.name().to_string(),
            harmonics: nh,
            mode: opts.mode,
            output_names: outputs.iter().map(|o| o.name.to_string()).collect(),
            output: opts.output,
            to: opts.to,
            linear: (f64::NAN, f64::NAN),
            points: Vec::new(),
            events: Vec::new(),
            ended: End::Stopped,
            iterations: 0,
            steps: 0,
        };
        let mut eu = vec![0.0; n + 3];
        eu[n + 2] = 1.0;
        let u0 = y[n + 2];
        sys.correct(&mut y, &eu, u0, opts.max_iter.max(LOCATE_ITER)).map_err(|why| {
            Stall::ModeStart { mode: opts.mode, omega: lm.omega, cause: Box::new(why) }
        })?;
        let eval = OutputEval::new(model, nh, 1);
        let mut t = sys.tangent();
        if t[n + 2] < 0.0 {
            t.iter_mut().for_each(|v| *v = -*v);
        }
        let others = (1..=ndof)
            .filter(|&k| k != opts.mode)
            .filter_map(|k| linear_mode(model, k).ok().map(|m| (k, m.omega)))
            .collect();
        let stability = stability::ModeStability::new(model, nh)?;
        let mut tracer = Tracer {
            sys,
            eval,
            h: opts.initial_step,
            opts: opts.clone(),
            goal,
            others,
            stability: Some(stability),
        };
        let start = tracer.point(&y);
        res.linear = (start.omega, start.damping);
        res.points.push(start);
        res.iterations = tracer.sys.iterations;
        Ok(BackboneContinuation { tracer, y, t, res, told: (0, 0), done: false })
    }

    /// Everything traced so far.
    pub fn traced(&self) -> &Backbone {
        &self.res
    }

    /// Report what the last step found, or take the next step.
    pub fn step(&mut self) -> BackboneEvent {
        loop {
            if self.told.1 < self.res.events.len() {
                self.told.1 += 1;
                return BackboneEvent::Event(self.told.1 - 1);
            }
            if self.told.0 < self.res.points.len() {
                self.told.0 += 1;
                return BackboneEvent::Point(self.told.0 - 1);
            }
            if self.done {
                return BackboneEvent::Finished;
            }
            match self.tracer.step(&mut self.y, &mut self.t, &mut self.res) {
                Some(end) => {
                    self.res.ended = end;
                    self.done = true;
                }
                None => self.res.steps += 1,
            }
            self.res.iterations = self.tracer.sys.iterations;
        }
    }

    /// Step until the backbone is done or `observer` stops it; the backbone.
    pub fn run(mut self, observer: &mut dyn Observer<BackboneEvent, Backbone>) -> Backbone {
        loop {
            let e = self.step();
            if e == BackboneEvent::Finished || observer.observe(&e, &self.res) == Control::Stop {
                return self.finish();
            }
        }
    }

    /// What is traced: ended [`End::Stopped`] unless the backbone was done.
    pub fn finish(mut self) -> Backbone {
        if !self.done {
            self.res.ended = End::Stopped;
        }
        self.res
    }
}

/// The EPMC system of mode `mode` (1-based), scaled at rest: its linear mode and the
/// mass matrix (row-major). `rest` is the model linearised (`model` itself, or a copy
/// at the first value of the parameter `param` a family frees, which the balance of
/// `model` takes too). The phase fixes the sine of harmonic 1 of the mode's largest
/// DOF, so two systems of the same model and mode share it.
fn system<'m>(
    model: &'m dyn DynModel,
    rest: &dyn DynModel,
    param: Option<(usize, f64)>,
    mode: usize,
    harmonics: usize,
    tol: f64,
) -> Result<(Epmc<'m>, crate::linearisation::LinearMode, Vec<f64>)> {
    let lm = linear_mode(rest, mode)?;
    let mut bal = Balance::new(model, harmonics)?;
    if let Some((index, value)) = param {
        bal.set_param(index, value);
    }
    let n = bal.len();
    let len = 2 * harmonics + 1;
    let ndof = model.dofs().len();
    let mass = Linearisation::at_rest(rest, lm.omega).mass();
    // the reference DOF: the mode's largest entry (its sine of harmonic 1 is fixed)
    let dref =
        (0..ndof).max_by(|&i, &j| lm.shape[i].abs().total_cmp(&lm.shape[j].abs())).unwrap_or(0);
    let mut sys = Epmc::new(bal, mass.clone(), dref * len + harmonics + 1, tol);
    sys.so = lm.omega;
    let mut j0 = faer::Mat::<f64>::zeros(n, n);
    let mut r = vec![0.0; n];
    sys.bal.jacobian(&vec![0.0; n], lm.omega, &mut r, j0.as_mut());
    sys.sr = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .fold(0.0f64, |m, (i, j)| m.max(j0[(i, j)].abs()));
    if !(sys.sr > 0.0 && sys.sr.is_finite()) {
        sys.sr = 1.0;
    }
    Ok((sys, lm, mass))
}

struct Tracer<'m> {
    sys: Epmc<'m>,
    eval: OutputEval,
    h: f64,
    opts: BackboneOptions,
    goal: Goal,
    /// The other modes (1-based) and their linear frequencies: internal resonances.
    others: Vec<(usize, f64)>,
    /// Hill's method for points with ξ = 0 (`None`: no verdict is asked for).
    stability: Option<stability::ModeStability>,
}

impl Tracer<'_> {
    fn point(&mut self, y: &[f64]) -> ModePoint {
        let coeffs = self.sys.coeffs(y);
        let (omega, xi) = (self.sys.omega(y), self.sys.xi(y));
        let params = self.sys.params_at(y);
        let at = At { model: self.sys.bal.model(), params: &params, omega, period: 1 };
        let mut outputs = Vec::new();
        self.eval.points(&at, &coeffs, &mut outputs);
        let (stability, exponents) = match &mut self.stability {
            Some(s) => s.at(&mut self.sys.bal, &coeffs, omega, xi),
            None => (Stability::Unknown(Unknown::NotChecked), Vec::new()),
        };
        ModePoint {
            omega,
            xi,
            damping: xi / (2.0 * omega),
            amplitude: self.sys.log_amplitude(y).exp(),
            coeffs,
            outputs,
            stability,
            exponents,
        }
    }

    fn amplitude(&self, p: &ModePoint) -> f64 {
        p.outputs[self.opts.output].max_abs
    }

    /// One accepted point (pushed to `res`), or the end.
    fn step(&mut self, y: &mut Vec<f64>, t: &mut Vec<f64>, res: &mut Backbone) -> Option<End> {
        if res.points.len() >= self.opts.max_steps {
            let last =
                res.points.last().map_or((f64::NAN, f64::NAN), |p| (p.xi, self.amplitude(p)));
            return Some(End::Stalled(match self.goal {
                Goal::Amplitude(_) => Stall::StepLimit { steps: self.opts.max_steps },
                Goal::ZeroDamping(_) => Stall::DampingKeptSign {
                    xi: last.0,
                    output: res.output_names[self.opts.output].clone(),
                    amplitude: last.1,
                    steps: Some(self.opts.max_steps),
                },
            }));
        }
        let (step, point, tangent) = match self.advance(y, t) {
            Ok(x) => x,
            Err(why) => return Some(End::Stalled(why)),
        };
        let z = point.clone();
        let p = self.point(&z);
        match self.goal {
            Goal::Amplitude(to) if self.amplitude(&p) >= to => {
                return Some(self.land(y, &z, to, res));
            }
            Goal::ZeroDamping(_) if self.sys.xi(y) * p.xi <= 0.0 => {
                return Some(self.land_zero_damping(y, &z, res));
            }
            Goal::ZeroDamping(max) if self.amplitude(&p) > max => {
                return Some(End::Stalled(Stall::DampingKeptSign {
                    xi: p.xi,
                    output: res.output_names[self.opts.output].clone(),
                    amplitude: self.amplitude(&p),
                    steps: None,
                }));
            }
            _ => {}
        }
        self.push(res, p);
        self.adapt(&step);
        *y = point;
        *t = tangent;
        None
    }

    /// Append `p` to `res`, with the events between the last point and it.
    fn push(&self, res: &mut Backbone, p: ModePoint) {
        let k = res.points.len();
        if let (Some(a), Some(b)) = (k.checked_sub(2).map(|i| &res.points[i]), res.points.last()) {
            let (aa, ab, ap) = (self.amplitude(a), self.amplitude(b), self.amplitude(&p));
            if (ab - aa) * (ap - ab) < 0.0 {
                // the vertex of the parabola through the three points (in the index)
                let t = 0.5 * (aa - ap) / (aa - 2.0 * ab + ap);
                let quad = |fm: f64, f0: f64, fp: f64| {
                    f0 + 0.5 * (fp - fm) * t + 0.5 * (fp - 2.0 * f0 + fm) * t * t
                };
                res.events.push(ModeEvent {
                    kind: EventKind::Turn,
                    omega: quad(a.omega, b.omega, p.omega),
                    amplitude: quad(aa, ab, ap),
                    after: k - 1,
                });
            }
        }
        if let Some(b) = res.points.last() {
            let (ab, ap) = (self.amplitude(b), self.amplitude(&p));
            for &(mode, wj) in &self.others {
                for h in 1..=self.opts.harmonics {
                    let (sb, sp) = (h as f64 * b.omega - wj, h as f64 * p.omega - wj);
                    let crosses = (sb < 0.0 && sp >= 0.0) || (sb > 0.0 && sp <= 0.0);
                    if !crosses || !self.harmonic_present(&p.coeffs, h) {
                        continue;
                    }
                    let omega = wj / h as f64;
                    let f = (omega - b.omega) / (p.omega - b.omega);
                    res.events.push(ModeEvent {
                        kind: EventKind::InternalResonance { mode, ratio: h },
                        omega,
                        amplitude: ab + f * (ap - ab),
                        after: k - 1,
                    });
                }
            }
        }
        res.points.push(p);
    }

    /// Whether harmonic `h` is in the motion (any DOF's above 1e-9 of the largest
    /// first harmonic): a symmetric model's even harmonics are not, and meet nothing.
    fn harmonic_present(&self, coeffs: &[f64], h: usize) -> bool {
        let nh = self.opts.harmonics;
        let len = 2 * nh + 1;
        let size =
            |k: usize| coeffs.chunks(len).map(|c| c[k].hypot(c[nh + k])).fold(0.0f64, f64::max);
        size(h) > 1e-9 * size(1)
    }

    /// One pseudo-arclength step from `y` along `t` ([`path::advance`]): the
    /// corrected point, its tangent (oriented along `t`), the Newton iterations and
    /// the turn of the tangent, or the corrector's reason below the smallest step.
    /// Nothing is recorded: the caller accepts the point (and then calls
    /// [`Tracer::adapt`]) or not.
    fn advance(&mut self, y: &[f64], t: &[f64]) -> Result<(Stepped, Vec<f64>, Vec<f64>), Stall> {
        let (size, budget) = (self.step_size(), self.opts.max_iter);
        let mut rejected = 0;
        let never = |_: &[f64]| None::<std::convert::Infallible>;
        let along = Orientation::AlongLast;
        match path::advance(
            &mut self.sys,
            y,
            t,
            &mut self.h,
            size,
            budget,
            along,
            &mut rejected,
            never,
        ) {
            (Advance::Accepted(s), point, tangent) => Ok((s, point, tangent)),
            (Advance::Stalled(why), ..) => Err(why),
            (Advance::Left(at), ..) => match at {},
        }
    }

    fn step_size(&self) -> StepSize {
        let o = &self.opts;
        // The extended system's Newton has no chord steps: two iterations are easy.
        StepSize { min: o.min_step, max: o.max_step, max_turn: o.max_turn, easy: 2 }
    }

    /// The next step after `s` was accepted.
    fn adapt(&mut self, s: &Stepped) {
        self.h = self.step_size().after(self.h, s.iterations, s.turn, 1.0);
    }

    /// The point between `y` and `z` where ξ = 0, by Newton on the row `ξ = 0` from
    /// the linear interpolation.
    fn land_zero_damping(&mut self, y: &[f64], z: &[f64], res: &mut Backbone) -> End {
        let n = self.sys.n;
        let (xa, xb) = (y[n + 1], z[n + 1]);
        let f = if xb != xa { xa / (xa - xb) } else { 0.5 };
        let mut w: Vec<f64> = y.iter().zip(z).map(|(a, b)| a + f * (b - a)).collect();
        let mut e = vec![0.0; n + 3];
        e[n + 1] = 1.0;
        match self.sys.correct(&mut w, &e, 0.0, self.opts.max_iter.max(LOCATE_ITER)) {
            Ok(_) => {
                let p = self.point(&w);
                self.push(res, p);
                End::ReachedAmplitude
            }
            Err(why) => End::Stalled(Stall::LocateZeroDamping { cause: Box::new(why) }),
        }
    }

    /// The point where the output's amplitude is `to`, between `y` (below) and `z`
    /// (above): secant iterations on the log amplitude, corrected at fixed `u`.
    fn land(&mut self, y: &[f64], z: &[f64], to: f64, res: &mut Backbone) -> End {
        let n = self.sys.n;
        let mut eu = vec![0.0; n + 3];
        eu[n + 2] = 1.0;
        let pa = res.points.last().map_or(0.0, |p| self.amplitude(p));
        let (mut ua, mut fa) = (y[n + 2], (pa / to).ln());
        let mut zb = z.to_vec();
        let pb = self.point(z);
        let (mut ub, mut fb) = (z[n + 2], (self.amplitude(&pb) / to).ln());
        let mut best = pb;
        for _ in 0..40 {
            let u = if fb != fa { ub - fb * (ub - ua) / (fb - fa) } else { 0.5 * (ua + ub) };
            let mut w: Vec<f64> = zb.clone();
            w[n + 2] = u;
            if let Err(why) = self.sys.correct(&mut w, &eu, u, self.opts.max_iter.max(LOCATE_ITER))
            {
                return End::Stalled(Stall::LandAmplitude { amplitude: to, cause: Box::new(why) });
            }
            let p = self.point(&w);
            let f = (self.amplitude(&p) / to).ln();
            best = p;
            (ua, fa) = (ub, fb);
            (ub, fb) = (u, f);
            zb = w;
            if f.abs() < 1e-13 {
                break;
            }
        }
        self.push(res, best);
        End::ReachedAmplitude
    }
}
