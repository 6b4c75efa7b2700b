//! The book's example programs, run once each: `cargo test` compiles `examples/` but
//! does not run them, and the book quotes their output.

#[allow(dead_code)]
#[path = "../examples/user_model.rs"]
mod user_model;

#[allow(dead_code)]
#[path = "../examples/compare_td.rs"]
mod compare_td;

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
