//! The continuation as a state machine a caller drives: [`Continuation::step`] does
//! one piece of work (the first point of a segment, one accepted arc-length step, the
//! end of the trace) and returns what happened as an [`Event`]; an [`Observer`] given
//! to [`Continuation::run`] sees every event with everything traced so far and may
//! stop the run. [`sweep`](super::sweep) is `run` with an observer that never stops.
//!
//! Stability is analysed as points are accepted (Hill's exponents tracked from point
//! to point), so an event already carries the verdict, and a change of stability is
//! located inside the step that crossed it before the next step is taken.

use super::events::{Control, Event, Observer, Trace};
use super::path::{self, Advance, Orientation};
use super::tracer::{dot, unit, Axis, Tracer};
use super::{AmplitudeBound, Predictor, SweepOptions};
use crate::balance::Balance;
use crate::error::Result;
use crate::model::{DynModel, Model};
use crate::outputs::{At, Direction, OutputEval};
use crate::results::{
    Bifurcation, BifurcationKind, Curve, CurvePoint, CurveStats, End, Parameter, PointOutput,
    Segment, Stability, Stall, Unknown,
};
use crate::stability::{Crossing, Hill};
use std::collections::VecDeque;

/// The ratio `hi / lo` of a positive range from which its parameter is continued as
/// `ln λ` (three decades: the reference study's 1–100 rad/s stays linear).
pub const LOG_RANGE: f64 = 1e3;

/// One accepted point of the trace, in scaled variables.
pub(super) struct Node {
    pub y: Vec<f64>,
    /// Unit tangent, oriented along the direction of travel.
    pub t: Vec<f64>,
    /// Direction and length of the step that reached this point from the previous one
    /// (`border · (y - y_prev) = h`), for locating events inside the step.
    pub border: Vec<f64>,
    pub h: f64,
    pub segment: usize,
    /// Largest real part of the exponents minus the tolerance (NaN: no verdict).
    pub growth: f64,
    /// How the leading exponent would cross (for naming a stability change).
    pub crossing: Option<Crossing>,
    /// Per output, the rate of change of its `max_abs` along the tangent (a peak lies
    /// where it goes from positive to negative).
    pub slopes: Vec<f64>,
}

/// Stability along the run: the tracking analysis and, created when first needed, a
/// second one for locating stability changes (so that locating never disturbs what
/// is being tracked).
struct Stab {
    opts: crate::stability::StabilityOptions,
    hill: Hill,
    locator: Option<Hill>,
}

enum State {
    /// Start segment `seg` (0: from the low end up, 1: from the high end down).
    Start(usize),
    /// Stepping along segment `seg`, from `first` (its first node), step `h`.
    Walk {
        seg: usize,
        first: usize,
        h: f64,
    },
    /// The last segment has ended.
    Ending,
    Done,
}

/// A start by branch switching: leave the solution `a0` at Ω = `omega0` along the
/// coefficient direction `v`, and end where the branch crosses back through the
/// solutions it left: where its component along `v` in the coefficients of `mask`
/// (the directions the branch adds, which those solutions lack) changes sign.
#[derive(Debug, Clone)]
pub(super) struct Branch {
    pub a0: Vec<f64>,
    pub omega0: f64,
    pub v: Vec<f64>,
    /// The first step along `v`, relative to the largest coefficient of `a0`.
    pub step: f64,
    pub mask: Vec<bool>,
    /// The component along `v` at the first point (set when it is accepted).
    pub start_size: f64,
}

/// A continuation run, driven step by step.
///
/// ```
/// use ihbm::continuation::{Continuation, Event, SweepOptions};
/// use ihbm::models::Duffing;
///
/// // Stop a hardening Duffing sweep at its first fold.
/// let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
/// let opts = SweepOptions { harmonics: 1, ..Default::default() };
/// let mut run = Continuation::omega(&model, 0.5, 2.5, &opts)?;
/// loop {
///     match run.step() {
///         Event::Fold(_) | Event::Finished => break,
///         _ => {}
///     }
/// }
/// let curve = run.finish();
/// assert_eq!(curve.folds.len(), 1);
/// // Stopped before the range end: the segment says so.
/// assert_eq!(curve.segments.last().unwrap().ended, ihbm::results::End::Stopped);
/// # Ok::<(), ihbm::Error>(())
/// ```
pub struct Continuation<'m> {
    pub(super) model: &'m dyn DynModel,
    pub(super) tr: Tracer<'m>,
    pub(super) opts: SweepOptions,
    lo: f64,
    hi: f64,
    pub(super) nodes: Vec<Node>,
    pub(super) trace: Trace,
    pub(super) out: OutputEval,
    bound: Option<f64>,
    stab: Option<Stab>,
    state: State,
    queue: VecDeque<Event>,
    /// Started by branch switching rather than at the range end.
    branch: Option<Branch>,
    /// A parameter held at another value than the model's (index, value): the
    /// frequency sweep that finds a parameter sweep's start.
    fixed: Option<(usize, f64)>,
    // step buffers
    y: Vec<f64>,
    t: Vec<f64>,
    dirv: Vec<f64>,
}

/// How far from a parameter sweep's frequency the frequency trace that finds its start
/// begins (a factor, above and then below).
const ALONG_OMEGA: f64 = 4.0;

impl<'m> Continuation<'m> {
    /// A frequency sweep of `model` for Ω from `from` to `to` (rad/s), checked as
    /// [`sweep`](super::sweep) checks it. `opts.convergence` is not used here (a
    /// convergence study is a run per harmonic count: [`sweep`](super::sweep)).
    pub fn omega(model: &'m dyn DynModel, from: f64, to: f64, opts: &SweepOptions) -> Result<Self> {
        super::check_sweep(model, from, to, opts)?;
        Self::new(model, Axis::Omega, from, to, opts)
    }

    /// A sweep of parameter `param` from `from` to `to` at fixed frequency `omega`.
    pub fn param(
        model: &'m dyn DynModel,
        param: &str,
        from: f64,
        to: f64,
        omega: f64,
        opts: &SweepOptions,
    ) -> Result<Self> {
        let index = super::check_sweep_param(model, param, from, to, omega, opts)?;
        Self::new(model, Axis::Param { index, omega }, from, to, opts)
    }

    pub(super) fn new(
        model: &'m dyn DynModel,
        axis: Axis,
        lo: f64,
        hi: f64,
        opts: &SweepOptions,
    ) -> Result<Self> {
        Self::build(model, axis, lo, hi, opts, None)
    }

    /// [`Continuation::new`] with parameter `fixed.0` held at `fixed.1` throughout.
    fn build(
        model: &'m dyn DynModel,
        axis: Axis,
        lo: f64,
        hi: f64,
        opts: &SweepOptions,
        fixed: Option<(usize, f64)>,
    ) -> Result<Self> {
        let nh = opts.harmonics;
        // Sizes first (the harmonic balance's are checked by `Balance`): a count too
        // large for Hill's matrices is refused before the harmonic balance spends
        // minutes on it.
        let mut bal = Balance::with_period(model, nh, opts.period)?;
        if let Some((index, value)) = fixed {
            bal.set_param(index, value);
        }
        if opts.stability.is_some() {
            crate::stability::check_size(model, nh)?;
        }
        // A coefficient undefined at an end of the range is an error before any step
        // (inside the range, it ends the segment: `Tracer::assemble`).
        for end in [lo, hi] {
            match axis {
                Axis::Omega => bal.check_coefficients(end)?,
                Axis::Param { index, omega } => {
                    bal.set_param(index, end);
                    bal.check_coefficients(omega)?;
                }
            }
        }
        let mut tr = Tracer::new(bal, axis, opts.tol, opts.max_iter);
        let n = tr.n;
        // Many decades: continue in ln λ (see the tracer's module docs).
        tr.log = lo > 0.0 && hi / lo >= LOG_RANGE;
        tr.sl = if tr.log { std::f64::consts::LN_10 } else { hi - lo };
        tr.range = (lo, hi);
        // Reference force: the residual at zero response (the forcing).
        let sr = tr.reference_force(lo).max(tr.reference_force(hi));
        tr.sr = if sr > 0.0 && sr.is_finite() { sr } else { 1.0 };
        // Reference amplitude: the linearised response over the range, solved in
        // units of the reference force (unit stiffness as the first guess), so that the
        // bordered matrix is balanced whatever the force's size (with the coefficients
        // unscaled, a force of 1e-14 left the matrix looking singular).
        tr.sa = tr.sr;
        let mut sa = 0.0f64;
        let mut y = vec![0.0; n + 1];
        let e_n = unit(n);
        for i in 0..17 {
            let f = i as f64 / 16.0;
            let lam = if axis == Axis::Omega { lo * (hi / lo).powf(f) } else { lo + f * (hi - lo) };
            y.fill(0.0);
            y[n] = tr.scaled(lam);
            if tr.newton_step(&mut y, &e_n, tr.scaled(lam)).is_ok() {
                sa = sa.max(tr.sa * y[..n].iter().fold(0.0, |m: f64, v| m.max(v.abs())));
            }
        }
        tr.sa = if sa > 0.0 && sa.is_finite() { sa } else { 1.0 };
        let bound = match opts.amplitude_bound {
            AmplitudeBound::Relative(f) => Some(f),
            AmplitudeBound::Absolute(_) | AmplitudeBound::None => None,
        };
        let stab = match opts.stability {
            Some(so) => Some(Stab {
                opts: so,
                hill: Hill::with_period(model, nh, opts.period)?,
                locator: None,
            }),
            None => None,
        };
        let parameter = match axis {
            Axis::Omega => Parameter::Omega,
            Axis::Param { index, .. } => {
                Parameter::Model { index, name: model.params_info()[index].name.to_string() }
            }
        };
        Ok(Continuation {
            model,
            tr,
            opts: opts.clone(),
            lo,
            hi,
            nodes: Vec::new(),
            trace: Trace {
                harmonics: nh,
                parameter,
                output_names: model.outputs().iter().map(|o| o.name.to_string()).collect(),
                points: Vec::new(),
                folds: Vec::new(),
                bifurcations: Vec::new(),
                peaks: Vec::new(),
                segments: Vec::new(),
                stats: CurveStats::default(),
            },
            out: OutputEval::new(model, nh, opts.period),
            bound,
            stab,
            state: State::Start(0),
            queue: VecDeque::new(),
            branch: None,
            fixed,
            y: vec![0.0; n + 1],
            t: vec![0.0; n + 1],
            dirv: vec![0.0; n + 1],
        })
    }

    pub(super) fn queue_event(&mut self, e: Event) {
        self.queue.push_back(e);
    }

    /// Everything traced so far.
    pub fn trace(&self) -> &Trace {
        &self.trace
    }

    /// Do the next piece of work and say what happened.
    pub fn step(&mut self) -> Event {
        loop {
            if let Some(e) = self.queue.pop_front() {
                return e;
            }
            match self.state {
                State::Start(seg) => self.start_segment(seg),
                State::Walk { seg, first, h } => self.walk(seg, first, h),
                State::Ending => {
                    self.state = State::Done;
                    return Event::Finished;
                }
                State::Done => return Event::Finished,
            }
        }
    }

    /// Step until finished or until `observer` says stop; the curve.
    pub fn run(mut self, observer: &mut dyn Observer) -> Curve {
        self.drive(observer);
        self.finish()
    }

    /// Step, showing `observer` every event, until finished (`false`) or until it
    /// says stop (`true`).
    pub(super) fn drive(&mut self, observer: &mut dyn Observer) -> bool {
        loop {
            let e = self.step();
            let control = observer.observe(&e, &self.trace);
            if e == Event::Finished {
                return false;
            }
            if control == Control::Stop {
                return true;
            }
        }
    }

    /// The curve traced so far, with its jumps. A segment still being traced ends
    /// [`End::Stopped`].
    pub fn finish(mut self) -> Curve {
        if let State::Walk { seg, .. } = self.state {
            self.end_segment(seg, End::Stopped);
        }
        self.queue.clear();
        let stats = &mut self.trace.stats;
        stats.folds = self.trace.folds.len();
        stats.folds_unlocated = self.trace.folds.iter().filter(|f| !f.located).count();
        stats.corrector_iterations = self.tr.iterations;
        stats.chord_steps = self.tr.chord_steps;
        stats.stability_full = self.stab.as_ref().map_or(0, |s| s.hill.counts().full);
        let (mut jumps, landings) = super::jumps::find_landings(
            &self.trace.points,
            &self.trace.folds,
            &self.trace.output_names,
        );
        self.land_exactly(&mut jumps, &landings);
        self.trace.into_curve(self.model.name(), self.opts.stability.is_some(), jumps)
    }

    fn end_segment(&mut self, seg: usize, ended: End) {
        let start = if seg == 0 { self.lo } else { self.hi };
        let mut on = self.nodes.iter().filter(|nd| nd.segment == seg);
        let from = on.next().map_or(start, |nd| self.tr.lambda(&nd.y));
        let to = on.next_back().map_or(from, |nd| self.tr.lambda(&nd.y));
        let reached_hi = matches!(ended, End::ReachedEnd)
            && self.nodes.last().is_some_and(|nd| {
                nd.segment == seg && self.tr.lambda(&nd.y) >= self.hi - 1e-12 * (self.hi - self.lo)
            });
        self.trace.segments.push(Segment { from, to, ended });
        self.queue.push_back(Event::SegmentEnd(self.trace.segments.len() - 1));
        // The sweep restarts from the other end when the first segment did not get
        // there (runaway branch, stall); nothing of the first is discarded. A branch
        // has one segment: from its start the other way is its mirror image.
        self.state = if seg == 0 && !reached_hi && self.branch.is_none() {
            State::Start(1)
        } else {
            State::Ending
        };
    }

    /// Solve at `lam` from the linearised response (or the corrector for Ω).
    fn start_point(&mut self, lam: f64) -> Result<Vec<f64>, Stall> {
        let n = self.tr.n;
        let mut y = vec![0.0; n + 1];
        let e_n = unit(n);
        let target = self.tr.scaled(lam);
        y[n] = target;
        let guess = if self.tr.axis == Axis::Omega && self.fixed.is_none() {
            let so = crate::corrector::SolveOptions {
                harmonics: self.opts.harmonics,
                period: self.opts.period,
                ..Default::default()
            };
            crate::corrector::solve(self.model, lam, &so, None).ok().map(|s| s.coeffs)
        } else {
            None
        };
        match guess {
            Some(c) => {
                for (yi, ci) in y.iter_mut().zip(&c) {
                    *yi = ci / self.tr.sa;
                }
            }
            // Linearised response: one Newton step from zero.
            None => {
                if let Err(why) = self.tr.newton_step(&mut y, &e_n, target) {
                    return self.start_along_omega(lam, &mut y).ok_or(why);
                }
            }
        }
        match self.tr.locate(&mut y, &e_n, target) {
            Ok(_) => Ok(y),
            Err(why) => self.start_along_omega(lam, &mut y).ok_or(why),
        }
    }

    /// A parameter sweep's start that Newton from the linearised response misses (a
    /// point past a fold of the frequency curve, a resonance): the frequency curve at
    /// the parameter value `lam`, traced from `ALONG_OMEGA` times the sweep's frequency
    /// down to it (small, nearly linear responses up there), else from as far below
    /// up to it, through any folds on the way; its point at the sweep's frequency,
    /// corrected in the sweep's own coordinates, is the start. `None` on the
    /// frequency axis, or when neither trace reaches the frequency.
    fn start_along_omega(&mut self, lam: f64, y: &mut [f64]) -> Option<Vec<f64>> {
        let Axis::Param { index, omega } = self.tr.axis else { return None };
        let opts = SweepOptions { stability: None, convergence: None, ..self.opts.clone() };
        let (n, target) = (self.tr.n, self.tr.scaled(lam));
        for (lo, hi) in [(omega, ALONG_OMEGA * omega), (omega / ALONG_OMEGA, omega)] {
            let Ok(c) = Self::build(self.model, Axis::Omega, lo, hi, &opts, Some((index, lam)))
            else {
                continue;
            };
            let curve = c.run(&mut ());
            let Some(p) = curve.points.iter().find(|p| p.omega == omega) else { continue };
            for (yi, ci) in y.iter_mut().zip(&p.coeffs) {
                *yi = ci / self.tr.sa;
            }
            y[n] = target;
            if self.tr.locate(y, &unit(n), target).is_ok() {
                return Some(y.to_vec());
            }
        }
        None
    }

    /// Start a branch by switching ([`Branch`]).
    pub(super) fn with_branch(mut self, b: Branch) -> Self {
        self.branch = Some(b);
        self
    }

    /// The first point of a switched branch: corrected with Ω free on
    /// `vᵀ(a − a0) = ε`, which the solution it leaves cannot satisfy.
    fn start_branch(&mut self) {
        let n = self.tr.n;
        let Some(b) = self.branch.clone() else { return };
        let sa = self.tr.sa;
        let mut y0: Vec<f64> = b.a0.iter().map(|a| a / sa).collect();
        y0.push(self.tr.scaled(b.omega0));
        let amp = y0[..n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let eps = b.step * amp.max(f64::MIN_POSITIVE);
        let mut border: Vec<f64> = b.v.clone();
        let norm = dot(&border, &border).sqrt();
        border.iter_mut().for_each(|x| *x /= norm);
        border.push(0.0);
        let target = dot(&border, &y0) + eps;
        let mut y: Vec<f64> = y0.iter().zip(&border).map(|(a, d)| a + eps * d).collect();
        if let Err(why) = self.tr.locate_exact(&mut y, &border, target) {
            let why = Stall::NoBranch { omega: b.omega0, cause: Box::new(why) };
            return self.end_segment(0, End::Stalled(why));
        }
        let mut t0 = vec![0.0; n + 1];
        self.tr.tangent(&mut t0);
        // the tangent solves K t = e: it points along the border, away from a0
        let size = Self::branch_component(&b, &y);
        if let Some(br) = self.branch.as_mut() {
            br.start_size = size;
        }
        self.accept(y, t0.clone(), t0, 0.0, 0);
        let first = self.nodes.len() - 1;
        self.state = State::Walk { seg: 0, first, h: self.opts.initial_step };
    }

    /// The component of `y` along the branch direction, in the coefficients the
    /// branch adds.
    fn branch_component(b: &Branch, y: &[f64]) -> f64 {
        b.v.iter().zip(&b.mask).zip(y).filter(|&((_, &m), _)| m).map(|((v, _), y)| v * y).sum()
    }

    /// A switched branch back through the solutions it left (the component along its
    /// direction has changed sign since its first point): it rejoined them, at
    /// another branch point, and from there it would retrace its mirror image.
    fn rejoined(&self, y: &[f64]) -> bool {
        let Some(b) = &self.branch else { return false };
        Self::branch_component(b, y) * b.start_size < 0.0
    }

    fn start_segment(&mut self, seg: usize) {
        if seg == 0 && self.branch.is_some() {
            return self.start_branch();
        }
        let n = self.tr.n;
        let (lam0, dir) = if seg == 0 { (self.lo, 1.0) } else { (self.hi, -1.0) };
        let y0 = match self.start_point(lam0) {
            Ok(y) => y,
            Err(why) => {
                let why = Stall::NoStart { at: lam0, cause: Box::new(why) };
                return self.end_segment(seg, End::Stalled(why));
            }
        };
        let mut t0 = vec![0.0; n + 1];
        self.tr.tangent(&mut t0);
        if t0[n] * dir < 0.0 {
            t0.iter_mut().for_each(|v| *v = -*v);
        }
        let mut border = vec![0.0; n + 1];
        border[n] = dir;
        self.accept(y0, t0, border, 0.0, seg);
        if self.beyond_bound() {
            return self.end_segment(seg, End::AmplitudeBound);
        }
        let first = self.nodes.len() - 1;
        self.state = State::Walk { seg, first, h: self.opts.initial_step };
    }

    /// Attempts from the last node until one step is accepted or the segment ends.
    fn walk(&mut self, seg: usize, first: usize, mut h: f64) {
        let n = self.tr.n;
        let (lo_s, hi_s) = (self.tr.scaled(self.lo), self.tr.scaled(self.hi));
        // The sweep's corrector ends with chord steps: one iteration fewer is as easy.
        let step = self.opts.step_size(1);
        let (mut y, mut t, mut dirv) = (
            std::mem::take(&mut self.y),
            std::mem::take(&mut self.t),
            std::mem::take(&mut self.dirv),
        );
        let last = self.nodes.len() - 1;
        let budget = self.tr.max_iter;
        // The end of the range a point lies beyond, if any.
        let outside = move |y: &[f64]| {
            (y[n] > hi_s || y[n] < lo_s).then_some(if y[n] > hi_s { hi_s } else { lo_s })
        };
        let ended = 'step: {
            if self.trace.stats.steps >= self.opts.max_steps {
                break 'step Some(End::Stalled(Stall::StepLimit { steps: self.opts.max_steps }));
            }
            self.direction(first, &mut dirv);
            let nd = &self.nodes[last];
            // Second order with the tangent predictor: the curvature from the last two
            // tangents, so that the first Newton step lands close enough for chord
            // updates to finish.
            let bend = (self.opts.predictor == Predictor::Tangent && last > first && nd.h > 0.0)
                .then(|| &self.nodes[last - 1].t);
            let predict = |h: f64, y: &mut [f64]| {
                for i in 0..=n {
                    y[i] = nd.y[i] + h * dirv[i];
                }
                if let Some(prev) = bend {
                    let f = 0.5 * h * h / nd.h;
                    for i in 0..=n {
                        y[i] += f * (nd.t[i] - prev[i]);
                    }
                }
            };
            let s = path::Step {
                border: &dirv,
                base: dot(&dirv, &nd.y),
                tangent: &nd.t,
                size: step,
                budget,
                orientation: Orientation::AsGiven,
            };
            let stats = &mut self.trace.stats;
            let r = path::advance_with(
                &mut self.tr,
                &s,
                &mut h,
                &mut stats.rejected_steps,
                predict,
                // A prediction beyond the range: land on its end from inside instead
                // of correcting out there (the model is never evaluated outside it).
                outside,
                &mut y,
                &mut t,
            );
            let accepted = match r {
                Advance::Accepted(a) => a,
                Advance::Left(b) => {
                    self.trace.stats.steps += 1;
                    break 'step Some(self.land_on_end(last, b, &y, &dirv, seg));
                }
                Advance::Stalled(why) => break 'step Some(End::Stalled(why)),
            };
            self.trace.stats.steps += 1;
            // Left the range: land exactly on its end.
            if let Some(b) = outside(&y) {
                break 'step Some(self.land_on_end(last, b, &y, &dirv, seg));
            }
            // A switched branch that crossed back through the solutions it left ends
            // before that step: the step holds the other branch point, where the
            // branch turns in Ω like at a fold but is not one.
            if self.rejoined(&y) {
                break 'step Some(End::Rejoined);
            }
            if self.nodes[last].t[n] * t[n] < 0.0 {
                self.locate_fold(last, &dirv, h, t[n]);
            }
            self.accept(y.clone(), t.clone(), dirv.clone(), h, seg);
            if self.beyond_bound() {
                break 'step Some(End::AmplitudeBound);
            }
            // Far above the reference amplitude (a branch climbing an asymptote) the
            // natural step is relative: let the largest step grow with the response.
            let amp = self.nodes[last + 1].y[..n].iter().fold(1.0f64, |m, v| m.max(v.abs()));
            h = step.after(h, accepted.iterations, accepted.turn, amp);
            None
        };
        (self.y, self.t, self.dirv) = (y, t, dirv);
        match ended {
            Some(e) => self.end_segment(seg, e),
            None => self.state = State::Walk { seg, first, h },
        }
    }

    /// The predictor's direction from the last node: its tangent, or with the secant
    /// predictor the unit chord from the node before.
    fn direction(&self, first: usize, dirv: &mut [f64]) {
        let n = self.tr.n;
        let last = self.nodes.len() - 1;
        let nd = &self.nodes[last];
        match self.opts.predictor {
            Predictor::Secant if last > first => {
                let prev = &self.nodes[last - 1];
                for i in 0..=n {
                    dirv[i] = nd.y[i] - prev.y[i];
                }
                let norm = dot(dirv, dirv).sqrt();
                dirv.iter_mut().for_each(|v| *v /= norm);
            }
            _ => dirv.copy_from_slice(&nd.t),
        }
    }

    /// Land the step that left the range (at `y`, predicted or corrected) on its end
    /// `b` (scaled); how the segment ends.
    fn land_on_end(&mut self, last: usize, b: f64, y: &[f64], dirv: &[f64], seg: usize) -> End {
        let n = self.tr.n;
        let yl = &self.nodes[last].y;
        let f = (b - yl[n]) / (y[n] - yl[n]);
        let mut yb: Vec<f64> = yl.iter().zip(y).map(|(a, c)| a + f * (c - a)).collect();
        match self.tr.locate_exact(&mut yb, &unit(n), b) {
            Ok(_) => {
                let mut tb = vec![0.0; n + 1];
                self.tr.tangent(&mut tb);
                if dot(&tb, &self.nodes[last].t) < 0.0 {
                    tb.iter_mut().for_each(|v| *v = -*v);
                }
                let hb = dot(dirv, &yb) - dot(dirv, &self.nodes[last].y);
                self.accept(yb, tb, dirv.to_vec(), hb, seg);
                End::ReachedEnd
            }
            // The point outside the range is not kept: the curve ends at the last
            // node, inside.
            Err(why) => End::Stalled(Stall::LandRangeEnd { cause: Box::new(why) }),
        }
    }

    fn beyond_bound(&self) -> bool {
        let Some(nd) = self.nodes.last() else { return false };
        match self.opts.amplitude_bound {
            AmplitudeBound::Relative(_) => {
                let f = self.bound.unwrap_or(f64::INFINITY);
                nd.y[..self.tr.n].iter().any(|v| v.abs() > f)
            }
            AmplitudeBound::Absolute(b) => {
                self.trace.points.last().is_some_and(|p| p.outputs.iter().any(|o| o.max_abs > b))
            }
            AmplitudeBound::None => false,
        }
    }

    /// Unscaled point data at `y`: Ω, the parameter, coefficients, outputs.
    pub(super) fn point_at(&mut self, y: &[f64]) -> (f64, f64, Vec<f64>, Vec<PointOutput>) {
        let mut coeffs = vec![0.0; self.tr.n];
        self.tr.coeffs(y, &mut coeffs);
        let (omega, params) = (self.tr.omega(y), self.tr.params_at(y));
        let at = At { model: self.model, params: &params, omega, period: self.opts.period };
        let mut outputs = Vec::new();
        self.out.points(&at, &coeffs, &mut outputs);
        (omega, self.tr.lambda(y), coeffs, outputs)
    }

    /// Accept a node: the point with its outputs and stability, and a located change
    /// of stability inside the step that reached it.
    fn accept(&mut self, y: Vec<f64>, t: Vec<f64>, border: Vec<f64>, h: f64, segment: usize) {
        let (omega, param, coeffs, outputs) = self.point_at(&y);
        // The slopes of the outputs' max_abs, for finding peaks (none when not asked).
        let mut slopes = Vec::new();
        if self.opts.peaks {
            let mut dc = vec![0.0; self.tr.n];
            self.tr.coeffs(&t, &mut dc);
            let (domega, param) = self.tr.rates(&y, &t);
            let dir = Direction { coeffs: &dc, omega: domega, param };
            let params = self.tr.params_at(&y);
            let at = At { model: self.model, params: &params, omega, period: self.opts.period };
            self.out.slopes(&at, &dir, &mut slopes);
        }
        let i = self.nodes.len();
        if self.opts.peaks && i > 0 && self.nodes[i - 1].segment == segment {
            self.locate_peaks(i - 1, &border, (&y, &t), &slopes);
        }
        // Exponents are tracked from point to point, except across a segment start or
        // a fold (there the full analysis runs).
        let continues = i > 0
            && self.nodes[i - 1].segment == segment
            && !self.trace.folds.iter().any(|f| f.after + 1 == i);
        let mut node = Node { y, t, border, h, segment, growth: f64::NAN, crossing: None, slopes };
        let stability = match &mut self.stab {
            None => Stability::Unknown(Unknown::NotChecked),
            Some(st) => {
                if !continues {
                    st.hill.reset();
                }
                self.tr.set_point(&node.y);
                match st.hill.track(&mut self.tr.bal, &coeffs, omega, &st.opts) {
                    Ok(f) => {
                        // A counted verdict has no distance to the threshold.
                        node.growth =
                            if f.counted { f64::NAN } else { f.max_real - st.opts.tol * omega };
                        // Nor an exponent that shows the root it counted.
                        node.crossing = if f.counted { None } else { f.leading_crossing(omega) };
                        self.trace.stats.stability_unrefined += usize::from(!f.refined);
                        Stability::from_verdict(f.stable)
                    }
                    // Not shown stable: say so rather than guess.
                    Err(e) => {
                        self.trace.stats.stability_unrefined += 1;
                        Stability::Unknown(Unknown::Failed(e.to_string()))
                    }
                }
            }
        };
        self.nodes.push(node);
        self.trace.points.push(CurvePoint { omega, param, coeffs, stability, outputs, segment });
        self.queue.push_back(Event::Point(i));
        if continues {
            self.stability_change(i - 1);
        }
    }

    /// A change of stability between nodes `i` and `i + 1` (not across a fold): locate
    /// it and report it.
    fn stability_change(&mut self, i: usize) {
        let (a, b) = (&self.trace.points[i].stability, &self.trace.points[i + 1].stability);
        let (Some(sa), Some(sb)) = (a.verdict(), b.verdict()) else { return };
        if sa == sb || self.trace.folds.iter().any(|f| f.after == i) {
            return;
        }
        let (g0, g1) = (self.nodes[i].growth, self.nodes[i + 1].growth);
        let unstable = if sa { i + 1 } else { i };
        let kind = BifurcationKind::of_crossing(self.nodes[unstable].crossing);
        if !(g0.is_finite() && g1.is_finite()) {
            // A verdict counted rather than read off an exponent: nothing to bracket,
            // the change is reported where it was seen.
            let y = self.nodes[i + 1].y.clone();
            self.push_bifurcation(kind, &y, i, false);
            return;
        }
        let Some(st) = self.stab.as_mut() else { return };
        let so = st.opts;
        let mut locator = match st.locator.take() {
            Some(h) => h,
            None => match Hill::with_period(self.model, self.opts.harmonics, self.opts.period) {
                Ok(h) => h,
                Err(_) => return,
            },
        };
        // Its exponents continue from the tracked ones at the step's end.
        locator.follow(&st.hill);
        let StabilityChange { y, located } =
            self.locate_stability_change(&mut locator, &so, i, g0, g1);
        if let Some(st) = self.stab.as_mut() {
            st.locator = Some(locator);
        }
        self.push_bifurcation(kind, &y, i, located);
    }

    /// Report a change of stability at `y`, between nodes `after` and `after + 1`.
    fn push_bifurcation(&mut self, kind: BifurcationKind, y: &[f64], after: usize, located: bool) {
        let (omega, param, _, outputs) = self.point_at(y);
        self.trace.bifurcations.push(Bifurcation { kind, omega, param, after, outputs, located });
        self.queue.push_back(Event::Bifurcation(self.trace.bifurcations.len() - 1));
    }
}

/// Where a change of stability was found, and whether the search converged.
pub(super) struct StabilityChange {
    pub y: Vec<f64>,
    pub located: bool,
}
