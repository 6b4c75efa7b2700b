//! Hill stability: closed forms, centring, tracking, time integration, chains against
//! their monodromy matrices.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/stability/`.

#[path = "stability/centring.rs"]
mod centring;
#[path = "stability/common.rs"]
mod common;
#[path = "stability/fractional.rs"]
mod fractional;
#[path = "shared/heap.rs"]
mod heap;
#[path = "stability/mathieu.rs"]
mod mathieu;
#[path = "shared/mathieu.rs"]
mod mathieu_model;
#[path = "stability/scale.rs"]
mod scale;
#[path = "stability/size.rs"]
mod size;
#[path = "stability/timedomain.rs"]
mod timedomain;
#[path = "stability/tracking.rs"]
mod tracking;
