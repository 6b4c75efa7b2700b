//! A model whose transform takes a sample count of its own: [`WithSamples`].

use super::boxed::forward_equations;
use super::{BoxedModel, Model, Output, ParamInfo, Scalar, Signal, Text};
use crate::error::Error;

/// `inner`, with the transform of every analysis taking `samples` samples per forcing
/// period ([`Model::aft_samples`]) instead of the count the model's shape gives: how
/// `--aft-samples` reaches a non-smooth model, whose terms no count makes alias-free,
/// so that the error's fall with the samples can be measured. The solvers check the
/// count when they set up (at least `2N + 1`, and for a smooth model at least its
/// alias-free count).
///
/// ```
/// use ihbm::model::{BoxedModel, Model, WithSamples};
/// use ihbm::models::Duffing;
/// let m = WithSamples::new(BoxedModel::new(Duffing::default()), 64);
/// assert_eq!(m.aft_samples(), Some(64));
/// assert_eq!(m.name(), "duffing");
/// ```
#[derive(Debug, Clone)]
pub struct WithSamples {
    inner: BoxedModel,
    samples: usize,
}

impl WithSamples {
    /// `inner` with `samples` samples per forcing period.
    pub fn new(inner: BoxedModel, samples: usize) -> Self {
        WithSamples { inner, samples }
    }
}

impl Model for WithSamples {
    forward_equations!(self => self.inner.as_dyn());
    fn param_value(&self, index: usize) -> f64 {
        Model::param_value(self.inner.as_dyn(), index)
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        Model::set_param_value(self.inner.as_dyn_mut(), index, value)
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), Error> {
        Model::set_param(self.inner.as_dyn_mut(), name, value)
    }
    fn validate(&self) -> Result<(), Error> {
        Model::validate(self.inner.as_dyn())
    }
    fn aft_samples(&self) -> Option<usize> {
        Some(self.samples)
    }
}
