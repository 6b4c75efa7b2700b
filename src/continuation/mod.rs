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

mod jumps;
mod tracer;

use crate::error::{Error, Result};
use crate::model::{Model, Order};
use crate::results::{
    Bifurcation, BifurcationKind, Curve, CurvePoint, CurveStats, Fold, HarmonicConvergence,
    HarmonicLevel, PointOutput, Segment, SegmentEnd,
};
use crate::stability::{Crossing, Hill, StabilityOptions};
use tracer::{dot, Axis, Tracer};

pub use jumps::{find_jumps, find_landings, Landing};

/// Predictor direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// The unit tangent at the last point (exact, one extra solve per step).
    Tangent,
    /// The secant through the last two points (the tangent at the first).
    Secant,
}

/// When a branch counts as running away.
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
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            harmonics: 5,
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
        }
    }
}

/// Trace the amplitude–frequency curve of `model` for Ω from `from` to `to` (rad/s).
///
/// Errors only for bad input (`from >= to`, non-finite or non-positive frequencies,
/// N = 0, invalid model parameters). Numerical trouble ends a segment and is reported
/// in [`Curve::segments`]; the curve is returned with everything computed.
pub fn sweep<M: Model>(model: &M, from: f64, to: f64, opts: &SweepOptions) -> Result<Curve> {
    check_range("frequency", from, to)?;
    if from <= 0.0 {
        return Err(invalid("start frequency", from, "a positive frequency in rad/s"));
    }
    check_options(opts)?;
    model.validate()?;
    with_convergence(opts, |o| trace(model, Axis::Omega, from, to, o))
}

/// Trace the response of `model` at fixed frequency `omega` as parameter `param`
/// goes from `from` to `to`. The parameter derivative comes from the dual-number
/// residual ([`Balance::d_param`](crate::balance::Balance::d_param)).
pub fn sweep_param<M: Model>(
    model: &M,
    param: &str,
    from: f64,
    to: f64,
    omega: f64,
    opts: &SweepOptions,
) -> Result<Curve> {
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
    check_options(opts)?;
    model.validate()?;
    with_convergence(opts, |o| trace(model, Axis::Param { index, omega }, from, to, o))
}

/// Frequency sweeps of a family of models that differ in `param`, run in parallel
/// (rayon, one curve per task; feature `parallel`). One result per value, in order.
#[cfg(feature = "parallel")]
pub fn sweep_family<M: Model + Clone>(
    model: &M,
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
            let mut m = model.clone();
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
    Ok(())
}

fn check_options(o: &SweepOptions) -> Result<()> {
    if o.harmonics == 0 {
        return Err(invalid("number of harmonics", 0.0, "at least 1"));
    }
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

/// Run once, or rerun with more harmonics until the curve converges.
fn with_convergence(
    opts: &SweepOptions,
    run: impl Fn(&SweepOptions) -> Result<Curve>,
) -> Result<Curve> {
    let Some(conv) = opts.convergence else {
        return run(opts);
    };
    let mut o = opts.clone();
    o.convergence = None;
    let mut levels: Vec<HarmonicLevel> = Vec::new();
    let mut prev: Option<(Vec<f64>, Vec<f64>)> = None;
    loop {
        let mut curve = run(&o)?;
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
        if converged || o.harmonics + conv.increment.max(1) > conv.max_harmonics {
            curve.convergence =
                Some(HarmonicConvergence { levels, tol: conv.tol, converged, estimate: change });
            return Ok(curve);
        }
        prev = Some((peaks, folds));
        o.harmonics += conv.increment.max(1);
    }
}

/// One accepted point of the trace, in scaled variables.
struct Node {
    y: Vec<f64>,
    /// Unit tangent, oriented along the direction of travel.
    t: Vec<f64>,
    /// Direction and length of the step that reached this point from the previous one
    /// (`border · (y - y_prev) = h`), for locating events inside the step.
    border: Vec<f64>,
    h: f64,
    segment: usize,
    outputs: Vec<PointOutput>,
}

struct RawFold {
    y: Vec<f64>,
    after: usize,
    located: bool,
}

/// Output summaries of a coefficient vector, with a reusable buffer.
struct OutputEval {
    harmonics: usize,
    peaks: crate::fourier::MaxAbs,
    buf: Vec<f64>,
    outputs: Vec<Vec<(usize, f64)>>,
}

impl OutputEval {
    fn new<M: Model>(model: &M, harmonics: usize) -> Self {
        OutputEval {
            harmonics,
            peaks: crate::fourier::MaxAbs::new(harmonics),
            buf: vec![0.0; 2 * harmonics + 1],
            outputs: model.outputs().iter().map(|o| o.terms.to_vec()).collect(),
        }
    }

    fn eval(&mut self, coeffs: &[f64], out: &mut Vec<PointOutput>) {
        let (nh, len) = (self.harmonics, 2 * self.harmonics + 1);
        out.clear();
        for terms in &self.outputs {
            self.buf.fill(0.0);
            for &(d, c) in terms {
                for (b, &a) in self.buf.iter_mut().zip(&coeffs[d * len..(d + 1) * len]) {
                    *b += c * a;
                }
            }
            out.push(PointOutput {
                max_abs: self.peaks.eval(&self.buf),
                mean: self.buf[0],
                amp1: self.buf[1].hypot(self.buf[nh + 1]),
            });
        }
    }
}

struct Run<'a, 'm, M: Model> {
    tr: Tracer<'m, M>,
    opts: &'a SweepOptions,
    lo: f64,
    hi: f64,
    nodes: Vec<Node>,
    folds: Vec<RawFold>,
    stats: CurveStats,
    out: OutputEval,
    coeffs: Vec<f64>,
    bound: Option<f64>,
}

fn trace<M: Model>(model: &M, axis: Axis, lo: f64, hi: f64, opts: &SweepOptions) -> Result<Curve> {
    let nh = opts.harmonics;
    let bal = crate::balance::Balance::new(model, nh)?;
    let mut tr = Tracer::new(bal, axis, opts.tol, opts.max_iter);
    let n = tr.n;
    tr.sl = hi - lo;
    // Reference force: the residual at zero response (the forcing).
    let sr = tr.reference_force(lo).max(tr.reference_force(hi));
    tr.sr = if sr > 0.0 && sr.is_finite() { sr } else { 1.0 };
    // Reference amplitude: the linearised response over the range.
    let mut sa = 0.0f64;
    let mut y = vec![0.0; n + 1];
    let mut e_n = vec![0.0; n + 1];
    e_n[n] = 1.0;
    for i in 0..17 {
        let f = i as f64 / 16.0;
        let lam = if axis == Axis::Omega { lo * (hi / lo).powf(f) } else { lo + f * (hi - lo) };
        y.fill(0.0);
        y[n] = lam / tr.sl;
        if tr.newton_step(&mut y, &e_n, lam / tr.sl).is_ok() {
            sa = sa.max(y[..n].iter().fold(0.0, |m: f64, v| m.max(v.abs())));
        }
    }
    tr.sa = if sa > 0.0 && sa.is_finite() { sa } else { 1.0 };
    let bound = match opts.amplitude_bound {
        AmplitudeBound::Relative(f) => Some(f),
        AmplitudeBound::Absolute(_) | AmplitudeBound::None => None,
    };
    let mut run = Run {
        tr,
        opts,
        lo,
        hi,
        nodes: Vec::new(),
        folds: Vec::new(),
        stats: CurveStats::default(),
        out: OutputEval::new(model, nh),
        coeffs: vec![0.0; n],
        bound,
    };
    let mut segments = Vec::new();
    let end0 = run.segment(model, lo, 1.0, 0);
    let reached_hi = matches!(end0, SegmentEnd::ReachedEnd)
        && run.nodes.last().is_some_and(|nd| run.tr.lambda(&nd.y) >= hi - 1e-12 * (hi - lo));
    segments.push(run.segment_record(0, lo, end0));
    if !reached_hi {
        let end1 = run.segment(model, hi, -1.0, 1);
        segments.push(run.segment_record(1, hi, end1));
    }
    run.finish(model, axis, segments)
}

impl<'m, M: Model> Run<'_, 'm, M> {
    fn segment_record(&self, seg: usize, start: f64, ended: SegmentEnd) -> Segment {
        let mut it = self.nodes.iter().filter(|nd| nd.segment == seg);
        let first = it.next().map_or(start, |nd| self.tr.lambda(&nd.y));
        let last = self
            .nodes
            .iter()
            .rev()
            .find(|nd| nd.segment == seg)
            .map_or(start, |nd| self.tr.lambda(&nd.y));
        Segment { from_omega: first, to_omega: last, ended }
    }

    /// Solve at `lam` from the linearised response (or the corrector for Ω).
    fn start(&mut self, model: &M, lam: f64) -> Result<Vec<f64>, String> {
        let n = self.tr.n;
        let mut y = vec![0.0; n + 1];
        let mut e_n = vec![0.0; n + 1];
        e_n[n] = 1.0;
        let target = lam / self.tr.sl;
        y[n] = target;
        let guess = if self.tr.axis == Axis::Omega {
            let so = crate::corrector::SolveOptions {
                harmonics: self.opts.harmonics,
                ..Default::default()
            };
            crate::corrector::solve(model, lam, &so, None).ok().map(|s| s.coeffs)
        } else {
            None
        };
        match guess {
            Some(c) => {
                for (yi, ci) in y.iter_mut().zip(&c) {
                    *yi = ci / self.tr.sa;
                }
            }
            None => {
                // Linearised response: one Newton step from zero.
                self.tr.newton_step(&mut y, &e_n, target)?;
            }
        }
        self.tr.locate(&mut y, &e_n, target).map(|_| y)
    }

    fn push(&mut self, y: Vec<f64>, t: Vec<f64>, border: Vec<f64>, h: f64, segment: usize) {
        self.tr.coeffs(&y, &mut self.coeffs);
        let mut outputs = Vec::new();
        self.out.eval(&self.coeffs, &mut outputs);
        self.nodes.push(Node { y, t, border, h, segment, outputs });
    }

    fn beyond_bound(&self, nd: &Node) -> bool {
        match self.opts.amplitude_bound {
            AmplitudeBound::Relative(_) => {
                let f = self.bound.unwrap_or(f64::INFINITY);
                nd.y[..self.tr.n].iter().any(|v| v.abs() > f)
            }
            AmplitudeBound::Absolute(b) => nd.outputs.iter().any(|o| o.max_abs > b),
            AmplitudeBound::None => false,
        }
    }

    /// Trace one segment from `lam0` in direction `dir` (+1 up, -1 down).
    fn segment(&mut self, model: &M, lam0: f64, dir: f64, seg: usize) -> SegmentEnd {
        let n = self.tr.n;
        let opts = self.opts;
        let y0 = match self.start(model, lam0) {
            Ok(y) => y,
            Err(why) => {
                return SegmentEnd::Stalled(format!("no solution at the start {lam0}: {why}"))
            }
        };
        let mut t0 = vec![0.0; n + 1];
        self.tr.tangent(&mut t0);
        if t0[n] * dir < 0.0 {
            t0.iter_mut().for_each(|v| *v = -*v);
        }
        let mut border = vec![0.0; n + 1];
        border[n] = dir;
        self.push(y0, t0, border, 0.0, seg);
        if self.beyond_bound(self.nodes.last().expect("just pushed")) {
            return SegmentEnd::AmplitudeBound;
        }
        let (lo_s, hi_s) = (self.lo / self.tr.sl, self.hi / self.tr.sl);
        let mut h = opts.initial_step;
        let mut y = vec![0.0; n + 1];
        let mut t = vec![0.0; n + 1];
        let mut dirv = vec![0.0; n + 1];
        let first = self.nodes.len() - 1;
        loop {
            if self.stats.steps >= opts.max_steps {
                return SegmentEnd::Stalled(format!("step limit {} reached", opts.max_steps));
            }
            let last = self.nodes.len() - 1;
            {
                let nd = &self.nodes[last];
                match opts.predictor {
                    Predictor::Secant if last > first => {
                        let prev = &self.nodes[last - 1];
                        for i in 0..=n {
                            dirv[i] = nd.y[i] - prev.y[i];
                        }
                        let norm = dot(&dirv, &dirv).sqrt();
                        dirv.iter_mut().for_each(|v| *v /= norm);
                    }
                    _ => dirv.copy_from_slice(&nd.t),
                }
                for i in 0..=n {
                    y[i] = nd.y[i] + h * dirv[i];
                }
                // Second order: the curvature from the last two tangents, so that the
                // first Newton step lands close enough for chord updates to finish.
                if opts.predictor == Predictor::Tangent && last > first && nd.h > 0.0 {
                    let prev = &self.nodes[last - 1];
                    let f = 0.5 * h * h / nd.h;
                    for i in 0..=n {
                        y[i] += f * (nd.t[i] - prev.t[i]);
                    }
                }
            }
            let target = dot(&dirv, &self.nodes[last].y) + h;
            let it = match self.tr.correct(&mut y, &dirv, target) {
                Ok(it) => it,
                Err(why) => {
                    self.stats.rejected_steps += 1;
                    h *= 0.5;
                    if h < opts.min_step {
                        return SegmentEnd::Stalled(why);
                    }
                    continue;
                }
            };
            self.tr.tangent(&mut t);
            let cosang = dot(&self.nodes[last].t, &t).clamp(-1.0, 1.0);
            let angle = cosang.acos();
            if angle > 2.0 * opts.max_turn && h > 2.0 * opts.min_step {
                self.stats.rejected_steps += 1;
                h *= 0.5;
                continue;
            }
            self.stats.steps += 1;
            // Left the range: land exactly on its end.
            if y[n] > hi_s || y[n] < lo_s {
                let b = if y[n] > hi_s { hi_s } else { lo_s };
                let yl = &self.nodes[last].y;
                let f = (b - yl[n]) / (y[n] - yl[n]);
                let mut yb: Vec<f64> = yl.iter().zip(&y).map(|(a, c)| a + f * (c - a)).collect();
                let mut e_n = vec![0.0; n + 1];
                e_n[n] = 1.0;
                return match self.tr.locate_exact(&mut yb, &e_n, b) {
                    Ok(_) => {
                        let mut tb = vec![0.0; n + 1];
                        self.tr.tangent(&mut tb);
                        if dot(&tb, &self.nodes[last].t) < 0.0 {
                            tb.iter_mut().for_each(|v| *v = -*v);
                        }
                        let hb = dot(&dirv, &yb) - dot(&dirv, &self.nodes[last].y);
                        self.push(yb, tb, dirv.clone(), hb, seg);
                        SegmentEnd::ReachedEnd
                    }
                    Err(why) => {
                        self.push(y.clone(), t.clone(), dirv.clone(), h, seg);
                        SegmentEnd::Stalled(format!("could not land on the range end: {why}"))
                    }
                };
            }
            if self.nodes[last].t[n] * t[n] < 0.0 {
                self.locate_fold(last, &dirv, h, t[n]);
            }
            self.push(y.clone(), t.clone(), dirv.clone(), h, seg);
            if self.beyond_bound(self.nodes.last().expect("just pushed")) {
                return SegmentEnd::AmplitudeBound;
            }
            // Step control: corrector effort and tangent turn.
            // (Newton iterations: chord updates in between are cheap.)
            let mut factor: f64 = match it {
                0..=1 => 1.6,
                2 => 1.25,
                3 => 1.0,
                _ => 0.6,
            };
            if angle > 0.0 {
                factor = factor.min(opts.max_turn / angle);
            }
            // Far above the reference amplitude (a branch climbing an asymptote) the
            // natural step is relative: let the largest step grow with the response.
            let amp = self.nodes[last + 1].y[..n].iter().fold(1.0f64, |m, v| m.max(v.abs()));
            h = (h * factor.clamp(0.25, 2.0)).clamp(opts.min_step, opts.max_step * amp);
        }
    }
}

/// A sign-change bracket `[a, b]` of a function along the step, narrowed by regula
/// falsi with the Illinois modification (halve the stale end's value when the same
/// end moves twice), which keeps superlinear convergence without stalling.
struct Illinois {
    a: f64,
    fa: f64,
    b: f64,
    fb: f64,
    side: i8,
}

impl Illinois {
    /// The bracket `[0, h]` with function values `fa` at 0 and `fb` at `h`.
    fn new(h: f64, fa: f64, fb: f64) -> Self {
        Illinois { a: 0.0, fa, b: h, fb, side: 0 }
    }

    /// The next trial point (the secant root, or the midpoint if that leaves the bracket).
    fn next(&self) -> f64 {
        let (a, fa, b, fb) = (self.a, self.fa, self.b, self.fb);
        let s = if fb != fa { (a * fb - b * fa) / (fb - fa) } else { 0.5 * (a + b) };
        if s > a && s < b {
            s
        } else {
            0.5 * (a + b)
        }
    }

    /// Replace the end with the same sign as `f` by `s`.
    fn update(&mut self, s: f64, f: f64) {
        if f * self.fa > 0.0 {
            self.a = s;
            self.fa = f;
            if self.side == -1 {
                self.fb *= 0.5;
            }
            self.side = -1;
        } else {
            self.b = s;
            self.fb = f;
            if self.side == 1 {
                self.fa *= 0.5;
            }
            self.side = 1;
        }
    }

    /// Width of the bracket.
    fn width(&self) -> f64 {
        self.b - self.a
    }
}

impl<'m, M: Model> Run<'_, 'm, M> {
    /// Locate the fold inside the step from `nodes[last]` (direction `dirv`, length
    /// `h`) by regula falsi (Illinois) on the λ-component of the tangent.
    fn locate_fold(&mut self, last: usize, dirv: &[f64], h: f64, f_end: f64) {
        let n = self.tr.n;
        let y_i = self.nodes[last].y.clone();
        let base = dot(dirv, &y_i);
        let mut bracket = Illinois::new(h, self.nodes[last].t[n], f_end);
        let mut y = vec![0.0; n + 1];
        let mut t = vec![0.0; n + 1];
        let mut best: Option<Vec<f64>> = None;
        let mut located = false;
        for _ in 0..100 {
            let s = bracket.next();
            for i in 0..=n {
                y[i] = y_i[i] + s * dirv[i];
            }
            if self.tr.locate_exact(&mut y, dirv, base + s).is_err() {
                break;
            }
            self.tr.tangent(&mut t);
            let f = t[n];
            best = Some(y.clone());
            if f.abs() < 1e-13 || bracket.width() < 1e-14 * h {
                located = true;
                break;
            }
            bracket.update(s, f);
        }
        // Not located: the fold is still there (the tangent turned between two
        // converged points); report the last converged trial, or the point before it.
        let y = best.unwrap_or(y_i);
        self.folds.push(RawFold { y, after: last, located });
    }

    /// Locate where `growth` (largest Re λ minus the tolerance) changes sign inside
    /// the step into `nodes[i + 1]`; the point there, and whether the search converged.
    fn locate_stability_change(
        &mut self,
        hill: &mut Hill,
        so: &StabilityOptions,
        i: usize,
        g0: f64,
        g1: f64,
    ) -> (Vec<f64>, bool) {
        let n = self.tr.n;
        let y_i = self.nodes[i].y.clone();
        let dirv = self.nodes[i + 1].border.clone();
        let h = self.nodes[i + 1].h;
        let base = dot(&dirv, &y_i);
        let mut bracket = Illinois::new(h, g0, g1);
        let mut y = vec![0.0; n + 1];
        let mut best = self.nodes[if g0.abs() < g1.abs() { i } else { i + 1 }].y.clone();
        let mut coeffs = vec![0.0; n];
        for _ in 0..40 {
            let s = bracket.next();
            for k in 0..=n {
                y[k] = y_i[k] + s * dirv[k];
            }
            if self.tr.locate(&mut y, &dirv, base + s).is_err() {
                break;
            }
            self.tr.set_point(&y);
            self.tr.coeffs(&y, &mut coeffs);
            let omega = self.tr.omega(&y);
            let Ok(fl) = hill.analyse(&mut self.tr.bal, &coeffs, omega, so) else {
                break;
            };
            let f = fl.max_real - so.tol * omega;
            best.copy_from_slice(&y);
            if f == 0.0 || bracket.width() < 1e-10 * h {
                return (best, true);
            }
            bracket.update(s, f);
        }
        (best, false)
    }

    /// Replace the polyline's landing amplitudes by the solution at the jump's
    /// parameter, corrected from the interpolated coefficients (kept as they are if
    /// the corrector fails there).
    fn land_exactly(
        &mut self,
        jumps: &mut [crate::results::Jump],
        landings: &[Landing],
        nout: usize,
    ) {
        let n = self.tr.n;
        let mut e_n = vec![0.0; n + 1];
        e_n[n] = 1.0;
        for l in landings {
            let Some(first) = jumps.get(l.jump) else { continue };
            let (ya, yb) = (&self.nodes[l.a].y, &self.nodes[l.b].y);
            let mut y: Vec<f64> = ya.iter().zip(yb).map(|(p, q)| p + l.w * (q - p)).collect();
            let target = first.omega / self.tr.sl;
            y[n] = target;
            if self.tr.locate(&mut y, &e_n, target).is_err() {
                continue;
            }
            let (_, _, _, outputs) = self.point_at(&y);
            for (j, o) in jumps[l.jump..].iter_mut().take(nout).zip(&outputs) {
                j.to = o.max_abs;
            }
        }
    }

    /// Unscaled point data at `y`.
    fn point_at(&mut self, y: &[f64]) -> (f64, f64, Vec<f64>, Vec<PointOutput>) {
        let mut coeffs = vec![0.0; self.tr.n];
        self.tr.coeffs(y, &mut coeffs);
        let mut outputs = Vec::new();
        self.out.eval(&coeffs, &mut outputs);
        (self.tr.omega(y), self.tr.lambda(y), coeffs, outputs)
    }

    /// Stability, bifurcations and jumps of the traced nodes; the curve.
    fn finish(mut self, model: &M, axis: Axis, segments: Vec<Segment>) -> Result<Curve> {
        let nodes = std::mem::take(&mut self.nodes);
        let mut points: Vec<CurvePoint> = nodes
            .iter()
            .map(|nd| {
                let mut coeffs = vec![0.0; self.tr.n];
                self.tr.coeffs(&nd.y, &mut coeffs);
                CurvePoint {
                    omega: self.tr.omega(&nd.y),
                    param: self.tr.lambda(&nd.y),
                    coeffs,
                    stable: true,
                    outputs: nd.outputs.clone(),
                    segment: nd.segment,
                }
            })
            .collect();
        let raw = std::mem::take(&mut self.folds);
        let mut folds = Vec::with_capacity(raw.len());
        let mut bifurcations = Vec::new();
        for f in &raw {
            let (omega, param, coeffs, outputs) = self.point_at(&f.y);
            bifurcations.push(Bifurcation {
                kind: BifurcationKind::Fold,
                omega,
                param,
                after: f.after,
                outputs: outputs.clone(),
                located: f.located,
            });
            folds.push(Fold { omega, param, coeffs, outputs, after: f.after, located: f.located });
        }
        self.nodes = nodes;
        if let Some(so) = self.opts.stability {
            let mut hill = Hill::new(model, self.opts.harmonics)?;
            let mut growth = vec![f64::NAN; points.len()];
            let mut kinds = vec![None; points.len()];
            for (i, p) in points.iter_mut().enumerate() {
                // Exponents are tracked from point to point, except across a segment
                // start or a fold (there the full analysis runs).
                let continues = i > 0
                    && self.nodes[i].segment == self.nodes[i - 1].segment
                    && !raw.iter().any(|f| f.after + 1 == i);
                if !continues {
                    hill.reset();
                }
                self.tr.set_point(&self.nodes[i].y);
                match hill.track(&mut self.tr.bal, &p.coeffs, p.omega, &so) {
                    Ok(f) => {
                        p.stable = f.stable;
                        growth[i] = f.max_real - so.tol * p.omega;
                        kinds[i] = f.leading_crossing(p.omega);
                        self.stats.stability_unrefined += usize::from(!f.refined);
                    }
                    // Not shown stable: say so rather than guess.
                    Err(_) => {
                        p.stable = false;
                        self.stats.stability_unrefined += 1;
                    }
                }
            }
            self.stats.stability_full = hill.counts().full;
            for i in 0..points.len().saturating_sub(1) {
                let same = self.nodes[i].segment == self.nodes[i + 1].segment;
                if !same
                    || points[i].stable == points[i + 1].stable
                    || raw.iter().any(|f| f.after == i)
                {
                    continue;
                }
                if !(growth[i].is_finite() && growth[i + 1].is_finite()) {
                    continue;
                }
                let unstable = if points[i].stable { i + 1 } else { i };
                let kind = match kinds[unstable] {
                    Some(Crossing::Real) => BifurcationKind::BranchPoint,
                    Some(Crossing::PeriodDoubling) => BifurcationKind::PeriodDoubling,
                    _ => BifurcationKind::Torus,
                };
                let (y, located) =
                    self.locate_stability_change(&mut hill, &so, i, growth[i], growth[i + 1]);
                let (omega, param, _, outputs) = self.point_at(&y);
                bifurcations.push(Bifurcation { kind, omega, param, after: i, outputs, located });
            }
            bifurcations.sort_by_key(|b| b.after);
        }
        self.stats.folds = folds.len();
        self.stats.folds_unlocated = folds.iter().filter(|f| !f.located).count();
        self.stats.corrector_iterations = self.tr.iterations;
        self.stats.chord_steps = self.tr.chord_steps;
        let output_names: Vec<String> =
            model.outputs().iter().map(|o| o.name.to_string()).collect();
        let (mut jumps, landings) = find_landings(&points, &folds, &output_names);
        self.land_exactly(&mut jumps, &landings, output_names.len());
        Ok(Curve {
            model: model.name().to_string(),
            harmonics: self.opts.harmonics,
            parameter: match axis {
                Axis::Omega => "omega".to_string(),
                Axis::Param { index, .. } => model.params_info()[index].name.to_string(),
            },
            output_names,
            points,
            stability_checked: self.opts.stability.is_some(),
            folds,
            jumps,
            segments,
            stats: self.stats,
            bifurcations,
            convergence: None,
        })
    }
}
