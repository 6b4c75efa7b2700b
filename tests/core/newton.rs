//! Newton on the strongly nonlinear quarter car: convergence from the linearized guess
//! and a quadratically falling residual; bad input gives errors naming the value.

use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::QuarterCar;
use ihbm::{Error, Model};

/// The smallest k3 (doubling from 1e6) at which the cubic term changes the body
/// response at `omega` by more than 10 % relative to the linear car.
fn strong_k3(omega: f64) -> f64 {
    let linear = QuarterCar { k3: 0.0, ..QuarterCar::default() };
    let base =
        solve(&linear, omega, &SolveOptions::default(), None).unwrap().outputs(&linear)[0].max_abs;
    let mut k3 = 1e6;
    loop {
        let car = QuarterCar { k3, ..QuarterCar::default() };
        let amp =
            solve(&car, omega, &SolveOptions::default(), None).unwrap().outputs(&car)[0].max_abs;
        if ((amp - base) / base).abs() > 0.10 {
            return k3;
        }
        k3 *= 2.0;
        assert!(k3 < 1e12, "no k3 changes the response by 10 %");
    }
}

#[test]
fn newton_converges_quadratically_on_strong_cubic() {
    let omega = 9.0;
    let k3 = strong_k3(omega);
    let car = QuarterCar { k3, ..QuarterCar::default() };
    let opts = SolveOptions { tol: 1e-14, ..SolveOptions::default() };
    let sol = solve(&car, omega, &opts, None).unwrap();
    let r: Vec<f64> = sol.history.iter().map(|h| h.residual_norm).collect();
    eprintln!("k3 = {k3:.3e}; residual history {r:?}");
    assert!(sol.iterations >= 3, "a 10 % nonlinear effect should need several Newton steps");
    // every step taken at full length, and the residual falls monotonically
    assert!(sol.history.iter().all(|h| h.damping == 1.0));
    assert!(r.windows(2).all(|w| w[1] < w[0]));
    // quadratic: ln(r_{k+1}/r_k) / ln(r_k/r_{k-1}) ≈ 2 while above round-off
    let floor = 1e-11 * r[0];
    let mut orders = Vec::new();
    for w in r.windows(3) {
        if w[2] > floor {
            orders.push((w[2] / w[1]).ln() / (w[1] / w[0]).ln());
        }
    }
    eprintln!("observed orders {orders:.2?}");
    let last = orders.last().copied().expect("at least one triple above round-off");
    assert!(last > 1.8 && last < 2.5, "last observed order {last}");
}

#[test]
fn bad_input_is_an_error_naming_the_value() {
    let car = QuarterCar::default();
    let e = solve(&car, 0.0, &SolveOptions::default(), None).unwrap_err();
    assert!(e.to_string().contains("omega") && e.to_string().contains('0'), "{e}");
    let e = solve(&car, f64::NAN, &SolveOptions::default(), None).unwrap_err();
    assert!(e.to_string().contains("NaN"), "{e}");
    let e = solve(&car, 8.0, &SolveOptions { harmonics: 0, ..SolveOptions::default() }, None)
        .unwrap_err();
    assert!(e.to_string().contains("harmonics"), "{e}");
    let mut bad = car.clone();
    let e = bad.set_param("k9", 1.0).unwrap_err();
    assert!(matches!(e, Error::UnknownParameter { .. }) && e.to_string().contains("k9"), "{e}");
    let e = bad.set_param("k1", f64::INFINITY).unwrap_err();
    assert!(e.to_string().contains("inf"), "{e}");
    bad.p = 2.5;
    let e = solve(&bad, 8.0, &SolveOptions::default(), None).unwrap_err();
    assert!(e.to_string().contains("2.5") && e.to_string().contains("[0, 2]"), "{e}");
    let e = solve(&car, 8.0, &SolveOptions::default(), Some(&[0.0; 3])).unwrap_err();
    assert!(e.to_string().contains("guess"), "{e}");
}

#[test]
fn non_convergence_keeps_last_iterate_and_history() {
    let car = QuarterCar { k3: 5e7, F: 0.05, ..QuarterCar::default() };
    let opts = SolveOptions { max_iter: 2, ..SolveOptions::default() };
    match solve(&car, 20.0, &opts, None) {
        Err(Error::NotConverged { last, history, iterations, residual_norm, .. }) => {
            assert_eq!(last.len(), 22);
            assert_eq!(history.len(), 3);
            assert_eq!(iterations, 2);
            assert_eq!(history[2].residual_norm, residual_norm);
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
}
