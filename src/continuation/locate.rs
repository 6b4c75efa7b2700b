//! Locating events inside an accepted step: folds (the tangent's parameter component
//! changes sign), changes of stability (the largest real part of the exponents
//! crosses zero) and the exact landing points of jumps. Each search walks along the
//! step's border direction, correcting back onto the curve at every trial.

use super::events::Event;
use super::jumps::Landing;
use super::stepper::{Continuation, StabilityChange};
use super::tracer::{dot, unit};
use crate::outputs::{At, Direction};
use crate::results::{Fold, Jump, Peak};
use crate::stability::{Hill, StabilityOptions};

/// The cubic Hermite interpolant of a step of the curve, from `(y0, t0)` to
/// `(y1, t1)` (unit tangents, scaled by the chord's length), at `σ ∈ [0, 1]`.
struct Hermite<'a> {
    y0: &'a [f64],
    t0: &'a [f64],
    y1: &'a [f64],
    t1: &'a [f64],
    chord: f64,
}

impl Hermite<'_> {
    /// The point at `σ` and the direction of the interpolant there (not normalised).
    fn at(&self, s: f64, y: &mut [f64], t: &mut [f64]) {
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) =
            (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2);
        let (d00, d10, d01, d11) =
            (6.0 * s2 - 6.0 * s, 3.0 * s2 - 4.0 * s + 1.0, -6.0 * s2 + 6.0 * s, 3.0 * s2 - 2.0 * s);
        let l = self.chord;
        for i in 0..y.len() {
            let (a, b, c, d) = (self.y0[i], l * self.t0[i], self.y1[i], l * self.t1[i]);
            y[i] = h00 * a + h10 * b + h01 * c + h11 * d;
            t[i] = d00 * a + d10 * b + d01 * c + d11 * d;
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

    /// The rate of change of output `k`'s `max_abs` along the curve at `y`, moving
    /// along `t` (only its sign and its zero matter: coefficients are scaled).
    fn peak_slope(&mut self, y: &[f64], t: &[f64], k: usize) -> f64 {
        let n = self.tr.n;
        let mut c = vec![0.0; n];
        let mut dc = vec![0.0; n];
        self.tr.coeffs(y, &mut c);
        self.tr.coeffs(t, &mut dc);
        let (domega, param) = self.tr.rates(y, t);
        let dir = Direction { coeffs: &dc, omega: domega, param };
        let params = self.tr.params_at(y);
        let at = At {
            model: self.model,
            params: &params,
            omega: self.tr.omega(y),
            period: self.opts.period,
        };
        self.out.slope(&at, &c, &dir, k)
    }

    /// Locate and report every output's local maximum of `max_abs` inside the step
    /// from `nodes[last]` (direction `dirv`) to the point `y` with tangent `t`, whose
    /// slopes of `max_abs` are `slopes`: where a slope goes from rising to falling.
    ///
    /// The zero is found first on the cubic Hermite interpolant of the step (no
    /// corrector: its points are off the curve by `O(h⁴)`), then refined by secant
    /// steps on points corrected back onto the curve, each predicted along the last
    /// one's tangent, until the last move is below 1e-6 of the step: usually one
    /// correction, two corrector iterations.
    pub(super) fn locate_peaks(
        &mut self,
        last: usize,
        dirv: &[f64],
        (y, t): (&[f64], &[f64]),
        slopes: &[f64],
    ) {
        let n = self.tr.n;
        let (y0, t0) = (self.nodes[last].y.clone(), self.nodes[last].t.clone());
        let chord = y.iter().zip(&y0).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
        let hermite = Hermite { y0: &y0, t0: &t0, y1: y, t1: t, chord };
        let (mut yp, mut tp) = (vec![0.0; n + 1], vec![0.0; n + 1]);
        let (mut yq, mut tq) = (vec![0.0; n + 1], vec![0.0; n + 1]);
        for (k, &f1) in slopes.iter().enumerate() {
            let f0 = self.nodes[last].slopes.get(k).copied().unwrap_or(f64::NAN);
            if !(f0 > 0.0 && f1 < 0.0) {
                continue;
            }
            // On the interpolant: σ in [0, 1], no closer than its own error.
            let mut bracket = Illinois::new(1.0, f0, f1);
            for _ in 0..60 {
                let sg = bracket.next();
                hermite.at(sg, &mut yp, &mut tp);
                let f = self.peak_slope(&yp, &tp, k);
                if f == 0.0 || bracket.width() < 1e-7 {
                    break;
                }
                bracket.update(sg, f);
            }
            let s0 = bracket.next().clamp(0.0, 1.0);
            // The interpolant's rate of change of the slope along `dirv` at `s0`, for
            // the first refinement.
            let rate = {
                hermite.at((s0 - 1e-6).max(0.0), &mut yp, &mut tp);
                hermite.at((s0 + 1e-6).min(1.0), &mut yq, &mut tq);
                let df = self.peak_slope(&yq, &tq, k) - self.peak_slope(&yp, &tp, k);
                df / (dot(dirv, &yq) - dot(dirv, &yp))
            };
            hermite.at(s0, &mut yp, &mut tp);
            // On the curve: the position along `dirv` of each trial, and the secant.
            let mut target = dot(dirv, &yp);
            let mut prev: Option<(f64, f64)> = None;
            let mut best: Option<Vec<f64>> = None;
            let mut located = false;
            let step = dot(dirv, y) - dot(dirv, &y0);
            for _ in 0..8 {
                if self.tr.locate_exact(&mut yp, dirv, target).is_err() {
                    break;
                }
                self.tr.tangent(&mut tp);
                let f = self.peak_slope(&yp, &tp, k);
                best = Some(yp.clone());
                let next = match prev {
                    Some((c1, g1)) if f != g1 => target - f * (target - c1) / (f - g1),
                    _ if rate != 0.0 && rate.is_finite() => target - f / rate,
                    _ => target,
                };
                if f == 0.0 {
                    located = true;
                    break;
                }
                prev = Some((target, f));
                // Along the tangent to the next estimate: within O(Δ²) of the curve.
                let along = dot(dirv, &tp);
                if along.abs() < 1e-12 {
                    break;
                }
                let d = (next - target) / along;
                for i in 0..=n {
                    yp[i] += d * tp[i];
                }
                target = next;
                // A last move below 1e-6 of the step: the estimate is within about
                // 1e-8 of the step of the zero (the rate is known to a percent or
                // better), and the tangent's point within 1e-12 of the curve; it
                // needs no corrector.
                if (d * along).abs() < 1e-6 * step.abs() {
                    best = Some(yp.clone());
                    located = true;
                    break;
                }
            }
            // Not located: the peak is there (the slope changed sign between two
            // converged points); report the best converged trial, or the point before.
            let at = best.unwrap_or_else(|| y0.clone());
            let (omega, param, _, outputs) = self.point_at(&at);
            let value = outputs.get(k).map_or(f64::NAN, |o| o.max_abs);
            self.trace.peaks.push(Peak { output: k, omega, param, value, after: last, located });
            self.queue_event(Event::Peak(self.trace.peaks.len() - 1));
        }
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
