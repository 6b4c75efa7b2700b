//! The DSL twins against the hand-written models they replaced
//! (`handwritten.rs` beside this file): the same signals, the same residual and the same
//! signal derivatives at every sample, and the same harmonic-balance residual and
//! Jacobian, at random coefficients, Ω and parameters.

use crate::common as dsl_common;

use crate::handwritten;
use dsl_common::{rel_diff, residual_jacobian, scale_params};
use ihbm::model::Model;
use ihbm::models::{Duffing, FractionalDuffing, QuarterCar};
use num_dual::Dual64;
use proptest::prelude::*;

/// Same parameter table, outputs, degree and forcing; signals equal as sets.
/// Returns, for each hand-written signal, the index of the DSL signal with the same
/// terms and order.
fn signal_map<A: Model, B: Model>(dsl: &A, hand: &B) -> Vec<usize> {
    assert_eq!(dsl.name(), hand.name());
    assert_eq!(dsl.dofs(), hand.dofs());
    assert_eq!(dsl.params_info().len(), hand.params_info().len());
    for (a, b) in dsl.params_info().iter().zip(hand.params_info()) {
        assert_eq!((&a.name, a.default, a.domain), (&b.name, b.default, b.domain));
        assert!(!a.doc.is_empty(), "parameter {} has no doc", a.name);
    }
    assert_eq!(dsl.outputs(), hand.outputs());
    assert_eq!(dsl.degree(), hand.degree());
    assert_eq!(dsl.max_forcing_harmonic(), hand.max_forcing_harmonic());
    assert_eq!(dsl.signals().len(), hand.signals().len());
    hand.signals()
        .iter()
        .map(|s| {
            dsl.signals()
                .iter()
                .position(|d| d == s)
                .unwrap_or_else(|| panic!("hand-written signal {s:?} missing in the DSL model"))
        })
        .collect()
}

/// Residual and every ∂r/∂signal, ∂r/∂Ω, ∂r/∂param at one sample agree.
pub(crate) fn sample_check<A: Model, B: Model>(
    dsl: &A,
    hand: &B,
    sig: &[f64],
    omega: f64,
    phase: f64,
) {
    let map = signal_map(dsl, hand);
    let ns = map.len();
    let ndof = dsl.dofs().len();
    let np = dsl.params_info().len();
    let params = dsl.param_values();
    // direction 0..ns: signals, ns: omega, ns+1..: params
    for dir in 0..ns + 1 + np {
        let mut s_hand = vec![Dual64::from(0.0); ns];
        let mut s_dsl = vec![Dual64::from(0.0); ns];
        for (h, &d) in map.iter().enumerate() {
            let eps = if dir == h { 1.0 } else { 0.0 };
            s_hand[h] = Dual64::new(sig[h], eps);
            s_dsl[d] = Dual64::new(sig[h], eps);
        }
        let om = Dual64::new(omega, if dir == ns { 1.0 } else { 0.0 });
        let p: Vec<Dual64> = (0..np)
            .map(|i| Dual64::new(params[i], if dir == ns + 1 + i { 1.0 } else { 0.0 }))
            .collect();
        let mut out_h = vec![Dual64::from(0.0); ndof];
        let mut out_d = vec![Dual64::from(0.0); ndof];
        hand.residual(&p, om, phase, &s_hand, &mut out_h);
        dsl.residual(&p, om, phase, &s_dsl, &mut out_d);
        for e in 0..ndof {
            let (a, b) = (out_d[e], out_h[e]);
            let scale = 1.0 + b.re.abs();
            assert!((a.re - b.re).abs() <= 1e-12 * scale, "r{e}: {} vs {}", a.re, b.re);
            let dscale = 1.0 + b.eps.abs();
            assert!(
                (a.eps - b.eps).abs() <= 1e-12 * dscale,
                "dr{e}/d(direction {dir}): {} vs {}",
                a.eps,
                b.eps
            );
        }
    }
}

/// Harmonic-balance residual and Jacobian agree (relative to their largest entry).
pub(crate) fn harmonic_check<A: Model, B: Model>(
    dsl: &A,
    hand: &B,
    n: usize,
    a: &[f64],
    omega: f64,
) {
    let (r1, j1) = residual_jacobian(dsl, n, a, omega);
    let (r2, j2) = residual_jacobian(hand, n, a, omega);
    let dr = rel_diff(&r1, &r2, 1e-300);
    let dj = rel_diff(&j1, &j2, 1e-300);
    assert!(dr < 1e-12, "residual differs by {dr:.2e} (relative)");
    assert!(dj < 1e-12, "Jacobian differs by {dj:.2e} (relative)");
}

pub(crate) fn coeffs(raw: &[f64], len: usize, scale: f64) -> Vec<f64> {
    (0..len).map(|i| scale * raw[i % raw.len()]).collect()
}

#[test]
fn quarter_car_defaults_and_structure_match() {
    let (d, h) = (QuarterCar::default(), handwritten::QuarterCar::default());
    let _ = signal_map(&d, &h);
    assert_eq!(d.param_values(), h.param_values());
    assert_eq!(Duffing::default().param_values(), handwritten::Duffing::default().param_values());
    assert_eq!(
        FractionalDuffing::default().param_values(),
        handwritten::FractionalDuffing::default().param_values()
    );
    assert_eq!(d.description(), "Quarter-car suspension with a metal-rubber (fractional) element.");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn quarter_car_samples_agree(
        factors in prop::collection::vec(0.5f64..2.0, 9),
        p in 0.0f64..1.0,
        sig in prop::collection::vec(-0.1f64..0.1, 6),
        omega in 0.5f64..100.0,
        phase in 0.0f64..std::f64::consts::TAU,
    ) {
        let mut d = QuarterCar::default();
        scale_params(&mut d, &factors, &["p"]);
        d.p = p;
        let mut h = handwritten::QuarterCar::default();
        for i in 0..9 { h.set_param_value(i, d.param_value(i)); }
        sample_check(&d, &h, &sig, omega, phase);
    }

    #[test]
    fn quarter_car_harmonic_balance_agrees(
        factors in prop::collection::vec(0.5f64..2.0, 9),
        p in 0.0f64..1.0,
        raw in prop::collection::vec(-1.0f64..1.0, 22),
        omega in 0.5f64..100.0,
        n in 1usize..8,
    ) {
        let mut d = QuarterCar::default();
        scale_params(&mut d, &factors, &["p"]);
        d.p = p;
        let mut h = handwritten::QuarterCar::default();
        for i in 0..9 { h.set_param_value(i, d.param_value(i)); }
        let a = coeffs(&raw, 2 * (2 * n + 1), 0.05);
        harmonic_check(&d, &h, n, &a, omega);
    }

    #[test]
    fn duffings_agree(
        factors in prop::collection::vec(0.5f64..2.0, 7),
        p in 0.0f64..2.0,
        raw in prop::collection::vec(-1.0f64..1.0, 11),
        sig in prop::collection::vec(-2.0f64..2.0, 4),
        omega in 0.1f64..5.0,
        phase in 0.0f64..std::f64::consts::TAU,
        n in 1usize..8,
    ) {
        let mut d = Duffing::default();
        scale_params(&mut d, &factors, &[]);
        let mut h = handwritten::Duffing::default();
        for i in 0..5 { h.set_param_value(i, d.param_value(i)); }
        sample_check(&d, &h, &sig[..3], omega, phase);
        let a = coeffs(&raw, 2 * n + 1, 1.0);
        harmonic_check(&d, &h, n, &a, omega);

        let mut d = FractionalDuffing::default();
        scale_params(&mut d, &factors, &["p"]);
        d.p = p;
        let mut h = handwritten::FractionalDuffing::default();
        for i in 0..7 { h.set_param_value(i, d.param_value(i)); }
        sample_check(&d, &h, &sig, omega, phase);
        harmonic_check(&d, &h, n, &a, omega);
    }
}
