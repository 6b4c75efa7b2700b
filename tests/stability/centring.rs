//! The selection of Floquet exponents by eigenvector centring, against an independent
//! source: the quarter car at small amplitude is nearly linear, and the exponents of
//! its 2-DOF linearisation are the roots of
//! `det(M λ² + (c λ + h λ^p) B + K) = 0` (`B = [[1, -1], [-1, 1]]`, principal branch),
//! found here by scalar complex Newton on the 2×2 determinant. Hill's method must
//! report them (modulo `iΩ`) at every Ω, also far below the wheel mode (77 rad/s),
//! where the truncated harmonics `kΩ ≤ 5Ω` do not reach it.

use ihbm::balance::Balance;
use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::QuarterCar;
use ihbm::stability::{Hill, StabilityOptions};
use num_complex::Complex64;

/// A root of the quarter car's linear characteristic determinant near `l`.
fn root(q: &QuarterCar, mut l: Complex64) -> Complex64 {
    for _ in 0..100 {
        let s = q.c * l + q.h * l.powf(q.p) + q.k1;
        let ds = q.c + q.h * q.p * l.powf(q.p - 1.0);
        let (a, b) = (q.m1 * l * l + s, q.m2 * l * l + s + q.kt);
        let f = a * b - s * s;
        let df = (2.0 * q.m1 * l + ds) * b + a * (2.0 * q.m2 * l + ds) - 2.0 * s * ds;
        let step = f / df;
        l -= step;
        if step.norm() < 1e-14 * l.norm() {
            break;
        }
    }
    l
}

/// The two linear modes (upper half plane): body and wheel, from the undamped
/// frequencies of `M⁻¹K` as starting points.
fn linear_modes(q: &QuarterCar) -> [Complex64; 2] {
    // det(K - ω² M) = 0: m1 m2 ω⁴ - (m1 (k1 + kt) + m2 k1) ω² + k1 kt = 0.
    let (a, b, c) = (q.m1 * q.m2, q.m1 * (q.k1 + q.kt) + q.m2 * q.k1, q.k1 * q.kt);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let (w1, w2) = (((b - disc) / (2.0 * a)).sqrt(), ((b + disc) / (2.0 * a)).sqrt());
    [root(q, Complex64::new(0.0, w1)), root(q, Complex64::new(0.0, w2))]
}

/// Distance between `a` and `b` modulo `iΩ`.
fn dist_mod(a: Complex64, b: Complex64, omega: f64) -> f64 {
    let d = a - b;
    let im = d.im - (d.im / omega).round() * omega;
    Complex64::new(d.re, im).norm()
}

/// Hill's exponents of the quarter car at `omega` (N = 5), and a bound on the
/// relative effect of the cubic spring: `3 k3 max|y|² / k1`.
fn exponents(q: &QuarterCar, omega: f64) -> (Vec<Complex64>, f64) {
    let n = 5;
    let sol = solve(q, omega, &SolveOptions { harmonics: n, ..Default::default() }, None).unwrap();
    let len = 2 * n + 1;
    let ymax: f64 = (0..len).map(|i| (sol.coeffs[i] - sol.coeffs[len + i]).abs()).sum();
    let mut bal = Balance::new(q, n).unwrap();
    let mut hill = Hill::new(q, n).unwrap();
    let f = hill.analyse(&mut bal, &sol.coeffs, omega, &StabilityOptions::default()).unwrap();
    assert!(f.stable && f.refined, "Ω = {omega}: {f:?}");
    (f.exponents, 3.0 * q.k3 * ymax * ymax / q.k1)
}

#[test]
fn weakly_nonlinear_exponents_are_the_linear_modes_at_every_frequency() {
    let q = QuarterCar::default();
    let modes = linear_modes(&q);
    // Sanity of the independent source: the wheel hop near sqrt((k1 + kt)/m2).
    assert!((modes[1].im - ((q.k1 + q.kt) / q.m2).sqrt()).abs() < 0.1 * modes[1].im);
    for omega in [1.0, 2.0, 3.7, 6.0, 9.5, 13.0, 20.0, 35.0, 60.0, 100.0] {
        let (exps, nl) = exponents(&q, omega);
        assert_eq!(exps.len(), 4, "Ω = {omega}: {exps:?}");
        for m in modes {
            for target in [m, m.conj()] {
                // The cubic spring shifts the modes by at most ~nl relative to |λ|.
                let tol = 1e-8 * m.norm() + 2.0 * nl * m.norm();
                let hits = exps.iter().filter(|&&e| dist_mod(e, target, omega) <= tol).count();
                assert_eq!(hits, 1, "Ω = {omega}: {target} (tol {tol:e}) in {exps:?}");
            }
        }
    }
}

#[test]
fn the_wheel_mode_is_selected_far_below_it() {
    let q = QuarterCar::default();
    let [body, wheel] = linear_modes(&q);
    let (exps, nl) = exponents(&q, 2.0);
    assert!(nl < 1e-6, "nearly linear at Ω = 2: {nl}");
    // The wheel mode decays much faster than the body mode: its real part identifies it.
    assert!(wheel.re < 5.0 * body.re, "{wheel} vs {body}");
    let wheels = exps.iter().filter(|e| (e.re - wheel.re).abs() <= 1e-6 * wheel.norm()).count();
    let bodies = exps.iter().filter(|e| (e.re - body.re).abs() <= 1e-6 * body.norm()).count();
    assert_eq!((wheels, bodies), (2, 2), "{exps:?}; linear modes {body}, {wheel}");
}
