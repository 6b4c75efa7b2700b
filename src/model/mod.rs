//! The model trait: what an oscillator tells the solvers about itself.
//!
//! A model is a set of equations `r_e(signals, θ) = 0`, one per degree of freedom,
//! that are polynomial in a fixed list of *signals*. A signal is a derivative of a
//! linear combination of DOFs: displacement (order 0), velocity (1), acceleration (2)
//! or a fractional derivative of order `p` taken from a parameter. The solvers turn
//! Fourier coefficients into signal values; the model only evaluates its equations at
//! one time sample. The residual is generic over dual numbers, so every Jacobian
//! (with respect to signals, Ω or any parameter) comes from one code path and no
//! derivative is ever written by hand.

use crate::error::Error;
use num_dual::{Dual64, DualNum, HyperDual64};
use std::borrow::Cow;

mod boxed;
pub mod kink;
mod with_params;
mod with_samples;
pub use boxed::{BoxedModel, DynModel};
pub use with_params::WithParams;
pub use with_samples::WithSamples;

/// The scalar types the solvers evaluate a residual in: `f64` (values), [`Dual64`]
/// (first derivatives: Jacobians, ∂R/∂Ω, ∂R/∂θ) and [`HyperDual64`] (second
/// derivatives: fold and bifurcation curves). The set is closed — [`DynModel`]
/// dispatches on it — and a model implements [`Model::residual`] for any
/// `D: DualNum<Primitive = f64> + Copy`, which covers all three.
pub trait Scalar: DualNum<Primitive = f64> + Copy + boxed::Dispatch {}

impl Scalar for f64 {}
impl Scalar for Dual64 {}
impl Scalar for HyperDual64 {}

/// Text a model owns or borrows: `Cow::Borrowed` for the `'static` data `oscillator!`
/// generates, `Cow::Owned` for a model built at run time (a chain sized in a loop, a
/// model read from a file).
pub type Text = Cow<'static, str>;

/// `(dof index, coefficient)` pairs of a linear combination of DOFs, borrowed or owned.
pub type Terms = Cow<'static, [(usize, f64)]>;

/// The derivative order of a signal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Order {
    /// An integer order: 0 (the value itself), 1, 2, ...
    Int(u32),
    /// A fractional order given by the parameter with this index (steady-state
    /// Weyl/Caputo sense: `D^p e^{ikΩt} = (ikΩ)^p e^{ikΩt}`, `D^p const = 0` for p > 0).
    Param(usize),
}

/// One signal the residual reads: `D^order (Σ coef · x_dof)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Signal {
    /// The linear combination of DOFs, as `(dof index, coefficient)` pairs.
    pub terms: Terms,
    /// The derivative order applied to the combination.
    pub order: Order,
}

/// A named observable that results report.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// The name used in JSON, CSV and plots.
    pub name: Text,
    /// What it is.
    pub kind: OutputKind,
}

/// What an [`Output`] is.
#[derive(Debug, Clone, PartialEq)]
pub enum OutputKind {
    /// A linear combination of DOFs with fixed coefficients, `(dof index, coefficient)`
    /// pairs: its Fourier coefficients are those of the DOFs combined, exactly.
    Dofs(Terms),
    /// Any expression of the signals in [`Model::output_signals`], the parameters, Ω
    /// and time (an acceleration, a spring force, a tyre force that cannot pull):
    /// result `i` of [`Model::output_values`], evaluated on the transform's time grid
    /// and projected onto the solution's harmonics.
    Expression(usize),
}

impl Output {
    /// The output `name` that is the linear combination `terms` of DOFs.
    pub fn dofs(name: impl Into<Text>, terms: impl Into<Terms>) -> Output {
        Output { name: name.into(), kind: OutputKind::Dofs(terms.into()) }
    }

    /// The output `name` that is result `index` of [`Model::output_values`].
    pub fn expression(name: impl Into<Text>, index: usize) -> Output {
        Output { name: name.into(), kind: OutputKind::Expression(index) }
    }
}

/// One end of a [`Domain`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// No bound on this side (`-inf` or `inf`, always open).
    Unbounded,
    /// The end itself is excluded: `(a` or `b)`.
    Open(f64),
    /// The end itself is included: `[a` or `b]`.
    Closed(f64),
}

/// The values a parameter may take: an interval of the reals, each end open, closed or
/// unbounded. Declared in a model after the default (`m = 1.0 in (0, inf)`) and
/// checked by [`Model::validate`], so a value outside it is refused wherever it enters
/// (`--set`, study files, continuation ranges), not discovered as a strange result.
///
/// ```
/// use ihbm::model::{Bound, Domain};
///
/// let stiffness = Domain { lower: Bound::Closed(0.0), upper: Bound::Unbounded };
/// assert_eq!(stiffness.to_string(), "[0, inf)");
/// assert!(stiffness.contains(0.0) && stiffness.contains(1e300) && !stiffness.contains(-1e-9));
/// assert!(Domain::ANY.contains(-5.0));
/// assert!(!Domain::ANY.contains(f64::NAN));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// The lower end.
    pub lower: Bound,
    /// The upper end.
    pub upper: Bound,
}

impl Domain {
    /// All reals, `(-inf, inf)`: the domain of a parameter that declares none.
    pub const ANY: Domain = Domain { lower: Bound::Unbounded, upper: Bound::Unbounded };

    /// Whether `x` lies in the domain (NaN never does).
    pub fn contains(&self, x: f64) -> bool {
        let above = match self.lower {
            Bound::Unbounded => !x.is_nan(),
            Bound::Open(a) => x > a,
            Bound::Closed(a) => x >= a,
        };
        let below = match self.upper {
            Bound::Unbounded => !x.is_nan(),
            Bound::Open(b) => x < b,
            Bound::Closed(b) => x <= b,
        };
        above && below
    }

    /// Whether this is [`Domain::ANY`] (nothing declared, nothing to check).
    pub fn is_any(&self) -> bool {
        *self == Domain::ANY
    }
}

impl std::fmt::Display for Domain {
    /// Interval notation, `(0, inf)`, `[0, 2]`, `(-inf, 1]`, as the model language
    /// reads it back (in quotes when half-open: `in "[0, inf)"`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::error::Num;
        match self.lower {
            Bound::Unbounded => write!(f, "(-inf, ")?,
            Bound::Open(a) => write!(f, "({}, ", Num(a))?,
            Bound::Closed(a) => write!(f, "[{}, ", Num(a))?,
        }
        match self.upper {
            Bound::Unbounded => write!(f, "inf)"),
            Bound::Open(b) => write!(f, "{})", Num(b)),
            Bound::Closed(b) => write!(f, "{}]", Num(b)),
        }
    }
}

/// A declared parameter: name, default value, domain and a line of documentation
/// (units).
#[derive(Debug, Clone, PartialEq)]
pub struct ParamInfo {
    /// Name used by `--set NAME=VALUE` and study files.
    pub name: Text,
    /// The declared default value (inside `domain`).
    pub default: f64,
    /// What it is, with units.
    pub doc: Text,
    /// The values it may take ([`Domain::ANY`] if the model declares none).
    pub domain: Domain,
}

/// An oscillator whose periodic steady state the solvers can compute.
///
/// Implement it by hand or let [`oscillator!`](crate::oscillator) generate it.
/// Parameters are addressed by index in the order of [`Model::params_info`]. The
/// metadata (names, signals, outputs) is borrowed from `self`, so a model decided at
/// run time — its DOF count, parameters and signals built in a loop or read from a
/// file — implements the trait as well as a generated one (whose data is `'static`).
/// The book's chapter "Writing your own model" builds an n-mass chain that way.
///
/// ```
/// use ihbm::model::{Bound, Domain, Model, Order, Output, OutputKind, ParamInfo, Signal, Text};
/// use num_dual::DualNum;
/// use std::borrow::Cow::Borrowed;
///
/// /// m x'' + c x' + k x = F cos(Ωt)
/// #[derive(Clone, Default)]
/// struct Linear { m: f64, c: f64, k: f64, f: f64 }
///
/// impl Model for Linear {
///     fn name(&self) -> &str { "linear" }
///     fn dofs(&self) -> &[Text] { &[Borrowed("x")] }
///     fn params_info(&self) -> &[ParamInfo] {
///         const P: &[ParamInfo] = &[
///             ParamInfo { name: Borrowed("m"), default: 1.0, doc: Borrowed("mass (kg)"),
///                         domain: Domain { lower: Bound::Open(0.0), upper: Bound::Unbounded } },
///             ParamInfo { name: Borrowed("c"), default: 0.1, doc: Borrowed("damping (N s/m)"),
///                         domain: Domain::ANY },
///             ParamInfo { name: Borrowed("k"), default: 1.0, doc: Borrowed("stiffness (N/m)"),
///                         domain: Domain::ANY },
///             ParamInfo { name: Borrowed("F"), default: 1.0, doc: Borrowed("force amplitude (N)"),
///                         domain: Domain::ANY },
///         ];
///         P
///     }
///     fn param_value(&self, i: usize) -> f64 { [self.m, self.c, self.k, self.f][i] }
///     fn set_param_value(&mut self, i: usize, v: f64) {
///         *[&mut self.m, &mut self.c, &mut self.k, &mut self.f][i] = v;
///     }
///     fn signals(&self) -> &[Signal] {
///         const S: &[Signal] = &[
///             Signal { terms: Borrowed(&[(0, 1.0)]), order: Order::Int(0) },
///             Signal { terms: Borrowed(&[(0, 1.0)]), order: Order::Int(1) },
///             Signal { terms: Borrowed(&[(0, 1.0)]), order: Order::Int(2) },
///         ];
///         S
///     }
///     fn outputs(&self) -> &[Output] {
///         const O: &[Output] =
///             &[Output { name: Borrowed("x"), kind: OutputKind::Dofs(Borrowed(&[(0, 1.0)])) }];
///         O
///     }
///     fn degree(&self) -> usize { 1 }
///     fn residual<D: DualNum<Primitive = f64> + Copy>(
///         &self, p: &[D], _omega: D, phase: f64, s: &[D], r: &mut [D],
///     ) {
///         r[0] = p[0] * s[2] + p[1] * s[1] + p[2] * s[0] - p[3] * phase.cos();
///     }
/// }
///
/// let mut m = Linear { m: 1.0, c: 0.1, k: 1.0, f: 1.0 };
/// m.set_param("k", 4.0).unwrap();
/// assert_eq!(m.param("k").unwrap(), 4.0);
/// assert!(m.set_param("q", 1.0).is_err());
/// // A mass is positive: the domain refuses -1 (and `validate` any value set otherwise).
/// let e = m.set_param("m", -1.0).unwrap_err().to_string();
/// assert!(e.contains("a value in (0, inf) (the domain model 'linear' declares for m)"), "{e}");
/// m.set_param_value(0, -1.0);
/// assert!(m.validate().is_err());
/// ```
pub trait Model: Send + Sync {
    /// A short name (the CLI's model name for built-in models).
    fn name(&self) -> &str;

    /// One line (or a paragraph) saying what the model is.
    fn description(&self) -> &str {
        ""
    }

    /// Names of the degrees of freedom, in coefficient order.
    fn dofs(&self) -> &[Text];

    /// Declared parameters: names, defaults, docs.
    fn params_info(&self) -> &[ParamInfo];

    /// The current value of parameter `index` (`index < params_info().len()`).
    fn param_value(&self, index: usize) -> f64;

    /// Set parameter `index` (`index < params_info().len()`).
    fn set_param_value(&mut self, index: usize, value: f64);

    /// The signals the residual reads, in the order of its `signals` argument.
    fn signals(&self) -> &[Signal];

    /// Named observables reported in results.
    fn outputs(&self) -> &[Output];

    /// The signals the expression outputs read ([`OutputKind::Expression`]), in the
    /// order of [`Model::output_values`]'s `signals` argument: a list of its own, so
    /// that an output reading the acceleration or a fractional derivative adds nothing
    /// to the cost of the residual. Empty (the default) when every output is a
    /// combination of DOFs.
    fn output_signals(&self) -> &[Signal] {
        &[]
    }

    /// The polynomial degree of the expression outputs in their signals (as
    /// [`Model::degree`] for the residual): the transform that evaluates them takes
    /// enough samples to project a product of that degree onto the harmonics without
    /// aliasing.
    fn output_degree(&self) -> usize {
        1
    }

    /// Whether the expression outputs are smooth ([`Model::smooth`] for the outputs: a
    /// tyre force `max(0, …)` is not), which sets how finely they are sampled.
    fn outputs_smooth(&self) -> bool {
        true
    }

    /// Evaluate the expression outputs at one time sample, as [`Model::residual`]
    /// evaluates the equations: `signals` are the values of [`Model::output_signals`],
    /// `out` receives one value per [`OutputKind::Expression`] index. The default
    /// writes nothing (a model whose outputs are all combinations of DOFs).
    fn output_values<D: Scalar>(
        &self,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        let _ = (params, omega, phase, signals, out);
    }

    /// Polynomial degree of the residual in the signals (1 for a linear model, 3 for
    /// a cubic spring). Sets the alias-free sample count.
    fn degree(&self) -> usize;

    /// Whether the residual is smooth: `false` when it applies a non-smooth function
    /// ([`kink`]: `max`, `min`, `abs`, `sign`) to signals or to time (a bump stop, an
    /// asymmetric damper, a tyre that leaves the road). Such a term has harmonics
    /// without end, so no sample count is alias-free: the transform then takes
    /// [`crate::fourier::KINK_OVERSAMPLING`] times the samples the harmonics need, or
    /// [`Model::aft_samples`]. The default `true` is what a polynomial model is.
    fn smooth(&self) -> bool {
        true
    }

    /// The samples per forcing period the transform takes, where the model is asked
    /// to use a count of its own ([`WithSamples`], `--aft-samples`); `None` (the
    /// default): the count [`crate::fourier::model_sample_count`] derives.
    fn aft_samples(&self) -> Option<usize> {
        None
    }

    /// The highest harmonic of the time dependence (`cos(k Ω t)` with `k` up to this),
    /// forcing and parametric terms alike. Fewer harmonics than this are refused.
    fn max_forcing_harmonic(&self) -> usize {
        1
    }

    /// The highest harmonic `k` of a time-varying factor `cos/sin(kΩt)` that multiplies
    /// signals (parametric excitation: a stiffness `k (1 + ε cos 2Ωt)`), 0 (the
    /// default) if there is none. Such a product of signals of total degree up to
    /// [`Model::degree`] has harmonics up to `degree·N + k`, which the sample count
    /// keeps alias-free ([`crate::fourier::model_sample_count`]). A value too low
    /// makes the projection alias without an error, like a degree too low.
    fn parametric_harmonic(&self) -> usize {
        0
    }

    /// The equations as text, for `ihbm models NAME`.
    fn equations(&self) -> &[Text] {
        &[]
    }

    /// Structure the solvers may exploit: `affine[s]` is `true` when every equation is
    /// affine in signal `s` with a coefficient that depends on parameters and Ω only
    /// (not on the other signals, nor on time), so `∂r/∂s` is constant over a period
    /// and is evaluated at one sample instead of all of them. Empty (the default)
    /// means "unknown": every signal is treated as nonlinear. `oscillator!` derives it
    /// from the equations; [`Balance::new`](crate::balance::Balance::new) checks a
    /// hand-written claim at random states and rejects a wrong one.
    fn affine_signals(&self) -> &[bool] {
        &[]
    }

    /// Which signals each equation reads: `reads[e * signals().len() + s]` is `true`
    /// wherever `∂r_e/∂s` may be non-zero (a conservative claim: `true` where terms
    /// merely might cancel). The solvers then seed signals that no equation reads
    /// together in one dual pass over the samples (a chain's Jacobian takes three
    /// passes instead of one per signal). Empty (the default) means "unknown": one
    /// pass per signal. `oscillator!` derives it from the equations;
    /// [`Balance::new`](crate::balance::Balance::new) tests a claim at random states
    /// and rejects one that leaves out a derivative it finds.
    fn signal_reads(&self) -> &[bool] {
        &[]
    }

    /// Whether the residual depends on Ω other than through the signals (e.g. a
    /// base excitation `m Ω² F cos Ωt`). `false` lets `∂R/∂Ω` come from the signal
    /// gradients without another pass over the samples. The default `true` is
    /// always correct; a wrong `false` is caught by
    /// [`Balance::new`](crate::balance::Balance::new).
    fn explicit_omega(&self) -> bool {
        true
    }

    /// Evaluate all equations at one time sample.
    ///
    /// - `params`: parameter values, in `params_info` order (dual numbers so that
    ///   derivatives with respect to parameters come for free);
    /// - `omega`: the forcing frequency Ω in rad/s;
    /// - `phase`: `Ω t` at this sample (forcing terms are `cos(k·phase)`, `sin(k·phase)`);
    /// - `signals`: the signal values at this sample, in `signals()` order;
    /// - `out`: one residual per DOF, written (not accumulated).
    ///
    /// The solvers call it with the [`Scalar`] types; an implementation is generic
    /// over any `D: DualNum<Primitive = f64> + Copy` (a looser bound, as in the
    /// example above); one that forwards to another model's residual declares
    /// `D: Scalar`, as the trait does.
    fn residual<D: Scalar>(&self, params: &[D], omega: D, phase: f64, signals: &[D], out: &mut [D]);

    /// Check that every coefficient is finite at parameters `params` and frequency
    /// `omega` (a coefficient may be any smooth expression of them, `sqrt(k - m Ω²)`,
    /// `1 / Ω`, `ln(a)`): an error naming the first that is not, instead of a residual
    /// full of NaN. The solvers call it at every point where they evaluate the model
    /// (the corrector, each continuation step, the time integrator). The default
    /// accepts every point; `oscillator!` generates it from the equations.
    fn check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error> {
        let _ = (params, omega);
        Ok(())
    }

    /// Index of the parameter called `name`.
    fn param_index(&self, name: &str) -> Result<usize, Error> {
        self.params_info().iter().position(|p| p.name == name).ok_or_else(|| {
            Error::UnknownParameter {
                name: name.to_string(),
                model: self.name().to_string(),
                known: self.params_info().iter().map(|p| &*p.name).collect::<Vec<_>>().join(", "),
            }
        })
    }

    /// The value of the parameter called `name`.
    fn param(&self, name: &str) -> Result<f64, Error> {
        Ok(self.param_value(self.param_index(name)?))
    }

    /// Set the parameter called `name`; unknown names, non-finite values and values
    /// outside the parameter's [`Domain`] are errors (the value is not set).
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        let i = self.param_index(name)?;
        if !value.is_finite() {
            return Err(Error::InvalidValue {
                what: format!("parameter {name}"),
                value: value.to_string(),
                expected: "a finite number".into(),
            });
        }
        check_domain(self.name(), &self.params_info()[i], &param_what(self, i), value)?;
        self.set_param_value(i, value);
        Ok(())
    }

    /// All parameter values, in `params_info` order.
    fn param_values(&self) -> Vec<f64> {
        (0..self.params_info().len()).map(|i| self.param_value(i)).collect()
    }

    /// Index of the output called `name`.
    fn output_index(&self, name: &str) -> Result<usize, Error> {
        self.outputs().iter().position(|o| o.name == name).ok_or_else(|| Error::UnknownOutput {
            name: name.to_string(),
            model: self.name().to_string(),
            known: self.outputs().iter().map(|o| &*o.name).collect::<Vec<_>>().join(", "),
        })
    }

    /// Check what the solvers rely on: finite parameters, each in its declared
    /// [`Domain`], and fractional orders in [0, 2]. Called by every solver entry point.
    /// (That there is one equation per DOF is a property of `residual`, which writes
    /// `dofs().len()` outputs; the macro checks it at compile time.)
    fn validate(&self) -> Result<(), Error> {
        for (i, info) in self.params_info().iter().enumerate() {
            let v = self.param_value(i);
            if !v.is_finite() {
                return Err(Error::InvalidValue {
                    what: format!("parameter {}", info.name),
                    value: v.to_string(),
                    expected: "a finite number".into(),
                });
            }
            check_domain(self.name(), info, &param_what(self, i), v)?;
        }
        for s in self.signals() {
            if let Order::Param(i) = s.order {
                let v = self.param_value(i);
                if !(0.0..=2.0).contains(&v) {
                    return Err(Error::InvalidValue {
                        what: format!("fractional order {}", self.params_info()[i].name),
                        value: v.to_string(),
                        expected: "a value in [0, 2]".into(),
                    });
                }
            }
        }
        Ok(())
    }
}

/// "fractional order p" for a parameter some signal takes as its order, else
/// "parameter k": how messages name parameter `i` of `model`.
fn param_what<M: Model + ?Sized>(model: &M, i: usize) -> String {
    let name = &model.params_info()[i].name;
    if model.signals().iter().any(|s| s.order == Order::Param(i)) {
        format!("fractional order {name}")
    } else {
        format!("parameter {name}")
    }
}

/// Refuse `value` for parameter `info` of model `model` if it lies outside the declared
/// domain: the one message for every place a value enters (`set_param`, `validate`,
/// the ends of a continuation range); `what` names the value ("parameter m1", "end of
/// the range of m1").
pub fn check_domain(model: &str, info: &ParamInfo, what: &str, value: f64) -> Result<(), Error> {
    if info.domain.contains(value) {
        return Ok(());
    }
    Err(Error::InvalidValue {
        what: what.to_string(),
        value: crate::error::Num(value).to_string(),
        expected: format!(
            "a value in {} (the domain model '{model}' declares for {})",
            info.domain, info.name
        ),
    })
}

/// `Σ c · x[d]` over `terms`: the value of a linear combination of DOFs.
pub fn combine(terms: &[(usize, f64)], x: &[f64]) -> f64 {
    terms.iter().map(|&(d, c)| c * x[d]).sum()
}

/// `out = Σ c · x[d·len .. (d + 1)·len]` over `terms` (`len = out.len()`): the same
/// linear combination of per-DOF blocks, e.g. of Fourier coefficients.
pub fn combine_blocks(terms: &[(usize, f64)], x: &[f64], out: &mut [f64]) {
    let len = out.len();
    out.fill(0.0);
    for &(d, c) in terms {
        for (o, &v) in out.iter_mut().zip(&x[d * len..(d + 1) * len]) {
            *o += c * v;
        }
    }
}

impl Order {
    /// The numeric order for the current parameter values.
    pub fn value(&self, params: &[f64]) -> f64 {
        match *self {
            Order::Int(n) => n as f64,
            Order::Param(i) => params[i],
        }
    }
}
