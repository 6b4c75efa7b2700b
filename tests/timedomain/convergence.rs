//! Observed convergence order over a fixed horizon, from rest.
//!
//! Each run records the outputs at the coarse grid times `k · h0`; the error of a
//! run is the largest difference over the horizon from a reference run at `h0/64`
//! (BDF2 — its own error there is below 1e-3 of the coarsest error measured). Halving
//! the step must divide the error by about 2 (GL, first order) or 4 (BDF2, second
//! order). The horizon holds the start-up, where the solution behaves like `t²`
//! plus `t^(4-p)` terms, so a lost order near t = 0 would show.

use ihbm::model::Model;
use ihbm::models::{FractionalDuffing, QuarterCar};
use ihbm::timedomain::{Scheme, Stepper, StepperOptions};

/// Outputs at times `k * h0`, `k = 0..=n0`, from a run with step `h0 / refine`.
fn run<M: Model>(
    model: &M,
    omega: f64,
    h0: f64,
    n0: usize,
    refine: usize,
    scheme: Scheme,
) -> Vec<f64> {
    let steps = n0 * refine;
    let opts = StepperOptions { scheme, ..StepperOptions::new(h0 / refine as f64, steps) };
    let mut s = Stepper::new(model, omega, &opts).unwrap();
    let nout = model.outputs().len();
    let mut out = Vec::with_capacity((n0 + 1) * nout);
    for k in 0..=steps {
        if k > 0 {
            s.step().unwrap();
        }
        if k % refine == 0 {
            out.extend((0..nout).map(|i| s.output(i)));
        }
    }
    out
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// Errors at h0, h0/2, h0/4 and the observed orders between them.
fn orders<M: Model>(model: &M, omega: f64, h0: f64, n0: usize, scheme: Scheme) -> Vec<f64> {
    let reference = run(model, omega, h0, n0, 64, Scheme::Bdf2);
    let errors: Vec<f64> = [1, 2, 4]
        .iter()
        .map(|&r| max_diff(&run(model, omega, h0, n0, r, scheme), &reference))
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("{} {scheme}: errors {errors:?} orders {orders:.3?}", model.name());
    orders
}

fn assert_orders(orders: &[f64], scheme: Scheme) {
    let (lo, hi) = match scheme {
        Scheme::Gl => (0.8, 1.3),
        Scheme::Bdf2 => (1.7, 2.4),
    };
    for &o in orders {
        assert!((lo..=hi).contains(&o), "{scheme}: observed order {o} outside [{lo}, {hi}]");
    }
}

#[test]
fn fractional_duffing_orders() {
    // Strongly cubic (k3 x³ comparable to k x at |x| ~ 1), 20 s, h0 = 0.05.
    let model = FractionalDuffing { k3: 1.0, h: 0.3, F: 1.0, ..Default::default() };
    for scheme in [Scheme::Gl, Scheme::Bdf2] {
        assert_orders(&orders(&model, 1.2, 0.05, 400, scheme), scheme);
    }
}

#[test]
fn fractional_duffing_order_above_one() {
    let model = FractionalDuffing { k3: 1.0, h: 0.3, p: 1.5, F: 1.0, ..Default::default() };
    for scheme in [Scheme::Gl, Scheme::Bdf2] {
        assert_orders(&orders(&model, 1.2, 0.05, 400, scheme), scheme);
    }
}

#[test]
fn quarter_car_orders() {
    // Table 1 with a strong cubic spring, 2 s at Ω = 8 rad/s, h0 = 2 ms (the wheel
    // mode is near 77 rad/s: 40 steps per its period at h0).
    let model = QuarterCar { k3: 5e6, F: 0.02, ..Default::default() };
    for scheme in [Scheme::Gl, Scheme::Bdf2] {
        assert_orders(&orders(&model, 8.0, 2e-3, 1000, scheme), scheme);
    }
}
