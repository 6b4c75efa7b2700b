//! The linear quarter car (k3 = 0) against its closed form:
//! G(Ω) = k1 + i c Ω + h (iΩ)^p, Δ(Ω) = m1 m2 Ω^4 - [kt m1 + (m1 + m2) G] Ω^2 + kt G,
//! Z1/F = kt G / Δ, Y/F = kt m1 Ω^2 / Δ.

use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::QuarterCar;
use num_complex::Complex64;

fn closed_form(car: &QuarterCar, omega: f64) -> (Complex64, Complex64) {
    let i = Complex64::new(0.0, 1.0);
    let g = car.k1 + i * car.c * omega + car.h * (i * omega).powf(car.p);
    let w2 = omega * omega;
    let delta =
        car.m1 * car.m2 * w2 * w2 - (car.kt * car.m1 + (car.m1 + car.m2) * g) * w2 + car.kt * g;
    (car.kt * g / delta * car.F, car.kt * car.m1 * w2 / delta * car.F)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn linear_quarter_car_matches_closed_form() {
    let mut worst = 0.0f64;
    for p in [0.0, 0.25, 0.5, 0.75, 1.0] {
        let car = QuarterCar { k3: 0.0, p, ..QuarterCar::default() };
        let mut omega: f64 = 0.5;
        while omega <= 200.0 {
            let sol = solve(&car, omega, &SolveOptions::default(), None).unwrap();
            let out = sol.outputs(&car);
            let (z1, y) = closed_form(&car, omega);
            // x = Re(X e^{iθ}) = a cos θ + b sin θ with a = Re X, b = -Im X
            for (o, x) in [(&out[0], z1), (&out[2], y)] {
                let errs = [
                    rel(o.cos[1], x.re).min((o.cos[1] - x.re).abs() / x.norm()),
                    (o.sin[1] + x.im).abs() / x.norm(),
                    rel(o.amp1, x.norm()),
                    rel(o.max_abs, x.norm()),
                ];
                for e in errs {
                    worst = worst.max(e);
                    assert!(e < 1e-10, "p = {p}, Ω = {omega}: {} error {e:.2e}", o.name);
                }
                // a linear response has no mean and no higher harmonics
                let higher = o.cos[2..].iter().chain(&o.sin[2..]).chain([&o.cos[0]]);
                assert!(higher.into_iter().all(|c| c.abs() < 1e-12 * x.norm()));
            }
            omega *= 1.07;
        }
    }
    eprintln!("worst relative error {worst:.2e}");
}

#[test]
fn errata_reference_values_at_8_rad_s() {
    // |Z1/F| = 2.2972768, |Y/F| = 1.7136480 at Ω = 8 rad/s (the closed form, evaluated independently)
    let car = QuarterCar { k3: 0.0, ..QuarterCar::default() };
    let sol = solve(&car, 8.0, &SolveOptions::default(), None).unwrap();
    let out = sol.outputs(&car);
    assert!((out[0].amp1 / car.F - 2.2972768).abs() < 1e-6);
    assert!((out[2].amp1 / car.F - 1.7136480).abs() < 1e-6);
}
