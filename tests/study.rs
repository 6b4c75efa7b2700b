//! The report writers and the reference study.
//!
//! One test binary per area (each integration-test binary links the whole crate, and
//! linking one per file dominated a fresh `cargo test`); the tests are in `tests/study/`.

#[path = "study/backbones.rs"]
mod backbones;
#[path = "shared/elliptic.rs"]
mod elliptic;
#[path = "study/locations.rs"]
mod locations;
#[path = "study/reference.rs"]
mod reference;
#[path = "study/report_files.rs"]
mod report_files;
#[path = "study/report_peaks.rs"]
mod report_peaks;
