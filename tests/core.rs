//! The numerical core: closed forms, Newton, spectral identities, structure shortcuts.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/core/`.

#[path = "core/boxed.rs"]
mod boxed;
#[path = "core/linear.rs"]
mod linear;
#[path = "core/newton.rs"]
mod newton;
#[path = "core/sensitivities.rs"]
mod sensitivities;
#[path = "core/spectral.rs"]
mod spectral;
#[path = "core/structure.rs"]
mod structure;
