//! The book's example programs, run once each: `cargo test` compiles `examples/` but
//! does not run them, and the book quotes their output.

#[allow(dead_code)]
#[path = "../../examples/user_model.rs"]
mod user_model;

#[allow(dead_code)]
#[path = "../../examples/compare_td.rs"]
mod compare_td;

#[allow(dead_code)]
#[path = "../../examples/sweep_plot.rs"]
mod sweep_plot;

#[test]
fn sweep_plot_example_writes_its_files() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("ihbm-sweep-plot-{}", std::process::id()));
    let folds = sweep_plot::run(&dir).unwrap();
    // a hardening curve with this forcing folds twice
    assert_eq!(folds.len(), 2, "{folds:?}");
    for f in ["sweep.csv", "sweep.json", "sweep.svg"] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let svg = std::fs::read_to_string(dir.join("sweep.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("the SVG is well-formed XML");
    let lines = doc.descendants().filter(|n| n.has_tag_name("polyline")).count();
    // the stable branches plus the dashes of the unstable one
    assert!(lines > 3, "only {lines} polylines");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn user_model_example_runs() {
    user_model::run(None).unwrap();
    // A bad parameter is an error naming it, not a panic.
    let e = user_model::run(Some("G=1".into())).unwrap_err().to_string();
    assert!(e.contains("'G'"), "{e}");
}

#[test]
fn compare_td_example_runs() {
    compare_td::run().unwrap();
}
