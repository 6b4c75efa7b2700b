//! Arc-length continuation: closed forms, the reference paper's curves, harmonic
//! convergence, snapshots.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/continuation/`.

#[path = "continuation/backbones.rs"]
mod backbones;
#[path = "continuation/convergence.rs"]
mod convergence;
#[path = "continuation/cycle_families.rs"]
mod cycle_families;
#[path = "continuation/duffing.rs"]
mod duffing;
#[path = "shared/elliptic.rs"]
mod elliptic;
#[path = "continuation/fold_curves.rs"]
mod fold_curves;
#[path = "continuation/forced_peaks.rs"]
mod forced_peaks;
#[path = "continuation/half_car.rs"]
mod half_car;
#[path = "continuation/internal_resonances.rs"]
mod internal_resonances;
#[path = "continuation/mode_stability.rs"]
mod mode_stability;
#[path = "continuation/period_two.rs"]
mod period_two;
#[path = "continuation/quarter_car.rs"]
mod quarter_car;
#[path = "continuation/snapshots.rs"]
mod snapshots;
#[path = "continuation/torus_curves.rs"]
mod torus_curves;
