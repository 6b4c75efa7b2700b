//! The continuation flags of `sweep` and the `sweep-param` command, end to end through
//! the `ihbm` binary. Evidence: closed forms of linear models (amplitude ∝ force,
//! the fractional order entering through (iΩ)^p), the one-harmonic balance of the
//! Duffing oscillator (its amplitude–force relation and folds), identities between
//! runs (stability does not move points; the convergence estimate is the change
//! between two independent runs), and error messages that name flag and value.

use crate::common as cli_common;

use cli_common::{assert_rejected, ihbm, stderr, stdout, tmp};
use num_complex::Complex64;
use serde_json::Value;

/// Run, expect success, parse the JSON written to standard output.
fn json(args: &[&str]) -> Value {
    let o = ihbm(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    serde_json::from_str(&stdout(&o)).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

/// A bad input: exit status 2 (bad input), one line naming every `needle`.
fn assert_usage(args: &[&str], needles: &[&str]) {
    assert_rejected(args, needles);
    assert_eq!(ihbm(args).status.code(), Some(2), "{args:?}: bad input exits with 2");
}

/// Words of a command line (no argument here contains a space).
fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

fn points(v: &Value) -> &Vec<Value> {
    v["points"].as_array().unwrap()
}

fn x_max(p: &Value) -> f64 {
    p["outputs"]["x"]["max_abs"].as_f64().unwrap()
}

fn f(p: &Value, key: &str) -> f64 {
    p[key].as_f64().unwrap_or_else(|| panic!("no number '{key}' in {p}"))
}

/// |X| of m x'' + c x' + k x + h D^p x = F cos Ωt (steady state, Weyl sense).
fn linear(m: f64, c: f64, k: f64, h: f64, p: f64, force: f64, omega: f64) -> f64 {
    let iw = Complex64::new(0.0, omega);
    force / (k - m * omega * omega + c * iw + h * iw.powf(p)).norm()
}

#[test]
fn sweep_param_force_on_a_linear_oscillator_is_proportional() {
    // Duffing defaults m = 1, c = 0.1, k = 1 with k3 = 0: |X| = F / |k - mΩ² + icΩ|.
    let (csv, svg) = (tmp("force.csv"), tmp("force.svg"));
    let line = format!(
        "sweep-param duffing --param F --from 0.1 --to 2 --omega 1.2 --set k3=0 --csv {} --plot {} --json -",
        csv.display(),
        svg.display()
    );
    let v = json(&words(&line));
    assert_eq!(v["parameter"], "F");
    assert_eq!(v["model"], "duffing");
    let pts = points(&v);
    assert!(pts.len() >= 5, "{}", pts.len());
    for p in pts {
        let force = f(p, "param");
        assert_eq!(f(p, "omega"), 1.2);
        let exact = linear(1.0, 0.1, 1.0, 0.0, 1.0, force, 1.2);
        assert!((x_max(p) - exact).abs() < 1e-9 * exact, "F = {force}: {} vs {exact}", x_max(p));
        assert_eq!(p["stable"], true, "a damped linear oscillator is stable");
    }
    let (first, last) = (f(&pts[0], "param"), f(&pts[pts.len() - 1], "param"));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(first, 0.1) && close(last, 2.0), "{first} .. {last}");
    let seg = &v["segments"][0];
    assert!(close(f(seg, "from_param"), 0.1) && close(f(seg, "to_param"), 2.0), "{seg}");
    // the ends are values of F: `from_omega`/`to_omega` are the fixed frequency
    assert!(f(seg, "from_omega") == 1.2 && f(seg, "to_omega") == 1.2, "{seg}");
    assert_eq!(seg["ended"], "reached end");
    assert!(v["folds"].as_array().unwrap().is_empty() && v["jumps"].as_array().unwrap().is_empty());

    // The CSV's first column is F, with the parameter values; the plot's x axis too.
    let csv = std::fs::read_to_string(&csv).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("F,stable,x_max_abs,x_mean,x_amp1,x_rms,x_min,x_max"));
    let col: Vec<f64> = lines.map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();
    assert_eq!(col.len(), pts.len());
    for (c, p) in col.iter().zip(pts) {
        assert!(close(*c, f(p, "param")), "{c} vs {}", p["param"]);
    }
    let svg = std::fs::read_to_string(&svg).unwrap();
    roxmltree::Document::parse(&svg).unwrap();
    assert!(svg.contains("parameter F"), "x axis not labelled by the parameter");
    assert!(!svg.contains("forcing frequency"), "a parameter sweep has no frequency axis");
}

#[test]
fn sweep_param_fractional_order_matches_the_closed_form() {
    // fractional-duffing defaults m = 1, c = 0.05, k = 1, h = 0.1, F = 0.5; k3 = 0:
    // |X| = F / |k - mΩ² + icΩ + h (iΩ)^p| as p goes from 0.05 to 1.95.
    let v = json(&words(
        "sweep-param fractional-duffing --param p --from 0.05 --to 1.95 --omega 1.3 --set k3=0 --json",
    ));
    assert_eq!(v["parameter"], "p");
    let pts = points(&v);
    assert!(pts.len() >= 5);
    for q in pts {
        let p = f(q, "param");
        assert!((0.05..=1.95).contains(&p));
        let exact = linear(1.0, 0.05, 1.0, 0.1, p, 0.5, 1.3);
        assert!((x_max(q) - exact).abs() < 1e-9 * exact, "p = {p}: {} vs {exact}", x_max(q));
    }
    assert!((f(&pts[pts.len() - 1], "param") - 1.95).abs() < 1e-12);
}

/// F(A) of the one-harmonic balance of m x'' + c x' + k x + k3 x³ = F cos Ωt.
fn duffing_force(a: f64, (m, c, k, k3): (f64, f64, f64, f64), w: f64) -> f64 {
    let d = k - m * w * w + 0.75 * k3 * a * a;
    a * (d * d + (c * w).powi(2)).sqrt()
}

#[test]
fn sweep_param_force_of_a_hardening_duffing_passes_its_folds() {
    // Above resonance (Ω = 2) a hardening Duffing oscillator's amplitude–force curve is
    // an S: the upper branch appears at F ≈ 0.2 and the lower one ends at F ≈ 2.31.
    // With N = 1 every point obeys F(A) of the one-harmonic balance, and the folds
    // are where dF/dA = 0: 3a²u² + 4adu + d² + e² = 0 in u = A², a = 3k3/4,
    // d = k - mΩ², e = cΩ.
    let (m, c, k, k3, w) = (1.0, 0.05, 1.0, 1.0, 2.0);
    let v = json(&words(
        "sweep-param duffing --param F --from 0.1 --to 5 --omega 2 --harmonics 1 --set c=0.05 --json",
    ));
    for p in points(&v) {
        let amp = p["outputs"]["x"]["amp1"].as_f64().unwrap();
        let force = duffing_force(amp, (m, c, k, k3), w);
        assert!((force - f(p, "param")).abs() < 1e-8 * force, "{force} vs {}", p["param"]);
    }
    let (a, d, e) = (0.75 * k3, k - m * w * w, c * w);
    let disc = (16.0 * a * a * d * d - 12.0 * a * a * (d * d + e * e)).sqrt();
    let mut fold_forces: Vec<f64> = [-1.0, 1.0]
        .iter()
        .map(|s| {
            let u = (-4.0 * a * d + s * disc) / (6.0 * a * a);
            duffing_force(u.sqrt(), (m, c, k, k3), w)
        })
        .collect();
    fold_forces.sort_by(f64::total_cmp);
    let mut got: Vec<f64> = v["folds"].as_array().unwrap().iter().map(|x| f(x, "param")).collect();
    got.sort_by(f64::total_cmp);
    assert_eq!(got.len(), 2, "{}", v["folds"]);
    for (g, e) in got.iter().zip(&fold_forces) {
        assert!((g - e).abs() < 1e-8 * e, "fold at F = {g}, expected {e}");
    }
    for fold in v["folds"].as_array().unwrap() {
        assert_eq!(f(fold, "omega"), 2.0);
    }
    // Between the folds the middle branch is a saddle; slow sweeps jump both ways.
    assert!(points(&v).iter().any(|p| p["stable"] == false));
    let dirs: Vec<&str> =
        v["jumps"].as_array().unwrap().iter().map(|j| j["direction"].as_str().unwrap()).collect();
    assert!(dirs.contains(&"up") && dirs.contains(&"down"), "{dirs:?}");
}

/// A hardening Duffing sweep (c = 0.05, F = 0.2: two folds) with N harmonics and
/// `extra` arguments.
fn hardening(n: usize, extra: &str) -> String {
    format!("sweep duffing --from 0.5 --to 2.5 --harmonics {n} --set c=0.05 --set F=0.2 {extra}")
}

fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = base.to_vec();
    v.extend_from_slice(extra);
    v
}

#[test]
fn no_stability_keeps_the_points_and_drops_the_verdicts() {
    let a = json(&words(&hardening(3, "--json")));
    let b = json(&words(&hardening(3, "--no-stability --json")));
    let (pa, pb) = (points(&a), points(&b));
    assert_eq!(pa.len(), pb.len());
    for (p, q) in pa.iter().zip(pb) {
        assert_eq!(p["omega"], q["omega"]);
        assert_eq!(p["outputs"], q["outputs"]);
        // No verdict is `null`, not a `true` that was never checked.
        assert_eq!(
            q["stable"],
            serde_json::Value::Null,
            "without stability no point has a verdict"
        );
        assert!(p["stable"].is_boolean(), "with stability every point has one: {p}");
    }
    assert!(pa.iter().any(|p| p["stable"] == false), "the middle branch is unstable");
    assert_eq!(a["folds"], b["folds"]);
    // The curve says whether its verdicts were checked.
    assert_eq!((&a["stability_checked"], &b["stability_checked"]), (&true.into(), &false.into()));
}

#[test]
fn smaller_max_step_gives_more_points_on_the_same_curve() {
    // Linear oscillator (k3 = 0): every point on |X| = F / |k - mΩ² + icΩ|.
    let base = ["sweep", "duffing", "--from", "0.5", "--to", "2", "--set", "k3=0"];
    let coarse = json(&with(&base, &["--json"]));
    let fine = json(&with(&base, &["--max-step", "0.01", "--json"]));
    let secant =
        json(&with(&base, &["--predictor", "secant", "--initial-step", "0.001", "--json"]));
    assert!(
        points(&fine).len() > 2 * points(&coarse).len(),
        "{} vs {}",
        points(&fine).len(),
        points(&coarse).len()
    );
    for v in [&coarse, &fine, &secant] {
        for p in points(v) {
            let exact = linear(1.0, 0.1, 1.0, 0.0, 1.0, 0.5, f(p, "omega"));
            assert!((x_max(p) - exact).abs() < 1e-9 * exact, "{p}");
        }
        assert_eq!(v["segments"][0]["ended"], "reached end");
    }
}

#[test]
fn amplitude_bound_ends_a_segment_where_asked() {
    // Lightly damped linear oscillator: the peak F/(cΩ) ≈ 0.5 / 0.01 = 50 exceeds 1.
    let base =
        ["sweep", "duffing", "--from", "0.5", "--to", "2", "--set", "k3=0", "--set", "c=0.01"];
    let v = json(&with(&base, &["--amplitude-bound", "abs:1", "--json"]));
    let segs = v["segments"].as_array().unwrap();
    assert!(segs.iter().all(|s| s["ended"] == "amplitude bound"), "{segs:?}");
    // Both ends were traced towards the resonance and stopped at the first point above 1.
    let above: Vec<f64> = points(&v).iter().map(x_max).filter(|&x| x > 1.0).collect();
    assert_eq!(above.len(), 2, "one point beyond the bound per segment");
    let v = json(&with(&base, &["--amplitude-bound", "none", "--json"]));
    assert_eq!(v["segments"][0]["ended"], "reached end");
    let peak = points(&v).iter().map(x_max).fold(0.0, f64::max);
    assert!(peak > 40.0, "{peak}");
}

#[test]
fn converge_reports_an_estimate_that_two_plain_runs_confirm() {
    let v = json(&words(&hardening(3, "--converge=1e-4 --json")));
    let conv = &v["convergence"];
    assert_eq!(conv["tol"].as_f64(), Some(1e-4));
    assert_eq!(conv["converged"], true);
    let levels = conv["levels"].as_array().unwrap();
    assert!(levels.len() >= 2);
    let ns: Vec<u64> = levels.iter().map(|l| l["harmonics"].as_u64().unwrap()).collect();
    assert_eq!(ns[0], 3);
    assert!(ns.windows(2).all(|w| w[1] == w[0] + 2), "{ns:?}");
    let last = *ns.last().unwrap();
    assert_eq!(v["harmonics"].as_u64(), Some(last), "the curve returned is the last level's");
    let estimate = f(conv, "estimate");
    assert!(estimate < 1e-4);
    // Independent runs at the last two N: the estimate is the largest relative change
    // of the peak and of the fold frequencies between them.
    let run = |n: u64| {
        let v = json(&words(&hardening(n as usize, "--json")));
        let peak = points(&v).iter().map(x_max).fold(0.0, f64::max);
        let folds: Vec<f64> =
            v["folds"].as_array().unwrap().iter().map(|x| f(x, "omega")).collect();
        (peak, folds)
    };
    let (p1, f1) = run(last - 2);
    let (p2, f2) = run(last);
    let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(b.abs());
    let mut change = rel(p1, p2);
    assert_eq!(f1.len(), f2.len());
    for (a, b) in f1.iter().zip(&f2) {
        change = change.max(rel(*a, *b));
    }
    assert!((change - estimate).abs() <= 1e-3 * estimate + 1e-15, "{change} vs {estimate}");
    // Without --converge there is no convergence field (the contract's document).
    assert!(json(&words(&hardening(3, "--json"))).get("convergence").is_none());
    // The human summary states the estimate.
    let o = ihbm(&words(&hardening(3, "--converge")));
    assert!(o.status.success());
    assert!(stdout(&o).contains("harmonic convergence"), "{}", stdout(&o));
}

#[test]
fn bad_continuation_flags_name_the_flag_and_value() {
    let s =
        |extra: &[&'static str]| with(&["sweep", "duffing", "--from", "0.5", "--to", "2"], extra);
    assert_usage(&s(&["--max-step", "-1"]), &["--max-step", "-1", "> 0"]);
    assert_usage(&s(&["--max-step", "0"]), &["--max-step", "0"]);
    assert_usage(&s(&["--min-step", "nan"]), &["--min-step", "NaN"]);
    assert_usage(&s(&["--initial-step", "inf"]), &["--initial-step", "inf"]);
    assert_usage(&s(&["--tol", "0"]), &["--tol", "0"]);
    assert_usage(&s(&["--tol", "tiny"]), &["--tol", "tiny"]);
    assert_usage(
        &s(&["--min-step", "0.5", "--max-step", "0.1"]),
        &["--min-step", "0.5", "--max-step", "0.1"],
    );
    assert_usage(
        &s(&["--initial-step", "0.2", "--max-step", "0.1"]),
        &["--initial-step", "0.2", "at most --max-step"],
    );
    assert_usage(&s(&["--predictor", "euler"]), &["--predictor", "euler", "tangent", "secant"]);
    for bad in ["rel:x", "abs:-1", "half", "max:3", "rel:0"] {
        assert_usage(&s(&["--amplitude-bound", bad]), &["--amplitude-bound", bad, "rel:", "none"]);
    }
    assert_usage(&s(&["--max-steps", "0"]), &["--max-steps", "0"]);
    assert_usage(&s(&["--max-steps", "-5"]), &["--max-steps", "-5"]);
    assert_usage(&s(&["--converge=0"]), &["--converge", "0"]);
    assert_usage(&s(&["--converge=-1e-3"]), &["--converge", "-0.001"]);
    assert_usage(&s(&["--converge=soon"]), &["--converge", "soon"]);
    assert_usage(&s(&["--no-stability=yes"]), &["--no-stability"]);
    // The tolerance needs '=' (a bare --converge may be followed by other arguments).
    assert_usage(&s(&["--converge", "1e-4"]), &["1e-4", "--converge=TOL"]);
}

#[test]
fn bad_sweep_param_inputs_fail_with_a_reason() {
    let base = ["sweep-param", "fractional-duffing", "--omega", "1"];
    assert_usage(
        &with(&base, &["--param", "q", "--from", "0", "--to", "1"]),
        &["unknown parameter 'q'", "fractional-duffing", "k3"],
    );
    assert_usage(
        &with(&base, &["--param", "p", "--from", "0.5", "--to", "2.5"]),
        &["fractional order p", "2.5", "[0, 2]"],
    );
    assert_usage(&with(&base, &["--param", "F", "--from", "2", "--to", "1"]), &["F", "2", "1"]);
    assert_usage(&with(&base, &["--param", "F", "--from", "1", "--to", "inf"]), &["inf"]);
    assert_usage(
        &["sweep-param", "duffing", "--param", "F", "--from", "1", "--to", "2", "--omega", "0"],
        &["--omega", "0"],
    );
    assert_usage(
        &["sweep-param", "duffing", "--param", "F", "--from", "1", "--to", "2"],
        &["--omega"],
    );
    assert_usage(
        &["sweep-param", "duffing", "--from", "1", "--to", "2", "--omega", "1"],
        &["--param"],
    );
    assert_usage(
        &["sweep-param", "nope", "--param", "F", "--from", "1", "--to", "2", "--omega", "1"],
        &["unknown model", "nope"],
    );
    assert_usage(
        &with(&base, &["--param", "F", "--from", "1", "--to", "2", "--max-step", "-1"]),
        &["--max-step", "-1"],
    );
}

#[test]
fn help_documents_the_flags() {
    for cmd in ["sweep", "sweep-param"] {
        let o = ihbm(&[cmd, "--help"]);
        assert!(o.status.success());
        let h = stdout(&o);
        for flag in [
            "--max-step",
            "--min-step",
            "--initial-step",
            "--tol",
            "--predictor",
            "--amplitude-bound",
            "--max-steps",
            "--no-stability",
            "--converge",
            "--csv",
            "--json",
            "--plot",
        ] {
            assert!(h.contains(flag), "{cmd} --help lacks {flag}");
        }
    }
    let h = stdout(&ihbm(&["sweep-param", "--help"]));
    assert!(h.contains("--param") && h.contains("--omega"), "{h}");
    let h = stdout(&ihbm(&["--help"]));
    assert!(h.contains("sweep-param"), "{h}");
}

#[test]
fn study_sweep_tables_take_the_same_settings_and_checks() {
    let write = |name: &str, sweep: &str| {
        let path = tmp(name);
        std::fs::write(
            &path,
            format!(
                "model = \"duffing\"\nfrequency = {{ from = 0.5, to = 2.0 }}\nharmonics = 1\n\
                 params = {{ k3 = 0.0 }}\nsweep = {{ {sweep} }}\n\n[[figure]]\nid = \"lin\"\n"
            ),
        )
        .unwrap();
        path
    };
    let bad = write("bad_tol.toml", "tol = -1.0");
    assert_usage(&["run", bad.to_str().unwrap()], &["bad_tol.toml", "sweep.tol = -1", "> 0"]);
    let bad = write("bad_bound.toml", "amplitude_bound = \"rel:x\"");
    assert_usage(&["run", bad.to_str().unwrap()], &["bad_bound.toml", "amplitude_bound", "rel:x"]);
    let bad = write("bad_steps.toml", "min_step = 0.5, max_step = 0.1");
    assert_usage(
        &["run", bad.to_str().unwrap()],
        &["sweep.min_step = 0.5", "at most sweep.max_step (0.1)"],
    );
    let bad = write("bad_pred.toml", "predictor = \"euler\"");
    assert_usage(&["run", bad.to_str().unwrap()], &["bad_pred.toml", "euler"]);

    // Good settings run; the curve JSON carries the convergence study.
    let good = write(
        "good.toml",
        "max_step = 0.05, predictor = \"secant\", amplitude_bound = \"none\", \
         stability = false, converge = 1e-6",
    );
    let dir = tmp("good-out");
    let o = ihbm(&["run", good.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("lin.json")).unwrap()).unwrap();
    assert_eq!(v["convergence"]["converged"], true, "{}", v["convergence"]);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("harmonic convergence (N = 1, 3)"), "{summary}");
    for p in points(&v) {
        let exact = linear(1.0, 0.1, 1.0, 0.0, 1.0, 0.5, f(p, "omega"));
        assert!((x_max(p) - exact).abs() < 1e-9 * exact);
    }
}

/// Points with an unrefined fractional exponent (verdict counted) are announced,
/// as many as the library's own analysis of the same points finds unrefined; a curve
/// without any says nothing.
#[test]
fn unrefined_stability_verdicts_are_counted_and_announced() {
    use ihbm::balance::Balance;
    use ihbm::stability::{Hill, StabilityOptions};
    let base = ["sweep", "quarter-car", "--from", "1", "--to", "100"];
    let hard = with(&base, &["--set", "k3=5e6", "--set", "F=0.1"]);
    let v = json(&with(&hard, &["--json", "-"]));
    let counted = v["stats"]["stability_unrefined"].as_u64().unwrap() as usize;
    // Independently: a full analysis at every point of the curve.
    let model = ihbm::models::QuarterCar { k3: 5e6, F: 0.1, ..Default::default() };
    let curve = ihbm::continuation::sweep(&model, 1.0, 100.0, &Default::default()).unwrap();
    let mut bal = Balance::new(&model, 5).unwrap();
    let mut hill = Hill::new(&model, 5).unwrap();
    let so = StabilityOptions::default();
    let full = curve
        .points
        .iter()
        .filter(|p| !hill.analyse(&mut bal, &p.coeffs, p.omega, &so).unwrap().refined)
        .count();
    assert!(full > 0, "test setup: this curve has points with unrefined exponents");
    // Tracked points are refined roots by construction, so only full analyses count.
    assert!(counted > 0 && counted <= full, "counted {counted}, unrefined in full {full}");
    let text = stdout(&ihbm(&hard));
    let warning = format!("warning: at {counted} of {} points", points(&v).len());
    assert!(text.contains(&warning), "{text}");
    assert!(!stdout(&ihbm(&base)).contains("warning"));
}

/// Sweeps over ranges of many decades: every point finite and inside the range (the
/// model is never evaluated outside it), segments that end at finite values, and no
/// jump between two copies of one branch.
#[test]
fn wide_ranges_give_finite_points_inside_the_range() {
    for line in [
        "sweep fractional-duffing --from 1e-3 --to 1e4 --json",
        "sweep base-excited --from 1e-4 --to 1e3 --json",
        "sweep duffing --from 1e-6 --to 1e6 --json",
    ] {
        let v = json(&words(line));
        let range: Vec<f64> =
            line.split_whitespace().filter_map(|w| w.parse::<f64>().ok()).collect();
        assert_eq!(f(&v["segments"][0], "from_omega"), range[0], "{line}");
        assert!(!points(&v).is_empty(), "{line}");
        for p in points(&v) {
            let w = f(p, "omega");
            assert!(w >= range[0] * (1.0 - 1e-12) && w <= range[1] * (1.0 + 1e-12), "{line}: {p}");
            for o in p["outputs"].as_object().unwrap().values() {
                for key in ["max_abs", "mean", "amp1", "rms", "min", "max"] {
                    assert!(o[key].as_f64().is_some_and(f64::is_finite), "{line}: {p}");
                }
            }
        }
        for s in v["segments"].as_array().unwrap() {
            assert!(f(s, "from_omega").is_finite() && f(s, "to_omega").is_finite(), "{line}: {s}");
        }
        for j in v["jumps"].as_array().unwrap() {
            let (a, b) = (f(j, "from"), f(j, "to"));
            assert!((a - b).abs() > 1e-6 * a.abs().max(b.abs()), "{line}: {j}");
        }
    }
}

/// Twelve decades are continued in ln Ω: one segment from end to end, points in
/// every decade (in Ω itself, steps suited to 10⁶ rad/s jumped over everything below
/// and the first segment turned back at once), each on the closed-form linear
/// response of the fractional oscillator (k3 = 0).
#[test]
fn a_sweep_over_twelve_decades_covers_each_of_them() {
    let (m, c, k, h, p, force) = (1.0, 0.05, 1.0, 0.1, 0.5, 0.3);
    let v =
        json(&words("sweep fractional-duffing --from 1e-6 --to 1e6 --set k3=0 --set F=0.3 --json"));
    let segs = v["segments"].as_array().unwrap();
    assert_eq!(segs.len(), 1, "{segs:?}");
    assert_eq!(segs[0]["ended"], "reached end");
    assert!((f(&segs[0], "to_omega") / 1e6 - 1.0).abs() < 1e-9, "{segs:?}");
    let mut per_decade = [0usize; 12];
    // Newton's tolerance is on coefficients scaled by the reference amplitude (the
    // largest response, near resonance): far above it, where the response is 10⁻⁹
    // of that, the error is relative to the peak.
    let peak = points(&v)
        .iter()
        .map(|pt| linear(m, c, k, h, p, force, f(pt, "omega")))
        .fold(0.0, f64::max);
    for pt in points(&v) {
        let w = f(pt, "omega");
        per_decade[((w.log10() + 6.0).floor() as usize).min(11)] += 1;
        let exact = linear(m, c, k, h, p, force, w);
        let err = (x_max(pt) - exact).abs();
        assert!(err <= 1e-9 * exact + 1e-12 * peak, "Ω = {w}: {} vs {exact}", x_max(pt));
    }
    // The largest step, 0.1 of a decade, makes at least ten a decade.
    assert!(per_decade.iter().all(|&n| n >= 10), "points per decade: {per_decade:?}");
}

/// A sweep that traces no point fails (exit 1, one line with the segments' reasons)
/// and still writes its JSON; a tiny force is no reason to fail: in the linear regime
/// the response scales exactly with it.
#[test]
fn a_sweep_with_no_point_fails_and_tiny_forces_scale() {
    let o = ihbm(&words("sweep duffing --from 1 --to 3 --set F=1e20 --json"));
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim_end().lines().count(), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("no point"), "{}", stderr(&o));
    let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!(points(&v).is_empty() && !v["segments"].as_array().unwrap().is_empty());

    let a = json(&words("sweep duffing --from 1 --to 3 --set F=1e-20 --json"));
    let b = json(&words("sweep duffing --from 1 --to 3 --set F=1e-14 --json"));
    assert_eq!(points(&a).len(), points(&b).len());
    for (p, q) in points(&a).iter().zip(points(&b)) {
        let ratio = x_max(q) / x_max(p);
        assert!((ratio / 1e6 - 1.0).abs() < 1e-9, "Ω = {}: ratio {ratio}", p["omega"]);
    }
}
