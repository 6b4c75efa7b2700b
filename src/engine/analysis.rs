//! One value per analysis the application runs, and one per result: the command line
//! parses into an [`Analysis`], a study turns each job of a figure into one, Python
//! builds one from its keywords; [`NamedModel::run`](super::registry::NamedModel::run)
//! runs it against any model and gives an [`Outcome`]. While it runs, one observer
//! trait ([`Watch`]) sees what every kind of analysis has traced so far
//! ([`Progress`]), shows it and may stop it.
//!
//! The checks of what a caller typed are made here once ([`Analysis::check`]) and
//! worded with the caller's own names ([`ArgNames`]: flags, Python keywords).
//!
//! ```
//! use ihbm::engine::analysis::{Analysis, Outcome, Progress};
//! use ihbm::engine::registry::Registry;
//! use ihbm::engine::{ArgNames, SweepSettings};
//! use ihbm::continuation::Control;
//!
//! let model = Registry::builtin().get("duffing").unwrap();
//! let sweep = Analysis::Sweep {
//!     from: 0.5,
//!     to: 2.5,
//!     settings: SweepSettings { harmonics: 3, ..Default::default() },
//! };
//! // Stop after ten points: what was traced is the outcome.
//! let mut watch = |p: &Progress| if p.points() < 10 { Control::Continue } else { Control::Stop };
//! let Outcome::Curve(c) = model.run(&sweep, &ArgNames::CLI, &mut watch).unwrap() else {
//!     unreachable!()
//! };
//! assert_eq!((c.model.as_str(), c.points.len()), ("duffing", 10));
//! ```

use super::{check_omega, ArgNames, BackboneSettings, SimSettings, SolveSettings};
use super::{SweepBackbone, SweepSettings};
use crate::backbone::{Backbone, BackboneEvent, Cycle, CycleFamily, FamilyEvent, FamilyOptions};
use crate::bifurcation::{self, Boundary, FoldCurves, FoldEvent, PeriodDoubled, SymmetryBroken};
use crate::continuation::{self, Control, Event, SweepOptions, Trace};
use crate::error::Result;
use crate::model::{DynModel, Model};
use crate::results::{Curve, SimRecord, SolveRecord};
use crate::timedomain::CompareRow;

/// What to compute. Each variant holds what its user gives, as a user gives it
/// (parameters by name, settings with their defaults unset).
#[derive(Debug, Clone, PartialEq)]
pub enum Analysis {
    /// The periodic solution at one frequency, from the linearised guess.
    Solve {
        /// Forcing frequency, rad/s.
        omega: f64,
        /// Harmonics.
        settings: SolveSettings,
    },
    /// The amplitude–frequency curve from `from` to `to` (rad/s).
    Sweep {
        /// First frequency.
        from: f64,
        /// Last frequency.
        to: f64,
        /// Harmonics and continuation settings.
        settings: SweepSettings,
    },
    /// The period-1 curve and the period-2 branches switched onto at its period
    /// doublings ([`bifurcation::period_two`]); the harmonics count those of Ω/2.
    PeriodTwo {
        /// First frequency.
        from: f64,
        /// Last frequency.
        to: f64,
        /// Harmonics and continuation settings.
        settings: SweepSettings,
    },
    /// A symmetric curve and the branch that breaks its symmetry at its first branch
    /// point ([`bifurcation::break_symmetry`]).
    BreakSymmetry {
        /// First frequency.
        from: f64,
        /// Last frequency.
        to: f64,
        /// Harmonics and continuation settings.
        settings: SweepSettings,
    },
    /// The response at a fixed frequency as one parameter goes from `from` to `to`.
    SweepParam {
        /// The parameter's name.
        param: String,
        /// First value.
        from: f64,
        /// Last value.
        to: f64,
        /// The fixed forcing frequency, rad/s.
        omega: f64,
        /// Harmonics and continuation settings.
        settings: SweepSettings,
    },
    /// The fold (period-doubling, torus) curves in the plane of Ω and one parameter,
    /// and their cusps.
    Folds {
        /// The parameter's name.
        param: String,
        /// First value.
        from: f64,
        /// Last value.
        to: f64,
        /// The frequency range whose folds are continued, rad/s.
        omega: (f64, f64),
        /// What the curves follow.
        boundary: Boundary,
        /// Harmonics and continuation settings.
        settings: SweepSettings,
    },
    /// The backbone (nonlinear mode) of one mode.
    Backbone(BackboneSettings),
    /// The backbones drawn over a sweep: every mode with its linear frequency in
    /// `range`, each continued in every output to `tops[output]`
    /// (each as [`Analysis::Backbone`] would).
    Backbones {
        /// The frequency range, rad/s.
        range: (f64, f64),
        /// The amplitude each output's backbone is continued to (0: not continued).
        tops: Vec<f64>,
        /// Harmonics.
        harmonics: usize,
    },
    /// The limit cycle of an autonomous model near a frequency guess.
    Cycle {
        /// The guess, rad/s.
        omega: f64,
        /// Harmonics.
        harmonics: usize,
    },
    /// A limit cycle continued in a parameter, with its Hopf point.
    Cycles(FamilyOptions),
    /// Time integration from rest.
    Simulate {
        /// Forcing frequency, rad/s.
        omega: f64,
        /// Step, length and scheme.
        settings: SimSettings,
    },
    /// Harmonic balance against time integration at one frequency.
    Compare {
        /// Forcing frequency, rad/s.
        omega: f64,
        /// The integration's settings.
        sim: SimSettings,
        /// Harmonics of the balance.
        harmonics: usize,
    },
}

/// What an [`Analysis`] gave, by kind.
#[derive(Debug)]
pub enum Outcome {
    /// Of [`Analysis::Solve`].
    Solved(SolveRecord),
    /// Of [`Analysis::Sweep`] and [`Analysis::SweepParam`].
    Curve(Curve),
    /// Of [`Analysis::PeriodTwo`].
    PeriodTwo(PeriodDoubled),
    /// Of [`Analysis::BreakSymmetry`].
    BrokenSymmetry(SymmetryBroken),
    /// Of [`Analysis::Folds`].
    Folds(FoldCurves),
    /// Of [`Analysis::Backbone`].
    Backbone(Backbone),
    /// Of [`Analysis::Backbones`].
    Backbones(Vec<SweepBackbone>),
    /// Of [`Analysis::Cycle`].
    Cycle(Cycle),
    /// Of [`Analysis::Cycles`].
    Cycles(CycleFamily),
    /// Of [`Analysis::Simulate`].
    Simulated(SimRecord),
    /// Of [`Analysis::Compare`] (a method's failure is in the row).
    Compared(CompareRow),
}

impl Outcome {
    /// Give every result in it the model's name (the name the model was registered or
    /// read under, which the solvers do not know).
    pub fn set_model(&mut self, name: &str) {
        let name = name.to_string();
        match self {
            Outcome::Solved(r) => r.model = name,
            Outcome::Curve(c) => c.model = name,
            Outcome::PeriodTwo(p) => {
                p.period_one.model = name.clone();
                p.period_two.model = name;
            }
            Outcome::BrokenSymmetry(s) => {
                s.symmetric.model = name.clone();
                s.broken.model = name;
            }
            Outcome::Folds(f) => f.model = name,
            Outcome::Backbone(b) => b.model = name,
            Outcome::Backbones(found) => {
                for b in found.iter_mut().filter_map(|f| f.backbone.as_mut().ok()) {
                    b.model = name.clone();
                }
            }
            Outcome::Cycle(c) => c.model = name,
            Outcome::Cycles(f) => f.model = name,
            Outcome::Simulated(r) => r.model = name,
            Outcome::Compared(_) => {}
        }
    }
}

/// What a running analysis has traced so far, at one of its events.
#[derive(Debug, Clone, Copy)]
pub enum Progress<'a> {
    /// A curve (a frequency or parameter sweep).
    Curve(&'a Event, &'a Trace),
    /// Fold curves.
    Folds(&'a FoldEvent, &'a FoldCurves),
    /// A backbone.
    Backbone(&'a BackboneEvent, &'a Backbone),
    /// A family of limit cycles.
    Cycles(&'a FamilyEvent, &'a CycleFamily),
}

impl Progress<'_> {
    /// Points traced so far.
    pub fn points(&self) -> usize {
        match self {
            Progress::Curve(_, t) => t.points.len(),
            Progress::Folds(_, f) => f.curves.iter().map(|c| c.points.len()).sum(),
            Progress::Backbone(_, b) => b.points.len(),
            Progress::Cycles(_, f) => f.points.len(),
        }
    }

    /// Where the run is: the continuation parameter of the point just accepted (a
    /// curve, fold curves, a family) or the continued output's amplitude (a
    /// backbone); NaN before the first point.
    pub fn value(&self) -> f64 {
        match *self {
            Progress::Curve(e, t) => match *e {
                Event::Point(i) => t.points.get(i),
                _ => t.points.last(),
            }
            .map_or(f64::NAN, |p| p.param),
            Progress::Folds(_, f) => {
                f.curves.iter().rev().find_map(|c| c.points.last()).map_or(f64::NAN, |p| p.value)
            }
            Progress::Backbone(_, b) => {
                let size = b.points.last().and_then(|p| p.outputs.get(b.output));
                size.map_or(f64::NAN, |o| o.max_abs)
            }
            Progress::Cycles(_, f) => f.points.last().map_or(f64::NAN, |p| p.value),
        }
    }
}

/// Sees every event of a running analysis and says whether it goes on: the one
/// observer the command line, a study and Python implement (progress display, Ctrl-C).
/// Closures `FnMut(&Progress) -> Control` are watchers, and so is `()` (it never stops).
pub trait Watch {
    /// See what is traced at one event.
    fn watch(&mut self, progress: &Progress<'_>) -> Control;
}

impl<F: FnMut(&Progress<'_>) -> Control> Watch for F {
    fn watch(&mut self, progress: &Progress<'_>) -> Control {
        self(progress)
    }
}

impl Watch for () {
    fn watch(&mut self, _: &Progress<'_>) -> Control {
        Control::Continue
    }
}

impl Analysis {
    /// What it is, in running text ("sweep", "fold curves"), for messages.
    pub fn noun(&self) -> &'static str {
        match self {
            Analysis::Solve { .. } => "solve",
            Analysis::Sweep { .. } => "sweep",
            Analysis::PeriodTwo { .. } => "period-2 sweep",
            Analysis::BreakSymmetry { .. } => "symmetry-breaking sweep",
            Analysis::SweepParam { .. } => "parameter sweep",
            Analysis::Folds { .. } => "fold curves",
            Analysis::Backbone(_) => "backbone",
            Analysis::Backbones { .. } => "backbones",
            Analysis::Cycle { .. } => "limit cycle",
            Analysis::Cycles(_) => "limit-cycle family",
            Analysis::Simulate { .. } => "time integration",
            Analysis::Compare { .. } => "comparison with time integration",
        }
    }

    /// What a stop before its first event misses, for messages ("interrupted before
    /// the first fold").
    pub fn first(&self) -> &'static str {
        match self {
            Analysis::Folds { .. } => "the first fold",
            Analysis::Backbone(_) => "the first point of the backbone",
            Analysis::Cycles(_) => "the first limit cycle",
            Analysis::Cycle { .. } => "the limit cycle was found",
            Analysis::Solve { .. } | Analysis::Simulate { .. } | Analysis::Compare { .. } => {
                "it finished"
            }
            _ => "the first point",
        }
    }

    /// Whether the result carries Hill's verdicts (a curve stopped part way keeps
    /// the flag).
    pub fn checks_stability(&self) -> bool {
        match self {
            Analysis::Sweep { settings, .. }
            | Analysis::PeriodTwo { settings, .. }
            | Analysis::BreakSymmetry { settings, .. }
            | Analysis::SweepParam { settings, .. } => settings.checks_stability(),
            _ => true,
        }
    }

    /// The checks of what the caller gave, worded with the caller's names: the
    /// frequencies and the continuation settings. (What only the model can judge —
    /// a parameter's name or domain, a mode's number — is checked when it runs.)
    pub fn check(&self, names: &ArgNames) -> Result<()> {
        self.options(names).map(drop)
    }

    /// The checks of [`Analysis::check`], and the continuation options where the
    /// analysis has some.
    fn options(&self, names: &ArgNames) -> Result<Option<SweepOptions>> {
        let sweep = |s: &SweepSettings| s.options().map(Some).map_err(|e| e.named(names.setting));
        match self {
            Analysis::Solve { omega, settings } => {
                check_omega(names.omega, *omega)?;
                crate::fourier::check_harmonics(settings.harmonics)?;
                Ok(None)
            }
            Analysis::Sweep { from, to, settings }
            | Analysis::PeriodTwo { from, to, settings }
            | Analysis::BreakSymmetry { from, to, settings } => {
                check_omega(names.from, *from)?;
                check_omega(names.to, *to)?;
                sweep(settings)
            }
            Analysis::SweepParam { omega, settings, .. } => {
                check_omega(names.omega, *omega)?;
                sweep(settings)
            }
            Analysis::Folds { omega, settings, .. } => {
                check_omega(names.omega_from, omega.0)?;
                check_omega(names.omega_to, omega.1)?;
                sweep(settings)
            }
            Analysis::Simulate { omega, .. } | Analysis::Compare { omega, .. } => {
                check_omega(names.omega, *omega)?;
                Ok(None)
            }
            Analysis::Backbone(_)
            | Analysis::Backbones { .. }
            | Analysis::Cycle { .. }
            | Analysis::Cycles(_) => Ok(None),
        }
    }

    /// Run it on `model` ([`Analysis::check`] first, worded by `names`), every event
    /// shown to `watch`, which may stop it: what was traced is then the outcome, its
    /// open piece ended "stopped". The results carry the model's own name
    /// ([`Outcome::set_model`] renames them).
    pub fn run(
        &self,
        model: &dyn DynModel,
        names: &ArgNames,
        watch: &mut dyn Watch,
    ) -> Result<Outcome> {
        let opts = self.options(names)?;
        let opts = || opts.clone().unwrap_or_default();
        Ok(match self {
            Analysis::Solve { omega, settings } => {
                Outcome::Solved(super::solve(model, *omega, settings)?)
            }
            Analysis::Sweep { from, to, .. } => {
                let mut obs = |e: &Event, t: &Trace| watch.watch(&Progress::Curve(e, t));
                Outcome::Curve(continuation::sweep_with(model, *from, *to, &opts(), &mut obs)?)
            }
            Analysis::PeriodTwo { from, to, .. } => {
                Outcome::PeriodTwo(bifurcation::period_two(model, *from, *to, &opts())?)
            }
            Analysis::BreakSymmetry { from, to, .. } => {
                Outcome::BrokenSymmetry(bifurcation::break_symmetry(model, *from, *to, &opts())?)
            }
            Analysis::SweepParam { param, from, to, omega, .. } => {
                let mut obs = |e: &Event, t: &Trace| watch.watch(&Progress::Curve(e, t));
                let c = continuation::sweep_param_with(
                    model,
                    param,
                    *from,
                    *to,
                    *omega,
                    &opts(),
                    &mut obs,
                )?;
                Outcome::Curve(c)
            }
            Analysis::Folds { param, from, to, omega, boundary, .. } => {
                let index = model.param_index(param)?;
                let fo = bifurcation::FoldCurveOptions {
                    boundary: *boundary,
                    sweep: opts(),
                    omega: *omega,
                };
                let mut obs = |e: &FoldEvent, f: &FoldCurves| watch.watch(&Progress::Folds(e, f));
                Outcome::Folds(bifurcation::fold_curves_with(
                    model, index, *from, *to, &fo, &mut obs,
                )?)
            }
            Analysis::Backbone(s) => {
                let mut obs =
                    |e: &BackboneEvent, b: &Backbone| watch.watch(&Progress::Backbone(e, b));
                Outcome::Backbone(super::backbone(model, s, &mut obs)?)
            }
            Analysis::Backbones { range, tops, harmonics } => {
                Outcome::Backbones(super::sweep_backbones(model, *range, tops, *harmonics))
            }
            Analysis::Cycle { omega, harmonics } => {
                let opts = crate::backbone::CycleOptions {
                    omega: *omega,
                    harmonics: *harmonics,
                    ..Default::default()
                };
                Outcome::Cycle(crate::backbone::cycle(model, &opts)?)
            }
            Analysis::Cycles(opts) => {
                let mut obs =
                    |e: &FamilyEvent, f: &CycleFamily| watch.watch(&Progress::Cycles(e, f));
                Outcome::Cycles(crate::backbone::cycles_with(model, opts, &mut obs)?)
            }
            Analysis::Simulate { omega, settings } => {
                Outcome::Simulated(super::simulate(model, *omega, settings)?)
            }
            Analysis::Compare { omega, sim, harmonics } => {
                Outcome::Compared(super::compare(model, *omega, sim, *harmonics))
            }
        })
    }
}
