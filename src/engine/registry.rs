//! Models registered by name: [`NamedModel`], a model and the name it answers to,
//! and [`Registry`], the models a CLI knows.
//!
//! Every named model holds a [`BoxedModel`] (the model type erased behind the
//! object-safe [`DynModel`](crate::model::DynModel)), so the solvers an
//! [`Analysis`] calls are compiled once for all of them (not once per model type).
//!
use super::analysis::{Analysis, Outcome, Watch};
use super::ArgNames;
use crate::error::{Error, Result};
use crate::model::{BoxedModel, Model, Output, ParamInfo, Text, WithSamples};
use crate::runtime::RuntimeModel;
use std::path::{Path, PathBuf};

/// A model under the name it was registered (or read) under, with its current
/// parameter values, usable without its type. Cloning it copies the parameter values.
#[derive(Debug, Clone)]
pub struct NamedModel {
    name: String,
    model: BoxedModel,
}

impl NamedModel {
    /// Register `model` under `name`.
    pub fn new(name: &str, model: BoxedModel) -> Self {
        NamedModel { name: name.to_string(), model }
    }

    /// Errors name the registered model, not the type's own name.
    fn named(&self, e: Error) -> Error {
        match e {
            Error::UnknownParameter { name, known, .. } => {
                Error::UnknownParameter { name, model: self.name.clone(), known }
            }
            e => e,
        }
    }

    /// The registered name (the CLI's `NAME`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The model's description.
    pub fn description(&self) -> &str {
        self.model.description()
    }

    /// Degrees of freedom.
    pub fn dofs(&self) -> &[Text] {
        self.model.dofs()
    }

    /// Declared parameters.
    pub fn params_info(&self) -> &[ParamInfo] {
        self.model.params_info()
    }

    /// Current value of parameter `i`.
    pub fn param_value(&self, i: usize) -> f64 {
        self.model.param_value(i)
    }

    /// Set a parameter by name (unknown names and non-finite values are errors).
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<()> {
        self.model.set_param(name, value).map_err(|e| self.named(e))
    }

    /// Whether the current values are in the model's domain ([`Model::validate`]).
    pub fn validate(&self) -> Result<()> {
        self.model.validate()
    }

    /// Whether `harmonics` fits in memory: the harmonic balance's Jacobians and, with
    /// `stability`, Hill's matrices (errors name the largest N that fits).
    pub fn check_size(&self, harmonics: usize, stability: bool) -> Result<()> {
        crate::balance::check_size(self.model.dofs().len(), harmonics)?;
        if stability {
            crate::stability::check_size(self.model.as_dyn(), harmonics)?;
        }
        Ok(())
    }

    /// Make every analysis's transform take `samples` samples per forcing period
    /// ([`WithSamples`]), after checking the count at `harmonics` harmonics: at least
    /// `2N + 1`, and for a smooth model at least its alias-free count. `what` names the
    /// setting in the error (`--aft-samples`, `aft_samples`).
    pub fn set_aft_samples(&mut self, samples: usize, harmonics: usize, what: &str) -> Result<()> {
        let model = BoxedModel::new(WithSamples::new(self.model.clone(), samples));
        crate::fourier::check_samples(model.as_dyn(), harmonics, 1).map_err(|e| match e {
            Error::InvalidValue { value, expected, .. } => {
                Error::InvalidValue { what: what.to_string(), value, expected }
            }
            e => e,
        })?;
        self.model = model;
        Ok(())
    }

    /// The samples per period the transform takes at `harmonics` harmonics (what the
    /// results report as `aft_samples`).
    pub fn samples(&self, harmonics: usize) -> usize {
        crate::fourier::model_sample_count(self.model.as_dyn(), harmonics, 1)
    }

    /// Named outputs.
    pub fn outputs(&self) -> &[Output] {
        self.model.outputs()
    }

    /// Equations as text.
    pub fn equations(&self) -> &[Text] {
        self.model.equations()
    }

    /// Run `analysis` on this model ([`Analysis::run`]): checked with the caller's
    /// `names`, every event shown to `watch` (which may stop it), its results and
    /// errors naming the model as registered.
    pub fn run(
        &self,
        analysis: &Analysis,
        names: &ArgNames,
        watch: &mut dyn Watch,
    ) -> Result<Outcome> {
        let mut outcome =
            analysis.run(self.model.as_dyn(), names, watch).map_err(|e| self.named(e))?;
        outcome.set_model(&self.name);
        Ok(outcome)
    }
}

/// The models a CLI knows, in registration order.
#[derive(Default)]
pub struct Registry {
    entries: Vec<NamedModel>,
}

impl Registry {
    /// Register `M::default()` under `name` (a later registration of the same name
    /// replaces the earlier one).
    pub fn add<M: Model + Default + Clone + 'static>(&mut self, name: &str) {
        self.add_boxed(name, BoxedModel::new(M::default()));
    }

    /// Every built-in model ([`crate::models::builtin`]), under its own name.
    pub fn builtin() -> Self {
        let mut reg = Registry::default();
        for model in crate::models::builtin() {
            let name = model.name().to_string();
            reg.add_boxed(&name, model);
        }
        reg
    }

    /// Register `model` (with its current parameter values) under `name`, replacing
    /// an earlier registration of the name.
    pub fn add_boxed(&mut self, name: &str, model: BoxedModel) {
        self.entries.retain(|e| e.name() != name);
        self.entries.push(NamedModel::new(name, model));
    }

    /// Registered names, in order.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name()).collect()
    }

    /// All entries.
    pub fn entries(&self) -> &[NamedModel] {
        &self.entries
    }

    /// A fresh copy (default parameters) of the model called `name`, or the model
    /// read from `name` when it is the path of a model file (see [`is_model_file`]).
    pub fn get(&self, name: &str) -> Result<NamedModel> {
        self.get_in(name, None)
    }

    /// [`Registry::get`], a relative model-file path taken from `dir` (a study file's
    /// directory) when given.
    pub fn get_in(&self, name: &str, dir: Option<&Path>) -> Result<NamedModel> {
        if is_model_file(name) {
            let path = match dir {
                Some(d) if Path::new(name).is_relative() => d.join(name),
                _ => PathBuf::from(name),
            };
            let model = RuntimeModel::from_file(&path)?;
            let own = model.name().to_string();
            return Ok(NamedModel::new(&own, BoxedModel::new(model)));
        }
        self.entries.iter().find(|e| e.name() == name).cloned().ok_or_else(|| Error::UnknownModel {
            name: name.to_string(),
            known: self.names().join(", "),
        })
    }
}

/// Whether a model name is the path of a model file: it ends in `.ihbm` or names a
/// directory (`./m`, `dir/m`). Registered names are kebab-case words, so no name is
/// both.
pub fn is_model_file(name: &str) -> bool {
    name.ends_with(".ihbm") || name.contains('/') || name.contains(std::path::MAIN_SEPARATOR)
}
