//! Second derivatives of the residual, exactly: the gradient of `wᵀ J v` with respect
//! to the coefficients, Ω and one parameter, for fixed vectors `w` and `v`.
//!
//! That is what the derivative of a fold's test function needs (`g_z = -wᵀ J_z v`,
//! [`crate::bifurcation`]). Each direction `u` is one pass of the model with
//! hyper-dual numbers: signals carry `s + ε₁ s_v + ε₂ s_u + ε₁ε₂ s_uv` (the signal of
//! `v`, the signal's derivative along `u`, and the derivative of the former along the
//! latter), so the `ε₁ε₂` part of the model's output is `D_v D_u r` at each sample,
//! with no truncation error. The signals are polynomials of the same degree as for
//! the residual, so the samples that are alias-free for `R` are for these too.

use super::Balance;
use crate::fourier::{apply_factor, spectral_factor};
use crate::model::{Model, Order};
use num_complex::Complex64;
use num_dual::HyperDual64;
use std::f64::consts::FRAC_PI_2;

/// Buffers of [`Balance::bilinear_gradient`], sized for one balance and reused.
#[derive(Debug, Clone)]
pub struct BilinearWork {
    /// signal samples of `v`, `s * M + j`
    sv: Vec<f64>,
    /// the derivative of each signal along the current direction, `s * M + j`
    su: Vec<f64>,
    /// the derivative of `sv` along the current direction
    suv: Vec<f64>,
    /// projected `D_v D_u R`
    out: Vec<f64>,
    /// coefficient scratch: a unit vector
    unit: Vec<f64>,
    h_params: Vec<HyperDual64>,
    h_sig: Vec<HyperDual64>,
    h_out: Vec<HyperDual64>,
}

impl BilinearWork {
    /// Buffers for `bal`.
    pub fn new<M: Model>(bal: &Balance<'_, M>) -> Self {
        let (m, nsig, n) = (bal.m, bal.nsig, bal.len());
        let zero = HyperDual64::new(0.0, 0.0, 0.0, 0.0);
        BilinearWork {
            sv: vec![0.0; nsig * m],
            su: vec![0.0; nsig * m],
            suv: vec![0.0; nsig * m],
            out: vec![0.0; n],
            unit: vec![0.0; n],
            h_params: vec![zero; bal.params.len()],
            h_sig: vec![zero; nsig],
            h_out: vec![zero; bal.ndof],
        }
    }
}

/// What a second derivative is taken along (besides `v`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Along {
    Coeff(usize),
    Omega,
    Param(usize),
}

impl<M: Model> Balance<'_, M> {
    /// The gradient of `ψ = wᵀ J(a, Ω, θ) v` (`J = ∂R/∂a`) at fixed `w` and `v`:
    /// `∂ψ/∂a` into `d_a`, and `(∂ψ/∂Ω, ∂ψ/∂θ_param)` returned (the second 0 without
    /// a parameter). Exact (hyper-dual numbers); `n + 2` passes over the samples.
    ///
    /// ```
    /// use ihbm::balance::{Balance, BilinearWork};
    /// use ihbm::models::Duffing;
    /// // One harmonic: R₁ = (k - mΩ²) a + (3/4) k3 a (a² + b²) - F, R₂ likewise in b.
    /// let model = Duffing::default();
    /// let mut hb = Balance::new(&model, 1).unwrap();
    /// let mut work = BilinearWork::new(&hb);
    /// let (a, b) = (0.3, 0.2);
    /// let x = [0.0, a, b];
    /// // wᵀ J v with w = v = e₁ is ∂R₁/∂a = k - mΩ² + (3/4) k3 (3a² + b²)
    /// let e1 = [0.0, 1.0, 0.0];
    /// let mut d_a = [0.0; 3];
    /// let (d_omega, _) = hb.bilinear_gradient(&x, 1.5, &e1, &e1, None, &mut work, &mut d_a);
    /// let k3 = model.k3;
    /// assert!((d_a[1] - 4.5 * k3 * a).abs() < 1e-12);
    /// assert!((d_a[2] - 1.5 * k3 * b).abs() < 1e-12);
    /// assert!((d_omega + 2.0 * model.m * 1.5).abs() < 1e-12);
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn bilinear_gradient(
        &mut self,
        a: &[f64],
        omega: f64,
        w: &[f64],
        v: &[f64],
        param: Option<usize>,
        work: &mut BilinearWork,
        d_a: &mut [f64],
    ) -> (f64, f64) {
        self.fill_signals(a, omega);
        let m = self.m;
        for s in 0..self.nsig {
            self.signal_of(s, v, omega, false, &mut work.sv[s * m..(s + 1) * m]);
        }
        for k in 0..self.len() {
            d_a[k] = self.along(Along::Coeff(k), omega, a, v, w, work);
        }
        let d_omega = self.along(Along::Omega, omega, a, v, w, work);
        let d_param = param.map_or(0.0, |i| self.along(Along::Param(i), omega, a, v, w, work));
        (d_omega, d_param)
    }

    /// Samples of signal `s` for coefficients `x`: the spectral operator `(ikΩ)^q`,
    /// or with `dq` its derivative with respect to the order `q`.
    fn signal_of(&mut self, s: usize, x: &[f64], omega: f64, dq: bool, out: &mut [f64]) {
        let model = self.model;
        crate::model::combine_blocks(&model.signals()[s].terms, x, &mut self.comb);
        let q = self.orders[s];
        match dq {
            false => {
                let lam = &self.lam[s * (self.n + 1)..(s + 1) * (self.n + 1)];
                apply_factor(&self.comb, &mut self.op, |k| lam[k]);
            }
            true => apply_factor(&self.comb, &mut self.op, |k| {
                if k == 0 {
                    Complex64::new(0.0, 0.0)
                } else {
                    spectral_factor(k, omega, q)
                        * Complex64::new((k as f64 * omega).ln(), FRAC_PI_2)
                }
            }),
        }
        self.fourier.synthesize(&self.op, out);
    }

    /// `wᵀ D_v D_u R` for one direction `u` (signals of `a` filled, `work.sv` set).
    fn along(
        &mut self,
        u: Along,
        omega: f64,
        a: &[f64],
        v: &[f64],
        w: &[f64],
        work: &mut BilinearWork,
    ) -> f64 {
        let m = self.m;
        work.suv.fill(0.0);
        match u {
            Along::Coeff(k) => {
                work.unit.fill(0.0);
                work.unit[k] = 1.0;
                let unit = std::mem::take(&mut work.unit);
                for s in 0..self.nsig {
                    self.signal_of(s, &unit, omega, false, &mut work.su[s * m..(s + 1) * m]);
                }
                work.unit = unit;
            }
            Along::Omega => {
                // every factor (ikΩ)^q moves by (q/Ω)(ikΩ)^q
                for s in 0..self.nsig {
                    let f = self.orders[s] / omega;
                    for j in 0..m {
                        work.su[s * m + j] = f * self.sig[s * m + j];
                        work.suv[s * m + j] = f * work.sv[s * m + j];
                    }
                }
            }
            Along::Param(index) => {
                work.su.fill(0.0);
                let model = self.model;
                for s in 0..self.nsig {
                    if model.signals()[s].order == Order::Param(index) {
                        self.signal_of(s, a, omega, true, &mut work.su[s * m..(s + 1) * m]);
                        self.signal_of(s, v, omega, true, &mut work.suv[s * m..(s + 1) * m]);
                    }
                }
            }
        }
        let (d_omega, d_param) = match u {
            Along::Omega => (1.0, None),
            Along::Param(i) => (0.0, Some(i)),
            Along::Coeff(_) => (0.0, None),
        };
        for (i, (h, &p)) in work.h_params.iter_mut().zip(&self.params).enumerate() {
            *h = HyperDual64::new(p, 0.0, if Some(i) == d_param { 1.0 } else { 0.0 }, 0.0);
        }
        let h_omega = HyperDual64::new(omega * self.period, 0.0, d_omega * self.period, 0.0);
        for j in 0..m {
            for s in 0..self.nsig {
                let i = s * m + j;
                work.h_sig[s] = HyperDual64::new(self.sig[i], work.sv[i], work.su[i], work.suv[i]);
            }
            self.model.residual(
                &work.h_params,
                h_omega,
                self.phases[j],
                &work.h_sig,
                &mut work.h_out,
            );
            for e in 0..self.ndof {
                self.res[e * m + j] = work.h_out[e].eps1eps2;
            }
        }
        self.project(&mut work.out);
        work.out.iter().zip(w).map(|(x, y)| x * y).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::QuarterCar;
    use faer::Mat;

    /// `wᵀ J v` at `(a, Ω)` with the model's parameters as set in `bal`.
    fn psi(bal: &mut Balance<'_, QuarterCar>, a: &[f64], omega: f64, w: &[f64], v: &[f64]) -> f64 {
        let n = a.len();
        let mut j = Mat::<f64>::zeros(n, n);
        let mut r = vec![0.0; n];
        bal.jacobian(a, omega, &mut r, j.as_mut());
        (0..n).map(|i| w[i] * (0..n).map(|k| j[(i, k)] * v[k]).sum::<f64>()).sum()
    }

    /// The exact gradient against central differences of `wᵀ J v` (a different
    /// method: Jacobians at shifted points), in every coefficient, in Ω, and in a
    /// parameter that is a coefficient (`k3`) and one that is a fractional order (`p`).
    #[test]
    fn the_bilinear_gradient_matches_central_differences_of_the_jacobian() {
        let model = QuarterCar::default();
        let mut bal = Balance::new(&model, 3).unwrap();
        let n = bal.len();
        let wave =
            |s: f64| -> Vec<f64> { (0..n).map(|i| 1e-2 * ((i as f64 + 1.0) * s).sin()).collect() };
        let (a, v, w) = (wave(0.7), wave(1.3), wave(2.9));
        let omega = 12.0;
        let mut work = BilinearWork::new(&bal);
        let mut d_a = vec![0.0; n];
        for (param, name) in
            [(model.param_index("k3").unwrap(), "k3"), (model.param_index("p").unwrap(), "p")]
        {
            let (d_o, d_p) =
                bal.bilinear_gradient(&a, omega, &w, &v, Some(param), &mut work, &mut d_a);
            let scale = d_a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for k in 0..n {
                let h = 1e-5;
                let (mut ap, mut am) = (a.clone(), a.clone());
                ap[k] += h;
                am[k] -= h;
                let fd = (psi(&mut bal, &ap, omega, &w, &v) - psi(&mut bal, &am, omega, &w, &v))
                    / (2.0 * h);
                assert!((fd - d_a[k]).abs() < 1e-6 * scale, "∂/∂a{k}: {} vs {fd}", d_a[k]);
            }
            let h = 1e-5 * omega;
            let fd = (psi(&mut bal, &a, omega + h, &w, &v) - psi(&mut bal, &a, omega - h, &w, &v))
                / (2.0 * h);
            assert!((fd - d_o).abs() < 1e-6 * fd.abs(), "∂/∂Ω: {d_o} vs {fd}");
            let p0 = bal.params()[param];
            let h = 1e-5 * p0;
            bal.set_param(param, p0 + h);
            let fp = psi(&mut bal, &a, omega, &w, &v);
            bal.set_param(param, p0 - h);
            let fm = psi(&mut bal, &a, omega, &w, &v);
            bal.set_param(param, p0);
            let fd = (fp - fm) / (2.0 * h);
            assert!((fd - d_p).abs() < 1e-6 * fd.abs(), "∂/∂{name}: {d_p} vs {fd}");
        }
    }
}
