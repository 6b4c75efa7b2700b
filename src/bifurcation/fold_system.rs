//! The minimally extended system of a fold: `R(a, Ω, P) = 0` and one scalar `g` that
//! vanishes where `∂R/∂a` is singular, solved by a bordered Newton method in two
//! free parameters (Ω and `P`) plus an arc-length condition.
//!
//! `g` comes from bordering the scaled Jacobian `J` with vectors `b`, `c` that are
//! close to its left and right null vectors:
//!
//! ```text
//! [ J   b ] [v]   [0]        [ Jᵀ  c ] [w]   [0]
//! [ cᵀ  0 ] [g] = [1],       [ bᵀ  0 ] [h] = [1],
//! ```
//!
//! so `g = 0` exactly where `J` is singular (then `v` is its null vector), and
//! `∂g/∂z = -wᵀ (∂J/∂z) v` for every unknown `z`: second derivatives of the residual,
//! which [`Balance::bilinear_gradient`] gives exactly from hyper-dual numbers. The
//! borders are renewed from `w` and `v` at every accepted point, which keeps the
//! bordered matrix well conditioned along the whole curve without changing where
//! `g` vanishes.
//!
//! Unknowns are scaled as in the one-parameter tracer: `y = [a/s_a, Ω/s_Ω, φ(P)/s_P]`,
//! with `φ` the identity or, for a parameter range spanning a decade or more of
//! positive values, the logarithm (so that steps are relative in `P`).

use super::period_two::{embedding, odd_harmonics};
use super::torus::TorusTest;
use crate::balance::{Balance, BilinearWork};
use crate::continuation::path::Extended;
use crate::continuation::tracer::{dot, iterate, newton_update, unit_tangent};
use crate::error::{Matrix, Quantity};
use crate::linalg::DenseLu;
use crate::model::DynModel;
use crate::results::Stall;
use faer::prelude::ReborrowMut;
use faer::{Mat, MatMut};

/// How the parameter is represented among the unknowns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ParamScale {
    Linear,
    Log,
}

impl ParamScale {
    pub fn forward(self, p: f64) -> f64 {
        match self {
            ParamScale::Linear => p,
            ParamScale::Log => p.ln(),
        }
    }

    pub fn inverse(self, u: f64) -> f64 {
        match self {
            ParamScale::Linear => u,
            ParamScale::Log => u.exp(),
        }
    }
}

pub(crate) struct FoldSystem<'m> {
    pub bal: Balance<'m>,
    /// The second parameter (by index).
    pub param: usize,
    pub scale: ParamScale,
    pub n: usize,
    pub sa: f64,
    pub so: f64,
    pub sp: f64,
    pub sr: f64,
    /// Ω and P ranges: nothing is evaluated outside them.
    pub omega_range: (f64, f64),
    pub param_range: (f64, f64),
    pub tol: f64,
    /// Newton iterations, all calls together.
    pub iterations: usize,
    /// Max-norm of the scaled residual and test function before the last step.
    last_residual: f64,
    /// Which matrix the test function borders.
    test: TestMatrix<'m>,
    /// Its size: `n`, or the odd coefficients of the period-2 balance.
    nt: usize,
    /// Borders of the test function (unit vectors, renewed at accepted points).
    b: Vec<f64>,
    c: Vec<f64>,
    /// The bordered Jacobian of the test function, `(n+1)²`.
    lu_m: DenseLu,
    /// The Newton matrix of the extended system, `(n+2)²`.
    lu_k: DenseLu,
    work: BilinearWork,
    a: Vec<f64>,
    r: Vec<f64>,
    d_omega: Vec<f64>,
    d_param: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
    d_a: Vec<f64>,
    rhs: Vec<f64>,
    /// The bordered test function's right-hand side and solution, `nt + 1`.
    x: Vec<f64>,
}

/// The matrix whose singularity the curve follows.
pub(crate) enum TestMatrix<'m> {
    /// `∂R/∂a`: folds.
    Jacobian,
    /// The odd-harmonic block of the Jacobian of the balance in Ω/2 at the period-1
    /// solution (a multiplier −1): period doubling.
    OddBlock(Box<OddBlock<'m>>),
    /// Hill's operator `T(iω)`, the torus frequency ω one more unknown (a pair of
    /// multipliers `e^{±2πiω/Ω}` on the unit circle): Neimark–Sacker. Complex, so
    /// not through [`FoldSystem::fill_test`] but [`FoldSystem::torus_rows`].
    Torus {
        test: Box<TorusTest>,
        /// ω at the start point.
        start: f64,
    },
}

/// The period-2 balance of a period-doubling curve and its buffers.
pub(crate) struct OddBlock<'m> {
    bal: Balance<'m>,
    work: BilinearWork,
    /// Where each period-1 coefficient goes among the period-2 ones.
    emb: Vec<usize>,
    /// The odd-harmonic coefficients of the period-2 balance.
    odd: Vec<usize>,
    a2: Vec<f64>,
    r2: Vec<f64>,
    j2: Mat<f64>,
    w2: Vec<f64>,
    v2: Vec<f64>,
    d_a2: Vec<f64>,
}

impl<'m> OddBlock<'m> {
    /// For a period-1 balance of `n1` harmonics with `ndof` DOFs: the balance of
    /// `model` with period 2 in `2 n1` harmonics of Ω/2 (so that every period-1
    /// harmonic has its place).
    pub fn new(model: &'m dyn DynModel, ndof: usize, n1: usize) -> crate::error::Result<Self> {
        let n2 = 2 * n1;
        let bal = Balance::with_period(model, n2, 2)?;
        let len = bal.len();
        // n2 = 2 n1: every period-1 coefficient has its place
        let emb: Vec<usize> = embedding(ndof, n1, n2).into_iter().flatten().collect();
        let odd: Vec<usize> = odd_harmonics(ndof, n2)
            .into_iter()
            .enumerate()
            .filter_map(|(i, o)| o.then_some(i))
            .collect();
        Ok(OddBlock {
            work: BilinearWork::new(&bal),
            bal,
            emb,
            odd,
            a2: vec![0.0; len],
            r2: vec![0.0; len],
            j2: Mat::zeros(len, len),
            w2: vec![0.0; len],
            v2: vec![0.0; len],
            d_a2: vec![0.0; len],
        })
    }

    fn embed(&mut self, a: &[f64]) {
        self.a2.fill(0.0);
        for (&i, &x) in self.emb.iter().zip(a) {
            self.a2[i] = x;
        }
    }
}

/// Scaled residuals at rounding level (see [`FoldSystem::correct`]).
const ROUNDING_RESIDUAL: f64 = 1e-11;
/// The largest update that may be rounding noise (see [`FoldSystem::correct`]).
const ROUNDING_STEP: f64 = 1e-8;

impl<'m> FoldSystem<'m> {
    pub fn new(bal: Balance<'m>, param: usize, scale: ParamScale, tol: f64) -> Self {
        let n = bal.len();
        let work = BilinearWork::new(&bal);
        let mut e = vec![0.0; n];
        e[n / 2] = 1.0;
        FoldSystem {
            bal,
            param,
            scale,
            n,
            sa: 1.0,
            so: 1.0,
            sp: 1.0,
            sr: 1.0,
            omega_range: (f64::NEG_INFINITY, f64::INFINITY),
            param_range: (f64::NEG_INFINITY, f64::INFINITY),
            tol,
            iterations: 0,
            last_residual: f64::INFINITY,
            test: TestMatrix::Jacobian,
            nt: n,
            b: e.clone(),
            c: e,
            lu_m: DenseLu::new(n + 1),
            lu_k: DenseLu::new(n + 2),
            work,
            a: vec![0.0; n],
            r: vec![0.0; n],
            d_omega: vec![0.0; n],
            d_param: vec![0.0; n],
            v: vec![0.0; n],
            w: vec![0.0; n],
            d_a: vec![0.0; n],
            rhs: vec![0.0; n + 2],
            x: vec![0.0; n + 1],
        }
    }

    /// The system of a period-doubling curve: the odd block of `odd` bordered
    /// instead of the Jacobian.
    pub fn period_doubling(mut self, odd: OddBlock<'m>) -> Self {
        let nt = odd.odd.len();
        let mut e = vec![0.0; nt];
        e[nt / 2] = 1.0;
        self.nt = nt;
        self.b = e.clone();
        self.c = e;
        self.lu_m = DenseLu::new(nt + 1);
        self.v = vec![0.0; nt];
        self.w = vec![0.0; nt];
        self.x = vec![0.0; nt + 1];
        self.test = TestMatrix::OddBlock(Box::new(odd));
        self
    }

    /// The system of a torus curve started at torus frequency `torus` (the
    /// imaginary part of the critical Floquet exponent).
    pub fn torus(mut self, torus: f64) -> crate::error::Result<Self> {
        let test = Box::new(TorusTest::new(&self.bal)?);
        self.test = TestMatrix::Torus { test, start: torus };
        self.lu_k = DenseLu::new(self.n + 3);
        self.rhs = vec![0.0; self.n + 3];
        Ok(self)
    }

    /// The number of unknowns (and equations, with the arc-length condition):
    /// coefficients, Ω, the parameter, and the torus frequency of a torus curve.
    pub fn dim(&self) -> usize {
        match self.test {
            TestMatrix::Torus { .. } => self.n + 3,
            _ => self.n + 2,
        }
    }

    /// The torus frequency ω of `y` (torus curves only).
    pub fn torus_frequency(&self, y: &[f64]) -> Option<f64> {
        match self.test {
            TestMatrix::Torus { .. } => Some(y[self.n + 2] * self.so),
            _ => None,
        }
    }

    /// The scaled Jacobian and residual `self.r` at the point in `self.a` into the
    /// top-left block of `lu_k`.
    fn fill_jacobian(&mut self, omega: f64) {
        let n = self.n;
        let cs = self.sa / self.sr;
        let mut kk = self.lu_k.matrix_mut();
        self.bal.jacobian(&self.a, omega, &mut self.r, kk.rb_mut().submatrix_mut(0, 0, n, n));
        for j in 0..n {
            for i in 0..n {
                kk[(i, j)] *= cs;
            }
        }
    }

    /// The scaled test matrix at the point in `self.a` and `(Ω, P)` into `out`
    /// (`nt × nt`), and the scaled Jacobian (and residual `self.r`) into the top-left
    /// block of `lu_k`.
    fn fill_test(&mut self, omega: f64, p: f64, mut out: MatMut<'_, f64>) {
        let n = self.n;
        let cs = self.sa / self.sr;
        self.fill_jacobian(omega);
        let kk = self.lu_k.matrix_mut();
        match &mut self.test {
            TestMatrix::Torus { .. } => {}
            TestMatrix::Jacobian => {
                for j in 0..n {
                    for i in 0..n {
                        out[(i, j)] = kk[(i, j)];
                    }
                }
            }
            TestMatrix::OddBlock(ob) => {
                ob.embed(&self.a);
                ob.bal.set_param(self.param, p);
                ob.bal.jacobian(&ob.a2, 0.5 * omega, &mut ob.r2, ob.j2.as_mut());
                for (j, &oj) in ob.odd.iter().enumerate() {
                    for (i, &oi) in ob.odd.iter().enumerate() {
                        out[(i, j)] = cs * ob.j2[(oi, oj)];
                    }
                }
            }
        }
    }

    /// The scaled unknowns of `(a, Ω, P)`.
    pub fn scaled(&self, a: &[f64], omega: f64, p: f64) -> Vec<f64> {
        let mut y: Vec<f64> = a.iter().map(|v| v / self.sa).collect();
        y.push(omega / self.so);
        y.push(self.scale.forward(p) / self.sp);
        if let TestMatrix::Torus { start, .. } = self.test {
            y.push(start / self.so);
        }
        y
    }

    pub fn omega(&self, y: &[f64]) -> f64 {
        y[self.n] * self.so
    }

    pub fn value(&self, y: &[f64]) -> f64 {
        self.scale.inverse(y[self.n + 1] * self.sp)
    }

    pub fn coeffs(&self, y: &[f64]) -> Vec<f64> {
        y[..self.n].iter().map(|v| v * self.sa).collect()
    }

    /// `dP/dy_P`.
    fn dp_dy(&self, p: f64) -> f64 {
        match self.scale {
            ParamScale::Linear => self.sp,
            ParamScale::Log => p * self.sp,
        }
    }

    /// Unscaled point of `y` into `self.a` and the model; `(Ω, P)`, or why not (a
    /// parameter outside its range: the model is never evaluated there).
    fn unscale(&mut self, y: &[f64]) -> Result<(f64, f64), Stall> {
        let n = self.n;
        for (a, &v) in self.a.iter_mut().zip(&y[..n]) {
            *a = v * self.sa;
        }
        let (omega, p) = (self.omega(y), self.value(y));
        let inside = |x: f64, (lo, hi): (f64, f64)| {
            let slack = 1e-9 * (hi - lo).abs().max(hi.abs());
            x >= lo - slack && x <= hi + slack
        };
        if !inside(omega, self.omega_range) {
            return Err(Stall::LeftFrequencyRange { omega });
        }
        if !inside(p, self.param_range) {
            return Err(Stall::LeftParameterRange { at: p });
        }
        self.bal.set_param(self.param, p);
        // a coefficient undefined here is named, not met as a non-finite residual
        self.bal.check_coefficients(omega)?;
        Ok((omega, p))
    }

    /// Fill the bordered test-function matrix at the point in `self.a` (the scaled
    /// Jacobian also into the top-left block of `lu_k`); solve for `v`, `w` and return
    /// `g`.
    fn test_function(&mut self, omega: f64, p: f64) -> Result<f64, Stall> {
        let nt = self.nt;
        let mut lu_m = std::mem::replace(&mut self.lu_m, DenseLu::new(0));
        {
            let mut km = lu_m.matrix_mut();
            self.fill_test(omega, p, km.rb_mut().submatrix_mut(0, 0, nt, nt));
            for i in 0..nt {
                km[(i, nt)] = self.b[i];
                km[(nt, i)] = self.c[i];
            }
            km[(nt, nt)] = 0.0;
        }
        let pivots = lu_m.factor();
        let mut x = std::mem::take(&mut self.x);
        x.fill(0.0);
        x[nt] = 1.0;
        lu_m.solve(&mut x);
        let g = x[nt];
        self.v.copy_from_slice(&x[..nt]);
        x.fill(0.0);
        x[nt] = 1.0;
        lu_m.solve_transpose(&mut x);
        self.w.copy_from_slice(&x[..nt]);
        self.x = x;
        self.lu_m = lu_m;
        if pivots.is_nan() || pivots <= 1e-15 {
            return Err(Stall::Singular { matrix: Matrix::TestFunction, omega });
        }
        Ok(g)
    }

    /// `∂ψ/∂a` into `self.d_a` and `(∂ψ/∂Ω, ∂ψ/∂P)` for `ψ = wᵀ A v`, `A` the test
    /// matrix (unscaled).
    fn psi_gradient(&mut self, omega: f64) -> (f64, f64) {
        match &mut self.test {
            TestMatrix::Torus { .. } => (0.0, 0.0), // complex: `torus_rows`
            TestMatrix::Jacobian => self.bal.bilinear_gradient(
                &self.a,
                omega,
                &self.w,
                &self.v,
                Some(self.param),
                &mut self.work,
                &mut self.d_a,
            ),
            TestMatrix::OddBlock(ob) => {
                ob.w2.fill(0.0);
                ob.v2.fill(0.0);
                for (k, &o) in ob.odd.iter().enumerate() {
                    ob.w2[o] = self.w[k];
                    ob.v2[o] = self.v[k];
                }
                let (po, pp) = ob.bal.bilinear_gradient(
                    &ob.a2,
                    0.5 * omega,
                    &ob.w2,
                    &ob.v2,
                    Some(self.param),
                    &mut ob.work,
                    &mut ob.d_a2,
                );
                // a2 = E a, the period-2 balance at Ω/2
                for (d, &e) in self.d_a.iter_mut().zip(&ob.emb) {
                    *d = ob.d_a2[e];
                }
                (0.5 * po, pp)
            }
        }
    }

    /// One Newton step of the extended system at `y` (updated in place) with the
    /// arc-length condition `border · y = target`; the max-norm of the step.
    pub fn newton_step(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
    ) -> Result<f64, Stall> {
        let n = self.n;
        let d = self.dim();
        self.iterations += 1;
        let (omega, p) = self.unscale(y)?;
        // rows n..d-1: the test function (one real row, or two for a complex one)
        self.test_rows(y, omega, p)?;
        self.bal.d_omega(&self.a, omega, &mut self.d_omega);
        self.bal.d_param(&self.a, omega, self.param, &mut self.d_param);
        let dpy = self.dp_dy(p);
        let mut k = self.lu_k.matrix_mut();
        for i in 0..n {
            k[(i, n)] = self.d_omega[i] * self.so / self.sr;
            k[(i, n + 1)] = self.d_param[i] * dpy / self.sr;
            for j in n + 2..d {
                k[(i, j)] = 0.0; // R does not depend on the torus frequency
            }
            self.rhs[i] = self.r[i] / self.sr;
        }
        for j in 0..d {
            k[(d - 1, j)] = border[j];
        }
        self.rhs[d - 1] = dot(border, y) - target;
        self.last_residual = self.rhs[..d - 1].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        newton_update(&mut self.lu_k, &mut self.rhs, y, omega)
    }

    /// Row `n` of the Newton matrix and its right-hand side for a real test function
    /// (folds, period doubling); the scaled Jacobian into the top-left block.
    fn real_row(&mut self, omega: f64, p: f64) -> Result<(), Stall> {
        let n = self.n;
        let g = self.test_function(omega, p)?;
        let (psi_o, psi_p) = self.psi_gradient(omega);
        // ψ was of the raw Jacobian; g belongs to the scaled one: -(s_a/s_r) ψ_z,
        // then by the chain rule into the scaled unknowns.
        let cs = self.sa / self.sr;
        let dpy = self.dp_dy(p);
        let mut k = self.lu_k.matrix_mut();
        for i in 0..n {
            k[(n, i)] = -cs * self.sa * self.d_a[i];
        }
        k[(n, n)] = -cs * self.so * psi_o;
        k[(n, n + 1)] = -cs * dpy * psi_p;
        self.rhs[n] = g;
        Ok(())
    }

    /// The rows of the test function: [`FoldSystem::real_row`], or for a torus curve
    /// rows `n`, `n + 1` (real and imaginary parts of the complex test function) of
    /// its Newton matrix, with the column of the torus frequency; the scaled Jacobian
    /// into the top-left block.
    fn test_rows(&mut self, y: &[f64], omega: f64, p: f64) -> Result<(), Stall> {
        let n = self.n;
        let Some(torus) = self.torus_frequency(y) else { return self.real_row(omega, p) };
        if !(torus > 0.0 && torus < 0.5 * omega) {
            return Err(Stall::LeftTorusRange { torus, omega });
        }
        let cs = self.sa / self.sr;
        let dpy = self.dp_dy(p);
        self.fill_jacobian(omega);
        // (a torus frequency is a torus curve's: the real row is the others')
        let TestMatrix::Torus { test, .. } = &mut self.test else { return self.real_row(omega, p) };
        let g = test.evaluate(&mut self.bal, &self.a, omega, torus, cs)?;
        let grad = test.gradient(&mut self.bal, &self.a, omega, torus, self.param);
        let mut k = self.lu_k.matrix_mut();
        for (i, da) in test.d_a.iter().enumerate() {
            let z = -cs * self.sa * da;
            k[(n, i)] = z.re;
            k[(n + 1, i)] = z.im;
        }
        for (j, (dz, s)) in [(grad.omega, self.so), (grad.param, dpy), (grad.torus, self.so)]
            .into_iter()
            .enumerate()
        {
            let z = -cs * s * dz;
            k[(n, n + j)] = z.re;
            k[(n + 1, n + j)] = z.im;
        }
        self.rhs[n] = g.re;
        self.rhs[n + 1] = g.im;
        Ok(())
    }

    /// The unit tangent from the LU of the last Newton step (oriented along its border).
    pub fn tangent(&mut self) -> Vec<f64> {
        let mut t = vec![0.0; self.dim()];
        unit_tangent(&mut self.lu_k, &mut t);
        t
    }

    /// Renew the borders from the null vectors of the last test function.
    pub fn renew_borders(&mut self) {
        if let TestMatrix::Torus { test, .. } = &mut self.test {
            test.renew_borders();
            return;
        }
        let nv = dot(&self.v, &self.v).sqrt();
        let nw = dot(&self.w, &self.w).sqrt();
        if nv > 0.0 && nw > 0.0 && nv.is_finite() && nw.is_finite() {
            for i in 0..self.nt {
                self.c[i] = self.v[i] / nv;
                self.b[i] = self.w[i] / nw;
            }
        }
    }

    /// Borders for a start point `(a, Ω, P)` near a fold (or a period doubling): the
    /// right and left null vectors of the scaled test matrix by two steps of inverse
    /// iteration.
    pub fn init_borders(&mut self, a: &[f64], omega: f64, p: f64) -> Result<(), Stall> {
        let nt = self.nt;
        self.bal.set_param(self.param, p);
        self.a.copy_from_slice(a);
        if let TestMatrix::Torus { test, start } = &mut self.test {
            let cs = self.sa / self.sr;
            return test.init_borders(&mut self.bal, a, omega, *start, cs);
        }
        let mut lu = DenseLu::new(nt);
        self.fill_test(omega, p, lu.matrix_mut());
        if lu.factor().is_nan() {
            return Err(Stall::NonFinite { quantity: Quantity::StartJacobian, omega });
        }
        let mut v = vec![1.0; nt];
        let mut w = vec![1.0; nt];
        for _ in 0..2 {
            lu.solve(&mut v);
            lu.solve_transpose(&mut w);
            for x in [&mut v, &mut w] {
                let norm = dot(x, x).sqrt();
                if !(norm.is_finite() && norm > 0.0) {
                    return Err(Stall::NoNullVector { omega });
                }
                x.iter_mut().for_each(|e| *e /= norm);
            }
        }
        self.c = v;
        self.b = w;
        Ok(())
    }
}

impl Extended for FoldSystem<'_> {
    /// Newton from `y` to the fold curve on `border · y = target`; iterations used.
    fn correct(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
        budget: usize,
    ) -> Result<usize, Stall> {
        let tol = self.tol;
        iterate(budget, tol, |it, prev| {
            let dn = self.newton_step(y, border, target)?;
            // Where the extended system is ill conditioned (near a point where two
            // fold curves meet), rounding alone moves the iterate by more than `tol`
            // (measured: updates of 1e-10 to 5e-10 going round at residuals of 1e-12
            // on the quarter car). An update that stopped shrinking at such a level,
            // with both residuals at rounding level, is converged.
            let floor = self.last_residual <= ROUNDING_RESIDUAL && dn <= ROUNDING_STEP;
            Ok((dn, self.omega(y), it >= 2 && dn > 0.5 * prev && floor))
        })
    }

    fn tangent(&mut self, t: &mut [f64]) {
        unit_tangent(&mut self.lu_k, t);
    }
}
