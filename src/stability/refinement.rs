//! Roots of the nonlinear `T(λ)v = 0`: nonlinear inverse iteration with a two-sided
//! Rayleigh step, and the re-centring of fractional candidates.

use super::*;

/// Scratch of the nonlinear iteration: the pivots of `T(λ)`'s LU, the solution of a
/// step, the adjoint vector of the certification step.
pub(super) struct Scratch {
    pub(super) piv: Vec<usize>,
    x: Vec<Complex64>,
    w: Vec<Complex64>,
}

impl Scratch {
    /// For `m` unknowns.
    pub(super) fn new(m: usize) -> Scratch {
        let zero = Complex64::new(0.0, 0.0);
        Scratch { piv: vec![0; m], x: vec![zero; m], w: vec![zero; m] }
    }
}

impl Hill {
    /// One step of inverse iteration at `l0` from a fixed start vector: the start of
    /// the nonlinear iteration when no eigenvector is known.
    pub(super) fn start_vector(
        &mut self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        exact: bool,
    ) -> Option<Vec<Complex64>> {
        self.op.eval_t(params, omega, l0, exact);
        let mut v: Vec<Complex64> =
            (0..self.op.m).map(|i| Complex64::new(1.0 + (i as f64 * 0.37).sin(), 0.0)).collect();
        if !self.op.factor_t(&mut self.nw.piv) {
            return None;
        }
        self.op.solve_t(&self.nw.piv, &mut v);
        normalise(&mut v)?;
        Some(v)
    }

    /// Nonlinear inverse iteration from the candidate `l0`, then re-centring: the root
    /// it reaches is returned only if its eigenvector is centred (`|centre| ≤ 1/2`);
    /// otherwise it is a copy `λ - ijΩ` of the centred root (centre near `j`), and the
    /// iteration is restarted from `λ + ijΩ`. If the restarts do not settle (the root of
    /// a mode mixed between two harmonics lands on one copy, then the other), the best
    /// centred root is kept if its `|centre|` is at most [`OFF_CENTRE_MAX`]: a root of
    /// `T`, where a frozen value would be none. The root and its `|centre|`; `None` if
    /// it fails.
    ///
    /// Why: the frozen candidate of a mode whose fractional damping is large (the body
    /// and wheel modes of the quarter car, whose `k = 0` block has no damping at all
    /// when frozen) is off the true root by more than `Ω/2` at low Ω, and Newton then
    /// converges to whichever copy is nearest. That copy is a root of the truncated
    /// `T(λ)` too, but a less accurate one, and tracking from it would leave the
    /// centred copy at the first step.
    pub(super) fn refine(
        &mut self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        mut v0: Option<Vec<Complex64>>,
        max_iter: usize,
    ) -> Option<(Complex64, f64)> {
        let mut start = l0;
        let mut best: Option<(f64, Complex64)> = None;
        for _ in 0..RECENTRE_TRIES {
            let (v, factored) = match v0.take() {
                Some(v) => (v, false),
                // `self.op.t` holds the LU of T(start) from the start vector: the first
                // step reuses it.
                None => (self.start_vector(params, omega, start, true)?, true),
            };
            let (mut l, mut v, _) =
                self.newton(params, omega, start, v, max_iter, factored, true)?;
            to_upper_half(&mut l, &mut v, omega);
            let c = spread(&v, self.op.ndof, self.op.harmonics).centre;
            if c.abs() <= 0.5 {
                return Some((l, c.abs()));
            }
            if best.is_none_or(|(b, _)| c.abs() < b) {
                best = Some((c.abs(), l));
            }
            start = l + Complex64::new(0.0, c.round() * omega);
        }
        best.filter(|&(c, _)| c <= OFF_CENTRE_MAX).map(|(c, l)| (l, c))
    }

    /// Nonlinear inverse iteration (Ruhe 1973) on `T(λ) v = 0` from `(l0, v)`, `v` of
    /// unit norm: `T(λ) x = T'(λ) v`, `λ ← λ - (uᴴv)/(uᴴx)`, `v ← x/(uᴴx)` with
    /// `u` the start vector. Converged when the step is below `1e-12·scale`, or below
    /// `1e-7·scale` and `1e-3` times the previous one (quadratic convergence observed:
    /// the remaining error is then below `1e-10·scale`). `factored`: `self.op.t` already
    /// holds the LU of `T(l0)`. The root, its unit eigenvector and the iterations.
    ///
    /// After each step the next one is first tried without a factorisation: with `w`
    /// from one adjoint inverse iteration on the factors at hand (`T(λ_k)ᴴ w = u`, close
    /// to the left eigenvector as `λ_k` is close to the root), the two-sided Rayleigh
    /// functional step `δ = wᴴT(λ)v / wᴴT'(λ)v` (Ostrowski; Schreiber 2008) is the Newton
    /// step on the scalar `wᴴT(λ)v = 0`, and its error is of the order of the product of
    /// the errors of `v` and `w`, both first order in `λ_k`'s. It is accepted under the
    /// same rule as a full step; otherwise the full step follows. Along a curve this
    /// saves the second factorisation of most points.
    #[allow(clippy::too_many_arguments)] // the iteration's inputs, no natural grouping
    pub(super) fn newton(
        &mut self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        mut v: Vec<Complex64>,
        max_iter: usize,
        factored: bool,
        exact: bool,
    ) -> Option<(Complex64, Vec<Complex64>, usize)> {
        let u = v.clone();
        let mut lambda = l0;
        let scale = omega.max(l0.norm());
        let mut last = f64::INFINITY;
        let done =
            |s: f64, last: f64| s <= 1e-12 * scale || (s <= 1e-7 * scale && s <= 1e-3 * last);
        for it in 0..max_iter {
            let reuse = factored && it == 0;
            if !reuse {
                self.op.eval_t(params, omega, lambda, exact);
            }
            self.op.apply_t(params, omega, lambda, exact, &v, false);
            self.nw.x.copy_from_slice(&self.op.dtv);
            if !reuse && !self.op.factor_t(&mut self.nw.piv) {
                return None;
            }
            self.op.solve_t(&self.nw.piv, &mut self.nw.x);
            let ux: Complex64 = u.iter().zip(&self.nw.x).map(|(a, b)| a.conj() * b).sum();
            let uv: Complex64 = u.iter().zip(&v).map(|(a, b)| a.conj() * b).sum();
            if ux.norm() == 0.0 || !ux.re.is_finite() || !ux.im.is_finite() {
                return None;
            }
            let step = uv / ux;
            lambda -= step;
            for (vi, xi) in v.iter_mut().zip(&self.nw.x) {
                *vi = xi / ux;
            }
            if !lambda.re.is_finite() || !lambda.im.is_finite() {
                return None;
            }
            let s = step.norm();
            // Quadratic convergence: the next error is about s²/last ≤ 1e-3·s.
            if done(s, last) {
                return converged(lambda, v, it + 1);
            }
            last = s;
            // The Rayleigh step at the new λ: w from the factors of T(λ_k), T(λ)v and
            // T'(λ)v without assembling T(λ).
            self.nw.w.copy_from_slice(&u);
            self.op.solve_t_adjoint(&self.nw.piv, &mut self.nw.w);
            self.op.apply_t(params, omega, lambda, exact, &v, true);
            let wr: Complex64 = self.nw.w.iter().zip(&self.op.tv).map(|(a, b)| a.conj() * b).sum();
            let wd: Complex64 = self.nw.w.iter().zip(&self.op.dtv).map(|(a, b)| a.conj() * b).sum();
            let delta = wr / wd;
            if delta.re.is_finite() && delta.im.is_finite() && done(delta.norm(), last) {
                return converged(lambda - delta, v, it + 1);
            }
        }
        None
    }
}

/// One exponent of each conjugate pair is kept, the one in the upper half plane:
/// conjugate `l` and its eigenvector `v` if `l` is below it (beyond rounding, `1e-12·Ω`).
/// Whether it did.
pub(super) fn to_upper_half(l: &mut Complex64, v: &mut [Complex64], omega: f64) -> bool {
    if l.im >= -1e-12 * omega {
        return false;
    }
    *l = l.conj();
    v.iter_mut().for_each(|x| *x = x.conj());
    true
}

/// Restarts of a fractional refinement that lands on an off-centre copy.
pub(super) const RECENTRE_TRIES: usize = 3;

/// The largest `|centre|` of a root kept when re-centring does not settle: within one
/// harmonic of the centre (on the 5-mass chain such roots alternate between centres
/// about 0.55 and -0.51; those that wander farther, 1.4 to 3.3, are lost).
pub(super) const OFF_CENTRE_MAX: f64 = 1.0;

/// Whether a root of `T` with eigenvector centre `centre` (absolute) may decide that a
/// solution is unstable: a centred one may; an off-centre one (kept within
/// [`OFF_CENTRE_MAX`]) only where it is stable. An off-centre root is a copy of an
/// exponent whose centred copy was not found, and truncation can leave a root far from
/// the centre with no centred counterpart at all: on the 20-mass chain at N = 11,
/// 0.119 rad/s, 0.0025 + 0.126i (centre -0.89) while the root count of the centred
/// strip finds no unstable root, and time integration started on the solution sees a
/// perturbation decay. Such a root leaves the verdict to the count.
pub(super) fn may_witness(l: Complex64, centre: f64, threshold: f64) -> bool {
    centre <= 0.5 || l.re <= threshold
}

/// The result of [`Hill::newton`] at convergence: the root, its unit eigenvector and
/// the iterations; `None` at exactly zero (where the fractional factors `λ^q` branch)
/// or for an eigenvector that cannot be normalised.
pub(super) fn converged(
    lambda: Complex64,
    mut v: Vec<Complex64>,
    its: usize,
) -> Option<(Complex64, Vec<Complex64>, usize)> {
    if lambda == Complex64::new(0.0, 0.0) {
        return None;
    }
    normalise(&mut v)?;
    Some((lambda, v, its))
}

/// Scale `v` to unit 2-norm; `None` if it is zero or not finite.
pub(super) fn normalise(v: &mut [Complex64]) -> Option<()> {
    let n = v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    v.iter_mut().for_each(|z| *z /= n);
    Some(())
}
