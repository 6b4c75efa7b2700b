//! Continuation settings as a user writes them — the `sweep` / `sweep-param` flags or
//! a study's `sweep` table — parsed and checked in one place and turned into
//! [`SweepOptions`]. Both front ends name a bad setting their own way (`--max-step`,
//! `sweep.max_step`) from the same [`SettingError`].
//!
//! ```
//! use ihbm::continuation::AmplitudeBound;
//! use ihbm::engine::settings::SweepSettings;
//! let s = SweepSettings { harmonics: 3, max_step: Some(0.02), ..Default::default() };
//! let o = s.options().unwrap();
//! // The unspecified first step shrinks to fit under the given largest step.
//! assert_eq!((o.harmonics, o.max_step, o.initial_step), (3, 0.02, 0.01));
//! assert_eq!("rel:1e3".parse::<AmplitudeBound>(), Ok(AmplitudeBound::Relative(1e3)));
//! let bad = SweepSettings { min_step: Some(0.5), max_step: Some(0.1), ..Default::default() };
//! assert_eq!(bad.options().unwrap_err().cli().to_string(),
//!            "invalid --min-step: 0.5 (expected at most --max-step (0.1))");
//! ```

use crate::continuation::{AmplitudeBound, ConvergenceOptions, Predictor, SweepOptions};
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// Settings of a continuation run; `None` keeps the solver's default
/// ([`SweepOptions::default`]). Steps are in the solver's scaled arc length, where the
/// parameter range and the linearised response both have length 1.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSettings {
    /// Number of harmonics N (>= 1; not a key of the `sweep` table).
    #[serde(skip)]
    pub harmonics: usize,
    /// First step.
    pub initial_step: Option<f64>,
    /// Smallest step before a segment is declared stalled.
    pub min_step: Option<f64>,
    /// Largest step.
    pub max_step: Option<f64>,
    /// Corrector (Newton) tolerance on the scaled step.
    pub tol: Option<f64>,
    /// Predictor direction.
    pub predictor: Option<Predictor>,
    /// When a branch counts as running away (a number means `abs:`).
    pub amplitude_bound: Option<AmplitudeBound>,
    /// Cap on the accepted continuation steps.
    pub max_steps: Option<usize>,
    /// Hill stability of every point (`false` skips it).
    pub stability: Option<bool>,
    /// Harmonic convergence: rerun with N, N+2, ... until peaks and folds change by
    /// less than this relative tolerance.
    pub converge: Option<f64>,
}

/// A setting out of range. `key` is the study-file key (`max_step`); [`Self::flag`]
/// gives the command-line flag.
#[derive(Debug, Clone, PartialEq)]
pub struct SettingError {
    /// The setting, as a study-file key.
    pub key: &'static str,
    /// Its value, as given.
    pub value: String,
    /// What it must be; may name another setting (see [`Expected`]).
    pub expected: Expected,
}

/// What a setting must be.
#[derive(Debug, Clone, PartialEq)]
pub enum Expected {
    /// A fixed description.
    Text(&'static str),
    /// At most the value of another setting (its key and value).
    AtMost(&'static str, f64),
}

/// The command-line flag of a study-file key: `max_step` -> `--max-step`.
pub fn flag(key: &str) -> String {
    match key {
        "stability" => "--no-stability".to_string(),
        k => format!("--{}", k.replace('_', "-")),
    }
}

impl SettingError {
    /// The command-line flag of the setting.
    pub fn flag(&self) -> String {
        flag(self.key)
    }

    /// What was expected, naming other settings with `name`.
    pub fn expected_with(&self, name: impl Fn(&str) -> String) -> String {
        match &self.expected {
            Expected::Text(t) => t.to_string(),
            Expected::AtMost(k, v) => format!("at most {} ({v})", name(k)),
        }
    }

    /// The error as the command line reports it (`invalid --max-step: ...`).
    pub fn cli(&self) -> Error {
        self.named(flag)
    }

    /// The error with every setting named by `name` (from its study-file key): `flag`
    /// for the command line, the key itself for Python's keywords.
    pub fn named(&self, name: fn(&str) -> String) -> Error {
        Error::InvalidValue {
            what: name(self.key),
            value: self.value.clone(),
            expected: self.expected_with(name),
        }
    }

    /// The message as a study file reports it (`sweep.max_step = ...`).
    pub fn study(&self) -> String {
        format!(
            "sweep.{} = {}: expected {}",
            self.key,
            self.value,
            self.expected_with(|k| format!("sweep.{k}"))
        )
    }
}

fn positive(key: &'static str, v: Option<f64>) -> Result<Option<f64>, SettingError> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => Err(SettingError {
            key,
            value: x.to_string(),
            expected: Expected::Text("a finite number > 0"),
        }),
        _ => Ok(v),
    }
}

impl SweepSettings {
    /// Check every given setting and build the solver's options. Unspecified steps
    /// adapt to the given ones (a `max_step` below the default first step lowers the
    /// first step), so only the settings the user gave can conflict.
    pub fn options(&self) -> Result<SweepOptions, SettingError> {
        let d = SweepOptions::default();
        let min = positive("min_step", self.min_step)?;
        let init = positive("initial_step", self.initial_step)?;
        let max = positive("max_step", self.max_step)?;
        let tol = positive("tol", self.tol)?;
        let converge = positive("converge", self.converge)?;
        if self.max_steps == Some(0) {
            return Err(SettingError {
                key: "max_steps",
                value: "0".into(),
                expected: Expected::Text("at least 1"),
            });
        }
        let order = [("min_step", min), ("initial_step", init), ("max_step", max)];
        for (i, &(ka, a)) in order.iter().enumerate() {
            for &(kb, b) in &order[i + 1..] {
                if let (Some(a), Some(b)) = (a, b) {
                    if a > b {
                        return Err(SettingError {
                            key: ka,
                            value: a.to_string(),
                            expected: Expected::AtMost(kb, b),
                        });
                    }
                }
            }
        }
        let min_step = min.unwrap_or(d.min_step.min(init.or(max).unwrap_or(f64::INFINITY)));
        let max_step = max.unwrap_or(d.max_step.max(init.or(min).unwrap_or(0.0)));
        let initial_step = init.unwrap_or(d.initial_step.max(min_step).min(max_step));
        let convergence = converge.map(|tol| {
            let c = ConvergenceOptions::default();
            // At least two levels above the starting N, whatever N is.
            let max_harmonics = c.max_harmonics.max(self.harmonics + 2 * c.increment);
            ConvergenceOptions { tol, max_harmonics, ..c }
        });
        Ok(SweepOptions {
            harmonics: self.harmonics,
            initial_step,
            min_step,
            max_step,
            tol: tol.unwrap_or(d.tol),
            predictor: self.predictor.unwrap_or(d.predictor),
            max_steps: self.max_steps.unwrap_or(d.max_steps),
            amplitude_bound: self.amplitude_bound.unwrap_or(d.amplitude_bound),
            stability: self.stability_options(),
            convergence,
            ..d
        })
    }

    /// The stability options of the sweep: the default ones unless switched off.
    fn stability_options(&self) -> Option<crate::stability::StabilityOptions> {
        if self.stability == Some(false) {
            None
        } else {
            SweepOptions::default().stability
        }
    }

    /// Whether the sweep checks the stability of its points.
    pub fn checks_stability(&self) -> bool {
        self.stability_options().is_some()
    }

    /// These settings with the ones `over` gives replacing them (a study figure's
    /// `sweep` table over the study's).
    pub fn merged(&self, over: Option<&SweepSettings>) -> SweepSettings {
        let mut s = self.clone();
        if let Some(o) = over {
            s.initial_step = o.initial_step.or(s.initial_step);
            s.min_step = o.min_step.or(s.min_step);
            s.max_step = o.max_step.or(s.max_step);
            s.tol = o.tol.or(s.tol);
            s.predictor = o.predictor.or(s.predictor);
            s.amplitude_bound = o.amplitude_bound.or(s.amplitude_bound);
            s.max_steps = o.max_steps.or(s.max_steps);
            s.stability = o.stability.or(s.stability);
            s.converge = o.converge.or(s.converge);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_parse_and_print_round_trip() {
        for (s, b) in [
            ("rel:1e3", AmplitudeBound::Relative(1e3)),
            ("abs:0.5", AmplitudeBound::Absolute(0.5)),
            ("ABS: 2", AmplitudeBound::Absolute(2.0)),
            ("0.25", AmplitudeBound::Absolute(0.25)),
            ("none", AmplitudeBound::None),
        ] {
            assert_eq!(s.parse::<AmplitudeBound>(), Ok(b), "{s}");
            assert_eq!(b.to_string().parse::<AmplitudeBound>(), Ok(b));
        }
        for s in ["rel:", "rel:-1", "abs:0", "abs:inf", "max:3", "x", ""] {
            assert!(s.parse::<AmplitudeBound>().is_err(), "{s}");
        }
    }

    #[test]
    fn defaults_are_the_solvers() {
        let o = SweepSettings { harmonics: 5, ..Default::default() }.options().unwrap();
        assert_eq!(o, SweepOptions::default());
    }

    #[test]
    fn unspecified_steps_fit_around_given_ones() {
        let d = SweepOptions::default();
        let o = SweepSettings { initial_step: Some(0.5), ..Default::default() }.options().unwrap();
        assert_eq!((o.min_step, o.initial_step, o.max_step), (d.min_step, 0.5, 0.5));
        let o = SweepSettings { max_step: Some(1e-7), ..Default::default() }.options().unwrap();
        assert_eq!((o.min_step, o.initial_step, o.max_step), (1e-7, 1e-7, 1e-7));
        let o = SweepSettings { min_step: Some(0.2), ..Default::default() }.options().unwrap();
        assert_eq!((o.min_step, o.initial_step, o.max_step), (0.2, 0.2, 0.2));
    }

    #[test]
    fn bad_settings_name_the_setting_and_value() {
        let e = SweepSettings { tol: Some(-1.0), ..Default::default() }.options().unwrap_err();
        assert_eq!(e.cli().to_string(), "invalid --tol: -1 (expected a finite number > 0)");
        assert_eq!(e.study(), "sweep.tol = -1: expected a finite number > 0");
        let e =
            SweepSettings { initial_step: Some(0.3), max_step: Some(0.2), ..Default::default() }
                .options()
                .unwrap_err();
        assert_eq!(e.study(), "sweep.initial_step = 0.3: expected at most sweep.max_step (0.2)");
        let e = SweepSettings { max_steps: Some(0), ..Default::default() }.options().unwrap_err();
        assert_eq!(e.flag(), "--max-steps");
        let e = SweepSettings { converge: Some(f64::NAN), ..Default::default() }.options();
        assert_eq!(e.unwrap_err().flag(), "--converge");
    }

    #[test]
    fn a_front_end_names_the_settings_its_own_way() {
        let bad = SweepSettings { min_step: Some(0.5), max_step: Some(0.1), ..Default::default() };
        let e = bad.options().unwrap_err();
        assert_eq!(
            e.named(|k| k.to_string()).to_string(),
            "invalid min_step: 0.5 (expected at most max_step (0.1))"
        );
        assert_eq!(e.named(flag).to_string(), e.cli().to_string());
    }
}
