//! Helpers of the end-to-end tests of the `ihbm` binary.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Run the built `ihbm` binary.
pub fn ihbm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ihbm")).args(args).output().expect("the ihbm binary runs")
}

/// Standard output as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A path in a per-process temporary directory.
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("ihbm-cli-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A bad input: non-zero exit, one line on stderr that contains every `needle`.
pub fn assert_rejected(args: &[&str], needles: &[&str]) {
    let o = ihbm(args);
    assert!(!o.status.success(), "{args:?} succeeded: {}", stdout(&o));
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: stderr does not name '{n}': {err}");
    }
}
