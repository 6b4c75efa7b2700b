//! Limit cycles continued in a parameter, and the Hopf point they are born at:
//! the van der Pol family in μ against its small-μ expansion, and a self-excited
//! oscillator with a fractional damper, whose Hopf point is a closed form of `Z(iω)`
//! and whose cycles near it follow the normal form's square-root law.

use ihbm::backbone::{cycles, End, FamilyOptions};
use ihbm::models::VanDerPol;
use ihbm::results::Stability;
use std::f64::consts::PI;

ihbm::oscillator! {
    /// x'' - (mu - x²) x' + h D^p x + k x = 0: the equilibrium's damping is
    /// h ω^(p-1) sin(pπ/2) - mu, and it oscillates by itself once mu exceeds it.
    pub struct FracHopf {
        params {
            /// linear (negative) damping
            mu = 0.5,
            /// fractional damping coefficient
            h = 0.2,
            /// fractional order
            p = 0.5,
            /// stiffness
            k = 1.0,
        }
        dofs { x }
        equations {
            D(x, 2) - (mu - x.powi(2)) * D(x, 1) + h * D(x, p) + k * x = 0.0;
        }
        outputs { x }
    }
}

/// van der Pol, μ from 1 to -0.5: the cycle of amplitude 2 + O(μ²) and frequency
/// 1 - μ²/16 + O(μ⁴) lives on both sides of μ = 0 (stable for μ > 0; for μ < 0 time
/// runs backwards: unstable); the equilibrium's eigenvalues μ/2 ± i√(1 - μ²/4)
/// cross the imaginary axis at μ = 0 with ω = 1.
#[test]
fn the_van_der_pol_family_crosses_its_hopf_point_at_mu_zero() {
    let opts = FamilyOptions {
        param: "mu".into(),
        from: 1.0,
        to: -0.5,
        omega: 1.0,
        harmonics: 15,
        ..Default::default()
    };
    let f = cycles(&VanDerPol::default(), &opts).unwrap();
    assert_eq!(f.ended, End::ReachedEnd, "{} points", f.points.len());
    assert!((f.points.last().unwrap().value + 0.5).abs() < 1e-12);
    let h = f.hopf.expect("a Hopf point");
    assert!(h.value.abs() < 1e-10, "μ_H = {:e}", h.value);
    assert!((h.omega - 1.0).abs() < 1e-10, "ω_H = {}", h.omega);
    let mut small = 0;
    for p in &f.points {
        let mu: f64 = p.value;
        if mu.abs() <= 0.2 {
            let w = 1.0 - mu * mu / 16.0;
            assert!(
                (p.omega - w).abs() < 0.05 * mu.powi(4) + 1e-12,
                "μ = {mu}: ω = {} vs {w}",
                p.omega
            );
            let a = p.outputs[0].max_abs;
            assert!((a - 2.0).abs() < 0.1 * mu * mu + 1e-9, "μ = {mu}: amplitude {a}");
            small += 1;
        }
        if mu.abs() > 1e-3 {
            let want = if mu > 0.0 { Stability::Stable } else { Stability::Unstable };
            assert_eq!(p.stability, want, "μ = {mu}");
        }
    }
    assert!(small >= 5, "{small} points with |μ| <= 0.2");
}

/// The Hopf condition `Z(iω) = k - ω² - iωμ + h (iω)^p = 0`: the real part gives
/// `k - ω² + h ω^p cos(pπ/2) = 0` (solved here by bisection), the imaginary part
/// `μ_H = h ω^(p-1) sin(pπ/2)`. One harmonic of `x = A cos ωt` balances the damping
/// over a period when `A² = 4 (μ - μ_H)`, at the Hopf frequency (the cubic damping
/// has no in-phase part); the third harmonic corrects that by a relative
/// `a3/a1 ≈ A²/32`, so within `A²/8` of the law.
fn fractional_hopf(h: f64, p: f64, k: f64) -> (f64, f64) {
    let re = |w: f64| k - w * w + h * w.powf(p) * (p * PI / 2.0).cos();
    let (mut lo, mut hi) = (1e-6, 10.0 * (k + h).sqrt());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if re(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let w = 0.5 * (lo + hi);
    (h * w.powf(p - 1.0) * (p * PI / 2.0).sin(), w)
}

#[test]
fn a_fractional_self_excited_family_collapses_at_the_closed_form_hopf_point() {
    for (h, p) in [(0.2, 0.5), (0.3, 1.5), (0.0, 0.5)] {
        let model = FracHopf { h, p, ..Default::default() };
        let (mu_h, w_h) = fractional_hopf(h, p, model.k);
        let opts = FamilyOptions {
            param: "mu".into(),
            from: mu_h + 0.5,
            to: mu_h - 0.3,
            omega: w_h,
            harmonics: 11,
            ..Default::default()
        };
        let f = cycles(&model, &opts).unwrap();
        assert_eq!(f.ended, End::Collapsed, "h = {h}, p = {p}");
        let hopf = f.hopf.expect("a Hopf point");
        assert!(
            (hopf.value - mu_h).abs() < 1e-10,
            "h = {h}, p = {p}: μ_H = {} vs {mu_h}",
            hopf.value
        );
        assert!(
            (hopf.omega - w_h).abs() < 1e-10,
            "h = {h}, p = {p}: ω_H = {} vs {w_h}",
            hopf.omega
        );
        let mut near = 0;
        for pt in &f.points {
            let d = pt.value - mu_h;
            let a = pt.outputs[0].max_abs;
            assert!(d > 0.0, "a cycle below the Hopf point: μ - μ_H = {d:e}");
            if d < 0.05 {
                let law = 2.0 * d.sqrt();
                assert!(
                    (a / law - 1.0).abs() <= a * a / 8.0,
                    "h = {h}, p = {p}: μ - μ_H = {d:e}: A = {a} vs {law}"
                );
                near += 1;
            }
            assert_eq!(pt.stability, Stability::Stable, "h = {h}, p = {p}, μ = {}", pt.value);
        }
        assert!(near >= 5, "{near} points near the Hopf point");
    }
}

#[test]
fn bad_family_input_is_refused_with_the_reason() {
    let base = FamilyOptions {
        param: "mu".into(),
        from: 0.5,
        to: 0.1,
        omega: 1.0,
        harmonics: 7,
        ..Default::default()
    };
    let e = cycles(&VanDerPol::default(), &FamilyOptions { param: "nu".into(), ..base.clone() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("nu") && e.contains("mu"), "{e}");
    // below its Hopf point the equilibrium is stable and every amplitude damped: no
    // cycle to start from
    let e = cycles(&FracHopf::default(), &FamilyOptions { from: 0.0, ..base.clone() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("no limit cycle"), "{e}");
    let e =
        cycles(&VanDerPol::default(), &FamilyOptions { to: 0.5, ..base }).unwrap_err().to_string();
    assert!(e.contains("range"), "{e}");
}

/// The family is observable point by point, and an observer may stop it: what was
/// traced is kept, and it says it was stopped.
#[test]
fn an_observer_sees_every_point_and_may_stop_the_family() {
    use ihbm::backbone::{cycles_with, CycleFamily, FamilyEvent};
    use ihbm::continuation::Control;
    let opts = FamilyOptions {
        param: "mu".into(),
        from: 1.0,
        to: 0.1,
        omega: 1.0,
        harmonics: 7,
        ..Default::default()
    };
    let mut seen = Vec::new();
    let f = cycles_with(&VanDerPol::default(), &opts, &mut |_: &FamilyEvent, f: &CycleFamily| {
        seen.push(f.points.len());
        if f.points.len() >= 4 {
            Control::Stop
        } else {
            Control::Continue
        }
    })
    .unwrap();
    assert_eq!(f.ended, End::Stopped);
    assert_eq!(seen, [1, 2, 3, 4]);
    assert_eq!(f.points.len(), 4);
    // the equilibrium is unstable over the whole range covered: no Hopf point there
    // (its eigenvalues μ/2 ± i√(1 - μ²/4) have Re λ > 0 for μ in [0.1, 1])
    assert!(f.hopf.is_none(), "{:?}", f.hopf);
}
