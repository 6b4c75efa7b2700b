//! Torus (Neimark–Sacker) curves of the quarter car at k3 = 5e6 N/m³: the bubble of
//! quasi-periodic response between Ω ≈ 57.3 and 62.1 rad/s at F = 0.1 m, followed in
//! (Ω, F), against ordinary sweeps and full Hill analyses (different methods: the
//! sweeps locate each torus point as a zero of the largest real part of the
//! exponents, the curves solve for a singular bordered `T(iω)`).

use ihbm::balance::Balance;
use ihbm::bifurcation::{fold_curves, Boundary, End, FoldCurveOptions, FoldCurves};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::QuarterCar;
use ihbm::results::BifurcationKind;
use ihbm::stability::{Hill, StabilityOptions};
use ihbm::Model;

const HARMONICS: usize = 5;
const BAND: (f64, f64) = (50.0, 70.0);

fn model() -> QuarterCar {
    let mut m = QuarterCar::default();
    m.set_param("k3", 5e6).unwrap();
    m
}

fn bubble() -> (QuarterCar, FoldCurves) {
    let model = model();
    let mut opts =
        FoldCurveOptions { boundary: Boundary::Torus, omega: BAND, ..Default::default() };
    opts.sweep.harmonics = HARMONICS;
    let f = model.param_index("F").unwrap();
    let res = fold_curves(&model, f, 0.1, 0.05, &opts).unwrap();
    (model, res)
}

/// The torus points of an ordinary sweep at road amplitude `f`.
fn sweep_torus(model: &QuarterCar, f: f64) -> Vec<f64> {
    let mut m = model.clone();
    m.set_param("F", f).unwrap();
    let so = SweepOptions {
        harmonics: HARMONICS,
        stability: Some(StabilityOptions::default()),
        ..SweepOptions::default()
    };
    let curve = sweep(&m, BAND.0, BAND.1, &so).unwrap();
    curve
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::Torus && b.located)
        .map(|b| b.omega)
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// One curve from the lower torus point turns at the least F and comes back to the
/// upper one: the bubble closes. Its start and end agree with the sweep's located
/// torus points to 1e-8 (the location goal, by two methods).
#[test]
fn the_torus_bubble_closes_at_a_least_road_amplitude() {
    let (model, res) = bubble();
    assert_eq!(res.start_folds.0, 2, "{:?}", res.curves);
    assert_eq!(res.curves.len(), 1, "the second start is the first curve's end");
    let c = &res.curves[0];
    assert_eq!(c.ended, End::ReachedEnd);
    assert_eq!(res.cusps.len(), 1);
    let turn = &res.cusps[0];
    assert!(turn.located);
    let swept = sweep_torus(&model, 0.1);
    assert_eq!(swept.len(), 2, "{swept:?}");
    let (first, last) = (&c.points[0], c.points.last().unwrap());
    assert!(rel(first.omega, swept[0]) < 1e-8, "{} vs {}", first.omega, swept[0]);
    assert!(rel(last.omega, swept[1]) < 1e-8, "{} vs {}", last.omega, swept[1]);
    // just above the least F the sweep finds the pair, just below nothing
    assert_eq!(sweep_torus(&model, turn.value * (1.0 + 1e-3)).len(), 2);
    assert_eq!(sweep_torus(&model, turn.value * (1.0 - 1e-3)).len(), 0);
}

/// Points inside the curve are torus points of ordinary sweeps at their F, and a
/// full Hill analysis there has the pair `±iω` on the imaginary axis.
#[test]
fn torus_curve_points_are_torus_points_of_sweeps_and_of_hills_method() {
    let (model, res) = bubble();
    let c = &res.curves[0];
    let mid = c.points.len() / 2;
    for p in [&c.points[mid / 2], &c.points[(3 * mid) / 2]] {
        let swept = sweep_torus(&model, p.value);
        let nearest = swept.iter().map(|&w| rel(w, p.omega)).fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-7,
            "F = {}: no sweep torus point near Ω = {} ({nearest:e})",
            p.value,
            p.omega
        );
        let mut m = model.clone();
        m.set_param("F", p.value).unwrap();
        let mut bal = Balance::new(&m, HARMONICS).unwrap();
        let mut hill = Hill::new(&m, HARMONICS).unwrap();
        let fl = hill.analyse(&mut bal, &p.coeffs, p.omega, &StabilityOptions::default()).unwrap();
        let w = p.torus_frequency.unwrap();
        let crit = fl
            .exponents
            .iter()
            .min_by(|a, b| (a.im.abs() - w).abs().total_cmp(&(b.im.abs() - w).abs()))
            .unwrap();
        assert!(crit.re.abs() < 1e-8 * p.omega, "Re λ = {:e} at Ω = {}", crit.re, p.omega);
        assert!(rel(crit.im.abs(), w) < 1e-8, "Im λ = {} vs ω = {w}", crit.im);
    }
}
