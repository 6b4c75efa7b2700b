//! `oscillator!` rejects non-polynomial models at compile time, with a message that says
//! what is allowed and a span on the offending token. Each `tests/ui/NAME.rs` holds one
//! refused model and `NAME.stderr` the error exactly as rustc prints it.
//!
//! The check runs what the macro runs before it writes Rust — `ihbm_dsl::check_tokens`,
//! the parser and the symbolic checks — on the invocation's tokens, parsed from the file
//! so that every span keeps its line and column, and renders the error in rustc's layout
//! (message, location, source line, carets under the span) to compare with the `.stderr`
//! text byte for byte.
//!
//! It does not start a compiler. A check through trybuild (a cargo build per case,
//! started from the test) reported every case as compiled on some machines: cargo's
//! target probe there read unrelated text on its standard input, failed, and trybuild
//! found no diagnostics to compare. Here a case that is accepted, or refused with another
//! message or span, fails with the expected and the actual text side by side.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The cases, sorted, with their expected output.
fn cases() -> Vec<(PathBuf, PathBuf)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ui");
    let mut cases: Vec<(PathBuf, PathBuf)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .map(|p| (p.clone(), p.with_extension("stderr")))
        .collect();
    cases.sort();
    cases
}

/// The tokens inside the file's `oscillator! { ... }` (with their positions in the file).
fn invocation(file: &syn::File) -> Option<proc_macro2::TokenStream> {
    file.items.iter().find_map(|item| match item {
        syn::Item::Macro(m) if m.mac.path.segments.last()?.ident == "oscillator" => {
            Some(m.mac.tokens.clone())
        }
        _ => None,
    })
}

/// One error as rustc prints it for a span on one line: `error: message`, the location,
/// the source line, carets under the span (at least one).
fn render(error: &syn::Error, source: &str, shown_path: &str) -> String {
    let span = error.span();
    let (start, end) = (span.start(), span.end());
    let line_text = source.lines().nth(start.line.saturating_sub(1)).unwrap_or("");
    let number = start.line.to_string();
    let pad = " ".repeat(number.len());
    let width =
        if end.line == start.line { end.column.saturating_sub(start.column).max(1) } else { 1 };
    let mut out = String::new();
    let _ = writeln!(out, "error: {error}");
    let _ = writeln!(out, "{pad}--> {shown_path}:{}:{}", start.line, start.column + 1);
    let _ = writeln!(out, "{pad} |");
    let _ = writeln!(out, "{number} | {line_text}");
    let _ = writeln!(out, "{pad} | {}{}", " ".repeat(start.column), "^".repeat(width));
    out
}

/// What the macro prints for a case, or why it prints nothing.
fn diagnostics(path: &Path) -> Result<String, String> {
    let source = std::fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
    let file = syn::parse_file(&source).map_err(|e| format!("not a Rust file: {e}"))?;
    let tokens = invocation(&file).ok_or("no `oscillator! { ... }` in the file")?;
    let shown = format!("tests/ui/{}", path.file_name().unwrap_or_default().to_string_lossy());
    match ihbm_dsl::check_tokens(tokens) {
        Ok(_) => {
            Err("the macro accepted the model: zero diagnostics for a case that must fail".into())
        }
        Err(errors) => Ok(errors.into_iter().map(|e| render(&e, &source, &shown)).collect()),
    }
}

#[test]
fn every_case_is_refused_with_its_expected_message_and_span() {
    let cases = cases();
    assert!(cases.len() >= 30, "expected the 30 cases of tests/ui, found {}", cases.len());
    let mut failures = Vec::new();
    for (case, expected_path) in &cases {
        let name = case.file_name().unwrap_or_default().to_string_lossy().into_owned();
        let expected = match std::fs::read_to_string(expected_path) {
            Ok(text) => text,
            Err(e) => {
                failures
                    .push(format!("{name}: no expected output {}: {e}", expected_path.display()));
                continue;
            }
        };
        match diagnostics(case) {
            Err(why) => failures.push(format!("{name}: {why}\nexpected:\n{expected}")),
            Ok(actual) if actual.trim_end() != expected.trim_end() => failures.push(format!(
                "{name}: a different error\nexpected:\n{expected}\nactual:\n{actual}"
            )),
            Ok(_) => println!("{name} ... ok"),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// The check itself is not vacuous: a model the macro accepts is reported as such, and a
/// wrong expectation is a mismatch.
#[test]
fn an_accepted_model_fails_the_check() {
    let dir = std::env::temp_dir().join(format!("ihbm-diagnostics-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let case = dir.join("good.rs");
    std::fs::write(
        &case,
        "ihbm_macros::oscillator! {\n    pub struct Good {\n        params { k = 1.0, F = 1.0 }\n        dofs { x }\n        equations { D(x, 2) + k * x = F * cos(omega * t); }\n    }\n}\n",
    )
    .expect("write the case");
    let outcome = diagnostics(&case);
    let _ = std::fs::remove_dir_all(&dir);
    let why = outcome.expect_err("an accepted model must not produce diagnostics");
    assert!(why.contains("zero diagnostics"), "{why}");
}
