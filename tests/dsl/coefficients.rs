//! Coefficient expressions: smooth functions of parameters and Ω. A delayed road input
//! `F cos(Ωt − Ωτ)` written with `cos(omega * tau)` / `sin(omega * tau)` coefficients
//! must be its hand-expanded twin with the coefficients as numbers; a mount whose
//! stiffness depends on Ω must match its closed-form response; ∂R/∂Ω from dual numbers
//! must match central differences; and a coefficient that is not finite where the
//! model is evaluated must be an error that names it, in the library and on the
//! command line.

use crate::common::{rel_diff, residual, residual_jacobian};
use ihbm::balance::Balance;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::fourier::coeff_len;
use ihbm::{Error, Model};
use num_complex::Complex64;

ihbm::oscillator! {
    /// A wheel meeting the road τ later: the delay in the coefficients of the forcing.
    pub struct Delayed {
        params { m = 1.0, c = 0.1, k = 1.0, k3 = 0.5, F = 0.3, tau = 0.4 }
        dofs { x }
        let road = F * cos(omega * tau) * cos(omega * t) + F * (omega * tau).sin() * sin(omega * t);
        equations { m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3) = road; }
    }
}

ihbm::oscillator! {
    /// The same with the two forcing amplitudes as parameters (set to F cos Ωτ, F sin Ωτ).
    pub struct Expanded {
        params { m = 1.0, c = 0.1, k = 1.0, k3 = 0.5, A = 0.0, B = 0.0 }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3) = A * cos(omega * t) + B * sin(omega * t);
        }
    }
}

ihbm::oscillator! {
    /// Every coefficient function at once, in a stiffness and a damping (no Ω in them).
    pub struct Functions {
        params { m = 1.0, a = 2.0, b = 0.3, q = 1.5, F = 0.2 }
        dofs { x }
        let ke = sqrt(a) * exp(b) / ln(a + 1.0) + tan(b).abs() * a.powf(q) + a.powi(-2);
        equations {
            m * D(x, 2) + b.cos() * (a * b).sin() * D(x, 1) + ke * x + b * x.powi(3)
                = F * cos(omega * t);
        }
    }
}

ihbm::oscillator! {
    /// The same stiffness and damping as parameters.
    pub struct Numbers {
        params { m = 1.0, ce = 0.0, ke = 0.0, b = 0.3, F = 0.2 }
        dofs { x }
        equations { m * D(x, 2) + ce * D(x, 1) + ke * x + b * x.powi(3) = F * cos(omega * t); }
    }
}

ihbm::oscillator! {
    /// A frequency-dependent mount: k(Ω) = k (1 + a ln(1 + Ω/w0)) and
    /// c(Ω) = c / sqrt(1 + (Ω/w0)²), fractional element, forced at Ω.
    pub struct Mount {
        params { m = 1.0, c = 0.2, k = 4.0, a = 0.3, w0 = 1.5, h = 0.1, p = 0.6, F = 1.0 }
        dofs { x }
        equations {
            m * D(x, 2) + c / sqrt(1.0 + (omega / w0).powi(2)) * D(x, 1)
                + k * (1.0 + a * ln(1.0 + omega / w0)) * x + h * D(x, p) = F * cos(omega * t);
        }
    }
}

ihbm::oscillator! {
    /// A stiffness that is not real above Ω = sqrt(k/m), and a pole at Ω = w1.
    pub struct Undefined {
        params { m = 1.0, c = 0.1, k = 4.0, w1 = 3.0, F = 1.0 }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + sqrt(k - m * omega.powi(2)) * x + x / (omega - w1)
                = F * cos(omega * t);
        }
    }
}

ihbm::oscillator! {
    /// A stiffness that is real below Ω = w1 and above w2, not between.
    pub struct Gap {
        params { m = 1.0, c = 0.1, k = 1.0, w1 = 2.0, w2 = 3.0, F = 0.1 }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + (k + sqrt((omega - w1) * (omega - w2))) * x
                = F * cos(omega * t);
        }
    }
}

/// Reproducible coefficients of size ~0.3 (a state, not a solution).
fn state(len: usize) -> Vec<f64> {
    (0..len).map(|i| 0.3 * ((i * 5 % 13) as f64 / 13.0 - 0.5)).collect()
}

#[test]
fn delayed_input_is_its_hand_expanded_twin() {
    let d = Delayed::default();
    let nh = 5;
    let a = state(coeff_len(nh));
    for omega in [0.5, 1.7, 4.0] {
        let (fc, fs) = (d.F * (omega * d.tau).cos(), d.F * (omega * d.tau).sin());
        let e = Expanded { A: fc, B: fs, ..Expanded::default() };
        let (r1, j1) = residual_jacobian(&d, nh, &a, omega);
        let (r2, j2) = residual_jacobian(&e, nh, &a, omega);
        assert!(rel_diff(&r1, &r2, 1e-3) < 1e-12, "Ω = {omega}: residual");
        assert!(rel_diff(&j1, &j2, 1e-3) < 1e-12, "Ω = {omega}: Jacobian");
    }
    // The coefficients depend on Ω: Ω is explicit, the signals stay affine where they
    // were (the forcing does not multiply them).
    assert!(d.explicit_omega() && !Expanded::default().explicit_omega());
    assert_eq!(d.affine_signals(), Expanded::default().affine_signals());
}

#[test]
fn every_coefficient_function_evaluates_as_in_f64() {
    let f = Functions::default();
    let (a, b, q) = (f.a, f.b, f.q);
    let ke = a.sqrt() * b.exp() / (a + 1.0).ln() + b.tan().abs() * a.powf(q) + 1.0 / (a * a);
    let ce = b.cos() * (a * b).sin();
    let n = Numbers { ke, ce, ..Numbers::default() };
    let nh = 3;
    let x = state(coeff_len(nh));
    let (r1, j1) = residual_jacobian(&f, nh, &x, 1.3);
    let (r2, j2) = residual_jacobian(&n, nh, &x, 1.3);
    assert!(rel_diff(&r1, &r2, 1e-3) < 1e-12 && rel_diff(&j1, &j2, 1e-3) < 1e-12);
    // No Ω in any coefficient: not explicit (Balance::new probes that claim).
    assert!(!f.explicit_omega());
    // ∂R/∂q through `a.powf(q)`, from the dual pass, against central differences.
    let qi = f.param_index("q").unwrap();
    let mut hb = Balance::new(&f, nh).unwrap();
    let mut dq = vec![0.0; hb.len()];
    hb.d_param(&x, 1.3, qi, &mut dq);
    let h = 1e-6;
    let rp = residual(&Functions { q: q + h, ..f.clone() }, nh, &x, 1.3);
    let rm = residual(&Functions { q: q - h, ..f.clone() }, nh, &x, 1.3);
    let fd: Vec<f64> = rp.iter().zip(&rm).map(|(p, m)| (p - m) / (2.0 * h)).collect();
    assert!(rel_diff(&dq, &fd, 1e-3) < 1e-7, "{dq:?} vs {fd:?}");
}

/// The mount is linear: X = F / (k(Ω) − mΩ² + i c(Ω) Ω + h (iΩ)^p), one harmonic.
#[test]
fn omega_dependent_mount_matches_its_closed_form() {
    let m = Mount::default();
    let closed = |w: f64| {
        let kw = m.k * (1.0 + m.a * (1.0 + w / m.w0).ln());
        let cw = m.c / (1.0 + (w / m.w0).powi(2)).sqrt();
        let iw = Complex64::new(0.0, w);
        (m.F / (kw - m.m * w * w + cw * iw + m.h * iw.powf(m.p))).norm()
    };
    for w in [0.5, 2.0, 2.4, 5.0] {
        let sol = solve(&m, w, &SolveOptions::default(), None).unwrap();
        let got = sol.outputs(&m)[0].amp1;
        let x = closed(w);
        assert!((got - x).abs() < 1e-12 * x, "Ω = {w}: {got} vs {x}");
    }
    // Traced through the resonance, every point is the closed form too (the predictor
    // uses ∂R/∂Ω, which here includes the coefficients' own derivatives).
    let curve = sweep(&m, 0.5, 5.0, &SweepOptions { harmonics: 3, ..Default::default() }).unwrap();
    assert_eq!(curve.segments.last().unwrap().ended.to_string(), "reached end");
    for p in &curve.points {
        let x = closed(p.omega);
        assert!((p.outputs[0].amp1 - x).abs() < 1e-9 * x, "Ω = {}", p.omega);
    }
}

/// ∂R/∂Ω from the dual pass (explicit Ω in the coefficients) against central
/// differences in Ω, also right after the Jacobian (where a model without explicit Ω
/// would reuse the signal gradients instead).
#[test]
fn d_omega_from_duals_matches_central_differences() {
    let nh = 4;
    let x = state(coeff_len(nh));
    for omega in [0.8, 2.2] {
        let check = |model: &dyn Fn(&[f64], f64) -> Vec<f64>, exact: Vec<f64>, what: &str| {
            let h = 1e-6 * omega;
            let (rp, rm) = (model(&x, omega + h), model(&x, omega - h));
            let fd: Vec<f64> = rp.iter().zip(&rm).map(|(p, m)| (p - m) / (2.0 * h)).collect();
            assert!(rel_diff(&exact, &fd, 1e-3) < 1e-7, "{what}, Ω = {omega}");
        };
        let (d, m) = (Delayed::default(), Mount::default());
        let mut hd = Balance::new(&d, nh).unwrap();
        let mut hm = Balance::new(&m, nh).unwrap();
        let (mut dd, mut dm) = (vec![0.0; hd.len()], vec![0.0; hm.len()]);
        let mut r = vec![0.0; hd.len()];
        let mut jac = faer::Mat::<f64>::zeros(hd.len(), hd.len());
        hd.jacobian(&x, omega, &mut r, jac.as_mut());
        hd.d_omega(&x, omega, &mut dd);
        hm.jacobian(&x, omega, &mut r, jac.as_mut());
        hm.d_omega(&x, omega, &mut dm);
        check(&|a, w| residual(&d, nh, a, w), dd, "delayed");
        check(&|a, w| residual(&m, nh, a, w), dm, "mount");
    }
}

#[test]
fn a_coefficient_that_is_not_finite_is_an_error_naming_it() {
    let u = Undefined::default();
    let opts = SolveOptions::default();
    // Below sqrt(k/m) = 2 and away from the pole: fine.
    assert!(solve(&u, 1.0, &opts, None).is_ok());
    match solve(&u, 2.5, &opts, None) {
        Err(Error::NonFiniteCoefficient { term, value, omega, params, .. }) => {
            assert_eq!(term, "sqrt(k - m * omega.powi(2))");
            assert!(value.is_nan() && omega == 2.5);
            assert_eq!(params, "m = 1, k = 4");
        }
        other => panic!("expected NonFiniteCoefficient, got {other:?}"),
    }
    let u2 = Undefined { k: 100.0, ..Undefined::default() };
    let e = solve(&u2, 3.0, &opts, None).unwrap_err().to_string();
    assert_eq!(
        e,
        "model 'undefined': the coefficient `1 / (omega - w1)` is inf at Ω = 3 rad/s \
         (w1 = 3); a coefficient must be finite wherever the model is evaluated: choose a \
         frequency range and parameter values where it is defined"
    );
    // A sweep into the region where it is undefined: an error before any step...
    let sopts = SweepOptions { harmonics: 3, ..Default::default() };
    let e = sweep(&u, 1.0, 2.5, &sopts).unwrap_err();
    assert!(matches!(e, Error::NonFiniteCoefficient { omega, .. } if omega == 2.5), "{e}");
    // ...and through it (defined at both ends, not between): each piece of the curve
    // (traced from either end) stops there, saying why, and no point is NaN.
    let curve = sweep(&Gap::default(), 1.0, 5.0, &sopts).unwrap();
    let why: Vec<String> = curve.segments.iter().map(|s| s.ended.to_string()).collect();
    assert!(
        why.iter()
            .any(|w| w.contains("the coefficient `sqrt((omega - w1) * (omega - w2))` is NaN")),
        "{why:?}"
    );
    assert!(!curve.points.is_empty());
    for p in &curve.points {
        let inside = p.omega > 2.0 + 1e-12 && p.omega < 3.0 - 1e-12;
        assert!(!inside && p.outputs[0].max_abs.is_finite(), "Ω = {}", p.omega);
    }
}

/// Time integration refuses the same coefficient.
#[test]
fn time_integration_refuses_an_undefined_coefficient() {
    let u = Undefined::default();
    let e = ihbm::timedomain::simulate(&u, 2.5, &Default::default()).unwrap_err();
    assert!(matches!(e, Error::NonFiniteCoefficient { .. }), "{e}");
}

#[test]
fn the_command_line_reports_it_in_one_line() {
    let cli = ihbm::Cli::new().model::<Undefined>("undefined");
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let code = cli.run_with(["ihbm", "solve", "undefined", "--omega", "2.5"], &mut out, &mut err);
    let err = String::from_utf8(err).unwrap();
    assert_ne!(code, 0);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("the coefficient `sqrt(k - m * omega.powi(2))` is NaN at Ω = 2.5"),
        "{err}"
    );
}

ihbm::oscillator! {
    /// A coefficient of parameters alone that is not real for k < k0.
    pub struct ParamOnly {
        params { m = 1.0, k = 1.0, k0 = 2.0, F = 1.0 }
        dofs { x }
        equations { m * D(x, 2) + 0.1 * D(x, 1) + sqrt(k - k0) * x = F * cos(omega * t); }
    }
}

/// Without Ω in its coefficients the model claims no explicit Ω, which `Balance::new`
/// probes; a NaN coefficient must still be reported as itself, not as a wrong claim.
#[test]
fn a_parameter_only_coefficient_is_named_too() {
    let m = ParamOnly::default();
    assert!(!m.explicit_omega());
    let e = solve(&m, 1.0, &SolveOptions::default(), None).unwrap_err();
    assert!(
        matches!(&e, Error::NonFiniteCoefficient { term, params, .. }
            if term == "sqrt(k - k0)" && params == "k = 1, k0 = 2"),
        "{e}"
    );
    assert!(solve(&ParamOnly { k: 3.0, ..m }, 1.0, &SolveOptions::default(), None).is_ok());
}

ihbm::oscillator! {
    /// A Duffing oscillator whose forcing amplitude is undefined for F in (0.09, 0.11)
    /// (and above the cusp's 0.0516 on either side, so fold curves run into the gap).
    pub struct ForcingGap {
        params { m = 1.0, c = 0.1, k = 1.0, k3 = 1.0, F = 0.3 }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3)
                = (F + 0.1 * ((F - 0.1).powi(2) - 1e-4).sqrt()) * cos(omega * t);
        }
    }
}

/// A fold curve that runs into parameter values where a coefficient is undefined ends
/// there, stalled, with the term named (not "non-finite residual"), and keeps what it
/// traced.
#[test]
fn a_fold_curve_stops_at_an_undefined_coefficient_naming_it() {
    use ihbm::bifurcation::{fold_curves, End, FoldCurveOptions};
    let model = ForcingGap::default();
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 1;
    opts.omega = (0.5, 3.0);
    let f = model.param_index("F").unwrap();
    let res = fold_curves(&model, f, 0.3, 0.01, &opts).unwrap();
    let c = res.curves.iter().find(|c| c.start == ihbm::bifurcation::RangeEnd::From).unwrap();
    assert!(c.points.len() > 3, "{:?}", c.ended);
    let End::Stalled(why) = &c.ended else { panic!("{:?}", c.ended) };
    let why = why.to_string();
    assert!(why.contains("sqrt") && why.contains("NaN"), "{why}");
    assert!(c.points.iter().all(|p| p.value >= 0.11 - 1e-9), "no point inside the gap");
}
