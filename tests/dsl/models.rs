//! Every reference model written with `oscillator!`: the dual-number Jacobian equals
//! central finite differences, and the linearized model's harmonic balance solution
//! equals its closed-form complex frequency response (built by hand below, per model).

use crate::common as dsl_common;

use dsl_common::{fd_jacobian, rel_diff, residual, residual_jacobian, scale_params};
use ihbm::balance::Balance;
use ihbm::corrector::{solve, SolveOptions};
use ihbm::model::{Model, OutputKind};
use ihbm::models::{BaseExcited, Duffing, FractionalDuffing, QuarterCar, TwoMassChain};
use num_complex::Complex64;
use proptest::prelude::*;

const I: Complex64 = Complex64::new(0.0, 1.0);

/// `(iw)^p`, principal branch.
fn ipow(w: f64, p: f64) -> Complex64 {
    Complex64::from_polar(w.powf(p), p * std::f64::consts::FRAC_PI_2)
}

fn fd_check<M: Model>(model: &M, n: usize, a: &[f64], omega: f64, h: f64) {
    let (_, j) = residual_jacobian(model, n, a, omega);
    let fd = fd_jacobian(model, n, a, omega, h);
    let d = rel_diff(&j, &fd, 1e-300);
    assert!(d < 1e-7, "{}: Jacobian vs central differences {d:.2e}", model.name());
}

fn coeffs(raw: &[f64], len: usize, scale: f64) -> Vec<f64> {
    (0..len).map(|i| scale * raw[i % raw.len()]).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn jacobians_equal_finite_differences(
        factors in prop::collection::vec(0.5f64..2.0, 14),
        p01 in 0.05f64..0.95,
        p12 in 1.05f64..1.95,
        raw in prop::collection::vec(-1.0f64..1.0, 30),
        omega in 0.3f64..3.0,
        n in 1usize..6,
    ) {
        let l = 2 * n + 1;
        let mut qc = QuarterCar::default();
        scale_params(&mut qc, &factors, &["p"]);
        qc.p = p01;
        fd_check(&qc, n, &coeffs(&raw, 2 * l, 0.05), 10.0 * omega, 1e-7);

        let mut d = Duffing::default();
        scale_params(&mut d, &factors, &[]);
        fd_check(&d, n, &coeffs(&raw, l, 1.0), omega, 1e-6);

        let mut fdm = FractionalDuffing::default();
        scale_params(&mut fdm, &factors, &["p"]);
        fdm.p = p01;
        fd_check(&fdm, n, &coeffs(&raw, l, 1.0), omega, 1e-6);

        let mut ch = TwoMassChain::default();
        scale_params(&mut ch, &factors, &["p"]);
        ch.p = p01;
        // forced at 2Ω: one harmonic is refused (it would drop that forcing)
        let nc = n.max(2);
        fd_check(&ch, nc, &coeffs(&raw, 2 * (2 * nc + 1), 1.0), omega, 1e-6);

        let mut be = BaseExcited::default();
        scale_params(&mut be, &factors, &["p"]);
        be.p = p12;
        fd_check(&be, n, &coeffs(&raw, l, 1.0), omega, 1e-6);
    }

    /// `omega` used as a coefficient (m U Ω² of the base-excited model) is seen by the
    /// dual numbers: ∂R/∂Ω equals a central difference in Ω.
    #[test]
    fn base_excited_d_omega_equals_finite_difference(
        raw in prop::collection::vec(-1.0f64..1.0, 11),
        omega in 0.3f64..3.0,
        p in 1.05f64..1.95,
    ) {
        let be = BaseExcited { p, ..BaseExcited::default() };
        let n = 5;
        let a = coeffs(&raw, 11, 0.3);
        let mut hb = Balance::new(&be, n).unwrap();
        let mut d = vec![0.0; 11];
        hb.d_omega(&a, omega, &mut d);
        let h = 1e-6;
        let rp = residual(&be, n, &a, omega + h);
        let rm = residual(&be, n, &a, omega - h);
        let fd: Vec<f64> = rp.iter().zip(&rm).map(|(p, m)| (p - m) / (2.0 * h)).collect();
        let e = rel_diff(&d, &fd, 1e-300);
        prop_assert!(e < 1e-7, "dR/dΩ vs central difference: {e:.2e}");
    }
}

/// Per harmonic `k`, the complex amplitude of each DOF: `X_k` with
/// `x = Σ Re(X_k e^{ikθ})`, so `a_k = Re X_k`, `b_k = -Im X_k`.
fn check_linear<M: Model>(
    model: &M,
    omega: f64,
    expected: &[(usize, usize, Complex64)], // (dof, k, X)
) -> f64 {
    let n = 3;
    let l = 2 * n + 1;
    let opts = SolveOptions { harmonics: n, tol: 1e-13, ..SolveOptions::default() };
    let sol = solve(model, omega, &opts, None).unwrap();
    let scale = expected.iter().fold(0.0f64, |s, e| s.max(e.2.norm()));
    // Closed-form coefficients: every other coefficient must vanish.
    let mut a = vec![0.0; model.dofs().len() * l];
    for &(d, k, x) in expected {
        a[d * l + k] = x.re;
        a[d * l + n + k] = -x.im;
    }
    let err = rel_diff(&sol.coeffs, &a, scale);
    assert!(err < 1e-10, "{} at Ω = {omega}: HB vs closed form {err:.2e}", model.name());
    err
}

#[test]
fn linearized_models_match_closed_form_frequency_responses() {
    let mut worst = 0.0f64;
    for omega in [0.3, 0.8, 1.0, 1.3, 2.5, 7.0] {
        for p in [0.2, 0.5, 0.9] {
            // Quarter car (closed form): G = k1 + icΩ + h(iΩ)^p,
            // Δ = m1 m2 Ω^4 - [kt m1 + (m1 + m2) G] Ω^2 + kt G,
            // Z1 = kt G F / Δ, Y = kt m1 Ω^2 F / Δ, Z2 = Z1 - Y.
            let w = 8.0 * omega;
            let car = QuarterCar { k3: 0.0, p, ..QuarterCar::default() };
            let g = car.k1 + I * car.c * w + car.h * ipow(w, p);
            let w2 = w * w;
            let delta = car.m1 * car.m2 * w2 * w2 - (car.kt * car.m1 + (car.m1 + car.m2) * g) * w2
                + car.kt * g;
            let z1 = car.kt * g * car.F / delta;
            let y = car.kt * car.m1 * w2 * car.F / delta;
            worst = worst.max(check_linear(&car, w, &[(0, 1, z1), (1, 1, z1 - y)]));

            // Duffing, k3 = 0: X = F / (k - mΩ² + icΩ).
            let d = Duffing { k3: 0.0, ..Duffing::default() };
            let x = d.F / (d.k - d.m * omega * omega + I * d.c * omega);
            worst = worst.max(check_linear(&d, omega, &[(0, 1, x)]));

            // Fractional Duffing, k3 = 0: X = F / (k - mΩ² + icΩ + h(iΩ)^p).
            let f = FractionalDuffing { k3: 0.0, p, ..FractionalDuffing::default() };
            let x = f.F / (f.k - f.m * omega * omega + I * f.c * omega + f.h * ipow(omega, p));
            worst = worst.max(check_linear(&f, omega, &[(0, 1, x)]));

            // Base-excited, k3 = 0, order p + 1 in (1, 2): Y = m U Ω² / (k - mΩ² + icΩ + h(iΩ)^q).
            let q = 1.0 + p;
            let b = BaseExcited { k3: 0.0, p: q, ..BaseExcited::default() };
            let x = b.m * b.U * omega * omega
                / (b.k - b.m * omega * omega + I * b.c * omega + b.h * ipow(omega, q));
            worst = worst.max(check_linear(&b, omega, &[(0, 1, x)]));

            // Two-mass chain, kq = k3 = cc = 0: per harmonic w = kΩ,
            // [k1 + kc + hc(iw)^p - m1 w² + i c1 w, -(kc + hc(iw)^p);
            //  -(kc + hc(iw)^p), k2 + kc + hc(iw)^p - m2 w² + i c2 w] X = [f_k, 0],
            // f_1 = F1 (cos), f_2 = -i F2 (sin θ = Re(-i e^{iθ})).
            let ch = TwoMassChain { kq: 0.0, k3: 0.0, cc: 0.0, p, ..TwoMassChain::default() };
            let mut expected = Vec::new();
            for (k, f) in [(1usize, Complex64::new(ch.F1, 0.0)), (2, -I * ch.F2)] {
                let w = k as f64 * omega;
                let coup = ch.kc + ch.hc * ipow(w, p);
                let h11 = ch.k1 - ch.m1 * w * w + I * ch.c1 * w + coup;
                let h22 = ch.k2 - ch.m2 * w * w + I * ch.c2 * w + coup;
                let det = h11 * h22 - coup * coup;
                expected.push((0, k, f * h22 / det));
                expected.push((1, k, f * coup / det));
            }
            worst = worst.max(check_linear(&ch, omega, &expected));
        }
    }
    eprintln!("worst relative error of linearized HB vs closed form: {worst:.2e}");
}

#[test]
fn generated_metadata_is_what_was_declared() {
    let ch = TwoMassChain::default();
    assert_eq!(ch.name(), "two-mass-chain");
    assert_eq!(ch.degree(), 3);
    assert_eq!(ch.max_forcing_harmonic(), 2);
    assert_eq!(ch.dofs(), &["x1", "x2"]);
    let names: Vec<&str> = ch.outputs().iter().map(|o| &*o.name).collect();
    assert_eq!(names, ["x1", "x2", "rel"]);
    assert_eq!(ch.outputs()[2].kind, OutputKind::Dofs([(0, 1.0), (1, -1.0)].to_vec().into()));
    // D(rel, p) is one signal on x1 - x2 of order Param(p)
    let p = ch.param_index("p").unwrap();
    assert!(ch
        .signals()
        .iter()
        .any(|s| *s.terms == [(0, 1.0), (1, -1.0)] && s.order == ihbm::model::Order::Param(p)));
    assert_eq!(ch.params_info()[3].doc, "cubic damping of mass 1 to ground, N s^3/m^3");

    let qc = QuarterCar::default();
    assert_eq!(qc.name(), "quarter-car");
    assert_eq!(qc.equations()[0], "m1 * D(z1, 2) + fs = 0.0");
    assert_eq!(qc.equations()[2], "where y = z1 - z2");
    assert_eq!(Duffing::default().name(), "duffing");
    assert_eq!(FractionalDuffing::default().name(), "fractional-duffing");
    assert_eq!(BaseExcited::default().name(), "base-excited");

    let mut be = BaseExcited::default();
    be.set_param("U", 0.2).unwrap();
    assert_eq!(be.U, 0.2);
    assert!(be.set_param("omega", 1.0).is_err());
}
