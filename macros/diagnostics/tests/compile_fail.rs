//! `oscillator!` rejects non-polynomial models at compile time, with a message that says
//! what is allowed and a span on the offending token (the `.stderr` files are the
//! expected diagnostics).
//!
//! In a crate of its own: see its `Cargo.toml`.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
