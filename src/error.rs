//! Errors a user can act on.

use thiserror::Error;

/// One Newton iteration, kept so that a failure can show how it went.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct IterationRecord {
    /// Iteration number, 0 for the initial guess.
    pub iteration: usize,
    /// Norm of the residual at the start of this iteration.
    pub residual_norm: f64,
    /// Norm of the Newton increment taken (0 before the first step).
    pub step_norm: f64,
    /// Damping factor applied to the increment (1 = full Newton step).
    pub damping: f64,
}

/// A number as messages show it: plain where that is short, in exponent form for the
/// very large and the very small (`1e300`, not three hundred digits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if v.is_finite() && v != 0.0 && (v.abs() >= 1e7 || v.abs() < 1e-4) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}

/// Everything that can go wrong in ihbm.
#[derive(Debug, Error)]
pub enum Error {
    /// A parameter name the model does not declare.
    #[error("unknown parameter '{name}' for model '{model}' (known: {known})")]
    UnknownParameter { name: String, model: String, known: String },
    /// An output name the model does not declare.
    #[error("unknown output '{name}' for model '{model}' (known: {known})")]
    UnknownOutput { name: String, model: String, known: String },
    /// A model's text (a model file) that the language refuses: every error, each as
    /// `origin:line:column: message`, one per line.
    #[error("{diagnostics}")]
    ModelText {
        /// Where the text came from (a file name).
        origin: String,
        /// The located messages.
        diagnostics: String,
    },
    /// A model name that is not registered.
    #[error("unknown model '{name}' (known: {known})")]
    UnknownModel { name: String, known: String },
    /// A problem too large for the machine: what it would need, and the largest
    /// harmonic count that fits.
    #[error("N = {harmonics} harmonics with {dofs} DOF(s) needs about {needed} for the dense {what} (limit {limit}); the largest N that fits is {largest}")]
    TooLarge {
        /// The harmonic count asked for.
        harmonics: usize,
        /// DOFs of the model.
        dofs: usize,
        /// Which part (for example "harmonic-balance Jacobians").
        what: String,
        /// The estimated memory, readable (`"1.3 TB"`).
        needed: String,
        /// The limit, readable.
        limit: String,
        /// The largest N within the limit.
        largest: usize,
    },
    /// A value outside what the method accepts.
    #[error("invalid {what}: {value} (expected {expected})")]
    InvalidValue { what: String, value: String, expected: String },
    /// Two-parameter continuation found no fold to start from at either end of the
    /// parameter range.
    #[error("no {what} for Ω in [{omega_from}, {omega_to}] at {parameter} = {from} or at {parameter} = {to}: nothing to continue (widen the frequency or the parameter range)")]
    NoFolds {
        /// What was looked for, in words ([`BifurcationKind::noun`](crate::results::BifurcationKind::noun)).
        what: String,
        /// The parameter's name.
        parameter: String,
        /// The ends of its range.
        from: f64,
        /// See `from`.
        to: f64,
        /// The frequency range swept at both ends.
        omega_from: f64,
        /// See `omega_from`.
        omega_to: f64,
    },
    /// A period-2 sweep found no period-doubling point of the period-1 curve to switch at.
    #[error("no period doubling on the period-1 curve for Ω in [{from}, {to}]: no period-2 branch to switch onto (widen the range, or raise the forcing)")]
    NoPeriodDoubling {
        /// The frequency range swept.
        from: f64,
        /// See `from`.
        to: f64,
    },
    /// A symmetry-breaking sweep found no branch point on the curve to switch at.
    #[error("no branch point on the curve for Ω in [{from}, {to}]: no symmetry-breaking branch to switch onto")]
    NoBranchPoint {
        /// The frequency range swept.
        from: f64,
        /// See `from`.
        to: f64,
    },
    /// A symmetry-breaking sweep's branch point lies on a solution whose even
    /// harmonics are not negligible: the symmetry is already broken there.
    #[error("the branch point at Ω = {omega} is not on a symmetric solution (its even harmonics are {ratio:.1e} of the odd ones): nothing to break")]
    NotSymmetric {
        /// Ω of the branch point, rad/s.
        omega: f64,
        /// The largest even-harmonic coefficient over the largest odd one.
        ratio: f64,
    },
    /// Branch switching (at a period doubling or a symmetry-breaking branch point)
    /// found no direction to leave the solution along.
    #[error("{failure} at the branch at ω = {omega}")]
    NoCriticalDirection {
        /// The frequency of the balance there, rad/s (`Ω/2` at a period doubling,
        /// whose balance is in the harmonics of `Ω/2`; Ω at a branch point).
        omega: f64,
        /// Why.
        failure: DirectionFailure,
    },
    /// A coefficient of the model (a function of parameters and Ω) is NaN or infinite
    /// where the model is evaluated: a square root of a negative number, a logarithm
    /// of a non-positive one, a division by zero.
    #[error(fmt = coefficient)]
    NonFiniteCoefficient {
        /// The model's name.
        model: String,
        /// The coefficient's source text.
        term: String,
        /// Its value (NaN or ±inf).
        value: f64,
        /// The frequency where it was evaluated (rad/s).
        omega: f64,
        /// The parameters it reads, `name = value, ...` ("none" if it reads none).
        params: String,
    },
    /// Newton did not converge; the last iterate is kept.
    #[error("Newton did not converge at omega = {} after {iterations} iterations (residual norm {residual_norm:.3e}); last iterate kept", Num(*.omega))]
    NotConverged {
        omega: f64,
        iterations: usize,
        residual_norm: f64,
        /// The last iterate (Fourier coefficients).
        last: Vec<f64>,
        history: Vec<IterationRecord>,
    },
    /// The Jacobian could not be factorised.
    #[error("singular Jacobian at omega = {}: {detail}", Num(*.omega))]
    SingularJacobian { omega: f64, detail: String },
    /// A time integration blew up.
    #[error("time integration diverged at t = {time} s: {detail}")]
    Diverged { time: f64, detail: String },
    /// Reading or writing a file.
    #[error("{path}: {source}")]
    Io { path: String, source: std::io::Error },
    /// A study file that does not parse.
    #[error("{0}")]
    Study(String),
    /// Hill's method found no exponents at a point (the point's stability is then
    /// `Unknown` with this as its reason).
    #[error(fmt = hill)]
    Hill { omega: f64, failure: HillFailure },
    /// The linearisation of a model at rest gave no natural frequencies or mode
    /// shapes (for a backbone's or a limit cycle's start).
    #[error(transparent)]
    Linearisation(#[from] LinearisationFailure),

    /// A model's structure claim ([`crate::model::Model::affine_signals`],
    /// `explicit_omega`, `signal_reads`) contradicted at a test state: trusted, it
    /// would give wrong Jacobians.
    #[error("model '{model}': {claim} is wrong: {detail}")]
    WrongClaim { model: String, claim: Claim, detail: String },
    /// A model declares a signal (a combination of DOFs its residual reads) with a DOF
    /// index the model does not have.
    #[error("model '{model}' declares a signal on a DOF index outside 0..{dofs}")]
    SignalOutsideDofs {
        /// The model's name.
        model: String,
        /// Its number of DOFs (valid indices are `0..dofs`).
        dofs: usize,
    },

    /// A path that could not start where that fails the whole computation (a
    /// backbone that did not leave its linear mode, a limit cycle that did not
    /// converge at the start of a family): the reason, as a path's end would give it.
    #[error(transparent)]
    Stall(#[from] Stall),

    /// A figure asked of something empty: a backbone without points, a family
    /// without limit cycles, a fold analysis without curves, a trend without points.
    #[error("no {what} to draw")]
    NothingToDraw {
        /// What was empty.
        what: Drawable,
    },
    /// The plotting library failed while drawing a figure.
    #[error("drawing a figure failed: {reason}")]
    Plot {
        /// Its report (the `Debug` text of its error).
        reason: String,
    },
    /// A curve's polylines found no placeholder to replace in the SVG the plotting
    /// library wrote (the placeholder text was dropped or rewritten).
    #[error("drawing a figure failed: curve slot {slot} lost")]
    CurveSlotLost {
        /// The slot's index, in the order the curves were reserved.
        slot: usize,
    },
    /// A time integration with memory (a fractional derivative) took more steps than
    /// its history of past values was made for.
    #[error(
        "history buffer full ({capacity} values): more steps than the integrator was set up for"
    )]
    HistoryFull {
        /// The number of values the history holds.
        capacity: usize,
    },
    /// The FFT of the fast history sum failed.
    #[error("fast history FFT: {reason}")]
    HistoryFft {
        /// The FFT library's report.
        reason: String,
    },
    /// The backbone traced to find a limit cycle (where the mode's artificial damping
    /// is zero) ended without reaching one.
    #[error("no limit cycle near ω = {omega} rad/s (mode {mode}): {ended}")]
    NoLimitCycle {
        /// The frequency guess, rad/s.
        omega: f64,
        /// The mode whose linear frequency is nearest the guess (1-based).
        mode: usize,
        /// How the backbone ended.
        ended: End,
    },
    /// The limit cycle found is no larger than ten times the amplitude its backbone
    /// started at: the mode is at its Hopf point, where the cycle shrinks to the
    /// equilibrium.
    #[error("the cycle near ω = {omega:.6} rad/s collapses to the equilibrium (max |x| = {amplitude:.3e}): the mode is at its Hopf point")]
    CycleCollapses {
        /// The cycle's frequency, rad/s.
        omega: f64,
        /// The `max |x|` of its first output (0 for a model without outputs).
        amplitude: f64,
    },
    /// A family of limit cycles found no cycle to start from at the first value of
    /// its parameter.
    #[error(fmt = no_cycle_to_continue)]
    NoCycleToContinue {
        /// The parameter's name.
        parameter: String,
        /// Its first value.
        value: f64,
        /// Why no cycle was found there (none when the cycle found had no point to start
        /// from).
        cause: Option<Box<Error>>,
    },
}

/// Shorthand for results in this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Why Hill's method gave no exponents.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum HillFailure {
    /// The eigendecomposition of the companion matrix did not converge (faer's
    /// report).
    #[error("the eigenvalues of the companion matrix failed to converge ({0})")]
    Eigensolve(String),
    /// The generalised eigenproblem (a singular leading coefficient) failed.
    #[error("the generalized eigenvalues failed to converge ({0})")]
    GeneralizedEigensolve(String),
    /// The workspace was made for another model size than the balance it was given.
    #[error("workspace for {samples} samples and {unknowns} unknowns used with a balance of {got_samples} and {got_unknowns}")]
    Workspace { samples: usize, unknowns: usize, got_samples: usize, got_unknowns: usize },
    /// Counting the roots of `det T` (the verdict where a fractional exponent did not
    /// refine, the search for a real root a fold left, `Hill::unstable_roots`) failed.
    #[error("counting the roots of det T failed: {0}")]
    RootCount(String),
}

/// What a figure had nothing of ([`Error::NothingToDraw`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drawable {
    /// The points of a backbone.
    BackbonePoints,
    /// The limit cycles of a family.
    LimitCycles,
    /// The curves of a fold analysis.
    FoldCurves,
    /// The points of a trend (a quantity against a varied value).
    Points,
}

impl std::fmt::Display for Drawable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Drawable::BackbonePoints => "backbone points",
            Drawable::LimitCycles => "limit cycles",
            Drawable::FoldCurves => "fold curves",
            Drawable::Points => "points",
        })
    }
}

/// Why branch switching found no direction ([`Error::NoCriticalDirection`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DirectionFailure {
    /// The Jacobian at the branch is not finite (the pivot ratio of its factorisation
    /// is NaN).
    NonFiniteJacobian,
    /// Inverse iteration lost the direction: its vector became zero or not finite.
    Vanished,
}

impl std::fmt::Display for DirectionFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            DirectionFailure::NonFiniteJacobian => "non-finite Jacobian",
            DirectionFailure::Vanished => "no critical direction",
        })
    }
}

/// Why the linearisation at rest gave no modes ([`Error::Linearisation`]).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum LinearisationFailure {
    /// The generalised eigenproblem `K φ = μ M φ` did not converge (faer's report,
    /// its `Debug` text).
    #[error("the linearised model's eigenvalues failed: {0}")]
    Eigensolve(String),
    /// `K − μ M` at a mode's eigenvalue is not finite (the pivot ratio of its
    /// factorisation is NaN).
    #[error("non-finite linearised model")]
    NonFinite,
    /// Inverse iteration for a mode shape lost its vector (zero or not finite).
    #[error("no mode shape: the linearised model is degenerate")]
    Degenerate,
}

/// A model's structure claim ([`Error::WrongClaim`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Claim {
    /// [`crate::model::Model::affine_signals`]
    AffineSignals,
    /// [`crate::model::Model::explicit_omega`]
    ExplicitOmega,
    /// [`crate::model::Model::signal_reads`]
    SignalReads,
}

impl std::fmt::Display for Claim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Claim::AffineSignals => "affine_signals()",
            Claim::ExplicitOmega => "explicit_omega()",
            Claim::SignalReads => "signal_reads()",
        })
    }
}

/// The text of [`Error::NonFiniteCoefficient`] and [`Stall::Coefficient`].
fn coefficient(
    model: &str,
    term: &str,
    value: &f64,
    omega: &f64,
    params: &str,
    f: &mut std::fmt::Formatter<'_>,
) -> std::fmt::Result {
    write!(
        f,
        "model '{model}': the coefficient `{term}` is {value} at Ω = {} rad/s ({params}); a \
         coefficient must be finite wherever the model is evaluated: choose a frequency range \
         and parameter values where it is defined",
        Num(*omega)
    )
}

/// The text of [`Error::NoCycleToContinue`]: the cause after a colon, when there is one.
fn no_cycle_to_continue(
    parameter: &str,
    value: &f64,
    cause: &Option<Box<Error>>,
    f: &mut std::fmt::Formatter<'_>,
) -> std::fmt::Result {
    write!(f, "no limit cycle to continue at {parameter} = {value}")?;
    match cause {
        Some(e) => write!(f, ": {e}"),
        None => Ok(()),
    }
}

/// The text of [`Error::Hill`] and [`Stall::Hill`].
fn hill(omega: &f64, failure: &HillFailure, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
    write!(f, "Hill's method at Ω = {}: {failure}", Num(*omega))
}

/// Why a traced path could not go on, or could not start: a segment of a curve
/// ([`End::Stalled`](crate::results::End::Stalled)), a fold curve, a
/// backbone, a family of limit cycles. Each reason keeps what was known where it
/// happened, numbers as numbers; its text is what the reports show after `stalled: `.
///
/// The corrector's own failures come first; then a point where the model is not
/// evaluated (outside the range traced, a coefficient that is not finite); then the
/// ends of a path that are not a corrector's failure; last, what was being done when
/// another reason stopped it (`cause`, shown after a colon).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Stall {
    /// Newton's updates stopped shrinking: from the third iteration on, one more than
    /// half the one before, not the quadratic convergence a correct Jacobian gives
    /// near a solution (more iterations would not help).
    #[error("Newton not contracting at Ω = {omega:.6} (step {step:.2e} after {previous:.2e})")]
    NotContracting {
        /// Ω at the last iterate, rad/s.
        omega: f64,
        /// The max-norm of the last update (scaled unknowns).
        step: f64,
        /// The max-norm of the update before it.
        previous: f64,
    },
    /// Newton used its whole budget of iterations.
    #[error("no convergence in {iterations} iterations at Ω = {omega:.6}")]
    NoConvergence {
        /// The budget.
        iterations: usize,
        /// Ω at the last iterate, rad/s.
        omega: f64,
    },
    /// A matrix the corrector factors is singular (or its factorisation not finite).
    #[error(fmt = singular)]
    Singular {
        /// Which.
        matrix: Matrix,
        /// Ω where it was assembled, rad/s.
        omega: f64,
    },
    /// A value the corrector computed is NaN or infinite.
    #[error(fmt = non_finite)]
    NonFinite {
        /// Which.
        quantity: Quantity,
        /// Ω where (or near where, for an update) it was computed, rad/s.
        omega: f64,
    },
    /// The test matrix of a fold (or period-doubling) curve's start gave no null
    /// vector to border it with.
    #[error("no null vector at the start at Ω = {omega:.6}")]
    NoNullVector {
        /// Ω of the start, rad/s.
        omega: f64,
    },
    /// Hill's operator `T(iω)` at a torus curve's start gave no null vector to border
    /// it with.
    #[error("no null vector of T(iω) at Ω = {omega:.6}")]
    NoHillNullVector {
        /// Ω of the start, rad/s.
        omega: f64,
    },

    /// An iterate left the range of the continuation parameter (the model is never
    /// evaluated outside it).
    #[error("an iterate left the range [{lo}, {hi}] (at {at:.6e})")]
    LeftRange {
        /// The range's lower end.
        lo: f64,
        /// Its upper end.
        hi: f64,
        /// The iterate's value of the parameter.
        at: f64,
    },
    /// An iterate of a fold curve left its frequency range.
    #[error("an iterate left the frequency range (Ω = {omega:.6e})")]
    LeftFrequencyRange {
        /// The iterate's Ω, rad/s.
        omega: f64,
    },
    /// An iterate of a fold curve left the range of its parameter.
    #[error("an iterate left the parameter range (at {at:.6e})")]
    LeftParameterRange {
        /// The iterate's value of the parameter.
        at: f64,
    },
    /// An iterate of a nonlinear mode or limit cycle has a frequency or a modal
    /// amplitude that is not positive and finite.
    #[error("the iterate left the physical range (ω = {omega:e}, q = {amplitude:e})")]
    LeftPhysicalRange {
        /// Its frequency ω, rad/s.
        omega: f64,
        /// Its modal amplitude q.
        amplitude: f64,
    },
    /// The parameter of a family of limit cycles became NaN or infinite.
    #[error("the parameter left the finite range ({value:e})")]
    ParameterNotFinite {
        /// Its value.
        value: f64,
    },
    /// A torus curve's torus frequency left `(0, Ω/2)`.
    #[error("the torus frequency left (0, Ω/2) (ω = {torus:.6e} at Ω = {omega:.6})")]
    LeftTorusRange {
        /// The torus frequency ω, rad/s.
        torus: f64,
        /// The forcing frequency Ω, rad/s.
        omega: f64,
    },
    /// A coefficient of the model is not finite at an iterate
    /// ([`Error::NonFiniteCoefficient`], which names the same).
    #[error(fmt = coefficient)]
    Coefficient {
        /// The model's name.
        model: String,
        /// The coefficient's source text.
        term: String,
        /// Its value (NaN or ±inf).
        value: f64,
        /// The frequency where it was evaluated (rad/s).
        omega: f64,
        /// The parameters it reads, `name = value, ...` ("none" if it reads none).
        params: String,
    },
    /// Hill's method failed where a torus curve needs it ([`Error::Hill`]).
    #[error(fmt = hill)]
    Hill {
        /// Ω, rad/s.
        omega: f64,
        /// Why.
        failure: HillFailure,
    },
    /// Another error met on the way (a model's own check of its coefficients), as
    /// its message.
    #[error("{0}")]
    Other(String),

    /// The cap on accepted steps was reached.
    #[error("step limit {steps} reached")]
    StepLimit {
        /// The cap.
        steps: usize,
    },
    /// A limit cycle's backbone never reached zero artificial damping: the mode has
    /// no limit cycle (up to the amplitude, or within the step limit).
    #[error(fmt = damping_kept_sign)]
    DampingKeptSign {
        /// The artificial damping ξ at the last point.
        xi: f64,
        /// The output continued.
        output: String,
        /// Its `max |x|` there.
        amplitude: f64,
        /// The step limit, when that is what ended it.
        steps: Option<usize>,
    },
    /// At a located torus point no pair of Floquet exponents lies away from 0 and
    /// ±Ω/2: no torus frequency to start its curve with.
    #[error("no complex pair of exponents at the torus point Ω = {omega:.6}")]
    NoComplexPair {
        /// Ω of the torus point, rad/s.
        omega: f64,
    },

    /// No solution at the first value of a segment.
    #[error("no solution at the start {}: {cause}", Num(*.at))]
    NoStart {
        /// The value of the continuation parameter.
        at: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// No point of a switched branch beside the solution it leaves.
    #[error("no branch found at Ω = {omega}: {cause}")]
    NoBranch {
        /// Ω of the branch point, rad/s.
        omega: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// The fold (or other bifurcation) a curve starts from did not converge on the
    /// extended system.
    #[error("the start fold at Ω = {omega:.6} did not converge: {cause}")]
    FoldStart {
        /// Ω of the fold, rad/s.
        omega: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// A backbone did not start at its linear mode.
    #[error(
        "the backbone of mode {mode} did not start at the linear mode (ω = {omega:.6} rad/s): {cause}"
    )]
    ModeStart {
        /// The mode (1-based).
        mode: usize,
        /// Its linear natural frequency, rad/s.
        omega: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// A family's first limit cycle did not converge at the first parameter value.
    #[error("the limit cycle at {parameter} = {value} did not converge: {cause}")]
    CycleStart {
        /// The parameter's name.
        parameter: String,
        /// Its first value.
        value: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// The Floquet exponents at a torus point, for its torus frequency, failed.
    #[error("no Floquet exponents at the torus point: {cause}")]
    TorusExponents {
        /// Why.
        cause: Box<Stall>,
    },
    /// Hill's operator of a torus curve could not be prepared.
    #[error("Hill's operator at Ω = {omega:.6}: {cause}")]
    HillOperator {
        /// Ω, rad/s.
        omega: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// The step that left the range did not land on its end.
    #[error("could not land on the range end: {cause}")]
    LandRangeEnd {
        /// Why.
        cause: Box<Stall>,
    },
    /// A backbone did not land on the amplitude asked for.
    #[error("could not land on max |x| = {amplitude}: {cause}")]
    LandAmplitude {
        /// The amplitude (`max |x|` of the output continued).
        amplitude: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// A family of limit cycles did not land on the end of its parameter range.
    #[error("could not land on {parameter} = {value}: {cause}")]
    LandParameter {
        /// The parameter's name.
        parameter: String,
        /// The end of the range.
        value: f64,
        /// Why.
        cause: Box<Stall>,
    },
    /// A limit cycle's backbone crossed zero artificial damping, but the crossing was
    /// not located.
    #[error("could not locate ξ = 0: {cause}")]
    LocateZeroDamping {
        /// Why.
        cause: Box<Stall>,
    },
}

/// Why a path ended: a segment of a sweep, a fold (period-doubling, torus) curve, a
/// backbone, a family of limit cycles. One enum for every path; each variant says
/// which paths end that way. Its text is the JSON's `ended`.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    /// The continuation parameter reached the end of the requested range (every path
    /// but a backbone).
    ReachedEnd,
    /// The continued output reached the requested amplitude (a backbone; its last
    /// point is there).
    ReachedAmplitude,
    /// The response exceeded the amplitude bound (a sweep's branch climbing an
    /// undamped asymptote, a fold climbing towards a runaway branch).
    AmplitudeBound,
    /// Ω reached the end of the frequency range (a fold curve).
    LeftOmegaRange,
    /// The curve came back to its first point (an isola of folds).
    Closed,
    /// A torus curve's torus frequency reached 0 or Ω/2 (a strong resonance: the
    /// curve meets a fold or a period-doubling curve there).
    StrongResonance,
    /// The cycle shrank to the equilibrium (a family of limit cycles, at its Hopf
    /// point; the last point is the smallest traced).
    Collapsed,
    /// A branch started by switching came back to the solutions it left (a
    /// period-2 branch rejoining the period-1 curve at another period doubling).
    Rejoined,
    /// The corrector failed even at the minimum step, the step limit, or another
    /// failure; the reason.
    Stalled(Stall),
    /// An observer stopped the run (what was traced is kept).
    Stopped,
}

impl std::fmt::Display for End {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            End::ReachedEnd => write!(f, "reached end"),
            End::ReachedAmplitude => write!(f, "reached the amplitude"),
            End::AmplitudeBound => write!(f, "amplitude bound"),
            End::LeftOmegaRange => write!(f, "left the frequency range"),
            End::Closed => write!(f, "closed"),
            End::StrongResonance => write!(f, "strong resonance"),
            End::Collapsed => write!(f, "collapsed to the equilibrium"),
            End::Rejoined => write!(f, "rejoined the curve it branched from"),
            End::Stalled(why) => write!(f, "stalled: {why}"),
            End::Stopped => write!(f, "stopped"),
        }
    }
}

impl From<Error> for Stall {
    /// The reason in an error met while tracing: a coefficient the model refuses and
    /// Hill's method keep their kind, anything else its message.
    fn from(e: Error) -> Stall {
        match e {
            Error::Stall(s) => s,
            Error::NonFiniteCoefficient { model, term, value, omega, params } => {
                Stall::Coefficient { model, term, value, omega, params }
            }
            Error::Hill { omega, failure } => Stall::Hill { omega, failure },
            e => Stall::Other(e.to_string()),
        }
    }
}

/// A matrix the corrector factors ([`Stall::Singular`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Matrix {
    /// The bordered Jacobian of a one-parameter continuation.
    Bordered,
    /// The Newton matrix of an extended system (a backbone, a family of limit cycles,
    /// a fold curve).
    Extended,
    /// The bordered test function of a fold or period-doubling curve.
    TestFunction,
    /// The bordered complex test function of a torus curve.
    TorusTestFunction,
    /// Hill's operator `T(iω)` at a torus curve's start (exactly singular: a nearly
    /// singular one is expected there).
    HillOperator,
}

fn singular(matrix: &Matrix, omega: &f64, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
    let omega = *omega;
    match matrix {
        Matrix::Bordered => write!(f, "singular bordered Jacobian at Ω = {}", Num(omega)),
        Matrix::Extended => write!(f, "singular extended Jacobian at Ω = {omega:.6}"),
        Matrix::TestFunction => write!(f, "singular bordered test function at Ω = {omega:.6}"),
        Matrix::TorusTestFunction => {
            write!(f, "singular bordered torus test function at Ω = {omega:.6}")
        }
        Matrix::HillOperator => write!(f, "Hill's operator is exactly singular at Ω = {omega:.6}"),
    }
}

/// A value the corrector computes ([`Stall::NonFinite`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// The residual.
    Residual,
    /// A Newton update.
    NewtonStep,
    /// A chord update (the residual solved with the LU of an earlier Newton step).
    ChordStep,
    /// The complex test function of a torus curve.
    TorusTestFunction,
    /// The test matrix at a fold (or period-doubling) curve's start (its
    /// factorisation).
    StartJacobian,
}

fn non_finite(
    quantity: &Quantity,
    omega: &f64,
    f: &mut std::fmt::Formatter<'_>,
) -> std::fmt::Result {
    // An update moves the iterate: it is near Ω, not at it.
    let (what, at) = match quantity {
        Quantity::Residual => ("residual", "at"),
        Quantity::NewtonStep => ("Newton step", "near"),
        Quantity::ChordStep => ("chord step", "near"),
        Quantity::TorusTestFunction => ("torus test function", "at"),
        Quantity::StartJacobian => ("Jacobian at the start", "at"),
    };
    write!(f, "non-finite {what} {at} Ω = {omega:.6}")
}

fn damping_kept_sign(
    xi: &f64,
    output: &str,
    amplitude: &f64,
    steps: &Option<usize>,
    f: &mut std::fmt::Formatter<'_>,
) -> std::fmt::Result {
    write!(f, "the artificial damping kept its sign (ξ = {xi:.6e}) up to max |{output}| = {amplitude:.3e}")?;
    if let Some(n) = steps {
        write!(f, " ({n} steps)")?;
    }
    f.write_str(": no limit cycle of this mode")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every reason reads as the sentence the solvers wrote before it had a type (each
    /// expected text is built by the `format!` that built it then), so reports,
    /// summaries and JSON show the same words.
    #[test]
    fn a_stall_reads_as_the_sentence_it_replaced() {
        let (w, lo, hi, at) = (1.2345678, 0.5, 2.5, 2.7654321);
        let inner = || Box::new(Stall::NoConvergence { iterations: 30, omega: w });
        let why = format!("no convergence in {} iterations at Ω = {w:.6}", 30);
        let hill = HillFailure::RootCount("no contour".into());
        let cases: Vec<(Stall, String)> = vec![
            (
                Stall::NotContracting { omega: w, step: 3e-3, previous: 4e-3 },
                format!("Newton not contracting at Ω = {w:.6} (step {:.2e} after {:.2e})", 3e-3, 4e-3),
            ),
            (*inner(), why.clone()),
            (
                Stall::Singular { matrix: Matrix::Bordered, omega: w },
                format!("singular bordered Jacobian at Ω = {}", Num(w)),
            ),
            (
                Stall::Singular { matrix: Matrix::Bordered, omega: 1e-9 },
                "singular bordered Jacobian at Ω = 1e-9".to_string(),
            ),
            (
                Stall::Singular { matrix: Matrix::Extended, omega: w },
                format!("singular extended Jacobian at Ω = {w:.6}"),
            ),
            (
                Stall::Singular { matrix: Matrix::TestFunction, omega: w },
                format!("singular bordered test function at Ω = {w:.6}"),
            ),
            (
                Stall::Singular { matrix: Matrix::TorusTestFunction, omega: w },
                format!("singular bordered torus test function at Ω = {w:.6}"),
            ),
            (
                Stall::Singular { matrix: Matrix::HillOperator, omega: w },
                format!("Hill's operator is exactly singular at Ω = {w:.6}"),
            ),
            (
                Stall::NonFinite { quantity: Quantity::Residual, omega: w },
                format!("non-finite residual at Ω = {w:.6}"),
            ),
            (
                Stall::NonFinite { quantity: Quantity::NewtonStep, omega: w },
                format!("non-finite {} near Ω = {w:.6}", "Newton step"),
            ),
            (
                Stall::NonFinite { quantity: Quantity::ChordStep, omega: w },
                format!("non-finite {} near Ω = {w:.6}", "chord step"),
            ),
            (
                Stall::NonFinite { quantity: Quantity::TorusTestFunction, omega: w },
                format!("non-finite torus test function at Ω = {w:.6}"),
            ),
            (
                Stall::NonFinite { quantity: Quantity::StartJacobian, omega: w },
                format!("non-finite Jacobian at the start at Ω = {w:.6}"),
            ),
            (Stall::NoNullVector { omega: w }, format!("no null vector at the start at Ω = {w:.6}")),
            (Stall::NoHillNullVector { omega: w }, format!("no null vector of T(iω) at Ω = {w:.6}")),
            (
                Stall::LeftRange { lo, hi, at },
                format!("an iterate left the range [{lo}, {hi}] (at {at:.6e})"),
            ),
            (
                Stall::LeftFrequencyRange { omega: w },
                format!("an iterate left the frequency range (Ω = {w:.6e})"),
            ),
            (
                Stall::LeftParameterRange { at },
                format!("an iterate left the parameter range (at {at:.6e})"),
            ),
            (
                Stall::LeftPhysicalRange { omega: -w, amplitude: f64::INFINITY },
                format!("the iterate left the physical range (ω = {:e}, q = {:e})", -w, f64::INFINITY),
            ),
            (
                Stall::ParameterNotFinite { value: f64::NAN },
                format!("the parameter left the finite range ({:e})", f64::NAN),
            ),
            (
                Stall::LeftTorusRange { torus: at, omega: w },
                format!("the torus frequency left (0, Ω/2) (ω = {at:.6e} at Ω = {w:.6})"),
            ),
            (
                Stall::Coefficient {
                    model: "gap".into(),
                    term: "sqrt(F - 0.1)".into(),
                    value: f64::NAN,
                    omega: w,
                    params: "F = 0.05".into(),
                },
                Error::NonFiniteCoefficient {
                    model: "gap".into(),
                    term: "sqrt(F - 0.1)".into(),
                    value: f64::NAN,
                    omega: w,
                    params: "F = 0.05".into(),
                }
                .to_string(),
            ),
            (
                Stall::Hill { omega: w, failure: hill.clone() },
                Error::Hill { omega: w, failure: hill.clone() }.to_string(),
            ),
            (Stall::StepLimit { steps: 20000 }, format!("step limit {} reached", 20000)),
            (
                Stall::DampingKeptSign {
                    xi: 0.25,
                    output: "x".into(),
                    amplitude: 3.5,
                    steps: Some(400),
                },
                format!(
                    "the artificial damping kept its sign (ξ = {:.6e}) up to max |{}| = {:.3e} ({} steps): no limit cycle of this mode",
                    0.25, "x", 3.5, 400
                ),
            ),
            (
                Stall::DampingKeptSign { xi: 0.25, output: "x".into(), amplitude: 3.5, steps: None },
                format!(
                    "the artificial damping kept its sign (ξ = {:.6e}) up to max |{}| = {:.3e}: no limit cycle of this mode",
                    0.25, "x", 3.5
                ),
            ),
            (
                Stall::NoComplexPair { omega: w },
                format!("no complex pair of exponents at the torus point Ω = {w:.6}"),
            ),
            (
                Stall::NoStart { at, cause: inner() },
                format!("no solution at the start {}: {why}", Num(at)),
            ),
            (
                Stall::NoBranch { omega: w, cause: inner() },
                format!("no branch found at Ω = {}: {why}", w),
            ),
            (
                Stall::FoldStart { omega: w, cause: inner() },
                format!("the start fold at Ω = {w:.6} did not converge: {why}"),
            ),
            (
                Stall::ModeStart { mode: 2, omega: w, cause: inner() },
                format!(
                    "the backbone of mode {} did not start at the linear mode (ω = {:.6} rad/s): {why}",
                    2, w
                ),
            ),
            (
                Stall::CycleStart { parameter: "mu".into(), value: lo, cause: inner() },
                format!("the limit cycle at {} = {lo} did not converge: {why}", "mu"),
            ),
            (
                Stall::TorusExponents { cause: Box::new(Stall::Hill { omega: w, failure: hill.clone() }) },
                format!(
                    "no Floquet exponents at the torus point: {}",
                    Error::Hill { omega: w, failure: hill.clone() }
                ),
            ),
            (
                Stall::HillOperator { omega: w, cause: Box::new(Stall::Hill { omega: w, failure: hill.clone() }) },
                format!("Hill's operator at Ω = {w:.6}: {}", Error::Hill { omega: w, failure: hill }),
            ),
            (
                Stall::LandRangeEnd { cause: inner() },
                format!("could not land on the range end: {why}"),
            ),
            (
                Stall::LandAmplitude { amplitude: hi, cause: inner() },
                format!("could not land on max |x| = {hi}: {why}"),
            ),
            (
                Stall::LandParameter { parameter: "mu".into(), value: hi, cause: inner() },
                format!("could not land on {} = {hi}: {why}", "mu"),
            ),
            (Stall::LocateZeroDamping { cause: inner() }, format!("could not locate ξ = 0: {why}")),
        ];
        for (stall, text) in cases {
            assert_eq!(stall.to_string(), text, "{stall:?}");
            // An error that is a stall reads as the stall.
            assert_eq!(Error::from(stall).to_string(), text);
        }
    }

    /// Every error that once was a bare message reads as that message did (each
    /// expected text is built by the `format!` or literal that built it then).
    #[test]
    fn a_typed_error_reads_as_the_message_it_replaced() {
        let cases: Vec<(Error, String)> = vec![
            (
                Error::NothingToDraw { what: Drawable::BackbonePoints },
                "no backbone points to draw".to_string(),
            ),
            (
                Error::NothingToDraw { what: Drawable::LimitCycles },
                "no limit cycles to draw".to_string(),
            ),
            (
                Error::NothingToDraw { what: Drawable::FoldCurves },
                "no fold curves to draw".to_string(),
            ),
            (Error::NothingToDraw { what: Drawable::Points }, "no points to draw".to_string()),
            (
                Error::Plot { reason: format!("{:?}", "backend") },
                format!("drawing a figure failed: {:?}", "backend"),
            ),
            (
                Error::CurveSlotLost { slot: 3 },
                format!("drawing a figure failed: curve slot {} lost", 3),
            ),
            (
                Error::HistoryFull { capacity: 4096 },
                format!(
                    "history buffer full ({} values): more steps than the integrator was set up for",
                    4096
                ),
            ),
            (
                Error::HistoryFft { reason: "wrong length".into() },
                format!("fast history FFT: {}", "wrong length"),
            ),
            (
                Error::SignalOutsideDofs { model: "duffing".into(), dofs: 2 },
                format!(
                    "model '{}' declares a signal on a DOF index outside 0..{}",
                    "duffing", 2
                ),
            ),
            (
                Error::NoLimitCycle {
                    omega: 1.5,
                    mode: 2,
                    ended: End::Stalled(Stall::StepLimit { steps: 500 }),
                },
                format!(
                    "no limit cycle near ω = {} rad/s (mode {}): {}",
                    1.5, 2, "stalled: step limit 500 reached"
                ),
            ),
            (
                Error::CycleCollapses { omega: 1.2345678, amplitude: 2.5e-9 },
                format!(
                    "the cycle near ω = {:.6} rad/s collapses to the equilibrium (max |x| = {:.3e}): the mode is at its Hopf point",
                    1.2345678, 2.5e-9
                ),
            ),
            (
                Error::NoCycleToContinue {
                    parameter: "mu".into(),
                    value: 0.25,
                    cause: Some(Box::new(Error::CycleCollapses {
                        omega: 1.0,
                        amplitude: 1e-9,
                    })),
                },
                format!(
                    "no limit cycle to continue at {} = {}: {}",
                    "mu",
                    0.25,
                    Error::CycleCollapses { omega: 1.0, amplitude: 1e-9 }
                ),
            ),
            (
                Error::NoCycleToContinue { parameter: "mu".into(), value: 0.25, cause: None },
                format!("no limit cycle to continue at {} = {}", "mu", 0.25),
            ),
            (
                Error::NotSymmetric { omega: 1.75, ratio: 0.0123 },
                format!(
                    "the branch point at Ω = {} is not on a symmetric solution (its even harmonics are {:.1e} of the odd ones): nothing to break",
                    1.75, 0.0123
                ),
            ),
            (
                Error::NoCriticalDirection {
                    omega: 0.875,
                    failure: DirectionFailure::NonFiniteJacobian,
                },
                format!("non-finite Jacobian at the branch at ω = {}", 0.875),
            ),
            (
                Error::NoCriticalDirection { omega: 0.875, failure: DirectionFailure::Vanished },
                format!("no critical direction at the branch at ω = {}", 0.875),
            ),
            (
                Error::from(LinearisationFailure::Eigensolve(format!("{:?}", "NoConvergence"))),
                format!("the linearised model's eigenvalues failed: {:?}", "NoConvergence"),
            ),
            (
                Error::Linearisation(LinearisationFailure::NonFinite),
                "non-finite linearised model".to_string(),
            ),
            (
                Error::Linearisation(LinearisationFailure::Degenerate),
                "no mode shape: the linearised model is degenerate".to_string(),
            ),
        ];
        for (error, text) in cases {
            assert_eq!(error.to_string(), text, "{error:?}");
        }
    }

    /// An error met while tracing keeps its kind as a reason, and a stall made an
    /// error comes back unchanged.
    #[test]
    fn an_error_met_on_a_path_becomes_its_reason() {
        let coefficient = Error::NonFiniteCoefficient {
            model: "m".into(),
            term: "ln(k)".into(),
            value: f64::NEG_INFINITY,
            omega: 2.0,
            params: "k = 0".into(),
        };
        let text = coefficient.to_string();
        let s = Stall::from(coefficient);
        assert!(
            matches!(&s, Stall::Coefficient { term, omega, .. } if term == "ln(k)" && *omega == 2.0)
        );
        assert_eq!(s.to_string(), text);
        let step = Stall::StepLimit { steps: 7 };
        assert_eq!(Stall::from(Error::from(step.clone())), step);
        let other = Error::HistoryFull { capacity: 8 };
        let text = other.to_string();
        assert_eq!(Stall::from(other), Stall::Other(text));
    }
}
