//! Fold curves and cusps (two-parameter continuation) against closed forms, against
//! ordinary sweeps and against an exact scaling law.

use ihbm::bifurcation::{fold_curves, End, FoldCurveOptions, FoldCurves};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{Duffing, QuarterCar};
use ihbm::Model;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The one-harmonic Duffing oscillator: the amplitude equation
/// `H(u) = u [(k - mΩ² + βu)² + (cΩ)²] - F² = 0`, `u = A²`, `β = 3k3/4`, is cubic in
/// `u`; a fold is a double root, the cusp a triple root: `k - mΩ² = -√3 cΩ`,
/// `u = 2cΩ/(√3 β)`, `F² = 8 (cΩ)³ / (3√3 β)`.
fn duffing_cusp(d: &Duffing) -> (f64, f64) {
    let s3 = 3f64.sqrt();
    let omega = (s3 * d.c + (3.0 * d.c * d.c + 4.0 * d.m * d.k).sqrt()) / (2.0 * d.m);
    let beta = 0.75 * d.k3;
    let f = (8.0 * (d.c * omega).powi(3) / (3.0 * s3 * beta)).sqrt();
    (omega, f)
}

fn duffing_folds() -> (Duffing, FoldCurves) {
    let model = Duffing::default();
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 1;
    opts.omega = (0.5, 3.0);
    let f = model.param_index("F").unwrap();
    let res = fold_curves(&model, f, 0.01, 0.3, &opts).unwrap();
    (model, res)
}

#[test]
fn the_duffing_cusp_is_the_triple_root_of_the_amplitude_equation() {
    let (model, res) = duffing_folds();
    let (omega_c, f_c) = duffing_cusp(&model);
    assert_eq!(res.start_folds, (0, 2), "no fold at F = 0.01, two at F = 0.3");
    assert_eq!(res.cusps.len(), 1, "{:?}", res.cusps);
    let cusp = &res.cusps[0];
    assert!(cusp.located);
    assert!(rel(cusp.value, f_c) < 1e-8, "F_c {} vs {f_c}", cusp.value);
    assert!(rel(cusp.omega, omega_c) < 1e-8, "Ω_c {} vs {omega_c}", cusp.omega);
    // one curve: from the upper fold at F = 0.3 through the cusp back to the lower one
    assert_eq!(
        res.curves.len(),
        1,
        "{:?}",
        res.curves.iter().map(|c| &c.ended).collect::<Vec<_>>()
    );
    assert_eq!(res.curves[0].ended, End::ReachedEnd);
}

#[test]
fn every_duffing_fold_curve_point_is_a_double_root() {
    let (model, res) = duffing_folds();
    let beta = 0.75 * model.k3;
    let mut checked = 0;
    for p in res.curves.iter().flat_map(|c| &c.points) {
        // coefficients [a0, a1, b1]
        let u = p.coeffs[1].powi(2) + p.coeffs[2].powi(2);
        let s = model.k - model.m * p.omega * p.omega;
        let g = model.c * p.omega;
        let h = u * ((s + beta * u).powi(2) + g * g) - p.value * p.value;
        let dh = (s + beta * u).powi(2) + g * g + 2.0 * beta * u * (s + beta * u);
        // scale: the size of the terms of H and of H'
        let scale = p.value * p.value;
        assert!(h.abs() < 1e-9 * scale, "H = {h:e} at Ω = {}, F = {}", p.omega, p.value);
        assert!(
            dh.abs() < 1e-7 * (g * g + s * s),
            "H' = {dh:e} at Ω = {}, F = {}",
            p.omega,
            p.value
        );
        checked += 1;
    }
    assert!(checked > 10, "only {checked} points");
}

/// A point of a fold curve is a fold of the ordinary sweep at that parameter value:
/// on the quarter car's fold curve in F (k3 = 5e6), one point on each of the two
/// folds that meet at the first cusp (the hysteresis of the body resonance). Past the
/// second cusp the curve runs on the folds of a detached high-amplitude branch, which a
/// sweep from Ω = 5 to 60 never visits (at F = 0.0275 its fold is at Ω = 18.65 with
/// max |z1| = 0.50 m, while the swept curve has its two folds at 12.49 and 13.19).
#[test]
fn quarter_car_fold_curves_pass_through_the_folds_of_ordinary_sweeps() {
    let mut model = QuarterCar::default();
    model.set_param("k3", 5e6).unwrap();
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 3;
    opts.omega = (5.0, 60.0);
    let f = model.param_index("F").unwrap();
    let res = fold_curves(&model, f, 0.005, 0.2, &opts).unwrap();
    assert_eq!(res.cusps.len(), 2, "{:?}", res.cusps);
    let c = &res.curves[0];
    let (k1, k2) = (res.cusps[0].after, res.cusps[1].after);
    for i in [k1 / 2, (k1 + k2) / 2] {
        let p = &c.points[i];
        let mut m = model.clone();
        m.set_param_value(f, p.value);
        let so = SweepOptions { harmonics: 3, stability: None, ..SweepOptions::default() };
        let curve = sweep(&m, 5.0, 60.0, &so).unwrap();
        let nearest =
            curve.folds.iter().map(|f| rel(f.omega, p.omega)).fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-7,
            "F = {}: no sweep fold near Ω = {} ({nearest:e})",
            p.value,
            p.omega
        );
    }
}

/// x → s·x maps (k3, F) to (k3·s², F/s) in a model whose only nonlinearity is cubic:
/// the cusp's F·√k3 and Ω do not depend on k3.
#[test]
fn the_quarter_car_cusp_obeys_the_cubic_scaling_law() {
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 3;
    opts.omega = (5.0, 60.0);
    let mut cusps = Vec::new();
    for k3 in [5e6, 2e7] {
        let mut model = QuarterCar::default();
        model.set_param("k3", k3).unwrap();
        let f = model.param_index("F").unwrap();
        let res = fold_curves(&model, f, 0.005, 0.2, &opts).unwrap();
        assert!(!res.cusps.is_empty(), "k3 = {k3}: no cusp");
        let c = res.cusps.iter().min_by(|a, b| a.value.total_cmp(&b.value)).unwrap();
        assert!(c.located);
        cusps.push((c.omega, c.value * k3.sqrt()));
    }
    assert!(rel(cusps[0].0, cusps[1].0) < 1e-8, "Ω_c {:?}", cusps);
    assert!(rel(cusps[0].1, cusps[1].1) < 1e-8, "F_c √k3 {:?}", cusps);
}

#[test]
fn a_range_without_folds_is_refused_with_the_ranges_in_the_message() {
    let model = Duffing::default();
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 1;
    opts.omega = (0.5, 3.0);
    let f = model.param_index("F").unwrap();
    let e = fold_curves(&model, f, 0.001, 0.01, &opts).unwrap_err().to_string();
    assert!(e.contains("no fold") && e.contains("F = 0.001") && e.contains("[0.5, 3]"), "{e}");
}

/// Driving the fold analysis step by step is the same computation as `fold_curves`:
/// the events name both end sweeps, every curve's start, points and end, and the
/// cusp, each once and in order; and a run stopped at its cusp keeps, bit for bit, a
/// prefix of the whole analysis, the curve being traced ended "stopped".
#[test]
fn stepping_the_fold_analysis_gives_fold_curves_and_a_stop_keeps_a_prefix() {
    use ihbm::bifurcation::{FoldContinuation, FoldEvent, RangeEnd};
    let (model, whole) = duffing_folds();
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 1;
    opts.omega = (0.5, 3.0);
    let f = model.param_index("F").unwrap();
    let mut run = FoldContinuation::new(&model, f, 0.01, 0.3, &opts).unwrap();
    let mut events = Vec::new();
    loop {
        let e = run.step().unwrap();
        if e == FoldEvent::Finished {
            break;
        }
        events.push(e);
    }
    assert_eq!(run.step().unwrap(), FoldEvent::Finished, "finished stays finished");
    assert_eq!(run.finish(), whole);
    assert_eq!(
        events[..2],
        [FoldEvent::Swept(RangeEnd::From, 0), FoldEvent::Swept(RangeEnd::To, 2)]
    );
    let count = |want: fn(&FoldEvent) -> bool| events.iter().filter(|e| want(e)).count();
    assert_eq!(count(|e| matches!(e, FoldEvent::CurveStart(_))), whole.curves.len());
    assert_eq!(count(|e| matches!(e, FoldEvent::CurveEnd(_))), whole.curves.len());
    assert_eq!(count(|e| matches!(e, FoldEvent::Cusp(_))), whole.cusps.len());
    // Every curve's points after its start, in order: each step's, and the last one
    // a landing on the end of the range adds with the curve's end.
    for (ci, c) in whole.curves.iter().enumerate() {
        let seen: Vec<usize> = events
            .iter()
            .filter_map(|e| match *e {
                FoldEvent::Point { curve, index } if curve == ci => Some(index),
                _ => None,
            })
            .collect();
        assert_eq!(seen, (1..=seen.len()).collect::<Vec<_>>());
        assert!(
            c.points.len() - seen.len() <= 2,
            "{} points, {} events",
            c.points.len(),
            seen.len()
        );
    }

    let mut run = FoldContinuation::new(&model, f, 0.01, 0.3, &opts).unwrap();
    while !matches!(run.step().unwrap(), FoldEvent::Cusp(_) | FoldEvent::Finished) {}
    let part = run.finish();
    assert_eq!(part.cusps, whole.cusps);
    let c = part.curves.len() - 1;
    assert_eq!(part.curves[..c], whole.curves[..c]);
    let (p, w) = (&part.curves[c].points, &whole.curves[c].points);
    assert_eq!(p[..], w[..p.len()]);
    assert_eq!(part.curves[c].ended, End::Stopped);
}
