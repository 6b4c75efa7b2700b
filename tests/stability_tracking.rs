//! Tracking the Floquet exponents along a curve ([`Hill::track`]) against the full
//! analysis ([`Hill::analyse`]) at every point: the same verdict and the same largest
//! real part, on curves with folds, a torus bubble, period doubling, fractional terms.
//! The full analysis is the reference here; it is itself checked against closed forms,
//! RK4 monodromy and time integration in the other stability tests.

mod stability_common;

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{Duffing, FractionalDuffing, QuarterCar};
use stability_common::compare;

fn car(k3: f64, f: f64) -> QuarterCar {
    QuarterCar { k3, F: f, ..Default::default() }
}

#[test]
fn quarter_car_default_curve() {
    let model = QuarterCar::default();
    let c = sweep(&model, 1.0, 100.0, &SweepOptions::default()).unwrap();
    let k = compare(&model, &c, 5);
    eprintln!("quarter car default: {} points, {k:?}", c.points.len());
}

#[test]
fn quarter_car_with_folds() {
    let model = car(5e6, 0.03);
    let c = sweep(&model, 1.0, 100.0, &SweepOptions::default()).unwrap();
    assert_eq!(c.folds.len(), 2);
    assert!(c.points.iter().any(|p| !p.stable), "the middle branch is unstable");
    let k = compare(&model, &c, 5);
    eprintln!("quarter car folds: {} points, {k:?}", c.points.len());
}

#[test]
fn quarter_car_torus_bubble() {
    let model = car(5e6, 0.1);
    let c = sweep(&model, 1.0, 100.0, &SweepOptions::default()).unwrap();
    let inside = c.points.iter().filter(|p| (58.0..61.5).contains(&p.omega));
    assert!(inside.clone().count() > 0 && inside.clone().all(|p| !p.stable));
    let k = compare(&model, &c, 5);
    eprintln!("quarter car torus: {} points, {k:?}", c.points.len());
}

#[test]
fn duffing_hardening_n1_and_n5() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    for n in [1, 5] {
        let o = SweepOptions { harmonics: n, ..Default::default() };
        let c = sweep(&model, 0.5, 2.5, &o).unwrap();
        assert_eq!(c.folds.len(), 2);
        let k = compare(&model, &c, n);
        eprintln!("duffing N = {n}: {} points, {k:?}", c.points.len());
    }
}

#[test]
fn fractional_duffing() {
    let model = FractionalDuffing { m: 1.0, c: 0.02, k: 1.0, k3: 1.0, h: 0.05, p: 0.5, F: 0.2 };
    for n in [1, 3] {
        let o = SweepOptions { harmonics: n, ..Default::default() };
        let c = sweep(&model, 0.5, 2.5, &o).unwrap();
        let k = compare(&model, &c, n);
        eprintln!(
            "fractional duffing N = {n}: {} points, {} folds, {k:?}",
            c.points.len(),
            c.folds.len()
        );
    }
}
