//! The operator `T(λ)` of Hill's method and its derivative: the Galerkin projections
//! of the signal gradients, the matrix polynomial of the integer orders (fractional
//! ones frozen at `λ = 0` on request), and `T(λ)`, `T'(λ)v` with the exact fractional
//! factors `(λ ± ikΩ)^q`.

use super::*;
use crate::error::HillFailure;
use crate::linalg::{complex_band_lu_factor, complex_band_lu_solve, complex_band_lu_solve_adjoint};
use crate::model::DynModel;

/// `T(λ)` at one solution and what it is made of: the projections of the signal
/// gradients, the matrix polynomial of the integer orders, the fractional factors, and
/// `T(λ)` itself (assembled, or applied to a vector with `T'(λ)`).
pub(super) struct Operator {
    pub(super) ndof: usize,
    pub(super) harmonics: usize,
    pub(super) len: usize,
    pub(super) m: usize,
    pub(super) samples: usize,
    /// Highest integer order, the degree of the matrix polynomial.
    pub(super) degree: usize,
    pub(super) signals: Vec<(Vec<(usize, f64)>, Order)>,
    /// Some order is fractional at the current parameters, and which signals.
    pub(super) fractional: bool,
    pub(super) fractional_signals: Vec<usize>,
    /// Projection matrices `P[g_{e,j}]`, row-major len×len, index (e * nsig + j).
    pub(super) proj: Vec<f64>,
    /// Gradient spectrum `ĝ_m`, `m = 0..=2N`, the scratch of the block formula, and its
    /// unit spectral factors (`N + 1` ones).
    ghat: Vec<Complex64>,
    ext: Vec<Complex64>,
    ones: Vec<Complex64>,
    /// One projection assembled column-major (the block formula writes columns)
    proj_block: faer::Mat<f64>,
    /// Constant gradient of each projection (`P = g0·I`), if it is one.
    pub(super) diag: Vec<Option<f64>>,
    /// `M_0 .. M_degree`, row-major `m × m`.
    pub(super) coef: Vec<Vec<f64>>,
    /// Nonzero entries `(index, value)` of `M_1 .. M_degree` (index `r - 1`): mass and
    /// damping terms are usually linear, their blocks diagonal in the harmonics, and
    /// `T(λ)` is then `M_0` plus a few entries (see [`Operator::eval_t`]).
    sparse: Vec<Vec<(usize, f64)>>,
    /// The real-basis fractional factors and their derivatives per harmonic, and the
    /// `(q, Ω, λ)` they are for (`None`: scratch of the polynomial's assembly).
    alpha: Vec<[Complex64; 4]>,
    alpha_at: Option<(f64, f64, Complex64)>,
    /// `T(λ)` of [`Operator::eval_t`], row-major (the nonlinear iteration factorises
    /// it in place).
    pub(super) t: Vec<Complex64>,
    /// Diagonals of `T` below and above the main one that can be nonzero: those of
    /// the balance Jacobian (`T(0)`), whose block pattern `T(λ)` shares (equation `e`
    /// reads the signals of DOF `d` at every `λ`). A chain's is block-tridiagonal.
    band: (usize, usize),
    /// `T(λ)v`, `T'(λ)v` of [`Operator::apply_t`], and its per-block scratch (`2·len`).
    pub(super) tv: Vec<Complex64>,
    pub(super) dtv: Vec<Complex64>,
    block: Vec<Complex64>,
}

impl Operator {
    /// The workspace for `model` at `harmonics` harmonics, `period` forcing periods,
    /// and a polynomial of `degree`.
    pub(super) fn new(
        model: &dyn DynModel,
        harmonics: usize,
        period: usize,
        degree: usize,
    ) -> Operator {
        let ndof = model.dofs().len();
        let len = 2 * harmonics + 1;
        let m = ndof * len;
        let signals: Vec<_> = model.signals().iter().map(|s| (s.terms.to_vec(), s.order)).collect();
        let nsig = signals.len();
        let zero = Complex64::new(0.0, 0.0);
        Operator {
            ndof,
            harmonics,
            len,
            m,
            samples: crate::fourier::model_sample_count(model, harmonics, period),
            degree,
            signals,
            fractional: model.signals().iter().any(|s| matches!(s.order, Order::Param(_))),
            fractional_signals: Vec::new(),
            proj: vec![0.0; ndof * nsig * len * len],
            ghat: vec![zero; 2 * harmonics + 1],
            ext: vec![zero; 4 * harmonics + 1],
            ones: vec![Complex64::new(1.0, 0.0); harmonics + 1],
            proj_block: faer::Mat::zeros(len, len),
            diag: vec![None; ndof * nsig],
            coef: (0..=degree).map(|_| vec![0.0; m * m]).collect(),
            sparse: (0..degree).map(|_| Vec::with_capacity(m * m)).collect(),
            alpha: vec![[zero; 4]; harmonics + 1],
            alpha_at: None,
            t: vec![zero; m * m],
            band: (m.saturating_sub(1), m.saturating_sub(1)),
            tv: vec![zero; m],
            dtv: vec![zero; m],
            block: vec![zero; 2 * len],
        }
    }

    /// The order of signal `j` if it is an integer at `params` (a parameter order such
    /// as `p = 1` included, up to the polynomial's degree): its factor `(λ + ikΩ)^q`
    /// is then polynomial, exact in the companion linearisation, with nothing to refine.
    pub(super) fn integer_order(&self, j: usize, params: &[f64]) -> Option<usize> {
        match self.signals[j].1 {
            Order::Int(q) => Some(q as usize),
            order => {
                let q = order.value(params);
                (q >= 0.0 && q.fract() == 0.0 && q <= self.degree as f64).then_some(q as usize)
            }
        }
    }

    /// Which orders are fractional at `params`; whether that changed between none and
    /// some (the kind of problem).
    fn set_orders(&mut self, params: &[f64]) -> bool {
        self.fractional_signals.clear();
        for j in 0..self.signals.len() {
            if self.integer_order(j, params).is_none() {
                self.fractional_signals.push(j);
            }
        }
        let fractional = !self.fractional_signals.is_empty();
        let changed = fractional != self.fractional;
        self.fractional = fractional;
        changed
    }

    /// Galerkin projections `P[g_{e,j}]` of the signal gradients at the solution:
    /// from the gradients' spectra `ĝ_m`, `m ≤ 2N`, by the harmonic balance Jacobian's
    /// own block formula with unit spectral factors (the same samples, so the same
    /// projection as a direct quadrature of `g φ_l φ_k`, at `O(N²)` instead of
    /// `O(M N²)`). Whether the orders changed kind ([`Operator::set_orders`]).
    pub(super) fn project_gradients(
        &mut self,
        bal: &mut Balance<'_>,
        coeffs: &[f64],
        omega: f64,
    ) -> Result<bool> {
        let (len, ns, nh) = (self.len, self.samples, self.harmonics);
        let nsig = self.signals.len();
        if bal.samples() != ns || bal.len() != self.m {
            return Err(Error::Hill {
                omega,
                failure: HillFailure::Workspace {
                    samples: ns,
                    unknowns: self.m,
                    got_samples: bal.samples(),
                    got_unknowns: bal.len(),
                },
            });
        }
        bal.signal_gradients(coeffs, omega);
        self.band = bal.jacobian_band();
        for e in 0..self.ndof {
            for j in 0..nsig {
                let idx = e * nsig + j;
                let g = &bal.gradients()[idx * ns..][..ns];
                if g.iter().all(|&x| x == g[0]) {
                    // A linear term: multiplication by a constant projects to g0·I.
                    self.diag[idx] = Some(g[0]);
                    continue;
                }
                self.diag[idx] = None;
                bal.gradient_spectrum(e, j, &mut self.ghat);
                let (g, ext, ones) = (&self.ghat, &mut self.ext, &self.ones);
                let mut block = self.proj_block.as_mut();
                block.fill(0.0);
                // a block of its own size always holds the whole projection
                let _ = crate::balance::add_block(&mut block, nh, 0, 0, 1.0, g, ext, ones);
                // Row-major, as `T(λ)` is assembled and applied by rows: the block
                // formula writes contiguous columns, so the copy is the transposition
                // of the layout (len² per projection, against the len² per signal term
                // that every `eval_t` and `apply_t` reads).
                let p = &mut self.proj[idx * len * len..(idx + 1) * len * len];
                for (r, row) in p.chunks_exact_mut(len).enumerate() {
                    for (c, v) in row.iter_mut().enumerate() {
                        *v = self.proj_block[(r, c)];
                    }
                }
            }
        }
        Ok(self.set_orders(bal.params()))
    }

    /// `M_r` of `T(λ) = Σ_r λ^r M_r` from the integer-order signals, plus (if `frozen`)
    /// the fractional ones frozen at `λ = 0`.
    pub(super) fn assemble_polynomial(&mut self, params: &[f64], omega: f64, frozen: bool) {
        let (len, nh, nsig, m) = (self.len, self.harmonics, self.signals.len(), self.m);
        self.alpha_at = None; // `alpha` is scratch here
        for c in &mut self.coef {
            c.fill(0.0);
        }
        for j in 0..nsig {
            let order = self.signals[j].1;
            let int = self.integer_order(j, params);
            let (rmax, qi) = match int {
                Some(q) => (q, q),
                None if frozen => (0, 0),
                None => continue,
            };
            let q = order.value(params);
            for r in 0..=rmax {
                // Coefficient of λ^r in (λ ± ikΩ)^q: binom(q, r) (±ikΩ)^(q - r); for a
                // frozen fractional order, r = 0 and the factor (±ikΩ)^p.
                let (binom, s) = match int {
                    Some(_) => (binomial(qi, r), qi as f64 - r as f64),
                    None => (1.0, q),
                };
                for k in 0..=nh {
                    let (a, b) = if k == 0 {
                        (if s == 0.0 { binom } else { 0.0 }, 0.0)
                    } else {
                        let z = crate::fourier::spectral_factor(k, omega, s);
                        (binom * z.re, -binom * z.im)
                    };
                    self.alpha[k][0] = Complex64::new(a, 0.0);
                    self.alpha[k][1] = Complex64::new(b, 0.0);
                }
                let ab = &self.alpha;
                for e in 0..self.ndof {
                    let idx = e * nsig + j;
                    let p = &self.proj[idx * len * len..(idx + 1) * len * len];
                    for &(d, c) in &self.signals[j].0 {
                        let dst = &mut self.coef[r];
                        let (r0, c0) = (e * len, d * len);
                        match self.diag[idx] {
                            Some(g) => {
                                add_diag(dst, m, r0, c0, c * g, nh, |k| (ab[k][0].re, ab[k][1].re))
                            }
                            None => add_product(dst, m, r0, c0, c, p, len, nh, |k| {
                                (ab[k][0].re, ab[k][1].re)
                            }),
                        }
                    }
                }
            }
        }
        for (nz, c) in self.sparse.iter_mut().zip(&self.coef[1..]) {
            nz.clear();
            nz.extend(c.iter().enumerate().filter(|z| *z.1 != 0.0).map(|(i, &x)| (i, x)));
        }
    }

    /// `T(λ)` (row-major, into `self.t`): the polynomial `self.coef` (`M_0` in full, the
    /// higher coefficients by their nonzero entries), and, if `exact`, the fractional
    /// signals with their true factors (principal branch; `self.coef` then assembled
    /// with `frozen = false`). `T'(λ)` is only ever applied: [`Operator::apply_t`].
    pub(super) fn eval_t(&mut self, params: &[f64], omega: f64, lambda: Complex64, exact: bool) {
        let (len, nh, nsig, m, d) =
            (self.len, self.harmonics, self.signals.len(), self.m, self.degree);
        let (pw, _) = powers(lambda, d);
        for (t, &c) in self.t.iter_mut().zip(&self.coef[0]) {
            *t = Complex64::new(c, 0.0);
        }
        for r in 1..=d {
            for &(i, c) in &self.sparse[r - 1] {
                self.t[i] += pw[r] * c;
            }
        }
        if !(self.fractional && exact) {
            return;
        }
        for fi in 0..self.fractional_signals.len() {
            let j = self.fractional_signals[fi];
            self.fractional_factors(self.signals[j].1.value(params), omega, lambda);
            let ab = &self.alpha;
            for e in 0..self.ndof {
                let idx = e * nsig + j;
                let p = &self.proj[idx * len * len..(idx + 1) * len * len];
                for &(dof, c) in &self.signals[j].0 {
                    let (r0, c0) = (e * len, dof * len);
                    let f = |k: usize| (ab[k][0], ab[k][1]);
                    match self.diag[idx] {
                        Some(g) => add_diag(&mut self.t, m, r0, c0, c * g, nh, f),
                        None => add_product(&mut self.t, m, r0, c0, c, p, len, nh, f),
                    }
                }
            }
        }
    }

    /// `self.alpha[k]` for a fractional order `q` at `λ`: the real-basis factors
    /// `(α_k, β_k)` of `(λ ± ikΩ)^q` (principal branch) and their λ-derivatives.
    pub(super) fn fractional_factors(&mut self, q: f64, omega: f64, lambda: Complex64) {
        // A Newton step assembles T(λ) and applies T'(λ) at the same point.
        if self.alpha_at == Some((q, omega, lambda)) {
            return;
        }
        self.alpha_at = Some((q, omega, lambda));
        let zero = Complex64::new(0.0, 0.0);
        let i1 = Complex64::new(0.0, 1.0);
        let f = |z: Complex64| -> (Complex64, Complex64) {
            if q == 0.0 {
                (Complex64::new(1.0, 0.0), zero)
            } else if z == zero {
                (zero, Complex64::new(if q == 1.0 { 1.0 } else { 0.0 }, 0.0))
            } else {
                let v = z.powf(q);
                (v, q * v / z)
            }
        };
        // k = 0: f(λ) itself (α = f₊ = f₋).
        for k in 0..=self.harmonics {
            let w = Complex64::new(0.0, k as f64 * omega);
            let (fp, dfp) = f(lambda + w);
            let (fm, dfm) = if k == 0 { (fp, dfp) } else { f(lambda - w) };
            self.alpha[k] =
                [(fp + fm) * 0.5, i1 * (fp - fm) * 0.5, (dfp + dfm) * 0.5, i1 * (dfp - dfm) * 0.5];
        }
    }

    /// `T(λ)v` and `T'(λ)v` into `self.tv`, `self.dtv` without assembling `T` (the
    /// certification step of [`Hill::newton`]): `M_0 v` in full (real times complex),
    /// the higher coefficients by their nonzero entries, and, if `exact`, each
    /// fractional block `c·P·D` applied as `D` then `P`, the operators of
    /// [`Operator::eval_t`]. Without `want_tv` (a Newton step needs `T'(λ)v` only) the
    /// dense `M_0 v` is skipped and `self.tv` is not valid.
    #[allow(clippy::too_many_arguments)] // the iteration's inputs, as in `newton`
    pub(super) fn apply_t(
        &mut self,
        params: &[f64],
        omega: f64,
        lambda: Complex64,
        exact: bool,
        v: &[Complex64],
        want_tv: bool,
    ) {
        let (len, nh, nsig, m, d) =
            (self.len, self.harmonics, self.signals.len(), self.m, self.degree);
        let zero = Complex64::new(0.0, 0.0);
        let (pw, dpw) = powers(lambda, d);
        if want_tv {
            for (y, row) in self.tv.iter_mut().zip(self.coef[0].chunks_exact(m)) {
                // Real times complex: two real dot products.
                let (mut re, mut im) = (0.0, 0.0);
                for (&a, x) in row.iter().zip(v) {
                    re += a * x.re;
                    im += a * x.im;
                }
                *y = Complex64::new(re, im);
            }
        }
        self.dtv.fill(zero);
        for r in 1..=d {
            for &(i, c) in &self.sparse[r - 1] {
                let x = v[i % m] * c;
                self.tv[i / m] += pw[r] * x;
                self.dtv[i / m] += dpw[r] * x;
            }
        }
        if !(self.fractional && exact) {
            return;
        }
        for fi in 0..self.fractional_signals.len() {
            let j = self.fractional_signals[fi];
            self.fractional_factors(self.signals[j].1.value(params), omega, lambda);
            for e in 0..self.ndof {
                let idx = e * nsig + j;
                for &(dof, c) in &self.signals[j].0 {
                    // D x and D' x for this block's columns.
                    let x = &v[dof * len..(dof + 1) * len];
                    let (y, dy) = self.block.split_at_mut(len);
                    let a0 = &self.alpha[0];
                    y[0] = a0[0] * x[0];
                    dy[0] = a0[2] * x[0];
                    for k in 1..=nh {
                        let [al, be, dal, dbe] = self.alpha[k];
                        let (xa, xb) = (x[k], x[nh + k]);
                        y[k] = al * xa - be * xb;
                        y[nh + k] = be * xa + al * xb;
                        dy[k] = dal * xa - dbe * xb;
                        dy[nh + k] = dbe * xa + dal * xb;
                    }
                    let (tv, dtv) =
                        (&mut self.tv[e * len..][..len], &mut self.dtv[e * len..][..len]);
                    match self.diag[idx] {
                        Some(g) => {
                            let cg = c * g;
                            for l in 0..len {
                                tv[l] += y[l] * cg;
                                dtv[l] += dy[l] * cg;
                            }
                        }
                        None => {
                            let p = &self.proj[idx * len * len..(idx + 1) * len * len];
                            for (l, row) in p.chunks_exact(len).enumerate() {
                                let (mut a, mut b) = (zero, zero);
                                for ((&pk, &yk), &dyk) in row.iter().zip(y.iter()).zip(dy.iter()) {
                                    a += yk * pk;
                                    b += dyk * pk;
                                }
                                tv[l] += a * c;
                                dtv[l] += b * c;
                            }
                        }
                    }
                }
            }
        }
    }
}

impl Operator {
    /// Factorise `self.t` in place within its band, pivots into `piv`; `false` on a
    /// zero or non-finite pivot (the factors then do not solve).
    pub(super) fn factor_t(&mut self, piv: &mut [usize]) -> bool {
        complex_band_lu_factor(&mut self.t, self.m, self.band, piv, 0.0) == 0
    }

    /// `T x = b` in place with the factors of [`Operator::factor_t`].
    pub(super) fn solve_t(&self, piv: &[usize], b: &mut [Complex64]) {
        complex_band_lu_solve(&self.t, self.m, self.band.0 + self.band.1, piv, b);
    }

    /// `Tᴴ x = b` in place with the factors of [`Operator::factor_t`].
    pub(super) fn solve_t_adjoint(&self, piv: &[usize], b: &mut [Complex64]) {
        complex_band_lu_solve_adjoint(&self.t, self.m, self.band.0 + self.band.1, piv, b);
    }
}

/// `λ^r` and `d/dλ λ^r = r λ^{r-1}` for `r = 0..=min(d, 7)`.
pub(super) fn powers(lambda: Complex64, d: usize) -> ([Complex64; 8], [Complex64; 8]) {
    let zero = Complex64::new(0.0, 0.0);
    let (mut pw, mut dpw) = ([zero; 8], [zero; 8]);
    let mut p = Complex64::new(1.0, 0.0);
    for r in 0..=d.min(7) {
        pw[r] = p;
        dpw[r] = if r == 0 { zero } else { pw[r - 1] * r as f64 };
        p *= lambda;
    }
    (pw, dpw)
}

pub(super) fn binomial(n: usize, r: usize) -> f64 {
    (0..r).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// `dst[row0.., col0..] += c · P · D` (`dst` row-major with `stride` columns), where
/// `D` is the real-basis operator with constant factor `ab(0).0` and 2×2 blocks
/// `[[α_k, -β_k], [β_k, α_k]]`, `(α_k, β_k) = ab(k)`, on `(a_k, b_k)`; `P` is
/// row-major `len × len`.
#[allow(clippy::too_many_arguments)]
pub(super) fn add_product<T>(
    dst: &mut [T],
    stride: usize,
    row0: usize,
    col0: usize,
    c: f64,
    p: &[f64],
    len: usize,
    nh: usize,
    ab: impl Fn(usize) -> (T, T),
) where
    T: Copy
        + std::ops::AddAssign
        + std::ops::Add<Output = T>
        + std::ops::Mul<f64, Output = T>
        + std::ops::Neg<Output = T>,
{
    let a0 = ab(0).0;
    for l in 0..len {
        let pl = &p[l * len..(l + 1) * len];
        let row = &mut dst[(row0 + l) * stride + col0..(row0 + l) * stride + col0 + len];
        let pc = pl[0] * c;
        if pc != 0.0 {
            row[0] += a0 * pc;
        }
        for k in 1..=nh {
            let (pa, pb) = (pl[k] * c, pl[nh + k] * c);
            if pa == 0.0 && pb == 0.0 {
                continue;
            }
            let (alpha, beta) = ab(k);
            // (P D)[:, a_k] = P[:, a_k] α + P[:, b_k] β; (P D)[:, b_k] = -P[:, a_k] β + P[:, b_k] α
            row[k] += alpha * pa + beta * pb;
            row[nh + k] += -(beta * pa) + alpha * pb;
        }
    }
}

/// [`add_product`] for `P = g·I` (a constant gradient, `cg = c·g`): only the diagonal
/// 2×2 blocks of `D`.
pub(super) fn add_diag<T>(
    dst: &mut [T],
    stride: usize,
    row0: usize,
    col0: usize,
    cg: f64,
    nh: usize,
    ab: impl Fn(usize) -> (T, T),
) where
    T: Copy + std::ops::AddAssign + std::ops::Mul<f64, Output = T> + std::ops::Neg<Output = T>,
{
    if cg == 0.0 {
        return;
    }
    let at = |i: usize, j: usize| (row0 + i) * stride + col0 + j;
    dst[at(0, 0)] += ab(0).0 * cg;
    for k in 1..=nh {
        let (alpha, beta) = ab(k);
        dst[at(k, k)] += alpha * cg;
        dst[at(k, nh + k)] += -(beta * cg);
        dst[at(nh + k, k)] += beta * cg;
        dst[at(nh + k, nh + k)] += alpha * cg;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagonal_shortcut_equals_the_dense_product() {
        // P = g·I through the dense path and the diagonal one.
        let (nh, len, m) = (3, 7, 14);
        let g = 2.5;
        let p: Vec<f64> =
            (0..len * len).map(|k| if k / len == k % len { g } else { 0.0 }).collect();
        let ab = |k: usize| (Complex64::new(1.0 + k as f64, 0.3), Complex64::new(-0.2, k as f64));
        let mut dense = vec![Complex64::new(0.0, 0.0); m * m];
        let mut diag = dense.clone();
        add_product(&mut dense, m, 7, 0, 1.5, &p, len, nh, ab);
        add_diag(&mut diag, m, 7, 0, 1.5 * g, nh, ab);
        assert_eq!(dense, diag);
    }

    #[test]
    fn applied_t_equals_the_assembled_matrix_and_its_derivative() {
        // T(λ)v from `apply_t` against the matrix `eval_t` assembles, and T'(λ)v against
        // a central difference of T(λ)v, on the quarter car (fractional, a dense
        // projection) and the Duffing oscillator, at complex λ.
        use crate::corrector::{solve, SolveOptions};
        use crate::models::{Duffing, QuarterCar};
        fn check(model: &dyn DynModel, omega: f64, lambda: Complex64) {
            let nh = 4;
            let so = SolveOptions { harmonics: nh, ..Default::default() };
            let sol = solve(model, omega, &so, None).unwrap();
            let mut bal = Balance::new(model, nh).unwrap();
            let mut hill = Hill::new(model, nh).unwrap();
            hill.project(&mut bal, &sol.coeffs, omega).unwrap();
            let params = bal.params().to_vec();
            hill.op.assemble_polynomial(&params, omega, false);
            let m = hill.op.m;
            let v: Vec<Complex64> =
                (0..m).map(|i| Complex64::new((i as f64 * 0.7).sin(), (i as f64).cos())).collect();
            let tv_at = |hill: &mut Hill, l: Complex64| {
                hill.op.apply_t(&params, omega, l, true, &v, true);
                (hill.op.tv.clone(), hill.op.dtv.clone())
            };
            let (tv, dtv) = tv_at(&mut hill, lambda);
            hill.op.eval_t(&params, omega, lambda, true);
            let scale = hill.op.t.iter().fold(0.0f64, |a, z| a.max(z.norm()));
            for i in 0..m {
                let dense: Complex64 = (0..m).map(|j| hill.op.t[i * m + j] * v[j]).sum();
                assert!(
                    (dense - tv[i]).norm() <= 1e-13 * scale * m as f64,
                    "{i}: {dense} vs {}",
                    tv[i]
                );
            }
            let h = 1e-5 * lambda.norm();
            let (tp, _) = tv_at(&mut hill, lambda + h);
            let (tm, _) = tv_at(&mut hill, lambda - h);
            for i in 0..m {
                let fd = (tp[i] - tm[i]) / (2.0 * h);
                let tol = 1e-6 * (dtv[i].norm() + scale / lambda.norm());
                assert!((fd - dtv[i]).norm() <= tol, "{i}: {fd} vs {}", dtv[i]);
            }
        }
        check(
            &QuarterCar { k3: 5e6, F: 0.03, ..Default::default() },
            10.0,
            Complex64::new(-1.3, 9.0),
        );
        check(
            &Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 },
            0.9,
            Complex64::new(-0.2, 1.1),
        );
        // A fractional signal inside a nonlinear term: its projection is dense.
        crate::oscillator! {
            /// x'' + c x' + x + h x² D^p x = F cos Ωt.
            pub struct FracProduct {
                params { c = 0.1, h = 0.3, p = 0.6, F = 0.3 }
                dofs { x }
                equations {
                    D(x, 2) + c * D(x, 1) + x + h * x.powi(2) * D(x, p) = F * cos(omega * t);
                }
            }
        }
        let model = FracProduct::default();
        assert!(model.signals().iter().any(|s| matches!(s.order, Order::Param(_))));
        check(&model, 0.8, Complex64::new(-0.1, 0.9));
    }

    #[test]
    fn spectral_projection_equals_the_sample_quadrature() {
        // P[g]_{lk} = w_l Σ_s φ_l(θ_s) g(θ_s) φ_k(θ_s), directly, against `project` on
        // the cubic spring's gradients of the Duffing oscillator and the quarter car
        // (M samples, fewer than 4N + 1 for the Duffing oscillator at N = 5).
        use crate::corrector::{solve, SolveOptions};
        use crate::models::{Duffing, QuarterCar};
        fn check(model: &dyn DynModel, omega: f64) {
            let nh = 5;
            let sol =
                solve(model, omega, &SolveOptions { harmonics: nh, ..Default::default() }, None)
                    .unwrap();
            let mut bal = Balance::new(model, nh).unwrap();
            let mut hill = Hill::new(model, nh).unwrap();
            hill.project(&mut bal, &sol.coeffs, omega).unwrap();
            let (len, ns) = (hill.op.len, hill.op.samples);
            let mut nonconstant = 0;
            for (idx, d) in hill.op.diag.iter().enumerate() {
                if d.is_some() {
                    continue;
                }
                nonconstant += 1;
                let g = &bal.gradients()[idx * ns..][..ns];
                let phi = |s: usize, l: usize| {
                    let th = 2.0 * std::f64::consts::PI * s as f64 / ns as f64;
                    match l {
                        0 => 1.0,
                        l if l <= nh => (l as f64 * th).cos(),
                        l => ((l - nh) as f64 * th).sin(),
                    }
                };
                let p = &hill.op.proj[idx * len * len..][..len * len];
                let big = g.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for l in 0..len {
                    let w = if l == 0 { 1.0 } else { 2.0 } / ns as f64;
                    for k in 0..len {
                        let q: f64 = (0..ns).map(|s| w * phi(s, l) * g[s] * phi(s, k)).sum();
                        let d = (p[l * len + k] - q).abs();
                        assert!(d <= 1e-13 * big, "{idx} ({l},{k}): {} vs {q}", p[l * len + k]);
                    }
                }
            }
            assert!(nonconstant > 0);
        }
        check(&Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 }, 0.9);
        check(&QuarterCar { k3: 5e6, F: 0.03, ..Default::default() }, 10.0);
    }
}
