//! The one place where the command line and studies call the solvers (solve, sweep,
//! simulate) for a concrete model type: settings as a user writes them in, records
//! out. Below it, models registered by name ([`registry`]), the settings
//! ([`settings`]) and the progress display ([`progress`]); above it, [`crate::study`]
//! and the command line. Nothing here imports either.

use crate::balance::Balance;
use crate::continuation;
use crate::corrector::{self, SolveOptions};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::report::{SimOutput, SimRecord, SolveRecord};
use crate::results::Curve;
use crate::stability::{Hill, StabilityOptions};
use crate::timedomain::{self, Scheme, SimOptions};
use serde::{Deserialize, Serialize};

pub mod progress;
pub mod registry;
pub mod settings;

pub use settings::SweepSettings;

/// Settings of a single-frequency solve.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveSettings {
    /// Number of harmonics N (>= 1).
    pub harmonics: usize,
}

impl Default for SolveSettings {
    fn default() -> Self {
        SolveSettings { harmonics: 5 }
    }
}

/// The time-integration scheme of `simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum SchemeName {
    /// Grünwald–Letnikov, first order (the paper's "power series expansion").
    Gl,
    /// Second-order (BDF2-type) fractional rule.
    Bdf2,
}

impl SchemeName {
    /// `"gl"` or `"bdf2"`.
    pub fn as_str(self) -> &'static str {
        match self {
            SchemeName::Gl => "gl",
            SchemeName::Bdf2 => "bdf2",
        }
    }
}

/// Settings of a time integration.
#[derive(Debug, Clone, PartialEq)]
pub struct SimSettings {
    /// Time step, s; `None`: the integrator's default (T/400, T = 2π/Ω).
    pub dt: Option<f64>,
    /// Forcing periods to integrate (at least `timedomain::MIN_PERIODS`).
    pub periods: usize,
    /// Scheme.
    pub scheme: SchemeName,
}

impl Default for SimSettings {
    fn default() -> Self {
        SimSettings { dt: None, periods: 100, scheme: SchemeName::Bdf2 }
    }
}

/// Check a frequency: finite and > 0.
pub fn check_omega(what: &str, omega: f64) -> Result<()> {
    if omega.is_finite() && omega > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidValue {
            what: what.into(),
            value: omega.to_string(),
            expected: "a finite frequency > 0 rad/s".into(),
        })
    }
}

/// Check a harmonic count: >= 1.
pub fn check_harmonics(n: usize) -> Result<()> {
    if n >= 1 {
        Ok(())
    } else {
        Err(Error::InvalidValue {
            what: "number of harmonics".into(),
            value: n.to_string(),
            expected: "N >= 1".into(),
        })
    }
}

/// Solve at one frequency from the linearized guess. A Newton failure is not an error
/// here: the record carries `converged: false` and the last iterate.
pub fn solve<M: Model>(
    name: &str,
    model: &M,
    omega: f64,
    s: &SolveSettings,
) -> Result<SolveRecord> {
    check_omega("omega", omega)?;
    check_harmonics(s.harmonics)?;
    let opts = SolveOptions { harmonics: s.harmonics, ..SolveOptions::default() };
    let (coeffs, converged, iterations, residual_norm) =
        match corrector::solve(model, omega, &opts, None) {
            Ok(sol) => (sol.coeffs, true, sol.iterations, sol.residual_norm),
            Err(Error::NotConverged { last, iterations, residual_norm, .. }) => {
                (last, false, iterations, residual_norm)
            }
            Err(e) => return Err(e),
        };
    let stable = stability(model, omega, s.harmonics, &coeffs, converged);
    Ok(SolveRecord {
        model: name.to_string(),
        omega,
        harmonics: s.harmonics,
        converged,
        iterations,
        residual_norm,
        stable,
        outputs: corrector::output_summaries(model, &coeffs, s.harmonics),
    })
}

/// Stability verdict of a converged solution (Hill's method); `None` when it could not
/// be computed (not converged, or the eigenproblem failed).
fn stability<M: Model>(
    model: &M,
    omega: f64,
    harmonics: usize,
    coeffs: &[f64],
    converged: bool,
) -> Option<bool> {
    if !converged {
        return None;
    }
    let mut hill = Hill::new(model, harmonics).ok()?;
    let mut bal = Balance::new(model, harmonics).ok()?;
    hill.analyse(&mut bal, coeffs, omega, &StabilityOptions::default()).ok().map(|f| f.stable)
}

/// Trace the amplitude–frequency curve from `from` to `to` (rad/s).
pub fn sweep<M: Model>(
    name: &str,
    model: &M,
    from: f64,
    to: f64,
    s: &SweepSettings,
) -> Result<Curve> {
    check_omega("--from", from)?;
    check_omega("--to", to)?;
    check_harmonics(s.harmonics)?;
    if from >= to {
        return Err(Error::InvalidValue {
            what: "frequency range".into(),
            value: format!("from {from} to {to}"),
            expected: "from < to".into(),
        });
    }
    let opts = s.options().map_err(|e| e.cli())?;
    let mut curve = continuation::sweep(model, from, to, &opts)?;
    curve.model = name.to_string();
    Ok(curve)
}

/// A parameter sweep at a fixed frequency: which parameter, over which range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamRange<'a> {
    /// Parameter name (as declared by the model).
    pub param: &'a str,
    /// Start value.
    pub from: f64,
    /// End value (> from).
    pub to: f64,
    /// Forcing frequency, rad/s (> 0), fixed along the curve.
    pub omega: f64,
}

/// Trace the response at fixed frequency as a parameter goes over its range; the
/// curve's `parameter` names it.
pub fn sweep_param<M: Model>(
    name: &str,
    model: &M,
    r: &ParamRange,
    s: &SweepSettings,
) -> Result<Curve> {
    let ParamRange { param, from, to, omega } = *r;
    check_omega("--omega", omega)?;
    check_harmonics(s.harmonics)?;
    model.param_index(param)?;
    if !(from.is_finite() && to.is_finite() && from < to) {
        return Err(Error::InvalidValue {
            what: format!("--from/--to range of {param}"),
            value: format!("from {from} to {to}"),
            expected: "finite values with from < to".into(),
        });
    }
    let opts = s.options().map_err(|e| e.cli())?;
    let mut curve = continuation::sweep_param(model, param, from, to, omega, &opts)?;
    curve.model = name.to_string();
    Ok(curve)
}

/// Integrate from rest and report the steady statistics of every output.
pub fn simulate<M: Model>(name: &str, model: &M, omega: f64, s: &SimSettings) -> Result<SimRecord> {
    check_omega("omega", omega)?;
    let opts = SimOptions {
        dt: s.dt,
        periods: s.periods,
        scheme: match s.scheme {
            SchemeName::Gl => Scheme::Gl,
            SchemeName::Bdf2 => Scheme::Bdf2,
        },
        ..SimOptions::default()
    };
    let sim = timedomain::simulate(model, omega, &opts)?;
    Ok(SimRecord {
        model: name.to_string(),
        omega,
        dt: sim.dt,
        periods: sim.periods,
        scheme: s.scheme.as_str().to_string(),
        outputs: sim
            .outputs
            .iter()
            .map(|o| SimOutput { name: o.name.clone(), max_abs: o.max_abs, mean: o.mean })
            .collect(),
    })
}
