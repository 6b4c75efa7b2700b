//! Tracking the Floquet exponents along a curve ([`Hill::track`]) against the full
//! analysis ([`Hill::analyse`]) at every point: the same verdict and the same largest
//! real part, on curves with folds, a torus bubble, period doubling, fractional terms.
//! The full analysis is the reference here; it is itself checked against closed forms,
//! RK4 monodromy and time integration in the other stability tests.

use crate::common as stability_common;

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{Duffing, FractionalDuffing, QuarterCar};
use ihbm::results::Curve;
use ihbm::stability::TrackCounts;
use stability_common::compare;

/// The quarter car's curve 1 → 100 rad/s at N = 5 with `k3`, `F`; `check` on the
/// curve, then tracking vs the full analysis at every point.
fn car_curve(k3: f64, f: f64, what: &str, check: impl Fn(&Curve)) -> TrackCounts {
    let model = QuarterCar { k3, F: f, ..Default::default() };
    let c = sweep(&model, 1.0, 100.0, &SweepOptions::default()).unwrap();
    check(&c);
    let (k, _) = compare(&model, &c, 5);
    // The sweep's own statistics count what this replay of its tracking counts.
    assert_eq!(c.stats.stability_full, k.full, "{what}: {:?}", c.stats);
    eprintln!("quarter car {what}: {} points, {k:?}", c.points.len());
    k
}

#[test]
fn quarter_car_default_curve() {
    let d = QuarterCar::default();
    let k = car_curve(d.k3, d.F, "default", |c| {
        assert!(c.points.iter().all(|p| p.stability.is_stable()));
        assert_eq!(c.stats.stability_unrefined, 0);
    });
    // Nearly linear at every point: once the first analysis has the centred copies, no
    // point needs another (before the refinement re-centred its roots, the first
    // analysis kept off-centre copies below 6.3 rad/s and 13 points fell back).
    assert_eq!(k.full, 1, "{k:?}");
}

#[test]
fn quarter_car_with_folds() {
    car_curve(5e6, 0.03, "folds", |c| {
        let folds: Vec<f64> = c.folds.iter().map(|f| f.omega).collect();
        assert_eq!(folds.len(), 2);
        assert!(folds.iter().any(|w| (w - 13.01).abs() < 0.01), "{folds:?}");
        assert!(folds.iter().any(|w| (w - 15.51).abs() < 0.01), "{folds:?}");
        assert!(c.points.iter().any(|p| !p.stability.is_stable()), "the middle branch is unstable");
    });
}

#[test]
fn quarter_car_torus_bubble() {
    car_curve(5e6, 0.1, "torus", |c| {
        let inside = c.points.iter().filter(|p| (58.0..61.5).contains(&p.omega));
        assert!(inside.clone().count() > 0 && inside.clone().all(|p| !p.stability.is_stable()));
    });
}

#[test]
fn duffing_hardening_n1_and_n5() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    for n in [1, 5] {
        let o = SweepOptions { harmonics: n, ..Default::default() };
        let c = sweep(&model, 0.5, 2.5, &o).unwrap();
        assert_eq!(c.folds.len(), 2);
        let (k, _) = compare(&model, &c, n);
        eprintln!("duffing N = {n}: {} points, {k:?}", c.points.len());
    }
}

#[test]
fn fractional_duffing() {
    let model = FractionalDuffing { m: 1.0, c: 0.02, k: 1.0, k3: 1.0, h: 0.05, p: 0.5, F: 0.2 };
    for n in [1, 3] {
        let o = SweepOptions { harmonics: n, ..Default::default() };
        let c = sweep(&model, 0.5, 2.5, &o).unwrap();
        let (k, _) = compare(&model, &c, n);
        eprintln!(
            "fractional duffing N = {n}: {} points, {} folds, {k:?}",
            c.points.len(),
            c.folds.len()
        );
    }
}
