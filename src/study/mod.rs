//! Studies: TOML files describing families of curves, time-domain comparisons and the
//! paper's claims; running one writes CSV, JSON, SVG and `summary.md`.
//!
//! ```
//! use ihbm::{study, Cli};
//! let reg = Cli::builtin();
//! let s = study::parse(study::REFERENCE_STUDY, "reference").unwrap();
//! s.validate(reg.registry()).unwrap();
//! let bad = study::parse("model = 1", "bad.toml").unwrap_err().to_string();
//! assert!(bad.starts_with("bad.toml:1:9:"), "{bad}");
//! ```

pub mod claims;
pub mod outcome;
pub mod runner;
pub mod spec;
pub mod summary;

pub use outcome::StudyOutcome;
pub use runner::{output_files, run, run_until};
pub use spec::{parse, Study};

/// The reference study of the quarter car (models/reference_study.toml), built in so
/// that `ihbm run` works from any directory.
pub const REFERENCE_STUDY: &str = include_str!("../../models/reference_study.toml");
