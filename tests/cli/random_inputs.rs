//! Random argument vectors and random (mostly malformed) study documents: never a
//! panic; either success or a non-zero status with one `error: ...` line.

use ihbm::{study, Cli};
use proptest::prelude::*;

/// Tests here may write files named by random arguments (`--json 1`): keep them in a
/// scratch directory.
fn scratch() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("ihbm-proptest-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::env::set_current_dir(&dir).unwrap();
}

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("models".to_string()),
        Just("solve".to_string()),
        Just("sweep".to_string()),
        Just("simulate".to_string()),
        Just("quarter-car".to_string()),
        Just("duffing".to_string()),
        Just("fractional-duffing".to_string()),
        Just("nope".to_string()),
        Just("--omega".to_string()),
        Just("--from".to_string()),
        Just("--to".to_string()),
        Just("--harmonics".to_string()),
        Just("--set".to_string()),
        Just("--json".to_string()),
        Just("--csv".to_string()),
        Just("--plot".to_string()),
        Just("--dt".to_string()),
        Just("--periods".to_string()),
        Just("--scheme".to_string()),
        Just("gl".to_string()),
        Just("bdf2".to_string()),
        Just("-".to_string()),
        Just("--help".to_string()),
        Just("out.svg".to_string()),
        Just("k3=1e6".to_string()),
        Just("F=x".to_string()),
        Just("p=3".to_string()),
        Just("=".to_string()),
        // Frequencies kept small so that a valid sweep or simulation is quick.
        Just("0.5".to_string()),
        Just("0.8".to_string()),
        Just("1".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e400".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("20".to_string()),
        // Wide ranges: continued in decades, quick, and never a NaN point.
        Just("1e-6".to_string()),
        Just("1e6".to_string()),
        Just("1e-300".to_string()),
        Just("".to_string()),
        "[a-z=0-9.-]{1,6}",
    ]
}

fn args() -> impl Strategy<Value = Vec<String>> {
    (
        prop_oneof![Just("models"), Just("solve"), Just("sweep"), Just("simulate"), Just("bogus")],
        prop::collection::vec(token(), 0..9),
    )
        .prop_map(|(cmd, rest)| {
            let mut v = vec!["ihbm".to_string(), cmd.to_string()];
            v.extend(rest);
            v
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn random_arguments_never_panic(argv in args()) {
        scratch();
        let cli = Cli::builtin();
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let code = cli.run_with(argv.clone(), &mut out, &mut err);
        let err = String::from_utf8_lossy(&err).into_owned();
        if code == 0 {
            prop_assert!(err.is_empty(), "{argv:?}: exit 0 with stderr {err}");
            // A successful run's JSON holds no NaN or infinity (serde_json writes them
            // as null) and no null but a stability verdict that does not exist.
            let text = String::from_utf8_lossy(&out).into_owned();
            if let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) {
                prop_assert!(no_null(&v, ""), "{argv:?}: null in {text}");
            }
            prop_assert!(!text.contains("NaN"), "{argv:?}: {text}");
        } else {
            prop_assert_eq!(err.lines().count(), 1, "{:?}: {}", argv, err);
            prop_assert!(err.starts_with("error: ") && err.len() > 8, "{argv:?}: {err}");
        }
    }
}

/// No `null` in `v` but under the key `stable` (`null` there means "no verdict").
fn no_null(v: &serde_json::Value, key: &str) -> bool {
    use serde_json::Value::*;
    match v {
        Null => key == "stable",
        Array(a) => a.iter().all(|x| no_null(x, key)),
        Object(m) => m.iter().all(|(k, x)| no_null(x, k)),
        _ => true,
    }
}

/// `file:line:col: ...`
fn located(m: &str, file: &str) -> bool {
    let Some(rest) = m.strip_prefix(file).and_then(|r| r.strip_prefix(':')) else { return false };
    let mut parts = rest.splitn(3, ':');
    let num =
        |p: Option<&str>| p.is_some_and(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()));
    num(parts.next()) && num(parts.next()) && parts.next().is_some_and(|r| r.starts_with(' '))
}

const GOOD: &str = r#"model = "quarter-car"
frequency = { from = 1.0, to = 2.0 }
[[figure]]
id = "a"
vary = "k3"
values = [1e6]
"#;

fn fragment() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("model = \"quarter-car\"\n".to_string()),
        Just("model = \"duffing\"\n".to_string()),
        Just("model = 3\n".to_string()),
        Just("harmonics = 0\n".to_string()),
        Just("harmonics = 4\n".to_string()),
        Just("harmonics = -1\n".to_string()),
        Just("unit = \"Hz\"\n".to_string()),
        Just("unit = \"furlongs\"\n".to_string()),
        Just("frequency = { from = 1.0, to = 2.0 }\n".to_string()),
        Just("frequency = { from = 2.0, to = 1.0 }\n".to_string()),
        Just("frequency = { from = 1.0 }\n".to_string()),
        Just("params = { k3 = 1e6 }\n".to_string()),
        Just("params = { zz = 1 }\n".to_string()),
        Just("params = { k3 = \"big\" }\n".to_string()),
        Just("outputs = [\"z1\", \"y\"]\n".to_string()),
        Just("outputs = [\"w\"]\n".to_string()),
        Just("[[figure]]\n".to_string()),
        Just("id = \"f1\"\n".to_string()),
        Just("id = \"bad id\"\n".to_string()),
        Just("vary = \"harmonics\"\n".to_string()),
        Just("vary = \"nope\"\n".to_string()),
        Just("values = [4, 5]\n".to_string()),
        Just("values = [0.5]\n".to_string()),
        Just("values = []\n".to_string()),
        Just("timedomain = { omegas = [1.0], periods = 3 }\n".to_string()),
        Just("timedomain = { omegas = [-1.0] }\n".to_string()),
        Just("[[figure.check]]\n".to_string()),
        Just("kind = \"peak\"\n".to_string()),
        Just("kind = \"magic\"\n".to_string()),
        Just("expect = \"decreasing\"\n".to_string()),
        Just("band = [3.0, 1.0]\n".to_string()),
        Just("[sweep]\n".to_string()),
        Just("max_step = 0.1\n".to_string()),
        Just("bogus = true\n".to_string()),
        Just("sweep = { max_step = -1.0 }\n".to_string()),
        Just("sweep = { tol = 1e-300, min_step = 2.0 }\n".to_string()),
        Just("labels = { w = \"x\" }\n".to_string()),
        Just("frequency = { from = 1e-6, to = 1e6 }\n".to_string()),
        Just("harmonics = 1001\n".to_string()),
        Just("timedomain = { omegas = [1.0], steps_per_period = 5.0 }\n".to_string()),
        Just("output = \"w\"\n".to_string()),
        Just("tol = -1.0\n".to_string()),
        Just("from_value = nan\n".to_string()),
        Just("values = [1e6, 1e6]\n".to_string()),
        Just("params = { p = 3.0 }\n".to_string()),
        Just("kind = \"timedomain\"\n".to_string()),
        "[ -~]{0,20}\n",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn random_study_documents_never_panic(frags in prop::collection::vec(fragment(), 0..12), keep in any::<bool>()) {
        let text = if keep { format!("{GOOD}{}", frags.concat()) } else { frags.concat() };
        let reg = Cli::builtin();
        match study::parse(&text, "random.toml") {
            Ok(s) => {
                if let Err(e) = s.validate(reg.registry()) {
                    // Every refused value is located: file:line:col.
                    let m = e.to_string();
                    prop_assert!(located(&m, "random.toml") && !m.contains('\n'), "{m}");
                }
            }
            Err(e) => {
                let m = e.to_string();
                prop_assert!(m.starts_with("random.toml:") && !m.contains('\n'), "{m}");
            }
        }
    }
}

#[test]
fn the_good_document_is_valid() {
    let s = study::parse(GOOD, "good.toml").unwrap();
    s.validate(Cli::builtin().registry()).unwrap();
}
