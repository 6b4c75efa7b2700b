//! A model behind a pointer: one object-safe trait, [`DynModel`], and the owning
//! handle [`BoxedModel`] that implements [`Model`] again.
//!
//! [`Model`] is not object-safe (its residual is generic over the scalar type), so a
//! solver called with ten model types is compiled ten times. The application (the
//! command line, studies, Python) holds models it only knows at run time — the
//! built-in ones, a model file — and runs every analysis on them: behind a
//! [`BoxedModel`] the whole solver stack is compiled once, and each model contributes
//! only its residual in the three scalar types the solvers use ([`Scalar`]). The
//! price is one indirect call per residual evaluation (per time sample), measured in
//! the `boxed` bench; code that names its model type (a user's own program) stays
//! monomorphised.
//!
//! ```
//! use ihbm::model::{BoxedModel, Model};
//! use ihbm::models::Duffing;
//!
//! let mut m = BoxedModel::new(Duffing::default());
//! m.set_param("F", 0.5).unwrap();
//! assert_eq!(m.name(), "duffing");
//! assert_eq!(m.param("F").unwrap(), 0.5);
//! // The same solvers, the same answer, the model type erased.
//! let typed = Duffing { F: 0.5, ..Duffing::default() };
//! let opts = Default::default();
//! let direct = ihbm::corrector::solve(&typed, 3.0, &opts, None).unwrap();
//! let boxed = ihbm::corrector::solve(&m, 3.0, &opts, None).unwrap();
//! assert_eq!(direct.coeffs, boxed.coeffs);
//! ```

use super::{Model, Output, ParamInfo, Scalar, Signal, Text};
use crate::error::Error;
use num_dual::{Dual64, HyperDual64};

/// The object-safe face of a [`Model`]: every method of the trait, with the residual
/// spelled out for each [`Scalar`]. Implemented for every `Model + Clone`; held as a
/// [`BoxedModel`].
pub trait DynModel: Send + Sync {
    /// [`Model::name`].
    fn name(&self) -> &str;
    /// [`Model::description`].
    fn description(&self) -> &str;
    /// [`Model::dofs`].
    fn dofs(&self) -> &[Text];
    /// [`Model::params_info`].
    fn params_info(&self) -> &[ParamInfo];
    /// [`Model::param_value`].
    fn param_value(&self, index: usize) -> f64;
    /// [`Model::set_param_value`].
    fn set_param_value(&mut self, index: usize, value: f64);
    /// [`Model::signals`].
    fn signals(&self) -> &[Signal];
    /// [`Model::outputs`].
    fn outputs(&self) -> &[Output];
    /// [`Model::degree`].
    fn degree(&self) -> usize;
    /// [`Model::max_forcing_harmonic`].
    fn max_forcing_harmonic(&self) -> usize;
    /// [`Model::parametric_harmonic`].
    fn parametric_harmonic(&self) -> usize;
    /// [`Model::equations`].
    fn equations(&self) -> &[Text];
    /// [`Model::affine_signals`].
    fn affine_signals(&self) -> &[bool];
    /// [`Model::signal_reads`].
    fn signal_reads(&self) -> &[bool];
    /// [`Model::explicit_omega`].
    fn explicit_omega(&self) -> bool;
    /// [`Model::residual`] in `f64`.
    fn residual_f64(&self, p: &[f64], omega: f64, phase: f64, s: &[f64], out: &mut [f64]);
    /// [`Model::residual`] in first-order dual numbers.
    fn residual_dual(
        &self,
        p: &[Dual64],
        omega: Dual64,
        phase: f64,
        s: &[Dual64],
        out: &mut [Dual64],
    );
    /// [`Model::residual`] in hyper-dual numbers (second derivatives).
    fn residual_hyper_dual(
        &self,
        p: &[HyperDual64],
        omega: HyperDual64,
        phase: f64,
        s: &[HyperDual64],
        out: &mut [HyperDual64],
    );
    /// [`Model::check_coefficients`].
    fn check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error>;
    /// [`Model::set_param`].
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error>;
    /// [`Model::validate`].
    fn validate(&self) -> Result<(), Error>;
    /// A copy behind a new box.
    fn clone_box(&self) -> Box<dyn DynModel>;
}

impl<M: Model + Clone + 'static> DynModel for M {
    fn name(&self) -> &str {
        Model::name(self)
    }
    fn description(&self) -> &str {
        Model::description(self)
    }
    fn dofs(&self) -> &[Text] {
        Model::dofs(self)
    }
    fn params_info(&self) -> &[ParamInfo] {
        Model::params_info(self)
    }
    fn param_value(&self, index: usize) -> f64 {
        Model::param_value(self, index)
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        Model::set_param_value(self, index, value)
    }
    fn signals(&self) -> &[Signal] {
        Model::signals(self)
    }
    fn outputs(&self) -> &[Output] {
        Model::outputs(self)
    }
    fn degree(&self) -> usize {
        Model::degree(self)
    }
    fn max_forcing_harmonic(&self) -> usize {
        Model::max_forcing_harmonic(self)
    }
    fn parametric_harmonic(&self) -> usize {
        Model::parametric_harmonic(self)
    }
    fn equations(&self) -> &[Text] {
        Model::equations(self)
    }
    fn affine_signals(&self) -> &[bool] {
        Model::affine_signals(self)
    }
    fn signal_reads(&self) -> &[bool] {
        Model::signal_reads(self)
    }
    fn explicit_omega(&self) -> bool {
        Model::explicit_omega(self)
    }
    fn residual_f64(&self, p: &[f64], omega: f64, phase: f64, s: &[f64], out: &mut [f64]) {
        Model::residual(self, p, omega, phase, s, out)
    }
    fn residual_dual(
        &self,
        p: &[Dual64],
        omega: Dual64,
        phase: f64,
        s: &[Dual64],
        out: &mut [Dual64],
    ) {
        Model::residual(self, p, omega, phase, s, out)
    }
    fn residual_hyper_dual(
        &self,
        p: &[HyperDual64],
        omega: HyperDual64,
        phase: f64,
        s: &[HyperDual64],
        out: &mut [HyperDual64],
    ) {
        Model::residual(self, p, omega, phase, s, out)
    }
    fn check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error> {
        Model::check_coefficients(self, params, omega)
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        Model::set_param(self, name, value)
    }
    fn validate(&self) -> Result<(), Error> {
        Model::validate(self)
    }
    fn clone_box(&self) -> Box<dyn DynModel> {
        Box::new(self.clone())
    }
}

/// Any model, its type erased: a [`Model`] (and `Clone`) whatever it holds, so every
/// solver takes it. See the [module documentation](self) for when to use one.
pub struct BoxedModel(Box<dyn DynModel>);

impl BoxedModel {
    /// Erase the type of `model`.
    pub fn new<M: Model + Clone + 'static>(model: M) -> Self {
        BoxedModel(Box::new(model))
    }
}

impl Clone for BoxedModel {
    fn clone(&self) -> Self {
        BoxedModel(self.0.clone_box())
    }
}

impl std::fmt::Debug for BoxedModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("BoxedModel").field(&self.0.name()).finish()
    }
}

impl Model for BoxedModel {
    fn name(&self) -> &str {
        self.0.name()
    }
    fn description(&self) -> &str {
        self.0.description()
    }
    fn dofs(&self) -> &[Text] {
        self.0.dofs()
    }
    fn params_info(&self) -> &[ParamInfo] {
        self.0.params_info()
    }
    fn param_value(&self, index: usize) -> f64 {
        self.0.param_value(index)
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        self.0.set_param_value(index, value)
    }
    fn signals(&self) -> &[Signal] {
        self.0.signals()
    }
    fn outputs(&self) -> &[Output] {
        self.0.outputs()
    }
    fn degree(&self) -> usize {
        self.0.degree()
    }
    fn max_forcing_harmonic(&self) -> usize {
        self.0.max_forcing_harmonic()
    }
    fn parametric_harmonic(&self) -> usize {
        self.0.parametric_harmonic()
    }
    fn equations(&self) -> &[Text] {
        self.0.equations()
    }
    fn affine_signals(&self) -> &[bool] {
        self.0.affine_signals()
    }
    fn signal_reads(&self) -> &[bool] {
        self.0.signal_reads()
    }
    fn explicit_omega(&self) -> bool {
        self.0.explicit_omega()
    }
    fn residual<D: Scalar>(
        &self,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        D::residual_of(&*self.0, params, omega, phase, signals, out)
    }
    fn check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error> {
        self.0.check_coefficients(params, omega)
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        self.0.set_param(name, value)
    }
    fn validate(&self) -> Result<(), Error> {
        self.0.validate()
    }
}

/// Each scalar type's residual method of a [`DynModel`] (public in a private module:
/// [`Scalar`] is sealed).
pub trait Dispatch: Sized {
    /// Call the method of `model` for this scalar type.
    fn residual_of(
        model: &dyn DynModel,
        p: &[Self],
        omega: Self,
        phase: f64,
        s: &[Self],
        out: &mut [Self],
    );
}

impl Dispatch for f64 {
    fn residual_of(
        model: &dyn DynModel,
        p: &[f64],
        omega: f64,
        phase: f64,
        s: &[f64],
        out: &mut [f64],
    ) {
        model.residual_f64(p, omega, phase, s, out)
    }
}

impl Dispatch for Dual64 {
    fn residual_of(
        model: &dyn DynModel,
        p: &[Self],
        omega: Self,
        phase: f64,
        s: &[Self],
        out: &mut [Self],
    ) {
        model.residual_dual(p, omega, phase, s, out)
    }
}

impl Dispatch for HyperDual64 {
    fn residual_of(
        model: &dyn DynModel,
        p: &[Self],
        omega: Self,
        phase: f64,
        s: &[Self],
        out: &mut [Self],
    ) {
        model.residual_hyper_dual(p, omega, phase, s, out)
    }
}
