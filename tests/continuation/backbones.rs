//! Backbones (nonlinear modes by EPMC) against closed forms: the undamped Duffing
//! oscillator's exact backbone (Jacobi elliptic functions), the one-harmonic
//! fractional Duffing's EPMC amplitude equation, and the linear limit of the quarter
//! car (the damped modes of its linearisation, fractional part included).

use crate::elliptic::duffing_omega;
use ihbm::backbone::{backbone, BackboneOptions, End};
use ihbm::models::{Duffing, FractionalDuffing, QuarterCar};
use num_complex::Complex64;
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// x'' + x + k3 x³ = 0 with max |x| = a: Ω = π √(1 + k3 a²) / (2 K(m)),
/// m = k3 a² / (2 (1 + k3 a²)).
#[test]
fn the_undamped_duffing_backbone_is_the_elliptic_closed_form() {
    let model = Duffing { c: 0.0, ..Default::default() };
    let opts = BackboneOptions { to: 2.0, harmonics: 21, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    // the start is at max |x| = 2e-4: ω - 1 = O(¾ a²) = 3e-8
    assert!(rel(b.linear.0, 1.0) < 1e-7, "linear frequency {}", b.linear.0);
    let last = b.points.last().unwrap();
    assert!(rel(last.outputs[0].max_abs, 2.0) < 1e-10, "{}", last.outputs[0].max_abs);
    let mut checked = 0;
    for p in b.points.iter().step_by(3).chain([last]) {
        let a = p.outputs[0].max_abs;
        let exact = duffing_omega(model.k3, a);
        assert!(rel(p.omega, exact) < 1e-9, "a = {a}: ω = {} vs {exact}", p.omega);
        assert!(p.xi.abs() < 1e-12, "a conservative model has ξ = 0, got {}", p.xi);
        checked += 1;
    }
    assert!(checked >= 5);
}

/// One harmonic, x = a cos ωt: ω² - h ω^p cos(pπ/2) = k + ¾ k3 a² and
/// ξ = c + h ω^{p-1} sin(pπ/2) (m = 1), so D = ξ / (2ω).
#[test]
fn the_one_harmonic_fractional_duffing_mode_is_the_epmc_closed_form() {
    let model = FractionalDuffing::default();
    let opts = BackboneOptions { to: 1.5, harmonics: 1, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    let (h, p, c) = (model.h, model.p, model.c);
    let (cp, sp) = ((p * PI / 2.0).cos(), (p * PI / 2.0).sin());
    for pt in &b.points {
        let a = pt.outputs[0].amp1;
        // ω from the amplitude equation by Newton
        let mut w = pt.omega;
        for _ in 0..50 {
            let f = w * w - h * w.powf(p) * cp - model.k - 0.75 * model.k3 * a * a;
            let df = 2.0 * w - h * p * w.powf(p - 1.0) * cp;
            w -= f / df;
        }
        assert!(rel(pt.omega, w) < 1e-10, "a = {a}: ω = {} vs {w}", pt.omega);
        let d = (c + h * w.powf(p - 1.0) * sp) / (2.0 * w);
        assert!(rel(pt.damping, d) < 1e-10, "a = {a}: D = {} vs {d}", pt.damping);
    }
}

/// The linearised quarter car, z = φ e^{λt}: `Z(λ) φ = 0` with
/// `Z = [[m1 λ² + s, -s], [-s, m2 λ² + s + kt]]`, `s = k1 + c λ + h λ^p`. A backbone's
/// start solves `det(Z(iω) - iω ξ M) = 0` for (ω, ξ): found here by Newton on the
/// determinant from the undamped frequencies.
#[test]
fn quarter_car_backbones_start_at_the_damped_modes_of_the_linearisation() {
    let q = QuarterCar::default();
    let det = |w: f64, xi: f64| -> Complex64 {
        let l = Complex64::new(0.0, w);
        let s = q.k1 + q.c * l + q.h * l.powf(q.p);
        let a = q.m1 * l * l + s - xi * l * q.m1;
        let d = q.m2 * l * l + s + q.kt - xi * l * q.m2;
        a * d - s * s
    };
    for (mode, guess) in [(1, (q.k1 / q.m1).sqrt()), (2, ((q.k1 + q.kt) / q.m2).sqrt())] {
        let (mut w, mut xi) = (guess, 0.0);
        for _ in 0..60 {
            let f = det(w, xi);
            let (hw, hx) = (1e-7 * w, 1e-7 * w);
            let fw = (det(w + hw, xi) - det(w - hw, xi)) / (2.0 * hw);
            let fx = (det(w, xi + hx) - det(w, xi - hx)) / (2.0 * hx);
            // [Re fw Re fx; Im fw Im fx] [dw; dx] = -[Re f; Im f]
            let m = fw.re * fx.im - fx.re * fw.im;
            w -= (f.re * fx.im - fx.re * f.im) / m;
            xi -= (fw.re * f.im - f.re * fw.im) / m;
        }
        let opts =
            BackboneOptions { to: 0.05, mode, harmonics: 5, output: 2, ..Default::default() };
        let b = backbone(&q, &opts).unwrap();
        let first = &b.points[0];
        assert!(rel(first.omega, w) < 1e-7, "mode {mode}: ω = {} vs {w}", first.omega);
        let d = xi / (2.0 * w);
        assert!(rel(first.damping, d) < 1e-6, "mode {mode}: D = {} vs {d}", first.damping);
    }
}

#[test]
fn a_mode_beyond_the_dofs_is_refused() {
    let opts = BackboneOptions { to: 0.05, mode: 3, ..Default::default() };
    let e = backbone(&QuarterCar::default(), &opts).unwrap_err().to_string();
    assert!(e.contains("mode") && e.contains("1 to 2"), "{e}");
    let opts = BackboneOptions { to: -1.0, ..Default::default() };
    let e = backbone(&QuarterCar::default(), &opts).unwrap_err().to_string();
    assert!(e.contains("positive"), "{e}");
}

/// The softening Duffing oscillator (k3 = -1): the same closed form with m < 0 below
/// the separatrix (max |x| < 1), and the backbone cannot reach beyond it: it ends
/// stalled with its frequency near 0, the points traced kept.
#[test]
fn the_softening_backbone_matches_the_closed_form_and_stops_at_the_separatrix() {
    let model = Duffing { c: 0.0, k3: -1.0, ..Default::default() };
    let opts = BackboneOptions { to: 2.0, harmonics: 21, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert!(matches!(b.ended, End::Stalled(_)), "{:?}", b.ended);
    let mut checked = 0;
    for p in b.points.iter().filter(|p| p.outputs[0].max_abs < 0.8) {
        let a = p.outputs[0].max_abs;
        let exact = duffing_omega(model.k3, a);
        assert!(rel(p.omega, exact) < 1e-9, "a = {a}: ω = {} vs {exact}", p.omega);
        checked += 1;
    }
    assert!(checked >= 5, "{checked}");
    assert!(b.points.last().unwrap().omega < 0.05);
}

/// The van der Pol cycle `x'' - μ(1 - x²)x' + x = 0` against the small-μ expansion
/// (amplitude 2 + O(μ²), ω = 1 - μ²/16 + O(μ⁴)) and against RK4 of the equation
/// from a point of the cycle (after one period it is back, to the integration's
/// accuracy); its stability (the phase exponent left out) is stable.
#[test]
fn the_van_der_pol_cycle_matches_the_expansion_and_time_integration() {
    use ihbm::backbone::{cycle, CycleOptions};
    use ihbm::models::VanDerPol;
    for mu in [0.05, 0.1, 0.2] {
        let model = VanDerPol { mu, ..Default::default() };
        let c = cycle(&model, &CycleOptions { omega: 1.0, harmonics: 15, ..Default::default() })
            .unwrap();
        let w = 1.0 - mu * mu / 16.0;
        assert!(
            (c.omega - w).abs() < 0.05 * mu.powi(4) + 1e-12,
            "μ = {mu}: ω = {} vs {w}",
            c.omega
        );
        let a = c.outputs[0].max_abs;
        assert!((a - 2.0).abs() < 0.1 * mu * mu, "μ = {mu}: amplitude {a}");
        assert_eq!(c.stability, ihbm::results::Stability::Stable, "{:?}", c.exponents);
        // RK4 over one period from the cycle at t = 0
        let x0: f64 = c.outputs[0].cos.iter().sum();
        let v0: f64 =
            c.outputs[0].sin.iter().enumerate().map(|(k, s)| k as f64 * c.omega * s).sum();
        let f = |x: f64, v: f64| (v, mu * (1.0 - x * x) * v - x);
        let steps = 20_000;
        let h = c.period / steps as f64;
        let (mut x, mut v) = (x0, v0);
        for _ in 0..steps {
            let k1 = f(x, v);
            let k2 = f(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = f(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = f(x + h * k3.0, v + h * k3.1);
            x += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        assert!(
            (x - x0).abs() < 1e-9 && (v - v0).abs() < 1e-9,
            "μ = {mu}: ({x}, {v}) vs ({x0}, {v0})"
        );
    }
}

/// A model that is not self-excited has no cycle: the damped Duffing oscillator's
/// artificial damping stays positive.
#[test]
fn a_damped_model_has_no_limit_cycle() {
    use ihbm::backbone::{cycle, CycleOptions};
    let e =
        cycle(&Duffing::default(), &CycleOptions { omega: 1.0, ..Default::default() }).unwrap_err();
    assert!(e.to_string().contains("no limit cycle"), "{e}");
}
