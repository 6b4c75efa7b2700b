//! Harmonic balance against time integration on the quarter car (Table 1 with a
//! strongly nonlinear cubic spring), the paper's Fig. 6 check made quantitative.
//!
//! Claim: with the BDF2 rule at dt = T/400 and at least 20 s simulated, `max_abs`
//! agrees with harmonic balance (N = 9, converged in N) to 1e-4 relative for every
//! output. Evidence that the remaining gap is the time step's and not the algebraic
//! Caputo transient from rest: doubling the simulated time leaves it unchanged, and
//! halving dt divides it by about 4 (second order).

use ihbm::corrector::SolveOptions;
use ihbm::models::{HalfCar, QuarterCar};
use ihbm::timedomain::{compare, CompareRow, SimOptions};
use ihbm::Model;
use std::f64::consts::TAU;

fn rows<M: Model>(model: &M, omega: f64, periods: usize, dt_div: f64) -> CompareRow {
    let sim = SimOptions { periods, dt: Some(TAU / omega / dt_div), ..Default::default() };
    let hb = SolveOptions { harmonics: 9, tol: 1e-12, ..Default::default() };
    let mut r = compare(model, &[omega], &sim, &hb).unwrap();
    let row = r.remove(0);
    assert!(row.failure.is_none(), "{:?}", row.failure);
    row
}

fn check<M: Model>(model: &M, omega: f64) {
    let periods = (20.0 * omega / TAU).ceil().max(20.0) as usize;
    let base = rows(model, omega, periods, 400.0);
    let long = rows(model, omega, 2 * periods, 400.0);
    let fine = rows(model, omega, periods, 800.0);
    for ((b, l), f) in base.outputs.iter().zip(&long.outputs).zip(&fine.outputs) {
        println!(
            "{} Ω {omega} {}: hb {:.9e} td {:.9e} rel {:.2e} (2x time {:.2e}, dt/2 {:.2e}) drift {:.1e}",
            model.name(), b.name, b.hb_max_abs, b.td_max_abs, b.rel_diff, l.rel_diff, f.rel_diff, b.td_drift
        );
        assert!(b.rel_diff < 1e-4, "{}: {:e}", b.name, b.rel_diff);
        // Not the transient: twice the simulated time moves max_abs by less than 1e-6
        // relative, 1 % of the claim (measured: at most ~1e-7, on the small z1 at 60
        // rad/s, where the tail from rest decays roughly like t^-1.5).
        let moved = (l.td_max_abs - b.td_max_abs).abs() / b.hb_max_abs;
        assert!(moved < 1e-6, "{}: {moved:e}", b.name);
        // The time step: second order where the gap is above the HB/refinement floor.
        if b.rel_diff > 1e-6 {
            let ratio = b.rel_diff / f.rel_diff;
            assert!((3.0..5.0).contains(&ratio), "{}: dt halving ratio {ratio}", b.name);
        }
    }
}

#[test]
fn strong_cubic_quarter_car_low_frequency() {
    for f in [0.01, 0.02] {
        check(&QuarterCar { k3: 5e6, F: f, ..Default::default() }, 8.0);
    }
}

#[test]
fn strong_cubic_quarter_car_high_frequency() {
    for f in [0.01, 0.02] {
        check(&QuarterCar { k3: 5e6, F: f, ..Default::default() }, 60.0);
    }
}

/// The half car on a delayed road: the rear wheel's input `F cos(Ωt − Ωτ)` integrated
/// in time (its coefficients cos Ωτ, sin Ωτ evaluated like any other), strong cubic
/// springs, at the body modes and between the wheelbase filter's zeros.
#[test]
fn strong_cubic_half_car_on_a_delayed_road() {
    let car = HalfCar { k3f: 5e6, k3r: 5e6, F: 0.02, ..Default::default() };
    for omega in [8.0, 30.0] {
        check(&car, omega);
    }
}
