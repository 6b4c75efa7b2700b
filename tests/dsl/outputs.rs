//! Outputs as expressions: an acceleration, a tyre force with the road in it, a
//! suspension force with a fractional element, evaluated on the transform's grid and
//! projected onto the harmonics, against the closed form of the linear quarter car,
//! against time integration, and along a sweep (where the peaks of an output that
//! depends on Ω must be found where the closed form has them). The same model read as
//! text gives the macro's numbers.

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::model::{Model, OutputKind};
use ihbm::runtime::RuntimeModel;
use ihbm::timedomain::newmark::{PeriodicStart, Stepper, StepperOptions};
use num_complex::Complex64;
use proptest::prelude::*;

ihbm::oscillator! {
    /// The linear fractional quarter car with the outputs a suspension engineer reads.
    pub struct LinearCar {
        params {
            m1 = 240.0, m2 = 30.0, k1 = 16000.0, kt = 160000.0, c = 1000.0, h = 1000.0,
            p = 0.5, F = 0.01,
        }
        dofs { z1, z2 }
        let y = z1 - z2;
        let fs = k1 * y + c * D(y, 1) + h * D(y, p);
        equations {
            m1 * D(z1, 2) + fs = 0.0;
            m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - fs = 0.0;
        }
        outputs {
            z1, travel = z1 - z2, acc = D(z1, 2), tyre = kt * (z2 - F * cos(omega * t)), fs,
            load = 2.0 + 0.5 * (z1 - z2)
        }
    }
}

/// The same model as a model file.
const TEXT: &str = "
    /// The linear fractional quarter car with the outputs a suspension engineer reads.
    pub struct LinearCar {
        params {
            m1 = 240.0, m2 = 30.0, k1 = 16000.0, kt = 160000.0, c = 1000.0, h = 1000.0,
            p = 0.5, F = 0.01,
        }
        dofs { z1, z2 }
        let y = z1 - z2;
        let fs = k1 * y + c * D(y, 1) + h * D(y, p);
        equations {
            m1 * D(z1, 2) + fs = 0.0;
            m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - fs = 0.0;
        }
        outputs {
            z1, travel = z1 - z2, acc = D(z1, 2), tyre = kt * (z2 - F * cos(omega * t)), fs,
            load = 2.0 + 0.5 * (z1 - z2)
        }
    }";

/// The complex amplitudes `(Z1, Z2)` and the suspension's `K(iΩ)`, solved from the
/// 2×2 frequency response written out here (not by the library).
fn closed_form(m: &LinearCar, w: f64) -> (Complex64, Complex64, Complex64) {
    let iw = Complex64::new(0.0, w);
    let k = m.k1 + m.c * iw + m.h * iw.powf(m.p);
    let (a11, a12) = (k - m.m1 * w * w, -k);
    let (a21, a22) = (-k, k + m.kt - m.m2 * w * w);
    let b2 = Complex64::from(m.kt * m.F);
    let det = a11 * a22 - a12 * a21;
    (-a12 * b2 / det, a11 * b2 / det, k)
}

/// The expected first-harmonic amplitudes of `acc`, `tyre` and `fs` at Ω.
fn expected(m: &LinearCar, w: f64) -> [f64; 3] {
    let (z1, z2, k) = closed_form(m, w);
    [w * w * z1.norm(), m.kt * (z2 - m.F).norm(), (k * (z1 - z2)).norm()]
}

#[test]
fn outputs_that_are_expressions_match_the_closed_form_of_the_linear_quarter_car() {
    let macro_model = LinearCar::default();
    let file_model = RuntimeModel::from_text(TEXT, "car.ihbm").unwrap();
    // What each output is: combinations of DOFs stay exact combinations.
    let kinds: Vec<bool> =
        macro_model.outputs().iter().map(|o| matches!(o.kind, OutputKind::Expression(_))).collect();
    assert_eq!(kinds, [false, false, true, true, true, true]);
    assert_eq!(macro_model.outputs(), file_model.outputs());
    let opts = SolveOptions { harmonics: 3, ..Default::default() };
    for w in [3.0, 8.5, 20.0, 70.0] {
        let want = expected(&macro_model, w);
        for model in [&macro_model as &dyn ihbm::model::DynModel, &file_model] {
            let sol = solve(model, w, &opts, None).unwrap();
            let out = sol.outputs(model);
            for (k, name) in ["acc", "tyre", "fs"].iter().enumerate() {
                let o = out.iter().find(|o| o.name == *name).unwrap();
                assert!((o.amp1 - want[k]).abs() < 1e-9 * want[k], "{name} at {w}: {o:?}");
                // A pure harmonic: its peak is its amplitude, its RMS that over √2.
                assert!((o.max_abs - want[k]).abs() < 1e-9 * want[k], "{name}: {o:?}");
                assert!((o.rms - want[k] / 2f64.sqrt()).abs() < 1e-9 * want[k], "{name}");
                assert!(o.mean.abs() < 1e-9 * want[k] && (o.max + o.min).abs() < 1e-9 * want[k]);
            }
            // A constant term is a mean, the rest a scaled travel.
            let travel = out.iter().find(|o| o.name == "travel").unwrap();
            let load = out.iter().find(|o| o.name == "load").unwrap();
            assert!((load.mean - 2.0).abs() < 1e-12, "{load:?}");
            assert!((load.amp1 - 0.5 * travel.amp1).abs() < 1e-12 * travel.amp1);
            assert!((load.max - 2.0 - 0.5 * travel.max_abs).abs() < 1e-9);
        }
    }
}

#[test]
fn time_integration_reports_the_expression_outputs_of_the_periodic_solution() {
    // Started on the harmonic-balance solution, the fractional Newmark stepper stays
    // on it; its outputs (the acceleration, the tyre force with the road in it, the
    // suspension force whose fractional part has a memory of its own) follow the
    // outputs' Fourier series to the scheme's error.
    let model = LinearCar::default();
    let (w, nh) = (8.5, 3);
    let sol =
        solve(&model, w, &SolveOptions { harmonics: nh, ..Default::default() }, None).unwrap();
    let out = sol.outputs(&model);
    let period = std::f64::consts::TAU / w;
    let per = 2000;
    let dt = period / per as f64;
    let start = PeriodicStart::new(sol.coeffs.clone(), nh);
    let mut s = Stepper::on_periodic(&model, w, &start, &StepperOptions::new(dt, 3 * per)).unwrap();
    let names: Vec<&str> = model.outputs().iter().map(|o| &*o.name).collect();
    let mut worst = [0.0f64; 6];
    for step in 0..3 * per {
        s.step().unwrap();
        if step % 97 != 0 {
            continue;
        }
        let theta = w * s.time();
        for (k, o) in out.iter().enumerate() {
            let mut c = o.cos.clone();
            c.extend_from_slice(&o.sin[1..]);
            let hb = ihbm::fourier::eval(&c, theta);
            let err = (s.output(k) - hb).abs() / o.max_abs;
            worst[k] = worst[k].max(err);
        }
    }
    for (k, e) in worst.iter().enumerate() {
        assert!(*e < 2e-3, "{}: {e:e}", names[k]);
    }
}

#[test]
fn an_output_that_depends_on_omega_peaks_where_the_closed_form_does() {
    // The body's acceleration Ω²|Z1(Ω)| peaks above the body resonance and again near
    // wheel hop: its slope along the curve moves with Ω as well as with the
    // coefficients, and the located peaks are the closed form's maxima.
    let model = LinearCar::default();
    let opts = SweepOptions { harmonics: 3, ..Default::default() };
    let curve = sweep(&model, 2.0, 150.0, &opts).unwrap();
    let acc = curve.output_names.iter().position(|n| n == "acc").unwrap();
    let peaks: Vec<_> = curve.peaks.iter().filter(|p| p.output == acc).collect();
    assert_eq!(peaks.len(), 2, "{:?}", curve.peaks);
    let f = |w: f64| expected(&model, w)[0];
    for p in peaks {
        // The closed form's maximum near the peak, by golden-section search.
        let (mut a, mut b) = (0.8 * p.omega, 1.2 * p.omega);
        let g = (5f64.sqrt() - 1.0) / 2.0;
        while b - a > 1e-12 * p.omega {
            let (x1, x2) = (b - g * (b - a), a + g * (b - a));
            if f(x1) < f(x2) {
                a = x1;
            } else {
                b = x2;
            }
        }
        let top = 0.5 * (a + b);
        assert!(p.located, "{p:?}");
        assert!((p.omega - top).abs() < 1e-6 * top, "{p:?} vs {top}");
        assert!((p.value - f(top)).abs() < 1e-9 * f(top), "{p:?} vs {}", f(top));
    }
}

#[test]
fn outputs_with_reserved_taken_or_unknown_names_are_refused_where_they_are_written() {
    let model = |outputs: &str| {
        format!(
            "struct S {{ params {{ k = 1.0 }} dofs {{ x }}\n let f = k * x;\n \
             equations {{ D(x, 2) + f = cos(omega * t); }}\n outputs {{ {outputs} }} }}"
        )
    };
    let cases = [
        ("x, omega = x", 4, 15, "`omega` is a reserved name"),
        ("t = x", 4, 12, "`t` is a reserved name"),
        ("x = 2.0 * x", 4, 12, "output `x = ...` takes the name of a DOF"),
        ("k", 4, 12, "output `k` is a parameter"),
        ("v = D(x, 1) * q", 4, 26, "unknown name `q`"),
        ("x, x", 4, 15, "duplicate output name `x`"),
    ];
    for (outputs, line, column, message) in cases {
        let e = RuntimeModel::from_text(&model(outputs), "s.ihbm").err().unwrap().to_string();
        let at = format!("s.ihbm:{line}:{column}: {message}");
        assert!(e.contains(&at), "{outputs}: {e}");
    }
    // An output may be any expression an equation may hold, a product of DOFs too.
    let energy = model("f, e = 0.5 * k * x.powi(2) + 0.5 * D(x, 1).powi(2)");
    let m = RuntimeModel::from_text(&energy, "s.ihbm").unwrap();
    assert_eq!(m.output_degree(), 2);
}

proptest! {
    /// The RMS of a series from its coefficients (Parseval) is the RMS of its samples:
    /// a mean of squares over more than 4N + 1 equally spaced instants is exact for a
    /// squared series of N harmonics.
    #[test]
    fn rms_from_the_coefficients_is_the_rms_of_the_samples(
        c in proptest::collection::vec(-10.0f64..10.0, 1..=5).prop_flat_map(|a| {
            let n = a.len();
            (Just(a), proptest::collection::vec(-10.0f64..10.0, n))
        })
    ) {
        let (a, b) = c;
        let n = a.len() - 1;
        let mut coeffs = a.clone();
        coeffs.extend_from_slice(&b[1..]);
        let m = 4 * n + 3;
        let mean_square = (0..m)
            .map(|j| ihbm::fourier::eval(&coeffs, std::f64::consts::TAU * j as f64 / m as f64).powi(2))
            .sum::<f64>()
            / m as f64;
        let rms = ihbm::fourier::rms(&coeffs);
        prop_assert!((rms - mean_square.sqrt()).abs() <= 1e-12 * rms.max(1e-300));
    }
}

#[test]
fn a_sum_of_twenty_thousand_terms_is_refused_and_one_of_ten_thousand_read() {
    // Read at run time (from a test thread's small stack): the reader recurses per
    // operator, on a stack of its own.
    let model = |terms: usize| {
        format!(
            "struct S {{ params {{ k = 1.0 }} dofs {{ x }}\n equations {{ D(x, 2) + k * x = \
             cos(omega * t); }}\n outputs {{ s = x{} }} }}",
            " + x".repeat(terms)
        )
    };
    let e = RuntimeModel::from_text(&model(20_000), "long.ihbm").err().unwrap().to_string();
    assert!(e.contains("long.ihbm:3:") && e.contains("more than 10000 operators"), "{e}");
    let m = RuntimeModel::from_text(&model(9_990), "long.ihbm").unwrap();
    let sol = solve(&m, 0.5, &SolveOptions::default(), None).unwrap();
    let out = sol.outputs(&m);
    // s = 9991 x, an exact combination of DOFs.
    assert!(matches!(m.outputs()[0].kind, OutputKind::Dofs(_)));
    assert!((out[0].amp1 - 9991.0 * 1.0 / (1.0 - 0.25)).abs() < 1e-9 * out[0].amp1);
}

#[test]
fn the_half_cars_wheel_travel_with_parameter_coefficients_is_an_output() {
    // zf = z + a θ − yf has a parameter coefficient: an expression output, whose
    // coefficients are the DOFs' combined with a = 1.3 (computed here from the DOF
    // outputs of the same solution).
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/models/half_car.rs"))
        .unwrap();
    let body = crate::model_text::bodies(&text)[0]
        .replace("outputs { z, theta, yf, yr }", "outputs { z, theta, yf, yr, wheel = zf }");
    let m = RuntimeModel::from_text(&body, "half_car.ihbm").unwrap();
    assert!(matches!(m.outputs()[4].kind, OutputKind::Expression(_)));
    let sol = solve(&m, 9.0, &SolveOptions::default(), None).unwrap();
    let out = sol.outputs(&m);
    let a = m.param("a").unwrap();
    for k in 0..out[0].cos.len() {
        let want = |v: fn(&ihbm::results::OutputSummary) -> &Vec<f64>| {
            v(&out[0])[k] + a * v(&out[1])[k] - v(&out[2])[k]
        };
        let (c, s) = (want(|o| &o.cos), want(|o| &o.sin));
        assert!((out[4].cos[k] - c).abs() < 1e-12 * out[4].max_abs, "cos {k}");
        assert!((out[4].sin[k] - s).abs() < 1e-12 * out[4].max_abs, "sin {k}");
    }
}
