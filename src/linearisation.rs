//! The linearisation of a model at rest: the dynamic stiffness `Z(λ)`, the mass
//! matrix, and the natural frequencies and mode shapes that start a backbone.
//!
//! At `x = 0` every equation is linear in the signals to first order:
//! `r_e ≈ r_e(0) + Σ_s g_{e,s} s`, with `g = ∂r/∂s` from dual numbers. A signal
//! `D^q(Σ_d c_d x_d)` of `x = φ e^{λt}` is `λ^q Σ_d c_d φ_d e^{λt}`, so the linear
//! equations are `Z(λ) φ = 0` with `Z(λ)_{e,d} = Σ_s g_{e,s} λ^{q_s} c_{s,d}`: mass,
//! damping and stiffness, and fractional terms with their exact `(iω)^p`.

use crate::error::{Error, LinearisationFailure, Result};
use crate::linalg::DenseLu;
use crate::model::{DynModel, Model};
use faer::Mat;
use num_complex::Complex64;
use num_dual::Dual64;

/// `∂r/∂s` at rest and the signals' orders and combinations.
pub(crate) struct Linearisation {
    pub ndof: usize,
    /// `g[e * nsig + s]`
    g: Vec<f64>,
    orders: Vec<f64>,
    terms: Vec<Vec<(usize, f64)>>,
}

impl Linearisation {
    /// At rest, for the model's current parameters, at frequency `omega` (which only
    /// matters for coefficients that depend on Ω).
    pub fn at_rest(model: &dyn DynModel, omega: f64) -> Linearisation {
        let ndof = model.dofs().len();
        let signals = model.signals();
        let nsig = signals.len();
        let params: Vec<Dual64> =
            model.param_values().into_iter().map(|p| Dual64::new(p, 0.0)).collect();
        let mut s = vec![Dual64::new(0.0, 0.0); nsig];
        let mut out = vec![Dual64::new(0.0, 0.0); ndof];
        let mut g = vec![0.0; ndof * nsig];
        for j in 0..nsig {
            s.iter_mut()
                .enumerate()
                .for_each(|(k, x)| *x = Dual64::new(0.0, (k == j) as u8 as f64));
            model.residual(&params, Dual64::new(omega, 0.0), 0.0, &s, &mut out);
            for e in 0..ndof {
                g[e * nsig + j] = out[e].eps;
            }
        }
        let pv = model.param_values();
        Linearisation {
            ndof,
            g,
            orders: signals.iter().map(|s| s.order.value(&pv)).collect(),
            terms: signals.iter().map(|s| s.terms.to_vec()).collect(),
        }
    }

    /// `Z(λ)`, row-major `ndof × ndof`.
    pub fn z(&self, lambda: Complex64) -> Vec<Complex64> {
        self.assemble(|q| {
            if q == 0.0 {
                Complex64::new(1.0, 0.0)
            } else if lambda == Complex64::new(0.0, 0.0) {
                Complex64::new(0.0, 0.0)
            } else if q.fract() == 0.0 {
                lambda.powi(q as i32)
            } else {
                lambda.powf(q)
            }
        })
    }

    /// The mass matrix: the coefficients of the second-order signals (row-major).
    pub fn mass(&self) -> Vec<f64> {
        self.assemble(|q| Complex64::new((q == 2.0) as u8 as f64, 0.0))
            .iter()
            .map(|z| z.re)
            .collect()
    }

    fn assemble(&self, factor: impl Fn(f64) -> Complex64) -> Vec<Complex64> {
        let (nd, nsig) = (self.ndof, self.orders.len());
        let mut z = vec![Complex64::new(0.0, 0.0); nd * nd];
        for s in 0..nsig {
            let f = factor(self.orders[s]);
            for e in 0..nd {
                let g = self.g[e * nsig + s];
                if g == 0.0 {
                    continue;
                }
                for &(d, c) in &self.terms[s] {
                    z[e * nd + d] += f * (g * c);
                }
            }
        }
        z
    }
}

/// A mode of the linearised model: its frequency, shape (real, largest entry 1) and
/// the EPMC damping `ξ` that makes it periodic to first order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LinearMode {
    pub omega: f64,
    pub shape: Vec<f64>,
    pub xi: f64,
}

/// Mode `k` (1-based, by increasing frequency) of the linearised model: the
/// eigenproblem `K(ω) φ = ω² M φ` with `K(ω) = Re Z(iω) + ω² M` (the fractional
/// terms' stiffness at the mode's own frequency), iterated to a fixed point, and
/// `ξ = φᵀ Im Z(iω) φ / (ω φᵀ M φ)`. A start, refined by the harmonic balance.
pub(crate) fn linear_mode(model: &dyn DynModel, k: usize) -> Result<LinearMode> {
    let lin0 = Linearisation::at_rest(model, 1.0);
    let nd = lin0.ndof;
    if k == 0 || k > nd {
        return Err(Error::InvalidValue {
            what: "mode".into(),
            value: k.to_string(),
            expected: format!("a mode number from 1 to {nd} (the model's DOFs)"),
        });
    }
    let mass = lin0.mass();
    let mut omega = 1.0;
    let mut lin = lin0;
    let mut shape = vec![0.0; nd];
    for it in 0..60 {
        let z = lin.z(Complex64::new(0.0, omega));
        let kmat =
            Mat::<f64>::from_fn(nd, nd, |i, j| z[i * nd + j].re + omega * omega * mass[i * nd + j]);
        let mmat = Mat::<f64>::from_fn(nd, nd, |i, j| mass[i * nd + j]);
        let mut mus = eigenvalues(&kmat, &mmat)?;
        mus.sort_by(f64::total_cmp);
        if mus.len() < nd {
            return Err(Error::InvalidValue {
                what: "model for a backbone".into(),
                value: format!("{} finite natural frequencies for {nd} DOFs", mus.len()),
                expected: "a mass (second derivative) in every equation's mode".into(),
            });
        }
        let mu = mus[k - 1];
        if !(mu > 0.0 && mu.is_finite()) {
            return Err(Error::InvalidValue {
                what: format!("mode {k}"),
                value: format!("ω² = {mu:e} at rest"),
                expected: "an oscillatory mode (ω² > 0): the model is unstable or static at rest"
                    .into(),
            });
        }
        shape = null_vector(&kmat, &mmat, mu)?;
        let next = mu.sqrt();
        let done = (next - omega).abs() <= 1e-13 * next;
        omega = next;
        if done && it > 0 {
            break;
        }
        lin = Linearisation::at_rest(model, omega);
    }
    let z = lin.z(Complex64::new(0.0, omega));
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..nd {
        for j in 0..nd {
            num += shape[i] * z[i * nd + j].im * shape[j];
            den += shape[i] * mass[i * nd + j] * shape[j];
        }
    }
    Ok(LinearMode { omega, xi: num / (omega * den), shape })
}

/// The real eigenvalues `μ` of `K φ = μ M φ` (infinite and complex ones left out).
fn eigenvalues(k: &Mat<f64>, m: &Mat<f64>) -> Result<Vec<f64>> {
    let nd = k.nrows();
    let pairs: Vec<(Complex64, Complex64)> = if nd == 1 {
        // faer's generalized eigensolver needs n ≥ 2
        vec![(Complex64::new(k[(0, 0)], 0.0), Complex64::new(m[(0, 0)], 0.0))]
    } else {
        let ge = k
            .generalized_eigen(m)
            .map_err(|e| LinearisationFailure::Eigensolve(format!("{e:?}")))?;
        let (sa, sb) = (ge.S_a(), ge.S_b());
        (0..nd).map(|i| (sa[i], sb[i])).collect()
    };
    Ok(pairs
        .into_iter()
        .filter_map(|(x, y)| {
            let mu = x / y;
            (y.norm() > 1e-12 * x.norm().max(1e-300) && mu.im.abs() <= 1e-9 * mu.norm())
                .then_some(mu.re)
        })
        .collect())
}

/// The null vector of `K - μ M` (largest entry 1) by inverse iteration at a shift
/// just off `μ`.
fn null_vector(k: &Mat<f64>, m: &Mat<f64>, mu: f64) -> Result<Vec<f64>> {
    let nd = k.nrows();
    let mut lu = DenseLu::new(nd);
    let shift = mu * (1.0 + 1e-9);
    {
        let mut a = lu.matrix_mut();
        for i in 0..nd {
            for j in 0..nd {
                a[(i, j)] = k[(i, j)] - shift * m[(i, j)];
            }
        }
    }
    if lu.factor().is_nan() {
        return Err(LinearisationFailure::NonFinite.into());
    }
    let mut v: Vec<f64> = (0..nd).map(|i| 1.0 + 0.1 * i as f64).collect();
    for _ in 0..3 {
        lu.solve(&mut v);
        let big = v.iter().fold(0.0f64, |a, &x| if x.abs() > a.abs() { x } else { a });
        if !(big.is_finite() && big != 0.0) {
            return Err(LinearisationFailure::Degenerate.into());
        }
        v.iter_mut().for_each(|x| *x /= big);
    }
    Ok(v)
}
