//! The fast (FFT) history convolution against the direct sum.

use ihbm::models::QuarterCar;
use ihbm::timedomain::{simulate, History, Memory, Scheme, SimOptions, Stepper, StepperOptions};
use proptest::prelude::*;

fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale
}

/// Same run, both memories: every step's state and the steady statistics agree to
/// 1e-12 relative (to each signal's largest magnitude).
#[test]
fn fast_run_equals_naive_run() {
    let model = QuarterCar { k3: 5e6, F: 0.02, ..Default::default() };
    let omega = 8.0;
    let steps = 20_000; // 50 periods at T/400: squares up to 8192 go through the FFT
    let dt = std::f64::consts::TAU / omega / 400.0;
    let mut fast = Stepper::new(&model, omega, &StepperOptions::new(dt, steps)).unwrap();
    let mut naive = Stepper::new(
        &model,
        omega,
        &StepperOptions { memory: Memory::Naive, ..StepperOptions::new(dt, steps) },
    )
    .unwrap();
    let mut xf = Vec::new();
    let mut xn = Vec::new();
    for _ in 0..steps {
        fast.step().unwrap();
        naive.step().unwrap();
        xf.extend_from_slice(fast.displacements());
        xn.extend_from_slice(naive.displacements());
    }
    let scale = xn.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = xf.iter().zip(&xn).map(|(a, b)| rel(*a, *b, scale)).fold(0.0, f64::max);
    println!("largest state difference fast vs naive: {worst:.2e} relative");
    assert!(worst <= 1e-12, "{worst:e}");

    let opts = SimOptions { periods: 40, ..Default::default() };
    let a = simulate(&model, 60.0, &opts).unwrap();
    let b = simulate(&model, 60.0, &SimOptions { memory: Memory::Naive, ..opts }).unwrap();
    for (oa, ob) in a.outputs.iter().zip(&b.outputs) {
        assert!(rel(oa.max_abs, ob.max_abs, ob.max_abs) <= 1e-12, "{oa:?} vs {ob:?}");
        assert!(rel(oa.mean, ob.mean, ob.max_abs) <= 1e-12, "{oa:?} vs {ob:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]
    /// Random orders in (0, 2), both rules, random sequences of random length: the
    /// fast lag sums equal the direct ones to 1e-12 of the sum of |w_j e_k| terms
    /// (the size rounding is measured against) plus the FFT's norm-wise rounding.
    #[test]
    fn fast_lag_sums_equal_naive(
        q in 0.01f64..1.99,
        bdf2 in any::<bool>(),
        len in 1usize..3000,
        seed in prop::collection::vec(-1.0f64..1.0, 16),
    ) {
        let scheme = if bdf2 { Scheme::Bdf2 } else { Scheme::Gl };
        let w = scheme.weights(q, len + 1);
        let mut fast = History::new(Memory::Fast, w.clone());
        let mut naive = History::new(Memory::Naive, w.clone());
        for m in 0..=len {
            let a = fast.lag_sum().unwrap();
            let b = naive.lag_sum().unwrap();
            let terms = naive.values().iter().enumerate().map(|(k, e)| (w[m - k], *e));
            let bound: f64 = terms.clone().map(|(w, e)| (w * e).abs()).sum();
            // The FFT squares round norm-wise (Higham, *Accuracy and Stability*, §24.1:
            // ε·O(log n)·‖w‖₂‖e‖₂), which the component-wise sum does not bound where
            // one weight dwarfs the rest (q near 1: w₁ = -q, the others O(q - 1)) and
            // its source is small.
            let (w2, e2) = terms.fold((0.0, 0.0), |(a, b), (w, e)| (a + w * w, b + e * e));
            let fft = 8.0 * f64::EPSILON * ((len + 2) as f64).log2() * (w2 * e2).sqrt();
            prop_assert!((a - b).abs() <= 1e-12 * bound + fft + 1e-300, "m {} fast {} naive {} bound {} fft {}", m, a, b, bound, fft);
            // A rough random signal: seeded harmonics plus a jump every 97 steps.
            let t = m as f64;
            let e: f64 = seed.iter().enumerate().map(|(i, s)| s * (t * (i as f64 + 1.0) * 0.37).sin()).sum::<f64>()
                + if (m / 97) % 2 == 0 { 1.0 } else { -1.0 };
            fast.push(e).unwrap();
            naive.push(e).unwrap();
        }
    }
}

/// The recorded trajectory is the run itself: same length as the steps, and the
/// statistics recomputed from its last 10 periods are the reported ones.
#[test]
fn recorded_trajectory_matches_statistics() {
    let model = QuarterCar::default();
    let sim =
        simulate(&model, 8.0, &SimOptions { periods: 20, record: true, ..Default::default() })
            .unwrap();
    let tr = sim.trajectory.as_ref().unwrap();
    assert_eq!(tr.time.len(), sim.steps + 1);
    assert_eq!(tr.names, ["z1", "z2", "y"]);
    for (i, o) in sim.outputs.iter().enumerate() {
        let tail = &tr.outputs[i][sim.steps - 4000..];
        assert_eq!(ihbm::timedomain::steady::max_abs(tail), o.max_abs);
        assert_eq!(ihbm::timedomain::steady::mean(tail), o.mean);
    }
}
