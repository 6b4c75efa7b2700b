//! A user crate's command line built with `ihbm::Cli::new().model::<M>(name)`
//! (examples/user_cli.rs), driven in-process through `run_with`.

#[allow(dead_code)]
#[path = "../../examples/user_cli.rs"]
mod user_cli;

use num_complex::Complex64;
use serde_json::Value;

fn run(args: &[&str]) -> (u8, String, String) {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let mut argv = vec!["user_cli"];
    argv.extend_from_slice(args);
    let code = user_cli::cli().run_with(argv, &mut out, &mut err);
    (code, String::from_utf8(out).unwrap(), String::from_utf8(err).unwrap())
}

#[test]
fn lists_exactly_the_registered_models() {
    let (code, out, _) = run(&["models"]);
    assert_eq!(code, 0);
    let names: Vec<&str> = out.lines().filter_map(|l| l.split_whitespace().next()).collect();
    assert_eq!(names, ["base-isolator", "my-quarter-car"]);
    // The built-in names are not there: the builder starts empty.
    let (code, _, err) = run(&["solve", "quarter-car", "--omega", "8"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown model 'quarter-car'") && err.contains("base-isolator"), "{err}");
}

#[test]
fn solves_the_user_model_against_its_closed_form() {
    // k3 = 0: X = F / (k - m Ω² + i c Ω + h (iΩ)^p), a single harmonic.
    let (code, out, err) =
        run(&["solve", "base-isolator", "--omega", "3", "--set", "h=0.5", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["model"], "base-isolator");
    let iw = Complex64::new(0.0, 3.0);
    let x = (1.0 / (4.0 - 9.0 + 0.05 * iw + 0.5 * iw.powf(0.5))).norm();
    let got = v["outputs"]["x"]["max_abs"].as_f64().unwrap();
    assert!((got - x).abs() < 1e-8 * x, "{got} vs {x}");
}

#[test]
fn renamed_builtin_model_keeps_its_name_in_results_and_errors() {
    let (code, out, _) = run(&["solve", "my-quarter-car", "--omega", "8", "--json"]);
    assert_eq!(code, 0);
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["model"], "my-quarter-car");
    let (code, _, err) = run(&["solve", "my-quarter-car", "--omega", "8", "--set", "zz=1"]);
    assert_eq!(code, 2);
    assert!(err.contains("'my-quarter-car'"), "{err}");
}

#[test]
fn empty_builder_has_no_models() {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let code = ihbm::Cli::new().run_with(["x", "models"], &mut out, &mut err);
    assert_eq!(code, 0);
    assert_eq!(String::from_utf8(out).unwrap(), "no models registered\n");
}

#[test]
fn user_models_get_sweep_param_too() {
    // BaseIsolator defaults m = 1, c = 0.05, h = 0.2, k = 4, k3 = 0, F = 1: linear, so
    // |X| = F / |k - mΩ² + icΩ + h (iΩ)^p| as the fractional order p moves.
    let (code, out, err) = run(&[
        "sweep-param",
        "base-isolator",
        "--param",
        "p",
        "--from",
        "0.2",
        "--to",
        "1.8",
        "--omega",
        "3",
        "--max-step",
        "0.05",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!((v["model"].as_str(), v["parameter"].as_str()), (Some("base-isolator"), Some("p")));
    let points = v["points"].as_array().unwrap();
    assert!(points.len() > 5);
    let iw = Complex64::new(0.0, 3.0);
    for pt in points {
        let p = pt["param"].as_f64().unwrap();
        let x = (1.0 / (4.0 - 9.0 + 0.05 * iw + 0.2 * iw.powf(p))).norm();
        let got = pt["outputs"]["x"]["max_abs"].as_f64().unwrap();
        assert!((got - x).abs() < 1e-8 * x, "p = {p}: {got} vs {x}");
    }
    // Errors name the registered model.
    let (code, _, err) = run(&[
        "sweep-param",
        "base-isolator",
        "--param",
        "zz",
        "--from",
        "0",
        "--to",
        "1",
        "--omega",
        "1",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown parameter 'zz'") && err.contains("'base-isolator'"), "{err}");
}
