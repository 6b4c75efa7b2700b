//! Models registered by name, behind an object-safe trait.
//!
//! Every registered model is held as a [`BoxedModel`], so the solvers behind
//! [`AnyModel`] are compiled once for all of them (not once per model type).
//!
use super::{
    self as engine, BackboneSettings, FoldRange, ParamRange, SimSettings, SolveSettings,
    SweepBackbone, SweepSettings,
};
use crate::backbone::{Backbone, Cycle, CycleFamily, FamilyOptions};
use crate::bifurcation::{FoldCurves, FoldEvent, PeriodDoubled, SymmetryBroken};
use crate::continuation::{Control, Observer};
use crate::error::{Error, Result};
use crate::model::{BoxedModel, Model, Output, ParamInfo, Text};
use crate::results::{Curve, SimRecord, SolveRecord};
use crate::runtime::RuntimeModel;
use crate::timedomain::CompareRow;
use std::path::{Path, PathBuf};

/// A registered model with its current parameter values, usable without its type.
pub trait AnyModel: Send + Sync {
    /// The registered name (the CLI's `NAME`).
    fn name(&self) -> &str;
    /// The model's description.
    fn description(&self) -> &str;
    /// Degrees of freedom.
    fn dofs(&self) -> &[Text];
    /// Declared parameters.
    fn params_info(&self) -> &[ParamInfo];
    /// Current value of parameter `i`.
    fn param_value(&self, i: usize) -> f64;
    /// Set a parameter by name (unknown names and non-finite values are errors).
    fn set_param(&mut self, name: &str, value: f64) -> Result<()>;
    /// Whether the current values are in the model's domain ([`Model::validate`]).
    fn validate(&self) -> Result<()>;
    /// Whether `harmonics` fits in memory: the harmonic balance's Jacobians and, with
    /// `stability`, Hill's matrices (errors name the largest N that fits).
    fn check_size(&self, harmonics: usize, stability: bool) -> Result<()>;
    /// Named outputs.
    fn outputs(&self) -> &[Output];
    /// Equations as text.
    fn equations(&self) -> &[Text];
    /// Solve at one frequency.
    fn solve(&self, omega: f64, s: &SolveSettings) -> Result<SolveRecord>;
    /// Trace a frequency sweep.
    fn sweep(&self, from: f64, to: f64, s: &SweepSettings, obs: &mut dyn Observer)
        -> Result<Curve>;
    /// The period-2 branch, switched onto at a period doubling of the period-1 curve.
    fn sweep_period_two(&self, from: f64, to: f64, s: &SweepSettings) -> Result<PeriodDoubled>;
    /// The branch that breaks the curve's symmetry, switched onto at a branch point.
    fn sweep_break_symmetry(&self, from: f64, to: f64, s: &SweepSettings)
        -> Result<SymmetryBroken>;
    /// Trace the response at a fixed frequency as one parameter moves.
    fn sweep_param(
        &self,
        r: &ParamRange,
        s: &SweepSettings,
        obs: &mut dyn Observer,
    ) -> Result<Curve>;
    /// The fold curves in the plane of Ω and one parameter, and their cusps.
    fn fold_curves(
        &self,
        r: &FoldRange,
        s: &SweepSettings,
        obs: &mut dyn FnMut(&FoldEvent, &FoldCurves) -> Control,
    ) -> Result<FoldCurves>;
    /// The backbone (nonlinear mode) of one mode.
    fn backbone(&self, s: &BackboneSettings) -> Result<Backbone>;
    /// The backbones of the modes in `[range.0, range.1]`, each output's continued to
    /// `tops[output]` ([`engine::sweep_backbones`]).
    fn sweep_backbones(
        &self,
        range: (f64, f64),
        tops: &[f64],
        harmonics: usize,
    ) -> Vec<SweepBackbone>;
    /// The limit cycle near a frequency guess.
    fn cycle(&self, omega: f64, harmonics: usize) -> Result<Cycle>;
    /// The limit cycle continued in a parameter, with its Hopf point.
    fn cycles(&self, opts: &FamilyOptions) -> Result<CycleFamily>;
    /// Integrate in time.
    fn simulate(&self, omega: f64, s: &SimSettings) -> Result<SimRecord>;
    /// Harmonic balance against time integration at one frequency.
    fn compare(&self, omega: f64, s: &SimSettings, harmonics: usize) -> CompareRow;
    /// A copy with the same parameter values.
    fn clone_box(&self) -> Box<dyn AnyModel>;
}

/// A model registered under a name.
#[derive(Debug, Clone)]
pub struct Registered {
    name: String,
    model: BoxedModel,
}

impl Registered {
    /// Register `model` under `name`.
    pub fn new(name: &str, model: BoxedModel) -> Self {
        Registered { name: name.to_string(), model }
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
}

impl AnyModel for Registered {
    fn name(&self) -> &str {
        &self.name
    }
    fn description(&self) -> &str {
        self.model.description()
    }
    fn dofs(&self) -> &[Text] {
        self.model.dofs()
    }
    fn params_info(&self) -> &[ParamInfo] {
        self.model.params_info()
    }
    fn param_value(&self, i: usize) -> f64 {
        self.model.param_value(i)
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<()> {
        self.model.set_param(name, value).map_err(|e| self.named(e))
    }
    fn validate(&self) -> Result<()> {
        self.model.validate()
    }
    fn check_size(&self, harmonics: usize, stability: bool) -> Result<()> {
        crate::balance::check_size(self.model.dofs().len(), harmonics)?;
        if stability {
            crate::stability::check_size(&self.model, harmonics)?;
        }
        Ok(())
    }
    fn outputs(&self) -> &[Output] {
        self.model.outputs()
    }
    fn equations(&self) -> &[Text] {
        self.model.equations()
    }
    fn solve(&self, omega: f64, s: &SolveSettings) -> Result<SolveRecord> {
        engine::solve(&self.name, &self.model, omega, s)
    }
    fn sweep(
        &self,
        from: f64,
        to: f64,
        s: &SweepSettings,
        obs: &mut dyn Observer,
    ) -> Result<Curve> {
        let mut c = engine::sweep(&self.name, &self.model, from, to, s, obs)?;
        c.model = self.name.clone();
        Ok(c)
    }
    fn sweep_period_two(&self, from: f64, to: f64, s: &SweepSettings) -> Result<PeriodDoubled> {
        engine::sweep_period_two(&self.name, &self.model, from, to, s)
    }
    fn sweep_break_symmetry(
        &self,
        from: f64,
        to: f64,
        s: &SweepSettings,
    ) -> Result<SymmetryBroken> {
        engine::sweep_break_symmetry(&self.name, &self.model, from, to, s)
    }
    fn sweep_param(
        &self,
        r: &ParamRange,
        s: &SweepSettings,
        obs: &mut dyn Observer,
    ) -> Result<Curve> {
        engine::sweep_param(&self.name, &self.model, r, s, obs).map_err(|e| self.named(e))
    }
    fn fold_curves(
        &self,
        r: &FoldRange,
        s: &SweepSettings,
        obs: &mut dyn FnMut(&FoldEvent, &FoldCurves) -> Control,
    ) -> Result<FoldCurves> {
        engine::fold_curves(&self.name, &self.model, r, s, obs).map_err(|e| self.named(e))
    }
    fn backbone(&self, s: &BackboneSettings) -> Result<Backbone> {
        engine::backbone(&self.name, &self.model, s).map_err(|e| self.named(e))
    }
    fn cycle(&self, omega: f64, harmonics: usize) -> Result<Cycle> {
        let opts = crate::backbone::CycleOptions { omega, harmonics, ..Default::default() };
        let mut c = crate::backbone::cycle(&self.model, &opts).map_err(|e| self.named(e))?;
        c.model = self.name.clone();
        Ok(c)
    }
    fn sweep_backbones(
        &self,
        range: (f64, f64),
        tops: &[f64],
        harmonics: usize,
    ) -> Vec<SweepBackbone> {
        engine::sweep_backbones(&self.name, &self.model, range, tops, harmonics)
    }
    fn cycles(&self, opts: &FamilyOptions) -> Result<CycleFamily> {
        let mut f = crate::backbone::cycles(&self.model, opts).map_err(|e| self.named(e))?;
        f.model = self.name.clone();
        Ok(f)
    }
    fn simulate(&self, omega: f64, s: &SimSettings) -> Result<SimRecord> {
        engine::simulate(&self.name, &self.model, omega, s)
    }
    fn compare(&self, omega: f64, s: &SimSettings, harmonics: usize) -> CompareRow {
        engine::compare(&self.model, omega, s, harmonics)
    }
    fn clone_box(&self) -> Box<dyn AnyModel> {
        Box::new(self.clone())
    }
}

/// The models a CLI knows, in registration order.
#[derive(Default)]
pub struct Registry {
    entries: Vec<Box<dyn AnyModel>>,
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
        self.entries.push(Box::new(Registered::new(name, model)));
    }

    /// Registered names, in order.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name()).collect()
    }

    /// All entries.
    pub fn entries(&self) -> &[Box<dyn AnyModel>] {
        &self.entries
    }

    /// A fresh copy (default parameters) of the model called `name`, or the model
    /// read from `name` when it is the path of a model file (see [`is_model_file`]).
    pub fn get(&self, name: &str) -> Result<Box<dyn AnyModel>> {
        self.get_in(name, None)
    }

    /// [`Registry::get`], a relative model-file path taken from `dir` (a study file's
    /// directory) when given.
    pub fn get_in(&self, name: &str, dir: Option<&Path>) -> Result<Box<dyn AnyModel>> {
        if is_model_file(name) {
            let path = match dir {
                Some(d) if Path::new(name).is_relative() => d.join(name),
                _ => PathBuf::from(name),
            };
            let model = RuntimeModel::from_file(&path)?;
            let own = model.name().to_string();
            return Ok(Box::new(Registered::new(&own, BoxedModel::new(model))));
        }
        self.entries.iter().find(|e| e.name() == name).map(|e| e.clone_box()).ok_or_else(|| {
            Error::UnknownModel { name: name.to_string(), known: self.names().join(", ") }
        })
    }
}

/// Whether a model name is the path of a model file: it ends in `.ihbm` or names a
/// directory (`./m`, `dir/m`). Registered names are kebab-case words, so no name is
/// both.
pub fn is_model_file(name: &str) -> bool {
    name.ends_with(".ihbm") || name.contains('/') || name.contains(std::path::MAIN_SEPARATOR)
}
