//! Result types shared by the solvers and the report: points, curves, folds, jumps.
//!
//! Data flows one way: the corrector and continuation fill these, `report` and the
//! CLI turn them into JSON, CSV, SVG and Markdown.

use serde::Serialize;

/// Summary of one output over one period of a periodic solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputSummary {
    /// Output name.
    pub name: String,
    /// Largest |x(t)| over one period (the paper's "amplitude").
    pub max_abs: f64,
    /// Mean value (a0).
    pub mean: f64,
    /// First-harmonic amplitude sqrt(a1^2 + b1^2).
    pub amp1: f64,
    /// Coefficients of cos(kΩt), k = 0..=N (cos[0] = a0).
    pub cos: Vec<f64>,
    /// Coefficients of sin(kΩt), k = 0..=N (sin[0] = 0).
    pub sin: Vec<f64>,
}

/// Why a piece of a traced curve ended.
#[derive(Debug, Clone, PartialEq)]
pub enum SegmentEnd {
    /// The continuation parameter reached the end of the requested range.
    ReachedEnd,
    /// The response exceeded the amplitude bound (a branch climbing an undamped asymptote).
    AmplitudeBound,
    /// The corrector failed even at the minimum step, or another failure; the reason.
    Stalled(String),
}

impl std::fmt::Display for SegmentEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SegmentEnd::ReachedEnd => write!(f, "reached end"),
            SegmentEnd::AmplitudeBound => write!(f, "amplitude bound"),
            SegmentEnd::Stalled(why) => write!(f, "stalled: {why}"),
        }
    }
}
