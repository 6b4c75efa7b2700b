//! The `ihbm` command line end to end.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/cli/`.

#[path = "cli/commands.rs"]
mod commands;
#[path = "cli/common.rs"]
mod common;
#[path = "cli/continuation.rs"]
mod continuation;
#[path = "cli/interrupt.rs"]
mod interrupt;
#[path = "cli/model_files.rs"]
mod model_files;
#[path = "shared/model_text.rs"]
mod model_text;
#[path = "cli/random_inputs.rs"]
mod random_inputs;
