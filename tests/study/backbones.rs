//! Backbones in study figures: the spec's errors point at the file, line and column;
//! a figure's backbones are the closed form's, continued to the figure's largest
//! amplitude, written and drawn.

use ihbm::{study, Cli};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("ihbm-study-backbones-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn json(dir: &Path, stem: &str) -> Value {
    let text = std::fs::read_to_string(dir.join(format!("{stem}.json")))
        .unwrap_or_else(|e| panic!("{stem}.json: {e}"));
    serde_json::from_str(&text).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

const HEAD: &str = "model = \"duffing\"\nfrequency = { from = 0.5, to = 2.0 }\n";

#[test]
fn backbone_spec_errors_point_at_the_value() {
    let reg = Cli::builtin();
    for (figure, line, col, needle) in [
        (
            "backbone = { modes = [2] }",
            5,
            12,
            "backbone mode 2 is not a mode of model 'duffing' (1 to 1",
        ),
        ("backbone = { modes = [] }", 5, 12, "backbone modes is empty"),
        ("backbone = { modes = [1, 1] }", 5, 12, "backbone mode 1 is listed twice"),
        ("backbone = { mode = [1] }", 5, 14, "unknown field `mode`"),
        ("backbone = 1", 5, 12, "true, false or a table { modes = [1, 2] }"),
        (
            "folds = { param = \"F\", from = 0.1, to = 0.2 }\nbackbone = true",
            6,
            12,
            "a 'folds' figure draws no backbones",
        ),
    ] {
        let text = format!("{HEAD}[[figure]]\nid = \"b\"\n{figure}\n");
        let e = study::parse(&text, "bb.toml")
            .and_then(|s| s.validate(reg.registry()).map(|_| s))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(&format!("bb.toml:{line}:{col}: ")), "{figure}: {e}");
        assert!(e.contains(needle), "{figure}: {e}");
    }
    // `false` draws none and is valid
    let s = study::parse(&format!("{HEAD}[[figure]]\nid = \"b\"\nbackbone = false\n"), "ok.toml")
        .unwrap();
    s.validate(reg.registry()).unwrap();
}

/// The complete elliptic integral of the first kind K(m), by the AGM.
fn ellip_k(m: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - m).sqrt());
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// The damped Duffing oscillator x'' + c x' + x + x³ = F cos Ωt: EPMC's artificial
/// damping cancels c ẋ exactly (ξ = c, m = 1), so its mode is the undamped one, the
/// elliptic closed form Ω = π √(1 + a²) / (2 K(a² / (2(1 + a²)))), with D = c / (2ω).
/// The figure's backbone is that, up to the largest max |x| of its curves, in a CSV
/// and a JSON, drawn over the panel, and summarised.
#[test]
fn a_figure_draws_the_backbone_to_its_largest_amplitude() {
    let reg = Cli::builtin();
    let text = format!(
        "{HEAD}harmonics = 15\n[[figure]]\nid = \"d\"\nvary = \"F\"\nvalues = [0.1, 0.3]\nbackbone = true\n"
    );
    let s = study::parse(&text, "d.toml").unwrap();
    s.validate(reg.registry()).unwrap();
    let files = study::output_files(&s, reg.registry()).unwrap();
    for n in ["d_backbone1_x.csv", "d_backbone1_x.json"] {
        assert!(files.iter().any(|f| f == n), "{n} in {files:?}");
    }
    let dir = tmp("duffing");
    let out = study::run(&s, reg.registry(), &dir).unwrap();
    assert!(out.failures.is_empty(), "{:#?}", out.failures);
    let top = ["d_F_0.1", "d_F_0.3"]
        .iter()
        .flat_map(|stem| {
            json(&dir, stem)["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| f(&p["outputs"]["x"]["max_abs"]))
                .collect::<Vec<_>>()
        })
        .fold(0.0f64, f64::max);
    let b = json(&dir, "d_backbone1_x");
    assert_eq!(b["mode"], 1);
    assert_eq!(b["ended"], "reached the amplitude");
    let points = b["points"].as_array().unwrap();
    let last = points.last().unwrap();
    let a_last = f(&last["outputs"]["x"]["max_abs"]);
    assert!((a_last / top - 1.0).abs() < 1e-9, "continued to {a_last}, the curves' top {top}");
    for p in points {
        let (w, d, a) = (f(&p["omega"]), f(&p["damping"]), f(&p["outputs"]["x"]["max_abs"]));
        let s2 = a * a;
        let exact = PI * (1.0 + s2).sqrt() / (2.0 * ellip_k(s2 / (2.0 * (1.0 + s2))));
        assert!((w / exact - 1.0).abs() < 1e-8, "a = {a}: ω = {w} vs {exact}");
        assert!((d / (0.1 / (2.0 * w)) - 1.0).abs() < 1e-9, "a = {a}: D = {d}");
        assert!(p["stable"].is_null(), "ξ = c ≠ 0: not a motion of the model");
    }
    let csv = std::fs::read_to_string(dir.join("d_backbone1_x.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + points.len());
    let svg = std::fs::read_to_string(dir.join("d.svg")).unwrap();
    assert!(svg.contains("data-overlay=\"backbone mode 1 x\""), "the dotted backbone");
    assert!(svg.contains("modal damping ratio D"), "the row of ω and D against amplitude");
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    let row = summary.lines().find(|l| l.starts_with("| mode 1 | x |")).unwrap_or_else(|| {
        panic!("no backbone row in {summary}");
    });
    // linear ω = 1 and D = c/2 = 0.05; at the top, ω from the closed form
    let s2 = top * top;
    let w_top = PI * (1.0 + s2).sqrt() / (2.0 * ellip_k(s2 / (2.0 * (1.0 + s2))));
    for cell in [
        "1.0000".to_string(),
        "5.0000e-2".to_string(),
        format!("{top:.4e}"),
        format!("{w_top:.4}"),
        format!("{:.4e}", 0.1 / (2.0 * w_top)),
        "none".to_string(),
        "reached the amplitude".to_string(),
    ] {
        assert!(row.contains(&format!("| {cell} |")), "{cell} in {row}");
    }
}
