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
use crate::fourier::{apply_factor, order_rate};
use crate::model::{Model, Order};
use num_complex::Complex64;
use num_dual::HyperDual64;

/// Buffers of [`Balance::bilinear_gradient`], sized for one balance and reused.
#[derive(Debug, Clone)]
pub struct BilinearWork {
    /// signal samples of `v`, `s * M + j` (the real part, for a complex `v`)
    sv: Vec<f64>,
    /// the imaginary part of the signal samples of a complex `v`
    sv_im: Vec<f64>,
    /// the derivative of each signal along the current direction, `s * M + j`
    su: Vec<f64>,
    /// the derivative of `sv` along the current direction
    suv: Vec<f64>,
    suv_im: Vec<f64>,
    /// projected `D_v D_u R`
    out: Vec<f64>,
    /// coefficient scratch: a unit vector
    unit: Vec<f64>,
    /// one signal's combination of a complex `v` and its image (real, imaginary)
    comb: [Vec<f64>; 2],
    image: [Vec<f64>; 2],
    h_params: Vec<HyperDual64>,
    h_sig: Vec<HyperDual64>,
    h_out: Vec<HyperDual64>,
}

impl BilinearWork {
    /// Buffers for `bal`.
    pub fn new(bal: &Balance<'_>) -> Self {
        let (m, nsig, n) = (bal.m, bal.nsig, bal.len());
        let len = 2 * bal.n + 1;
        let zero = HyperDual64::new(0.0, 0.0, 0.0, 0.0);
        BilinearWork {
            sv: vec![0.0; nsig * m],
            sv_im: vec![0.0; nsig * m],
            su: vec![0.0; nsig * m],
            suv: vec![0.0; nsig * m],
            suv_im: vec![0.0; nsig * m],
            out: vec![0.0; n],
            unit: vec![0.0; n],
            comb: [vec![0.0; len], vec![0.0; len]],
            image: [vec![0.0; len], vec![0.0; len]],
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

/// Which factor of the shifted operator `(λ ± ikΩ)^q` a signal of `e^{λt} v` gets.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Factor {
    /// `(λ ± ikΩ)^q`
    Value,
    /// its derivative in Ω
    DOmega,
    /// its derivative in the order `q`
    DOrder,
}

impl Balance<'_> {
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
        let dot = |out: &[f64]| -> f64 { out.iter().zip(w).map(|(x, y)| x * y).sum() };
        for k in 0..self.len() {
            self.set_direction(Along::Coeff(k), omega, a, work);
            work.suv.fill(0.0);
            self.pass(Along::Coeff(k), omega, false, work);
            d_a[k] = dot(&work.out);
        }
        // every factor (ikΩ)^q moves by (q/Ω)(ikΩ)^q
        self.set_direction(Along::Omega, omega, a, work);
        for s in 0..self.nsig {
            let f = self.orders[s] / omega;
            for j in 0..m {
                work.suv[s * m + j] = f * work.sv[s * m + j];
            }
        }
        self.pass(Along::Omega, omega, false, work);
        let d_omega = dot(&work.out);
        let d_param = param.map_or(0.0, |index| {
            self.set_direction(Along::Param(index), omega, a, work);
            work.suv.fill(0.0);
            let model = self.model;
            for s in 0..self.nsig {
                if model.signals()[s].order == Order::Param(index) {
                    self.signal_of(s, v, omega, true, &mut work.suv[s * m..(s + 1) * m]);
                }
            }
            self.pass(Along::Param(index), omega, false, work);
            dot(&work.out)
        });
        (d_omega, d_param)
    }

    /// The gradient of `ψ = wᴴ T(λ) v` at fixed complex `w` and `v`, where `T(λ)` is
    /// Hill's operator at the exponent `λ`: the Jacobian of the residual applied to
    /// perturbations `e^{λt} v(t)`, whose signals carry the factors `(λ ± ikΩ)^q`
    /// instead of `(±ikΩ)^q` (so `T(0) = J`). `∂ψ/∂a` into `d_a`, `(∂ψ/∂Ω,
    /// ∂ψ/∂θ_param)` returned. Exact (hyper-dual numbers, the real and imaginary
    /// parts of `v` in two passes per direction): the derivative of a torus curve's
    /// test function ([`crate::bifurcation`]).
    #[allow(clippy::too_many_arguments)]
    pub fn shifted_bilinear_gradient(
        &mut self,
        a: &[f64],
        omega: f64,
        lambda: Complex64,
        w: &[Complex64],
        v: &[Complex64],
        param: Option<usize>,
        work: &mut BilinearWork,
        d_a: &mut [Complex64],
    ) -> (Complex64, Complex64) {
        self.fill_signals(a, omega);
        let model = self.model;
        let nsig = self.nsig;
        for s in 0..nsig {
            self.shifted_signal(s, v, omega, lambda, Factor::Value, work, true);
        }
        for k in 0..self.len() {
            self.set_direction(Along::Coeff(k), omega, a, work);
            work.suv.fill(0.0);
            work.suv_im.fill(0.0);
            d_a[k] = self.complex_pass(Along::Coeff(k), omega, w, work);
        }
        self.set_direction(Along::Omega, omega, a, work);
        for s in 0..nsig {
            self.shifted_signal(s, v, omega, lambda, Factor::DOmega, work, false);
        }
        let d_omega = self.complex_pass(Along::Omega, omega, w, work);
        let d_param = param.map_or(Complex64::new(0.0, 0.0), |index| {
            self.set_direction(Along::Param(index), omega, a, work);
            work.suv.fill(0.0);
            work.suv_im.fill(0.0);
            for s in 0..nsig {
                if model.signals()[s].order == Order::Param(index) {
                    self.shifted_signal(s, v, omega, lambda, Factor::DOrder, work, false);
                }
            }
            self.complex_pass(Along::Param(index), omega, w, work)
        });
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
            true => apply_factor(&self.comb, &mut self.op, |k| order_rate(k, omega, q)),
        }
        self.fourier.synthesize(&self.op, out);
    }

    /// Samples (real and imaginary parts) of signal `s` of the perturbation
    /// `e^{λt} v(t)`, without the `e^{λt}`: harmonic `k` of the DOF combination gets
    /// `(λ + ikΩ)^q` on `e^{ikθ}` and `(λ - ikΩ)^q` on `e^{-ikθ}` (principal branch,
    /// as in Hill's operator), or their derivative in Ω or `q`. Into `sv`/`sv_im` if
    /// `first`, else into `suv`/`suv_im`.
    #[allow(clippy::too_many_arguments)]
    fn shifted_signal(
        &mut self,
        s: usize,
        v: &[Complex64],
        omega: f64,
        lambda: Complex64,
        factor: Factor,
        work: &mut BilinearWork,
        first: bool,
    ) {
        let (m, nh) = (self.m, self.n);
        let q = self.orders[s];
        let terms = &self.model.signals()[s].terms;
        let len = 2 * nh + 1;
        for (part, comb) in work.comb.iter_mut().enumerate() {
            comb.fill(0.0);
            for &(d, c) in terms.iter() {
                for (o, x) in comb.iter_mut().zip(&v[d * len..(d + 1) * len]) {
                    *o += c * if part == 0 { x.re } else { x.im };
                }
            }
        }
        let zero = Complex64::new(0.0, 0.0);
        let i1 = Complex64::new(0.0, 1.0);
        // f(z) = z^q or its derivative; `dz` is dz/dΩ of z = λ ± ikΩ.
        let f = |z: Complex64, dz: f64| -> Complex64 {
            let pow = |z: Complex64, e: f64| -> Complex64 {
                if e == 0.0 {
                    Complex64::new(1.0, 0.0)
                } else if z == zero {
                    zero
                } else if e.fract() == 0.0 {
                    z.powi(e as i32)
                } else {
                    z.powf(e)
                }
            };
            match factor {
                Factor::Value => pow(z, q),
                Factor::DOmega if q == 0.0 => zero,
                Factor::DOmega => q * pow(z, q - 1.0) * dz,
                Factor::DOrder if z == zero => zero,
                Factor::DOrder => pow(z, q) * z.ln(),
            }
        };
        let ([cr, ci], [yr, yi]) = (&work.comb, &mut work.image);
        let y0 = f(lambda, 0.0);
        let x0 = Complex64::new(cr[0], ci[0]);
        let z0 = y0 * x0;
        (yr[0], yi[0]) = (z0.re, z0.im);
        for k in 1..=nh {
            let kw = k as f64 * omega;
            let fp = f(lambda + i1 * kw, k as f64);
            let fm = f(lambda - i1 * kw, -(k as f64));
            // Hill's real-basis factors: cos part α x_c - β x_s, sin part β x_c + α x_s
            let (fp, fm) = match factor {
                Factor::DOmega => (fp * i1, fm * i1),
                _ => (fp, fm),
            };
            let (al, be) = ((fp + fm) * 0.5, i1 * (fp - fm) * 0.5);
            let xc = Complex64::new(cr[k], ci[k]);
            let xs = Complex64::new(cr[nh + k], ci[nh + k]);
            let (c, sn) = (al * xc - be * xs, be * xc + al * xs);
            (yr[k], yi[k]) = (c.re, c.im);
            (yr[nh + k], yi[nh + k]) = (sn.re, sn.im);
        }
        let (re, im) = match first {
            true => (&mut work.sv, &mut work.sv_im),
            false => (&mut work.suv, &mut work.suv_im),
        };
        self.fourier.synthesize(yr, &mut re[s * m..(s + 1) * m]);
        self.fourier.synthesize(yi, &mut im[s * m..(s + 1) * m]);
    }

    /// `work.su`: the derivative of every signal of `a` along `u` (the parameter
    /// direction only moves the signals whose order is that parameter).
    fn set_direction(&mut self, u: Along, omega: f64, a: &[f64], work: &mut BilinearWork) {
        let m = self.m;
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
                for s in 0..self.nsig {
                    let f = self.orders[s] / omega;
                    for j in 0..m {
                        work.su[s * m + j] = f * self.sig[s * m + j];
                    }
                }
            }
            Along::Param(index) => {
                work.su.fill(0.0);
                let model = self.model;
                for s in 0..self.nsig {
                    if model.signals()[s].order == Order::Param(index) {
                        self.signal_of(s, a, omega, true, &mut work.su[s * m..(s + 1) * m]);
                    }
                }
            }
        }
    }

    /// `wᴴ D_v D_u R` for a complex `v` (both parts' signals set in `work`).
    fn complex_pass(
        &mut self,
        u: Along,
        omega: f64,
        w: &[Complex64],
        work: &mut BilinearWork,
    ) -> Complex64 {
        // wᴴ (x_re + i x_im) with w = w_re + i w_im
        let mut acc = Complex64::new(0.0, 0.0);
        for imag in [false, true] {
            self.pass(u, omega, imag, work);
            let unit = if imag { Complex64::new(0.0, 1.0) } else { Complex64::new(1.0, 0.0) };
            let s: Complex64 = work.out.iter().zip(w).map(|(&x, y)| y.conj() * x).sum();
            acc += unit * s;
        }
        acc
    }

    /// The projected `D_v D_u R` into `work.out`, `v`'s signals from `sv`/`suv` (or
    /// their imaginary parts), `a`'s from the filled signals and `su`.
    fn pass(&mut self, u: Along, omega: f64, imag: bool, work: &mut BilinearWork) {
        let m = self.m;
        let (d_omega, d_param) = match u {
            Along::Omega => (1.0, None),
            Along::Param(i) => (0.0, Some(i)),
            Along::Coeff(_) => (0.0, None),
        };
        for (i, (h, &p)) in work.h_params.iter_mut().zip(&self.params).enumerate() {
            *h = HyperDual64::new(p, 0.0, if Some(i) == d_param { 1.0 } else { 0.0 }, 0.0);
        }
        let h_omega = HyperDual64::new(omega * self.period, 0.0, d_omega * self.period, 0.0);
        let (sv, suv) = match imag {
            false => (&work.sv, &work.suv),
            true => (&work.sv_im, &work.suv_im),
        };
        for j in 0..m {
            for s in 0..self.nsig {
                let i = s * m + j;
                work.h_sig[s] = HyperDual64::new(self.sig[i], sv[i], work.su[i], suv[i]);
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::QuarterCar;
    use faer::Mat;

    /// `wᵀ J v` at `(a, Ω)` with the model's parameters as set in `bal`.
    fn psi(bal: &mut Balance<'_>, a: &[f64], omega: f64, w: &[f64], v: &[f64]) -> f64 {
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
