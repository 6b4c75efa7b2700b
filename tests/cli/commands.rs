//! End-to-end tests of the `ihbm` binary: every command on good input, every bad-input
//! class, and the JSON documents field for field (as the book's output reference gives them).

use crate::common as cli_common;

/// The statistics every output reports, in the JSON's order.
const STATS: [&str; 6] = ["max_abs", "mean", "amp1", "rms", "min", "max"];

use cli_common::{assert_rejected, ihbm, stderr, stdout, tmp};
use num_complex::Complex64;
use serde_json::Value;

/// Keys of a JSON object, in order.
fn keys(v: &Value) -> Vec<&str> {
    v.as_object()
        .unwrap_or_else(|| panic!("not an object: {v}"))
        .keys()
        .map(|k| k.as_str())
        .collect()
}

/// |Z1/F|, |Y/F| of the linear quarter car (its closed form), Table 1 values.
fn linear_qc(omega: f64) -> (f64, f64) {
    let (m1, m2, k1, kt, c, h, p) = (240.0, 30.0, 16_000.0, 160_000.0, 1_000.0, 1_000.0, 0.5);
    let iw = Complex64::new(0.0, omega);
    let g = k1 + iw * c + h * iw.powf(p);
    let delta = m1 * m2 * omega.powi(4) - (kt * m1 + (m1 + m2) * g) * omega * omega + kt * g;
    ((kt * g / delta).norm(), (kt * m1 * omega * omega / delta).norm())
}

#[test]
fn models_lists_the_builtin_models_and_shows_one() {
    let o = ihbm(&["models"]);
    assert!(o.status.success());
    let s = stdout(&o);
    for m in ["quarter-car", "duffing", "fractional-duffing"] {
        assert!(s.lines().any(|l| l.split_whitespace().next() == Some(m)), "{m} missing: {s}");
    }
    let o = ihbm(&["models", "quarter-car"]);
    assert!(o.status.success());
    let s = stdout(&o);
    for p in ["m1", "m2", "k1", "k3", "kt", "c", "h", "p", "F", "z1", "y", "240", "160000"] {
        assert!(s.contains(p), "{p} missing: {s}");
    }
    let o = ihbm(&["models", "fractional-duffing"]);
    let s = stdout(&o);
    for p in ["m ", "c ", "k ", "k3", "h ", "p ", "F "] {
        assert!(s.contains(p), "{p} missing: {s}");
    }
}

#[test]
fn help_on_every_command() {
    for args in [
        vec!["--help"],
        vec!["models", "--help"],
        vec!["solve", "--help"],
        vec!["sweep", "--help"],
        vec!["sweep-param", "--help"],
        vec!["folds", "--help"],
        vec!["simulate", "--help"],
        vec!["run", "--help"],
    ] {
        let o = ihbm(&args);
        assert!(o.status.success(), "{args:?}");
        assert!(stdout(&o).contains("Usage"), "{args:?}: {}", stdout(&o));
    }
}

#[test]
fn solve_json_matches_the_contract_and_the_linear_closed_form() {
    // k3 = 0: the model is linear, |Z1| = F |Z1/F| (closed form), a single harmonic.
    let o = ihbm(&["solve", "quarter-car", "--omega", "8", "--set", "k3=0", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(
        keys(&v),
        [
            "model",
            "omega",
            "harmonics",
            "converged",
            "iterations",
            "residual_norm",
            "stable",
            "outputs",
            "aft_samples"
        ]
    );
    assert_eq!(v["model"], "quarter-car");
    assert_eq!(v["omega"].as_f64(), Some(8.0));
    assert_eq!(v["harmonics"].as_u64(), Some(5));
    assert_eq!(v["converged"], true);
    assert!(v["iterations"].is_u64());
    assert!(v["residual_norm"].as_f64().unwrap() >= 0.0);
    // A damped linear system: every periodic solution is asymptotically stable.
    assert_eq!(v["stable"], true);
    assert_eq!(keys(&v["outputs"]), ["z1", "z2", "y"]);
    for out in ["z1", "z2", "y"] {
        let o = &v["outputs"][out];
        assert_eq!(keys(o), ["max_abs", "mean", "amp1", "rms", "min", "max", "cos", "sin"]);
        let cos = o["cos"].as_array().unwrap();
        let sin = o["sin"].as_array().unwrap();
        assert_eq!((cos.len(), sin.len()), (6, 6));
        assert_eq!(sin[0].as_f64(), Some(0.0));
        assert_eq!(o["mean"], cos[0]);
        let (a1, b1) = (cos[1].as_f64().unwrap(), sin[1].as_f64().unwrap());
        assert!((o["amp1"].as_f64().unwrap() - a1.hypot(b1)).abs() <= 1e-15);
        // The other statistics from the series itself, sampled densely: the RMS by the
        // trapezoidal rule (exact for a trigonometric polynomial of degree < samples),
        // the extremes to the sampling's O(h²).
        let c: Vec<f64> = cos.iter().map(|x| x.as_f64().unwrap()).collect();
        let s: Vec<f64> = sin.iter().map(|x| x.as_f64().unwrap()).collect();
        let m = 20_000;
        let x: Vec<f64> = (0..m)
            .map(|j| {
                let th = std::f64::consts::TAU * j as f64 / m as f64;
                (0..6).map(|k| c[k] * (k as f64 * th).cos() + s[k] * (k as f64 * th).sin()).sum()
            })
            .collect();
        let rms = (x.iter().map(|v| v * v).sum::<f64>() / m as f64).sqrt();
        let (lo, hi) = x.iter().fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        let scale = hi.abs().max(lo.abs());
        assert!((o["rms"].as_f64().unwrap() - rms).abs() <= 1e-12 * scale, "{out}: {o}");
        let (min, max) = (o["min"].as_f64().unwrap(), o["max"].as_f64().unwrap());
        assert!(min <= lo + 1e-15 && lo - min < 1e-6 * scale, "{out}: {min} vs {lo}");
        assert!(max >= hi - 1e-15 && max - hi < 1e-6 * scale, "{out}: {max} vs {hi}");
        assert_eq!(o["max_abs"].as_f64().unwrap(), max.max(-min));
    }
    let (z1, y) = linear_qc(8.0);
    let got_z1 = v["outputs"]["z1"]["max_abs"].as_f64().unwrap();
    let got_y = v["outputs"]["y"]["max_abs"].as_f64().unwrap();
    assert!((got_z1 - 0.01 * z1).abs() < 1e-8 * z1, "{got_z1} vs {}", 0.01 * z1);
    assert!((got_y - 0.01 * y).abs() < 1e-8 * y, "{got_y} vs {}", 0.01 * y);
}

#[test]
fn solve_json_to_a_file_and_human_output() {
    let path = tmp("solve.json");
    let o = ihbm(&[
        "solve",
        "duffing",
        "--omega",
        "2.5",
        "--harmonics",
        "3",
        "--json",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(v["harmonics"].as_u64(), Some(3));
    assert_eq!(v["outputs"]["x"]["cos"].as_array().unwrap().len(), 4);
    let o = ihbm(&["solve", "quarter-car", "--omega", "8"]);
    assert!(o.status.success());
    assert!(stdout(&o).contains("z1"), "{}", stdout(&o));
}

#[test]
fn non_converged_solve_writes_json_and_fails() {
    // A nearly undamped, strongly forced Duffing oscillator from the linear guess.
    let path = tmp("nc.json");
    let args = [
        "solve",
        "duffing",
        "--omega",
        "3",
        "--set",
        "k3=100",
        "--set",
        "c=0.001",
        "--set",
        "F=100",
        "--json",
        path.to_str().unwrap(),
    ];
    let o = ihbm(&args);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("did not converge"), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(v["converged"], false);
    assert_eq!(keys(&v)[3], "converged");
}

#[test]
fn bad_inputs_fail_with_a_reason() {
    assert_rejected(
        &["solve", "no-such-model", "--omega", "8"],
        &["unknown model", "no-such-model", "quarter-car"],
    );
    assert_rejected(
        &["solve", "quarter-car", "--omega", "8", "--set", "k4=1"],
        &["unknown parameter", "k4"],
    );
    assert_rejected(&["solve", "quarter-car", "--omega", "8", "--set", "k3=abc"], &["abc", "k3"]);
    assert_rejected(&["solve", "quarter-car", "--omega", "8", "--set", "k3"], &["k3", "P=V"]);
    assert_rejected(&["solve", "quarter-car", "--omega", "eight"], &["eight", "--omega"]);
    assert_rejected(
        &["solve", "quarter-car", "--omega", "8", "--harmonics", "0"],
        &["harmonics", "0"],
    );
    assert_rejected(&["solve", "quarter-car", "--omega", "8", "--harmonics", "-3"], &["-3"]);
    // forcing at 2Ω needs two harmonics at least; one would drop it
    for cmd in [
        vec!["solve", "two-mass-chain", "--omega", "1", "--harmonics", "1"],
        vec!["sweep", "two-mass-chain", "--from", "0.5", "--to", "2", "--harmonics", "1"],
    ] {
        assert_rejected(&cmd, &["N = 1", "N >= 2", "2Ω", "two-mass-chain"]);
    }
    assert_rejected(&["solve", "quarter-car", "--omega", "0"], &["omega", "0"]);
    assert_rejected(&["solve", "quarter-car", "--omega", "-2"], &["omega", "-2"]);
    assert_rejected(&["solve", "quarter-car", "--omega", "NaN"], &["omega", "NaN"]);
    assert_rejected(&["solve", "quarter-car"], &["--omega"]);
    assert_rejected(&["sweep", "quarter-car", "--from", "10", "--to", "5"], &["from", "10", "5"]);
    assert_rejected(&["sweep", "quarter-car", "--from", "5", "--to", "5"], &["from"]);
    assert_rejected(&["sweep", "quarter-car", "--from", "0", "--to", "5"], &["from", "0"]);
    assert_rejected(&["sweep", "nope", "--from", "1", "--to", "5"], &["unknown model", "nope"]);
    assert_rejected(
        &["sweep", "quarter-car", "--from", "1", "--to", "5", "--harmonics", "0"],
        &["harmonics"],
    );
    assert_rejected(
        &["simulate", "quarter-car", "--omega", "8", "--scheme", "rk4"],
        &["rk4", "scheme"],
    );
    assert_rejected(&["simulate", "quarter-car", "--omega", "8", "--dt", "-1"], &["dt", "-1"]);
    assert_rejected(
        &["simulate", "quarter-car", "--omega", "8", "--periods", "3"],
        &["periods", "3"],
    );
    assert_rejected(
        &["simulate", "quarter-car", "--omega", "8", "--set", "m9=1"],
        &["unknown parameter", "m9"],
    );
    assert_rejected(&["models", "nope"], &["unknown model", "nope"]);
    assert_rejected(&["frobnicate"], &["frobnicate"]);
    assert_rejected(&[], &["no command"]);
    assert_rejected(&["run", "/definitely/not/here.toml"], &["/definitely/not/here.toml"]);
    // a range one rounding unit wide holds nothing to trace (it once piled 20 002
    // points on itself)
    assert_rejected(
        &["sweep", "duffing", "--from", "1", "--to", "1.0000000000000002"],
        &["frequency", "wider than 1e-9"],
    );
    assert_rejected(
        &[
            "sweep-param",
            "duffing",
            "--param",
            "F",
            "--from",
            "0.5",
            "--to",
            "0.5000000000000001",
            "--omega",
            "1",
        ],
        &["F", "wider than 1e-9"],
    );
}

/// A full disk fails the command, whichever writer meets it, and a device named as the
/// output is written, not replaced by a file (renaming a temporary file over
/// `/dev/full` once turned it into a regular file and reported success).
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_fails_every_writer() {
    use std::os::unix::fs::FileTypeExt;
    let full = std::path::Path::new("/dev/full");
    let is_device = || std::fs::metadata(full).is_ok_and(|m| m.file_type().is_char_device());
    if !is_device() {
        eprintln!("no /dev/full device here: nothing to check");
        return;
    }
    let sweep = ["sweep", "duffing", "--from", "0.5", "--to", "3"];
    for flag in ["--json", "--csv", "--plot"] {
        let mut args = sweep.to_vec();
        args.extend([flag, "/dev/full"]);
        assert_rejected(&args, &["/dev/full", "No space left"]);
        assert!(is_device(), "{flag} /dev/full replaced the device");
    }
    for args in [
        &["solve", "duffing", "--omega", "1", "--json"][..],
        &["solve", "duffing", "--omega", "1"],
        &sweep,
    ] {
        let device = std::fs::OpenOptions::new().write(true).open(full).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_ihbm"))
            .args(args)
            .stdout(device)
            .output()
            .unwrap();
        assert!(!o.status.success(), "{args:?} > /dev/full succeeded");
        assert!(stderr(&o).contains("No space left"), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn malformed_study_files_name_file_line_and_column() {
    // deeper than the TOML parser's recursion limit, which reports no place itself
    let deep_key = format!(
        "model = \"quarter-car\"\nfrequency = {{ from = 1.0, to = 2.0 }}\n\n{} = 1\n",
        ["a"; 100].join(".")
    );
    let deep_header = format!(
        "model = \"quarter-car\"\nfrequency = {{ from = 1.0, to = 2.0 }}\n[{}]\nx = 1\n",
        ["b"; 100].join(".")
    );
    let cases: [(&str, &[&str]); 9] = [
        (&deep_key, &[":4:", "recursion"]),
        (&deep_header, &[":3:", "recursion"]),
        ("model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 }\nbogus = 3\n", &[":3:1:", "bogus"]),
        ("model = \"quarter-car\"\nfrequency = { from = 1.0, to = \"x\" }\n", &[":2:32:", "invalid type"]),
        ("model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 \n", &[":2:"]),
        ("model = \"nope\"\nfrequency = { from = 1.0, to = 2.0 }\n", &[":1:9:", "unknown model", "nope"]),
        (
            "model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 }\n[[figure]]\nid = \"a\"\nparams = { k9 = 1.0 }\n",
            &[":5:12:", "unknown parameter", "k9"],
        ),
        // a figure's own model: its name checked, and its parameters are that model's
        (
            "model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 }\n[[figure]]\nid = \"a\"\nmodel = \"nope\"\n",
            &[":5:9:", "unknown model", "nope"],
        ),
        (
            "model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 }\n[[figure]]\nid = \"a\"\nmodel = \"half-car\"\nparams = { m1 = 1.0 }\n",
            &[":6:12:", "unknown parameter", "m1", "half-car"],
        ),
    ];
    for (i, (text, needles)) in cases.iter().enumerate() {
        let path = tmp(&format!("bad{i}.toml"));
        std::fs::write(&path, text).unwrap();
        let mut n = vec![path.to_str().unwrap()];
        n.extend_from_slice(needles);
        assert_rejected(
            &["run", path.to_str().unwrap(), "--out", tmp("bad_out").to_str().unwrap()],
            &n,
        );
    }
}

#[test]
fn sweep_writes_contract_json_csv_and_plot() {
    // A hardening Duffing oscillator (backbone bends right): two folds, a jump each way.
    let (csv, svg) = (tmp("duffing.csv"), tmp("duffing.svg"));
    let o = ihbm(&[
        "sweep",
        "duffing",
        "--from",
        "0.5",
        "--to",
        "2.5",
        "--harmonics",
        "1",
        "--set",
        "c=0.05",
        "--set",
        "F=0.2",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
        "--json",
        "-",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(&keys(&v)[..6], ["model", "harmonics", "points", "folds", "jumps", "segments"]);
    assert_eq!(v["model"], "duffing");
    assert_eq!(v["harmonics"].as_u64(), Some(1));
    let points = v["points"].as_array().unwrap();
    for p in points {
        assert_eq!(keys(p), ["omega", "stable", "outputs"]);
        assert!(p["stable"].is_boolean());
        assert_eq!(keys(&p["outputs"]), ["x"]);
        assert_eq!(keys(&p["outputs"]["x"]), STATS);
    }
    let folds = v["folds"].as_array().unwrap();
    assert_eq!(folds.len(), 2, "{}", v["folds"]);
    for f in folds {
        assert_eq!(keys(f), ["omega", "outputs"]);
        assert_eq!(keys(&f["outputs"]["x"]), STATS);
    }
    let jumps = v["jumps"].as_array().unwrap();
    assert!(
        jumps.iter().any(|j| j["direction"] == "up")
            && jumps.iter().any(|j| j["direction"] == "down")
    );
    for j in jumps {
        assert_eq!(keys(j), ["direction", "omega", "output", "from", "to"]);
    }
    for s in v["segments"].as_array().unwrap() {
        assert_eq!(keys(s), ["from_omega", "to_omega", "ended"]);
    }
    // One resonance peak, above every point of the curve (the closed form's check is
    // in the continuation tests).
    let peaks = v["peaks"].as_array().unwrap();
    assert_eq!(peaks.len(), 1, "{}", v["peaks"]);
    assert_eq!(keys(&peaks[0]), ["omega", "output", "value", "located"]);
    assert_eq!((&peaks[0]["output"], &peaks[0]["located"]), (&"x".into(), &true.into()));
    let top = peaks[0]["value"].as_f64().unwrap();
    assert!(points.iter().all(|p| p["outputs"]["x"]["max_abs"].as_f64().unwrap() <= top));
    // The middle branch between the folds is unstable (a saddle).
    assert!(points.iter().any(|p| p["stable"] == false));
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(csv.lines().next(), Some("omega,stable,x_max_abs,x_mean,x_amp1,x_rms,x_min,x_max"));
    assert_eq!(csv.lines().count(), 1 + points.len());
    let svg = std::fs::read_to_string(&svg).unwrap();
    roxmltree::Document::parse(&svg).unwrap();
}

#[test]
fn simulate_json_matches_the_contract_and_the_closed_form() {
    // Linear quarter car (k3 = 0) from rest: after 200 periods the steady amplitude is
    // the closed-form one up to the scheme's error and the t^-p transient.
    let o = ihbm(&[
        "simulate",
        "quarter-car",
        "--omega",
        "8",
        "--set",
        "k3=0",
        "--periods",
        "200",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    // The contract's keys, then the extension: the start-up transient left.
    assert_eq!(keys(&v), ["model", "omega", "dt", "periods", "scheme", "outputs", "start_up_left"]);
    assert_eq!(v["scheme"], "bdf2");
    assert_eq!(v["periods"].as_u64(), Some(200));
    assert!(v["dt"].as_f64().unwrap() > 0.0);
    assert_eq!(keys(&v["outputs"]), ["z1", "z2", "y"]);
    for out in ["z1", "z2", "y"] {
        // the contract's keys, then the extensions saying whether the run settled
        let k: Vec<&str> = keys(&v["outputs"][out]);
        assert_eq!(k[..6], STATS);
        assert_eq!(k[6..], ["drift", "steady"]);
        assert_eq!(v["outputs"][out]["steady"], true, "damped, 200 periods");
    }
    let (z1, y) = linear_qc(8.0);
    let got = v["outputs"]["z1"]["max_abs"].as_f64().unwrap();
    assert!((got - 0.01 * z1).abs() < 1e-3 * 0.01 * z1, "{got} vs {}", 0.01 * z1);
    // The linear response is a pure harmonic of amplitude A: amp1 = A, rms = A/√2,
    // min = -A, max = A, to the scheme's error.
    for (out, a) in [("z1", 0.01 * z1), ("y", 0.01 * y)] {
        let o = &v["outputs"][out];
        let g = |k: &str| o[k].as_f64().unwrap();
        for (got, want) in
            [(g("amp1"), a), (g("rms"), a / 2f64.sqrt()), (g("min"), -a), (g("max"), a)]
        {
            assert!((got - want).abs() < 1e-3 * a, "{out}: {got} vs {want} in {o}");
        }
    }
    let path = tmp("sim.json");
    let o = ihbm(&[
        "simulate",
        "duffing",
        "--omega",
        "2",
        "--scheme",
        "gl",
        "--periods",
        "40",
        "--json",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(v["scheme"], "gl");
}

/// Two outputs on one path would leave only the last written: refused before any work,
/// naming both flags (exit 2), and nothing is written.
#[test]
fn two_outputs_on_one_path_are_refused() {
    let dir = tmp("clash");
    let file = dir.join("same.out");
    let f = file.to_str().unwrap();
    for (a, b) in [("--csv", "--json"), ("--csv", "--plot"), ("--json", "--plot")] {
        let args = ["sweep", "duffing", "--from", "1", "--to", "2", a, f, b, f];
        assert_rejected(&args, &[a, b, "same file"]);
        assert_eq!(ihbm(&args).status.code(), Some(2));
        assert!(!file.exists(), "{a} {b}: nothing written");
    }
    // `--json -` goes to standard output: no clash with a file.
    let o = ihbm(&["sweep", "duffing", "--from", "1", "--to", "2", "--csv", f, "--json", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(file.exists());
}

/// A harmonic count too large for memory is refused at once with the largest N that
/// fits (it panicked inside faer at N = 100000 and looped forever from N = 2^62 on,
/// the sample count overflowing).
#[test]
fn harmonic_counts_beyond_memory_are_refused_with_the_largest_that_fits() {
    for n in ["100000", "4611686018427387904", "18446744073709551615"] {
        for cmd in [
            &["solve", "quarter-car", "--omega", "8"][..],
            &["sweep", "duffing", "--from", "1", "--to", "2"],
        ] {
            let mut args = cmd.to_vec();
            args.extend(["--harmonics", n]);
            assert_rejected(&args, &["N = ", "largest N that fits"]);
            assert_eq!(ihbm(&args).status.code(), Some(2), "{args:?}");
        }
    }
    // Within the harmonic balance's limit but beyond that of Hill's matrices (see
    // tests/stability/size.rs): refused before any solve, naming Hill's limit.
    let args = ["sweep", "quarter-car", "--from", "1", "--to", "2", "--harmonics", "3000"];
    assert_rejected(&args, &["Hill stability matrices", "largest N that fits"]);
}

/// A time integration that has not settled says so: an undamped linear oscillator
/// started from rest keeps its free vibration, beating with the forced one at
/// Ω - 1 = 0.05 rad/s (a beat of 21 forcing periods), so the last two blocks of 10
/// periods differ; with damping (decay time 2m/c = 20 s against about 1200 s
/// integrated) they agree.
#[test]
fn simulate_flags_a_run_that_is_not_steady() {
    let run = |set: &[&str]| {
        let mut args = vec!["simulate", "duffing", "--omega", "1.05", "--set", "k3=0"];
        for s in set {
            args.extend(["--set", s]);
        }
        args.push("--json");
        let o = ihbm(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
        v["outputs"]["x"].clone()
    };
    let undamped = run(&["c=0"]);
    assert_eq!(undamped["steady"], false, "{undamped}");
    assert!(undamped["drift"].as_f64().unwrap() > 1e-2, "{undamped}");
    let damped = run(&[]);
    assert_eq!(damped["steady"], true, "{damped}");
    let o = ihbm(&["simulate", "duffing", "--omega", "1.05", "--set", "k3=0", "--set", "c=0"]);
    assert!(stdout(&o).contains("warning: x is not steady"), "{}", stdout(&o));
}

/// The undamped linear oscillator forced at its natural frequency (m = k = 1, Ω = 1,
/// c = k3 = 0) has a singular Jacobian at the start: the JSON is still written
/// (failure as data) with the start x = 0, whose residual is the forcing `F cos Ωt`
/// alone (norm F = 0.5), and the reason.
#[test]
fn solve_with_a_singular_jacobian_writes_its_json() {
    let json = tmp("singular.json");
    let _ = std::fs::remove_file(&json);
    let mut args = vec!["solve", "duffing", "--omega", "1"];
    for p in ["c=0", "k3=0"] {
        args.extend(["--set", p]);
    }
    args.extend(["--json", json.to_str().unwrap()]);
    let o = ihbm(&args);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim_end().lines().count(), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("singular Jacobian"), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["converged"], false);
    assert_eq!(v["iterations"].as_u64(), Some(0));
    assert!((v["residual_norm"].as_f64().unwrap() - 0.5).abs() < 1e-15, "{v}");
    assert_eq!(v["stable"], Value::Null);
    assert_eq!(v["outputs"]["x"]["max_abs"].as_f64(), Some(0.0));
    assert!(v["failure"].as_str().unwrap().contains("singular"), "{v}");
}

/// Far above resonance 200 periods are too short for the body mode to decay (its
/// decay time is 2/ξ with ξ the EPMC damping; see tests/timedomain/settling.rs): the
/// JSON says how much is left and the table warns; at 10 rad/s nothing is left.
#[test]
fn simulate_warns_of_a_transient_too_slow_to_drift() {
    let o = ihbm(&["simulate", "quarter-car", "--omega", "1e6"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("warning: the start-up transient may dominate"), "{}", stdout(&o));
    let o = ihbm(&["simulate", "quarter-car", "--omega", "1e6", "--json"]);
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!(v["start_up_left"].as_f64().unwrap() > 0.99, "{v}");
    let o = ihbm(&["simulate", "quarter-car", "--omega", "10"]);
    assert!(!stdout(&o).contains("warning"), "{}", stdout(&o));
}

/// `folds`: the JSON's keys, the one-harmonic Duffing's cusp from
/// its amplitude equation (the triple root: `k - mΩ² = -√3 cΩ`,
/// `F² = 8 (cΩ)³ / (3√3 · 3k3/4)`), the CSV and the figure; bad input refused.
#[test]
fn folds_writes_contract_json_csv_and_plot() {
    let (csv, svg) = (tmp("folds.csv"), tmp("folds.svg"));
    let o = ihbm(&[
        "folds",
        "duffing",
        "--param",
        "F",
        "--from",
        "0.01",
        "--to",
        "0.3",
        "--omega-from",
        "0.5",
        "--omega-to",
        "3",
        "--harmonics",
        "1",
        "--json",
        "-",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(keys(&v)[..5], ["model", "harmonics", "parameter", "curves", "cusps"]);
    assert_eq!(v["model"], "duffing");
    assert_eq!(v["parameter"], "F");
    let curve = &v["curves"][0];
    assert_eq!(keys(curve)[..2], ["points", "ended"]);
    assert_eq!(curve["ended"], "reached end");
    let p = &curve["points"][0];
    assert_eq!(keys(p), ["omega", "value", "outputs"]);
    assert_eq!(keys(&p["outputs"]["x"]), STATS);
    let cusps = v["cusps"].as_array().unwrap();
    assert_eq!(cusps.len(), 1);
    let (c, m, k, k3) = (0.1, 1.0, 1.0, 1.0);
    let s3 = 3f64.sqrt();
    let omega_c = (s3 * c + (3.0f64 * c * c + 4.0 * m * k).sqrt()) / (2.0 * m);
    let f_c = (8.0 * (c * omega_c).powi(3) / (3.0 * s3 * 0.75 * k3)).sqrt();
    let rel = |a: &Value, b: f64| (a.as_f64().unwrap() - b).abs() / b;
    assert!(rel(&cusps[0]["value"], f_c) < 1e-8, "{} vs {f_c}", cusps[0]["value"]);
    assert!(rel(&cusps[0]["omega"], omega_c) < 1e-8, "{} vs {omega_c}", cusps[0]["omega"]);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("curve,omega,F,x_max_abs\n"), "{text}");
    assert_eq!(text.lines().count(), 1 + curve["points"].as_array().unwrap().len());
    let figure = std::fs::read_to_string(&svg).unwrap();
    assert!(figure.contains("<svg") && figure.contains("<polygon"), "no shaded region");
    assert_rejected(
        &[
            "folds",
            "duffing",
            "--param",
            "F",
            "--from",
            "0.001",
            "--to",
            "0.01",
            "--harmonics",
            "1",
        ],
        &["no fold", "F = 0.001", "F = 0.01"],
    );
    assert_rejected(&["folds", "duffing", "--param", "q", "--from", "0.1", "--to", "1"], &["q"]);
    assert_rejected(
        &["folds", "duffing", "--param", "F", "--from", "0.1", "--to", "0.1"],
        &["range of F"],
    );
}

/// `sweep --period 2`: the JSON of `sweep` with `"period": 2`, Ω
/// the forcing frequency, starting where the period-1 curve (traced separately) has
/// its period doubling; bad periods and ranges without period doubling refused.
/// x'' + 0.05x' + x + 0.5x² = 0.6 cos Ωt doubles its period at Ω = 1.87514 and
/// 2.06687 (Floquet multipliers −1 of the period-1 curve). The branch born at the first
/// runs away below 1.8; the one born at the second crosses Ω = 2 and must be traced too.
#[test]
fn sweep_period_two_follows_every_period_doubling() {
    let o = ihbm(&[
        "sweep",
        "quadratic",
        "--set",
        "k2=0.5",
        "--set",
        "F=0.6",
        "--from",
        "1.8",
        "--to",
        "2.1",
        "--period",
        "2",
        "--harmonics",
        "8",
        "--json",
        "-",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let starts: Vec<f64> = v["segments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["from_omega"].as_f64().unwrap())
        .collect();
    assert_eq!(starts.len(), 2, "{}", v["segments"]);
    for (start, pd) in starts.iter().zip([1.87514, 2.06687]) {
        assert!((start - pd).abs() < 1e-5 * pd, "a branch starts at {start}, not at {pd}");
    }
    let omegas: Vec<f64> =
        v["points"].as_array().unwrap().iter().map(|p| p["omega"].as_f64().unwrap()).collect();
    // the first branch lies below 1.875: points on both sides of Ω = 2 are the second's
    assert!(omegas.iter().any(|&w| (1.9..2.0).contains(&w)));
    assert!(omegas.iter().any(|&w| (2.0..2.06).contains(&w)));
}

#[test]
fn sweep_period_two_switches_at_the_period_doubling() {
    let o = ihbm(&[
        "sweep",
        "quadratic",
        "--from",
        "1.5",
        "--to",
        "2.6",
        "--harmonics",
        "4",
        "--json",
        "-",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let p1: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let pd = p1["bifurcations"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["kind"] == "period-doubling")
        .unwrap_or_else(|| panic!("no period doubling: {}", p1["bifurcations"]))["omega"]
        .as_f64()
        .unwrap();
    let o = ihbm(&[
        "sweep",
        "quadratic",
        "--from",
        "1.5",
        "--to",
        "2.6",
        "--period",
        "2",
        "--harmonics",
        "8",
        "--json",
        "-",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(keys(&v)[..6], ["model", "harmonics", "points", "folds", "jumps", "segments"]);
    assert_eq!(v["period"], 2);
    assert_eq!(v["harmonics"], 8);
    let points = v["points"].as_array().unwrap();
    let first = points[0]["omega"].as_f64().unwrap();
    assert!((first - pd).abs() < 1e-5 * pd, "starts at {first}, period doubling at {pd}");
    assert!(points.iter().all(|p| (1.5..=2.6).contains(&p["omega"].as_f64().unwrap())));
    assert_rejected(
        &["sweep", "quadratic", "--from", "1.5", "--to", "2.6", "--period", "3"],
        &["--period", "3"],
    );
    let o = ihbm(&["sweep", "duffing", "--from", "0.5", "--to", "3", "--period", "2"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no period doubling"), "{}", stderr(&o));
}

/// `folds --boundary period-doubling`: curves of period doubling, each point a
/// period-doubling point of an ordinary sweep at that parameter value.
#[test]
fn folds_follow_period_doubling_on_request() {
    let o = ihbm(&[
        "folds",
        "quadratic",
        "--param",
        "F",
        "--from",
        "0.3",
        "--to",
        "0.6",
        "--omega-from",
        "1.5",
        "--omega-to",
        "2.6",
        "--boundary",
        "period-doubling",
        "--harmonics",
        "4",
        "--json",
        "-",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["boundary"], "period-doubling");
    let curve =
        v["curves"].as_array().unwrap().iter().find(|c| c["ended"] == "reached end").unwrap();
    let pts = curve["points"].as_array().unwrap();
    let p = &pts[pts.len() / 2];
    let (omega, f) = (p["omega"].as_f64().unwrap(), p["value"].as_f64().unwrap());
    let set = format!("F={f}");
    let o = ihbm(&[
        "sweep",
        "quadratic",
        "--from",
        "1.5",
        "--to",
        "2.6",
        "--harmonics",
        "4",
        "--set",
        &set,
        "--json",
        "-",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let nearest = s["bifurcations"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| b["kind"] == "period-doubling")
        .map(|b| (b["omega"].as_f64().unwrap() - omega).abs() / omega)
        .fold(f64::INFINITY, f64::min);
    assert!(
        nearest < 1e-7,
        "F = {f}: no period doubling of the sweep near Ω = {omega} ({nearest:e})"
    );
}

/// `sweep --break-symmetry`: the JSON of `sweep` with `"branch": "symmetry-breaking"`,
/// starting at the symmetric curve's branch point; not together with `--period 2`.
#[test]
fn sweep_break_symmetry_switches_at_the_branch_point() {
    let base = [
        "sweep",
        "duffing",
        "--from",
        "0.2",
        "--to",
        "4",
        "--set",
        "F=2",
        "--set",
        "c=0.05",
        "--harmonics",
        "6",
    ];
    let o = ihbm(&[&base[..], &["--json", "-"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let sym: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let bp = sym["bifurcations"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["kind"] == "branch-point")
        .unwrap_or_else(|| panic!("no branch point: {}", sym["bifurcations"]))["omega"]
        .as_f64()
        .unwrap();
    let o = ihbm(&[&base[..], &["--break-symmetry", "--json", "-"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["branch"], "symmetry-breaking");
    let first = v["points"][0]["omega"].as_f64().unwrap();
    assert!((first - bp).abs() < 1e-5 * bp, "starts at {first}, branch point at {bp}");
    assert!(v["points"].as_array().unwrap().iter().any(|p| p["outputs"]["x"]["mean"]
        .as_f64()
        .unwrap()
        .abs()
        > 0.1));
    assert_rejected(&[&base[..], &["--break-symmetry", "--period", "2"]].concat(), &["--period"]);
}

/// `backbone` writes the JSON of the book's output reference: the undamped Duffing backbone
/// ends at max |x| = A with the elliptic closed form's frequency; a mode beyond the
/// DOFs is a usage error, and an amplitude the mode cannot reach (the softening
/// backbone's frequency falls to 0 at the separatrix, max |x| = √(k/|k3|) = 1) writes
/// what was traced and fails.
#[test]
fn backbone_writes_contract_json_and_keeps_what_it_traced() {
    let (csv, svg) = (tmp("backbone.csv"), tmp("backbone.svg"));
    let o = ihbm(&[
        "backbone",
        "duffing",
        "--to",
        "1",
        "--set",
        "c=0",
        "--harmonics",
        "15",
        "--json",
        "-",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(keys(&v)[..4], ["model", "harmonics", "mode", "points"]);
    assert_eq!(
        (v["model"].as_str(), v["harmonics"].as_u64(), v["mode"].as_u64()),
        (Some("duffing"), Some(15), Some(1))
    );
    let points = v["points"].as_array().unwrap();
    let last = points.last().unwrap();
    assert_eq!(keys(last)[..3], ["omega", "damping", "stable"]);
    // c = 0: a conservative mode, a motion of the model, neutrally stable (Hill)
    assert_eq!(last["stable"].as_bool(), Some(true));
    assert_eq!(keys(&last["outputs"]["x"]), STATS);
    assert!((last["outputs"]["x"]["max_abs"].as_f64().unwrap() - 1.0).abs() < 1e-9);
    // π √2 / (2 K(1/4)), K(1/4) = 1.685750354812596
    let exact = std::f64::consts::PI * 2f64.sqrt() / (2.0 * 1.685750354812596);
    assert!((last["omega"].as_f64().unwrap() - exact).abs() < 1e-9 * exact, "{}", last["omega"]);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("omega,damping,xi,amplitude,x_max_abs,x_mean,x_amp1,x_rms,x_min,x_max\n"),
        "{text}"
    );
    assert_eq!(text.lines().count(), 1 + points.len());
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));

    assert_rejected(
        &["backbone", "quarter-car", "--to", "0.1", "--mode", "3"],
        &["mode", "1 to 2"],
    );
    assert_rejected(&["backbone", "duffing", "--to", "0"], &["amplitude", "positive"]);
    assert_rejected(&["backbone", "duffing", "--to", "1", "--output", "q"], &["q"]);
    let soft = tmp("soft.csv");
    let o = ihbm(&[
        "backbone",
        "duffing",
        "--to",
        "2",
        "--set",
        "c=0",
        "--set",
        "k3=-1",
        "--csv",
        soft.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("did not reach max |x| = 2") && err.contains("written"), "{err}");
    let rows = std::fs::read_to_string(&soft).unwrap();
    // the frequency falls towards 0 as the orbit nears the separatrix (its period
    // diverges); with finitely many harmonics the branch gets there slightly beyond
    // max |x| = 1
    let last: Vec<f64> =
        rows.lines().last().unwrap().split(',').map(|x| x.parse().unwrap()).collect();
    assert!(
        rows.lines().count() > 10 && last[0] < 1e-2,
        "ω = {} at max |x| = {}",
        last[0],
        last[4]
    );
    assert!(last[4] > 0.99 && last[4] < 1.2, "{}", last[4]);
}

/// `cycle` writes the JSON of the book's output reference; at μ = 2 the van der Pol cycle's
/// period is 7.62987 s (the classical value, Hairer–Wanner's tables), and a model
/// without self-excitation fails with the reason.
#[test]
fn cycle_writes_contract_json() {
    let o = ihbm(&[
        "cycle",
        "van-der-pol",
        "--omega",
        "1",
        "--set",
        "mu=2",
        "--harmonics",
        "40",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(
        keys(&v)[..7],
        ["model", "harmonics", "converged", "omega", "period", "stable", "outputs"]
    );
    assert_eq!(v["stable"], true);
    assert_eq!(
        keys(&v["outputs"]["x"]),
        ["max_abs", "mean", "amp1", "rms", "min", "max", "cos", "sin"]
    );
    let period = v["period"].as_f64().unwrap();
    assert!((period - 7.62987).abs() < 1e-5, "{period}");
    let o = ihbm(&["cycle", "duffing", "--omega", "1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no limit cycle"), "{}", stderr(&o));
    assert_rejected(&["cycle", "van-der-pol", "--omega", "-1"], &["frequency guess"]);
}

/// `cycle --param` continues the van der Pol cycle in μ through its Hopf point at
/// μ = 0 (the equilibrium's eigenvalues μ/2 ± i√(1 - μ²/4)): the JSON names it with
/// ω = 1, every point keeps amplitude 2 + O(μ²) and ω = 1 - μ²/16 + O(μ⁴), stable
/// for μ > 0 and unstable for μ < 0; CSV and SVG are written; bad input fails with
/// the reason.
#[test]
fn cycle_families_write_points_and_the_hopf_point() {
    let (csv, svg) = (tmp("cycles.csv"), tmp("cycles.svg"));
    let o = ihbm(&[
        "cycle",
        "van-der-pol",
        "--omega",
        "1",
        "--param",
        "mu",
        "--from",
        "1",
        "--to",
        "-0.5",
        "--harmonics",
        "15",
        "--json",
        "-",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["parameter"], "mu");
    assert_eq!(v["ended"], "reached end");
    assert!(v["hopf"]["value"].as_f64().unwrap().abs() < 1e-10, "{}", v["hopf"]);
    assert!((v["hopf"]["omega"].as_f64().unwrap() - 1.0).abs() < 1e-10, "{}", v["hopf"]);
    let points = v["points"].as_array().unwrap();
    assert_eq!(keys(&points[0])[..5], ["value", "omega", "period", "stable", "outputs"]);
    for p in points {
        let (mu, w) = (p["value"].as_f64().unwrap(), p["omega"].as_f64().unwrap());
        let period = p["period"].as_f64().unwrap();
        assert!((period * w - 2.0 * std::f64::consts::PI).abs() < 1e-12);
        if mu.abs() <= 0.2 {
            assert!(
                (w - (1.0 - mu * mu / 16.0)).abs() < 0.05 * mu.powi(4) + 1e-12,
                "μ = {mu}: {w}"
            );
            let a = p["outputs"]["x"]["max_abs"].as_f64().unwrap();
            assert!((a - 2.0).abs() < 0.1 * mu * mu + 1e-9, "μ = {mu}: {a}");
        }
        if mu.abs() > 1e-3 {
            assert_eq!(p["stable"], mu > 0.0, "μ = {mu}");
        }
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("mu,omega,period,stable,x_max_abs,x_mean,x_amp1,x_rms,x_min,x_max\n"),
        "{text}"
    );
    assert_eq!(text.lines().count(), 1 + points.len());
    assert!(std::fs::read_to_string(&svg).unwrap().contains("Hopf point"));

    assert_rejected(
        &["cycle", "van-der-pol", "--omega", "1", "--param", "nu", "--from", "1", "--to", "0"],
        &["nu", "mu"],
    );
    let o =
        ihbm(&["cycle", "duffing", "--omega", "1", "--param", "c", "--from", "0.1", "--to", "0.2"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no limit cycle"), "{}", stderr(&o));
    assert_rejected(
        &["cycle", "van-der-pol", "--omega", "1", "--param", "mu", "--from", "1"],
        &["--to"],
    );
}

/// `sweep --plot --backbone` draws the Duffing oscillator's backbone over the sweep,
/// continued to the sweep's largest amplitude: a dotted polyline with its legend
/// entry, whose vertices are the points of `ihbm backbone --to A_max` (an affine
/// image of them, to the SVG's 0.01-pixel rounding).
#[test]
fn sweep_plots_carry_the_backbone_of_the_modes_in_range() {
    let svg = tmp("sweep-backbone.svg");
    let o = ihbm(&[
        "sweep",
        "duffing",
        "--from",
        "0.5",
        "--to",
        "3",
        "--harmonics",
        "5",
        "--json",
        "-",
        "--plot",
        svg.to_str().unwrap(),
        "--backbone",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let top = v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["outputs"]["x"]["max_abs"].as_f64().unwrap())
        .fold(0.0f64, f64::max);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("backbone, mode 1"), "no legend entry");
    let doc = roxmltree::Document::parse(&text).unwrap();
    let lines: Vec<Vec<(f64, f64)>> = doc
        .descendants()
        .filter(|n| n.attribute("data-overlay") == Some("backbone mode 1 x"))
        .map(|n| {
            n.attribute("points")
                .unwrap()
                .split_whitespace()
                .map(|xy| {
                    let (x, y) = xy.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect();
    let [line] = lines.as_slice() else { panic!("one backbone polyline: {}", lines.len()) };
    let o = ihbm(&["backbone", "duffing", "--to", &top.to_string(), "--harmonics", "5", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let b: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let pts: Vec<(f64, f64)> = b["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["omega"].as_f64().unwrap(), p["outputs"]["x"]["max_abs"].as_f64().unwrap()))
        .collect();
    assert_eq!(line.len(), pts.len());
    assert!((pts.last().unwrap().1 - top).abs() < 1e-9 * top);
    let (p0, p1, q0, q1) = (pts[0], pts[pts.len() - 1], line[0], line[line.len() - 1]);
    let (ax, ay) = ((q1.0 - q0.0) / (p1.0 - p0.0), (q1.1 - q0.1) / (p1.1 - p0.1));
    for (p, q) in pts.iter().zip(line) {
        let (x, y) = (q0.0 + ax * (p.0 - p0.0), q0.1 + ay * (p.1 - p0.1));
        assert!(
            (x - q.0).abs() < 0.02 && (y - q.1).abs() < 0.02,
            "{p:?} drawn at {q:?}, expected ({x}, {y})"
        );
    }
    assert_rejected(&["sweep", "duffing", "--from", "0.5", "--to", "3", "--backbone"], &["--plot"]);
}

/// `backbone --json` reports the internal resonances met: the two-mass chain with its
/// second mode moved up (k2 = 7, no quadratic spring, no fractional damper: the
/// linear model is `K = [[k1 + kc, -kc], [-kc, k2 + kc]]`, `M = diag(m1, m2)`) has
/// the third harmonic of its stiffening first mode cross the second mode's linear
/// frequency at exactly a third of it.
#[test]
fn backbone_json_lists_the_internal_resonances_met() {
    let o = ihbm(&[
        "backbone",
        "two-mass-chain",
        "--to",
        "1.5",
        "--harmonics",
        "9",
        "--set",
        "k2=7",
        "--set",
        "kq=0",
        "--set",
        "hc=0",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let events = v["events"].as_array().unwrap();
    let [ev] = events.as_slice() else { panic!("one event: {events:?}") };
    assert_eq!(keys(ev)[..5], ["kind", "omega", "amplitude", "ratio", "mode"]);
    assert_eq!(
        (ev["kind"].as_str(), ev["ratio"].as_str(), ev["mode"].as_u64()),
        (Some("internal-resonance"), Some("3:1"), Some(2))
    );
    let (k1, kc, k2, m1, m2) = (1.0f64, 0.5, 7.0, 1.0, 0.5);
    // det(K - λ M) = m1 m2 λ² - (m1 (k2 + kc) + m2 (k1 + kc)) λ + (k1 + kc)(k2 + kc) - kc²
    let (a, b, c) = (m1 * m2, -(m1 * (k2 + kc) + m2 * (k1 + kc)), (k1 + kc) * (k2 + kc) - kc * kc);
    let w2 = ((-b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a)).sqrt();
    let w = ev["omega"].as_f64().unwrap();
    assert!((w - w2 / 3.0).abs() < 1e-9 * w2, "ω = {w} vs {}", w2 / 3.0);
}

/// A sweep over a range of six hundred decades with a force that leaves no solution
/// at either end produces no point: an error, and one that shows its numbers as
/// 1e-300 and 1e300, not as three hundred digits each.
#[test]
fn extreme_numbers_in_messages_are_short() {
    let o = ihbm(&["sweep", "duffing", "--from", "1e-300", "--to", "1e300", "--set", "F=1e20"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("no point") && err.contains("1e-300") && err.contains("1e300"), "{err}");
    assert!(err.len() < 400, "{} characters: {err}", err.len());
    assert!(!err.contains("00000000"), "{err}");
}

/// A value outside the domain a model declares for a parameter is bad input wherever
/// it enters (exit 2, one line naming the value, the domain, the model and the
/// parameter), before anything is computed; a value on a closed end is accepted.
#[test]
fn values_outside_a_parameter_domain_are_refused() {
    let usage = |args: &[&str], needles: &[&str]| {
        assert_rejected(args, needles);
        assert_eq!(ihbm(args).status.code(), Some(2), "{args:?}");
    };
    let domain = "a value in (0, inf) (the domain model 'quarter-car' declares for m1)";
    usage(&["solve", "quarter-car", "--omega", "8", "--set", "m1=-240"], &["m1", "-240", domain]);
    // an open end is excluded
    usage(&["solve", "quarter-car", "--omega", "8", "--set", "m1=0"], &["m1", domain]);
    usage(
        &["sweep", "base-excited", "--from", "0.5", "--to", "2", "--set", "p=0.5"],
        &["p", "0.5", "(1, 2)", "base-excited"],
    );
    // a closed end is included: no damping is a legitimate quarter car
    let o = ihbm(&["solve", "quarter-car", "--omega", "8", "--set", "c=0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // continuation in a parameter: a range with an end outside the domain
    usage(
        &[
            "sweep-param",
            "quarter-car",
            "--param",
            "c",
            "--from",
            "-100",
            "--to",
            "1000",
            "--omega",
            "8",
        ],
        &["end of the range of c", "-100", "[0, inf)"],
    );
    usage(
        &[
            "sweep-param",
            "quarter-car",
            "--param",
            "p",
            "--from",
            "0.5",
            "--to",
            "2.5",
            "--omega",
            "8",
        ],
        &["2.5", "[0, 2]"],
    );
    usage(
        &[
            "folds",
            "quarter-car",
            "--param",
            "m2",
            "--from",
            "30",
            "--to",
            "-30",
            "--omega-from",
            "5",
            "--omega-to",
            "60",
        ],
        &["end of the range of m2", "-30", "(0, inf)"],
    );
    // `ihbm models NAME` shows each domain
    let s = stdout(&ihbm(&["models", "base-excited"]));
    assert!(s.lines().any(|l| l.trim_start().starts_with('p') && l.contains("in (1, 2)")), "{s}");
    assert!(
        s.lines().any(|l| l.trim_start().starts_with("k3") && l.contains("in (-inf, inf)")),
        "{s}"
    );
}

/// In a study file, overrides, varied values and fold ranges outside a domain are
/// refused by validation with the file, line and column of the entry.
#[test]
fn study_values_outside_a_parameter_domain_name_file_line_and_column() {
    let head = "model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 }\n";
    let cases: [(&str, &[&str]); 4] = [
        ("params = { m2 = -30.0 }\n", &[":3:12:", "m2", "-30", "(0, inf)"]),
        (
            "[[figure]]\nid = \"a\"\nvary = \"p\"\nvalues = [0.5, 2.5]\n",
            &[":5:8:", "figure 'a'", "2.5", "[0, 2]"],
        ),
        (
            "[[figure]]\nid = \"a\"\nvary = \"c\"\nvalues = [-1.0, 0.0]\n",
            &[":5:8:", "figure 'a'", "-1", "[0, inf)"],
        ),
        (
            "[[figure]]\nid = \"a\"\nfolds = { param = \"kt\", from = -1e5, to = 2e5 }\n",
            &[":5:19:", "figure 'a'", "folds range of kt", "-100000", "[0, inf)"],
        ),
    ];
    for (i, (text, needles)) in cases.iter().enumerate() {
        let path = tmp(&format!("domain{i}.toml"));
        std::fs::write(&path, format!("{head}{text}")).unwrap();
        let mut n = vec![path.to_str().unwrap()];
        n.extend_from_slice(needles);
        let out = tmp("domain_out");
        let args = ["run", path.to_str().unwrap(), "--out", out.to_str().unwrap()];
        assert_rejected(&args, &n);
        assert_eq!(ihbm(&args).status.code(), Some(2), "{text}");
    }
}

#[test]
fn aft_samples_are_reported_and_a_count_that_would_alias_is_refused() {
    // A smooth model reports its alias-free count (the cubic at N = 5: 24).
    let o = ihbm(&["solve", "duffing", "--omega", "1", "--json"]);
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["aft_samples"], 24);
    let o = ihbm(&["solve", "duffing", "--omega", "1", "--aft-samples", "64", "--json"]);
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["aft_samples"], 64);
    assert_rejected(
        &["solve", "duffing", "--omega", "1", "--aft-samples", "16"],
        &["invalid --aft-samples: 16", "at least 24 for model 'duffing' at N = 5"],
    );
    assert_rejected(
        &[
            "sweep",
            "duffing",
            "--from",
            "1",
            "--to",
            "2",
            "--harmonics",
            "9",
            "--aft-samples",
            "12",
        ],
        &["invalid --aft-samples: 12", "at least 2N + 1 = 19"],
    );
    // A non-smooth model (a one-sided stop) takes 16 (2N + 1), rounded to a fast size.
    let path = tmp("stop.ihbm");
    std::fs::write(
        &path,
        "struct Stop { params { k = 1.0, F = 0.4 } dofs { x }\n\
         equations { D(x, 2) + 0.1 * D(x, 1) + k * x + 10.0 * max(0.0, x - 0.5) = F * cos(omega * t); } }",
    )
    .unwrap();
    let file = path.to_str().unwrap();
    let o = ihbm(&["sweep", file, "--from", "0.3", "--to", "0.6", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["aft_samples"], 180);
    let o =
        ihbm(&["backbone", "duffing", "--to", "0.5", "--set", "c=0", "--harmonics", "7", "--json"]);
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["aft_samples"], 30, "the cubic at N = 7: 4 N + 1 = 29, a fast size up");
    let o = ihbm(&["sweep", file, "--from", "0.3", "--to", "0.6", "--aft-samples", "12", "--json"]);
    assert!(o.status.success(), "a non-smooth model takes any count from 2N + 1: {}", stderr(&o));
}

#[test]
fn the_ride_study_runs_and_its_claims_hold() {
    // The book's chapter on stops and lift-off: the wheel leaves the road only at the
    // larger road amplitudes, and the bump stop trades travel for acceleration.
    let dir = tmp("ride");
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/quarter_car_ride.toml");
    let o = ihbm(&["run", study, "--out", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("4 agree, 0 disagree, 0 inconclusive"), "{summary}");
    for f in ["ride_lift_off.svg", "ride_bump_stop.svg"] {
        assert!(dir.join(f).exists(), "{f}");
    }
    // At 5 mm the wheel never leaves the road; at 15 mm it does.
    let curve = |f: &str| -> Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(f)).unwrap()).unwrap()
    };
    let air = |v: &Value| {
        v["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["outputs"]["air"]["max_abs"].as_f64().unwrap())
            .fold(0.0, f64::max)
    };
    assert_eq!(air(&curve("ride_lift_off_F_0.005.json")), 0.0);
    assert!(air(&curve("ride_lift_off_F_0.015.json")) > 0.01);
}

#[test]
fn solve_reports_sensitivities_of_every_output_and_refuses_an_unknown_parameter() {
    // The linear quarter car far below resonance: the body follows the road, so
    // d amp1(z1)/dF is about amp1 / F (the response is linear in F: exactly that).
    let o = ihbm(&[
        "solve",
        "quarter-car",
        "--omega",
        "3",
        "--set",
        "k3=0",
        "--sensitivity",
        "F",
        "--sensitivity",
        "k1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let z1 = &v["outputs"]["z1"];
    assert_eq!(keys(&z1["sensitivities"]), ["F", "k1"]);
    assert_eq!(keys(&z1["sensitivities"]["F"]), STATS);
    let (amp, rate) =
        (z1["amp1"].as_f64().unwrap(), z1["sensitivities"]["F"]["amp1"].as_f64().unwrap());
    assert!((rate - amp / 0.01).abs() < 1e-9 * rate, "{rate} vs {}", amp / 0.01);
    // The mean of a linear response does not move: 0 (a number, not null).
    assert!(z1["sensitivities"]["k1"]["mean"].as_f64().unwrap().abs() < 1e-12);
    assert_rejected(
        &["solve", "quarter-car", "--omega", "3", "--sensitivity", "q"],
        &["unknown parameter", "q"],
    );
}
