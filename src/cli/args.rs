//! The command line, as clap derive types.

use crate::continuation::{AmplitudeBound, InvalidBound, Predictor};
use crate::engine::settings::SweepSettings;
use crate::engine::SimSettings;
use crate::fourier::DEFAULT_HARMONICS;
use crate::timedomain::Scheme;
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
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// Forcing frequency Ω, rad/s (> 0).
        #[arg(long, value_name = "W", allow_negative_numbers = true)]
        omega: f64,
        /// Number of harmonics N (>= 1).
        #[arg(long, value_name = "N", default_value_t = DEFAULT_HARMONICS)]
        harmonics: usize,
        /// Samples per forcing period of the transform (>= 2N + 1) [default: the
        /// alias-free count; for a non-smooth model 16 (2N + 1)].
        #[arg(long, value_name = "M")]
        aft_samples: Option<usize>,
        /// Report how every output's statistics move with parameter P (repeatable):
        /// implicit derivatives along the solution, at fixed Ω.
        #[arg(long, value_name = "P")]
        sensitivity: Vec<String>,
        /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Write the JSON result to FILE, or to standard output with no FILE or `-`.
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
    },
    /// Trace the amplitude–frequency curve (continuation through folds, stability, jumps).
    #[command(after_help = SWEEP_AFTER_HELP)]
    Sweep {
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// Start frequency, rad/s (> 0).
        #[arg(long, value_name = "W0", allow_negative_numbers = true)]
        from: f64,
        /// End frequency, rad/s (> from).
        #[arg(long, value_name = "W1", allow_negative_numbers = true)]
        to: f64,
        /// 2: the branch of period 2·(2π/Ω), switched onto at the first period-doubling
        /// point of the period-1 curve in the range (`--harmonics` then counts
        /// harmonics of Ω/2).
        #[arg(long, value_name = "1|2", default_value_t = 1)]
        period: u32,
        /// The branch with even harmonics (a mean, 2Ω, ...) of a symmetric model,
        /// switched onto at the first symmetry-breaking branch point of the curve.
        #[arg(long, conflicts_with = "period")]
        break_symmetry: bool,
        /// Draw on the `--plot` the backbone of every mode whose linear natural
        /// frequency is in the range, on each output's panel up to the sweep's largest
        /// amplitude of it (dotted, one legend entry per mode).
        #[arg(long, requires = "plot", conflicts_with_all = ["period", "break_symmetry"])]
        backbone: bool,
        /// Harmonics, overrides, output files and continuation settings.
        #[command(flatten)]
        curve: CurveArgs,
    },
    /// Trace the response at a fixed forcing frequency while one model parameter moves
    /// (any parameter, a fractional order included): folds, stability, jumps.
    #[command(after_help = SWEEP_PARAM_AFTER_HELP)]
    SweepParam {
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// The parameter to vary (see `ihbm models NAME`).
        #[arg(long, value_name = "P")]
        param: String,
        /// Start value of the parameter.
        #[arg(long, value_name = "V0", allow_negative_numbers = true)]
        from: f64,
        /// End value of the parameter (> from).
        #[arg(long, value_name = "V1", allow_negative_numbers = true)]
        to: f64,
        /// Forcing frequency Ω, rad/s (> 0), fixed along the curve.
        #[arg(long, value_name = "W", allow_negative_numbers = true)]
        omega: f64,
        /// Harmonics, overrides, output files and continuation settings.
        #[command(flatten)]
        curve: CurveArgs,
    },
    /// Trace every fold of the amplitude–frequency curve as a curve in the plane of Ω
    /// and a parameter, and locate the cusps where two folds meet (where jumps begin).
    #[command(after_help = FOLDS_AFTER_HELP)]
    Folds {
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// The second parameter (see `ihbm models NAME`).
        #[arg(long, value_name = "P")]
        param: String,
        /// One end of the parameter range (the Ω-curves at both ends give the folds).
        #[arg(long, value_name = "V0", allow_negative_numbers = true)]
        from: f64,
        /// The other end of the parameter range.
        #[arg(long, value_name = "V1", allow_negative_numbers = true)]
        to: f64,
        /// Lowest forcing frequency of the sweeps and the fold curves, rad/s.
        #[arg(long, value_name = "W0", default_value_t = 1.0, allow_negative_numbers = true)]
        omega_from: f64,
        /// Highest forcing frequency, rad/s.
        #[arg(long, value_name = "W1", default_value_t = 100.0, allow_negative_numbers = true)]
        omega_to: f64,
        /// What the curves follow: `fold` (jumps), `period-doubling` (a Floquet
        /// multiplier −1) or `torus` (a pair of multipliers leaving the unit circle
        /// elsewhere, Neimark–Sacker); the last two are found by the stability
        /// analysis of the end sweeps.
        #[arg(long, value_enum, value_name = "KIND", default_value = "fold")]
        boundary: crate::bifurcation::Boundary,
        /// Harmonics, overrides, output files and continuation settings (`--plot`
        /// draws the fold curves in the (Ω, P) plane).
        #[command(flatten)]
        curve: CurveArgs,
    },
    /// Continue a nonlinear mode (backbone) from its linear natural frequency to an
    /// amplitude, every forcing term left out, damping balanced by the extended
    /// periodic motion concept: frequency and modal damping ratio against amplitude.
    #[command(after_help = BACKBONE_AFTER_HELP)]
    Backbone {
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// The amplitude to reach: max |X(t)| of the output X.
        #[arg(long, value_name = "A", allow_negative_numbers = true)]
        to: f64,
        /// The mode, in the order of the linearised natural frequencies (1 = lowest).
        #[arg(long, value_name = "K", default_value_t = 1)]
        mode: usize,
        /// The output whose amplitude is continued to A [default: the first output].
        #[arg(long, value_name = "X")]
        output: Option<String>,
        /// Number of harmonics N (>= 1).
        #[arg(long, value_name = "N", default_value_t = DEFAULT_HARMONICS)]
        harmonics: usize,
        /// Samples per forcing period of the transform (>= 2N + 1) [default: the
        /// alias-free count; for a non-smooth model 16 (2N + 1)].
        #[arg(long, value_name = "M")]
        aft_samples: Option<usize>,
        /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Write the points as CSV.
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        /// Write the backbone as JSON to FILE (`-`: standard output).
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
        /// Draw amplitude against frequency and damping ratio against amplitude (SVG).
        #[arg(long, value_name = "FILE.svg")]
        plot: Option<PathBuf>,
    },
    /// Solve for a self-excited periodic motion (limit cycle) of a model without
    /// forcing, near a frequency guess, with its stability.
    #[command(after_help = CYCLE_AFTER_HELP)]
    Cycle {
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// Frequency guess, rad/s: the linearised mode nearest it is followed.
        #[arg(long, value_name = "GUESS", allow_negative_numbers = true)]
        omega: f64,
        /// Number of harmonics N (>= 1).
        #[arg(long, value_name = "N", default_value_t = DEFAULT_HARMONICS)]
        harmonics: usize,
        /// Override a parameter, e.g. `--set mu=0.5` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Continue the cycle in this parameter (with `--from` and `--to`), and locate
        /// the Hopf point where it is born from the equilibrium.
        #[arg(long, value_name = "P", requires_all = ["from", "to"])]
        param: Option<String>,
        /// The parameter's first value (the family starts at the cycle there).
        #[arg(long, value_name = "V0", allow_negative_numbers = true, requires = "param")]
        from: Option<f64>,
        /// The parameter's last value.
        #[arg(long, value_name = "V1", allow_negative_numbers = true, requires = "param")]
        to: Option<f64>,
        /// Write JSON to FILE (`-` or no value: standard output).
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
        /// Write the family's points as CSV (with `--param`).
        #[arg(long, value_name = "FILE", requires = "param")]
        csv: Option<PathBuf>,
        /// Draw the family's amplitudes against the parameter (SVG, with `--param`).
        #[arg(long, value_name = "FILE.svg", requires = "param")]
        plot: Option<PathBuf>,
    },
    /// Integrate in time from rest (Caputo derivative from t = 0); steady statistics of
    /// the last 10 forcing periods.
    Simulate {
        /// Model name (see `ihbm models`), or the path of a model file (`*.ihbm`).
        name: String,
        /// Forcing frequency Ω, rad/s (> 0).
        #[arg(long, value_name = "W", allow_negative_numbers = true)]
        omega: f64,
        /// Time step, s [default: T/400 with T = 2π/Ω].
        #[arg(long, value_name = "DT", allow_negative_numbers = true)]
        dt: Option<f64>,
        /// Forcing periods to integrate (>= 20: statistics over the last 10, drift vs the 10 before).
        #[arg(long, value_name = "P", default_value_t = SimSettings::default().periods)]
        periods: usize,
        /// Integration scheme: `gl` (Grünwald–Letnikov, first order) or `bdf2` (second order).
        #[arg(long, value_enum, default_value_t = SimSettings::default().scheme)]
        scheme: Scheme,
        /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
        #[arg(long = "set", value_name = "P=V")]
        set: Vec<String>,
        /// Write the JSON result to FILE, or to standard output with no FILE or `-`.
        #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
        json: Option<String>,
    },
    /// Run a study file; with no file, the reference study of the quarter car (the
    /// paper's figures 4–12, folds, jumps and unstable branches, fold and torus
    /// curves) and of the half car (bounce and pitch at three speeds).
    Run {
        /// A study TOML file (omit for the built-in reference study).
        study: Option<PathBuf>,
        /// Output directory.
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
    },
}

/// What `sweep` and `sweep-param` share: harmonics, overrides, output files and the
/// continuation settings. The curve's first coordinate (CSV column, plot axis) is Ω
/// for `sweep` and the parameter for `sweep-param`.
#[derive(Debug, Clone, clap::Args)]
pub struct CurveArgs {
    /// Number of harmonics N (>= 1).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_HARMONICS)]
    pub harmonics: usize,
    /// Samples per forcing period of the transform (>= 2N + 1) [default: the alias-free
    /// count; for a non-smooth model 16 (2N + 1)].
    #[arg(long, value_name = "M")]
    pub aft_samples: Option<usize>,
    /// Override a parameter, e.g. `--set k3=3e6` (repeatable).
    #[arg(long = "set", value_name = "P=V")]
    pub set: Vec<String>,
    /// Write the curve as CSV (one row per point).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the curve as JSON to FILE (`-`: standard output).
    #[arg(long, value_name = "FILE|-", num_args = 0..=1, default_missing_value = "-")]
    pub json: Option<String>,
    /// Draw the curve (every output, one panel each) as SVG.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Continuation settings.
    #[command(flatten)]
    pub cont: ContinuationArgs,
}

/// The continuation settings of `sweep` and `sweep-param` (a study's `sweep` table
/// takes the same settings, with `_` for `-`).
#[derive(Debug, Clone, Default, clap::Args)]
#[command(next_help_heading = "Continuation")]
pub struct ContinuationArgs {
    /// Largest arc-length step, in scaled units (parameter range and linearised
    /// response both have length 1) [default: 0.1].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pub max_step: Option<f64>,
    /// Smallest step: a segment whose corrector fails at this step ends "stalled"
    /// [default: 1e-6].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pub min_step: Option<f64>,
    /// First step [default: 0.01, or within the given min/max steps].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pub initial_step: Option<f64>,
    /// Corrector (Newton) tolerance on the scaled step, max-norm [default: 1e-10].
    #[arg(long, value_name = "TOL", allow_negative_numbers = true)]
    pub tol: Option<f64>,
    /// Predictor direction [default: tangent].
    #[arg(long, value_enum, value_name = "KIND")]
    pub predictor: Option<Predictor>,
    /// When a branch counts as running away and its segment ends: `rel:F` (F times the
    /// largest Fourier coefficient of the linearised response), `abs:A` (any output's
    /// max_abs above A, model units; a plain number means this) or `none` [default: rel:1e3].
    #[arg(long, value_name = "BOUND", value_parser = parse_bound)]
    pub amplitude_bound: Option<AmplitudeBound>,
    /// Cap on accepted continuation steps [default: 20000].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub max_steps: Option<usize>,
    /// Skip Hill stability (faster): every point's `stable` is null (not checked) and
    /// jumps may land on unstable branches.
    #[arg(long)]
    pub no_stability: bool,
    /// Harmonic convergence: rerun with N, N+2, ... (up to 25, or N+4) until peaks and
    /// folds change by less than TOL relative [default TOL: 1e-3]; the summary and the
    /// JSON (`convergence`) report every level and the error estimate.
    #[arg(long, value_name = "TOL", num_args = 0..=1, require_equals = true)]
    pub converge: Option<Option<f64>>,
}

impl ContinuationArgs {
    /// The settings these flags give, for `harmonics` harmonics.
    pub fn settings(&self, harmonics: usize) -> SweepSettings {
        SweepSettings {
            harmonics,
            initial_step: self.initial_step,
            min_step: self.min_step,
            max_step: self.max_step,
            tol: self.tol,
            predictor: self.predictor,
            amplitude_bound: self.amplitude_bound,
            max_steps: self.max_steps,
            stability: self.no_stability.then_some(false),
            converge: self
                .converge
                .map(|t| t.unwrap_or(crate::continuation::ConvergenceOptions::default().tol)),
        }
    }
}

fn parse_bound(s: &str) -> Result<AmplitudeBound, InvalidBound> {
    s.parse()
}

const SWEEP_AFTER_HELP: &str = "\
Examples:
  ihbm sweep duffing --from 0.5 --to 3 --json d.json --plot d.svg
  ihbm sweep duffing --from 0.5 --to 3 --max-step 0.02 --amplitude-bound abs:5 --no-stability
  ihbm sweep quarter-car --from 1 --to 80 --converge=1e-4 --json -
  ihbm sweep quadratic --from 1.5 --to 2.6 --period 2 --harmonics 8 --plot p2.svg
  ihbm sweep duffing --from 0.2 --to 4 --set F=2 --set c=0.05 --break-symmetry --harmonics 6
  ihbm sweep quarter-car --from 1 --to 100 --plot q.svg --backbone

JSON: {model, harmonics, points, folds, jumps, segments, parameter, stats,
bifurcations, convergence (only with --converge), period (only with --period 2),
branch (\"symmetry-breaking\", only with --break-symmetry)}.
Frequencies in rad/s (with --period 2 still the forcing frequency).";

const FOLDS_AFTER_HELP: &str = "\
Examples:
  ihbm folds duffing --param F --from 0.01 --to 1 --omega-from 0.5 --omega-to 3 --plot f.svg
  ihbm folds quarter-car --param k3 --from 1e5 --to 1e7 --omega-from 5 --omega-to 100 --json -

JSON: {model, harmonics, parameter, curves: [{points: [{omega, value, outputs}], ended,
start}], cusps: [{omega, value, outputs, curve, located}], range, omega_range,
start_folds, stats}. A cusp's value is the least (or greatest) value of P at which a
slow sweep jumps. The CSV has one row per point: curve,omega,P,<out>_max_abs,...";

const BACKBONE_AFTER_HELP: &str = "\
Examples:
  ihbm backbone duffing --to 2 --set c=0 --harmonics 15 --plot b.svg
  ihbm backbone quarter-car --mode 2 --output y --to 0.05 --json -

JSON: {model, harmonics, mode, points: [{omega, damping, stable, xi, amplitude,
outputs: {X: {max_abs, mean, amp1}}}], output, to, linear: {omega, damping}, events:
[{kind: \"turn\" | \"internal-resonance\", omega, amplitude, ratio: \"k:1\" | null, mode,
after}], ended, stats}. A backbone is followed through its turns and internal resonances
(harmonic k of its frequency crossing another mode's linear frequency); events says
where they are. damping is the modal damping ratio D = xi / (2 omega) (0 for a conservative
model); stable is Hill's verdict where xi = 0 (a conservative model: stable only when
every exponent but the phase's zero one is on the imaginary axis) and null where xi != 0
(the point is not a motion of the model). The CSV has one row per point:
omega,damping,xi,amplitude,<out>_max_abs,<out>_mean,<out>_amp1,...";

const CYCLE_AFTER_HELP: &str = "\
Examples:
  ihbm cycle van-der-pol --omega 1 --harmonics 25 --json
  ihbm cycle van-der-pol --omega 1 --set mu=2 --harmonics 40

  ihbm cycle van-der-pol --omega 1 --param mu --from 1 --to -0.5 --json f.json --plot f.svg

JSON: {model, harmonics, converged, omega, period, stable, outputs: {X: {max_abs, mean,
amp1, cos, sin}}, mode}. The cycle is found by following the linearised mode nearest
the guess from the equilibrium until its artificial damping vanishes; stable leaves out
the zero exponent every autonomous cycle has (a shift in time).

With --param P --from V0 --to V1 the cycle at P = V0 is continued to V1: JSON {model,
harmonics, parameter, mode, points: [{value, omega, period, stable, outputs: {X:
{max_abs, mean, amp1}}}], hopf: {value, omega} or null, ended, range, stats}. ended is
\"reached end\", \"collapsed to the equilibrium\" (the cycle shrank
to nothing: the Hopf point is near), \"stalled: ...\" or \"stopped\"; hopf is where the
equilibrium's pair of eigenvalues of the cycle's mode crosses the imaginary axis in the
range covered. The CSV has one row per point: P,omega,period,stable,<out>_max_abs,...";

const SWEEP_PARAM_AFTER_HELP: &str = "\
Examples:
  ihbm sweep-param duffing --param F --from 0.01 --to 1 --omega 1.2 --csv f.csv
  ihbm sweep-param fractional-duffing --param p --from 0.1 --to 1.9 --omega 1 --plot p.svg

Output as for `sweep`; the curve's `parameter` names P. In the JSON every point and
fold keeps `omega` (the fixed Ω) and adds `param` (the value of P); so do jumps,
and segments add `from_param`/`to_param` (their `from_omega`/`to_omega` are the fixed
Ω). The CSV's first column is P.
A fractional order must stay inside [0, 2].";
