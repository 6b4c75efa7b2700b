//! Backbones in study figures: the spec's errors point at the file, line and column;
//! a figure's backbones are the closed form's, continued to the figure's largest
//! amplitude, written and drawn; the reference study's nonlinear-mode figure starts
//! at the quarter car's linearised damped modes.

use crate::elliptic::duffing_omega;
use ihbm::models::QuarterCar;
use ihbm::{study, Cli};
use num_complex::Complex64;
use serde_json::Value;
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

/// `backbone = true` with no linear natural frequency in the range (the Duffing
/// oscillator's is 1 rad/s, the range 2 to 3): a failed part saying so, and the
/// figure is still drawn, without backbones.
#[test]
fn no_mode_in_the_range_is_a_failed_part_and_the_figure_is_kept() {
    let reg = Cli::builtin();
    let text = "model = \"duffing\"\nfrequency = { from = 2.0, to = 3.0 }\n[[figure]]\nid = \"n\"\nbackbone = true\n";
    let s = study::parse(text, "n.toml").unwrap();
    s.validate(reg.registry()).unwrap();
    let dir = tmp("none-in-range");
    let out = study::run(&s, reg.registry(), &dir).unwrap();
    assert_eq!(
        out.failures,
        ["n: no mode's linear natural frequency lies in the range: no backbone drawn"]
    );
    let svg = std::fs::read_to_string(dir.join("n.svg")).unwrap();
    assert!(!svg.contains("data-overlay"));
    assert!(!dir.join("n_backbone1_x.json").exists());
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
        let exact = duffing_omega(1.0, a);
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
    let w_top = duffing_omega(1.0, top);
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

/// The linearised quarter car, z = φ e^{λt}: `det(Z(iω) - iω ξ M) = 0` with
/// `Z = [[m1 λ² + s, -s], [-s, m2 λ² + s + kt]]`, `s = k1 + c λ + h λ^p` (the exact
/// fractional factor), for (ω, ξ) by Newton from the undamped frequencies; D = ξ/(2ω).
fn damped_modes(q: &QuarterCar) -> [(f64, f64); 2] {
    let det = |w: f64, xi: f64| -> Complex64 {
        let l = Complex64::new(0.0, w);
        let s = q.k1 + q.c * l + q.h * l.powf(q.p);
        let a = q.m1 * l * l + s - xi * l * q.m1;
        let d = q.m2 * l * l + s + q.kt - xi * l * q.m2;
        a * d - s * s
    };
    [(q.k1 / q.m1).sqrt(), ((q.k1 + q.kt) / q.m2).sqrt()].map(|guess| {
        let (mut w, mut xi) = (guess, 0.0);
        for _ in 0..60 {
            let f = det(w, xi);
            let h = 1e-7 * w;
            let fw = (det(w + h, xi) - det(w - h, xi)) / (2.0 * h);
            let fx = (det(w, xi + h) - det(w, xi - h)) / (2.0 * h);
            let m = fw.re * fx.im - fx.re * fw.im;
            w -= (f.re * fx.im - fx.re * f.im) / m;
            xi -= (fw.re * f.im - f.re * fw.im) / m;
        }
        (w, xi / (2.0 * w))
    })
}

/// The reference study's figure of the quarter car's two modes, run alone: each
/// backbone starts at its damped linear mode (the 2×2 determinant above, to 1e-6),
/// the body mode stiffens and its forced peaks lean the same way (their frequency
/// grows with their amplitude), and the figure has both backbones and the damping row.
#[test]
fn the_reference_modes_figure_starts_at_the_linearised_quarter_car() {
    let reg = Cli::builtin();
    let mut s = study::parse(study::REFERENCE_STUDY, "reference").unwrap();
    s.figures.retain(|f| f.id.get_ref() == "modes_backbones");
    s.labels.retain(|k, _| k == "z1" || k == "y"); // the half car's are for its figures
    assert_eq!(s.figures.len(), 1);
    s.validate(reg.registry()).unwrap();
    let fig = &s.figures[0];
    let k3 = fig.params.iter().find(|(k, _)| k.get_ref() == "k3").map(|(_, v)| *v);
    let q = QuarterCar { k3: k3.unwrap(), ..Default::default() };
    let modes = damped_modes(&q);
    let dir = tmp("reference-modes");
    let out = study::run(&s, reg.registry(), &dir).unwrap();
    assert!(out.failures.is_empty(), "{:#?}", out.failures);
    // A backbone starts at 1e-4 of the amplitude it is continued to, in its output.
    // The wheel hop continued in z1 (which barely moves in it: z1/z2 ≈ -0.01) to the
    // body's forced amplitude starts with a wheel deflection ~100 times larger, where
    // the cubic spring already shifts ω by 3e-5: its start is not the linear limit.
    for (mode, o) in [(1, "z1"), (1, "y"), (2, "y")] {
        let (w, d) = modes[mode - 1];
        let b = json(&dir, &format!("modes_backbones_backbone{mode}_{o}"));
        let first = &b["points"][0];
        let (w0, d0) = (f(&first["omega"]), f(&first["damping"]));
        assert!((w0 / w - 1.0).abs() < 1e-6, "mode {mode} on {o}: ω = {w0} vs {w}");
        assert!((d0 / d - 1.0).abs() < 1e-6, "mode {mode} on {o}: D = {d0} vs {d}");
    }
    for (mode, o) in [(1, "z1"), (1, "y"), (2, "z1"), (2, "y")] {
        let b = json(&dir, &format!("modes_backbones_backbone{mode}_{o}"));
        assert_eq!(b["ended"], "reached the amplitude", "mode {mode} on {o}");
        assert!(b["points"].as_array().unwrap().iter().all(|p| p["stable"].is_null()));
    }
    // The body mode stiffens (k3 > 0): ω grows along its backbone in z1 ...
    let body = json(&dir, "modes_backbones_backbone1_z1");
    let pts = body["points"].as_array().unwrap();
    let (w_first, w_last) = (f(&pts[0]["omega"]), f(&pts[pts.len() - 1]["omega"]));
    assert!(w_last > w_first * 1.01, "the body mode stiffens: {w_first} to {w_last}");
    // ... and the forced body peaks (Ω below 40 rad/s) lean the same way: the larger
    // the road amplitude, the higher the peak and its frequency.
    let peaks: Vec<(f64, f64)> = ["0.01", "0.02", "0.03"]
        .iter()
        .map(|v| {
            let c = json(&dir, &format!("modes_backbones_F_{v}"));
            c["points"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|p| f(&p["omega"]) < 40.0)
                .map(|p| (f(&p["outputs"]["z1"]["max_abs"]), f(&p["omega"])))
                .fold((0.0, 0.0), |m, x| if x.0 > m.0 { x } else { m })
        })
        .collect();
    for w in peaks.windows(2) {
        assert!(w[1].0 > w[0].0 && w[1].1 > w[0].1, "peaks (max |z1|, Ω): {peaks:?}");
    }
    let texts = std::fs::read_to_string(dir.join("modes_backbones.svg")).unwrap();
    for tag in ["backbone mode 1 z1", "backbone mode 2 y"] {
        assert!(texts.contains(&format!("data-overlay=\"{tag}\"")), "{tag}");
    }
    assert!(texts.contains("modal damping ratio D"));
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    let (w1, d1) = modes[0];
    assert!(summary.contains(&format!("| mode 1 | z1 | {w1:.4} | {d1:.4e} |")), "{summary}");
    let (w2, d2) = modes[1];
    assert!(summary.contains(&format!("| mode 2 | y | {w2:.4} | {d2:.4e} |")), "{summary}");
}
