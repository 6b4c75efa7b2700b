//! The reference study: it encodes the paper's section 4 (values read off the paper's
//! text, not our output), it runs, and every file it writes exists and parses.

use ihbm::study::claims::fmt_num;
use ihbm::{study, Cli};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("ihbm-study-tests-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// (figure id, varied quantity, values) as printed in the paper's section 4 and its corrections.
fn paper() -> Vec<(&'static str, Option<&'static str>, Vec<f64>)> {
    vec![
        ("fig04_harmonics", Some("harmonics"), vec![4.0, 5.0, 6.0]),
        ("fig06_time_domain", None, vec![]),
        ("fig07_order", Some("p"), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]),
        ("fig08_coefficient", Some("h"), vec![500.0, 1000.0, 1500.0, 2000.0]),
        ("fig09_cubic_stiffness", Some("k3"), vec![1e6, 2e6, 3e6, 4e6, 5e6]),
        ("fig10_road_amplitude", Some("F"), vec![0.006, 0.008, 0.01]),
        ("fig11_body_mass", Some("m1"), vec![200.0, 220.0, 240.0, 260.0, 280.0]),
        ("fig12_wheel_mass", Some("m2"), vec![30.0, 40.0, 50.0, 60.0, 70.0]),
        ("fig_jumps", Some("F"), vec![0.02, 0.025, 0.03]),
    ]
}

#[test]
fn reference_study_encodes_the_papers_figures() {
    let s = study::parse(study::REFERENCE_STUDY, "reference").unwrap();
    s.validate(Cli::builtin().registry()).unwrap();
    assert_eq!(s.model.get_ref(), "quarter-car");
    assert_eq!((s.frequency.from, s.frequency.to), (1.0, 100.0));
    assert_eq!(s.harmonics, 5);
    let outs: Vec<&str> = s.outputs.iter().map(|o| o.get_ref().as_str()).collect();
    assert_eq!(outs, ["z1", "y"], "two panels: body displacement and suspension deflection");
    let ids: Vec<&str> = s.figures.iter().map(|f| f.id.get_ref().as_str()).collect();
    let expected = paper();
    let mut want: Vec<&str> = expected.iter().map(|e| e.0).collect();
    want.extend(["folds_k3", "folds_road", "torus_bubble", "modes_backbones"]);
    want.extend(["half_car_v10", "half_car_v20", "half_car_v30", "half_car_jumps"]);
    assert_eq!(
        ids, want,
        "the paper's figures, the fold curves that answer Fig. 9, the torus curve of the \
         bubble, the quarter car's nonlinear modes, the half car's"
    );
    // The half car: bounce and pitch at three speeds with the fractional order varied.
    // The dips its claims name are the symmetric car's wheelbase zeros, Ω(a+b)/v = π
    // (bounce) and 2π (pitch), with the model's a + b = 2.8 m.
    for v in [10.0, 20.0, 30.0] {
        let id = format!("half_car_v{v}");
        let f = s.figures.iter().find(|f| *f.id.get_ref() == id).unwrap();
        assert_eq!(f.model.as_ref().map(|m| m.get_ref().as_str()), Some("half-car"), "{id}");
        assert_eq!(f.vary.as_ref().map(|v| v.get_ref().as_str()), Some("p"), "{id}");
        assert_eq!(f.values, [0.2, 0.5, 0.8], "{id}");
        let outs: Vec<&str> =
            f.outputs.as_ref().unwrap().iter().map(|o| o.get_ref().as_str()).collect();
        assert_eq!(outs, ["z", "theta"], "{id}");
        assert_eq!(f.params.iter().find(|(k, _)| k.get_ref() == "v").map(|(_, x)| *x), Some(v));
        let claim = f.claim.as_deref().unwrap();
        for zero in [std::f64::consts::PI * v / 2.8, std::f64::consts::TAU * v / 2.8] {
            assert!(claim.contains(&format!("{zero:.1} rad/s")), "{id}: {zero:.1} in {claim}");
        }
        assert!(!f.checks.is_empty(), "{id} checks its claim");
    }
    for (fig, (id, vary, values)) in s.figures.iter().zip(&expected) {
        assert_eq!(fig.vary.as_ref().map(|v| v.get_ref().as_str()), *vary, "{id}");
        assert_eq!(&fig.values, values, "{id}");
        assert!(fig.claim.is_some(), "{id} quotes the paper's claim");
        assert!(!fig.checks.is_empty(), "{id} checks its claim");
    }
    let param = |id: &str, p: &str| {
        let f = s.figures.iter().find(|f| f.id.get_ref() == id).unwrap();
        f.params.iter().find(|(k, _)| k.get_ref() == p).map(|(_, v)| *v)
    };
    // The quarter car's two modes, body and wheel hop, over forced curves in F (the
    // forcing is left out of a mode, so one pair of backbones belongs to them all).
    let modes = s.figures.iter().find(|f| f.id.get_ref() == "modes_backbones").unwrap();
    assert_eq!(
        modes.backbone.as_ref().map(|b| b.get_ref().clone()),
        Some(ihbm::study::spec::BackboneSpec::Modes(vec![1, 2]))
    );
    assert_eq!(modes.vary.as_ref().map(|v| v.get_ref().as_str()), Some("F"));
    // Section 4.3: k3 = 3000 kN/m for Figs. 10 and 11.
    assert_eq!(param("fig10_road_amplitude", "k3"), Some(3e6));
    assert_eq!(param("fig11_body_mass", "k3"), Some(3e6));
    // The paper's time integration: GL with the step π/(100 Ω) = 200 steps per period,
    // and the second-order rule.
    let td = s.figures[1].timedomain.as_ref().unwrap();
    assert_eq!(td.steps_per_period, Some(200.0));
    assert_eq!(td.schemes.len(), 2);
}

fn svg_texts(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text)
        .unwrap_or_else(|e| panic!("{}: not XML: {e}", path.display()));
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

fn check_curve_files(dir: &Path, stem: &str) -> Value {
    let csv = std::fs::read_to_string(dir.join(format!("{stem}.csv")))
        .unwrap_or_else(|e| panic!("{stem}.csv: {e}"));
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("omega,stable,z1_max_abs,z1_mean,z1_amp1,z1_rms,z1_min,z1_max,z2_max_abs,z2_mean,z2_amp1,z2_rms,z2_min,z2_max,y_max_abs,y_mean,y_amp1,y_rms,y_min,y_max"));
    let mut rows = 0;
    for l in lines {
        let cols: Vec<&str> = l.split(',').collect();
        assert_eq!(cols.len(), 2 + 3 * 6, "{stem}: {l}");
        assert!(cols[1] == "true" || cols[1] == "false");
        for c in cols.iter().skip(2).chain(std::iter::once(&cols[0])) {
            c.parse::<f64>().unwrap_or_else(|_| panic!("{stem}: {c}"));
        }
        rows += 1;
    }
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join(format!("{stem}.json"))).unwrap())
            .unwrap();
    assert_eq!(v["points"].as_array().unwrap().len(), rows, "{stem}: CSV and JSON agree");
    assert!(rows > 10, "{stem}: {rows} points");
    v
}

#[test]
fn reference_study_runs_and_every_file_parses() {
    let cli = Cli::builtin();
    let s = study::parse(study::REFERENCE_STUDY, "reference").unwrap();
    let dir = tmp("reference");
    let outcome = study::run(&s, cli.registry(), &dir).unwrap();
    assert!(outcome.failures.is_empty(), "{:#?}", outcome.failures);
    for (id, vary, values) in paper() {
        let texts = svg_texts(&dir.join(format!("{id}.svg")));
        match vary {
            Some(v) => {
                for x in &values {
                    let label = if v == "harmonics" {
                        format!("N = {x}")
                    } else {
                        format!("{v} = {}", fmt_num(*x))
                    };
                    // One legend entry per panel (z1 and y).
                    assert_eq!(
                        texts.iter().filter(|t| **t == label).count(),
                        2,
                        "{id}: {label} in {texts:?}"
                    );
                    check_curve_files(&dir, &format!("{id}_{v}_{}", fmt_num(*x)));
                }
            }
            None => {
                assert_eq!(
                    texts.iter().filter(|t| *t == "quarter-car").count(),
                    2,
                    "{id}: {texts:?}"
                );
                check_curve_files(&dir, id);
            }
        }
    }
    // Fig. 6: both schemes appear as markers in both panels, and the comparison table.
    let texts = svg_texts(&dir.join("fig06_time_domain.svg"));
    for l in ["time integration (GL)", "time integration (BDF2)"] {
        assert_eq!(texts.iter().filter(|t| *t == l).count(), 2, "{l}");
    }
    let td = std::fs::read_to_string(dir.join("fig06_time_domain_timedomain.csv")).unwrap();
    // 7 frequencies x 2 schemes x 3 outputs.
    assert_eq!(td.lines().count(), 1 + 7 * 2 * 3, "{td}");
    // The multi-valued figure really folds, with an unstable branch and jumps.
    let v = check_curve_files(&dir, "fig_jumps_F_0.03");
    assert!(v["folds"].as_array().unwrap().len() >= 2, "{}", v["folds"]);
    assert!(v["points"].as_array().unwrap().iter().any(|p| p["stable"] == false));
    assert!(v["jumps"].as_array().unwrap().len() >= 2, "{}", v["jumps"]);
    let texts = svg_texts(&dir.join("fig_jumps.svg"));
    for l in ["unstable (dashed)", "fold", "jump (slow sweep)"] {
        assert!(texts.iter().any(|t| t == l), "{l}: {texts:?}");
    }
    // Where jumps begin: the cusp of the fold curve in k3 at F = 0.01, and the cusps in
    // F for five k3. The quarter car's only nonlinearity is cubic, so x → s·x maps
    // (k3, F) to (k3 s², F/s): F_c·√k3 is one constant and Ω_c one frequency.
    let json = |stem: &str| -> Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(format!("{stem}.json"))).unwrap())
            .unwrap()
    };
    let least_cusp = |v: &Value| -> (f64, f64) {
        v["cusps"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["kind"] == "cusp")
            .map(|c| (c["value"].as_f64().unwrap(), c["omega"].as_f64().unwrap()))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap_or_else(|| panic!("no cusp: {}", v["cusps"]))
    };
    let (k3_c, omega_c) = least_cusp(&json("folds_k3"));
    let invariant = 0.01 * k3_c.sqrt();
    for k3 in [1e6, 2e6, 5e6, 1e7, 2e7] {
        let (f_c, w) = least_cusp(&json(&format!("folds_road_k3_{}", fmt_num(k3))));
        assert!((f_c * k3.sqrt() / invariant - 1.0).abs() < 1e-7, "k3 = {k3}: F_c = {f_c}");
        assert!((w / omega_c - 1.0).abs() < 1e-7, "k3 = {k3}: Ω_c = {w} vs {omega_c}");
    }
    for f in ["folds_k3.svg", "folds_road.svg", "folds_road_cusps.svg", "folds_k3.csv"] {
        assert!(dir.join(f).exists(), "{f}");
    }
    // The half car's figures are the half car's: its columns, bounce and pitch panels.
    let csv = std::fs::read_to_string(dir.join("half_car_v20_p_0.5.csv")).unwrap();
    assert!(
        csv.starts_with("omega,stable,z_max_abs,z_mean,z_amp1,z_rms,z_min,z_max,theta_max_abs"),
        "{csv:.80}"
    );
    let texts = svg_texts(&dir.join("half_car_v20.svg"));
    assert_eq!(texts.iter().filter(|t| *t == "p = 0.5").count(), 2, "{texts:?}");
    assert!(texts.iter().any(|t| t.contains("body pitch")), "{texts:?}");
    let v = json("half_car_jumps_v_20");
    assert_eq!(v["model"], "half-car");
    assert!(v["folds"].as_array().unwrap().len() >= 4, "{}", v["folds"]);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("jumps begin at k3 = 3.2"), "the threshold next to the paper's claim");
    assert!(summary.contains("Model `half-car`"), "the figure's own model is named");
    for (id, _, _) in paper() {
        assert!(summary.contains(&format!("(`{id}`)")), "{id}");
    }
    assert!(summary.contains("**Paper:**"));
    assert!(!summary.contains("inconclusive ("), "every check decided");
}

#[test]
fn a_study_that_fails_part_way_writes_what_finished() {
    // A valid file whose parts can fail only when run: with c = 10 the Duffing curves
    // have no fold at either end of the range of F, so that fold analysis (and the
    // figure of it alone) fails; the c = 0.1 one must still be written. (A value out of
    // its domain, p = 2.5 as a fractional order, is refused at validation now.)
    let text = r#"
model = "duffing"
harmonics = 1
frequency = { from = 0.5, to = 3.0 }

[[figure]]
id = "ok_and_bad"
vary = "c"
values = [0.1, 10.0]
folds = { param = "F", from = 0.01, to = 0.3 }

[[figure]]
id = "bad_only"
params = { c = 10.0 }
folds = { param = "F", from = 0.01, to = 0.3 }
"#;
    let cli = Cli::builtin();
    let s = study::parse(text, "partial.toml").unwrap();
    s.validate(cli.registry()).unwrap();
    let dir = tmp("partial");
    let outcome = study::run(&s, cli.registry(), &dir).unwrap();
    assert!(dir.join("ok_and_bad_c_0.1.csv").exists());
    assert!(dir.join("ok_and_bad.svg").exists());
    assert!(!dir.join("ok_and_bad_c_10.csv").exists());
    assert!(!dir.join("bad_only.svg").exists());
    assert!(
        outcome.failures.iter().any(|f| f.contains("ok_and_bad, c = 10") && f.contains("no fold")),
        "{:#?}",
        outcome.failures
    );
    assert!(outcome.failures.iter().any(|f| f.starts_with("bad_only")), "{:#?}", outcome.failures);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("part(s) failed") && summary.contains("c = 10"), "{summary}");

    // Through the binary: non-zero exit, one line naming the failure, files written.
    let path = dir.join("partial.toml");
    std::fs::write(&path, text).unwrap();
    let out2 = dir.join("bin");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_ihbm"))
        .args(["run", path.to_str().unwrap(), "--out", out2.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("failed"), "{err}");
    assert!(out2.join("ok_and_bad_c_0.1.csv").exists());
    assert!(out2.join("summary.md").exists());
}

/// Two parts of a study that would write one file are refused before anything runs,
/// naming both; so is a study whose output would overwrite the study file itself.
#[test]
fn name_clashes_and_outputs_over_the_input_are_refused() {
    let cli = Cli::builtin();
    let head = "model = \"duffing\"\nfrequency = { from = 0.5, to = 2.0 }\n";
    for (figures, needles) in [
        // equal once rounded for the file name
        (
            "[[figure]]\nid = \"a\"\nvary = \"F\"\nvalues = [0.1, 0.1000001]\n",
            ["a_F_0.1.csv", "F = 0.1"],
        ),
        // the same value twice
        ("[[figure]]\nid = \"a\"\nvary = \"F\"\nvalues = [0.5, 0.5]\n", ["a_F_0.5.csv", "F = 0.5"]),
        // a figure id equal to another figure's derived name
        (
            "[[figure]]\nid = \"f1\"\nvary = \"F\"\nvalues = [1.0]\n[[figure]]\nid = \"f1_F_1\"\n",
            ["f1_F_1.csv", "figure 'f1_F_1'"],
        ),
    ] {
        let text = format!("{head}{figures}");
        let s = study::parse(&text, "clash.toml").unwrap();
        s.validate(cli.registry()).unwrap();
        let e = study::output_files(&s, cli.registry()).unwrap_err().to_string();
        for n in needles {
            assert!(e.contains(n), "{e}");
        }
        let dir = tmp("clash");
        assert!(study::run(&s, cli.registry(), &dir).is_err());
        assert!(!dir.exists(), "nothing written");
    }

    // `ihbm run f1.svg --out .`: the figure f1 would overwrite the study file.
    let dir = tmp("over-input");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("f1.svg");
    let text = format!("{head}[[figure]]\nid = \"f1\"\n");
    std::fs::write(&path, &text).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_ihbm"))
        .args(["run", path.to_str().unwrap(), "--out", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("over its own file"), "{err}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "the study file is untouched");
}

/// A fold figure's parameter and range are checked before anything runs, errors at
/// the parameter's name (`file:line:col`); claims checked on curves do not apply to it.
#[test]
fn fold_figures_are_validated_before_running() {
    let cli = Cli::builtin();
    let head =
        "model = \"duffing\"\nfrequency = { from = 0.5, to = 3.0 }\n[[figure]]\nid = \"f\"\n";
    for (fig, needles) in [
        ("folds = { param = \"q\", from = 0.01, to = 0.3 }\n", vec!["study.toml:5:19", "unknown parameter 'q'"]),
        ("folds = { param = \"F\", from = 0.3, to = 0.3 }\n", vec!["study.toml:5:19", "two different finite values"]),
        (
            "folds = { param = \"F\", from = 0.01, to = 0.3 }\n[[figure.check]]\nkind = \"folds\"\nexpect = \"present\"\n",
            vec!["study.toml:5:19", "takes no 'timedomain' or 'check'"],
        ),
    ] {
        let text = format!("{head}{fig}");
        let s = study::parse(&text, "study.toml").unwrap();
        let e = s.validate(cli.registry()).unwrap_err().to_string();
        for n in needles {
            assert!(e.contains(n), "{e} does not contain {n}");
        }
    }
    // and a valid one runs: the one-harmonic Duffing's cusp (closed form in the book)
    let text = format!("{head}harmonics = 1\nfolds = {{ param = \"F\", from = 0.01, to = 0.3 }}\n");
    let s = study::parse(&text, "study.toml").unwrap();
    s.validate(cli.registry()).unwrap();
    let dir = tmp("folds");
    let outcome = study::run(&s, cli.registry(), &dir).unwrap();
    assert!(outcome.failures.is_empty(), "{:#?}", outcome.failures);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("jumps begin at F = 5.158455e-2"), "{summary}");
}

/// Values that could only fail when run are refused at validation, at their place in
/// the file: a parameter out of its domain (study-wide or varied), a band of three
/// numbers, a non-finite from_value, a label for an output the model does not have.
#[test]
fn values_that_would_fail_later_are_refused_at_validation() {
    let cli = Cli::builtin();
    let head = "model = \"fractional-duffing\"\nfrequency = { from = 0.5, to = 2.0 }\n";
    for (rest, needles) in [
        ("params = { p = 3.0 }\n", vec!["study.toml:3:12", "fractional order p", "[0, 2]"]),
        (
            "[[figure]]\nid = \"a\"\nvary = \"p\"\nvalues = [0.5, 2.5]\n",
            vec!["study.toml:5:8", "fractional order p: 2.5"],
        ),
        (
            "[[figure]]\nid = \"a\"\n[[figure.check]]\nkind = \"folds\"\nexpect = \"present\"\nband = [1.0, 2.0, 3.0]\n",
            vec!["study.toml:8:8", "two numbers", "not 3"],
        ),
        (
            "[[figure]]\nid = \"a\"\n[[figure.check]]\nkind = \"folds\"\nexpect = \"present\"\nfrom_value = nan\n",
            vec!["from_value", "finite"],
        ),
        ("labels = { zz = \"nothing\" }\n", vec!["labels", "'zz'", "known: x"]),
    ] {
        let text = format!("{head}{rest}");
        let e = match study::parse(&text, "study.toml") {
            Err(e) => e.to_string(),
            Ok(s) => s.validate(cli.registry()).unwrap_err().to_string(),
        };
        for n in needles {
            assert!(e.contains(n), "{rest}: {e} does not contain {n}");
        }
    }
}

/// A torus figure (`boundary = "torus"`) follows torus points, not folds: the quarter
/// car's torus bubble at k3 = 5e6 turns at F ≈ 0.0987 (where sweeps just above find
/// two torus points and just below none: `tests/continuation/torus_curves.rs`). An
/// unknown boundary is refused at its position.
#[test]
fn torus_figures_follow_torus_points() {
    let cli = Cli::builtin();
    let head = "model = \"quarter-car\"\nfrequency = { from = 50.0, to = 80.0 }\n[[figure]]\nid = \"t\"\nparams = { k3 = 5e6 }\n";
    let bad =
        format!("{head}folds = {{ param = \"F\", from = 0.09, to = 0.2, boundary = \"tori\" }}\n");
    let e = study::parse(&bad, "study.toml").unwrap_err().to_string();
    assert!(e.contains("study.toml:6:") && e.contains("torus"), "{e}");
    let text =
        format!("{head}folds = {{ param = \"F\", from = 0.09, to = 0.2, boundary = \"torus\" }}\n");
    let s = study::parse(&text, "study.toml").unwrap();
    s.validate(cli.registry()).unwrap();
    let dir = tmp("torus");
    let outcome = study::run(&s, cli.registry(), &dir).unwrap();
    assert!(outcome.failures.is_empty(), "{:#?}", outcome.failures);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("torus) response begins at F = 9.87"), "{summary}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("t.json")).unwrap()).unwrap();
    assert_eq!(json["boundary"], "torus");
    let p = &json["curves"][0]["points"][0];
    let w = p["torus_frequency"].as_f64().unwrap();
    assert!(w > 0.0 && w < 0.5 * p["omega"].as_f64().unwrap(), "{p}");
}
