//! Parametric excitation in the DSL: `cos(k * omega * t)` multiplying DOF terms. The
//! forced damped Mathieu equation written with `oscillator!` must be the hand-written
//! model of the stability tests (residual, Jacobian and a solved point to 1e-12), and
//! its period-doubling tongue the Ince–Strutt edges of the monodromy matrix integrated
//! by RK4 (to 1e-8). A Mathieu–Duffing oscillator with a 2Ω stiffness modulation checks
//! the alias-free sample count against a brute-force Galerkin projection.

use crate::common::{fd_jacobian, rel_diff, residual, residual_jacobian};
use crate::mathieu_model::{
    assert_period_doubles_on_the_edges, assert_period_doubling_curves_on_the_edges, MODEL,
};
use ihbm::balance::Balance;
use ihbm::corrector::{solve, SolveOptions};
use ihbm::fourier::{coeff_len, sample_count};
use ihbm::Model;

ihbm::oscillator! {
    /// The forced damped Mathieu equation, parameters in the hand-written model's order.
    pub struct MathieuDsl {
        params { m = 1.0, c = 0.05, k = 1.0, eps = 0.4, F = 0.1 }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * (1.0 + eps * cos(omega * t)) * x = F * cos(omega * t);
        }
    }
}

ihbm::oscillator! {
    /// A Mathieu–Duffing oscillator: stiffness modulated at 2Ω, cubic spring, forced at Ω.
    pub struct MathieuDuffing {
        params { c = 0.1, k = 1.0, eps = 0.3, k3 = 0.5, F = 0.2 }
        dofs { x }
        equations {
            D(x, 2) + c * D(x, 1) + k * x + eps * k * cos(2 * omega * t) * x + k3 * x.powi(3)
                = F * cos(omega * t);
        }
    }
}

/// The twin with the hand-written model's parameters.
fn twin() -> MathieuDsl {
    MathieuDsl { m: MODEL.m, c: MODEL.c, k: MODEL.k, eps: MODEL.eps, F: MODEL.f }
}

/// Reproducible coefficients of size ~0.3 (a state, not a solution).
fn state(len: usize) -> Vec<f64> {
    (0..len).map(|i| 0.3 * ((i * 7 % 11) as f64 / 11.0 - 0.5)).collect()
}

#[test]
fn the_shape_counts_the_parametric_harmonic() {
    let m = twin();
    // cos(Ωt)·x has degree 1 in the signals; the modulation adds one harmonic.
    assert_eq!((m.degree(), m.parametric_harmonic(), m.max_forcing_harmonic()), (1, 1, 1));
    assert!(m.affine_signals().len() == 3 && !m.affine_signals()[m.signals().len() - 1]);
    // N = 7: products reach 7 + 1 harmonics, so M >= 2·7 + 1 + 1 = 16; without the
    // extra harmonic 15 samples would fold harmonic 8 onto 7.
    assert_eq!(Balance::new(&m, 7).unwrap().samples(), 16);
    assert_eq!(sample_count(1, 7, 1), 15);
    let md = MathieuDuffing::default();
    assert_eq!((md.degree(), md.parametric_harmonic(), md.max_forcing_harmonic()), (3, 2, 2));
}

#[test]
fn dsl_mathieu_is_the_hand_written_model() {
    let dsl = twin();
    // The hand-written model declares degree 2 (24 samples at N = 7), the twin degree 1
    // with one parametric harmonic (16): both are exact projections.
    for nh in [1, 4, 7] {
        let a = state(coeff_len(nh));
        for omega in [0.7, 2.0, 3.1] {
            let (r1, j1) = residual_jacobian(&MODEL, nh, &a, omega);
            let (r2, j2) = residual_jacobian(&dsl, nh, &a, omega);
            assert!(rel_diff(&r2, &r1, 1e-3) < 1e-12, "N = {nh}, Ω = {omega}: residual");
            assert!(rel_diff(&j2, &j1, 1e-3) < 1e-12, "N = {nh}, Ω = {omega}: Jacobian");
        }
    }
    // A solved point inside the tongue (unstable, unique): the same coefficients.
    let opts = SolveOptions { harmonics: 7, ..Default::default() };
    let s1 = solve(&MODEL, 2.0, &opts, None).unwrap();
    let s2 = solve(&dsl, 2.0, &opts, None).unwrap();
    assert!(rel_diff(&s2.coeffs, &s1.coeffs, 1e-6) < 1e-12);
}

/// The tongue of the twin located by a sweep: its period-doubling points are the edges
/// where the RK4 monodromy matrix has a multiplier −1, to 1e-8.
#[test]
fn dsl_mathieu_period_doubles_on_the_monodromy_edges() {
    assert_period_doubles_on_the_edges(&twin());
}

/// The damped Ince–Strutt diagram: the twin's period-doubling curves in (Ω, ε) lie on
/// the monodromy edges at that ε, to 1e-8.
#[test]
fn dsl_mathieu_tongue_in_two_parameters_is_the_ince_strutt_boundary() {
    assert_period_doubling_curves_on_the_edges(&twin());
}

/// The residual's Fourier coefficients by brute force: the model evaluated on `q`
/// samples of the series (signals x, x', x'' from the coefficients by hand), projected
/// by the trapezoid rule, exact for trigonometric polynomials of degree < q/2.
fn galerkin(model: &MathieuDuffing, nh: usize, a: &[f64], omega: f64, q: usize) -> Vec<f64> {
    let p = model.param_values();
    let mut r = vec![0.0; coeff_len(nh)];
    for j in 0..q {
        let th = 2.0 * std::f64::consts::PI * j as f64 / q as f64;
        let mut s = [a[0], 0.0, 0.0];
        for k in 1..=nh {
            let (kw, (sn, cs)) = (k as f64 * omega, (k as f64 * th).sin_cos());
            let (ak, bk) = (a[k], a[nh + k]);
            s[0] += ak * cs + bk * sn;
            s[1] += kw * (bk * cs - ak * sn);
            s[2] -= kw * kw * (ak * cs + bk * sn);
        }
        // Signal order of the generated model: x'', x', x.
        let order: Vec<f64> = model
            .signals()
            .iter()
            .map(|sig| match sig.order {
                ihbm::model::Order::Int(n) => s[n as usize],
                _ => unreachable!(),
            })
            .collect();
        let mut out = [0.0];
        model.residual(&p, omega, th, &order, &mut out);
        r[0] += out[0] / q as f64;
        for k in 1..=nh {
            let (sn, cs) = (k as f64 * th).sin_cos();
            r[k] += 2.0 * out[0] * cs / q as f64;
            r[nh + k] += 2.0 * out[0] * sn / q as f64;
        }
    }
    r
}

#[test]
fn mathieu_duffing_balance_is_the_exact_galerkin_projection() {
    let m = MathieuDuffing::default();
    // N = 4: x³ cos 2Ωt reaches harmonic 3·4 + 2 = 14; M = 20 >= 4·4 + 2 + 1 (18
    // samples, the count without the parametric harmonic, would alias).
    let nh = 4;
    assert_eq!(Balance::new(&m, nh).unwrap().samples(), 20);
    assert_eq!(sample_count(3, nh, 2), 18);
    let a = state(coeff_len(nh));
    for omega in [0.6, 1.3] {
        let got = residual(&m, nh, &a, omega);
        let exact = galerkin(&m, nh, &a, omega, 256);
        assert!(rel_diff(&got, &exact, 1e-3) < 1e-12, "Ω = {omega}: {got:?} vs {exact:?}");
        // and the dual-number Jacobian is its derivative
        let (_, j) = residual_jacobian(&m, nh, &a, omega);
        let fd = fd_jacobian(&m, nh, &a, omega, 1e-6);
        assert!(rel_diff(&j, &fd, 1e-3) < 1e-7, "Ω = {omega}: Jacobian");
    }
}
