//! Every value a study's validation refuses is named by `file:line:col` at the value
//! itself: each case marks the offending value with `@` (removed before parsing), and
//! the message must start with that position.

use ihbm::{study, Cli};

const HEAD: &str = "model = \"quarter-car\"\nfrequency = { from = 1.0, to = 2.0 }\n";
const FIG: &str = "[[figure]]\nid = \"a\"\n";

fn expect_at(text_with_marker: &str, needle: &str) {
    let at = text_with_marker.find('@').expect("a marker");
    let text = text_with_marker.replacen('@', "", 1);
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap().chars().count() + 1;
    let reg = Cli::builtin();
    let e = match study::parse(&text, "s.toml") {
        Ok(s) => s.validate(reg.registry()).expect_err(text_with_marker).to_string(),
        Err(e) => e.to_string(),
    };
    let prefix = format!("s.toml:{line}:{col}: ");
    assert!(e.starts_with(&prefix), "expected {prefix}...: {e}\n{text}");
    assert!(e.contains(needle), "{e}");
}

#[test]
fn every_refused_value_is_located() {
    let cases: Vec<(String, &str)> = vec![
        (format!("harmonics = @0\n{HEAD}"), "harmonics = 0"),
        (format!("{HEAD}{FIG}harmonics = @2000\n"), "harmonics = 2000"),
        ("model = \"quarter-car\"\nfrequency = @{ from = 2.0, to = 1.0 }\n".into(), "frequency from 2"),
        (format!("{HEAD}{FIG}frequency = @{{ from = 0.0, to = 1.0 }}\n"), "figure 'a': frequency"),
        (format!("{HEAD}sweep = {{ max_step = @-1.0 }}\n"), "sweep.max_step"),
        (format!("{HEAD}{FIG}sweep = {{ tol = @0.0 }}\n"), "sweep.tol"),
        (format!("{HEAD}{FIG}timedomain = @{{ omegas = [] }}\n"), "non-empty"),
        (format!("{HEAD}{FIG}timedomain = {{ omegas = [1.0, @-2.0] }}\n"), "omega -2"),
        (format!("{HEAD}{FIG}timedomain = {{ omegas = [1.0], periods = @3 }}\n"), "periods"),
        (
            format!("{HEAD}{FIG}timedomain = {{ omegas = [1.0], steps_per_period = @5.0 }}\n"),
            "steps_per_period",
        ),
        (format!("{HEAD}{FIG}[[figure.check]]\nkind = \"peak\"\nexpect = \"increasing\"\noutput = @\"w\"\n"), "'w'"),
        (format!("{HEAD}{FIG}[[figure.check]]\nkind = \"peak\"\nexpect = \"increasing\"\nband = @[3.0, 1.0]\n"), "lo < hi"),
        (format!("{HEAD}{FIG}[[figure.check]]\nkind = \"peak\"\nexpect = \"unchanged\"\ntol = @-1.0\n"), "tol"),
        (format!("{HEAD}{FIG}[[figure.check]]\nkind = \"folds\"\nexpect = \"present\"\nfrom_value = @nan\n"), "from_value"),
        (format!("{HEAD}{FIG}[[figure.check]]\nkind = @\"timedomain\"\nexpect = \"agree\"\n"), "'timedomain' table"),
        (format!("{HEAD}labels = {{ w = @\"x\" }}\n"), "labels: 'w'"),
        (
            format!("{HEAD}{FIG}vary = \"k3\"\nvalues = @[{}]\n", vec!["1.0"; 1001].join(", ")),
            "1001 values",
        ),
        // Within N <= 1000 but beyond the memory of Hill's matrices for the quarter
        // car (the largest N is 872: tests/stability/size.rs), at the count.
        (format!("{HEAD}{FIG}harmonics = @1000\n"), "Hill stability matrices"),
        (format!("harmonics = @1000\n{HEAD}{FIG}"), "largest N that fits"),
        // The second figure's value, not the first's.
        (format!("{HEAD}{FIG}[[figure]]\nid = \"b\"\nharmonics = @0\n"), "figure 'b'"),
    ];
    for (text, needle) in &cases {
        expect_at(text, needle);
    }
}

/// A model file is read once per study: validation, planning and the run use one
/// text of it, so an edit between them (here, the file emptied after validation)
/// changes nothing in the run.
#[test]
fn a_study_reads_its_model_file_once() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("ihbm-model-cache-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("qc.ihbm");
    std::fs::write(&model, include_str!("../../examples/quarter_car.ihbm")).unwrap();
    let text = "model = \"qc.ihbm\"\nfrequency = { from = 1.0, to = 2.0 }\n\
                [[figure]]\nid = \"a\"\n[[figure]]\nid = \"b\"\nmodel = \"qc.ihbm\"\n";
    let file = dir.join("s.toml");
    let s = study::parse(text, file.to_str().unwrap()).unwrap();
    let reg = Cli::builtin();
    s.validate(reg.registry()).unwrap();
    std::fs::write(&model, "not a model").unwrap();
    let out = study::run(&s, reg.registry(), &dir.join("out")).unwrap();
    assert!(out.failures.is_empty(), "{:?}", out.failures);
    assert!(dir.join("out/a.csv").exists() && dir.join("out/b.csv").exists());
}
