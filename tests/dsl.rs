//! The `oscillator!` macro: generated code against hand-written twins, closed forms and
//! time integration (its compile-time diagnostics are tested in the macro crate,
//! `macros/tests/`).
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/dsl/`.

#[path = "dsl/codegen.rs"]
mod codegen;
#[path = "dsl/coefficients.rs"]
mod coefficients;
#[path = "dsl/common.rs"]
mod common;
#[path = "dsl/equivalence.rs"]
mod equivalence;
#[path = "dsl/handwritten.rs"]
mod handwritten;
#[path = "shared/mathieu.rs"]
mod mathieu_model;
#[path = "shared/model_text.rs"]
mod model_text;
#[path = "dsl/models.rs"]
mod models;
#[path = "dsl/nonlinear.rs"]
mod nonlinear;
#[path = "dsl/nonsmooth.rs"]
mod nonsmooth;
#[path = "dsl/outputs.rs"]
mod outputs;
#[path = "dsl/parametric.rs"]
mod parametric;
#[path = "dsl/runtime.rs"]
mod runtime;
#[path = "dsl/timedomain.rs"]
mod timedomain;
