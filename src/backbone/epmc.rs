//! The extended periodic motion concept as a square system for Newton's method.
//!
//! A nonlinear mode of a damped model is the periodic motion of
//! `r(x) - ξ M ẋ = 0` with every forcing term left out (Krack 2015): the artificial
//! damping `-ξ M ẋ` compensates the dissipation over a period, and ξ is an unknown
//! with the frequency ω. In Fourier coefficients, with `a = q â` (q the modal
//! amplitude, continued as `u = ln q` so that steps are relative over decades):
//!
//! ```text
//! F(â, ω, ξ, u) = [R(qâ, ω) - R(0, ω) - ξ M D(ω) qâ] / (q s_r) = 0     (n rows)
//!                 â[phase] = 0                         (the sine of harmonic 1 of one DOF)
//!                 Σ M_ij (â_c1,i â_c1,j + â_s1,i â_s1,j) - 1 = 0     (q is the modal amplitude)
//! ```
//!
//! `R(0, ω)` holds the forcing (and any other term without a DOF), so subtracting it
//! leaves the free system; `D(ω)` is the derivative's spectral operator. `n + 2`
//! equations in `n + 3` unknowns: one more row (arc length, or a fixed `u`) makes it
//! square.
//!
//! The same system continues a family of limit cycles in a model parameter P
//! ([`Free::Param`]): ξ is held at 0 and P takes its place among the unknowns, so the
//! family stays regular down to the Hopf point, where q → 0.

use crate::balance::Balance;
use crate::continuation::path::Extended;
use crate::continuation::tracer::{dot, iterate, newton_update, unit_tangent};
use crate::linalg::DenseLu;
use crate::results::Stall;
use faer::prelude::ReborrowMut;

/// The unknown next to ω and `u = ln q`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Free {
    /// The artificial damping ξ (over `so`): a nonlinear mode.
    Xi,
    /// Model parameter `index` (its value is `y * scale`), with ξ = 0: limit cycles.
    Param { index: usize, scale: f64 },
}

pub(crate) struct Epmc<'m> {
    pub bal: Balance<'m>,
    pub n: usize,
    nh: usize,
    ndof: usize,
    /// `ndof × ndof`, row-major.
    mass: Vec<f64>,
    /// The coefficient fixed to 0 (the sine of harmonic 1 of the reference DOF).
    pub phase: usize,
    /// Residual and frequency scales.
    pub sr: f64,
    pub so: f64,
    pub tol: f64,
    pub iterations: usize,
    /// What the unknown `y[n + 1]` is.
    pub free: Free,
    lu: DenseLu,
    a: Vec<f64>,
    r: Vec<f64>,
    r0: Vec<f64>,
    dr: Vec<f64>,
    dr0: Vec<f64>,
    md: Vec<f64>,
    dp: Vec<f64>,
    dp0: Vec<f64>,
    zero: Vec<f64>,
    rhs: Vec<f64>,
}

impl<'m> Epmc<'m> {
    pub fn new(bal: Balance<'m>, mass: Vec<f64>, phase: usize, tol: f64) -> Self {
        let n = bal.len();
        let nh = bal.harmonics();
        let ndof = n / (2 * nh + 1);
        Epmc {
            bal,
            n,
            nh,
            ndof,
            mass,
            phase,
            sr: 1.0,
            so: 1.0,
            tol,
            iterations: 0,
            free: Free::Xi,
            lu: DenseLu::new(n + 3),
            a: vec![0.0; n],
            r: vec![0.0; n],
            r0: vec![0.0; n],
            dr: vec![0.0; n],
            dr0: vec![0.0; n],
            md: vec![0.0; n],
            dp: vec![0.0; n],
            dp0: vec![0.0; n],
            zero: vec![0.0; n],
            rhs: vec![0.0; n + 3],
        }
    }

    pub fn dim(&self) -> usize {
        self.n + 3
    }

    pub fn omega(&self, y: &[f64]) -> f64 {
        y[self.n] * self.so
    }

    /// The artificial damping (0 for a family of limit cycles).
    pub fn xi(&self, y: &[f64]) -> f64 {
        match self.free {
            Free::Xi => y[self.n + 1] * self.so,
            Free::Param { .. } => 0.0,
        }
    }

    /// The parameter's value at `y` (NaN for a nonlinear mode).
    pub fn param(&self, y: &[f64]) -> f64 {
        match self.free {
            Free::Xi => f64::NAN,
            Free::Param { scale, .. } => y[self.n + 1] * scale,
        }
    }

    /// The model's parameter values at `y` (the free one's included).
    pub fn params_at(&self, y: &[f64]) -> Vec<f64> {
        let mut p = self.bal.params().to_vec();
        if let Free::Param { index, .. } = self.free {
            p[index] = self.param(y);
        }
        p
    }

    pub fn log_amplitude(&self, y: &[f64]) -> f64 {
        y[self.n + 2]
    }

    /// The Fourier coefficients `q â` of `y`.
    pub fn coeffs(&self, y: &[f64]) -> Vec<f64> {
        let q = y[self.n + 2].exp();
        y[..self.n].iter().map(|v| v * q).collect()
    }

    /// `out = M D(ω) x`: the mass matrix applied to the derivative of `x`.
    fn mass_derivative(&self, x: &[f64], omega: f64, out: &mut [f64]) {
        let (nh, len) = (self.nh, 2 * self.nh + 1);
        out.fill(0.0);
        for i in 0..self.ndof {
            for j in 0..self.ndof {
                let m = self.mass[i * self.ndof + j];
                if m == 0.0 {
                    continue;
                }
                let (xi, oi) = (&x[j * len..(j + 1) * len], i * len);
                for k in 1..=nh {
                    let kw = k as f64 * omega;
                    out[oi + k] += m * kw * xi[nh + k];
                    out[oi + nh + k] -= m * kw * xi[k];
                }
            }
        }
    }

    /// The norm row's value at `â`.
    fn norm(&self, y: &[f64]) -> f64 {
        let (nh, len) = (self.nh, 2 * self.nh + 1);
        let mut s = 0.0;
        for i in 0..self.ndof {
            for j in 0..self.ndof {
                let m = self.mass[i * self.ndof + j];
                s += m
                    * (y[i * len + 1] * y[j * len + 1] + y[i * len + nh + 1] * y[j * len + nh + 1]);
            }
        }
        s
    }

    /// One Newton step at `y` (in place) with the last row `border · y = target`;
    /// the max-norm of the step.
    pub fn newton_step(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
    ) -> Result<f64, Stall> {
        let (n, nh, len) = (self.n, self.nh, 2 * self.nh + 1);
        self.iterations += 1;
        let (omega, xi, q) = (self.omega(y), self.xi(y), y[n + 2].exp());
        if !(omega > 0.0 && omega.is_finite() && q.is_finite() && q > 0.0) {
            return Err(Stall::LeftPhysicalRange { omega, amplitude: q });
        }
        for (a, &v) in self.a.iter_mut().zip(&y[..n]) {
            *a = v * q;
        }
        if let Free::Param { index, .. } = self.free {
            let v = self.param(y);
            if !v.is_finite() {
                return Err(Stall::ParameterNotFinite { value: v });
            }
            self.bal.set_param(index, v);
            // a coefficient that is not finite here ends the curve, naming it
            self.bal.check_coefficients(omega)?;
            self.bal.d_param(&self.a, omega, index, &mut self.dp);
            self.bal.d_param(&self.zero, omega, index, &mut self.dp0);
        }
        let mut k = self.lu.matrix_mut();
        self.bal.jacobian(&self.a, omega, &mut self.r, k.rb_mut().submatrix_mut(0, 0, n, n));
        self.bal.residual(&self.zero, omega, &mut self.r0);
        self.bal.d_omega(&self.a, omega, &mut self.dr);
        self.bal.d_omega(&self.zero, omega, &mut self.dr0);
        let a = std::mem::take(&mut self.a);
        let mut md = std::mem::take(&mut self.md);
        self.mass_derivative(&a, omega, &mut md);
        let mut k = self.lu.matrix_mut();
        // J_E = J - ξ M D: M D couples the cosine and sine of each harmonic
        for i in 0..self.ndof {
            for j in 0..self.ndof {
                let m = self.mass[i * self.ndof + j];
                if m == 0.0 {
                    continue;
                }
                for h in 1..=nh {
                    let kw = h as f64 * omega;
                    k[(i * len + h, j * len + nh + h)] -= xi * m * kw;
                    k[(i * len + nh + h, j * len + h)] += xi * m * kw;
                }
            }
        }
        let inv = 1.0 / (q * self.sr);
        for i in 0..n {
            let re = self.r[i] - self.r0[i] - xi * md[i];
            // ∂/∂u of e^{-u} R_E(e^u â) = (J_E a - R_E) / q
            let jea: f64 = (0..n).map(|j| k[(i, j)] * a[j]).sum();
            k[(i, n)] = self.so * (self.dr[i] - self.dr0[i] - xi * md[i] / omega) * inv;
            k[(i, n + 1)] = match self.free {
                Free::Xi => -self.so * md[i] * inv,
                Free::Param { scale, .. } => scale * (self.dp[i] - self.dp0[i]) * inv,
            };
            k[(i, n + 2)] = (jea - re) * inv;
            self.rhs[i] = re * inv;
        }
        for j in 0..n {
            for i in 0..n {
                k[(i, j)] /= self.sr;
            }
        }
        // the phase and norm rows
        for j in 0..n + 3 {
            k[(n, j)] = 0.0;
            k[(n + 1, j)] = 0.0;
            k[(n + 2, j)] = border[j];
        }
        k[(n, self.phase)] = 1.0;
        self.rhs[n] = y[self.phase];
        for i in 0..self.ndof {
            for j in 0..self.ndof {
                let m = self.mass[i * self.ndof + j];
                for c in [1, nh + 1] {
                    k[(n + 1, i * len + c)] += m * y[j * len + c];
                    k[(n + 1, j * len + c)] += m * y[i * len + c];
                }
            }
        }
        self.rhs[n + 1] = self.norm(y) - 1.0;
        self.rhs[n + 2] = dot(border, y) - target;
        self.a = a;
        self.md = md;
        newton_update(&mut self.lu, &mut self.rhs, y, omega)
    }

    /// The unit tangent from the LU of the last Newton step.
    pub fn tangent(&mut self) -> Vec<f64> {
        let mut t = vec![0.0; self.dim()];
        unit_tangent(&mut self.lu, &mut t);
        t
    }
}

impl Extended for Epmc<'_> {
    /// Newton from `y` on `border · y = target`; iterations used.
    fn correct(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
        budget: usize,
    ) -> Result<usize, Stall> {
        let tol = self.tol;
        iterate(budget, tol, |_, _| {
            let dn = self.newton_step(y, border, target)?;
            Ok((dn, self.omega(y), false))
        })
    }

    fn tangent(&mut self, t: &mut [f64]) {
        unit_tangent(&mut self.lu, t);
    }
}
