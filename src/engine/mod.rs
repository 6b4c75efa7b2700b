//! The one place where the command line, studies and Python call the solvers: an
//! [`analysis::Analysis`] (what to compute, as a user writes it) run against a model
//! registered by name ([`registry`]) gives an [`analysis::Outcome`]. Beside them, the
//! continuation settings ([`settings`]), the progress display ([`progress`]) and work
//! a signal cuts short ([`detach`]); above, [`crate::study`] and the command line.
//! Nothing here imports either.

use crate::backbone::{Backbone, BackboneEvent, BackboneOptions, End};
use crate::balance::Balance;
use crate::continuation::Observer;
use crate::corrector::{self, SolveOptions};
use crate::error::{Error, Result};
use crate::model::{DynModel, Model};
use crate::report::Overlay;
use crate::results::{Curve, SimOutput, SimRecord, SolveRecord, Stability, Unknown};
use crate::stability::{Hill, StabilityOptions};
use crate::timedomain::{self, CompareRow, Scheme, SimOptions};

pub mod analysis;
pub mod detach;
pub mod progress;
pub mod registry;
pub mod settings;

pub use settings::SweepSettings;

/// Settings of a single-frequency solve.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveSettings {
    /// Number of harmonics N (>= 1).
    pub harmonics: usize,
    /// The parameters whose sensitivities every output reports (none by default).
    pub sensitivity: Vec<String>,
}

impl Default for SolveSettings {
    fn default() -> Self {
        SolveSettings { harmonics: crate::fourier::DEFAULT_HARMONICS, sensitivity: Vec::new() }
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
    pub scheme: Scheme,
}

impl SimSettings {
    /// The integrator's options for these settings.
    pub fn options(&self) -> SimOptions {
        SimOptions {
            dt: self.dt,
            periods: self.periods,
            scheme: self.scheme,
            ..SimOptions::default()
        }
    }
}

impl Default for SimSettings {
    fn default() -> Self {
        let d = SimOptions::default();
        SimSettings { dt: d.dt, periods: d.periods, scheme: d.scheme }
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

/// How a front end names the arguments the engine checks, so that a message names
/// what its user typed: the command line's flags ([`ArgNames::CLI`]) or, say, Python
/// keywords (`omega_from`).
#[derive(Debug, Clone, Copy)]
pub struct ArgNames {
    /// The start of a frequency sweep.
    pub from: &'static str,
    /// The end of a frequency sweep.
    pub to: &'static str,
    /// The fixed frequency of a parameter sweep.
    pub omega: &'static str,
    /// The start of a fold analysis's frequency range.
    pub omega_from: &'static str,
    /// The end of a fold analysis's frequency range.
    pub omega_to: &'static str,
    /// A continuation setting, from its study-file key (`max_step`).
    pub setting: fn(&str) -> String,
}

impl ArgNames {
    /// The command line's flags (`--from`, `--max-step`).
    pub const CLI: ArgNames = ArgNames {
        from: "--from",
        to: "--to",
        omega: "--omega",
        omega_from: "--omega-from",
        omega_to: "--omega-to",
        setting: settings::flag,
    };
}

/// Solve at one frequency from the linearized guess (checked by
/// [`analysis::Analysis::check`]). A Newton failure is not an error here: the record
/// carries `converged: false` and the last iterate.
fn solve(model: &dyn DynModel, omega: f64, s: &SolveSettings) -> Result<SolveRecord> {
    let opts = SolveOptions { harmonics: s.harmonics, ..SolveOptions::default() };
    let indices =
        s.sensitivity.iter().map(|p| model.param_index(p)).collect::<Result<Vec<usize>>>()?;
    let mut failure = None;
    let nout = model.outputs().len();
    // Without a converged solution the rates do not exist.
    let mut rates = vec![vec![crate::results::OutputRates::NONE; nout]; indices.len()];
    let (coeffs, converged, iterations, residual_norm) =
        match corrector::solve(model, omega, &opts, None) {
            Ok(sol) => {
                if !indices.is_empty() {
                    rates = sol.output_rates(model, &indices)?;
                }
                (sol.coeffs, true, sol.iterations, sol.residual_norm)
            }
            Err(Error::NotConverged { last, iterations, residual_norm, .. }) => {
                (last, false, iterations, residual_norm)
            }
            // Failure as data: the start (x = 0) and its residual are what is known.
            Err(e @ Error::SingularJacobian { .. }) => {
                let mut hb = crate::balance::Balance::new(model, s.harmonics)?;
                let zero = vec![0.0; hb.len()];
                let mut r = vec![0.0; hb.len()];
                hb.residual(&zero, omega, &mut r);
                failure = Some(e.to_string());
                (zero, false, 0, corrector::norm(&r))
            }
            Err(e) => return Err(e),
        };
    let stability = stability(model, omega, s.harmonics, &coeffs, converged);
    let sensitivities = s.sensitivity.iter().cloned().zip(rates).collect();
    Ok(SolveRecord {
        model: model.name().to_string(),
        omega,
        harmonics: s.harmonics,
        converged,
        iterations,
        residual_norm,
        stability,
        outputs: corrector::output_summaries(
            &crate::outputs::At::model(model, &model.param_values(), omega),
            &coeffs,
            s.harmonics,
        ),
        failure,
        sensitivities,
    })
}

/// Stability of a solution by Hill's method, or why there is no verdict.
fn stability(
    model: &dyn DynModel,
    omega: f64,
    harmonics: usize,
    coeffs: &[f64],
    converged: bool,
) -> Stability {
    if !converged {
        return Stability::Unknown(Unknown::NotConverged);
    }
    let analysis = Hill::new(model, harmonics).and_then(|mut hill| {
        let mut bal = Balance::new(model, harmonics)?;
        hill.analyse(&mut bal, coeffs, omega, &StabilityOptions::default())
    });
    match analysis {
        Ok(f) => Stability::from_verdict(f.stable),
        Err(e) => Stability::Unknown(Unknown::Failed(e.to_string())),
    }
}

/// What a backbone is asked for, by name (the command line's and a study's terms).
#[derive(Debug, Clone, PartialEq)]
pub struct BackboneSettings {
    /// The mode, 1-based.
    pub mode: usize,
    /// The output continued to `to` (default: the first).
    pub output: Option<String>,
    /// The amplitude to reach (max |x(t)| of the output).
    pub to: f64,
    /// Number of harmonics N.
    pub harmonics: usize,
}

/// The backbone of mode `s.mode` of `model` ([`crate::backbone`]), reporting every
/// event to `observer`, which may stop it.
fn backbone(
    model: &dyn DynModel,
    s: &BackboneSettings,
    observer: &mut dyn Observer<BackboneEvent, Backbone>,
) -> Result<Backbone> {
    let output = match &s.output {
        Some(o) => model.output_index(o)?,
        None => 0,
    };
    let opts = BackboneOptions {
        mode: s.mode,
        output,
        to: s.to,
        harmonics: s.harmonics,
        ..Default::default()
    };
    crate::backbone::backbone_with(model, &opts, observer)
}

/// A backbone drawn over a sweep: of which mode, continued in which output.
#[derive(Debug)]
pub struct SweepBackbone {
    /// The mode (1-based).
    pub mode: usize,
    /// The output (index) continued to the sweep's largest amplitude of it.
    pub output: usize,
    /// The backbone (which may have ended before that amplitude: it says why), or why
    /// it could not start.
    pub backbone: Result<Backbone>,
}

/// The backbones that belong on a sweep's figure: for every mode whose linear
/// natural frequency lies in `[from, to]` and every output, the backbone continued in
/// that output up to `tops[output]` (the sweep's largest `max |x|` of it).
fn sweep_backbones(
    model: &dyn DynModel,
    (from, to): (f64, f64),
    tops: &[f64],
    harmonics: usize,
) -> Vec<SweepBackbone> {
    let mut out = Vec::new();
    for mode in 1..=model.dofs().len() {
        let Ok(lm) = crate::linearisation::linear_mode(model, mode) else { continue };
        if !(lm.omega >= from.min(to) && lm.omega <= from.max(to)) {
            continue;
        }
        for (output, &top) in tops.iter().enumerate() {
            if !(top > 0.0 && top.is_finite()) {
                continue;
            }
            let opts = BackboneOptions { mode, output, to: top, harmonics, ..Default::default() };
            let backbone = crate::backbone::backbone(model, &opts);
            out.push(SweepBackbone { mode, output, backbone });
        }
    }
    out
}

/// The largest finite `max |x|` of every output (in model order) over `curves`: how
/// far a figure's backbones are continued ([`analysis::Analysis::Backbones`]'s `tops`).
pub fn largest_amplitudes<'a>(
    curves: impl IntoIterator<Item = &'a Curve>,
    outputs: usize,
) -> Vec<f64> {
    let mut tops = vec![0.0f64; outputs];
    for c in curves {
        for p in &c.points {
            for (t, o) in tops.iter_mut().zip(&p.outputs) {
                if o.max_abs.is_finite() {
                    *t = t.max(o.max_abs);
                }
            }
        }
    }
    tops
}

/// The backbones of [`analysis::Analysis::Backbones`] as overlays of a figure (on the panel of the
/// output each was continued in, its `(ω, max |x|)` points), with a warning for each
/// that stopped short of its amplitude (drawn as far as it went) or could not start.
/// `output_names` are the model's, in order.
pub fn backbone_overlays(
    found: &[SweepBackbone],
    output_names: &[String],
) -> (Vec<Overlay>, Vec<String>) {
    let mut overlays = Vec::new();
    let mut warnings = Vec::new();
    for sb in found {
        let name = output_names.get(sb.output).cloned().unwrap_or_default();
        match &sb.backbone {
            Ok(b) => {
                if b.ended != End::ReachedAmplitude {
                    warnings.push(format!(
                        "the backbone of mode {} on {name} {} (drawn as far as it went)",
                        sb.mode, b.ended
                    ));
                }
                overlays.push(Overlay {
                    label: format!("backbone, mode {}", sb.mode),
                    output: name.clone(),
                    points: b
                        .points
                        .iter()
                        .filter_map(|p| p.outputs.get(sb.output).map(|o| (p.omega, o.max_abs)))
                        .collect(),
                    tag: format!("backbone mode {} {name}", sb.mode),
                });
            }
            Err(e) => warnings.push(format!("no backbone of mode {} on {name}: {e}", sb.mode)),
        }
    }
    (overlays, warnings)
}

/// Integrate from rest and report the steady statistics of every output.
fn simulate(model: &dyn DynModel, omega: f64, s: &SimSettings) -> Result<SimRecord> {
    let sim = timedomain::simulate(model, omega, &s.options())?;
    Ok(SimRecord {
        model: model.name().to_string(),
        omega,
        dt: sim.dt,
        periods: sim.periods,
        scheme: s.scheme.name().to_string(),
        outputs: sim.outputs.iter().map(SimOutput::from).collect(),
        start_up: sim.start_up,
    })
}

/// Harmonic balance (N = `harmonics`, from the linearised guess) against time
/// integration from rest at `omega`: the comparison of
/// [`timedomain::compare_at`], failures of either method recorded in the row.
fn compare(model: &dyn DynModel, omega: f64, s: &SimSettings, harmonics: usize) -> CompareRow {
    let hb = SolveOptions { harmonics, ..SolveOptions::default() };
    timedomain::compare_at(model, omega, &s.options(), &hb)
}
