//! The test function of a Neimark–Sacker (torus) curve: Hill's operator `T(iω)`
//! bordered, complex.
//!
//! A periodic solution has a pair of Floquet exponents `±iω` (multipliers
//! `e^{±2πiω/Ω}` on the unit circle) exactly where `T(iω)` is singular. Bordered with
//! vectors `b`, `c` close to its left and right null vectors,
//!
//! ```text
//! [ T(iω)  b ] [v]   [0]
//! [ cᴴ     0 ] [g] = [1],
//! ```
//!
//! `g` (complex: two real equations) vanishes exactly there, and the torus frequency
//! `ω` is one more unknown of the extended system. Its derivatives are
//! `∂g/∂z = -wᴴ (∂T/∂z) v` with `w` from the adjoint bordered system: in the
//! coefficients, Ω and the parameter from hyper-dual numbers
//! ([`Balance::shifted_bilinear_gradient`]), in ω from `T'(iω)v`
//! ([`Hill`]'s exact fractional factors).

use crate::balance::{Balance, BilinearWork};
use crate::error::{Matrix, Quantity};
use crate::linalg::{complex_lu_factor, complex_lu_solve, complex_lu_solve_adjoint};
use crate::results::Stall;
use crate::stability::Hill;
use num_complex::Complex64;

/// Hill's operator and the buffers of the bordered complex test function.
pub(crate) struct TorusTest {
    hill: Hill,
    work: BilinearWork,
    n: usize,
    /// Borders (unit vectors, renewed at accepted points).
    b: Vec<Complex64>,
    c: Vec<Complex64>,
    /// The bordered matrix, row-major `(n+1)²`, then its LU.
    k: Vec<Complex64>,
    piv: Vec<usize>,
    /// Right and left null vectors of the last evaluation.
    v: Vec<Complex64>,
    w: Vec<Complex64>,
    x: Vec<Complex64>,
    /// `∂ψ/∂a` of `ψ = wᴴ T v`.
    pub d_a: Vec<Complex64>,
}

/// The gradient of `ψ = wᴴ T(iω) v` in Ω, the parameter and ω (`d_a` in the test).
pub(crate) struct PsiGradient {
    pub omega: Complex64,
    pub param: Complex64,
    pub torus: Complex64,
}

impl TorusTest {
    pub fn new(bal: &Balance<'_>) -> crate::error::Result<Self> {
        let n = bal.len();
        let e = {
            let mut e = vec![Complex64::new(0.0, 0.0); n];
            e[n / 2] = Complex64::new(1.0, 0.0);
            e
        };
        Ok(TorusTest {
            hill: Hill::new(bal.model(), bal.harmonics())?,
            work: BilinearWork::new(bal),
            n,
            b: e.clone(),
            c: e,
            k: vec![Complex64::new(0.0, 0.0); (n + 1) * (n + 1)],
            piv: vec![0; n + 1],
            v: vec![Complex64::new(0.0, 0.0); n],
            w: vec![Complex64::new(0.0, 0.0); n],
            x: vec![Complex64::new(0.0, 0.0); n + 1],
            d_a: vec![Complex64::new(0.0, 0.0); n],
        })
    }

    /// `cs · T(iω)` at the solution `a` (parameters as set in `bal`) into the top-left
    /// block of `self.k`.
    fn fill(
        &mut self,
        bal: &mut Balance<'_>,
        a: &[f64],
        omega: f64,
        torus: f64,
        cs: f64,
    ) -> Result<(), Stall> {
        let n = self.n;
        self.hill
            .prepare_operator(bal, a, omega)
            .map_err(|e| Stall::HillOperator { omega, cause: Box::new(e.into()) })?;
        let t = self.hill.operator(bal.params(), omega, Complex64::new(0.0, torus));
        for i in 0..n {
            for j in 0..n {
                self.k[i * (n + 1) + j] = cs * t[i * n + j];
            }
        }
        Ok(())
    }

    /// `g` at `(a, Ω, ω)`, `T` scaled by `cs`; the null vectors `v`, `w` kept for
    /// [`TorusTest::gradient`].
    pub fn evaluate(
        &mut self,
        bal: &mut Balance<'_>,
        a: &[f64],
        omega: f64,
        torus: f64,
        cs: f64,
    ) -> Result<Complex64, Stall> {
        let n = self.n;
        self.fill(bal, a, omega, torus, cs)?;
        for i in 0..n {
            self.k[i * (n + 1) + n] = self.b[i];
            self.k[n * (n + 1) + i] = self.c[i].conj();
        }
        self.k[n * (n + 1) + n] = Complex64::new(0.0, 0.0);
        if complex_lu_factor(&mut self.k, n + 1, &mut self.piv, 1e-14) > 0 {
            return Err(Stall::Singular { matrix: Matrix::TorusTestFunction, omega });
        }
        let one = |x: &mut Vec<Complex64>| {
            x.fill(Complex64::new(0.0, 0.0));
            x[n] = Complex64::new(1.0, 0.0);
        };
        one(&mut self.x);
        complex_lu_solve(&self.k, n + 1, &self.piv, &mut self.x);
        let g = self.x[n];
        self.v.copy_from_slice(&self.x[..n]);
        one(&mut self.x);
        complex_lu_solve_adjoint(&self.k, n + 1, &self.piv, &mut self.x);
        self.w.copy_from_slice(&self.x[..n]);
        if !(g.re.is_finite() && g.im.is_finite()) {
            return Err(Stall::NonFinite { quantity: Quantity::TorusTestFunction, omega });
        }
        Ok(g)
    }

    /// The gradient of `ψ = wᴴ T(iω) v` (unscaled `T`) with `v`, `w` of the last
    /// [`TorusTest::evaluate`]: `∂ψ/∂a` into `self.d_a`.
    pub fn gradient(
        &mut self,
        bal: &mut Balance<'_>,
        a: &[f64],
        omega: f64,
        torus: f64,
        param: usize,
    ) -> PsiGradient {
        let lambda = Complex64::new(0.0, torus);
        let (d_omega, d_param) = bal.shifted_bilinear_gradient(
            a,
            omega,
            lambda,
            &self.w,
            &self.v,
            Some(param),
            &mut self.work,
            &mut self.d_a,
        );
        // ∂T(iω)/∂ω = i T'(iω); `prepare_operator` ran at this point in `evaluate`
        let dtv = self.hill.derivative_applied(bal.params(), omega, lambda, &self.v);
        let s: Complex64 = self.w.iter().zip(dtv).map(|(w, x)| w.conj() * x).sum();
        PsiGradient { omega: d_omega, param: d_param, torus: Complex64::new(0.0, 1.0) * s }
    }

    /// Borders for a start point: the null vectors of `cs · T(iω)` by two steps of
    /// inverse iteration.
    pub fn init_borders(
        &mut self,
        bal: &mut Balance<'_>,
        a: &[f64],
        omega: f64,
        torus: f64,
        cs: f64,
    ) -> Result<(), Stall> {
        let n = self.n;
        self.fill(bal, a, omega, torus, cs)?;
        let mut t: Vec<Complex64> = Vec::with_capacity(n * n);
        for i in 0..n {
            t.extend_from_slice(&self.k[i * (n + 1)..i * (n + 1) + n]);
        }
        let mut piv = vec![0; n];
        // a nearly singular T: tiny pivots are expected, only zero ones are refused
        if complex_lu_factor(&mut t, n, &mut piv, 0.0) > 0 {
            return Err(Stall::Singular { matrix: Matrix::HillOperator, omega });
        }
        let mut v = vec![Complex64::new(1.0, 0.0); n];
        let mut w = v.clone();
        for _ in 0..2 {
            complex_lu_solve(&t, n, &piv, &mut v);
            complex_lu_solve_adjoint(&t, n, &piv, &mut w);
            for x in [&mut v, &mut w] {
                let norm = x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
                if !(norm.is_finite() && norm > 0.0) {
                    return Err(Stall::NoHillNullVector { omega });
                }
                x.iter_mut().for_each(|z| *z /= norm);
            }
        }
        self.c = v;
        self.b = w;
        Ok(())
    }

    /// Renew the borders from the null vectors of the last evaluation.
    pub fn renew_borders(&mut self) {
        let norm = |x: &[Complex64]| x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
        let (nv, nw) = (norm(&self.v), norm(&self.w));
        if nv > 0.0 && nw > 0.0 && nv.is_finite() && nw.is_finite() {
            for i in 0..self.n {
                self.c[i] = self.v[i] / nv;
                self.b[i] = self.w[i] / nw;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use crate::models::QuarterCar;

    /// `wᴴ T(λ) v` from Hill's assembled operator (binomial matrix polynomial and
    /// fractional factors: a different code path from the hyper-dual passes).
    fn psi(
        hill: &mut Hill,
        bal: &mut Balance<'_>,
        a: &[f64],
        omega: f64,
        lambda: Complex64,
        w: &[Complex64],
        v: &[Complex64],
    ) -> Complex64 {
        let n = a.len();
        hill.prepare_operator(bal, a, omega).unwrap();
        let t = hill.operator(bal.params(), omega, lambda);
        (0..n).map(|i| w[i].conj() * (0..n).map(|k| t[i * n + k] * v[k]).sum::<Complex64>()).sum()
    }

    /// The exact gradient of `wᴴ T(λ) v` against central differences of Hill's
    /// operator, in every coefficient, in Ω, in `k3` (a coefficient) and in `p` (a
    /// fractional order), at a complex λ; and its ω-derivative against `T'`.
    #[test]
    fn the_shifted_bilinear_gradient_matches_central_differences_of_hills_operator() {
        let model = QuarterCar::default();
        let mut bal = Balance::new(&model, 3).unwrap();
        let mut hill = Hill::new(&model, 3).unwrap();
        let n = bal.len();
        let wave =
            |s: f64| -> Vec<f64> { (0..n).map(|i| 1e-2 * ((i as f64 + 1.0) * s).sin()).collect() };
        let cwave = |s: f64| -> Vec<Complex64> {
            (0..n)
                .map(|i| Complex64::new(((i as f64 + 1.0) * s).sin(), ((i as f64 + 2.0) * s).cos()))
                .collect()
        };
        let (a, v, w) = (wave(0.7), cwave(1.3), cwave(2.9));
        let omega = 12.0;
        let lambda = Complex64::new(-0.4, 3.1);
        let mut work = BilinearWork::new(&bal);
        let mut d_a = vec![Complex64::new(0.0, 0.0); n];
        for name in ["k3", "p"] {
            let param = model.param_index(name).unwrap();
            let (d_o, d_p) = bal.shifted_bilinear_gradient(
                &a,
                omega,
                lambda,
                &w,
                &v,
                Some(param),
                &mut work,
                &mut d_a,
            );
            let scale = d_a.iter().fold(0.0f64, |m, x| m.max(x.norm()));
            for k in 0..n {
                let h = 1e-5;
                let (mut ap, mut am) = (a.clone(), a.clone());
                ap[k] += h;
                am[k] -= h;
                let fd = (psi(&mut hill, &mut bal, &ap, omega, lambda, &w, &v)
                    - psi(&mut hill, &mut bal, &am, omega, lambda, &w, &v))
                    / (2.0 * h);
                assert!((fd - d_a[k]).norm() < 1e-6 * scale, "∂/∂a{k}: {} vs {fd}", d_a[k]);
            }
            let h = 1e-5 * omega;
            let fd = (psi(&mut hill, &mut bal, &a, omega + h, lambda, &w, &v)
                - psi(&mut hill, &mut bal, &a, omega - h, lambda, &w, &v))
                / (2.0 * h);
            assert!((fd - d_o).norm() < 1e-6 * fd.norm(), "∂/∂Ω: {d_o} vs {fd}");
            let p0 = bal.params()[param];
            let h = 1e-5 * p0;
            bal.set_param(param, p0 + h);
            let fp = psi(&mut hill, &mut bal, &a, omega, lambda, &w, &v);
            bal.set_param(param, p0 - h);
            let fm = psi(&mut hill, &mut bal, &a, omega, lambda, &w, &v);
            bal.set_param(param, p0);
            let fd = (fp - fm) / (2.0 * h);
            assert!((fd - d_p).norm() < 1e-6 * fd.norm(), "∂/∂{name}: {d_p} vs {fd}");
        }
        // T'(λ): central differences in λ along the imaginary axis
        let h = 1e-5;
        let step = Complex64::new(0.0, h);
        let fd = (psi(&mut hill, &mut bal, &a, omega, lambda + step, &w, &v)
            - psi(&mut hill, &mut bal, &a, omega, lambda - step, &w, &v))
            / (2.0 * h);
        hill.prepare_operator(&mut bal, &a, omega).unwrap();
        let dtv = hill.derivative_applied(bal.params(), omega, lambda, &v);
        let exact: Complex64 = Complex64::new(0.0, 1.0)
            * w.iter().zip(dtv).map(|(w, x)| w.conj() * x).sum::<Complex64>();
        assert!((fd - exact).norm() < 1e-6 * fd.norm(), "∂/∂ω: {exact} vs {fd}");
    }
}
