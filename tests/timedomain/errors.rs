//! Bad input gives a clear error naming the value; a run that blows up says when.

use ihbm::models::{Duffing, FractionalDuffing, QuarterCar};
use ihbm::timedomain::{
    growth, simulate, PeriodicStart, Scheme, SimOptions, Stepper, StepperOptions,
};
use ihbm::Error;

fn invalid_message(r: Result<ihbm::timedomain::Simulation, Error>) -> String {
    match r {
        Err(e @ Error::InvalidValue { .. }) => e.to_string(),
        other => panic!("expected InvalidValue, got {other:?}"),
    }
}

#[test]
fn bad_steps_and_periods() {
    let m = QuarterCar::default();
    for dt in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let msg =
            invalid_message(simulate(&m, 8.0, &SimOptions { dt: Some(dt), ..Default::default() }));
        assert!(msg.contains("time step dt") && msg.contains(&dt.to_string()), "{msg}");
    }
    for periods in [0, 1, 19] {
        let msg = invalid_message(simulate(&m, 8.0, &SimOptions { periods, ..Default::default() }));
        assert!(msg.contains("periods") && msg.contains("at least 20"), "{msg}");
    }
    for tol in [0.0, f64::NAN] {
        let msg = invalid_message(simulate(
            &m,
            8.0,
            &SimOptions { newton_tol: tol, ..Default::default() },
        ));
        assert!(msg.contains("Newton tolerance"), "{msg}");
    }
    for omega in [0.0, -8.0, f64::NAN] {
        let msg = invalid_message(simulate(&m, omega, &SimOptions::default()));
        assert!(msg.contains("omega"), "{msg}");
    }
}

#[test]
fn step_too_coarse_for_the_forcing() {
    let m = QuarterCar::default();
    let period = std::f64::consts::TAU / 8.0;
    // 10 steps per period: refused, and the message says the largest dt accepted.
    let msg = invalid_message(simulate(
        &m,
        8.0,
        &SimOptions { dt: Some(period / 10.0), ..Default::default() },
    ));
    assert!(msg.contains("10.0 steps per period") && msg.contains("at most"), "{msg}");
    // 20 steps per period is the threshold and is accepted.
    let ok = simulate(
        &m,
        8.0,
        &SimOptions { dt: Some(period / 20.0), periods: 20, ..Default::default() },
    );
    assert!(ok.is_ok(), "{ok:?}");
}

#[test]
fn bad_model_parameters() {
    let m = FractionalDuffing { p: 2.5, ..Default::default() };
    let msg = invalid_message(simulate(&m, 1.0, &SimOptions::default()));
    assert!(msg.contains("fractional order p") && msg.contains("2.5"), "{msg}");
    let m = QuarterCar { m1: f64::NAN, ..Default::default() };
    let msg = invalid_message(simulate(&m, 8.0, &SimOptions::default()));
    assert!(msg.contains("m1"), "{msg}");
}

/// A softening Duffing (k3 < 0) forced hard escapes its potential well: x'' ~ +x³
/// blows up in finite time. The run must stop with Diverged and the time it happened,
/// after the start and before the end.
#[test]
fn escaping_run_reports_the_time() {
    let m = Duffing { k3: -1.0, F: 2.0, ..Default::default() };
    let opts = SimOptions { periods: 40, scheme: Scheme::Bdf2, ..Default::default() };
    match simulate(&m, 1.0, &opts) {
        Err(Error::Diverged { time, detail }) => {
            let end = 40.0 * std::f64::consts::TAU;
            println!("diverged at t = {time}: {detail}");
            assert!(time > 0.0 && time < end, "{time}");
            let msg = Error::Diverged { time, detail }.to_string();
            assert!(msg.contains(&format!("t = {time}")), "{msg}");
        }
        other => panic!("expected Diverged, got {other:?}"),
    }
}

/// The stepper refuses to go past the steps it was sized for, with the time.
#[test]
fn stepper_past_capacity() {
    let m = FractionalDuffing::default();
    let mut s = Stepper::new(&m, 1.0, &StepperOptions::new(0.1, 3)).unwrap();
    for _ in 0..3 {
        s.step().unwrap();
    }
    match s.step() {
        Err(Error::Diverged { time, .. }) => assert!((time - 0.4).abs() < 1e-12),
        other => panic!("{other:?}"),
    }
    // The state is still the last good one.
    assert!((s.time() - 0.3).abs() < 1e-12);
}

/// Negative damping: the linear response grows like e^{50 t}. The residual stops
/// being finite once x³ overflows (|x| ≈ 5.6e102, t ≈ ln(5.6e102)/50 ≈ 4.7 s, even
/// with k3 = 0 since 0 · inf is NaN) or, at the latest, when x itself does
/// (t ≈ 709/50 ≈ 14 s); the run stops there with the time, not with NaN statistics.
#[test]
fn overflowing_run_reports_the_time() {
    let m = Duffing { c: -50.0, k3: 0.0, ..Default::default() };
    match simulate(&m, 1.0, &SimOptions { periods: 40, ..Default::default() }) {
        Err(Error::Diverged { time, detail }) => {
            println!("diverged at t = {time}: {detail}");
            assert!((4.0..15.0).contains(&time), "{time}");
            assert!(detail.contains("not finite"), "{detail}");
        }
        other => panic!("expected Diverged, got {other:?}"),
    }
}

/// A periodic start that does not fit the model (coefficients for other harmonics or
/// DOFs, a displacement per wrong DOF count, a NaN, period 0) is refused with what
/// was expected; nothing is integrated.
#[test]
fn a_periodic_start_that_does_not_fit_is_refused() {
    let car = QuarterCar::default();
    let opts = StepperOptions::new(1e-3, 10);
    let good = PeriodicStart::new(vec![0.01; 2 * 7], 3);
    assert!(Stepper::on_periodic(&car, 8.0, &good, &opts).is_ok());
    let cases = [
        (PeriodicStart::new(vec![0.01; 2 * 5], 3), "14: 2 DOFs × (2·3 + 1)"),
        (PeriodicStart { dx: vec![1e-3; 3], ..good.clone() }, "one per DOF (2)"),
        (PeriodicStart { dv: vec![f64::NAN, 0.0], ..good.clone() }, "finite"),
        (PeriodicStart { period: 0, ..good.clone() }, "at least 1"),
        (PeriodicStart::new(vec![0.0; 3], usize::MAX / 2), "more than memory holds"),
    ];
    for (start, expected) in cases {
        match Stepper::on_periodic(&car, 8.0, &start, &opts) {
            Err(e @ Error::InvalidValue { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(expected) && msg.contains("periodic start"), "{msg}");
            }
            other => panic!("expected InvalidValue, got {other:?}"),
        }
    }
}

/// `growth` follows a displacement: without one, or with fewer than 6 periods of the
/// solution to fit, it is refused before anything is integrated; a bad start is
/// refused as `Stepper::on_periodic` refuses it.
#[test]
fn growth_without_a_displacement_or_periods_to_fit_is_refused() {
    let car = QuarterCar::default();
    let start = PeriodicStart::new(vec![0.01; 2 * 7], 3);
    let opts = SimOptions::default();
    let message = |r: Result<ihbm::timedomain::Growth, Error>| match r {
        Err(e @ Error::InvalidValue { .. }) => e.to_string(),
        other => panic!("expected InvalidValue, got {other:?}"),
    };
    let msg = message(growth(&car, 8.0, &start, &opts));
    assert!(msg.contains("no displacement"), "{msg}");
    let moved = PeriodicStart { dx: vec![1e-6, 0.0], period: 4, ..start.clone() };
    let msg = message(growth(&car, 8.0, &moved, &SimOptions { periods: 20, ..opts.clone() }));
    assert!(msg.contains("at least 24"), "{msg}");
    let bad = PeriodicStart { dx: vec![1e-6; 3], ..start };
    let msg = message(growth(&car, 8.0, &bad, &opts));
    assert!(msg.contains("one per DOF"), "{msg}");
}
