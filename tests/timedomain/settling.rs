//! The start-up transient left at the end of a run: the closed form of a linear
//! oscillator, and the warning of a run far too short for its slowest mode.

use ihbm::models::{Duffing, QuarterCar};
use ihbm::timedomain::{simulate, SimOptions, StartUp};

/// `m x'' + c x' + k x`: the free mode is `√(k/m)`, and its amplitude decays like
/// `e^{-c t / (2 m)}`.
#[test]
fn a_linear_oscillator_keeps_its_closed_form_transient() {
    let (m, c, k) = (2.0, 0.1, 8.0);
    let model = Duffing { m, c, k, k3: 0.0, ..Default::default() };
    let omega = 100.0;
    let sim = simulate(&model, omega, &SimOptions::default()).unwrap();
    let s = sim.start_up.expect("an oscillatory mode");
    let t = sim.steps as f64 * sim.dt;
    assert!((s.omega - (k / m).sqrt()).abs() < 1e-12, "{s:?}");
    assert!((s.decay_time - 2.0 * m / c).abs() < 1e-9, "{s:?}");
    assert!((s.left - (-c * t / (2.0 * m)).exp()).abs() < 1e-12, "{s:?}");
    assert!(s.left > StartUp::NEGLIGIBLE, "200 periods at Ω = 100 are 12.6 s: {s:?}");
    // Undamped: nothing decays.
    let free = Duffing { m, c: 0.0, k, k3: 0.0, ..Default::default() };
    let s = simulate(&free, omega, &SimOptions::default()).unwrap().start_up.unwrap();
    assert_eq!((s.left, s.decay_time), (1.0, f64::INFINITY));
}

/// At Ω = 10⁶ rad/s the quarter car's 200 periods last 1.3 ms against a body mode
/// that decays in seconds; at Ω = 10 rad/s they last 126 s.
#[test]
fn the_quarter_car_far_above_resonance_is_not_settled() {
    let q = QuarterCar::default();
    let fast = simulate(&q, 1e6, &SimOptions::default()).unwrap().start_up.unwrap();
    assert!(fast.left > 0.99, "{fast:?}");
    let slow = simulate(&q, 10.0, &SimOptions::default()).unwrap().start_up.unwrap();
    assert!(slow.left < 1e-20, "{slow:?}");
}
