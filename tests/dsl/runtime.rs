//! Models read at run time (`ihbm::runtime::RuntimeModel`) against the macro: the same
//! front end must accept the same text with the same messages at the same places, and
//! the compiled program must be the generated code's twin.
//!
//! - Every compile-fail case of the macro (`macros/diagnostics/tests/ui/*.rs`), read as
//!   a model file, fails with the message and at the line and column the compiler
//!   printed (`*.stderr`).
//! - Every built-in model, read from its own source text, has the compiled model's
//!   metadata, structure hints, residual and every derivative at random samples, and
//!   harmonic-balance residual and Jacobian, to 1e-12; and whole sweeps agree.

use crate::equivalence::{coeffs, harmonic_check, sample_check};
use crate::model_text::bodies;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{
    BaseExcited, Duffing, FractionalDuffing, HalfCar, Quadratic, QuarterCar, QuarterCarRide,
    TwoMassChain, VanDerPol,
};
use ihbm::runtime::RuntimeModel;
use ihbm::{Error, Model};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_macro_diagnostic_is_the_run_time_readers() {
    let dir = root().join("macros/diagnostics/tests/ui");
    let mut cases = 0;
    let mut entries: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries.iter().filter(|p| p.extension().is_some_and(|e| e == "rs")) {
        let text = std::fs::read_to_string(path).unwrap();
        let stderr = std::fs::read_to_string(path.with_extension("stderr")).unwrap();
        let message = stderr.lines().next().unwrap().strip_prefix("error: ").unwrap();
        let at = stderr.lines().nth(1).unwrap().rsplit(':').take(2).collect::<Vec<_>>();
        let (line, column): (usize, usize) = (at[1].parse().unwrap(), at[0].parse().unwrap());
        let body = &bodies(&text)[0];
        let file = path.file_name().unwrap().to_string_lossy().to_string();
        let e = RuntimeModel::from_text(body, &file)
            .err()
            .unwrap_or_else(|| panic!("{file}: accepted"));
        let first = e.to_string().lines().next().unwrap().to_string();
        // Errors about the whole invocation (an empty or truncated body) are placed by
        // the compiler at the macro call, by the reader at the end of the text: the
        // message must agree, the place only where it is inside the body.
        let invocation = text.lines().nth(line - 1).unwrap().contains("oscillator!");
        let prefix = format!("{file}:{line}:{column}: ");
        if invocation {
            assert!(first.ends_with(message), "{file}: {first:?}\n  vs {message:?}");
        } else {
            assert_eq!(first, format!("{prefix}{message}"), "{file}");
        }
        cases += 1;
    }
    assert!(cases >= 20, "{cases} cases");
}

/// `compiled` and the model read from its own source agree in everything.
fn twin_of<M: Model>(compiled: &M, runtime: &RuntimeModel, omega: f64) {
    assert_eq!(runtime.name(), compiled.name());
    assert_eq!(runtime.description(), compiled.description());
    assert_eq!(runtime.params_info(), compiled.params_info());
    assert_eq!(runtime.signals(), compiled.signals());
    assert_eq!(runtime.equations(), compiled.equations());
    assert_eq!(
        (runtime.degree(), runtime.max_forcing_harmonic(), runtime.parametric_harmonic()),
        (compiled.degree(), compiled.max_forcing_harmonic(), compiled.parametric_harmonic())
    );
    assert_eq!(runtime.affine_signals(), compiled.affine_signals());
    assert_eq!(runtime.explicit_omega(), compiled.explicit_omega());
    assert_eq!(runtime.outputs(), compiled.outputs());
    assert_eq!(runtime.output_signals(), compiled.output_signals());
    assert_eq!(
        (runtime.smooth(), runtime.outputs_smooth(), runtime.output_degree()),
        (compiled.smooth(), compiled.outputs_smooth(), compiled.output_degree())
    );
    // The expression outputs at the same samples, to rounding.
    let (no, nos) = (compiled.outputs().len(), compiled.output_signals().len());
    let params = compiled.param_values();
    for phase in [0.3, 4.0] {
        let os: Vec<f64> = (0..nos).map(|i| 0.011 * (2.0 + (i as f64).cos())).collect();
        let (mut a, mut b) = (vec![0.0; no], vec![0.0; no]);
        runtime.output_values(&params, omega, phase, &os, &mut a);
        compiled.output_values(&params, omega, phase, &os, &mut b);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{x} vs {y}");
        }
    }
    let ns = compiled.signals().len();
    for (k, phase) in [0.0, 0.7, 2.9, 5.1].into_iter().enumerate() {
        let sig: Vec<f64> = (0..ns).map(|i| 0.013 * (1.0 + ((i + 3 * k) as f64).sin())).collect();
        sample_check(runtime, compiled, &sig, omega, phase);
    }
    let n = 5;
    let len = compiled.dofs().len() * (2 * n + 1);
    let a = coeffs(&[0.01, -0.02, 0.005, 0.013, -0.007, 0.002, 0.0], len, 1.0);
    harmonic_check(runtime, compiled, n, &a, omega);
}

fn from_source(file: &str, which: usize) -> RuntimeModel {
    let text = std::fs::read_to_string(root().join("models").join(file)).unwrap();
    RuntimeModel::from_text(&bodies(&text)[which], file).unwrap()
}

#[test]
fn every_built_in_model_read_at_run_time_is_the_compiled_one() {
    twin_of(&QuarterCar::default(), &from_source("quarter_car.rs", 0), 8.0);
    twin_of(&Duffing::default(), &from_source("duffing.rs", 0), 1.2);
    twin_of(&FractionalDuffing::default(), &from_source("duffing.rs", 1), 1.2);
    twin_of(&TwoMassChain::default(), &from_source("chain.rs", 0), 1.5);
    twin_of(&BaseExcited::default(), &from_source("base_excited.rs", 0), 2.0);
    twin_of(&Quadratic::default(), &from_source("quadratic.rs", 0), 0.9);
    twin_of(&VanDerPol::default(), &from_source("van_der_pol.rs", 0), 1.0);
    twin_of(&HalfCar::default(), &from_source("half_car.rs", 0), 22.0);
    twin_of(&QuarterCarRide::default(), &from_source("quarter_car_ride.rs", 0), 60.0);
}

#[test]
fn sweeps_of_a_run_time_model_are_the_compiled_models() {
    // The quarter car with folds (its unstable branch and jumps), and the half car.
    let mut rt = from_source("quarter_car.rs", 0);
    rt.set_param("k3", 5e6).unwrap();
    rt.set_param("F", 0.03).unwrap();
    let qc = QuarterCar { k3: 5e6, F: 0.03, ..Default::default() };
    let opts = SweepOptions::default();
    let (a, b) = (sweep(&rt, 1.0, 100.0, &opts).unwrap(), sweep(&qc, 1.0, 100.0, &opts).unwrap());
    assert_eq!(a.points.len(), b.points.len());
    assert_eq!(a.folds.len(), 2);
    for (p, q) in a.points.iter().zip(&b.points) {
        assert!((p.omega - q.omega).abs() <= 1e-12 * q.omega, "{} vs {}", p.omega, q.omega);
        assert_eq!(p.stability.is_stable(), q.stability.is_stable());
        let scale = q.coeffs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let d = p.coeffs.iter().zip(&q.coeffs).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(d <= 1e-12 * scale, "Ω {}: {d:e}", q.omega);
    }
    let hc = from_source("half_car.rs", 0);
    let (a, b) = (
        sweep(&hc, 1.0, 100.0, &opts).unwrap(),
        sweep(&HalfCar::default(), 1.0, 100.0, &opts).unwrap(),
    );
    assert_eq!(a.points.len(), b.points.len());
}

#[test]
fn a_run_time_coefficient_that_is_not_finite_is_named() {
    let text = "struct Pole { params { m = 1.0, k = 4.0, w1 = 3.0, F = 1.0 } dofs { x }
        equations { m * D(x, 2) + sqrt(k - m * omega.powi(2)) * x + x / (omega - w1) = F * cos(omega * t); } }";
    let m = RuntimeModel::from_text(text, "pole.ihbm").unwrap();
    let e = ihbm::corrector::solve(&m, 2.5, &Default::default(), None).unwrap_err();
    match e {
        Error::NonFiniteCoefficient { ref term, ref params, omega, .. } => {
            assert_eq!(term, "sqrt(k - m * omega.powi(2))");
            assert_eq!(params, "m = 1, k = 4");
            assert_eq!(omega, 2.5);
        }
        other => panic!("{other}"),
    }
    let e = ihbm::corrector::solve(&m, 1.0, &Default::default(), None).map(|_| ());
    assert!(e.is_ok(), "{e:?}");
}

#[test]
fn unreadable_huge_and_missing_model_files_are_refused_with_their_place() {
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("ihbm-runtime-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bytes = dir.join("bytes.ihbm");
    std::fs::write(&bytes, b"struct S {\n  params { a\xff = 1.0 } }").unwrap();
    let e = RuntimeModel::from_file(&bytes).unwrap_err().to_string();
    assert!(e.contains("bytes.ihbm:2:13: not UTF-8"), "{e}");
    let huge = dir.join("huge.ihbm");
    std::fs::write(&huge, "/".repeat(ihbm::runtime::MAX_TEXT_BYTES + 1)).unwrap();
    let e = RuntimeModel::from_file(&huge).unwrap_err().to_string();
    assert!(e.contains("at most") && e.contains("huge.ihbm"), "{e}");
    let e = RuntimeModel::from_file(&dir.join("missing.ihbm")).unwrap_err().to_string();
    assert!(e.contains("missing.ihbm"), "{e}");
    // a syntax error, a missing equation, an unknown name: each placed
    for (text, at, needle) in [
        (
            "struct S { params { m = 1.0 } dofs { x }\nequations { m * D(x, 2) + = 0.0; } }",
            "2:27",
            "expected",
        ),
        (
            "struct S { params { m = 1.0 } dofs { x, y }\nequations { m * D(x, 2) = 0.0; } }",
            "2:1",
            "1 equation(s) for 2 DOF(s)",
        ),
        (
            "struct S { params { m = 1.0 } dofs { x }\nequations { m * D(x, 2) + q * x = 0.0; } }",
            "2:27",
            "`q`",
        ),
    ] {
        let e = RuntimeModel::from_text(text, "s.ihbm").unwrap_err().to_string();
        assert!(e.starts_with(&format!("s.ihbm:{at}: ")) && e.contains(needle), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_example_model_files_are_the_built_in_quarter_cars() {
    let m = RuntimeModel::from_file(&root().join("examples/quarter_car.ihbm")).unwrap();
    twin_of(&QuarterCar::default(), &m, 8.0);
    let m = RuntimeModel::from_file(&root().join("examples/quarter_car_ride.ihbm")).unwrap();
    twin_of(&QuarterCarRide::default(), &m, 60.0);
}

ihbm::oscillator! {
    /// Every form of a domain, for the twin test below.
    pub struct Domains {
        params {
            /// positive
            a = 1.0 in (0, inf),
            /// non-negative, half-open: quoted
            b = 0.0 in "[0, inf)",
            /// an open order
            p = 1.5 in (1, 2),
            /// closed both ends
            q = 2 in [0, 2],
            /// bounded above only
            r = -1 in "(-inf, -0.5]",
            /// no domain
            s = 3.0,
        }
        dofs { x }
        equations { a * D(x, 2) + (b + q + s) * D(x, 1) + D(x, p) - r * x = cos(omega * t); }
    }
}

/// A domain written in a model file is the macro's: the same `ParamInfo`, the same
/// refusals; and `Display` writes a domain in the form the reader reads back.
#[test]
fn run_time_domains_are_the_macros_and_display_reads_back() {
    use ihbm::model::{Bound, Domain};
    let text = std::fs::read_to_string(root().join("tests/dsl/runtime.rs")).unwrap();
    let body = bodies(&text).pop().unwrap();
    let mut rt = RuntimeModel::from_text(&body, "runtime.rs").unwrap();
    let compiled = Domains::default();
    assert_eq!(rt.params_info(), compiled.params_info());
    let d = |lower, upper| Domain { lower, upper };
    let expected = [
        d(Bound::Open(0.0), Bound::Unbounded),
        d(Bound::Closed(0.0), Bound::Unbounded),
        d(Bound::Open(1.0), Bound::Open(2.0)),
        d(Bound::Closed(0.0), Bound::Closed(2.0)),
        d(Bound::Unbounded, Bound::Closed(-0.5)),
        Domain::ANY,
    ];
    let got: Vec<Domain> = compiled.params_info().iter().map(|p| p.domain).collect();
    assert_eq!(got, expected);
    let shown: Vec<String> = got.iter().map(|d| d.to_string()).collect();
    assert_eq!(shown, ["(0, inf)", "[0, inf)", "(1, 2)", "[0, 2]", "(-inf, -0.5]", "(-inf, inf)"]);
    // the same refusal from both, the value left as it was
    for (name, bad) in [("a", 0.0), ("b", -1e-12), ("p", 2.0), ("q", 2.5), ("r", -0.4)] {
        let mut c = compiled.clone();
        let (e1, e2) = (rt.set_param(name, bad).unwrap_err(), c.set_param(name, bad).unwrap_err());
        assert_eq!(
            e1.to_string().replace("'domains'", "'x'"),
            e2.to_string().replace("'domains'", "'x'")
        );
        assert!(matches!(e1, Error::InvalidValue { .. }), "{e1}");
        assert_eq!(rt.param(name).unwrap(), c.param(name).unwrap());
    }
    rt.set_param("b", 0.0).unwrap();
    rt.set_param("q", 0.0).unwrap();
    rt.set_param("r", -0.5).unwrap();
    rt.set_param("s", -1e300).unwrap();
    // Display round trip: each domain, written into a model file, reads back as itself.
    let more = [
        d(Bound::Open(-1e300), Bound::Closed(1e-300)),
        d(Bound::Closed(0.1), Bound::Open(0.30000000000000004)),
        d(Bound::Closed(-2.5), Bound::Closed(-2.5)),
    ];
    for dom in expected.iter().chain(&more) {
        let mid = match (dom.lower, dom.upper) {
            (Bound::Unbounded, Bound::Unbounded) => 0.0,
            (Bound::Open(a) | Bound::Closed(a), Bound::Unbounded) => a + 1.0,
            (Bound::Unbounded, Bound::Open(b) | Bound::Closed(b)) => b - 1.0,
            (Bound::Open(a) | Bound::Closed(a), Bound::Open(b) | Bound::Closed(b)) => {
                if a == b {
                    a
                } else {
                    a / 2.0 + b / 2.0
                }
            }
        };
        let text = format!(
            "struct S {{ params {{ v = {mid:e} in \"{dom}\" }} dofs {{ x }} equations {{ v * x = 0.0; }} }}"
        );
        let m = RuntimeModel::from_text(&text, "s.ihbm").unwrap_or_else(|e| panic!("{dom}: {e}"));
        assert_eq!(m.params_info()[0].domain, *dom, "{text}");
    }
}

/// The checks of a model file's domain are the macro's, at the same places (the
/// compile-fail cases run through the reader above); here, that they come out of
/// `RuntimeModel` as `origin:line:col`.
#[test]
fn a_bad_domain_in_a_model_file_names_its_place() {
    let text = "struct S {\n  params {\n    p = 0.5 in (1, 2),\n    k = 1 in [0, inf]\n  }\n  dofs { x }\n  equations { k * x + D(x, p) = 0.0; }\n}";
    let e = RuntimeModel::from_text(text, "s.ihbm").unwrap_err().to_string();
    assert_eq!(e, "s.ihbm:3:9: the default 0.5 of `p` is outside its declared domain (1, 2)");
    let text = text.replace("0.5 in", "1.5 in");
    let e = RuntimeModel::from_text(&text, "s.ihbm").unwrap_err().to_string();
    assert!(e.starts_with("s.ihbm:4:21: an infinite end of a domain is open"), "{e}");
}
