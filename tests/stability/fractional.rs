//! Hill's method with a fractional term: for a linear fractional oscillator the
//! Floquet exponents are the roots of `m λ² + c λ + h λ^p + k = 0` (principal branch),
//! found here independently by scalar complex Newton.

use ihbm::balance::Balance;
use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::FractionalDuffing;
use ihbm::stability::{Hill, StabilityOptions};
use num_complex::Complex64;

fn root(m: f64, c: f64, k: f64, h: f64, p: f64, mut l: Complex64) -> Complex64 {
    for _ in 0..100 {
        let f = m * l * l + c * l + h * l.powf(p) + k;
        let df = 2.0 * m * l + c + h * p * l.powf(p - 1.0);
        let step = f / df;
        l -= step;
        if step.norm() < 1e-15 {
            break;
        }
    }
    l
}

#[test]
fn linear_fractional_exponents_are_the_characteristic_roots() {
    for (h, p, omega) in [(0.3, 0.5, 0.7), (0.5, 0.3, 2.0), (0.2, 1.5, 1.3), (0.3, 0.5, 3.1)] {
        let model = FractionalDuffing { m: 1.0, c: 0.05, k: 1.0, k3: 0.0, h, p, F: 0.1 };
        let n = 3;
        let sol = solve(&model, omega, &SolveOptions { harmonics: n, ..Default::default() }, None)
            .unwrap();
        let mut bal = Balance::new(&model, n).unwrap();
        let mut hill = Hill::new(&model, n).unwrap();
        let f = hill.analyse(&mut bal, &sol.coeffs, omega, &StabilityOptions::default()).unwrap();
        assert!(f.refined);
        assert!(f.stable);
        let expected = root(1.0, 0.05, 1.0, h, p, Complex64::new(0.0, 1.0));
        assert_eq!(f.exponents.len(), 2, "{:?}", f.exponents);
        // The exponent is defined modulo iΩ.
        for e in [expected, expected.conj()] {
            let hit = f.exponents.iter().any(|x| {
                let d = x - e;
                let k = (d.im / omega).round();
                (d - Complex64::new(0.0, k * omega)).norm() < 1e-9
            });
            assert!(hit, "h={h} p={p} Ω={omega}: {:?} vs {e}", f.exponents);
        }
        // The frozen-order candidates alone would be off: refinement matters.
        let frozen = StabilityOptions { refine: false, ..Default::default() };
        let g = hill.analyse(&mut bal, &sol.coeffs, omega, &frozen).unwrap();
        assert!((g.max_real - f.max_real).abs() > 1e-4, "{:?} vs {:?}", g.exponents, f.exponents);
    }
}

#[test]
fn negative_damping_is_unstable() {
    // m x'' - 0.1 x' + k x + h D^p x: the fractional damping (h sin(pπ/2) λ^p) is too
    // weak to cancel the negative viscous term, so the rest state grows.
    let model = FractionalDuffing { m: 1.0, c: -0.3, k: 1.0, k3: 0.0, h: 0.1, p: 0.5, F: 0.1 };
    let n = 2;
    let omega = 0.5;
    let sol =
        solve(&model, omega, &SolveOptions { harmonics: n, ..Default::default() }, None).unwrap();
    let mut bal = Balance::new(&model, n).unwrap();
    let mut hill = Hill::new(&model, n).unwrap();
    let f = hill.analyse(&mut bal, &sol.coeffs, omega, &StabilityOptions::default()).unwrap();
    let expected = root(1.0, -0.3, 1.0, 0.1, 0.5, Complex64::new(0.1, 1.0));
    assert!(expected.re > 0.0);
    assert!(!f.stable);
    assert!((f.max_real - expected.re).abs() < 1e-9, "{:?} vs {expected}", f.exponents);
}

/// The count of unstable roots by the argument principle ([`Hill::unstable_roots`])
/// against the characteristic roots of the linear fractional oscillator, found by the
/// scalar Newton above: `λ² + cλ + 0.3 λ^0.5 + k` has for `k = 1` no positive real
/// root (every term is positive at `c = 0.05`; at `c = -0.6` the sum stays above 0.9)
/// and a complex pair whose real part decides, and for `k = -1` exactly one positive
/// real root (the function increases from -1) with the other real one on the branch
/// cut. With Ω = 4 the pair lies inside the strip `|Im λ| < Ω/2`.
#[test]
fn counted_unstable_roots_are_the_characteristic_ones() {
    let (h, p, omega, n) = (0.3, 0.5, 4.0, 3);
    for (c, k) in [(0.05, 1.0), (-0.6, 1.0), (0.05, -1.0)] {
        let expected = if k > 0.0 {
            let pair = root(1.0, c, k, h, p, Complex64::new(0.0, 1.0));
            assert!(pair.im.abs() > 0.1 && pair.im.abs() < omega / 2.0, "{pair}");
            if pair.re > 0.0 {
                2
            } else {
                0
            }
        } else {
            let r = root(1.0, c, k, h, p, Complex64::new(1.0, 0.0));
            assert!(r.re > 0.0 && r.im.abs() < 1e-12, "{r}");
            1
        };
        let model = FractionalDuffing { m: 1.0, c, k, k3: 0.0, h, p, F: 0.1 };
        let sol = solve(&model, omega, &SolveOptions { harmonics: n, ..Default::default() }, None)
            .unwrap();
        let mut bal = Balance::new(&model, n).unwrap();
        let mut hill = Hill::new(&model, n).unwrap();
        let so = StabilityOptions::default();
        let count = hill.unstable_roots(&mut bal, &sol.coeffs, omega, &so).unwrap();
        assert_eq!(count, expected, "c = {c}, k = {k}");
        let f = hill.analyse(&mut bal, &sol.coeffs, omega, &so).unwrap();
        assert_eq!(f.stable, expected == 0, "c = {c}, k = {k}: {f:?}");
    }
}
