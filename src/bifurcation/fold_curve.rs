//! One fold curve, traced step by step: pseudo-arclength continuation of the
//! extended system ([`super::fold_system`]) from a fold of an amplitude–frequency
//! curve, with the cusps (turning points of the parameter) located on the way.

use super::fold_system::FoldSystem;
use super::{Cusp, End, FoldPoint, TurnKind};
use crate::model::DynModel;

/// Corrector iterations that count as no effort ([`StepSize::easy`]): the extended
/// system's Newton has no chord steps.
///
/// [`StepSize::easy`]: crate::continuation::StepSize::easy
const EASY: usize = 2;

/// The largest Ω component of the unit tangent (scaled unknowns) at a turning point
/// of the parameter that counts as a cusp: there both components vanish together
/// (measured at located turning points: 6e-11 and 2e-15 at the cusps of the quarter
/// car and the Duffing oscillator, 0.12 where a detached branch joins the quarter
/// car's curve).
const CUSP_OMEGA_TANGENT: f64 = 1e-6;
use crate::continuation::path::{self, Advance, Extended, Orientation};
use crate::continuation::tracer::{dot, LOCATE_ITER};

/// How close (relative to Ω) a torus frequency may come to 0 or Ω/2 before the
/// curve ends at a strong resonance: the two exponents `±iω` (or `iω` and its copy
/// `i(Ω - ω)`) are then within `2·RESONANCE_GAP·Ω` of each other and the bordered
/// `T(iω)` nearly doubly singular.
const RESONANCE_GAP: f64 = 1e-3;
use crate::continuation::{AmplitudeBound, SweepOptions};
use crate::outputs::{At, OutputEval};
use crate::results::Stall;

/// What one [`FoldCurveTracer::step`] produced.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Step {
    /// A point was accepted (with the cusp located inside the step that reached it, if any).
    Point(Option<Cusp>),
    /// The curve ended.
    Ended(End),
}

struct Node {
    y: Vec<f64>,
    t: Vec<f64>,
}

pub(crate) struct FoldCurveTracer<'m> {
    pub sys: FoldSystem<'m>,
    out: OutputEval,
    opts: SweepOptions,
    nodes: Vec<Node>,
    pub points: Vec<FoldPoint>,
    h: f64,
    pub steps: usize,
    pub rejected: usize,
    ended: Option<End>,
}

impl<'m> FoldCurveTracer<'m> {
    /// Start at the fold `(a, Ω, P)` (located at fixed `P` by a sweep), heading
    /// towards increasing `P` if `up`. The fold is first corrected onto the extended
    /// system at that `P`.
    pub fn new(
        mut sys: FoldSystem<'m>,
        model: &dyn DynModel,
        opts: &SweepOptions,
        start: (&[f64], f64, f64),
        up: bool,
    ) -> Result<Self, Stall> {
        let (a, omega, p) = start;
        let n = sys.n;
        sys.init_borders(a, omega, p)?;
        let mut y = sys.scaled(a, omega, p);
        let mut e_p = vec![0.0; sys.dim()];
        e_p[n + 1] = 1.0;
        let target = y[n + 1];
        sys.correct(&mut y, &e_p, target, opts.max_iter.max(LOCATE_ITER))
            .map_err(|why| Stall::FoldStart { omega, cause: Box::new(why) })?;
        sys.renew_borders();
        let mut t = sys.tangent();
        if up != (t[n + 1] > 0.0) {
            t.iter_mut().for_each(|v| *v = -*v);
        }
        let mut tracer = FoldCurveTracer {
            sys,
            out: OutputEval::new(model, opts.harmonics, 1),
            opts: opts.clone(),
            nodes: Vec::new(),
            points: Vec::new(),
            h: opts.initial_step,
            steps: 0,
            rejected: 0,
            ended: None,
        };
        tracer.accept(y, t);
        Ok(tracer)
    }

    fn point_at(&mut self, y: &[f64]) -> FoldPoint {
        let coeffs = self.sys.coeffs(y);
        let (omega, value) = (self.sys.omega(y), self.sys.value(y));
        let mut params = self.sys.bal.params().to_vec();
        params[self.sys.param] = value;
        let at = At { model: self.sys.bal.model(), params: &params, omega, period: 1 };
        let mut outputs = Vec::new();
        self.out.points(&at, &coeffs, &mut outputs);
        FoldPoint { omega, value, torus_frequency: self.sys.torus_frequency(y), coeffs, outputs }
    }

    fn accept(&mut self, y: Vec<f64>, t: Vec<f64>) {
        let p = self.point_at(&y);
        self.points.push(p);
        self.nodes.push(Node { y, t });
    }

    /// The bounds of the scaled Ω and parameter unknowns.
    fn bounds(&self) -> [(f64, f64); 2] {
        let s = &self.sys;
        let (w0, w1) = s.omega_range;
        let (p0, p1) = s.param_range;
        let (u0, u1) = (s.scale.forward(p0) / s.sp, s.scale.forward(p1) / s.sp);
        [(w0 / s.so, w1 / s.so), (u0.min(u1), u0.max(u1))]
    }

    /// The bound the step from the last node to `y` crosses first ([`crossing`]).
    fn beyond(&self, y: &[f64]) -> Option<(usize, f64)> {
        crossing(&self.bounds(), self.sys.n, self.nodes.last().map(|nd| nd.y.as_slice()), y)
    }

    /// One step: a point accepted, or the end of the curve.
    pub fn step(&mut self) -> Step {
        if let Some(e) = &self.ended {
            return Step::Ended(e.clone());
        }
        let r = self.attempt();
        if let Step::Ended(e) = &r {
            self.ended = Some(e.clone());
        }
        r
    }

    fn attempt(&mut self) -> Step {
        if self.steps >= self.opts.max_steps {
            return Step::Ended(End::Stalled(Stall::StepLimit { steps: self.opts.max_steps }));
        }
        let n = self.sys.n;
        let last = self.nodes.len() - 1;
        let (y0, t0) = (self.nodes[last].y.clone(), self.nodes[last].t.clone());
        let (size, bounds) = (self.opts.step_size(EASY), self.bounds());
        let leaves = |y: &[f64]| crossing(&bounds, n, Some(&y0), y);
        let (r, point, tangent) = path::advance(
            &mut self.sys,
            &y0,
            &t0,
            &mut self.h,
            size,
            self.opts.max_iter,
            Orientation::AsGiven,
            &mut self.rejected,
            leaves,
        );
        let s = match r {
            Advance::Accepted(s) => s,
            Advance::Left((k, b)) => {
                self.steps += 1;
                return self.land(k, b, &point);
            }
            Advance::Stalled(why) => return Step::Ended(End::Stalled(why)),
        };
        self.steps += 1;
        if let Some((k, b)) = self.beyond(&point) {
            return self.land(k, b, &point);
        }
        let (y, t) = (point, tangent);
        let cusp =
            if t0[n + 1] * t[n + 1] < 0.0 { Some(self.locate_cusp(s.h, t[n + 1])) } else { None };
        self.sys.renew_borders();
        self.accept(y, t);
        let amp = self.nodes[last + 1].y[..n].iter().fold(1.0f64, |m, v| m.max(v.abs()));
        self.h = size.after(s.h, s.iterations, s.turn, amp);
        if self.closed() {
            return Step::Ended(End::Closed);
        }
        if self.beyond_bound() {
            return Step::Ended(End::AmplitudeBound);
        }
        if self.resonant() {
            return Step::Ended(End::StrongResonance);
        }
        Step::Point(cusp)
    }

    /// The last point's response beyond the amplitude bound: relative to the first
    /// fold's largest coefficient (the unit of the scaled coefficients), or any
    /// output's `max_abs` above an absolute bound.
    fn beyond_bound(&self) -> bool {
        let (Some(nd), Some(p)) = (self.nodes.last(), self.points.last()) else { return false };
        match self.opts.amplitude_bound {
            AmplitudeBound::Relative(f) => nd.y[..self.sys.n].iter().any(|v| v.abs() > f),
            AmplitudeBound::Absolute(b) => p.outputs.iter().any(|o| o.max_abs > b),
            AmplitudeBound::None => false,
        }
    }

    /// A torus curve whose torus frequency came within `RESONANCE_GAP · Ω` of 0 or
    /// Ω/2: there the pair of multipliers reaches +1 or −1 and the curve meets a fold
    /// or a period-doubling curve (a strong resonance), where `T(iω)` stops
    /// characterising the torus.
    fn resonant(&self) -> bool {
        let Some(p) = self.points.last() else { return false };
        p.torus_frequency.is_some_and(|w| {
            let r = w / p.omega;
            !(RESONANCE_GAP..=0.5 - RESONANCE_GAP).contains(&r)
        })
    }

    /// Back near the first point after going round: an isola (a closed fold curve).
    fn closed(&self) -> bool {
        let k = self.nodes.len();
        if k < 8 {
            return false;
        }
        let (first, last) = (&self.nodes[0], &self.nodes[k - 1]);
        let d = first.y.iter().zip(&last.y).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        d < 0.5 * self.h && dot(&first.t, &last.t) > 0.0
    }

    /// Land the step that left the box (at `y`) on the bound `b` of component `k`.
    fn land(&mut self, k: usize, b: f64, y: &[f64]) -> Step {
        let n = self.sys.n;
        let last = self.nodes.len() - 1;
        let yl = self.nodes[last].y.clone();
        let f = (b - yl[k]) / (y[k] - yl[k]);
        let mut yb: Vec<f64> = yl.iter().zip(y).map(|(a, c)| a + f * (c - a)).collect();
        let mut e = vec![0.0; self.sys.dim()];
        e[k] = 1.0;
        match self.sys.correct(&mut yb, &e, b, self.opts.max_iter.max(LOCATE_ITER)) {
            Ok(_) => {
                let mut t = self.sys.tangent();
                if dot(&t, &self.nodes[last].t) < 0.0 {
                    t.iter_mut().for_each(|v| *v = -*v);
                }
                self.accept(yb, t);
                Step::Ended(if k == n + 1 { End::ReachedEnd } else { End::LeftOmegaRange })
            }
            Err(why) => Step::Ended(End::Stalled(Stall::LandRangeEnd { cause: Box::new(why) })),
        }
    }

    /// Locate the zero of the tangent's parameter component inside the step of
    /// length `h` from the last node (regula falsi, Illinois), corrected onto the
    /// fold curve at every trial.
    fn locate_cusp(&mut self, h: f64, f_end: f64) -> Cusp {
        let n = self.sys.n;
        let last = self.nodes.len() - 1;
        let (y0, t0) = (self.nodes[last].y.clone(), self.nodes[last].t.clone());
        let base = dot(&t0, &y0);
        let (mut a, mut fa) = (0.0, t0[n + 1]);
        let (mut b, mut fb) = (h, f_end);
        let mut side = 0i8;
        let mut best: Option<(Vec<f64>, Vec<f64>)> = None;
        let mut located = false;
        for _ in 0..60 {
            let s = {
                let s = if fb != fa { (a * fb - b * fa) / (fb - fa) } else { 0.5 * (a + b) };
                if s > a && s < b {
                    s
                } else {
                    0.5 * (a + b)
                }
            };
            let mut y: Vec<f64> = y0.iter().zip(&t0).map(|(p, t)| p + s * t).collect();
            if self.sys.correct(&mut y, &t0, base + s, self.opts.max_iter.max(LOCATE_ITER)).is_err()
            {
                break;
            }
            let t = self.sys.tangent();
            let f = t[n + 1];
            best = Some((y, t));
            if f.abs() < 1e-13 || (b - a) < 1e-14 * h {
                located = true;
                break;
            }
            if f * fa > 0.0 {
                a = s;
                fa = f;
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                b = s;
                fb = f;
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
        }
        let (y, t) = best.unwrap_or((y0, t0));
        let p = self.point_at(&y);
        // At a cusp the curve's projection on the (Ω, P) plane stops: Ω turns with P.
        let kind = if t[n].abs() <= CUSP_OMEGA_TANGENT { TurnKind::Cusp } else { TurnKind::Isola };
        Cusp {
            kind,
            omega: p.omega,
            value: p.value,
            coeffs: p.coeffs,
            outputs: p.outputs,
            curve: 0,
            after: last,
            located,
        }
    }
}

/// The bound of the scaled Ω and parameter unknowns (`y[n]`, `y[n + 1]`, within
/// `bounds`) the step from `from` to `y` crosses first, as (component, bound value):
/// where a curve leaves through a corner of the (Ω, P) box, the other bound is
/// crossed later and landing on it would leave the box.
fn crossing(
    bounds: &[(f64, f64); 2],
    n: usize,
    from: Option<&[f64]>,
    y: &[f64],
) -> Option<(usize, f64)> {
    let mut first: Option<(f64, usize, f64)> = None;
    for (k, &(lo, hi)) in bounds.iter().enumerate() {
        let v = y[n + k];
        let b = if v > hi {
            hi
        } else if v < lo {
            lo
        } else {
            continue;
        };
        // the fraction of the step at which it crosses
        let f = from.map_or(1.0, |y0| {
            let d = v - y0[n + k];
            if d != 0.0 {
                (b - y0[n + k]) / d
            } else {
                1.0
            }
        });
        if first.is_none_or(|(g, _, _)| f < g) {
            first = Some((f, n + k, b));
        }
    }
    first.map(|(_, k, b)| (k, b))
}
