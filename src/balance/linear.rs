//! The linearised response at one frequency: the start of every solve.

use super::{check_inputs, Balance};
use crate::error::{Error, Result};
use crate::fourier::{coeff_len, spectral_factor};
use crate::model::{DynModel, Model};
use num_complex::Complex64;

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
pub fn linearized_guess(model: &dyn DynModel, omega: f64, harmonics: usize) -> Result<Vec<f64>> {
    check_inputs(harmonics, omega)?;
    let mut hb = Balance::new(model, harmonics)?;
    Ok(linearized_on(&mut hb, omega)?.0)
}

/// [`linearized_guess`] on an existing [`Balance`]; also returns `R(0)`, the residual
/// at rest (minus the forcing), which the corrector uses as its residual scale.
pub(crate) fn linearized_on(hb: &mut Balance<'_>, omega: f64) -> Result<(Vec<f64>, Vec<f64>)> {
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
                for &(d, c) in sig.terms.iter() {
                    t[e * ndof + d] += lam * (gbar[e * nsig + s] * c);
                }
            }
            x[e] = if k == 0 {
                Complex64::new(-r0[e * l], 0.0)
            } else {
                -Complex64::new(r0[e * l + k], -r0[e * l + n + k])
            };
        }
        complex_solve(&mut t, &mut x, ndof).map_err(|unknown| Error::SingularJacobian {
            omega,
            detail: format!(
                "the model linearized about zero is singular at harmonic {k} (zero pivot for \
                 unknown {unknown}); give an initial guess instead"
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

/// Solve a small dense complex system (row-major `a`, right-hand side `b` overwritten
/// by the solution). A zero pivot with a zero right-hand side gives the zero solution
/// for that unknown; with any other, the unknown is the error.
fn complex_solve(
    a: &mut [Complex64],
    b: &mut [Complex64],
    n: usize,
) -> std::result::Result<(), usize> {
    let scale = a.iter().fold(0.0f64, |s, z| s.max(z.norm()));
    let tiny = 1e-300 + 1e-14 * scale;
    let mut piv = vec![0; n];
    crate::linalg::complex_lu_factor(a, n, &mut piv, tiny);
    crate::linalg::complex_lu_solve_consistent(a, n, &piv, tiny, b)
}
