//! The command line of CONTRACT section 2, as clap derive types.

use super::engine::SchemeName;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Periodic steady states of nonlinear oscillators with fractional-order damping, by
/// the incremental harmonic balance method. Frequencies are in rad/s.
#[derive(Debug, Parser)]
#[command(name = "ihbm", version, about, long_about = None, propagate_version = true)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the models, or show one: parameters with defaults, dofs, outputs, equations.
    Models {
        /// A model name (omit to list all).
        name: Option<String>,
    },
    /// Periodic solution at one forcing frequency (initial guess: the linearized model).
    Solve {
        /// Model name (see `ihbm models`).
        name: String,
        /// Forcing frequency Ω, rad/s (> 0).
        #[arg(long, value_name = "W", allow_negative_numbers = true)]
        omega: f64,
        /// Number of harmonics N (>= 1).
        #[arg(long, value_name = "N", default_value_t = 5)]
        harmonics: usize,
        /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Write the JSON result to FILE, or to standard output with no FILE or `-`.
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
    },
    /// Trace the amplitude–frequency curve (continuation through folds, stability, jumps).
    Sweep {
        /// Model name (see `ihbm models`).
        name: String,
        /// Start frequency, rad/s (> 0).
        #[arg(long, value_name = "W0", allow_negative_numbers = true)]
        from: f64,
        /// End frequency, rad/s (> from).
        #[arg(long, value_name = "W1", allow_negative_numbers = true)]
        to: f64,
        /// Number of harmonics N (>= 1).
        #[arg(long, value_name = "N", default_value_t = 5)]
        harmonics: usize,
        /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Write the curve as CSV (one row per point).
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        /// Write the curve as JSON to FILE (`-`: standard output).
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
        /// Draw the curve (every output, one panel each) as SVG.
        #[arg(long, value_name = "FILE.svg")]
        plot: Option<PathBuf>,
    },
    /// Integrate in time from rest (Caputo derivative from t = 0); steady statistics of
    /// the last 10 forcing periods.
    Simulate {
        /// Model name (see `ihbm models`).
        name: String,
        /// Forcing frequency Ω, rad/s (> 0).
        #[arg(long, value_name = "W", allow_negative_numbers = true)]
        omega: f64,
        /// Time step, s [default: T/400 with T = 2π/Ω].
        #[arg(long, value_name = "DT", allow_negative_numbers = true)]
        dt: Option<f64>,
        /// Forcing periods to integrate (>= 20: statistics over the last 10, drift vs the 10 before).
        #[arg(long, value_name = "P", default_value_t = 100)]
        periods: usize,
        /// Integration scheme: `gl` (Grünwald–Letnikov, first order) or `bdf2` (second order).
        #[arg(long, value_enum, default_value_t = SchemeName::Bdf2)]
        scheme: SchemeName,
        /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Write the JSON result to FILE, or to standard output with no FILE or `-`.
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
    },
    /// Run a study file; with no file, the reference study of the quarter car (the
    /// paper's figures 4–12 and a figure with folds, jumps and an unstable branch).
    Run {
        /// A study TOML file (omit for the built-in reference study).
        study: Option<PathBuf>,
        /// Output directory.
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
    },
}
