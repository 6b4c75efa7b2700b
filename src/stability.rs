//! Stability of periodic solutions: Hill's method, extended to fractional orders.
//!
//! # The method
//!
//! A harmonic balance solution `x*(t)` of `r_e(s_1, …, s_S, Ωt) = 0` (one equation per
//! DOF, polynomial in the signals `s_j = D^{q_j}(Σ_d c_{jd} x_d)`) is perturbed,
//! `x = x* + δx`, and the equations are linearised:
//!
//! ```text
//! Σ_j g_{e,j}(Ωt) · D^{q_j}(Σ_d c_{jd} δx_d) = 0,      g_{e,j} = ∂r_e/∂s_j at x*(t),
//! ```
//!
//! a linear system with `T = 2π/Ω`-periodic coefficients. Floquet theory (integer
//! orders) gives solutions `δx = e^{λt} p(t)` with `p` periodic; Hill's method writes
//! `p(t) = Σ_{|k|≤N} v_k e^{ikΩt}` and projects onto the same harmonics (Galerkin).
//! A derivative acts on `e^{(λ+ikΩ)t}` as the factor `(λ + ikΩ)^q`, so
//!
//! ```text
//! T(λ) v = 0,   T(λ)_{(e,l),(d,k)} = Σ_j c_{jd} G_{e,j,l-k} (λ + ikΩ)^{q_j},
//! ```
//!
//! `G_{e,j,m}` the Fourier coefficients of `g_{e,j}`. The projection is the one the
//! harmonic balance Jacobian uses (the same samples, the same weights): indeed
//! `T(0)` *is* that Jacobian. For integer orders `T(λ) = Σ_r λ^r M_r` is a matrix
//! polynomial (quadratic for mechanical models: mass, damping and stiffness blocks)
//! and its eigenvalues come from a companion linearisation. Its `ndof·(2N+1)·q_max`
//! eigenvalues approximate the Floquet exponents and their copies shifted by `ikΩ`;
//! the `q_max·ndof` with the smallest `|Im λ|` are the *central* exponents
//! (`|Im λ| ≤ Ω/2`), the ones the truncation resolves best. The solution is
//! asymptotically stable iff every exponent has `Re λ < 0`; we report *unstable* iff
//! some central exponent has `Re λ > tol·Ω`.
//!
//! We work in the real basis `[a0, a_k, b_k]` of the harmonic balance: a derivative
//! of order `q` maps the pair `(a_k, b_k)` of `e^{λt}(a_k cos kθ + b_k sin kθ)` by
//! `[[α, -β], [β, α]]` with `α = (f₊ + f₋)/2`, `β = i(f₊ - f₋)/2`,
//! `f± = (λ ± ikΩ)^q`, and the constant by `λ^q`. For real `λ` and integer `q` these
//! are real, which keeps the integer-order problem real.
//!
//! # Fractional orders
//!
//! For a fractional signal (steady-state Liouville–Weyl derivative, the sense in which
//! harmonic balance solves `D^p`), the same ansatz gives the factor
//! `(λ + ikΩ)^p` on the principal branch: `T(λ)` is no longer polynomial, and the
//! Floquet exponents are the roots of a nonlinear eigenvalue problem
//! (Haacker, Leine, Chaudhary, Diethelm, Schmidt, Hashemishahraki, "Hill-type
//! stability analysis of periodic solutions of fractional-order differential
//! equations", arXiv:2509.24639, 2025). We solve it in two stages:
//!
//! 1. *Frozen order*: replace `(λ + ikΩ)^p` by its value at `λ = 0`, `(ikΩ)^p`
//!    (zero for `k = 0`, `p > 0`) — exactly the fractional contribution to the harmonic
//!    balance Jacobian — and solve the resulting polynomial problem as above. Its
//!    central eigenvalues are the candidates.
//! 2. *Refinement*: each candidate (one of each conjugate pair) is refined by nonlinear
//!    inverse iteration (Ruhe 1973) on the true `T(λ)`:
//!    `T(λ_k) x = T'(λ_k) v_k`, `λ_{k+1} = λ_k - (uᴴ v_k)/(uᴴ x)`, `v_{k+1} = x/(uᴴ x)`,
//!    quadratically convergent for a simple eigenvalue, with `T'` from
//!    `d/dλ (λ + ikΩ)^p = p (λ + ikΩ)^{p-1}`.
//!
//! # Justification and limits (the book should say these)
//!
//! - The branch cuts of `(λ + ikΩ)^p` lie on `λ ∈ -ikΩ + (-∞, 0]`, all in the closed
//!   left half plane, so `T(λ)` is analytic where instability lives (`Re λ > 0`):
//!   an exponentially growing mode is a genuine root there, and refinement of a
//!   growing candidate never meets a cut.
//! - Only exponentially growing perturbations are detected. Fractional systems also
//!   have algebraically decaying modes (the `t^{-p}` tails of the memory), invisible
//!   to any `e^{λt}` ansatz. "Stable" therefore means "no growing mode found", as in
//!   Haacker et al.
//! - Exponents with `Re λ < 0` near a branch cut (overdamped, relaxation-type modes)
//!   may not exist on the principal sheet; their refinement may fail. That does not
//!   change the verdict, but the reported values are then the frozen-order ones
//!   ([`Floquet::refined`] says so).
//! - The frozen-order candidates could in principle miss a growing root of the full
//!   problem that has no counterpart in the polynomial one (strong fractional terms);
//!   the refinement only corrects candidates it is given.
//! - Truncation: the Hill matrix is truncated at `N` harmonics; the central exponents
//!   converge quickly with `N`, the outer ones are not used. Near a stability boundary
//!   the verdict flips at `Re λ = tol·Ω` (default `1e-7·Ω`), not exactly at 0.
//!
//! Which exponent crosses classifies a loss of stability: a real one (`Im λ = 0`,
//! multiplier `+1`: fold or branch point), one at `Im λ = ±Ω/2` (multiplier `-1`:
//! period doubling) or a complex pair elsewhere (Neimark–Sacker: a torus).

use crate::balance::Balance;
use crate::error::{Error, Result};
use crate::model::{Model, Order};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::prelude::Solve;
use faer::{Mat, Par};
use num_complex::Complex64;

/// Settings of the stability analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilityOptions {
    /// A solution is unstable iff some central exponent has `Re λ > tol · Ω`.
    pub tol: f64,
    /// Refine fractional-order candidates on the nonlinear eigenproblem.
    pub refine: bool,
    /// Iteration limit of the refinement (per exponent).
    pub max_refine_iter: usize,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions { tol: 1e-7, refine: true, max_refine_iter: 30 }
    }
}

/// How a solution loses (or gains) stability: the exponent that crosses `Re λ = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Crossing {
    /// A real exponent (Floquet multiplier +1): fold or branch point.
    Real,
    /// An exponent at `Im λ = ±Ω/2` (multiplier -1): period doubling.
    PeriodDoubling,
    /// A complex pair elsewhere (multipliers on the unit circle): Neimark–Sacker.
    Torus,
}

/// The central Floquet exponents of one periodic solution and the verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Floquet {
    /// Central exponents (`|Im λ| ≤ Ω/2`), sorted by decreasing real part.
    pub exponents: Vec<Complex64>,
    /// Largest real part (`-inf` if there are none).
    pub max_real: f64,
    /// `true` iff no exponent has `Re λ > tol · Ω`.
    pub stable: bool,
    /// `false` if some fractional candidate did not converge in the refinement (its
    /// frozen-order value is reported). Always `true` for integer-order models.
    pub refined: bool,
}

impl Floquet {
    /// The kind of the exponent with the largest real part, relative to Ω.
    pub fn leading_crossing(&self, omega: f64) -> Option<Crossing> {
        let l = self.exponents.first()?;
        let im = l.im.abs();
        Some(if im < 1e-6 * omega {
            Crossing::Real
        } else if (im - omega / 2.0).abs() < 1e-6 * omega {
            Crossing::PeriodDoubling
        } else {
            Crossing::Torus
        })
    }
}

/// Reusable workspace for Hill's method on one model and harmonic count.
///
/// ```
/// use ihbm::balance::Balance;
/// use ihbm::corrector::{solve, SolveOptions};
/// use ihbm::models::Duffing;
/// use ihbm::stability::{Hill, StabilityOptions};
///
/// // Far below resonance a damped Duffing oscillator is stable.
/// let model = Duffing::default();
/// let opts = SolveOptions { harmonics: 3, ..Default::default() };
/// let sol = solve(&model, 0.3, &opts, None).unwrap();
/// let mut bal = Balance::new(&model, 3).unwrap();
/// let mut hill = Hill::new(&model, 3).unwrap();
/// let f = hill.analyse(&mut bal, &sol.coeffs, 0.3, &StabilityOptions::default()).unwrap();
/// assert!(f.stable);
/// assert_eq!(f.exponents.len(), 2);
/// // Linear limit: the exponents of m x'' + c x' + k_eff x are -c/2m ± i(...)
/// assert!((f.exponents[0].re + 0.05).abs() < 1e-3);
/// ```
pub struct Hill {
    ndof: usize,
    harmonics: usize,
    len: usize,
    m: usize,
    samples: usize,
    /// Highest integer order, the degree of the matrix polynomial.
    degree: usize,
    /// `phi[s * len + l]`: basis function l at sample s.
    phi: Vec<f64>,
    /// Galerkin weights per basis function (1/M for the constant, 2/M otherwise).
    weight: Vec<f64>,
    /// Projection matrices `P[g_{e,j}]`, row-major len×len, index (e * nsig + j).
    proj: Vec<f64>,
    r: Vec<f64>,
    jac: Mat<f64>,
    /// `M_0 .. M_degree`.
    coef: Vec<Mat<f64>>,
    companion: Mat<f64>,
    lead: Mat<f64>,
    s_re: Vec<f64>,
    s_im: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
    signals: Vec<(Vec<(usize, f64)>, Order)>,
    fractional: bool,
    cands: Vec<Complex64>,
}

impl Hill {
    /// A workspace for `model` truncated at `harmonics` harmonics.
    pub fn new<M: Model>(model: &M, harmonics: usize) -> Result<Hill> {
        if harmonics == 0 {
            return Err(Error::InvalidValue {
                what: "number of harmonics".into(),
                value: "0".into(),
                expected: "at least 1".into(),
            });
        }
        let ndof = model.dofs().len();
        let len = 2 * harmonics + 1;
        let m = ndof * len;
        let samples =
            crate::fourier::sample_count(model.degree(), harmonics, model.max_forcing_harmonic());
        let mut degree = 0usize;
        let mut fractional = false;
        let signals: Vec<_> = model
            .signals()
            .iter()
            .map(|s| {
                match s.order {
                    Order::Int(q) => degree = degree.max(q as usize),
                    Order::Param(_) => fractional = true,
                }
                (s.terms.to_vec(), s.order)
            })
            .collect();
        let degree = degree.max(1);
        let mut phi = vec![0.0; samples * len];
        for s in 0..samples {
            let th = 2.0 * std::f64::consts::PI * s as f64 / samples as f64;
            phi[s * len] = 1.0;
            for k in 1..=harmonics {
                let (sn, cs) = (k as f64 * th).sin_cos();
                phi[s * len + k] = cs;
                phi[s * len + harmonics + k] = sn;
            }
        }
        let mut weight = vec![2.0 / samples as f64; len];
        weight[0] = 1.0 / samples as f64;
        let neq = ndof;
        let nsig = signals.len();
        let big = degree * m;
        let scratch =
            faer::linalg::evd::evd_scratch::<f64>(
                big,
                faer::linalg::evd::ComputeEigenvectors::No,
                faer::linalg::evd::ComputeEigenvectors::No,
                Par::Seq,
                Default::default(),
            )
            .or(faer::linalg::lu::partial_pivoting::factor::lu_in_place_scratch::<usize, f64>(
                m,
                m,
                Par::Seq,
                Default::default(),
            ))
            .or(faer::linalg::lu::partial_pivoting::solve::solve_in_place_scratch::<
                usize,
                f64,
            >(m, big, Par::Seq));
        Ok(Hill {
            ndof,
            harmonics,
            len,
            m,
            samples,
            degree,
            phi,
            weight,
            proj: vec![0.0; neq * nsig * len * len],
            r: vec![0.0; m],
            jac: Mat::zeros(m, m),
            coef: (0..=degree).map(|_| Mat::zeros(m, m)).collect(),
            companion: Mat::zeros(big, big),
            lead: Mat::zeros(m, m),
            s_re: vec![0.0; big],
            s_im: vec![0.0; big],
            perm: vec![0; m],
            perm_inv: vec![0; m],
            mem: MemBuffer::new(scratch),
            signals,
            fractional,
            cands: Vec::with_capacity(big),
        })
    }

    /// Number of central exponents (`degree · ndof`).
    pub fn central_count(&self) -> usize {
        self.degree * self.ndof
    }

    /// Floquet exponents and stability of the solution `coeffs` at frequency `omega`
    /// (parameters as currently set in `bal`).
    pub fn analyse<M: Model>(
        &mut self,
        bal: &mut Balance<'_, M>,
        coeffs: &[f64],
        omega: f64,
        opts: &StabilityOptions,
    ) -> Result<Floquet> {
        self.project(bal, coeffs, omega)?;
        self.assemble_polynomial(bal.params(), omega);
        self.candidates(omega)?;
        let mut refined = true;
        let mut exps: Vec<Complex64> = Vec::with_capacity(self.cands.len());
        if self.fractional && opts.refine {
            let params = bal.params().to_vec();
            let cands = std::mem::take(&mut self.cands);
            for &c in &cands {
                if c.im < -1e-12 * omega {
                    continue; // its conjugate is refined
                }
                match self.refine(&params, omega, c, opts.max_refine_iter) {
                    Some(l) => {
                        let l = fold_into_strip(l, omega);
                        exps.push(l);
                        if l.im.abs() > 1e-12 * omega {
                            exps.push(l.conj());
                        }
                    }
                    None => {
                        refined = false;
                        exps.push(c);
                        if c.im.abs() > 1e-12 * omega {
                            exps.push(c.conj());
                        }
                    }
                }
            }
            self.cands = cands;
        } else {
            exps.extend_from_slice(&self.cands);
        }
        exps.sort_by(|a, b| b.re.total_cmp(&a.re));
        let max_real = exps.first().map_or(f64::NEG_INFINITY, |l| l.re);
        Ok(Floquet { stable: max_real <= opts.tol * omega, max_real, exponents: exps, refined })
    }

    /// Galerkin projections `P[g_{e,j}]` of the signal gradients at the solution.
    fn project<M: Model>(
        &mut self,
        bal: &mut Balance<'_, M>,
        coeffs: &[f64],
        omega: f64,
    ) -> Result<()> {
        let (len, ns) = (self.len, self.samples);
        let nsig = self.signals.len();
        if bal.samples() != ns || bal.len() != self.m {
            return Err(Error::Other(format!(
                "Hill's method: workspace for {} samples and {} unknowns used with a balance of {} and {}",
                ns,
                self.m,
                bal.samples(),
                bal.len()
            )));
        }
        bal.jacobian(coeffs, omega, &mut self.r, self.jac.as_mut());
        let grads = bal.gradients();
        for e in 0..self.ndof {
            for j in 0..nsig {
                let p = &mut self.proj[(e * nsig + j) * len * len..(e * nsig + j + 1) * len * len];
                p.fill(0.0);
                let g = &grads[(e * nsig + j) * ns..][..ns];
                if g.iter().all(|&x| x == g[0]) {
                    // A linear term: multiplication by a constant projects to g0·I.
                    for l in 0..len {
                        p[l * len + l] = g[0];
                    }
                    continue;
                }
                for s in 0..ns {
                    let g = g[s];
                    if g == 0.0 {
                        continue;
                    }
                    let row = &self.phi[s * len..(s + 1) * len];
                    for l in 0..len {
                        let gl = g * row[l] * self.weight[l];
                        let pl = &mut p[l * len..(l + 1) * len];
                        for (pk, &fk) in pl.iter_mut().zip(row) {
                            *pk += gl * fk;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// `M_r` of `T(λ) = Σ_r λ^r M_r`, fractional signals frozen at `λ = 0`.
    fn assemble_polynomial(&mut self, params: &[f64], omega: f64) {
        let (len, nh, nsig) = (self.len, self.harmonics, self.signals.len());
        for c in &mut self.coef {
            c.fill(0.0);
        }
        let mut alpha = vec![0.0; nh + 1];
        let mut beta = vec![0.0; nh + 1];
        for j in 0..nsig {
            let (terms, order) = (&self.signals[j].0, self.signals[j].1);
            let q = order.value(params);
            let powers: Vec<(usize, f64)> = match order {
                Order::Int(q) => (0..=q as usize).map(|r| (r, q as f64)).collect(),
                Order::Param(_) => vec![(0, q)],
            };
            for (r, qq) in powers {
                // Coefficient of λ^r in (λ ± ikΩ)^q: binom(q, r) (±ikΩ)^(q - r); for a
                // frozen fractional order, r = 0 and the factor (±ikΩ)^p.
                let (binom, s) = match order {
                    Order::Int(qi) => (binomial(qi as usize, r), qi as f64 - r as f64),
                    Order::Param(_) => (1.0, qq),
                };
                alpha[0] = if s == 0.0 { binom } else { 0.0 };
                beta[0] = 0.0;
                for k in 1..=nh {
                    let z = crate::fourier::spectral_factor(k, omega, s);
                    alpha[k] = binom * z.re;
                    beta[k] = -binom * z.im;
                }
                for e in 0..self.ndof {
                    let p = &self.proj[(e * nsig + j) * len * len..(e * nsig + j + 1) * len * len];
                    for &(d, c) in terms {
                        add_product(
                            &mut self.coef[r],
                            e * len,
                            d * len,
                            c,
                            p,
                            len,
                            nh,
                            &alpha,
                            &beta,
                        );
                    }
                }
            }
        }
    }

    /// Central eigenvalues of the matrix polynomial into `self.cands`.
    fn candidates(&mut self, omega: f64) -> Result<()> {
        use faer::linalg::lu::partial_pivoting::{factor, solve};
        let (m, d) = (self.m, self.degree);
        let big = d * m;
        let count = self.central_count();
        self.lead.copy_from(&self.coef[d]);
        let scale = self.lead.norm_max();
        let (_, perm) = factor::lu_in_place(
            self.lead.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        let min_pivot = (0..m).map(|i| self.lead[(i, i)].abs()).fold(f64::INFINITY, f64::min);
        self.cands.clear();
        if min_pivot.is_nan() || min_pivot <= 1e-12 * scale {
            return self.candidates_generalized(omega);
        }
        // Companion: [[0, I, ...], ..., [-L⁻¹M_0, ..., -L⁻¹M_{d-1}]].
        self.companion.fill(0.0);
        for b in 0..d - 1 {
            for i in 0..m {
                self.companion[(b * m + i, (b + 1) * m + i)] = 1.0;
            }
        }
        for r in 0..d {
            for i in 0..m {
                for jj in 0..m {
                    self.companion[((d - 1) * m + i, r * m + jj)] = -self.coef[r][(i, jj)];
                }
            }
        }
        {
            let rows = self.companion.as_mut().subrows_mut((d - 1) * m, m);
            solve::solve_in_place(
                self.lead.as_ref(),
                self.lead.as_ref(),
                perm,
                rows,
                Par::Seq,
                MemStack::new(&mut self.mem),
            );
        }
        faer::linalg::evd::evd_real(
            self.companion.as_ref(),
            faer::diag::DiagMut::from_slice_mut(&mut self.s_re),
            faer::diag::DiagMut::from_slice_mut(&mut self.s_im),
            None,
            None,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        )
        .map_err(|e| {
            Error::Other(format!("Hill's method: eigenvalues failed at Ω = {omega}: {e:?}"))
        })?;
        for i in 0..big {
            self.cands.push(Complex64::new(self.s_re[i], self.s_im[i]));
        }
        select_central(&mut self.cands, count, omega);
        Ok(())
    }

    /// Fallback for a singular leading matrix: the companion pencil, QZ.
    fn candidates_generalized(&mut self, omega: f64) -> Result<()> {
        let (m, d) = (self.m, self.degree);
        let big = d * m;
        let mut a = Mat::<f64>::zeros(big, big);
        let mut b = Mat::<f64>::zeros(big, big);
        for blk in 0..d - 1 {
            for i in 0..m {
                a[(blk * m + i, (blk + 1) * m + i)] = 1.0;
                b[(blk * m + i, blk * m + i)] = 1.0;
            }
        }
        for r in 0..d {
            for i in 0..m {
                for jj in 0..m {
                    a[((d - 1) * m + i, r * m + jj)] = -self.coef[r][(i, jj)];
                }
            }
        }
        for i in 0..m {
            for jj in 0..m {
                b[((d - 1) * m + i, (d - 1) * m + jj)] = self.coef[d][(i, jj)];
            }
        }
        let ge = a.generalized_eigen(&b).map_err(|e| {
            Error::Other(format!(
                "Hill's method: generalized eigenvalues failed at Ω = {omega}: {e:?}"
            ))
        })?;
        let (sa, sb) = (ge.S_a(), ge.S_b());
        for i in 0..big {
            let (x, y) = (sa[i], sb[i]);
            if y.norm() > 1e-12 * x.norm().max(1e-300) {
                self.cands.push(x / y);
            }
        }
        let count = (self.cands.len() / self.len).max(1).min(self.cands.len());
        select_central(&mut self.cands, count, omega);
        Ok(())
    }

    /// `T(λ)` and `T'(λ)` with every order exact (principal branch).
    fn assemble_full(
        &self,
        params: &[f64],
        omega: f64,
        lambda: Complex64,
        t: &mut Mat<Complex64>,
        dt: &mut Mat<Complex64>,
    ) {
        let (len, nh, nsig) = (self.len, self.harmonics, self.signals.len());
        t.fill(Complex64::new(0.0, 0.0));
        dt.fill(Complex64::new(0.0, 0.0));
        let mut alpha = vec![Complex64::new(0.0, 0.0); nh + 1];
        let mut beta = alpha.clone();
        let mut dalpha = alpha.clone();
        let mut dbeta = alpha.clone();
        let i1 = Complex64::new(0.0, 1.0);
        for j in 0..nsig {
            let (terms, order) = (&self.signals[j].0, self.signals[j].1);
            let q = order.value(params);
            let f = |z: Complex64| -> (Complex64, Complex64) {
                if q == 0.0 {
                    (Complex64::new(1.0, 0.0), Complex64::new(0.0, 0.0))
                } else if z == Complex64::new(0.0, 0.0) {
                    let d = if q == 1.0 { 1.0 } else { 0.0 };
                    (Complex64::new(0.0, 0.0), Complex64::new(d, 0.0))
                } else if let Order::Int(qi) = order {
                    (z.powi(qi as i32), q * z.powi(qi as i32 - 1))
                } else {
                    let v = z.powf(q);
                    (v, q * v / z)
                }
            };
            for k in 0..=nh {
                let w = Complex64::new(0.0, k as f64 * omega);
                let (fp, dfp) = f(lambda + w);
                let (fm, dfm) = f(lambda - w);
                alpha[k] = (fp + fm) * 0.5;
                beta[k] = i1 * (fp - fm) * 0.5;
                dalpha[k] = (dfp + dfm) * 0.5;
                dbeta[k] = i1 * (dfp - dfm) * 0.5;
            }
            // k = 0: f(λ) itself (α = f₊ = f₋).
            for e in 0..self.ndof {
                let p = &self.proj[(e * nsig + j) * len * len..(e * nsig + j + 1) * len * len];
                for &(d, c) in terms {
                    add_product(t, e * len, d * len, c, p, len, nh, &alpha, &beta);
                    add_product(dt, e * len, d * len, c, p, len, nh, &dalpha, &dbeta);
                }
            }
        }
    }

    /// Nonlinear inverse iteration from the candidate `l0`; `None` if it fails.
    fn refine(
        &self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        max_iter: usize,
    ) -> Option<Complex64> {
        let m = self.m;
        let zero = Complex64::new(0.0, 0.0);
        let mut t = Mat::<Complex64>::zeros(m, m);
        let mut dt = Mat::<Complex64>::zeros(m, m);
        let mut lambda = l0;
        // Start vector: one step of inverse iteration at the candidate.
        self.assemble_full(params, omega, lambda, &mut t, &mut dt);
        let lu = t.partial_piv_lu();
        let b = Mat::<Complex64>::from_fn(m, 1, |i, _| {
            Complex64::new(1.0 + (i as f64 * 0.37).sin(), 0.0)
        });
        let mut v = lu.solve(&b);
        let u = v.clone();
        let norm = dot(&u, &v);
        if norm.norm() == 0.0 || !norm.re.is_finite() || !norm.im.is_finite() {
            return None;
        }
        for i in 0..m {
            v[(i, 0)] /= norm;
        }
        let scale = omega.max(l0.norm());
        for _ in 0..max_iter {
            self.assemble_full(params, omega, lambda, &mut t, &mut dt);
            let rhs = &dt * &v;
            let x = t.partial_piv_lu().solve(&rhs);
            let ux = dot(&u, &x);
            if ux.norm() == 0.0 || !ux.re.is_finite() || !ux.im.is_finite() {
                return None;
            }
            let uv = dot(&u, &v);
            let step = uv / ux;
            lambda -= step;
            for i in 0..m {
                v[(i, 0)] = x[(i, 0)] / ux;
            }
            if !lambda.re.is_finite() || !lambda.im.is_finite() {
                return None;
            }
            if step.norm() <= 1e-12 * scale {
                return if v.col(0).iter().all(|z| z.re.is_finite()) && lambda != zero {
                    Some(lambda)
                } else {
                    None
                };
            }
        }
        None
    }
}

fn dot(u: &Mat<Complex64>, v: &Mat<Complex64>) -> Complex64 {
    (0..u.nrows()).map(|i| u[(i, 0)].conj() * v[(i, 0)]).sum()
}

/// Exponents are defined modulo `iΩ`; bring one into `(-Ω/2, Ω/2]`.
fn fold_into_strip(l: Complex64, omega: f64) -> Complex64 {
    let shift = (l.im / omega).round();
    Complex64::new(l.re, l.im - shift * omega)
}

/// Keep `count` values with the smallest |Im|, one per exponent: values equal modulo
/// `iΩ` are the same Floquet exponent (at `|Im λ| = Ω/2`, period doubling, `λ` and
/// `conj λ = λ - iΩ` both appear), and among near-equal |Im| the larger real part
/// comes first so that a growing exponent is never the one left out.
fn select_central(c: &mut Vec<Complex64>, count: usize, omega: f64) {
    let tie = 1e-6 * omega;
    c.sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()));
    let mut start = 0;
    while start < c.len() {
        let base = c[start].im.abs();
        let end = start + c[start..].iter().take_while(|z| z.im.abs() - base <= tie).count();
        c[start..end].sort_by(|a, b| b.re.total_cmp(&a.re));
        start = end;
    }
    let mut kept: Vec<Complex64> = Vec::with_capacity(count);
    for &z in c.iter() {
        if kept.len() == count {
            break;
        }
        let same = kept.iter().any(|k| {
            let d = (z.im - k.im).rem_euclid(omega);
            (z.re - k.re).abs() <= tie && (d <= tie || omega - d <= tie)
        });
        if !same {
            kept.push(z);
        }
    }
    *c = kept;
}

fn binomial(n: usize, r: usize) -> f64 {
    (0..r).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// `dst[row0.., col0..] += c · P · D`, where `D` is the real-basis operator with
/// constant factor `alpha[0]` and 2×2 blocks `[[α_k, -β_k], [β_k, α_k]]` on
/// `(a_k, b_k)`; `P` is row-major `len × len`.
#[allow(clippy::too_many_arguments)]
fn add_product<T>(
    dst: &mut Mat<T>,
    row0: usize,
    col0: usize,
    c: f64,
    p: &[f64],
    len: usize,
    nh: usize,
    alpha: &[T],
    beta: &[T],
) where
    T: Copy
        + std::ops::AddAssign
        + std::ops::Add<Output = T>
        + std::ops::Mul<f64, Output = T>
        + std::ops::Neg<Output = T>,
{
    for l in 0..len {
        let pl = &p[l * len..(l + 1) * len];
        let pc = pl[0] * c;
        if pc != 0.0 {
            dst[(row0 + l, col0)] += alpha[0] * pc;
        }
        for k in 1..=nh {
            let (pa, pb) = (pl[k] * c, pl[nh + k] * c);
            if pa == 0.0 && pb == 0.0 {
                continue;
            }
            // (P D)[:, a_k] = P[:, a_k] α + P[:, b_k] β; (P D)[:, b_k] = -P[:, a_k] β + P[:, b_k] α
            dst[(row0 + l, col0 + k)] += alpha[k] * pa + beta[k] * pb;
            dst[(row0 + l, col0 + nh + k)] += -(beta[k] * pa) + alpha[k] * pb;
        }
    }
}
