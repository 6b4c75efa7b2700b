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

/// The outcome of one `solve`: what the solve JSON of CONTRACT section 2 reports.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveRecord {
    /// Model name as registered.
    pub model: String,
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// Whether Newton met its tolerance.
    pub converged: bool,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Residual norm of the returned coefficients.
    pub residual_norm: f64,
    /// Stability verdict (`None` when it could not be computed).
    pub stable: Option<bool>,
    /// Per output, in model output order.
    pub outputs: Vec<crate::results::OutputSummary>,
}

/// Steady statistics of one output of a time integration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimOutput {
    /// Output name.
    pub name: String,
    /// Largest |x| over the last 10 forcing periods.
    pub max_abs: f64,
    /// Mean over the last 10 forcing periods.
    pub mean: f64,
}

/// The outcome of one `simulate`: what the simulate JSON of CONTRACT section 2 reports.
#[derive(Debug, Clone, PartialEq)]
pub struct SimRecord {
    /// Model name as registered.
    pub model: String,
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Time step, s.
    pub dt: f64,
    /// Forcing periods integrated.
    pub periods: usize,
    /// `"gl"` or `"bdf2"`.
    pub scheme: String,
    /// Per output, in model output order.
    pub outputs: Vec<SimOutput>,
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
