//! A stability change without a fold: the forced damped Mathieu equation
//! `m x'' + c x' + k (1 + ε cos Ωt) x = F cos Ωt` is linear, so its periodic response
//! is unique and its curve never folds, yet inside the principal parametric tongue
//! (Ω ≈ 2√(k/m)) a Floquet multiplier leaves the unit circle through -1. Hill's method
//! must report that as period doubling, where the monodromy matrix (integrated here
//! independently with RK4) has a multiplier -1.

use crate::common as stability_common;

use crate::mathieu_model::{
    assert_period_doubles_on_the_edges, assert_period_doubling_curves_on_the_edges, monodromy_at,
    tongue, MODEL,
};
use ihbm::balance::Balance;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::results::BifurcationKind;
use ihbm::stability::{Hill, StabilityOptions};

/// Monodromy matrix of the homogeneous equation by RK4: (trace, determinant).
fn monodromy(w: f64) -> (f64, f64) {
    monodromy_at(w, MODEL.eps)
}

/// Largest Floquet exponent real part from the monodromy multipliers.
fn growth(w: f64) -> f64 {
    let (tr, det) = monodromy(w);
    let disc = tr * tr - 4.0 * det;
    let mu = if disc >= 0.0 { (tr.abs() + disc.sqrt()) / 2.0 } else { det.sqrt() };
    mu.ln() * w / (2.0 * std::f64::consts::PI)
}

#[test]
fn mathieu_tongue_is_period_doubling_without_fold() {
    let edges = tongue();
    assert_eq!(edges.len(), 2, "test setup: one tongue in range, got {edges:?}");
    let opts = SweepOptions { harmonics: 6, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
    assert!(curve.folds.is_empty());
    let pd: Vec<f64> = curve
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::PeriodDoubling)
        .map(|b| b.omega)
        .collect();
    assert_eq!(curve.all_bifurcations().len(), 2, "{:?}", curve.all_bifurcations());
    assert_eq!(pd.len(), 2, "{:?}", curve.all_bifurcations());
    assert!(curve.all_bifurcations().iter().all(|b| b.located));
    for (g, e) in pd.iter().zip(&edges) {
        assert!((g - e).abs() < 1e-6 * e, "period doubling at {g}, monodromy says {e}");
    }
    for p in &curve.points {
        let inside = p.omega > edges[0] && p.omega < edges[1];
        let margin = edges.iter().map(|e| (p.omega - e).abs()).fold(f64::INFINITY, f64::min);
        if margin > 1e-6 {
            assert_eq!(p.stability.is_stable(), !inside, "Ω = {}", p.omega);
        }
    }
}

/// The period-doubling points are the roots of max Re λ, not of the verdict's
/// tolerance: located to 1e-8 against the monodromy edges once N resolves them.
#[test]
fn period_doubling_is_located_to_1e_8_with_enough_harmonics() {
    assert_period_doubles_on_the_edges(&MODEL);
}

#[test]
fn hill_exponents_match_monodromy_multipliers() {
    let opts = SweepOptions { harmonics: 6, stability: None, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
    let mut bal = Balance::new(&MODEL, 6).unwrap();
    let mut hill = Hill::new(&MODEL, 6).unwrap();
    for p in &curve.points {
        let f = hill.analyse(&mut bal, &p.coeffs, p.omega, &StabilityOptions::default()).unwrap();
        let g = growth(p.omega);
        assert!(
            (f.max_real - g).abs() < 1e-7,
            "Ω = {}: Hill {} vs monodromy {g}",
            p.omega,
            f.max_real
        );
        assert_eq!(f.exponents.len(), 2);
    }
}

#[test]
fn tracking_agrees_with_the_full_analysis_through_the_tongue() {
    let opts = SweepOptions { harmonics: 6, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
    let (k, _) = stability_common::compare(&MODEL, &curve, 6);
    eprintln!("mathieu: {} points, {k:?}", curve.points.len());
}

/// The period-doubling boundary continued in (Ω, ε) is the tongue's edge: at points
/// of each curve, the monodromy matrix at that ε has a multiplier −1 at that Ω (the
/// edge found by bisection on `1 + tr + det`), to 1e-8.
#[test]
fn period_doubling_curves_are_the_tongue_edges_of_the_monodromy() {
    assert_period_doubling_curves_on_the_edges(&MODEL);
}
