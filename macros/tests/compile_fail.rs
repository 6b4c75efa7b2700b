//! `oscillator!` rejects non-polynomial models at compile time, with a message that says
//! what is allowed and a span on the offending token (the `.stderr` files are the
//! expected diagnostics).
//!
//! Here rather than in `ihbm`'s tests: trybuild builds the cases in a crate of its own
//! with this crate's dev-dependencies, so from here that is `ihbm` without its
//! application features, checked (`cargo check`) rather than built. From `ihbm`'s
//! tests it built clap, plotters, criterion and the rest unoptimised first, about
//! 150 s of a fresh `cargo test --workspace`.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
