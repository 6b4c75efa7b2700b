//! The memory of a time integration: the estimate made before allocating against the
//! heap actually taken (counted by this binary's allocator, per thread), and the
//! refusal of a run whose estimate exceeds the limit.

use crate::heap::peak_of;
use ihbm::balance::MEMORY_LIMIT;
use ihbm::models::{HalfCar, QuarterCar};
use ihbm::timedomain::{estimate_bytes, simulate, Memory, SimOptions};

#[test]
fn the_estimate_bounds_the_heap_an_integration_takes() {
    let model = QuarterCar::default();
    let omega = std::f64::consts::TAU;
    // Around a power of two of steps (2^17), where the FFT levels jump, and with the
    // direct sum; with and without the recorded trajectory.
    for (steps, memory, record) in [
        (130_000, Memory::Fast, false),
        (132_000, Memory::Fast, false),
        (132_000, Memory::Fast, true),
        (60_000, Memory::Naive, false),
    ] {
        let periods = 100;
        let opts = SimOptions {
            dt: Some(periods as f64 / steps as f64),
            periods,
            memory,
            record,
            ..SimOptions::default()
        };
        let est = estimate_bytes(&model, steps, steps as f64 / periods as f64, &opts);
        let used = peak_of(|| {
            simulate(&model, omega, &opts).unwrap();
        });
        let r = used / est;
        assert!((0.95..=1.05).contains(&r), "{steps} steps {memory:?} record {record}: heap {used:.3e} B, estimate {est:.3e} B ({r:.3})");
    }
}

#[test]
fn an_integration_beyond_the_memory_limit_is_refused_before_allocating() {
    // Two fractional signals (front and rear element) at 20M steps: about 6 GB.
    let model = HalfCar::default();
    let omega = 10.0;
    let period = std::f64::consts::TAU / omega;
    let opts = SimOptions { dt: Some(period / 400.0), periods: 50_000, ..SimOptions::default() };
    let used = peak_of(|| {
        let e = simulate(&model, omega, &opts).unwrap_err().to_string();
        assert!(e.contains("periods at this dt"), "{e}");
        // The periods it names fit, one more would not.
        let most: usize = e
            .split("at most ")
            .nth(2)
            .and_then(|t| t.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no period count in: {e}"));
        let bytes = |p: usize| estimate_bytes(&model, p * 400, 400.0, &opts);
        assert!(bytes(most) <= MEMORY_LIMIT && bytes(most + 1) > MEMORY_LIMIT, "{e}");
    });
    assert!(used < 1e6, "{used} B allocated before refusing");
}
