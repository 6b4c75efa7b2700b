//! Result types shared by the solvers and the report: points, curves, folds, jumps.
//!
//! Data flows one way: the corrector and continuation fill these, `report` and the
//! CLI turn them into JSON, CSV, SVG and Markdown.

use serde::Serialize;

/// Why a path could not go on: the reason of every `Stalled` end. It is defined in
/// [`crate::error`], whose `Error::Stall` holds one: `error` imports nothing from here.
pub use crate::error::{End, Stall};

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
    /// Root mean square over one period, the mean included.
    pub rms: f64,
    /// Least x(t) over one period.
    pub min: f64,
    /// Largest x(t) over one period.
    pub max: f64,
    /// Coefficients of cos(kΩt), k = 0..=N (`cos[0] = a0`).
    pub cos: Vec<f64>,
    /// Coefficients of sin(kΩt), k = 0..=N (`sin[0] = 0`).
    pub sin: Vec<f64>,
}

impl OutputSummary {
    /// Its statistics without the harmonics.
    pub fn stats(&self) -> PointOutput {
        PointOutput {
            max_abs: self.max_abs,
            mean: self.mean,
            amp1: self.amp1,
            rms: self.rms,
            min: self.min,
            max: self.max,
        }
    }
}

/// The rates of change of an output's statistics with one parameter, along the
/// solution (`d/dθ` of each [`PointOutput`] field); `None` where the derivative does
/// not exist (the amplitude or RMS of an output that is zero, a solution on a fold).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OutputRates {
    /// `d max_abs / dθ`, at the instant of the maximum (the envelope theorem).
    pub max_abs: Option<f64>,
    /// `d mean / dθ`.
    pub mean: Option<f64>,
    /// `d amp1 / dθ`.
    pub amp1: Option<f64>,
    /// `d rms / dθ`.
    pub rms: Option<f64>,
    /// `d min / dθ`, at the instant of the minimum.
    pub min: Option<f64>,
    /// `d max / dθ`, at the instant of the maximum.
    pub max: Option<f64>,
}

impl OutputRates {
    /// Rates that do not exist (a solution on a fold, where `dA/dθ` is unbounded).
    pub const NONE: OutputRates =
        OutputRates { max_abs: None, mean: None, amp1: None, rms: None, min: None, max: None };
}

/// The per-point summary of one output on a curve: statistics of its truncated
/// Fourier series over one period.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PointOutput {
    /// Largest |x(t)| over one period.
    pub max_abs: f64,
    /// Mean value (a0).
    pub mean: f64,
    /// First-harmonic amplitude.
    pub amp1: f64,
    /// Root mean square, the mean included: `sqrt(a0² + Σ (ak² + bk²) / 2)`.
    pub rms: f64,
    /// Least x(t).
    pub min: f64,
    /// Largest x(t).
    pub max: f64,
}

impl PointOutput {
    /// The statistics of the harmonic signal `mean + amplitude · cos Ωt`.
    ///
    /// ```
    /// use ihbm::results::PointOutput;
    /// let o = PointOutput::harmonic(1.0, 2.0);
    /// assert_eq!((o.max_abs, o.min, o.max, o.amp1), (3.0, -1.0, 3.0, 2.0));
    /// assert_eq!(o.rms, (1.0f64 + 2.0).sqrt()); // sqrt(1² + 2²/2)
    /// ```
    pub fn harmonic(mean: f64, amplitude: f64) -> Self {
        let a = amplitude.abs();
        PointOutput {
            max_abs: mean.abs() + a,
            mean,
            amp1: a,
            rms: (mean * mean + 0.5 * a * a).sqrt(),
            min: mean - a,
            max: mean + a,
        }
    }
}

/// What Hill's method says about a periodic solution.
///
/// `Stable` means that no growing mode was found: the fractional Hill method sees
/// exponentially growing perturbations, not algebraically decaying ones (book,
/// *Continuation, folds, jumps, stability*). Where no verdict exists the reason is kept.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stability {
    /// Every Floquet exponent has a real part below the tolerance.
    Stable,
    /// An exponent has a positive real part: a perturbation grows.
    Unstable,
    /// No verdict.
    Unknown(Unknown),
}

/// Why a point has no stability verdict.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unknown {
    /// Stability was not asked for (`SweepOptions::stability = None`, `--no-stability`).
    NotChecked,
    /// The solution itself did not converge, so there is nothing to analyse.
    NotConverged,
    /// The Hill analysis failed; its reason.
    Failed(String),
    /// A point of a damped nonlinear mode (artificial damping ξ ≠ 0): a periodic
    /// motion of the model with `-ξ M ẋ` added, not of the model itself, which has
    /// no periodic free motion to be stable or not (see `crate::backbone`).
    NotAMotion,
}

impl Stability {
    /// `Some(true)` for stable, `Some(false)` for unstable, `None` without a verdict
    /// (the JSON's `true`, `false`, `null`).
    pub fn verdict(&self) -> Option<bool> {
        match self {
            Stability::Stable => Some(true),
            Stability::Unstable => Some(false),
            Stability::Unknown(_) => None,
        }
    }

    /// Whether the verdict is "stable".
    pub fn is_stable(&self) -> bool {
        *self == Stability::Stable
    }

    /// Whether the verdict is "unstable" (unknown is neither).
    pub fn is_unstable(&self) -> bool {
        *self == Stability::Unstable
    }

    /// From a verdict: `true` stable, `false` unstable.
    pub fn from_verdict(stable: bool) -> Self {
        if stable {
            Stability::Stable
        } else {
            Stability::Unstable
        }
    }
}

impl std::fmt::Display for Stability {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stability::Stable => f.write_str("stable"),
            Stability::Unstable => f.write_str("unstable"),
            Stability::Unknown(Unknown::NotChecked) => f.write_str("not checked"),
            Stability::Unknown(Unknown::NotConverged) => f.write_str("unknown (not converged)"),
            Stability::Unknown(Unknown::Failed(why)) => write!(f, "unknown ({why})"),
            Stability::Unknown(Unknown::NotAMotion) => {
                f.write_str("unknown (ξ ≠ 0: not a motion of the model)")
            }
        }
    }
}

/// The continuation parameter of a curve.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Parameter {
    /// The forcing frequency Ω (a frequency sweep).
    Omega,
    /// The model parameter with this index and name, at a fixed Ω.
    Model {
        /// Index in [`Model::params_info`](crate::model::Model::params_info).
        index: usize,
        /// Its name.
        name: String,
    },
}

impl Parameter {
    /// `"omega"` or the parameter's name (the JSON's `parameter`, the CSV's first column).
    pub fn name(&self) -> &str {
        match self {
            Parameter::Omega => "omega",
            Parameter::Model { name, .. } => name,
        }
    }

    /// Whether this is a frequency sweep.
    pub fn is_omega(&self) -> bool {
        *self == Parameter::Omega
    }
}

impl std::fmt::Display for Parameter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One converged point of a traced curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvePoint {
    /// Forcing frequency Ω, rad/s.
    pub omega: f64,
    /// Value of the continuation parameter (equal to `omega` for a frequency sweep).
    pub param: f64,
    /// Fourier coefficients, layout `[a0, a1..aN, b1..bN]` per DOF.
    pub coeffs: Vec<f64>,
    /// Stability verdict (Hill's method), or why there is none.
    pub stability: Stability,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
    /// Index of the segment this point belongs to.
    pub segment: usize,
}

/// A fold (turning point) of a curve, located to 1e-8 relative in the parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Fold {
    /// Forcing frequency at the fold.
    pub omega: f64,
    /// Continuation parameter at the fold.
    pub param: f64,
    /// Fourier coefficients at the fold.
    pub coeffs: Vec<f64>,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
    /// The fold lies between `points[after]` and `points[after + 1]`.
    pub after: usize,
    /// Whether the location converged (the tangent's parameter component below
    /// 1e-13, or the bracket below 1e-14 of the step). `false` when the corrector
    /// failed on the way: the fold exists (the tangent turned between two converged
    /// points) but `omega` is only the last converged estimate inside that step, not
    /// located to 1e-8.
    pub located: bool,
}

/// A local maximum of one output's `max_abs` along a curve (a resonance peak),
/// located to 1e-8 relative in the continuation parameter: where the derivative of
/// `max_abs` along the curve changes sign from rising to falling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Peak {
    /// The output (index in [`Curve::output_names`]).
    pub output: usize,
    /// Forcing frequency there.
    pub omega: f64,
    /// Continuation parameter there (equal to `omega` for a frequency sweep).
    pub param: f64,
    /// The output's `max_abs` there.
    pub value: f64,
    /// It lies between `points[after]` and `points[after + 1]`.
    pub after: usize,
    /// Whether the location converged (`false`: the corrector failed on the way, and
    /// the place is the best estimate inside the step).
    pub located: bool,
}

/// Direction of a slow sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Increasing parameter (forward scan).
    Up,
    /// Decreasing parameter (reverse scan).
    Down,
}

/// Where a slow sweep in one direction would jump, and between which amplitudes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Jump {
    /// Sweep direction.
    pub direction: Direction,
    /// Value of the continuation parameter (Ω for frequency sweeps) at the jump.
    pub at: f64,
    /// The output the amplitudes refer to.
    pub output: String,
    /// `max_abs` before the jump.
    pub from: f64,
    /// `max_abs` after the jump.
    pub to: f64,
}

/// One piece of a traced curve and how it ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// Value of the continuation parameter where the segment starts.
    pub from: f64,
    /// Value where it ended.
    pub to: f64,
    /// Why it ended.
    pub ended: End,
}

/// Counters for a traced curve (snapshot-tested).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct CurveStats {
    /// Accepted continuation steps.
    pub steps: usize,
    /// Rejected (halved) steps.
    pub rejected_steps: usize,
    /// Corrector (Newton) iterations, all steps together: each one a Jacobian and an
    /// LU factorisation.
    pub corrector_iterations: usize,
    /// Chord updates between them (a residual solved with the LU at hand).
    pub chord_steps: usize,
    /// Folds found.
    pub folds: usize,
    /// Folds among them whose location did not converge ([`Fold::located`] `false`).
    pub folds_unlocated: usize,
    /// Points whose stability came from a full Hill analysis; the others were tracked
    /// from their neighbour (`stability::Hill::track`).
    pub stability_full: usize,
    /// Points where a fractional exponent did not refine to a root of its own (its
    /// frozen-order value is listed, `stability::Floquet::refined`
    /// `false`; the verdict then comes from counting the unstable roots of `det T`,
    /// `stability::Floquet::counted`), or whose analysis
    /// failed (reported unknown, with the reason). Book, *Continuation, folds, jumps, stability*, *Its limits*.
    pub stability_unrefined: usize,
}

/// A traced amplitude–frequency (or amplitude–parameter) curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// Model name.
    pub model: String,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The continuation parameter.
    pub parameter: Parameter,
    /// Output names, in model order (the order of every `outputs` vector).
    pub output_names: Vec<String>,
    /// Points in arc-length order.
    pub points: Vec<CurvePoint>,
    /// Whether stability was asked for. `false` when the sweep skipped it
    /// (`SweepOptions::stability = None`, `--no-stability`): every point's stability
    /// is then [`Unknown::NotChecked`].
    pub stability_checked: bool,
    /// Folds in arc-length order.
    pub folds: Vec<Fold>,
    /// Jumps of slow up and down sweeps.
    pub jumps: Vec<Jump>,
    /// The local maxima of every output's `max_abs` along the curve, in arc-length
    /// order.
    pub peaks: Vec<Peak>,
    /// The pieces of the curve.
    pub segments: Vec<Segment>,
    /// Solver counters.
    pub stats: CurveStats,
    /// Changes of stability that are not folds (period doubling, torus, branch point),
    /// in arc-length order. Folds are in [`Curve::folds`] only;
    /// [`Curve::all_bifurcations`] gives both in arc-length order.
    pub bifurcations: Vec<Bifurcation>,
    /// The harmonic-convergence study, when it was requested.
    pub convergence: Option<HarmonicConvergence>,
}

impl Curve {
    /// Add the points, segments and events of `other`, a curve of the same run (model,
    /// harmonics, parameter, outputs) traced separately — another branch — as further
    /// segments of this one: segment and point indices are shifted, counters added.
    pub fn append(&mut self, other: Curve) {
        let (points, segments) = (self.points.len(), self.segments.len());
        self.points.extend(other.points.into_iter().map(|mut p| {
            p.segment += segments;
            p
        }));
        self.segments.extend(other.segments);
        self.folds.extend(other.folds.into_iter().map(|mut f| {
            f.after += points;
            f
        }));
        self.bifurcations.extend(other.bifurcations.into_iter().map(|mut b| {
            b.after += points;
            b
        }));
        self.peaks.extend(other.peaks.into_iter().map(|mut p| {
            p.after += points;
            p
        }));
        self.jumps.extend(other.jumps);
        self.stability_checked &= other.stability_checked;
        let (s, o) = (&mut self.stats, other.stats);
        s.steps += o.steps;
        s.rejected_steps += o.rejected_steps;
        s.corrector_iterations += o.corrector_iterations;
        s.chord_steps += o.chord_steps;
        s.folds += o.folds;
        s.folds_unlocated += o.folds_unlocated;
        s.stability_full += o.stability_full;
        s.stability_unrefined += o.stability_unrefined;
    }

    /// Every bifurcation in arc-length order: the folds (as [`BifurcationKind::Fold`])
    /// and the changes of stability.
    pub fn all_bifurcations(&self) -> Vec<Bifurcation> {
        let mut all: Vec<Bifurcation> = self
            .folds
            .iter()
            .map(|f| Bifurcation {
                kind: BifurcationKind::Fold,
                omega: f.omega,
                param: f.param,
                after: f.after,
                outputs: f.outputs.clone(),
                located: f.located,
            })
            .chain(self.bifurcations.iter().cloned())
            .collect();
        // Stable: a fold before a stability change inside the same step.
        all.sort_by_key(|b| b.after);
        all
    }
}

/// What happens at a bifurcation point of a curve of periodic solutions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BifurcationKind {
    /// A turning point of the curve (Floquet multiplier +1, the curve folds back).
    Fold,
    /// A real exponent crosses zero without a fold (symmetry-breaking pitchfork or
    /// transcritical branch point).
    BranchPoint,
    /// A Floquet multiplier leaves the unit circle through -1 (a period-2 branch).
    PeriodDoubling,
    /// A complex pair of multipliers leaves the unit circle (Neimark–Sacker: a torus,
    /// quasi-periodic response).
    Torus,
    /// The verdict changes, and the unstable side's was counted
    /// (`stability::Floquet::counted`): no exponent shows the
    /// root that crossed, so which of the above it is is not known (nor is it located:
    /// [`Bifurcation::located`] is `false`).
    StabilityChange,
}

impl BifurcationKind {
    /// The kind in running text ("period doubling"), where [`Display`](std::fmt::Display)
    /// gives its one spelling as a key ("period-doubling", as the JSON writes it and
    /// the command line, study files and Python take it).
    pub fn noun(&self) -> &'static str {
        match self {
            BifurcationKind::Fold => "fold",
            BifurcationKind::BranchPoint => "branch point",
            BifurcationKind::PeriodDoubling => "period doubling",
            BifurcationKind::Torus => "torus",
            BifurcationKind::StabilityChange => "stability change",
        }
    }
}

impl std::fmt::Display for BifurcationKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BifurcationKind::Fold => "fold",
            BifurcationKind::BranchPoint => "branch-point",
            BifurcationKind::PeriodDoubling => "period-doubling",
            BifurcationKind::Torus => "torus",
            BifurcationKind::StabilityChange => "stability-change",
        })
    }
}

/// A bifurcation found on a traced curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bifurcation {
    /// What kind.
    pub kind: BifurcationKind,
    /// Forcing frequency there.
    pub omega: f64,
    /// Continuation parameter there (equal to `omega` for frequency sweeps).
    pub param: f64,
    /// It lies between `points[after]` and `points[after + 1]`.
    pub after: usize,
    /// Per output, in model output order.
    pub outputs: Vec<PointOutput>,
    /// Whether its location converged (a fold: see [`Fold::located`]; a stability
    /// change: the bracket on the largest real part below 1e-10 of the step). `false`:
    /// the corrector or the Hill analysis failed on the way, and the place is the last
    /// good estimate inside that step; or, for a stability change, the largest real
    /// part jumps there instead of crossing zero (it stays above 1 % of its values at
    /// the step's ends on both sides of a bracket of 1e-6 of the step, or above 30 %
    /// at 1e-3): the analyses on
    /// either side chose different sets of exponents, the place is the jump's, and
    /// the kind is the unstable side's crossing, not a bifurcation that was seen.
    pub located: bool,
}

/// One level of a harmonic-convergence study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HarmonicLevel {
    /// Number of harmonics N of this run.
    pub harmonics: usize,
    /// Peak `max_abs` over the curve, per output.
    pub peaks: Vec<f64>,
    /// Fold parameters (frequencies), in arc-length order.
    pub folds: Vec<f64>,
    /// Largest relative change of peaks and folds from the previous level
    /// (`inf` for the first level or when the number of folds changed).
    pub change: f64,
}

/// The result of rerunning a curve with N, N+2, ... harmonics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HarmonicConvergence {
    /// Every run, in order; the curve returned is the last one.
    pub levels: Vec<HarmonicLevel>,
    /// The tolerance on the relative change.
    pub tol: f64,
    /// Whether the last change is below the tolerance.
    pub converged: bool,
    /// The estimated relative error of the returned curve (the last change).
    pub estimate: f64,
}

/// The outcome of one `solve`: what the JSON of `ihbm solve` reports.
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
    /// Stability verdict (Hill's method), or why there is none.
    pub stability: Stability,
    /// Per output, in model output order.
    pub outputs: Vec<OutputSummary>,
    /// Why Newton could not start, when it could not (a Jacobian singular at the
    /// start: the record then holds the start, `x = 0`, and its residual).
    pub failure: Option<String>,
    /// Per parameter asked for (name), per output: the rates of change of the
    /// statistics ([`OutputRates`]); empty when none was asked for, every rate `None`
    /// when Newton did not converge.
    pub sensitivities: Vec<(String, Vec<OutputRates>)>,
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
    /// First-harmonic amplitude over the last 10 forcing periods.
    pub amp1: f64,
    /// Root mean square over the last 10 forcing periods, the mean included.
    pub rms: f64,
    /// Least x over the last 10 forcing periods.
    pub min: f64,
    /// Largest x over the last 10 forcing periods.
    pub max: f64,
    /// `|max_abs(last 10) - max_abs(10 before)| / max_abs(last 10)`: above
    /// [`SimOutput::STEADY_DRIFT`] the run had not settled and `max_abs` is no steady
    /// value.
    pub drift: f64,
}

impl SimOutput {
    /// The largest drift at which a run counts as steady.
    pub const STEADY_DRIFT: f64 = 1e-2;

    /// Whether the last two blocks of 10 periods agree (see [`SimOutput::drift`]).
    pub fn steady(&self) -> bool {
        self.drift <= Self::STEADY_DRIFT
    }
}

/// The outcome of one `simulate`: what the JSON of `ihbm simulate` reports.
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
    /// The slowest free mode's start-up transient left at the end of the run
    /// ([`StartUp`]).
    pub start_up: Option<StartUp>,
}

impl SimRecord {
    /// Why the statistics may still describe the start-up transient, if they may:
    /// an output that drifts is said by [`SimOutput::steady`]; this is the transient
    /// too slow to drift between the last windows.
    pub fn transient_warning(&self) -> Option<String> {
        let s = self.start_up.filter(|s| s.left > StartUp::NEGLIGIBLE)?;
        let run = self.periods as f64 * std::f64::consts::TAU / self.omega;
        let periods = s.settling_time() * self.omega / std::f64::consts::TAU;
        let more = if periods.is_finite() {
            format!("integrate at least {:.0} periods", periods.ceil())
        } else {
            "it is undamped and never decays".to_string()
        };
        Some(format!(
            "the start-up transient may dominate: the slowest free mode at rest (ω = {:.4} rad/s, \
             decay time {:.3e} s) keeps {:.1} % of its start-up amplitude after the {run:.3e} s \
             integrated ({more})",
            s.omega,
            s.decay_time,
            100.0 * s.left
        ))
    }
}

/// The free mode at rest whose start-up transient decays slowest (a run from rest
/// reports how much of it is left: `timedomain::start_up`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StartUp {
    /// Its linear natural frequency, rad/s.
    pub omega: f64,
    /// Its decay time `2/ξ`, s (infinite without damping).
    pub decay_time: f64,
    /// `e^{-t/decay_time}` at the end of the run: the fraction of its start-up
    /// amplitude still there (1 without damping).
    pub left: f64,
}

impl StartUp {
    /// More left than this and the statistics may describe the transient.
    pub const NEGLIGIBLE: f64 = 1e-3;

    /// The duration after which [`StartUp::NEGLIGIBLE`] is left (infinite without
    /// damping).
    pub fn settling_time(&self) -> f64 {
        self.decay_time * (1.0 / Self::NEGLIGIBLE).ln()
    }
}
