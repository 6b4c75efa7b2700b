//! The stability of backbone points: where ξ = 0 (a conservative model) Hill's
//! exponents against the Floquet multipliers of the variational equations integrated
//! by RK4 over one period; where ξ ≠ 0 no verdict.

use ihbm::backbone::{backbone, BackboneOptions, End, ModePoint};
use ihbm::models::{Duffing, QuarterCar};
use ihbm::results::{Stability, Unknown};
use num_complex::Complex64;

ihbm::oscillator! {
    /// x1'' + x1 + k3 x1³ + e (x1 - x2) = 0, x2'' + w2² x2 + e (x2 - x1) = 0.
    pub struct CoupledDuffing {
        params {
            /// cubic stiffness
            k3 = 1.0,
            /// the second oscillator's frequency
            w2 = 1.7,
            /// coupling stiffness
            e = 0.1,
        }
        dofs { x1, x2 }
        equations {
            D(x1, 2) + x1 + k3 * x1.powi(3) + e * (x1 - x2) = 0.0;
            D(x2, 2) + w2 * w2 * x2 + e * (x2 - x1) = 0.0;
        }
        outputs { x1, x2 }
    }
}

/// The state `(x_d, ẋ_d)` of every DOF at t = 0 from a point's coefficients
/// (`[a0, cos 1..N, sin 1..N]` per DOF).
fn state0(p: &ModePoint, ndof: usize, nh: usize) -> Vec<f64> {
    let len = 2 * nh + 1;
    let mut s = Vec::new();
    for d in 0..ndof {
        let c = &p.coeffs[d * len..(d + 1) * len];
        s.push(c[..=nh].iter().sum());
        s.push((1..=nh).map(|k| k as f64 * p.omega * c[nh + k]).sum());
    }
    s
}

/// The trace of the monodromy matrix: the state and its 2n×2n variational matrix
/// integrated together over one period by RK4, `f` the vector field and `a` its
/// Jacobian; also how far the orbit is from closing.
fn monodromy_trace(
    s0: &[f64],
    period: f64,
    f: impl Fn(&[f64]) -> Vec<f64>,
    a: impl Fn(&[f64]) -> Vec<f64>,
) -> (f64, f64) {
    let n = s0.len();
    let mut y = s0.to_vec();
    for i in 0..n {
        y.extend((0..n).map(|j| (i == j) as u8 as f64));
    }
    let rhs = |y: &[f64]| {
        let (s, phi) = y.split_at(n);
        let mut out = f(s);
        let am = a(s);
        for i in 0..n {
            for j in 0..n {
                out.push((0..n).map(|k| am[i * n + k] * phi[k * n + j]).sum());
            }
        }
        out
    };
    let steps = 20_000;
    let h = period / steps as f64;
    let axpy = |y: &[f64], k: &[f64], c: f64| -> Vec<f64> {
        y.iter().zip(k).map(|(a, b)| a + c * b).collect()
    };
    for _ in 0..steps {
        let k1 = rhs(&y);
        let k2 = rhs(&axpy(&y, &k1, 0.5 * h));
        let k3 = rhs(&axpy(&y, &k2, 0.5 * h));
        let k4 = rhs(&axpy(&y, &k3, h));
        for i in 0..y.len() {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    let closing = (0..n).map(|i| (y[i] - s0[i]).abs()).fold(0.0, f64::max);
    ((0..n).map(|i| y[n + i * n + i]).sum(), closing)
}

/// The sum of the multipliers: 2 for the double zero exponent of a conservative mode
/// (the phase, and the neighbouring orbit of another energy, which `exponents` leaves
/// out), and `exp(λT)` of the others.
fn hill_trace(p: &ModePoint) -> Complex64 {
    let period = std::f64::consts::TAU / p.omega;
    Complex64::new(2.0, 0.0) + p.exponents.iter().map(|l| (l * period).exp()).sum::<Complex64>()
}

/// x'' + x + x³ = 0: both multipliers are 1 (the phase, and the neighbouring orbit of
/// another amplitude, which drifts in phase but does not grow), so tr Φ = 2; Hill
/// has no exponent away from 0.
#[test]
fn the_undamped_duffing_backbone_is_neutrally_stable() {
    let model = Duffing { c: 0.0, ..Default::default() };
    let nh = 15;
    let b = backbone(&model, &BackboneOptions { to: 1.5, harmonics: nh, ..Default::default() })
        .unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    let mut checked = 0;
    for p in b.points.iter().step_by(4).chain(b.points.last()) {
        assert_eq!(p.stability, Stability::Stable, "ω = {}: {:?}", p.omega, p.exponents);
        assert!(p.exponents.is_empty(), "{:?}", p.exponents);
        let s0 = state0(p, 1, nh);
        let k3 = model.k3;
        let (tr, closing) = monodromy_trace(
            &s0,
            std::f64::consts::TAU / p.omega,
            |s| vec![s[1], -s[0] - k3 * s[0].powi(3)],
            |s| vec![0.0, 1.0, -1.0 - 3.0 * k3 * s[0] * s[0], 0.0],
        );
        assert!(closing < 1e-8, "ω = {}: the orbit closes to {closing:e}", p.omega);
        assert!((tr - 2.0).abs() < 1e-7, "ω = {}: tr Φ = {tr}", p.omega);
        let ht = hill_trace(p);
        assert!((ht - tr).norm() < 1e-9, "ω = {}: Hill {ht} vs RK4 {tr}", p.omega);
        checked += 1;
    }
    assert!(checked >= 4, "{checked} points checked");
}

/// Two coupled oscillators, the first a Duffing: the first mode's multipliers are 1,
/// 1 and a pair `e^{±iθ}` (symplectic), so tr Φ = 2 + 2 cos θ. Hill's multipliers
/// (1, 1 and `exp(λT)` of the pair of exponents away from 0, on the imaginary axis)
/// sum to the trace of RK4's monodromy matrix, |cos θ| < 1 (neutral), and the
/// verdict is stable.
#[test]
fn a_conservative_two_dof_backbone_has_the_multipliers_of_the_variational_equations() {
    let model = CoupledDuffing::default();
    let nh = 15;
    let opts = BackboneOptions { to: 1.0, harmonics: nh, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    let (k3, w2, e) = (model.k3, model.w2, model.e);
    let mut checked = 0;
    for p in b.points.iter().step_by(5).chain(b.points.last()) {
        let s0 = state0(p, 2, nh);
        let (tr, closing) = monodromy_trace(
            &s0,
            std::f64::consts::TAU / p.omega,
            |s| {
                vec![
                    s[1],
                    -s[0] - k3 * s[0].powi(3) - e * (s[0] - s[2]),
                    s[3],
                    -w2 * w2 * s[2] - e * (s[2] - s[0]),
                ]
            },
            |s| {
                let d = -1.0 - 3.0 * k3 * s[0] * s[0] - e;
                vec![
                    0.0,
                    1.0,
                    0.0,
                    0.0, //
                    d,
                    0.0,
                    e,
                    0.0, //
                    0.0,
                    0.0,
                    0.0,
                    1.0, //
                    e,
                    0.0,
                    -w2 * w2 - e,
                    0.0,
                ]
            },
        );
        assert!(closing < 1e-8, "ω = {}: the orbit closes to {closing:e}", p.omega);
        let cos = (tr - 2.0) / 2.0;
        assert!(cos.abs() < 1.0 - 1e-3, "ω = {}: cos θ = {cos}", p.omega);
        let ht = hill_trace(p);
        assert!((ht - tr).norm() < 1e-9, "ω = {}: Hill {ht} vs RK4 {tr}", p.omega);
        assert_eq!(p.stability, Stability::Stable, "ω = {}: {:?}", p.omega, p.exponents);
        assert_eq!(p.exponents.len(), 2, "{:?}", p.exponents);
        assert!(p.exponents.iter().all(|l| l.re.abs() <= 1e-7 * p.omega), "{:?}", p.exponents);
        checked += 1;
    }
    assert!(checked >= 4, "{checked} points checked");
}

/// The quarter car's modes are damped (ξ ≠ 0 everywhere): no point is a motion of
/// the model, and none has a verdict; the JSON says `"stable": null`.
#[test]
fn a_damped_backbone_has_no_stability_verdict() {
    let q = QuarterCar::default();
    let b = backbone(&q, &BackboneOptions { to: 0.02, mode: 1, ..Default::default() }).unwrap();
    assert!(b.points.len() > 3);
    for p in &b.points {
        assert!(p.xi.abs() > 1e-3 * p.omega, "ξ = {}", p.xi);
        assert_eq!(p.stability, Stability::Unknown(Unknown::NotAMotion));
        assert!(p.exponents.is_empty());
    }
    let json = ihbm::report::backbone_json(&b);
    assert!(json["points"].as_array().unwrap().iter().all(|p| p["stable"].is_null()));
}
