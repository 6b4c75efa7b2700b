//! DSL models against time integration from rest (an independent method: Caputo
//! derivatives by product integration, no Fourier series): `max_abs` of every output
//! agrees with harmonic balance. This exercises the mean and the even
//! harmonics (quadratic spring, 2Ω forcing), a fractional order in (1, 2), parametric
//! excitation and coefficients that depend on Ω.
//!
//! Damping is raised above the defaults so that the transient from rest (exponential
//! plus the algebraic Caputo tail) is gone within the simulated time.

use ihbm::corrector::SolveOptions;
use ihbm::models::{BaseExcited, TwoMassChain};
use ihbm::timedomain::{compare, SimOptions};
use ihbm::Model;
use std::f64::consts::TAU;

fn check<M: Model>(model: &M, omega: f64, seconds: f64, tol: f64) {
    let periods = ((seconds * omega / TAU).ceil() as usize).max(20);
    let sim = SimOptions { periods, dt: Some(TAU / omega / 400.0), ..Default::default() };
    let hb = SolveOptions { harmonics: 9, tol: 1e-12, ..Default::default() };
    let row = compare(model, &[omega], &sim, &hb).unwrap().remove(0);
    assert!(row.failure.is_none(), "{}: {:?}", model.name(), row.failure);
    for o in &row.outputs {
        eprintln!(
            "{} Ω = {omega}: {} hb {:.6e} td {:.6e} rel {:.2e}",
            model.name(),
            o.name,
            o.hb_max_abs,
            o.td_max_abs,
            o.rel_diff
        );
        assert!(o.rel_diff < tol, "{} {}: {:.2e}", model.name(), o.name, o.rel_diff);
    }
}

#[test]
fn two_mass_chain_agrees_with_time_integration() {
    let chain = TwoMassChain { c1: 0.3, c2: 0.3, kq: 0.6, F1: 0.3, F2: 0.1, ..Default::default() };
    check(&chain, 0.8, 200.0, 1e-3);
    // the compared state really has a mean and even harmonics
    let opts = SolveOptions { harmonics: 9, ..Default::default() };
    let sol = ihbm::corrector::solve(&chain, 0.8, &opts, None).unwrap();
    let x1 = &sol.outputs(&chain)[0];
    eprintln!("x1: mean {:.3e}, |2nd harmonic| {:.3e}", x1.mean, x1.cos[2].hypot(x1.sin[2]));
    assert!(x1.mean.abs() > 1e-2 * x1.amp1);
    assert!(x1.cos[2].hypot(x1.sin[2]) > 1e-2 * x1.amp1);
}

#[test]
fn base_excited_order_in_1_2_agrees_with_time_integration() {
    let be = BaseExcited { c: 0.3, p: 1.5, h: 0.1, U: 0.3, ..Default::default() };
    check(&be, 0.9, 200.0, 1e-3);
}

/// Parametric excitation: the stiffness modulated at 2Ω (with a cubic spring) is the
/// same time-varying term for the integrator, which knows nothing of harmonics.
#[test]
fn mathieu_duffing_agrees_with_time_integration() {
    let md = crate::parametric::MathieuDuffing { c: 0.3, ..Default::default() };
    check(&md, 1.3, 200.0, 1e-3);
}

/// Coefficients in Ω: the delayed road input, integrated as a function of time.
#[test]
fn delayed_input_agrees_with_time_integration() {
    let d = crate::coefficients::Delayed { c: 0.3, ..Default::default() };
    check(&d, 1.1, 200.0, 1e-3);
}
