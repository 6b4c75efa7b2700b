//! Harmonic balance: the residual in coefficient space and its derivatives.
//!
//! Alternating frequency/time (AFT): Fourier coefficients → signal samples (each
//! signal's spectral operator applied exactly) → the model's residual at each sample
//! → Fourier coefficients of the residual (the Galerkin projection, with the constant
//! term weighted like every harmonic coefficient: R is the coefficient vector of r(θ)).
//!
//! Derivatives never come from hand-written model terms: one pass of the model's
//! residual with a dual number per seeded direction gives `g_{e,s}(θ_j) = ∂r_e/∂s`
//! at every sample. The harmonic Jacobian is then assembled from the Fourier
//! coefficients `ĝ_m` of each `g_{e,s}`: multiplication by `g` is a
//! Toeplitz-plus-Hankel operator on the trigonometric basis, and `D^q` is diagonal in
//! it, so a block costs `O(N²)` instead of a dense `O(N² M)` sample sum.

use crate::error::{Error, Result};
use crate::fourier::{
    apply_factor, apply_order, coeff_len, sample_count, spectral_factor, Fourier,
};
use crate::model::{Model, Order};
use faer::prelude::ReborrowMut;
use faer::MatMut;
use num_complex::Complex64;
use num_dual::Dual64;
use std::f64::consts::FRAC_PI_2;

/// Residual and derivatives of the harmonic balance equations of one model.
///
/// Parameters are copied at construction (change them with [`Balance::set_param`]);
/// buffers are allocated once, so repeated evaluations do not allocate.
///
/// ```
/// use ihbm::balance::Balance;
/// use ihbm::models::Duffing;
/// let model = Duffing::default();
/// let mut hb = Balance::new(&model, 3).unwrap();
/// let a = vec![0.0; hb.len()];
/// let mut r = vec![0.0; hb.len()];
/// hb.residual(&a, 1.0, &mut r);
/// // at rest, the residual is minus the forcing: -F cos θ
/// assert!((r[1] + model.F).abs() < 1e-15);
/// ```
pub struct Balance<'m, M: Model> {
    model: &'m M,
    n: usize,
    ndof: usize,
    nsig: usize,
    m: usize,
    fourier: Fourier,
    params: Vec<f64>,
    orders: Vec<f64>,
    phases: Vec<f64>,
    /// signal samples, `s * M + j`
    sig: Vec<f64>,
    /// scratch samples (a derivative of each signal), `s * M + j`
    dsig: Vec<f64>,
    /// residual samples, `e * M + j`
    res: Vec<f64>,
    /// `∂r_e/∂s` samples, `(e * nsig + s) * M + j`
    grad: Vec<f64>,
    comb: Vec<f64>,
    op: Vec<f64>,
    f_sig: Vec<f64>,
    f_out: Vec<f64>,
    d_params: Vec<Dual64>,
    d_sig: Vec<Dual64>,
    d_out: Vec<Dual64>,
    /// which signals a directional pass seeds (reused, so passes do not allocate)
    seeded: Vec<bool>,
    ghat: Vec<Complex64>,
    /// spectral factors `(ikΩ)^q`, `s * (N + 1) + k`
    lam: Vec<Complex64>,
}

impl<M: Model> std::fmt::Debug for Balance<'_, M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Balance {{ model: {}, harmonics: {}, samples: {} }}",
            self.model.name(),
            self.n,
            self.m
        )
    }
}

/// Check a harmonic count and a frequency the way every entry point does.
pub fn check_inputs(harmonics: usize, omega: f64) -> Result<()> {
    if harmonics == 0 {
        return Err(Error::InvalidValue {
            what: "number of harmonics".into(),
            value: "0".into(),
            expected: "at least 1".into(),
        });
    }
    if !(omega.is_finite() && omega > 0.0) {
        return Err(Error::InvalidValue {
            what: "frequency omega".into(),
            value: omega.to_string(),
            expected: "a finite value > 0 rad/s".into(),
        });
    }
    Ok(())
}

impl<'m, M: Model> Balance<'m, M> {
    /// Buffers and FFT plans for `model` with `harmonics` harmonics.
    pub fn new(model: &'m M, harmonics: usize) -> Result<Self> {
        check_inputs(harmonics, 1.0)?;
        model.validate()?;
        let ndof = model.dofs().len();
        let nsig = model.signals().len();
        for s in model.signals() {
            if s.terms.iter().any(|&(d, _)| d >= ndof) {
                return Err(Error::Other(format!(
                    "model '{}' declares a signal on a DOF index outside 0..{ndof}",
                    model.name()
                )));
            }
        }
        let m = sample_count(model.degree(), harmonics, model.max_forcing_harmonic());
        let fourier = Fourier::new(harmonics, m)?;
        let phases = fourier.phases();
        let l = coeff_len(harmonics);
        let params = model.param_values();
        let mut hb = Balance {
            model,
            n: harmonics,
            ndof,
            nsig,
            m,
            fourier,
            orders: vec![0.0; nsig],
            params,
            phases,
            sig: vec![0.0; nsig * m],
            dsig: vec![0.0; nsig * m],
            res: vec![0.0; ndof * m],
            grad: vec![0.0; ndof * nsig * m],
            comb: vec![0.0; l],
            op: vec![0.0; l],
            f_sig: vec![0.0; nsig],
            f_out: vec![0.0; ndof],
            d_params: vec![Dual64::from_re(0.0); model.params_info().len()],
            d_sig: vec![Dual64::from_re(0.0); nsig],
            d_out: vec![Dual64::from_re(0.0); ndof],
            seeded: vec![false; nsig],
            ghat: vec![Complex64::new(0.0, 0.0); 2 * harmonics + 1],
            lam: vec![Complex64::new(0.0, 0.0); nsig * (harmonics + 1)],
        };
        hb.update_orders();
        Ok(hb)
    }

    fn update_orders(&mut self) {
        for (o, s) in self.orders.iter_mut().zip(self.model.signals()) {
            *o = s.order.value(&self.params);
        }
    }

    /// Length of the unknown vector: `ndof · (2N + 1)`.
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> usize {
        self.ndof * coeff_len(self.n)
    }

    /// Number of harmonics N.
    pub fn harmonics(&self) -> usize {
        self.n
    }

    /// Number of time samples per period M.
    pub fn samples(&self) -> usize {
        self.m
    }

    /// The model.
    pub fn model(&self) -> &'m M {
        self.model
    }

    /// Current parameter values.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// Change parameter `index` for later evaluations.
    pub fn set_param(&mut self, index: usize, value: f64) {
        self.params[index] = value;
        self.update_orders();
    }

    /// The numeric derivative order of each signal.
    pub fn signal_orders(&self) -> &[f64] {
        &self.orders
    }

    /// `∂r_e/∂s` at every sample, layout `(e * nsig + s) * M + j`; valid after
    /// [`Balance::jacobian`] (used by the stability analysis).
    pub fn gradients(&self) -> &[f64] {
        &self.grad
    }

    /// Complex Fourier coefficients `ĝ_m`, `m = 0..=2N`, of `∂r_e/∂s` (after
    /// [`Balance::jacobian`]).
    pub fn gradient_spectrum(&mut self, e: usize, s: usize, out: &mut [Complex64]) {
        let g = &self.grad[(e * self.nsig + s) * self.m..][..self.m];
        self.fourier.spectrum(g, out);
    }

    /// Signal samples from the coefficients, and the spectral factors for Ω.
    fn fill_signals(&mut self, a: &[f64], omega: f64) {
        let l = coeff_len(self.n);
        for (s, sig) in self.model.signals().iter().enumerate() {
            self.comb.fill(0.0);
            for &(d, c) in sig.terms {
                for (x, y) in self.comb.iter_mut().zip(&a[d * l..(d + 1) * l]) {
                    *x += c * y;
                }
            }
            let q = self.orders[s];
            apply_order(&self.comb, q, omega, &mut self.op);
            self.fourier.synthesize(&self.op, &mut self.sig[s * self.m..(s + 1) * self.m]);
            for k in 0..=self.n {
                self.lam[s * (self.n + 1) + k] = spectral_factor(k, omega, q);
            }
        }
    }

    /// Fourier coefficients of the per-equation sample buffer `res` into `out`.
    fn project(&mut self, out: &mut [f64]) {
        let l = coeff_len(self.n);
        for e in 0..self.ndof {
            self.fourier
                .analyze(&self.res[e * self.m..(e + 1) * self.m], &mut out[e * l..(e + 1) * l]);
        }
    }

    /// The harmonic balance residual `R(A, Ω)`.
    pub fn residual(&mut self, a: &[f64], omega: f64, r: &mut [f64]) {
        self.fill_signals(a, omega);
        for j in 0..self.m {
            for s in 0..self.nsig {
                self.f_sig[s] = self.sig[s * self.m + j];
            }
            self.model.residual::<f64>(
                &self.params,
                omega,
                self.phases[j],
                &self.f_sig,
                &mut self.f_out,
            );
            for e in 0..self.ndof {
                self.res[e * self.m + j] = self.f_out[e];
            }
        }
        self.project(r);
    }

    /// The residual `r` and its Jacobian `∂R/∂A` (written, not accumulated).
    pub fn jacobian(&mut self, a: &[f64], omega: f64, r: &mut [f64], mut jac: MatMut<'_, f64>) {
        self.fill_signals(a, omega);
        for (d, &p) in self.d_params.iter_mut().zip(&self.params) {
            *d = Dual64::from_re(p);
        }
        let (m, nsig) = (self.m, self.nsig);
        if nsig == 0 {
            self.residual(a, omega, r);
        }
        for s0 in 0..nsig {
            for j in 0..m {
                for s in 0..nsig {
                    self.d_sig[s] =
                        Dual64::new(self.sig[s * m + j], if s == s0 { 1.0 } else { 0.0 });
                }
                self.model.residual(
                    &self.d_params,
                    Dual64::from_re(omega),
                    self.phases[j],
                    &self.d_sig,
                    &mut self.d_out,
                );
                for e in 0..self.ndof {
                    self.grad[(e * nsig + s0) * m + j] = self.d_out[e].eps;
                    if s0 == 0 {
                        self.res[e * m + j] = self.d_out[e].re;
                    }
                }
            }
        }
        if nsig > 0 {
            self.project(r);
        }
        jac.fill(0.0);
        let signals = self.model.signals();
        for e in 0..self.ndof {
            for (s, sig) in signals.iter().enumerate() {
                let g = &self.grad[(e * nsig + s) * m..][..m];
                let lam = &self.lam[s * (self.n + 1)..][..self.n + 1];
                let g0 = g[0];
                if g.iter().all(|&x| x == g0) {
                    // a linear term: multiplication by a constant is diagonal
                    if g0 != 0.0 {
                        for &(d, c) in sig.terms {
                            add_diagonal_block(jac.rb_mut(), self.n, e, d, c * g0, lam);
                        }
                    }
                    continue;
                }
                self.fourier.spectrum(g, &mut self.ghat);
                for &(d, c) in sig.terms {
                    add_block(jac.rb_mut(), self.n, e, d, c, &self.ghat, lam);
                }
            }
        }
    }

    /// One directional-derivative pass: signals marked in `self.seeded` carry `dsig`
    /// (the others zero), Ω is seeded with `d_omega`, parameter `param` (if any) with
    /// 1; projected into `out`.
    fn directional(&mut self, omega: f64, d_omega: f64, param: Option<usize>, out: &mut [f64]) {
        for (i, (d, &p)) in self.d_params.iter_mut().zip(&self.params).enumerate() {
            *d = Dual64::new(p, if Some(i) == param { 1.0 } else { 0.0 });
        }
        let m = self.m;
        for j in 0..m {
            for s in 0..self.nsig {
                let eps = if self.seeded[s] { self.dsig[s * m + j] } else { 0.0 };
                self.d_sig[s] = Dual64::new(self.sig[s * m + j], eps);
            }
            self.model.residual(
                &self.d_params,
                Dual64::new(omega, d_omega),
                self.phases[j],
                &self.d_sig,
                &mut self.d_out,
            );
            for e in 0..self.ndof {
                self.res[e * m + j] = self.d_out[e].eps;
            }
        }
        self.project(out);
    }

    /// `∂R/∂Ω` at fixed coefficients. Every spectral factor `(ikΩ)^q` has
    /// derivative `(q/Ω)(ikΩ)^q`, so each signal moves by `(q/Ω)·s(θ)`.
    pub fn d_omega(&mut self, a: &[f64], omega: f64, out: &mut [f64]) {
        self.fill_signals(a, omega);
        let m = self.m;
        for s in 0..self.nsig {
            let f = self.orders[s] / omega;
            for j in 0..m {
                self.dsig[s * m + j] = f * self.sig[s * m + j];
            }
        }
        self.seeded.fill(true);
        self.directional(omega, 1.0, None, out);
    }

    /// `∂R/∂θ_i` for parameter `index` at fixed coefficients and Ω: the direct
    /// dependence (through the dual-number parameters) plus, when the parameter is a
    /// fractional order, `∂(ikΩ)^q/∂q = (ln kΩ + iπ/2)(ikΩ)^q` on its signals.
    pub fn d_param(&mut self, a: &[f64], omega: f64, index: usize, out: &mut [f64]) {
        self.fill_signals(a, omega);
        let l = coeff_len(self.n);
        let m = self.m;
        self.seeded.fill(false);
        for (s, sig) in self.model.signals().iter().enumerate() {
            if sig.order != Order::Param(index) {
                continue;
            }
            self.seeded[s] = true;
            self.comb.fill(0.0);
            for &(d, c) in sig.terms {
                for (x, y) in self.comb.iter_mut().zip(&a[d * l..(d + 1) * l]) {
                    *x += c * y;
                }
            }
            let q = self.orders[s];
            apply_factor(&self.comb, &mut self.op, |k| {
                if k == 0 {
                    Complex64::new(0.0, 0.0)
                } else {
                    spectral_factor(k, omega, q)
                        * Complex64::new((k as f64 * omega).ln(), FRAC_PI_2)
                }
            });
            self.fourier.synthesize(&self.op, &mut self.dsig[s * m..(s + 1) * m]);
        }
        self.directional(omega, 0.0, Some(index), out);
    }
}

/// `g` times the basis function, as a complex coefficient at harmonic `m` (|m| <= 2N).
#[inline]
fn g_at(ghat: &[Complex64], m: isize) -> Complex64 {
    if m >= 0 {
        ghat[m as usize]
    } else {
        ghat[(-m) as usize].conj()
    }
}

/// Add `c · D^q` into the `(e, d)` block (the case of a constant `g`, folded into `c`):
/// `D^q` maps `(cos kθ, sin kθ)` by the 2×2 rotation-scaling of `λ_k = (ikΩ)^q`.
fn add_diagonal_block(
    mut jac: MatMut<'_, f64>,
    n: usize,
    e: usize,
    d: usize,
    c: f64,
    lam: &[Complex64],
) {
    let l = coeff_len(n);
    let (row0, col0) = (e * l, d * l);
    jac[(row0, col0)] += c * lam[0].re;
    for k in 1..=n {
        let (re, im) = (c * lam[k].re, c * lam[k].im);
        jac[(row0 + k, col0 + k)] += re;
        jac[(row0 + n + k, col0 + k)] -= im;
        jac[(row0 + k, col0 + n + k)] += im;
        jac[(row0 + n + k, col0 + n + k)] += re;
    }
}

/// Add `c · P[g] · D^q` into the `(e, d)` block of the Jacobian: column `cos jθ` (or
/// `sin jθ`) is the coefficient vector of `g · D^q cos jθ` (or `sin`). With
/// `D^q cos jθ = Re(λ_j e^{ijθ})` the product has complex coefficients
/// `ŵ_k = ĝ_{k-j} û_j + ĝ_{k+j} û_{-j}`.
fn add_block(
    mut jac: MatMut<'_, f64>,
    n: usize,
    e: usize,
    d: usize,
    c: f64,
    ghat: &[Complex64],
    lam: &[Complex64],
) {
    let l = coeff_len(n);
    let (row0, col0) = (e * l, d * l);
    let half = Complex64::new(0.5, 0.0);
    let mut column = |col: usize, j: usize, up: Complex64, um: Complex64| {
        for k in 0..=n {
            let (ki, ji) = (k as isize, j as isize);
            let w = if j == 0 {
                g_at(ghat, ki) * up
            } else {
                g_at(ghat, ki - ji) * up + g_at(ghat, ki + ji) * um
            };
            if k == 0 {
                jac[(row0, col)] += c * w.re;
            } else {
                jac[(row0 + k, col)] += c * 2.0 * w.re;
                jac[(row0 + n + k, col)] -= c * 2.0 * w.im;
            }
        }
    };
    if lam[0].re != 0.0 {
        column(col0, 0, lam[0], Complex64::new(0.0, 0.0));
    }
    for j in 1..=n {
        let up = lam[j] * half;
        column(col0 + j, j, up, up.conj());
        // sin jθ = (e^{ijθ} - e^{-ijθ}) / 2i
        let up = lam[j] * Complex64::new(0.0, -0.5);
        column(col0 + n + j, j, up, up.conj());
    }
}

/// The exact periodic solution of the model linearized about zero: per harmonic, the
/// complex system `Σ_d T_k[e][d] X_{d,k} = -F_{e,k}` with
/// `T_k[e][d] = Σ_s ∂r_e/∂s · c_{s,d} · (ikΩ)^{q_s}`. The default initial guess.
///
/// ```
/// use ihbm::balance::linearized_guess;
/// use ihbm::models::Duffing;
/// // with k3 = 0 the Duffing oscillator is linear: X = F / (k - mΩ² + icΩ)
/// let mut m = Duffing::default();
/// m.k3 = 0.0;
/// let a = linearized_guess(&m, 2.0, 3).unwrap();
/// let den = num_complex::Complex64::new(m.k - m.m * 4.0, m.c * 2.0);
/// let x = num_complex::Complex64::new(m.F, 0.0) / den;
/// assert!((a[1] - x.re).abs() < 1e-14 && (a[4] + x.im).abs() < 1e-14);
/// ```
pub fn linearized_guess<M: Model>(model: &M, omega: f64, harmonics: usize) -> Result<Vec<f64>> {
    check_inputs(harmonics, omega)?;
    let mut hb = Balance::new(model, harmonics)?;
    Ok(linearized_on(&mut hb, omega)?.0)
}

/// [`linearized_guess`] on an existing [`Balance`]; also returns `R(0)`, the residual
/// at rest (minus the forcing), which the corrector uses as its residual scale.
pub(crate) fn linearized_on<M: Model>(
    hb: &mut Balance<'_, M>,
    omega: f64,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let model = hb.model;
    let (n, ndof, nsig, m) = (hb.n, hb.ndof, hb.nsig, hb.m);
    let l = coeff_len(n);
    let zero = vec![0.0; hb.len()];
    let mut r0 = vec![0.0; hb.len()];
    let mut jac = faer::Mat::<f64>::zeros(hb.len(), hb.len());
    hb.jacobian(&zero, omega, &mut r0, jac.as_mut());
    // ∂r/∂s at rest; constant in time for additive forcing, averaged otherwise
    let gbar: Vec<f64> = (0..ndof * nsig)
        .map(|i| hb.grad[i * m..(i + 1) * m].iter().sum::<f64>() / m as f64)
        .collect();
    let mut a = vec![0.0; hb.len()];
    let mut t = vec![Complex64::new(0.0, 0.0); ndof * ndof];
    let mut x = vec![Complex64::new(0.0, 0.0); ndof];
    for k in 0..=n {
        t.fill(Complex64::new(0.0, 0.0));
        for e in 0..ndof {
            for (s, sig) in model.signals().iter().enumerate() {
                let lam = spectral_factor(k, omega, hb.orders[s]);
                for &(d, c) in sig.terms {
                    t[e * ndof + d] += lam * (gbar[e * nsig + s] * c);
                }
            }
            x[e] = if k == 0 {
                Complex64::new(-r0[e * l], 0.0)
            } else {
                -Complex64::new(r0[e * l + k], -r0[e * l + n + k])
            };
        }
        complex_solve(&mut t, &mut x, ndof).map_err(|detail| Error::SingularJacobian {
            omega,
            detail: format!(
                "the model linearized about zero is singular at harmonic {k} ({detail}); \
                 give an initial guess instead"
            ),
        })?;
        for d in 0..ndof {
            a[d * l + k] = x[d].re;
            if k > 0 {
                a[d * l + n + k] = -x[d].im;
            }
        }
    }
    Ok((a, r0))
}

/// Gaussian elimination with partial pivoting on a small dense complex system
/// (row-major `a`, right-hand side `b` overwritten by the solution). A zero pivot
/// with a zero right-hand side gives the zero solution for that unknown.
fn complex_solve(
    a: &mut [Complex64],
    b: &mut [Complex64],
    n: usize,
) -> std::result::Result<(), String> {
    let scale = a.iter().fold(0.0f64, |s, z| s.max(z.norm()));
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| a[i * n + col].norm().total_cmp(&a[j * n + col].norm()))
            .unwrap_or(col);
        if piv != col {
            for k in 0..n {
                a.swap(col * n + k, piv * n + k);
            }
            b.swap(col, piv);
        }
        let p = a[col * n + col];
        if p.norm() <= 1e-300 + 1e-14 * scale {
            continue;
        }
        for i in col + 1..n {
            let f = a[i * n + col] / p;
            if f.norm() == 0.0 {
                continue;
            }
            for k in col..n {
                let v = a[col * n + k];
                a[i * n + k] -= f * v;
            }
            let v = b[col];
            b[i] -= f * v;
        }
    }
    for col in (0..n).rev() {
        let mut s = b[col];
        for k in col + 1..n {
            s -= a[col * n + k] * b[k];
        }
        let p = a[col * n + col];
        if p.norm() <= 1e-300 + 1e-14 * scale {
            if s.norm() <= 1e-14 * (1.0 + b.iter().fold(0.0f64, |m, z| m.max(z.norm()))) {
                b[col] = Complex64::new(0.0, 0.0);
                continue;
            }
            return Err(format!("zero pivot for unknown {col}"));
        }
        b[col] = s / p;
    }
    Ok(())
}
