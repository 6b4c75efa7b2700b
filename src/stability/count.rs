//! Roots of `det T(λ)` counted without an eigensolve: in the unstable half of the
//! central strip by the argument principle (the verdict where a candidate's refinement
//! failed, and a check of the analysis by another method), and on the positive real
//! axis by its sign changes (the real exponent a fractional fold leaves, which no
//! candidate refines to).
//!
//! The contour is the rectangle `tol·Ω ≤ Re λ ≤ right`, `y₀ ≤ Im λ ≤ y₀ + Ω`: one
//! strip of height Ω holds one copy of each exponent, and its left edge is the
//! verdict's threshold, so the count is the number of exponents that make the solution
//! unstable. `T` is analytic inside (the branch points `λ = -ikΩ` of the fractional
//! factors lie on the imaginary axis, left of the contour); the winding of `det T`
//! along it is followed by steps that turn its argument by at most [`MAX_TURN`].

use super::*;
use crate::error::HillFailure;
use std::f64::consts::PI;

/// The largest change of `arg det T` accepted between neighbouring contour points; a
/// larger one halves the step. Well below π, the limit beyond which a turn could be
/// mistaken for one the other way, and small enough that a root close to the contour
/// is not stepped past: at π/4 the count of the 5-mass chain at 0.577 rad/s was 1
/// where the verdict (and the count at π/8) is 0. A count there took about 500
/// factorisations (264 at π/4) when every accepted step doubled the next (fewer now,
/// [`STEP_AIM`]): the lightly damped exponents lie close to the left edge, each a
/// quick turn.
pub(super) const MAX_TURN: f64 = PI / 8.0;

/// Evaluations of `det T` a count may take (each a factorisation of `T`) before it
/// gives up: a root on or next to the contour.
pub(super) const MAX_EVALS: usize = 4000;

/// Cells of the logarithmic grid on which a missed real root is located.
const REAL_GRID: usize = 48;

/// The right edge of the counting contour and of the real-axis search: `Ω` plus
/// twice the largest real part of `known` (frozen candidates and roots; a root beyond
/// would be far from every eigenvalue of the frozen problem, which the fractional
/// factors' change from `λ = 0` moves by a fraction of the damping).
pub(super) fn right_edge(known: &[Complex64], omega: f64) -> f64 {
    omega + 2.0 * known.iter().map(|l| l.re).fold(0.0, f64::max)
}

/// The turn a step aims at, as a fraction of [`MAX_TURN`], when the last accepted one
/// sets its length. Measured on the 10-mass chain at N = 5 (130 counts): doubling
/// after every accepted step took 30 531 factorisations (13 009 of them rejected
/// steps); aiming at 0.6, 0.8, 0.9 and 1.0 of the limit, 21 353, 19 831, 19 681 and
/// 25 520, with the same verdicts.
const STEP_AIM: f64 = 0.8;

/// Initial steps per edge of the contour.
const EDGE_STEPS: usize = 16;

impl Hill {
    /// The number of roots of the exact `T(λ)` (assembled: [`Operator::assemble_polynomial`]
    /// with `frozen = false`) with `Re λ > tol·Ω` in a strip of height Ω placed away
    /// from the exponents `known` (folded or not) whose real parts are near or above
    /// the threshold, up to their [`right_edge`]. Fails with the reason if the winding is not
    /// resolved within [`MAX_EVALS`] factorisations or is not close to an integer.
    pub(super) fn count_unstable(
        &mut self,
        params: &[f64],
        omega: f64,
        tol: f64,
        known: &[Complex64],
    ) -> Result<usize> {
        let left = tol * omega;
        let right = right_edge(known, omega);
        let fail = |why: String| failure(omega, why);
        if !(right > left && right.is_finite()) {
            return Err(fail(format!("no contour: right edge {right:e} ≤ left edge {left:e}")));
        }
        let y0 = strip_bottom(known, left, omega);
        self.roots_inside(params, omega, [left, right, y0, y0 + omega])
    }

    /// The number of roots of `T(λ)` inside the rectangle `[re₀, re₁] × [im₀, im₁]`
    /// (`rect`), by the winding of `det T` along its edges. A rectangle symmetric about
    /// the real axis is walked along its upper half only: `T(λ̄)` is the conjugate of
    /// `T(λ)` (a real model in the real basis), so `arg det T` turns along the lower half
    /// as along the upper, and the half's turn from the real axis back to it (where
    /// `det T` is real) is half the winding, at half the factorisations.
    fn roots_inside(&mut self, params: &[f64], omega: f64, rect: [f64; 4]) -> Result<usize> {
        let [left, right, y0, y1] = rect;
        let c = Complex64::new;
        let (turn, halves) = if y0 == -y1 {
            let path = [c(right, 0.0), c(right, y1), c(left, y1), c(left, 0.0)];
            (self.turn_along(params, omega, &path)?, 2.0)
        } else {
            let path = [c(left, y0), c(right, y0), c(right, y1), c(left, y1), c(left, y0)];
            (self.turn_along(params, omega, &path)?, 1.0)
        };
        let winding = halves * turn / (2.0 * PI);
        let count = winding.round();
        if (winding - count).abs() > 0.25 || count < 0.0 {
            return Err(failure(
                omega,
                format!("the winding of det T is {winding:.3}, not a count"),
            ));
        }
        Ok(count as usize)
    }

    /// The turn of `arg det T` along the polyline through `path`, each segment walked
    /// in fractions of its length (at most `1/EDGE_STEPS`), a step that turns by more
    /// than [`MAX_TURN`] halved.
    fn turn_along(&mut self, params: &[f64], omega: f64, path: &[Complex64]) -> Result<f64> {
        let fail = |why: String| failure(omega, why);
        let mut evals = 0;
        let mut turn = 0.0;
        let mut cur = self
            .log_det(params, omega, path[0])
            .ok_or_else(|| fail(format!("T is singular at the contour's corner {}", path[0])))?;
        for e in path.windows(2) {
            let (a, b) = (e[0], e[1]);
            let (mut s, mut h) = (0.0, 1.0 / EDGE_STEPS as f64);
            while s < 1.0 {
                let t = (s + h).min(1.0);
                evals += 1;
                if evals > MAX_EVALS {
                    return Err(fail(format!(
                        "the winding of det T was not resolved in {MAX_EVALS} evaluations \
                         (a root on or next to the contour near {})",
                        a + (b - a) * s
                    )));
                }
                let z = a + (b - a) * t;
                let next = self
                    .log_det(params, omega, z)
                    .ok_or_else(|| fail(format!("T is singular on the contour at {z}")))?;
                let d = wrap(next.im - cur.im);
                if d.abs() > MAX_TURN {
                    h *= 0.5;
                    continue;
                }
                turn += d;
                cur = next;
                s = t;
                // The next step as long as this one's turn says (at most twice, at
                // least half as long): doubling after every accepted step had 43 % of
                // the steps rejected where `arg det T` turns fast, a factorisation each.
                let grow = (STEP_AIM * MAX_TURN / d.abs()).clamp(0.5, 2.0);
                h = (grow * h).min(1.0 / EDGE_STEPS as f64);
            }
        }
        Ok(turn)
    }

    /// A real root of `det T` in `(lo, hi)` that `exps` (folded) lacks, where the
    /// signs of `det T` at the ends say that an odd number of real roots lies between
    /// and `exps` has an even number there (or the other way round). `T(x)` is real for
    /// real `x` (the fractional factors of `±ikΩ` come as conjugates), so `det T` changes
    /// sign at a simple real root. `Ok(None)`: the parities agree. Located on a
    /// logarithmic grid (a root left unexplained by `exps` in one cell) and bisected
    /// to `1e-12` relative; an error if no cell explains the difference.
    ///
    /// Why: after a fold of a fractional model, the real exponent that crossed zero
    /// leaves the branch point `λ = 0` of `λ^q`, small and positive; its frozen
    /// candidate does not refine to it (the iteration meets the branch point), and the
    /// analysis would call the solution stable.
    pub(super) fn missed_real_root(
        &mut self,
        params: &[f64],
        omega: f64,
        lo: f64,
        hi: f64,
        exps: &[Complex64],
    ) -> Result<Option<f64>> {
        let fail = |why: String| failure(omega, why);
        let singular = |x: f64| fail(format!("T is singular at the real λ = {x:e}"));
        let reals = real_between(exps, omega, lo, hi);
        let s_lo = self.det_sign(params, omega, lo).ok_or_else(|| singular(lo))?;
        let s_hi = self.det_sign(params, omega, hi).ok_or_else(|| singular(hi))?;
        self.tr.sign_right = Some(s_hi);
        if (s_lo != s_hi) == (reals.len() % 2 == 1) {
            return Ok(None);
        }
        let ratio = (hi / lo).powf(1.0 / REAL_GRID as f64);
        let (mut a, mut sa) = (lo, s_lo);
        for j in 1..=REAL_GRID {
            let b = if j == REAL_GRID { hi } else { lo * ratio.powi(j as i32) };
            let sb = if j == REAL_GRID {
                s_hi
            } else {
                self.det_sign(params, omega, b).ok_or_else(|| singular(b))?
            };
            let inside = reals.iter().filter(|&&r| r > a && r <= b).count();
            if (sa != sb) != (inside % 2 == 1) {
                let (mut x0, mut x1) = (a, b);
                while x1 - x0 > 1e-12 * x1 {
                    let mid = 0.5 * (x0 + x1);
                    let sm = self.det_sign(params, omega, mid).ok_or_else(|| singular(mid))?;
                    if sm == sa {
                        x0 = mid;
                    } else {
                        x1 = mid;
                    }
                }
                return Ok(Some(0.5 * (x0 + x1)));
            }
            (a, sa) = (b, sb);
        }
        Err(fail(format!(
            "det T changes sign on ({lo:e}, {hi:e}) more often than the exponents found say, \
             but no cell of the grid shows where"
        )))
    }

    /// Whether the real exponents among `exps` (folded) in `(lo, hi)` are as many,
    /// modulo 2, as the signs of `det T` at the ends say (see
    /// [`Hill::missed_real_root`]); `false` also where `T` is singular. The check of a
    /// tracked point: one factorisation, at `lo`, with the sign beyond every root kept
    /// from the last full analysis (the sign at `+∞`, that of the leading coefficient's
    /// determinant, whatever `hi` is as long as no real root lies beyond it).
    pub(super) fn real_parity_agrees(
        &mut self,
        params: &[f64],
        omega: f64,
        lo: f64,
        hi: f64,
        exps: &[Complex64],
    ) -> bool {
        let odd = real_between(exps, omega, lo, hi).len() % 2 == 1;
        let right = self.tr.sign_right.or_else(|| self.det_sign(params, omega, hi));
        let Some(right) = right else { return false };
        self.tr.sign_right = Some(right);
        self.det_sign(params, omega, lo).is_some_and(|left| (left != right) == odd)
    }

    /// The sign of `det T(x)` at a real `x` (`true` positive); `None` if singular.
    fn det_sign(&mut self, params: &[f64], omega: f64, x: f64) -> Option<bool> {
        Some(self.log_det(params, omega, Complex64::new(x, 0.0))?.im.cos() > 0.0)
    }

    /// `log det T(λ)` (its imaginary part is `arg det` modulo 2π), from an LU of `T(λ)`;
    /// `None` if a pivot is zero or not finite.
    fn log_det(&mut self, params: &[f64], omega: f64, lambda: Complex64) -> Option<Complex64> {
        let m = self.op.m;
        self.op.eval_t(params, omega, lambda, true);
        if !self.op.factor_t(&mut self.nw.piv) {
            return None;
        }
        let swaps = (0..m).filter(|&k| self.nw.piv[k] != k).count();
        let mut l = Complex64::new(0.0, PI * (swaps % 2) as f64);
        for k in 0..m {
            let u = self.op.t[k * m + k];
            if u == Complex64::new(0.0, 0.0) || !u.re.is_finite() || !u.im.is_finite() {
                return None;
            }
            l += u.ln();
        }
        Some(l)
    }
}

/// The real exponents among `exps` (folded) in `(lo, hi)`.
fn real_between(exps: &[Complex64], omega: f64, lo: f64, hi: f64) -> Vec<f64> {
    exps.iter().filter(|l| real(**l, omega) && l.re > lo && l.re < hi).map(|l| l.re).collect()
}

/// A count that failed at `omega`, and why.
fn failure(omega: f64, why: String) -> Error {
    Error::Hill { omega, failure: HillFailure::RootCount(why) }
}

/// An angle brought into `(-π, π]`.
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}

/// Placements of the counting strip either side of the central one, up to `Ω/8`.
const SHIFTS: i32 = 4;

/// The bottom of the counting strip: `-Ω/2`, the strip symmetric about the real axis
/// (half the contour, see [`Hill::roots_inside`]), unless an exponent in `known` whose
/// real part is above `left - Ω/4` lies within `Ω/32` of its edges (modulo Ω; the
/// others are far from the edges); then of `-Ω/2 + jΩ/32` (`|j| ≤ 4`), the one
/// farthest from them. Near the central one: truncation makes the copies of an exponent
/// inexact, the more so the farther from the centre, and a strip reaching a branch
/// point `±iΩ` counts the roots near it, which have no centred counterpart.
fn strip_bottom(known: &[Complex64], left: f64, omega: f64) -> f64 {
    let near: Vec<f64> =
        known.iter().filter(|l| l.re > left - 0.25 * omega).map(|l| l.im).collect();
    let gap = |y: f64| {
        near.iter()
            .map(|&im| fold_into_strip(Complex64::new(0.0, im - y), omega).im.abs())
            .fold(f64::INFINITY, f64::min)
    };
    let spacing = omega / (8 * SHIFTS) as f64;
    if gap(-0.5 * omega) >= spacing {
        return -0.5 * omega;
    }
    (-SHIFTS..=SHIFTS)
        .map(|j| -0.5 * omega + j as f64 * spacing)
        .max_by(|&a, &b| gap(a).total_cmp(&gap(b)))
        .unwrap_or(-0.5 * omega)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_brings_angles_into_the_half_open_interval() {
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-15);
        assert!((wrap(2.0 * PI + 0.25) - 0.25).abs() < 1e-12);
    }

    /// A Hill workspace holding the exact `T` of the fractional oscillator
    /// `x'' + c x' + 0.3 D^0.5 x + k x` (3 harmonics; linear, so the state does not matter).
    fn prepared(c: f64, k: f64, omega: f64) -> (Hill, Vec<f64>) {
        use crate::models::FractionalDuffing;
        let model = FractionalDuffing { m: 1.0, c, k, k3: 0.0, h: 0.3, p: 0.5, F: 0.1 };
        let mut bal = Balance::new(&model, 3).unwrap();
        let mut hill = Hill::new(&model, 3).unwrap();
        let coeffs = [0.2, 0.5, -0.1, 0.05, 0.3, 0.02, -0.04];
        hill.prepare_operator(&mut bal, &coeffs, omega).unwrap();
        let params = bal.params().to_vec();
        (hill, params)
    }

    #[test]
    fn det_t_of_the_conjugate_is_the_conjugate() {
        let omega = 2.0;
        let (mut hill, params) = prepared(0.05, 1.0, omega);
        for z in [Complex64::new(0.3, 0.7), Complex64::new(1e-3, -0.9), Complex64::new(2.0, 0.1)] {
            let (a, b) = (
                hill.log_det(&params, omega, z).unwrap(),
                hill.log_det(&params, omega, z.conj()).unwrap(),
            );
            assert!((a.re - b.re).abs() < 1e-12 * a.re.abs().max(1.0), "{a} vs {b}");
            assert!(wrap(a.im + b.im).abs() < 1e-10, "{a} vs {b}");
        }
    }

    #[test]
    fn the_half_contour_counts_what_the_whole_rectangle_counts() {
        // Stable (0), a growing complex pair (2), a growing real root (1): the
        // symmetric strip walked along its upper half, and the same strip moved off
        // symmetry by 1e-9·Ω (walked whole), count alike.
        let omega = 4.0;
        for (c, k, expected) in [(0.05, 1.0, 0), (-0.6, 1.0, 2), (0.05, -1.0, 1)] {
            let (mut hill, params) = prepared(c, k, omega);
            let (left, right, y) = (1e-7 * omega, 3.0 * omega, 0.5 * omega);
            let half = hill.roots_inside(&params, omega, [left, right, -y, y]).unwrap();
            let off = [left, right, -y * (1.0 + 1e-9), y * (1.0 - 1e-9)];
            let whole = hill.roots_inside(&params, omega, off).unwrap();
            assert_eq!((half, whole), (expected, expected), "c = {c}, k = {k}");
        }
    }

    #[test]
    fn the_strip_avoids_the_exponents_near_the_threshold() {
        let omega = 1.0;
        // A period-doubling pair at Im = ±Ω/2: the edges move away from it as far as
        // the placements allow (Ω/8); an exponent far left does not count.
        let known = [Complex64::new(0.1, 0.5), Complex64::new(-5.0, 0.25)];
        let y = strip_bottom(&known, 0.0, omega);
        assert!(((y + 0.5).abs() - 0.125).abs() < 1e-12, "{y}");
        // Exponents well inside: the symmetric strip, exactly (its top is its bottom
        // negated, which selects the half contour).
        let known = [Complex64::new(0.1, 0.4), Complex64::new(-0.01, -0.2)];
        let y = strip_bottom(&known, 0.0, omega);
        assert!(y == -0.5 * omega && y + omega == -y, "{y}");
    }
}
