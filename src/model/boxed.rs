//! A model behind a pointer: one object-safe trait, [`DynModel`], that every
//! [`Model`] implements, and the owning handle [`BoxedModel`].
//!
//! [`Model`] is not object-safe (its residual is generic over the scalar type). The
//! solvers take `&dyn DynModel`, so the whole solver stack is compiled once, in this
//! crate, whatever the models: a program (or a test binary) with ten model types
//! compiles only their residuals, in the three scalar types the solvers use
//! ([`Scalar`]). A `&Duffing` passed where a solver wants `&dyn DynModel` converts by
//! itself. The price is one indirect call per residual evaluation (per time sample);
//! the `boxed` bench measures it against a call the compiler could inline.
//!
//! [`BoxedModel`] owns a model the application only knows at run time (a built-in
//! model chosen by name, a model file) and can be cloned.
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
/// spelled out for each [`Scalar`]. Implemented for every [`Model`]; what the solvers
/// take (`&dyn DynModel`), and `dyn DynModel` is a [`Model`] again.
pub trait DynModel: Send + Sync {
    /// [`Model::name`].
    fn dyn_name(&self) -> &str;
    /// [`Model::description`].
    fn dyn_description(&self) -> &str;
    /// [`Model::dofs`].
    fn dyn_dofs(&self) -> &[Text];
    /// [`Model::params_info`].
    fn dyn_params_info(&self) -> &[ParamInfo];
    /// [`Model::param_value`].
    fn dyn_param_value(&self, index: usize) -> f64;
    /// [`Model::set_param_value`].
    fn dyn_set_param_value(&mut self, index: usize, value: f64);
    /// [`Model::signals`].
    fn dyn_signals(&self) -> &[Signal];
    /// [`Model::outputs`].
    fn dyn_outputs(&self) -> &[Output];
    /// [`Model::output_signals`].
    fn dyn_output_signals(&self) -> &[Signal];
    /// [`Model::output_degree`].
    fn dyn_output_degree(&self) -> usize;
    /// [`Model::outputs_smooth`].
    fn dyn_outputs_smooth(&self) -> bool;
    /// [`Model::degree`].
    fn dyn_degree(&self) -> usize;
    /// [`Model::smooth`].
    fn dyn_smooth(&self) -> bool;
    /// [`Model::aft_samples`].
    fn dyn_aft_samples(&self) -> Option<usize>;
    /// [`Model::max_forcing_harmonic`].
    fn dyn_max_forcing_harmonic(&self) -> usize;
    /// [`Model::parametric_harmonic`].
    fn dyn_parametric_harmonic(&self) -> usize;
    /// [`Model::equations`].
    fn dyn_equations(&self) -> &[Text];
    /// [`Model::affine_signals`].
    fn dyn_affine_signals(&self) -> &[bool];
    /// [`Model::signal_reads`].
    fn dyn_signal_reads(&self) -> &[bool];
    /// [`Model::explicit_omega`].
    fn dyn_explicit_omega(&self) -> bool;
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
    /// [`Model::output_values`] in `f64`.
    fn output_values_f64(&self, p: &[f64], omega: f64, phase: f64, s: &[f64], out: &mut [f64]);
    /// [`Model::output_values`] in first-order dual numbers.
    fn output_values_dual(
        &self,
        p: &[Dual64],
        omega: Dual64,
        phase: f64,
        s: &[Dual64],
        out: &mut [Dual64],
    );
    /// [`Model::output_values`] in hyper-dual numbers.
    fn output_values_hyper_dual(
        &self,
        p: &[HyperDual64],
        omega: HyperDual64,
        phase: f64,
        s: &[HyperDual64],
        out: &mut [HyperDual64],
    );
    /// [`Model::check_coefficients`].
    fn dyn_check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error>;
    /// [`Model::set_param`].
    fn dyn_set_param(&mut self, name: &str, value: f64) -> Result<(), Error>;
    /// [`Model::validate`].
    fn dyn_validate(&self) -> Result<(), Error>;
}

impl<M: Model> DynModel for M {
    fn dyn_name(&self) -> &str {
        Model::name(self)
    }
    fn dyn_description(&self) -> &str {
        Model::description(self)
    }
    fn dyn_dofs(&self) -> &[Text] {
        Model::dofs(self)
    }
    fn dyn_params_info(&self) -> &[ParamInfo] {
        Model::params_info(self)
    }
    fn dyn_param_value(&self, index: usize) -> f64 {
        Model::param_value(self, index)
    }
    fn dyn_set_param_value(&mut self, index: usize, value: f64) {
        Model::set_param_value(self, index, value)
    }
    fn dyn_signals(&self) -> &[Signal] {
        Model::signals(self)
    }
    fn dyn_outputs(&self) -> &[Output] {
        Model::outputs(self)
    }
    fn dyn_output_signals(&self) -> &[Signal] {
        Model::output_signals(self)
    }
    fn dyn_output_degree(&self) -> usize {
        Model::output_degree(self)
    }
    fn dyn_outputs_smooth(&self) -> bool {
        Model::outputs_smooth(self)
    }
    fn dyn_degree(&self) -> usize {
        Model::degree(self)
    }
    fn dyn_smooth(&self) -> bool {
        Model::smooth(self)
    }
    fn dyn_aft_samples(&self) -> Option<usize> {
        Model::aft_samples(self)
    }
    fn dyn_max_forcing_harmonic(&self) -> usize {
        Model::max_forcing_harmonic(self)
    }
    fn dyn_parametric_harmonic(&self) -> usize {
        Model::parametric_harmonic(self)
    }
    fn dyn_equations(&self) -> &[Text] {
        Model::equations(self)
    }
    fn dyn_affine_signals(&self) -> &[bool] {
        Model::affine_signals(self)
    }
    fn dyn_signal_reads(&self) -> &[bool] {
        Model::signal_reads(self)
    }
    fn dyn_explicit_omega(&self) -> bool {
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
    fn output_values_f64(&self, p: &[f64], omega: f64, phase: f64, s: &[f64], out: &mut [f64]) {
        Model::output_values(self, p, omega, phase, s, out)
    }
    fn output_values_dual(
        &self,
        p: &[Dual64],
        omega: Dual64,
        phase: f64,
        s: &[Dual64],
        out: &mut [Dual64],
    ) {
        Model::output_values(self, p, omega, phase, s, out)
    }
    fn output_values_hyper_dual(
        &self,
        p: &[HyperDual64],
        omega: HyperDual64,
        phase: f64,
        s: &[HyperDual64],
        out: &mut [HyperDual64],
    ) {
        Model::output_values(self, p, omega, phase, s, out)
    }
    fn dyn_check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error> {
        Model::check_coefficients(self, params, omega)
    }
    fn dyn_set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        Model::set_param(self, name, value)
    }
    fn dyn_validate(&self) -> Result<(), Error> {
        Model::validate(self)
    }
}

/// A [`DynModel`] that can be copied: what a [`BoxedModel`] holds.
trait CloneModel: DynModel {
    fn clone_box(&self) -> Box<dyn CloneModel>;
    fn as_dyn(&self) -> &dyn DynModel;
    fn as_dyn_mut(&mut self) -> &mut dyn DynModel;
}

impl<M: Model + Clone + 'static> CloneModel for M {
    fn clone_box(&self) -> Box<dyn CloneModel> {
        Box::new(self.clone())
    }
    fn as_dyn(&self) -> &dyn DynModel {
        self
    }
    fn as_dyn_mut(&mut self) -> &mut dyn DynModel {
        self
    }
}

/// Any model, owned, its type erased: a [`Model`] (and `Clone`) whatever it holds.
/// See the [module documentation](self) for when to use one.
pub struct BoxedModel(Box<dyn CloneModel>);

impl BoxedModel {
    /// Erase the type of `model`.
    pub fn new<M: Model + Clone + 'static>(model: M) -> Self {
        BoxedModel(Box::new(model))
    }

    /// The model itself, for a solver: `solve(boxed.as_dyn(), …)` calls the model
    /// through one pointer, where `solve(&boxed, …)` goes through this handle too.
    pub fn as_dyn(&self) -> &dyn DynModel {
        self.0.as_dyn()
    }

    /// The model itself, mutably.
    pub fn as_dyn_mut(&mut self) -> &mut dyn DynModel {
        self.0.as_dyn_mut()
    }
}

impl Clone for BoxedModel {
    fn clone(&self) -> Self {
        BoxedModel(self.0.clone_box())
    }
}

impl std::fmt::Debug for BoxedModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("BoxedModel").field(&self.0.dyn_name()).finish()
    }
}

impl Model for dyn DynModel + '_ {
    fn name(&self) -> &str {
        DynModel::dyn_name(self)
    }
    fn description(&self) -> &str {
        DynModel::dyn_description(self)
    }
    fn dofs(&self) -> &[Text] {
        DynModel::dyn_dofs(self)
    }
    fn params_info(&self) -> &[ParamInfo] {
        DynModel::dyn_params_info(self)
    }
    fn param_value(&self, index: usize) -> f64 {
        DynModel::dyn_param_value(self, index)
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        DynModel::dyn_set_param_value(self, index, value)
    }
    fn signals(&self) -> &[Signal] {
        DynModel::dyn_signals(self)
    }
    fn outputs(&self) -> &[Output] {
        DynModel::dyn_outputs(self)
    }
    fn output_signals(&self) -> &[Signal] {
        DynModel::dyn_output_signals(self)
    }
    fn output_degree(&self) -> usize {
        DynModel::dyn_output_degree(self)
    }
    fn outputs_smooth(&self) -> bool {
        DynModel::dyn_outputs_smooth(self)
    }
    fn degree(&self) -> usize {
        DynModel::dyn_degree(self)
    }
    fn smooth(&self) -> bool {
        DynModel::dyn_smooth(self)
    }
    fn aft_samples(&self) -> Option<usize> {
        DynModel::dyn_aft_samples(self)
    }
    fn max_forcing_harmonic(&self) -> usize {
        DynModel::dyn_max_forcing_harmonic(self)
    }
    fn parametric_harmonic(&self) -> usize {
        DynModel::dyn_parametric_harmonic(self)
    }
    fn equations(&self) -> &[Text] {
        DynModel::dyn_equations(self)
    }
    fn affine_signals(&self) -> &[bool] {
        DynModel::dyn_affine_signals(self)
    }
    fn signal_reads(&self) -> &[bool] {
        DynModel::dyn_signal_reads(self)
    }
    fn explicit_omega(&self) -> bool {
        DynModel::dyn_explicit_omega(self)
    }
    fn residual<D: Scalar>(
        &self,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        D::residual_of(self, params, omega, phase, signals, out)
    }
    fn output_values<D: Scalar>(
        &self,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        D::output_values_of(self, params, omega, phase, signals, out)
    }
    fn check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error> {
        DynModel::dyn_check_coefficients(self, params, omega)
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        DynModel::dyn_set_param(self, name, value)
    }
    fn validate(&self) -> Result<(), Error> {
        DynModel::dyn_validate(self)
    }
}

/// The methods of [`Model`] that describe the equations (all but the parameter
/// values), forwarded to the `&dyn DynModel` that `$inner` names: how a handle or a
/// view of a model is a [`Model`] itself.
macro_rules! forward_equations {
    ($self:ident => $inner:expr) => {
        fn name(&$self) -> &str {
            Model::name($inner)
        }
        fn description(&$self) -> &str {
            Model::description($inner)
        }
        fn dofs(&$self) -> &[Text] {
            Model::dofs($inner)
        }
        fn params_info(&$self) -> &[ParamInfo] {
            Model::params_info($inner)
        }
        fn signals(&$self) -> &[Signal] {
            Model::signals($inner)
        }
        fn outputs(&$self) -> &[Output] {
            Model::outputs($inner)
        }
        fn output_signals(&$self) -> &[Signal] {
            Model::output_signals($inner)
        }
        fn output_degree(&$self) -> usize {
            Model::output_degree($inner)
        }
        fn outputs_smooth(&$self) -> bool {
            Model::outputs_smooth($inner)
        }
        fn degree(&$self) -> usize {
            Model::degree($inner)
        }
        fn smooth(&$self) -> bool {
            Model::smooth($inner)
        }
        fn max_forcing_harmonic(&$self) -> usize {
            Model::max_forcing_harmonic($inner)
        }
        fn parametric_harmonic(&$self) -> usize {
            Model::parametric_harmonic($inner)
        }
        fn equations(&$self) -> &[Text] {
            Model::equations($inner)
        }
        fn affine_signals(&$self) -> &[bool] {
            Model::affine_signals($inner)
        }
        fn signal_reads(&$self) -> &[bool] {
            Model::signal_reads($inner)
        }
        fn explicit_omega(&$self) -> bool {
            Model::explicit_omega($inner)
        }
        fn residual<D: Scalar>(
            &$self,
            params: &[D],
            omega: D,
            phase: f64,
            signals: &[D],
            out: &mut [D],
        ) {
            Model::residual($inner, params, omega, phase, signals, out)
        }
        fn output_values<D: Scalar>(
            &$self,
            params: &[D],
            omega: D,
            phase: f64,
            signals: &[D],
            out: &mut [D],
        ) {
            Model::output_values($inner, params, omega, phase, signals, out)
        }
        fn check_coefficients(&$self, params: &[f64], omega: f64) -> Result<(), Error> {
            Model::check_coefficients($inner, params, omega)
        }
    };
}
pub(super) use forward_equations;

impl Model for BoxedModel {
    forward_equations!(self => self.as_dyn());
    fn aft_samples(&self) -> Option<usize> {
        Model::aft_samples(self.as_dyn())
    }
    fn param_value(&self, index: usize) -> f64 {
        Model::param_value(self.as_dyn(), index)
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        Model::set_param_value(self.as_dyn_mut(), index, value)
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        Model::set_param(self.as_dyn_mut(), name, value)
    }
    fn validate(&self) -> Result<(), Error> {
        Model::validate(self.as_dyn())
    }
}

/// Each scalar type's residual and output methods of a [`DynModel`] (public in a
/// private module: [`Scalar`] is sealed).
pub trait Dispatch: Sized {
    /// Call the residual method of `model` for this scalar type.
    fn residual_of(
        model: &dyn DynModel,
        p: &[Self],
        omega: Self,
        phase: f64,
        s: &[Self],
        out: &mut [Self],
    );
    /// Call the output method of `model` for this scalar type.
    fn output_values_of(
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
    fn output_values_of(
        model: &dyn DynModel,
        p: &[f64],
        omega: f64,
        phase: f64,
        s: &[f64],
        out: &mut [f64],
    ) {
        model.output_values_f64(p, omega, phase, s, out)
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
    fn output_values_of(
        model: &dyn DynModel,
        p: &[Self],
        omega: Self,
        phase: f64,
        s: &[Self],
        out: &mut [Self],
    ) {
        model.output_values_dual(p, omega, phase, s, out)
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
    fn output_values_of(
        model: &dyn DynModel,
        p: &[Self],
        omega: Self,
        phase: f64,
        s: &[Self],
        out: &mut [Self],
    ) {
        model.output_values_hyper_dual(p, omega, phase, s, out)
    }
}
