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
    apply_factor, coeff_len, model_sample_count, order_rate, spectral_factor, Fourier,
};
use crate::linalg::Columns;
use crate::model::{DynModel, Model, Order};
use faer::MatMut;
use num_complex::Complex64;
use num_dual::Dual64;

mod linear;
mod second;
pub(crate) mod size;
mod structure;

pub use linear::linearized_guess;
pub(crate) use linear::linearized_on;
pub use second::BilinearWork;
pub use size::{check_size, MEMORY_LIMIT};

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
pub struct Balance<'m> {
    model: &'m dyn DynModel,
    n: usize,
    ndof: usize,
    nsig: usize,
    m: usize,
    fourier: Fourier,
    params: Vec<f64>,
    orders: Vec<f64>,
    /// The model's phase `Ωt` at each sample: `period` times the balance's own.
    phases: Vec<f64>,
    /// Solutions repeat every `period` forcing periods: the balance runs at
    /// `ω = Ω/period` in the harmonics of `ω`, the model sees `Ω = period·ω`.
    period: f64,
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
    /// The signals that are not affine, in groups no equation reads two of: one dual
    /// pass over the samples seeds a group ([`Model::signal_reads`]).
    groups: Vec<Vec<usize>>,
    /// per group and equation, the signal of the group it reads (`g * ndof + e`)
    group_reader: Vec<Option<usize>>,
    /// `∂r_e/∂s` is not zero at every sample (`e * nsig + s`, with `grad`)
    grad_nonzero: Vec<bool>,
    /// which signals a directional pass seeds (reused, so passes do not allocate)
    seeded: Vec<bool>,
    ghat: Vec<Complex64>,
    /// `ĝ_m` for `m = -2N..=2N` (scratch of `add_block`)
    ext: Vec<Complex64>,
    /// spectral factors `(ikΩ)^q`, `s * (N + 1) + k`
    lam: Vec<Complex64>,
    /// their Ω-free part `(ik)^q`, same layout (set with the orders)
    unit: Vec<Complex64>,
    /// signals whose gradient is constant over a period ([`Model::affine_signals`])
    affine: Vec<bool>,
    explicit_omega: bool,
    /// the coefficients and Ω the signal samples (and `lam`) were filled for
    cache_a: Vec<f64>,
    cache_omega: f64,
    sig_valid: bool,
    /// `grad` holds the gradients at the cached point (set by `jacobian`)
    grad_valid: bool,
    /// equation `e` reads signal `s`, `e * nsig + s` ([`Balance::jacobian_band`])
    reads: Vec<bool>,
}

impl std::fmt::Debug for Balance<'_> {
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
    crate::fourier::check_harmonics(harmonics)?;
    if !(omega.is_finite() && omega > 0.0) {
        return Err(Error::InvalidValue {
            what: "frequency omega".into(),
            value: omega.to_string(),
            expected: "a finite value > 0 rad/s".into(),
        });
    }
    Ok(())
}

impl<'m> Balance<'m> {
    /// Buffers and FFT plans for `model` with `harmonics` harmonics.
    pub fn new(model: &'m dyn DynModel, harmonics: usize) -> Result<Self> {
        Self::with_period(model, harmonics, 1)
    }

    /// The balance of solutions that repeat every `period` forcing periods: its
    /// frequency argument is `ω = Ω/period` and its harmonics are those of `ω` (a
    /// period-1 solution has only every `period`-th of them). `period = 2` is the
    /// branch a period doubling opens ([`crate::bifurcation::period_two`]).
    pub fn with_period(model: &'m dyn DynModel, harmonics: usize, period: usize) -> Result<Self> {
        check_inputs(harmonics, 1.0)?;
        if period == 0 {
            return Err(Error::InvalidValue {
                what: "period".into(),
                value: "0".into(),
                expected: "a whole number of forcing periods >= 1".into(),
            });
        }
        model.validate()?;
        let ndof = model.dofs().len();
        check_size(ndof, harmonics)?;
        // Fewer harmonics than the forcing has would drop part of it without a word.
        let kf = model.max_forcing_harmonic() * period;
        if harmonics < kf {
            return Err(Error::InvalidValue {
                what: "number of harmonics".into(),
                value: format!("N = {harmonics}"),
                expected: format!(
                    "N >= {kf}: model '{}' is forced at {}Ω{}, which fewer harmonics would drop",
                    model.name(),
                    model.max_forcing_harmonic(),
                    if period > 1 {
                        format!(" (harmonic {kf} of Ω/{period})")
                    } else {
                        String::new()
                    }
                ),
            });
        }
        let nsig = model.signals().len();
        for s in model.signals() {
            if s.terms.iter().any(|&(d, _)| d >= ndof) {
                return Err(Error::SignalOutsideDofs {
                    model: model.name().to_string(),
                    dofs: ndof,
                });
            }
        }
        crate::fourier::check_samples(model, harmonics, period)?;
        let m = model_sample_count(model, harmonics, period);
        let fourier = Fourier::new(harmonics, m)?;
        let phases: Vec<f64> = fourier.phases().iter().map(|p| p * period as f64).collect();
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
            period: period as f64,
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
            groups: Vec::new(),
            group_reader: Vec::new(),
            grad_nonzero: vec![false; ndof * nsig],
            seeded: vec![false; nsig],
            ghat: vec![Complex64::new(0.0, 0.0); 2 * harmonics + 1],
            ext: vec![Complex64::new(0.0, 0.0); 4 * harmonics + 1],
            lam: vec![Complex64::new(0.0, 0.0); nsig * (harmonics + 1)],
            unit: vec![Complex64::new(0.0, 0.0); nsig * (harmonics + 1)],
            affine: vec![false; nsig],
            explicit_omega: model.explicit_omega(),
            cache_a: vec![0.0; ndof * l],
            cache_omega: f64::NAN,
            sig_valid: false,
            grad_valid: false,
            reads: Vec::new(),
        };
        hb.update_orders();
        hb.check_structure()?;
        hb.adopt_reads()?;
        Ok(hb)
    }

    fn update_orders(&mut self) {
        for (o, s) in self.orders.iter_mut().zip(self.model.signals()) {
            *o = s.order.value(&self.params);
        }
        // (ikΩ)^q = (ik)^q Ω^q: the trigonometry and k^q once per order, not per call
        let n1 = self.n + 1;
        for (s, &q) in self.orders.iter().enumerate() {
            for k in 0..n1 {
                self.unit[s * n1 + k] = spectral_factor(k, 1.0, q);
            }
        }
        self.sig_valid = false;
        self.grad_valid = false;
    }

    /// [`Model::check_coefficients`] at the current parameters and `omega` (the
    /// balance's frequency argument, `Ω / period`): every coefficient finite.
    pub fn check_coefficients(&self, omega: f64) -> Result<()> {
        self.model.check_coefficients(&self.params, omega * self.period)
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
    pub fn model(&self) -> &'m dyn DynModel {
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

    /// Signal samples from the coefficients, and the spectral factors for Ω (kept
    /// when called again at the same point, as `d_omega` after `jacobian` is).
    fn fill_signals(&mut self, a: &[f64], omega: f64) {
        if self.sig_valid && omega == self.cache_omega && a == &self.cache_a[..] {
            return;
        }
        self.cache_a.copy_from_slice(a);
        self.cache_omega = omega;
        self.sig_valid = true;
        self.grad_valid = false;
        for (s, sig) in self.model.signals().iter().enumerate() {
            crate::model::combine_blocks(&sig.terms, a, &mut self.comb);
            let q = self.orders[s];
            let wq = if q.fract() == 0.0 { omega.powi(q as i32) } else { omega.powf(q) };
            let n1 = self.n + 1;
            let lam = &mut self.lam[s * n1..(s + 1) * n1];
            for (l, &u) in lam.iter_mut().zip(&self.unit[s * n1..(s + 1) * n1]) {
                *l = u * wq;
            }
            apply_factor(&self.comb, &mut self.op, |k| lam[k]);
            self.fourier.synthesize(&self.op, &mut self.sig[s * self.m..(s + 1) * self.m]);
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

    /// The number of forcing periods a solution repeats after (1, or 2 for the
    /// balance of a period-doubled branch): its frequency argument is `Ω / period`.
    pub fn period(&self) -> usize {
        self.period as usize
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
                omega * self.period,
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

    /// The signal gradients `∂r_e/∂s` at every sample ([`Balance::gradients`]) without
    /// the Jacobian: what the stability analysis needs.
    pub fn signal_gradients(&mut self, a: &[f64], omega: f64) {
        self.fill_signals(a, omega);
        self.gradient_pass(omega, false);
    }

    /// Fill `self.grad` (signals filled): one sample for an affine signal, one pass
    /// over the samples per group of the others (each signal of a group seeded with
    /// 1: an equation reads at most one of them, so its derivative is that signal's).
    /// With `want_r`, the residual samples from the first pass into `self.res`;
    /// `false` if no pass gave them. Marks in `grad_nonzero` the gradients that are
    /// not identically zero.
    fn gradient_pass(&mut self, omega: f64, want_r: bool) -> bool {
        for (d, &p) in self.d_params.iter_mut().zip(&self.params) {
            *d = Dual64::from_re(p);
        }
        let (m, nsig, ndof) = (self.m, self.nsig, self.ndof);
        self.grad_nonzero.fill(false);
        // Affine signals: the gradient at one sample holds for all.
        for s0 in 0..nsig {
            if !self.affine[s0] {
                continue;
            }
            self.seeded.fill(false);
            self.seeded[s0] = true;
            self.seed_sample(0, omega);
            for e in 0..ndof {
                let g = self.d_out[e].eps;
                self.grad[(e * nsig + s0) * m..][..m].fill(g);
                self.grad_nonzero[e * nsig + s0] = g != 0.0;
            }
        }
        // The others, a group per pass; the first pass also gives r.
        let mut have_r = false;
        for g in 0..self.groups.len() {
            self.seeded.fill(false);
            for &s in &self.groups[g] {
                self.seeded[s] = true;
            }
            for j in 0..m {
                self.seed_sample(j, omega);
                let reader = &self.group_reader[g * ndof..(g + 1) * ndof];
                for (e, (out, r)) in self.d_out.iter().zip(reader).enumerate() {
                    if want_r && !have_r {
                        self.res[e * m + j] = out.re;
                    }
                    if let Some(s0) = *r {
                        self.grad[(e * nsig + s0) * m + j] = out.eps;
                        self.grad_nonzero[e * nsig + s0] |= out.eps != 0.0;
                    }
                }
            }
            have_r = want_r;
        }
        self.grad_valid = true;
        have_r
    }

    /// The bandwidths `(kl, ku)` of the Jacobian, its unknowns ordered DOF by DOF: a
    /// block `(e, d)` is non-zero only where equation `e` reads a signal of DOF `d`
    /// (probed once, at construction), so a chain's Jacobian is block tridiagonal
    /// and `kl = ku = 2(2N+1) − 1` however long the chain.
    pub fn jacobian_band(&self) -> (usize, usize) {
        let (mut below, mut above) = (0usize, 0usize);
        for (s, sig) in self.model.signals().iter().enumerate() {
            for e in (0..self.ndof).filter(|&e| self.reads[e * self.nsig + s]) {
                for &(d, c) in sig.terms.iter() {
                    if c != 0.0 {
                        below = below.max(e.saturating_sub(d));
                        above = above.max(d.saturating_sub(e));
                    }
                }
            }
        }
        let l = coeff_len(self.n);
        let last = self.len().saturating_sub(1);
        ((below * l + l - 1).min(last), (above * l + l - 1).min(last))
    }

    /// The residual `r` and its Jacobian `∂R/∂A` (written, not accumulated) into
    /// `jac`, `len × len`; a matrix of another size is filled with NaN (which every
    /// solver reports as a non-finite step) rather than left in part.
    pub fn jacobian(&mut self, a: &[f64], omega: f64, r: &mut [f64], mut jac: MatMut<'_, f64>) {
        if jac.nrows() != self.len() || jac.ncols() != self.len() {
            jac.fill(f64::NAN);
            return;
        }
        if jac.row_stride() == 1 {
            // contiguous columns: a full matrix stores every block
            self.jacobian_into(a, omega, r, &mut jac);
        } else {
            // a view whose columns are not contiguous: assemble apart, then copy
            let mut own = faer::Mat::<f64>::zeros(jac.nrows(), jac.ncols());
            self.jacobian_into(a, omega, r, &mut own.as_mut());
            jac.copy_from(&own);
        }
    }

    /// The residual `r` and its Jacobian `∂R/∂A` into `jac` (cleared first); `false`
    /// if `jac` does not store a block the Jacobian has (a band narrower than
    /// [`Balance::jacobian_band`], which a parameter changed since may widen): the
    /// Jacobian is then incomplete and needs a wider target.
    pub fn jacobian_into<C: Columns>(
        &mut self,
        a: &[f64],
        omega: f64,
        r: &mut [f64],
        jac: &mut C,
    ) -> bool {
        self.fill_signals(a, omega);
        let (m, nsig) = (self.m, self.nsig);
        if self.gradient_pass(omega, true) {
            self.project(r);
        } else {
            self.residual(a, omega, r);
        }
        jac.clear();
        let signals = self.model.signals();
        for e in 0..self.ndof {
            for (s, sig) in signals.iter().enumerate() {
                if !self.grad_nonzero[e * nsig + s] {
                    continue;
                }
                let g = &self.grad[(e * nsig + s) * m..][..m];
                let lam = &self.lam[s * (self.n + 1)..][..self.n + 1];
                let g0 = g[0];
                if self.affine[s] || g.iter().all(|&x| x == g0) {
                    // a linear term: multiplication by a constant is diagonal
                    if g0 != 0.0 {
                        for &(d, c) in sig.terms.iter() {
                            if !add_diagonal_block(jac, self.n, e, d, c * g0, lam) {
                                return false;
                            }
                        }
                    }
                    continue;
                }
                self.fourier.spectrum(g, &mut self.ghat);
                for &(d, c) in sig.terms.iter() {
                    if !add_block(jac, self.n, e, d, c, &self.ghat, &mut self.ext, lam) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// The model at sample `j` with the signals marked in `self.seeded` seeded (dual
    /// parts 1, the others 0), into `d_out`.
    fn seed_sample(&mut self, j: usize, omega: f64) {
        let m = self.m;
        for (s, d) in self.d_sig.iter_mut().enumerate() {
            *d = Dual64::new(self.sig[s * m + j], if self.seeded[s] { 1.0 } else { 0.0 });
        }
        self.model.residual(
            &self.d_params,
            Dual64::from_re(omega * self.period),
            self.phases[j],
            &self.d_sig,
            &mut self.d_out,
        );
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
                Dual64::new(omega * self.period, d_omega * self.period),
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
    ///
    /// Right after [`Balance::jacobian`] at the same point, for a model without
    /// explicit Ω ([`Model::explicit_omega`]), this reuses its gradients:
    /// `∂r/∂Ω = Σ_s (∂r/∂s)(q_s/Ω) s(θ)`, with no further model evaluations.
    pub fn d_omega(&mut self, a: &[f64], omega: f64, out: &mut [f64]) {
        self.fill_signals(a, omega);
        let m = self.m;
        if self.grad_valid && !self.explicit_omega {
            let nsig = self.nsig;
            self.res.fill(0.0);
            for e in 0..self.ndof {
                for s in 0..nsig {
                    let f = self.orders[s] / omega;
                    if f == 0.0 || !self.grad_nonzero[e * nsig + s] {
                        continue;
                    }
                    let g = &self.grad[(e * nsig + s) * m..][..m];
                    let sig = &self.sig[s * m..][..m];
                    for ((r, &g), &x) in self.res[e * m..][..m].iter_mut().zip(g).zip(sig) {
                        *r += g * f * x;
                    }
                }
            }
            self.project(out);
            return;
        }
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
        let m = self.m;
        self.seeded.fill(false);
        for (s, sig) in self.model.signals().iter().enumerate() {
            if sig.order != Order::Param(index) {
                continue;
            }
            self.seeded[s] = true;
            crate::model::combine_blocks(&sig.terms, a, &mut self.comb);
            let q = self.orders[s];
            apply_factor(&self.comb, &mut self.op, |k| order_rate(k, omega, q));
            self.fourier.synthesize(&self.op, &mut self.dsig[s * m..(s + 1) * m]);
        }
        self.directional(omega, 0.0, Some(index), out);
    }
}

/// Add `c · D^q` into the `(e, d)` block (the case of a constant `g`, folded into `c`):
/// `D^q` maps `(cos kθ, sin kθ)` by the 2×2 rotation-scaling of `λ_k = (ikΩ)^q`.
/// `false` if `jac` does not store the block.
fn add_diagonal_block<C: Columns>(
    jac: &mut C,
    n: usize,
    e: usize,
    d: usize,
    c: f64,
    lam: &[Complex64],
) -> bool {
    let l = coeff_len(n);
    let (row0, col0) = (e * l, d * l);
    let Some(col) = jac.segment(col0, row0, l) else { return false };
    col[0] += c * lam[0].re;
    for k in 1..=n {
        let (re, im) = (c * lam[k].re, c * lam[k].im);
        let Some(cos) = jac.segment(col0 + k, row0, l) else { return false };
        cos[k] += re;
        cos[n + k] -= im;
        let Some(sin) = jac.segment(col0 + n + k, row0, l) else { return false };
        sin[k] += im;
        sin[n + k] += re;
    }
    true
}

/// Add `c · P[g] · D^q` into the `(e, d)` block of the Jacobian: column `cos jθ` (or
/// `sin jθ`) is the coefficient vector of `g · D^q cos jθ` (or `sin`). With
/// `D^q cos jθ = Re(λ_j e^{ijθ})` the product has complex coefficients
/// `ŵ_k = ĝ_{k-j} û_j + ĝ_{k+j} û_{-j}`. `ghat` holds `ĝ_m` for `m = 0..=2N`;
/// `ext` (scratch, `4N + 1`) receives `ĝ_m` for `m = -2N..=2N` (`ĝ_{-m} = conj ĝ_m`,
/// `g` being real), so the inner loop reads two contiguous runs. `false` if `jac`
/// does not store the block.
#[allow(clippy::too_many_arguments)]
pub(crate) fn add_block<C: Columns>(
    jac: &mut C,
    n: usize,
    e: usize,
    d: usize,
    c: f64,
    ghat: &[Complex64],
    ext: &mut [Complex64],
    lam: &[Complex64],
) -> bool {
    let l = coeff_len(n);
    let (row0, col0) = (e * l, d * l);
    let mid = 2 * n;
    for m in 0..=mid {
        ext[mid + m] = ghat[m];
        ext[mid - m] = ghat[m].conj();
    }
    let (c2, zero) = (2.0 * c, Complex64::new(0.0, 0.0));
    let mut column = |col: usize, j: usize, up: Complex64, um: Complex64| {
        let Some(colv) = jac.segment(col, row0, l) else { return false };
        // k = 0: ĝ_{-j} û_j + ĝ_{j} û_{-j}
        let w0 = ext[mid - j] * up + if j == 0 { zero } else { ext[mid + j] * um };
        colv[0] += c * w0.re;
        let lo = &ext[mid + 1 - j..][..n];
        let hi = &ext[mid + 1 + j..][..n];
        for (k, (&gl, &gh)) in lo.iter().zip(hi).enumerate() {
            let w = if j == 0 { gl * up } else { gl * up + gh * um };
            colv[1 + k] += c2 * w.re;
            colv[1 + n + k] -= c2 * w.im;
        }
        true
    };
    if lam[0].re != 0.0 && !column(col0, 0, lam[0], zero) {
        return false;
    }
    for j in 1..=n {
        let up = lam[j] * 0.5;
        // sin jθ = (e^{ijθ} - e^{-ijθ}) / 2i
        let vp = lam[j] * Complex64::new(0.0, -0.5);
        if !(column(col0 + j, j, up, up.conj()) && column(col0 + n + j, j, vp, vp.conj())) {
            return false;
        }
    }
    true
}
