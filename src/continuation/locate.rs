//! Locating events inside an accepted step: folds (the tangent's parameter component
//! changes sign), changes of stability (the largest real part of the exponents
//! crosses zero) and the exact landing points of jumps. Each search walks along the
//! step's border direction, correcting back onto the curve at every trial.

use super::events::Event;
use super::jumps::Landing;
use super::stepper::{Continuation, StabilityChange};
use super::tracer::{dot, unit};
use crate::results::{Fold, Jump};
use crate::stability::{Hill, StabilityOptions};

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

/// Trials of a search for a change of stability.
const MAX_TRIALS: usize = 40;

/// The search for the zero of the largest real part along a step: an [`Illinois`]
/// bracket that also tells a crossing from a jump. A continuous function is small at
/// both ends of a small bracket (a square root, as at a collision of two exponents, is
/// 1e-3 of its scale at 1e-6 of the step and 0.045 at 1e-3); one that stays large
/// there jumps: no exponent crosses zero, the set of exponents changed (two copies or
/// roots that rank alike traded places in the full analysis), and bisecting on to
/// 1e-10 of the step would only place the jump more finely.
struct CrossingSearch {
    bracket: Illinois,
    h: f64,
    /// The latest values on the side of `f(0)` and on the other (the bracket's own are
    /// scaled by the Illinois rule).
    ends: (f64, f64),
    scale: f64,
}

/// What one more value told a [`CrossingSearch`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Narrowed {
    Further,
    /// The bracket is below 1e-10 of the step, or the value is exactly zero.
    Crossing,
    /// The bracket is below 1e-6 of the step with values above 1e-2 of the ends' on
    /// both sides, or below 1e-3 with values above 0.3 of them.
    Jump,
}

impl CrossingSearch {
    fn new(h: f64, f0: f64, f1: f64) -> Self {
        let scale = f0.abs().max(f1.abs());
        CrossingSearch { bracket: Illinois::new(h, f0, f1), h, ends: (f0, f1), scale }
    }

    fn next(&self) -> f64 {
        self.bracket.next()
    }

    /// Take the value `f` at the trial `s`.
    fn update(&mut self, s: f64, f: f64) -> Narrowed {
        if f == 0.0 || self.bracket.width() < 1e-10 * self.h {
            return Narrowed::Crossing;
        }
        self.bracket.update(s, f);
        if f * self.ends.0 > 0.0 {
            self.ends.0 = f;
        } else {
            self.ends.1 = f;
        }
        let (least, w) = (self.ends.0.abs().min(self.ends.1.abs()), self.bracket.width());
        if (w < 1e-6 * self.h && least > 1e-2 * self.scale)
            || (w < 1e-3 * self.h && least > 0.3 * self.scale)
        {
            return Narrowed::Jump;
        }
        Narrowed::Further
    }
}

impl Continuation<'_> {
    /// Locate the fold inside the step from `nodes[last]` (direction `dirv`, length
    /// `h`) by regula falsi (Illinois) on the λ-component of the tangent, and report it.
    pub(super) fn locate_fold(&mut self, last: usize, dirv: &[f64], h: f64, f_end: f64) {
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
        let (omega, param, coeffs, outputs) = self.point_at(&y);
        self.trace.folds.push(Fold { omega, param, coeffs, outputs, after: last, located });
        self.queue_event(Event::Fold(self.trace.folds.len() - 1));
    }

    /// Locate where `growth` (largest Re λ minus the tolerance) changes sign inside
    /// the step into `nodes[i + 1]`, with the analysis `hill` (not the tracking one):
    /// its exponents are tracked from iterate to iterate (seeded from the step's end
    /// by [`Hill::follow`]), analysed in full where tracking cannot be trusted.
    pub(super) fn locate_stability_change(
        &mut self,
        hill: &mut Hill,
        so: &StabilityOptions,
        i: usize,
        g0: f64,
        g1: f64,
    ) -> StabilityChange {
        let n = self.tr.n;
        let y_i = self.nodes[i].y.clone();
        let dirv = self.nodes[i + 1].border.clone();
        let h = self.nodes[i + 1].h;
        let base = dot(&dirv, &y_i);
        // The verdict uses a tolerance (unstable iff max Re λ > tol·Ω), but the
        // bifurcation is where max Re λ = 0: locate that root when it lies in the step
        // (it does unless both ends are within the tolerance of zero), so that the
        // location converges with N instead of sitting at the tolerance's offset.
        let shift = |k: usize| so.tol * self.trace.points[k].omega;
        let (m0, m1) = (g0 + shift(i), g1 + shift(i + 1));
        let exact = m0 * m1 < 0.0;
        let (f0, f1) = if exact { (m0, m1) } else { (g0, g1) };
        let mut search = CrossingSearch::new(h, f0, f1);
        let mut y = vec![0.0; n + 1];
        let mut best = self.nodes[if f0.abs() < f1.abs() { i } else { i + 1 }].y.clone();
        let mut coeffs = vec![0.0; n];
        for _ in 0..MAX_TRIALS {
            let s = search.next();
            for k in 0..=n {
                y[k] = y_i[k] + s * dirv[k];
            }
            if self.tr.locate(&mut y, &dirv, base + s).is_err() {
                break;
            }
            self.tr.set_point(&y);
            self.tr.coeffs(&y, &mut coeffs);
            let omega = self.tr.omega(&y);
            hill.forget_motion();
            // A counted verdict has no largest real part to bracket.
            let Some(fl) =
                hill.track(&mut self.tr.bal, &coeffs, omega, so).ok().filter(|f| !f.counted)
            else {
                break;
            };
            let f = if exact { fl.max_real } else { fl.max_real - so.tol * omega };
            best.copy_from_slice(&y);
            match search.update(s, f) {
                Narrowed::Further => {}
                Narrowed::Crossing => return StabilityChange { y: best, located: true },
                Narrowed::Jump => break,
            }
        }
        StabilityChange { y: best, located: false }
    }

    /// Replace the polyline's landing amplitudes by the solution at the jump's
    /// parameter, corrected from the interpolated coefficients (kept as they are if
    /// the corrector fails there).
    pub(super) fn land_exactly(&mut self, jumps: &mut [Jump], landings: &[Landing]) {
        let n = self.tr.n;
        let nout = self.trace.output_names.len();
        let e_n = unit(n);
        for l in landings {
            let Some(first) = jumps.get(l.jump) else { continue };
            let (ya, yb) = (&self.nodes[l.a].y, &self.nodes[l.b].y);
            let mut y: Vec<f64> = ya.iter().zip(yb).map(|(p, q)| p + l.w * (q - p)).collect();
            let target = self.tr.scaled(first.at);
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Run a search on `f` over `[0, 1]`: the outcome, the last trial, the trials.
    fn search(f: impl Fn(f64) -> f64) -> (Option<Narrowed>, f64, usize) {
        let mut c = CrossingSearch::new(1.0, f(0.0), f(1.0));
        let mut s = 0.0;
        for k in 0..MAX_TRIALS {
            s = c.next();
            match c.update(s, f(s)) {
                Narrowed::Further => {}
                done => return (Some(done), s, k + 1),
            }
        }
        (None, s, MAX_TRIALS)
    }

    #[test]
    fn a_smooth_crossing_is_located_to_the_bracket_tolerance() {
        let root = 0.3141592653589793;
        let (r, s, _) = search(|s| (s - root) * (1.0 + s));
        assert_eq!(r, Some(Narrowed::Crossing));
        assert!((s - root).abs() < 1e-9, "{s}");
    }

    #[test]
    fn a_square_root_crossing_is_not_taken_for_a_jump() {
        // sign(s - r)·√|s - r|: continuous, with an infinite slope at the root, as the
        // real part of two exponents that collide there.
        let root = 0.7;
        let (r, s, _) = search(|s| (s - root).signum() * (s - root).abs().sqrt());
        assert_eq!(r, Some(Narrowed::Crossing));
        assert!((s - root).abs() < 1e-9, "{s}");
    }

    #[test]
    fn a_jump_is_told_apart_early_when_the_values_do_not_shrink() {
        let at = 0.4;
        let (r, s, trials) = search(|s| if s < at { -0.5 } else { 1.0 });
        assert_eq!(r, Some(Narrowed::Jump));
        assert!((s - at).abs() < 1e-3, "{s}");
        // Bisection to 1e-3 is 10 halvings; the Illinois steps are no slower.
        assert!(trials <= 15, "{trials}");
    }

    #[test]
    fn a_jump_whose_values_shrink_is_told_apart_at_a_millionth_of_the_step() {
        // Continuous up to a jump of a fifth of the scale: the values near the jump are
        // 0.2 and -0.2 of the scale, below the early rule's 0.3.
        let at = 0.6;
        let (r, s, trials) = search(|s| if s < at { 0.2 + (at - s) } else { -0.2 - (s - at) });
        assert_eq!(r, Some(Narrowed::Jump));
        assert!((s - at).abs() < 1e-6, "{s}");
        assert!(trials <= 30, "{trials}");
    }
}
