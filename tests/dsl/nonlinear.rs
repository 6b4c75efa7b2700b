//! Nonlinear checks against classical analytical results.
//!
//! 1. Fractional Duffing with one harmonic: the classical amplitude equation.
//! 2. A quadratic spring under pure cos forcing: the mean (a0) matches second-order
//!    perturbation theory in the small-forcing limit.

use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::FractionalDuffing;
use std::f64::consts::FRAC_PI_2;

/// With x = a cos θ + b sin θ (N = 1, a0 = 0 by symmetry), balancing cos θ and sin θ
/// in m x'' + c x' + k x + k3 x^3 + h D^p x = F cos θ, using cos^3 = (3/4) cos + ...,
/// D^p cos(Ωt) = Ω^p cos(Ωt + pπ/2) and amplitude A = |(a, b)|, gives
/// [(k + h Ω^p cos(pπ/2) - m Ω^2) A + (3/4) k3 A^3]^2 + [(c Ω + h Ω^p sin(pπ/2)) A]^2 = F^2.
/// Checked along frequency sweeps (each solution seeds the next, so the resonant
/// branch is followed up to its fold) at the default parameters, F = 0.5.
#[test]
fn fractional_duffing_single_harmonic_satisfies_amplitude_equation() {
    let opts = SolveOptions { harmonics: 1, tol: 1e-14, ..SolveOptions::default() };
    let (mut worst, mut checked, mut skipped) = (0.0f64, 0, 0);
    for p in [0.1, 0.5, 0.9, 1.5] {
        let m = FractionalDuffing { p, ..FractionalDuffing::default() };
        let mut guess: Option<Vec<f64>> = None;
        for i in 0..=180 {
            let omega = 0.2 + 0.02 * i as f64;
            let sol = match solve(&m, omega, &opts, guess.as_deref()) {
                Ok(s) => s,
                // past a fold the branch ends: restart from the linearized guess
                Err(_) => match solve(&m, omega, &opts, None) {
                    Ok(s) => s,
                    Err(_) => {
                        skipped += 1;
                        guess = None;
                        continue;
                    }
                },
            };
            let (a0, a, b) = (sol.coeffs[0], sol.coeffs[1], sol.coeffs[2]);
            assert!(a0.abs() < 1e-12, "mean {a0} should vanish by symmetry");
            let amp = a.hypot(b);
            let wp = omega.powf(p);
            let re = (m.k + m.h * wp * (p * FRAC_PI_2).cos() - m.m * omega * omega) * amp
                + 0.75 * m.k3 * amp.powi(3);
            let im = (m.c * omega + m.h * wp * (p * FRAC_PI_2).sin()) * amp;
            let err = ((re * re + im * im) - m.F * m.F).abs() / (m.F * m.F);
            worst = worst.max(err);
            checked += 1;
            assert!(err < 1e-10, "p = {p}, Ω = {omega}: amplitude equation off by {err:.2e}");
            guess = Some(sol.coeffs);
        }
    }
    eprintln!(
        "amplitude equation: {checked} solutions checked, worst relative error {worst:.2e}, \
         {skipped} frequencies where Newton found no solution"
    );
    assert!(skipped * 10 < checked, "too few solutions to check: {skipped} skipped");
}

ihbm::oscillator! {
    /// m x'' + c x' + k x + k2 x^2 = F cos(Ωt): an asymmetric (quadratic) spring.
    pub struct QuadraticSpring {
        params {
            /// mass, kg
            m = 1.0,
            /// viscous damping, N s/m
            c = 0.1,
            /// linear stiffness, N/m
            k = 1.0,
            /// quadratic stiffness, N/m^2
            k2 = 0.5,
            /// force amplitude, N
            F = 0.1,
        }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * x + k2 * x.powi(2) = F * cos(omega * t);
        }
    }
}

/// Second-order perturbation: x ≈ x1 + x2 with x1 = Re(X1 e^{iΩt}),
/// X1 = F / (k - mΩ² + icΩ). Then m x2'' + c x2' + k x2 = -k2 x1², and
/// x1² = |X1|²/2 + Re(X1² e^{2iΩt})/2, so the constant part of x2 is
/// a0 ≈ -k2 |X1|² / (2k). The next correction to the mean is O(F⁴) (from x2² and
/// x1 x3), so the relative error of this prediction is O(F) at worst (O(F²) here).
#[test]
fn quadratic_spring_mean_matches_second_order_perturbation() {
    let omega = 0.7;
    let opts = SolveOptions { harmonics: 6, tol: 1e-14, ..SolveOptions::default() };
    let mut errors = Vec::new();
    for f in [0.2, 0.1, 0.05, 0.025, 0.0125] {
        let model = QuadraticSpring { F: f, ..QuadraticSpring::default() };
        let sol = solve(&model, omega, &opts, None).unwrap();
        let x1 = num_complex::Complex64::new(model.k - model.m * omega * omega, model.c * omega);
        let x1 = model.F / x1.norm();
        let predicted = -model.k2 * x1 * x1 / (2.0 * model.k);
        let a0 = sol.coeffs[0];
        assert!(a0 < 0.0 && a0.abs() > 1e-6 * x1 * x1, "mean {a0} should be clearly non-zero");
        // even harmonics are excited too (second harmonic of x1²)
        let n = sol.harmonics;
        assert!(sol.coeffs[2].hypot(sol.coeffs[n + 2]) > 1e-3 * a0.abs());
        errors.push((f, (a0 / predicted - 1.0).abs()));
    }
    eprintln!("F, |a0/prediction - 1|: {errors:?}");
    for w in errors.windows(2) {
        let ((f0, e0), (f1, e1)) = (w[0], w[1]);
        let order = (e0 / e1).ln() / (f0 / f1).ln();
        assert!(order > 0.9, "relative error should fall at least like F: {w:?}, order {order:.2}");
    }
    let (_, last) = errors[errors.len() - 1];
    assert!(last < 1e-3, "ratio at the smallest F off by {last:.2e}");
}
