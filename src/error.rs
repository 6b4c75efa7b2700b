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
        /// What was looked for: "fold" or "period doubling".
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
    /// A coefficient of the model (a function of parameters and Ω) is NaN or infinite
    /// where the model is evaluated: a square root of a negative number, a logarithm
    /// of a non-positive one, a division by zero.
    #[error("model '{model}': the coefficient `{term}` is {value} at Ω = {} rad/s ({params}); a coefficient must be finite wherever the model is evaluated: choose a frequency range and parameter values where it is defined", Num(*.omega))]
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
    /// Anything else with a message.
    /// Hill's method found no exponents at a point (the point's stability is then
    /// `Unknown` with this as its reason).
    #[error("Hill's method at Ω = {}: {failure}", Num(*.omega))]
    Hill { omega: f64, failure: HillFailure },

    /// A model's structure claim ([`crate::model::Model::affine_signals`],
    /// `explicit_omega`, `signal_reads`) contradicted at a test state: trusted, it
    /// would give wrong Jacobians.
    #[error("model '{model}': {claim} is wrong: {detail}")]
    WrongClaim { model: String, claim: Claim, detail: String },

    #[error("{0}")]
    Other(String),
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
