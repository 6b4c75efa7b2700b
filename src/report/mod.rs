//! Turning results into files a user reads: CSV, JSON, SVG figures and `summary.md`.
//!
//! Data flows one way: solvers fill [`crate::results`] types (or the records below),
//! this module only formats them. Every writer takes data and returns text or writes
//! one file; nothing here solves anything.

pub mod csv;
pub mod json;
pub mod legend;
pub mod plot;
pub mod smooth;
pub mod summary;

use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::path::Path;

pub use csv::curve_csv;
pub use json::{simulate_json, solve_json, sweep_json};
pub use plot::{figure_svg, Figure, Panel, Series, TimeMarker};
pub use summary::{convergence_line, curve_facts, CurveFacts};

/// The unit of the frequency axis of figures (data files are always in rad/s).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FreqUnit {
    /// Radians per second (the solvers' unit).
    #[default]
    #[serde(rename = "rad/s")]
    RadPerSec,
    /// Hertz: Ω / 2π.
    #[serde(rename = "Hz")]
    Hz,
}

impl FreqUnit {
    /// Convert a frequency in rad/s to this unit.
    pub fn from_rad(self, omega: f64) -> f64 {
        match self {
            FreqUnit::RadPerSec => omega,
            FreqUnit::Hz => omega / std::f64::consts::TAU,
        }
    }

    /// The unit as printed on axes.
    pub fn label(self) -> &'static str {
        match self {
            FreqUnit::RadPerSec => "rad/s",
            FreqUnit::Hz => "Hz",
        }
    }
}

/// Write `text` to `path`, creating parent directories; errors name the path.
pub fn write_file(path: &Path, text: &str) -> Result<(), Error> {
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)
                .map_err(|source| Error::Io { path: dir.display().to_string(), source })?;
        }
    }
    std::fs::write(path, text)
        .map_err(|source| Error::Io { path: path.display().to_string(), source })
}
