//! Model files (`*.ihbm`) wherever a model name goes: `models`, `solve`, `sweep` and
//! studies (relative to the study file). The built-in Duffing's own source text, read
//! at run time, must give byte-identical JSON to the compiled built-in; bad files are
//! one-line errors with the file, line and column.

use crate::common::{assert_rejected, ihbm, stderr, stdout, tmp};
use crate::model_text::bodies;

/// The built-in `duffing`'s source, as a model file.
fn duffing_file() -> std::path::PathBuf {
    let src =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/models/duffing.rs")).unwrap();
    let path = tmp("duffing.ihbm");
    std::fs::write(&path, &bodies(&src)[0]).unwrap();
    path
}

#[test]
fn a_model_file_is_the_built_in_it_was_written_from() {
    let file = duffing_file();
    let f = file.to_str().unwrap();
    for args in [
        vec!["models", "NAME"],
        vec!["solve", "NAME", "--omega", "0.7", "--json", "-"],
        vec!["sweep", "NAME", "--from", "0.5", "--to", "2.5", "--set", "F=0.2", "--json", "-"],
        vec![
            "sweep-param",
            "NAME",
            "--param",
            "F",
            "--from",
            "0.1",
            "--to",
            "0.5",
            "--omega",
            "1.2",
            "--json",
            "-",
        ],
    ] {
        let with = |name: &str| -> Vec<String> {
            args.iter()
                .map(|a| if *a == "NAME" { name.to_string() } else { a.to_string() })
                .collect()
        };
        let (a, b) = (with(f), with("duffing"));
        let (a, b): (Vec<&str>, Vec<&str>) =
            (a.iter().map(|s| s.as_str()).collect(), b.iter().map(|s| s.as_str()).collect());
        let (oa, ob) = (ihbm(&a), ihbm(&b));
        assert!(oa.status.success(), "{a:?}: {}", stderr(&oa));
        assert_eq!(stdout(&oa), stdout(&ob), "{args:?}");
    }
}

#[test]
fn a_study_names_a_model_file_relative_to_itself() {
    let file = duffing_file();
    let dir = file.parent().unwrap().join("study_dir");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "model = \"../duffing.ihbm\"\nharmonics = 3\nfrequency = { from = 0.5, to = 2.5 }\n\
         [[figure]]\nid = \"f\"\nvary = \"F\"\nvalues = [0.1, 0.2]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = ihbm(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("f_F_0.2.csv").exists() && out.join("f.svg").exists());
    // a model file that is not there: the study's line and column, then the file
    std::fs::write(&study, "model = \"nope.ihbm\"\nfrequency = { from = 0.5, to = 2.5 }\n")
        .unwrap();
    assert_rejected(
        &["run", study.to_str().unwrap(), "--out", out.to_str().unwrap()],
        &["s.toml:1:9:", "nope.ihbm"],
    );
}

#[test]
fn bad_model_files_are_one_line_errors_with_their_place() {
    let cases: [(&str, &[u8], &[&str]); 4] = [
        ("syntax.ihbm", b"struct S { params { m = 1.0 } dofs { x }\nequations { m * D(x, 2) + = 0.0; } }", &["syntax.ihbm:2:27:", "expected"]),
        ("poly.ihbm", b"struct S { params { m = 1.0 } dofs { x }\nequations { m * D(x, 2) + x.sin() = 0.0; } }", &["poly.ihbm:2:27:", "not polynomial"]),
        ("count.ihbm", b"struct S { params { m = 1.0 } dofs { x, y }\nequations { m * D(x, 2) = 0.0; } }", &["count.ihbm:2:1:", "1 equation(s) for 2 DOF(s)"]),
        ("bytes.ihbm", b"struct S {\xfe }", &["bytes.ihbm:1:11:", "not UTF-8"]),
    ];
    for (name, text, needles) in cases {
        let path = tmp(name);
        std::fs::write(&path, text).unwrap();
        assert_rejected(&["solve", path.to_str().unwrap(), "--omega", "1"], needles);
    }
    assert_rejected(&["models", tmp("absent.ihbm").to_str().unwrap()], &["absent.ihbm"]);
}
