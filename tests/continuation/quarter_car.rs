//! The quarter car over the paper's whole frequency range, for every parameter value
//! of its sections 4.2 and 4.3, and a case with a genuine multi-valued region.

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::QuarterCar;
use ihbm::results::{Curve, Direction, End};
use ihbm::Model;

fn car(sets: &[(&str, f64)]) -> QuarterCar {
    let mut m = QuarterCar::default();
    for &(k, v) in sets {
        m.set_param(k, v).unwrap();
    }
    m
}

/// The curve covers 1..100 rad/s in one piece and every point solves the balance.
fn check_whole(c: &Curve, what: &str, model: &QuarterCar) {
    assert_eq!(c.segments.len(), 1, "{what}: {:?}", c.segments);
    assert_eq!(c.segments[0].ended, End::ReachedEnd, "{what}");
    assert_eq!(c.points[0].omega, 1.0, "{what}");
    assert!((c.points.last().unwrap().omega - 100.0).abs() < 1e-9, "{what}");
    // Independent of the continuation: each point is a harmonic balance solution.
    let mut hb = ihbm::balance::Balance::new(model, c.harmonics).unwrap();
    let mut r = vec![0.0; hb.len()];
    let mut r0 = vec![0.0; hb.len()];
    for p in c.points.iter().step_by(7) {
        hb.residual(&vec![0.0; hb.len()], p.omega, &mut r0);
        hb.residual(&p.coeffs, p.omega, &mut r);
        let scale = r0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let res = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(res < 1e-8 * scale, "{what}: residual {res:.2e} at Ω = {}", p.omega);
    }
}

#[test]
fn every_parameter_value_of_sections_4_2_and_4_3_traces_1_to_100() {
    let mut cases: Vec<Vec<(&str, f64)>> = Vec::new();
    for k3 in [1e6, 2e6, 3e6, 4e6, 5e6] {
        cases.push(vec![("k3", k3)]);
    }
    for f in [0.006, 0.008, 0.01] {
        cases.push(vec![("k3", 3e6), ("F", f)]);
    }
    for m1 in [200.0, 220.0, 240.0, 260.0, 280.0] {
        cases.push(vec![("k3", 3e6), ("m1", m1)]);
    }
    for m2 in [30.0, 40.0, 50.0, 60.0, 70.0] {
        cases.push(vec![("k3", 3e6), ("m2", m2)]);
    }
    for p in [0.0, 0.2, 0.4, 0.6, 0.8, 1.0] {
        cases.push(vec![("p", p)]);
    }
    for h in [500.0, 1000.0, 1500.0, 2000.0] {
        cases.push(vec![("h", h)]);
    }
    let opts = SweepOptions::default();
    for case in &cases {
        let model = car(case);
        let c = sweep(&model, 1.0, 100.0, &opts).unwrap_or_else(|e| panic!("{case:?}: {e}"));
        check_whole(&c, &format!("{case:?}"), &model);
        // The paper's corrected figures: at F <= 1 cm and Table 1 damping there is no fold for any k3.
        assert!(
            c.folds.is_empty(),
            "{case:?}: folds {:?}",
            c.folds.iter().map(|f| f.omega).collect::<Vec<_>>()
        );
        assert!(
            c.points.iter().all(|p| p.stability.is_stable()),
            "{case:?}: an unstable point without folds"
        );
        assert!(c.jumps.is_empty());
    }
}

/// Road amplitude 3 cm, cubic stiffness 5000 kN/m: the body resonance bends right and
/// folds twice.
#[test]
fn large_road_amplitude_folds_and_jumps() {
    let model = car(&[("F", 0.03), ("k3", 5e6)]);
    let c = sweep(&model, 1.0, 100.0, &SweepOptions::default()).unwrap();
    check_whole(&c, "F = 0.03, k3 = 5e6", &model);
    assert_eq!(c.folds.len(), 2, "{:?}", c.folds.iter().map(|f| f.omega).collect::<Vec<_>>());
    let (f0, f1) = (c.folds[0].after, c.folds[1].after);
    let (hi, lo) = (c.folds[0].omega, c.folds[1].omega);
    assert!(hi > lo, "the upper fold comes first along the curve");
    for (i, p) in c.points.iter().enumerate() {
        assert_eq!(p.stability.is_stable(), !(i > f0 && i <= f1), "point {i} at Ω = {}", p.omega);
    }
    // Each fold: the λ-tangent vanishes there, so nearby points on both sides lie on
    // the same side in Ω (a turning point, not a crossing).
    for f in &c.folds {
        let (a, b) = (&c.points[f.after], &c.points[f.after + 1]);
        assert!((a.omega - f.omega).signum() == (b.omega - f.omega).signum());
    }
    for (dir, at) in [(Direction::Up, hi), (Direction::Down, lo)] {
        let js: Vec<_> = c.jumps.iter().filter(|j| j.direction == dir).collect();
        assert_eq!(js.len(), 3, "one jump per output: {js:?}");
        for j in js {
            assert_eq!(j.at, at);
            // The landing value is on the curve at the same Ω: some stable traced
            // interval brackets it, and a fresh Newton solve there (the plain
            // corrector, started from the interpolated coefficients) gives the same
            // amplitude; the polyline itself is only good to its chord error.
            let k = c.output_names.iter().position(|n| *n == j.output).unwrap();
            let on_curve = c.points.windows(2).any(|w| {
                let (p, q) = (&w[0], &w[1]);
                let inside = (p.omega - at) * (q.omega - at) <= 0.0;
                inside && p.stability.is_stable() && q.stability.is_stable() && {
                    let t = (at - p.omega) / (q.omega - p.omega);
                    let guess: Vec<f64> =
                        p.coeffs.iter().zip(&q.coeffs).map(|(a, b)| a + t * (b - a)).collect();
                    let polyline =
                        p.outputs[k].max_abs + t * (q.outputs[k].max_abs - p.outputs[k].max_abs);
                    let so = SolveOptions { harmonics: c.harmonics, ..Default::default() };
                    let sol = solve(&model, at, &so, Some(&guess)).unwrap();
                    let exact = sol.outputs(&model)[k].max_abs;
                    (exact - j.to).abs() < 1e-9 * exact && (polyline - j.to).abs() < 3e-2 * exact
                }
            });
            assert!(on_curve, "{j:?}");
        }
    }
    let up = c.jumps.iter().find(|j| j.direction == Direction::Up && j.output == "z1").unwrap();
    let down = c.jumps.iter().find(|j| j.direction == Direction::Down && j.output == "z1").unwrap();
    assert!(up.from > up.to, "up sweep drops from the resonant branch");
    assert!(down.from < down.to, "down sweep jumps up onto it");
}

/// Road amplitude 5 cm: the resonant branch climbs the undamped locked-suspension
/// asymptote sqrt(kt/(m1+m2)) ≈ 24.3 rad/s; the sweep stops at the amplitude bound,
/// resumes from 100 rad/s and comes back to the same asymptote from the fold side.
#[test]
fn runaway_branch_stops_at_bound_and_resumes_from_the_other_end() {
    let model = car(&[("F", 0.05), ("k3", 5e6)]);
    let c = sweep(&model, 1.0, 100.0, &SweepOptions::default()).unwrap();
    assert_eq!(c.segments.len(), 2, "{:?}", c.segments);
    assert_eq!(c.segments[0].ended, End::AmplitudeBound);
    assert_eq!(c.segments[1].from, 100.0);
    let locked = (model.kt / (model.m1 + model.m2)).sqrt();
    for s in &c.segments {
        if s.ended == End::AmplitudeBound {
            assert!((s.to - locked).abs() < 0.02 * locked, "{s:?} vs {locked}");
        }
    }
    // Both pieces are kept, in order, and the second runs downwards from 100 rad/s.
    let first_of_second = c.points.iter().position(|p| p.segment == 1).unwrap();
    assert_eq!(c.points[first_of_second].omega, 100.0);
    assert!(c.points[..first_of_second].iter().all(|p| p.segment == 0));
    assert!(c.points[first_of_second + 1].omega < 100.0);
}
