//! A model with parameter values of its own: [`WithParams`].

use super::boxed::forward_equations;
use super::{DynModel, Model, Output, ParamInfo, Scalar, Signal, Text};
use crate::error::Error;

/// `base` with its own copy of the parameter values, changed without touching (or
/// cloning) `base`: how an analysis runs a model at another parameter value (the
/// ends of a fold-curve range, each curve of a family). The residual receives the
/// parameters as an argument, so the copy is all the solvers read;
/// [`Model::validate`] checks the copy.
///
/// ```
/// use ihbm::model::{Model, WithParams};
/// use ihbm::models::Duffing;
///
/// let duffing = Duffing::default();
/// let mut stiff = WithParams::new(&duffing);
/// stiff.set_param("k3", 2.0).unwrap();
/// assert_eq!(stiff.param("k3").unwrap(), 2.0);
/// assert_eq!(duffing.param("k3").unwrap(), Duffing::default().k3);
/// ```
#[derive(Clone)]
pub struct WithParams<'a> {
    base: &'a dyn DynModel,
    values: Vec<f64>,
}

impl<'a> WithParams<'a> {
    /// `base` with a copy of its current parameter values.
    pub fn new(base: &'a dyn DynModel) -> Self {
        let values = (0..base.params_info().len()).map(|i| base.param_value(i)).collect();
        WithParams { base, values }
    }

    /// `base` with parameter `index` set to `value` (not checked: see
    /// [`Model::validate`]).
    pub fn with(base: &'a dyn DynModel, index: usize, value: f64) -> Self {
        let mut m = WithParams::new(base);
        m.set_param_value(index, value);
        m
    }
}

impl std::fmt::Debug for WithParams<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WithParams")
            .field("model", &Model::name(self.base))
            .field("values", &self.values)
            .finish()
    }
}

impl Model for WithParams<'_> {
    forward_equations!(self => self.base);
    fn aft_samples(&self) -> Option<usize> {
        Model::aft_samples(self.base)
    }
    fn param_value(&self, index: usize) -> f64 {
        self.values[index]
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        self.values[index] = value;
    }
}
