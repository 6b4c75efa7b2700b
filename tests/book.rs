//! The book's example programs.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/book/`.

#[path = "book/cli_user_example.rs"]
mod cli_user_example;
#[path = "book/examples.rs"]
mod examples;
