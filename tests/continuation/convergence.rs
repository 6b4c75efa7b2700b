//! Harmonic convergence and parallel families.

use ihbm::continuation::{sweep, sweep_family, ConvergenceOptions, SweepOptions};
use ihbm::models::{Duffing, QuarterCar};

#[test]
fn harmonic_convergence_estimate_bounds_the_error() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let conv = ConvergenceOptions { tol: 1e-6, increment: 2, max_harmonics: 15 };
    let opts = SweepOptions { harmonics: 1, convergence: Some(conv), ..Default::default() };
    let curve = sweep(&model, 0.5, 2.5, &opts).unwrap();
    let report = curve.convergence.clone().unwrap();
    assert!(report.converged, "{report:?}");
    assert!(report.estimate < 1e-6);
    let ns: Vec<usize> = report.levels.iter().map(|l| l.harmonics).collect();
    assert_eq!(ns[..3], [1, 3, 5]);
    assert_eq!(curve.harmonics, *ns.last().unwrap());
    // Independent reference: a run with many more harmonics.
    let reference =
        sweep(&model, 0.5, 2.5, &SweepOptions { harmonics: 21, ..Default::default() }).unwrap();
    let peak = |c: &ihbm::results::Curve| {
        c.points.iter().map(|p| p.outputs[0].max_abs).fold(0.0, f64::max)
    };
    let err_peak = (peak(&curve) - peak(&reference)).abs() / peak(&reference);
    // The peak of a traced polyline is a sampled maximum; compare the folds instead
    // (located exactly), and the peak only to the sampling accuracy.
    assert!(err_peak < 1e-2, "{err_peak}");
    assert_eq!(curve.folds.len(), reference.folds.len());
    for (a, b) in curve.folds.iter().zip(&reference.folds) {
        let e = (a.omega - b.omega).abs() / b.omega;
        assert!(
            e <= report.estimate.max(1e-12) * 10.0,
            "fold {} vs {}: {e:.2e} > estimate {:.2e}",
            a.omega,
            b.omega,
            report.estimate
        );
    }
    // The change shrinks from level to level (spectral convergence).
    let changes: Vec<f64> = report.levels.iter().skip(1).map(|l| l.change).collect();
    assert!(changes.windows(2).all(|w| w[1] < w[0]), "{changes:?}");
}

#[test]
fn family_in_parallel_equals_sequential_sweeps() {
    let car = QuarterCar::default();
    let values = [1e6, 3e6, 5e6];
    let opts = SweepOptions::default();
    let fam = sweep_family(&car, "k3", &values, 1.0, 100.0, &opts);
    assert_eq!(fam.len(), 3);
    for (v, r) in values.iter().zip(fam) {
        let mut m = car.clone();
        m.k3 = *v;
        let seq = sweep(&m, 1.0, 100.0, &opts).unwrap();
        assert_eq!(r.unwrap(), seq);
    }
    let bad = sweep_family(&car, "nope", &values, 1.0, 100.0, &opts);
    assert!(bad.iter().all(|r| r.as_ref().err().unwrap().to_string().contains("nope")));
}
