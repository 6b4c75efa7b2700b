//! `oscillator!` rejects non-polynomial models at compile time, with a message that says
//! what is allowed and a span on the offending token (the `.stderr` files are the
//! expected diagnostics). The cases call `ihbm_macros::oscillator!`, which is what
//! `ihbm::oscillator!` re-exports, so that the check needs the macro crate alone (see
//! this crate's `Cargo.toml`).

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
