//! Time integration: closed forms, convergence orders, memory, errors, harmonic balance.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/timedomain/`.

#[path = "timedomain/convergence.rs"]
mod convergence;
#[path = "timedomain/errors.rs"]
mod errors;
#[path = "timedomain/hb.rs"]
mod hb;
#[path = "shared/heap.rs"]
mod heap;
#[path = "timedomain/linear.rs"]
mod linear;
#[path = "timedomain/memory.rs"]
mod memory;
#[path = "timedomain/memory_bound.rs"]
mod memory_bound;
#[path = "timedomain/settling.rs"]
mod settling;
