//! `oscillator!` rejects non-polynomial models at compile time, with a message that says
//! what is allowed and a span on the offending token (the `.stderr` files are the
//! expected diagnostics), and accepts the exact CONTRACT example in a user crate.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
    t.pass("tests/ui/pass/contract_example.rs");
}
