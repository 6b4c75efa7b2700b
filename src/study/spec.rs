//! The study file format (TOML) and its checks.
//!
//! ```toml
//! title = "My study"
//! model = "quarter-car"          # a registered model name, or a model file
//!                                # ("chain.ihbm", relative to this file)
//! harmonics = 5                  # default N for every curve
//! unit = "Hz"                    # frequency axis of figures: "rad/s" (default) or "Hz"
//! outputs = ["z1", "y"]          # panels of every figure (default: all outputs)
//! frequency = { from = 1.0, to = 100.0 }   # rad/s
//! params = { k3 = 3e6 }          # overrides for every figure
//! labels = { z1 = "body displacement max|z1| (m)" }   # y-axis labels
//! sweep = { max_step = 0.5, amplitude_bound = 1.0 }   # continuation settings
//! # sweep keys: initial_step, min_step, max_step, tol, predictor ("tangent" | "secant"),
//! # amplitude_bound ("rel:1e3" | "abs:0.5" | "none" | a number: abs), max_steps,
//! # stability (false skips it), converge (harmonic-convergence tolerance) — the same
//! # settings and checks as the `sweep` command's flags (crate::cli::settings)
//!
//! [[figure]]
//! id = "fig09"                   # file stem: fig09.svg, fig09_k3_1e6.csv, ...
//! title = "Fig. 9: cubic stiffness"
//! claim = "the resonance peak bends to the right as k3 grows"
//! vary = "k3"                    # a parameter, or "harmonics"
//! values = [1e6, 3e6, 5e6]       # one curve per value
//! params = { F = 0.01 }          # figure overrides (after the study's)
//! # model = "half-car"           # another registered model for this figure: it starts
//! #                              # from its own defaults (the study's params and outputs
//! #                              # belong to the study's model); labels cover every model
//! # harmonics, frequency, unit, outputs, sweep: as above, for this figure only
//! timedomain = { omegas = [5.0, 8.0], schemes = ["gl", "bdf2"], periods = 100 }
//! # or, instead of amplitude–frequency curves, fold curves in the (Ω, P) plane (one
//! # analysis per value of `vary`; no checks or timedomain):
//! # folds = { param = "F", from = 0.005, to = 0.2 }
//! # (boundary = "period-doubling" or "torus" in it follows those points instead)
//! backbone = { modes = [1, 2] }  # nonlinear modes over the curves (`true`: every
//! #                              # mode in the frequency range), each continued in a
//! #                              # panel's output to the figure's largest amplitude
//!
//! [[figure.check]]               # a claim checked against the curves
//! kind = "peak_omega"            # peak | peak_omega | folds | converges | timedomain
//! output = "z1"
//! band = [1.0, 30.0]             # rad/s
//! expect = "increasing"          # increasing | decreasing | unchanged | present | absent | agree
//! ```
//!
//! Unknown keys and wrong types are errors naming the file, line and column.
//! Time-domain points use the figure's parameters without the varied one.

use crate::engine::registry::{AnyModel, Registry};
use crate::engine::SweepSettings;
use crate::error::{Error, Result};
use crate::model::check_domain;
use crate::report::FreqUnit;
use crate::timedomain::Scheme;
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// A frequency range in rad/s.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// Start, rad/s (> 0).
    pub from: f64,
    /// End, rad/s (> from).
    pub to: f64,
}

/// Parameter overrides, with the spans of their names for error messages.
pub type Params = BTreeMap<Spanned<String>, f64>;

/// A whole study.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    /// Title for `summary.md`.
    pub title: Option<String>,
    /// Registered model name.
    pub model: Spanned<String>,
    /// Default number of harmonics.
    #[serde(default = "default_harmonics")]
    pub harmonics: usize,
    /// Default frequency-axis unit.
    #[serde(default)]
    pub unit: FreqUnit,
    /// Default frequency range, rad/s.
    pub frequency: Range,
    /// Parameter overrides for every figure.
    #[serde(default)]
    pub params: Params,
    /// Default panels (output names); empty: every output.
    #[serde(default)]
    pub outputs: Vec<Spanned<String>>,
    /// Y-axis labels by output name.
    #[serde(default)]
    pub labels: BTreeMap<String, String>,
    /// Default continuation settings.
    #[serde(default)]
    pub sweep: SweepSettings,
    /// The figures.
    #[serde(default, rename = "figure")]
    pub figures: Vec<FigureSpec>,
    /// File name and text, for error locations (set by [`parse`]).
    #[serde(skip)]
    pub source: Option<(String, String)>,
}

fn default_harmonics() -> usize {
    crate::fourier::DEFAULT_HARMONICS
}

/// One figure: a family of curves varying one parameter (or N), with its claims.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FigureSpec {
    /// File stem (letters, digits, `_`, `-`).
    pub id: Spanned<String>,
    /// Figure title.
    pub title: Option<String>,
    /// The paper's qualitative claim, quoted in `summary.md`.
    pub claim: Option<String>,
    /// The parameter varied over `values`, or `"harmonics"`.
    pub vary: Option<Spanned<String>>,
    /// Values of `vary`, one curve each.
    #[serde(default)]
    pub values: Vec<f64>,
    /// Registered model for this figure instead of the study's. It starts from its own
    /// defaults: the study's `params` and `outputs` are the study model's.
    pub model: Option<Spanned<String>>,
    /// Figure overrides (applied after the study's, or to `model`'s defaults).
    #[serde(default)]
    pub params: Params,
    /// Number of harmonics for this figure.
    pub harmonics: Option<usize>,
    /// Frequency range for this figure.
    pub frequency: Option<Range>,
    /// Frequency-axis unit for this figure.
    pub unit: Option<FreqUnit>,
    /// Panels for this figure.
    pub outputs: Option<Vec<Spanned<String>>>,
    /// Continuation settings for this figure (field-wise over the study's).
    pub sweep: Option<SweepSettings>,
    /// Time-domain comparison points.
    pub timedomain: Option<TimeDomainSpec>,
    /// Fold curves in the plane of Ω and a parameter instead of amplitude–frequency
    /// curves (one analysis per value of `vary`).
    pub folds: Option<FoldSpec>,
    /// Backbones drawn over the amplitude–frequency curves, each continued in a
    /// panel's output to the figure's largest amplitude of it (as `sweep --backbone`).
    pub backbone: Option<Spanned<BackboneSpec>>,
    /// Claims checked against the results.
    #[serde(default, rename = "check")]
    pub checks: Vec<CheckSpec>,
}

/// Which backbones a figure draws: `backbone = true` (every mode whose linear
/// natural frequency lies in the figure's frequency range), `false` (none), or
/// `backbone = { modes = [1, 2] }` (those modes, drawn where they are in the range).
///
/// They are the backbones of the figure's model with its parameters but not the
/// varied one, so they belong with a family in a forcing parameter (the forcing is
/// left out of a mode).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BackboneSpec {
    /// Every mode in the frequency range (`true`), or none (`false`).
    InRange(bool),
    /// These modes (1-based, in the order of the linearised natural frequencies).
    Modes(Vec<usize>),
}

/// The table form, `{ modes = [...] }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BackboneModes {
    modes: Vec<usize>,
}

impl<'de> Deserialize<'de> for BackboneSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = BackboneSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("true, false or a table { modes = [1, 2] }")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<BackboneSpec, E> {
                Ok(BackboneSpec::InRange(v))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                a: A,
            ) -> Result<BackboneSpec, A::Error> {
                let t =
                    BackboneModes::deserialize(serde::de::value::MapAccessDeserializer::new(a))?;
                Ok(BackboneSpec::Modes(t.modes))
            }
        }
        d.deserialize_any(V)
    }
}

impl BackboneSpec {
    /// The modes asked for by number (`None`: those in the frequency range; empty:
    /// none).
    pub fn modes(&self) -> Option<&[usize]> {
        match self {
            BackboneSpec::InRange(true) => None,
            BackboneSpec::InRange(false) => Some(&[]),
            BackboneSpec::Modes(m) => Some(m),
        }
    }
}

/// A two-parameter fold analysis: the folds of the Ω-curves at both ends of the
/// range of `param`, continued across it (`ihbm folds`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FoldSpec {
    /// The second parameter.
    pub param: Spanned<String>,
    /// One end of its range.
    pub from: f64,
    /// The other end.
    pub to: f64,
    /// What the curves follow: `"fold"` (default), `"period-doubling"` or `"torus"`.
    #[serde(default)]
    pub boundary: crate::bifurcation::Boundary,
}

/// Time integrations to compare with the harmonic balance (paper Fig. 6).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeDomainSpec {
    /// Forcing frequencies, rad/s.
    pub omegas: Vec<f64>,
    /// Schemes (default: both).
    #[serde(default = "default_schemes")]
    pub schemes: Vec<Scheme>,
    /// Forcing periods per run (default: `engine::SimSettings::default()`'s; at least
    /// `timedomain::MIN_PERIODS`).
    pub periods: Option<usize>,
    /// Steps per forcing period (default 200: the paper's step π/(100 Ω)).
    pub steps_per_period: Option<f64>,
}

fn default_schemes() -> Vec<Scheme> {
    vec![Scheme::Gl, Scheme::Bdf2]
}

/// What a check measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckKind {
    /// The peak `max_abs` of an output over a band, along the family.
    Peak,
    /// The frequency of that peak, along the family.
    PeakOmega,
    /// Whether folds (multi-valued regions) appear in the band.
    Folds,
    /// Relative change of the peak between successive curves (harmonic convergence).
    Converges,
    /// Harmonic balance vs time integration at the time-domain points.
    Timedomain,
}

/// The claimed behaviour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Expect {
    /// Grows along the family.
    Increasing,
    /// Falls along the family.
    Decreasing,
    /// Changes by at most `tol` relative.
    Unchanged,
    /// Present (folds) — on every curve, or from `from_value` on.
    Present,
    /// Absent (folds) on every curve.
    Absent,
    /// Agreement within `tol` (time domain).
    Agree,
}

/// A claim checked against the curves of a figure.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckSpec {
    /// What is measured.
    pub kind: CheckKind,
    /// The claimed behaviour.
    pub expect: Expect,
    /// Output (default: the figure's first panel).
    pub output: Option<String>,
    /// Frequency band, rad/s (default: the whole range): exactly two numbers.
    #[serde(default, deserialize_with = "two_numbers")]
    pub band: Option<[f64; 2]>,
    /// Relative tolerance: `unchanged` trends (default 0.02), `agree` (0.05), and
    /// `converges` (1e-5: the largest change that counts as converged).
    pub tol: Option<f64>,
    /// For `folds`/`present`: the family value from which folds are claimed.
    pub from_value: Option<f64>,
}

/// `[lo, hi]` and nothing else (a plain `[f64; 2]` took the first two of three).
fn two_numbers<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    let v: Vec<f64> = Vec::deserialize(d)?;
    match v[..] {
        [lo, hi] => Ok(Some([lo, hi])),
        _ => Err(serde::de::Error::custom(format!(
            "a band is two numbers [lo, hi], not {} number(s)",
            v.len()
        ))),
    }
}

/// 1-based line and column of byte offset `at` in `text`.
pub fn line_col(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = text.get(..at).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Parse a study; `file` names it in error messages (`file:line:col: message`).
pub fn parse(text: &str, file: &str) -> Result<Study> {
    toml::from_str::<Study>(text)
        .map_err(|e| {
            let msg = e.message().trim().replace('\n', " ");
            match e.span() {
                Some(span) => {
                    let (l, c) = line_col(text, span.start);
                    Error::Study(format!("{file}:{l}:{c}: {msg}"))
                }
                None => Error::Study(format!("{file}: {msg}")),
            }
        })
        .map(|mut s| {
            s.source = Some((file.to_string(), text.to_string()));
            s
        })
}

impl Study {
    /// `file:line:col: msg` for a span of the source.
    fn at(&self, span: std::ops::Range<usize>, msg: impl std::fmt::Display) -> Error {
        match &self.source {
            Some((file, text)) => {
                let (l, c) = line_col(text, span.start);
                Error::Study(format!("{file}:{l}:{c}: {msg}"))
            }
            None => Error::Study(msg.to_string()),
        }
    }

    /// `file: msg`.
    fn whole(&self, msg: impl std::fmt::Display) -> Error {
        match &self.source {
            Some((file, _)) => Error::Study(format!("{file}: {msg}")),
            None => Error::Study(msg.to_string()),
        }
    }

    /// The study's model with the study-level overrides applied.
    pub fn base_model(&self, reg: &Registry) -> Result<Box<dyn AnyModel>> {
        let mut m = self.model_named(&self.model, reg)?;
        apply(self, m.as_mut(), &self.params)?;
        Ok(m)
    }

    /// The registered model `name`, or the model file it names (relative to the study
    /// file's directory), errors pointing at the name.
    fn model_named(&self, name: &Spanned<String>, reg: &Registry) -> Result<Box<dyn AnyModel>> {
        let dir = self.source.as_ref().and_then(|(f, _)| std::path::Path::new(f).parent());
        reg.get_in(name.get_ref(), dir).map_err(|e| self.at(name.span(), e))
    }

    /// The model of figure `fig` with its overrides applied: the study's model (with
    /// the study's overrides) or the figure's own `model` (from its defaults).
    pub fn figure_model(&self, fig: &FigureSpec, reg: &Registry) -> Result<Box<dyn AnyModel>> {
        let mut m = match &fig.model {
            None => self.base_model(reg)?,
            Some(name) => self.model_named(name, reg)?,
        };
        apply(self, m.as_mut(), &fig.params)?;
        Ok(m)
    }

    /// The panels of figure `fig` whose model is `m`: the figure's `outputs`, else the
    /// study's (for the study's model), else every output of `m`.
    pub fn figure_outputs(&self, fig: &FigureSpec, m: &dyn AnyModel) -> Vec<String> {
        match (&fig.outputs, &fig.model) {
            (Some(o), _) => o.iter().map(|s| s.get_ref().clone()).collect(),
            (None, None) if !self.outputs.is_empty() => {
                self.outputs.iter().map(|o| o.get_ref().clone()).collect()
            }
            _ => m.outputs().iter().map(|o| o.name.to_string()).collect(),
        }
    }

    /// Check everything that can be checked without solving: names, ranges, counts.
    /// Errors point at the offending value (`file:line:col`).
    pub fn validate(&self, reg: &Registry) -> Result<()> {
        let base = self.base_model(reg)?;
        self.check_harmonics(self.harmonics, None)?;
        self.check_sweep(&self.sweep, None)?;
        self.check_range(&self.frequency, "frequency")?;
        check_outputs(self, base.as_ref(), &self.outputs)?;
        let mut models = vec![base.clone_box()];
        for fig in &self.figures {
            if fig.model.is_some() {
                models.push(self.figure_model(fig, reg)?);
            }
        }
        for name in self.labels.keys() {
            if !models.iter().any(|m| m.outputs().iter().any(|o| *o.name == **name)) {
                let mut names: Vec<&str> = models.iter().map(|m| m.name()).collect();
                names.dedup();
                let mut known: Vec<&str> =
                    models.iter().flat_map(|m| m.outputs().iter().map(|o| &*o.name)).collect();
                known.sort_unstable();
                known.dedup();
                return Err(self.whole(format!(
                    "labels: '{name}' is not an output of model '{}' (known: {})",
                    names.join("' or '"),
                    known.join(", ")
                )));
            }
        }
        let mut ids: Vec<&str> = Vec::new();
        for fig in &self.figures {
            let id = fig.id.get_ref();
            if id.is_empty()
                || !id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                return Err(self.at(
                    fig.id.span(),
                    format!("figure id '{id}' must be letters, digits, '_' or '-'"),
                ));
            }
            if ids.contains(&id.as_str()) {
                return Err(self.at(fig.id.span(), format!("figure id '{id}' is used twice")));
            }
            ids.push(id);
            let m = self.figure_model(fig, reg)?;
            if let Some(n) = fig.harmonics {
                self.check_harmonics(n, Some(id))?;
            }
            if fig.sweep.is_some() {
                self.check_sweep(&self.sweep.merged(fig.sweep.as_ref()), Some(id))?;
            }
            if let Some(r) = &fig.frequency {
                self.check_range(r, &format!("figure '{id}': frequency"))?;
            }
            if let Some(outs) = &fig.outputs {
                check_outputs(self, m.as_ref(), outs)?;
            }
            match &fig.vary {
                None if !fig.values.is_empty() => {
                    return Err(self.at(
                        fig.id.span(),
                        format!("figure '{id}': 'values' given without 'vary'"),
                    ));
                }
                None => {}
                Some(v) => {
                    if fig.values.is_empty() {
                        return Err(self.at(
                            v.span(),
                            format!(
                                "figure '{id}': 'vary = \"{}\"' needs a non-empty 'values' list",
                                v.get_ref()
                            ),
                        ));
                    }
                    for &x in &fig.values {
                        if v.get_ref() == "harmonics" {
                            if !(x >= 1.0 && x.fract() == 0.0 && x <= 1000.0) {
                                return Err(self.at(
                                    v.span(),
                                    format!(
                                        "figure '{id}': harmonics value {x} is not an integer >= 1"
                                    ),
                                ));
                            }
                        } else {
                            let mut mv = m.clone_box();
                            mv.set_param(v.get_ref(), x)
                                .and_then(|_| mv.validate())
                                .map_err(|e| self.at(v.span(), format!("figure '{id}': {e}")))?;
                        }
                    }
                }
            }
            if let Some(fs) = &fig.folds {
                let name = fs.param.get_ref();
                let here = |e| self.at(fs.param.span(), format!("figure '{id}': {e}"));
                if let Some(info) = m.params_info().iter().find(|p| *p.name == **name) {
                    // an interval: with both ends in the domain, the whole range is
                    // (a non-finite end has its own message below)
                    for v in [fs.from, fs.to].into_iter().filter(|v| v.is_finite()) {
                        let what = format!("end of the folds range of {name}");
                        check_domain(m.name(), info, &what, v).map_err(here)?;
                    }
                }
                m.clone_box()
                    .set_param(name, fs.from)
                    .and_then(|_| m.clone_box().set_param(name, fs.to))
                    .map_err(here)?;
                if !(fs.from.is_finite() && fs.to.is_finite() && fs.from != fs.to) {
                    return Err(self.at(
                        fs.param.span(),
                        format!(
                            "figure '{id}': folds range {} to {} must be two different finite values",
                            fs.from, fs.to
                        ),
                    ));
                }
                if fig.timedomain.is_some() || !fig.checks.is_empty() {
                    return Err(self.at(
                        fs.param.span(),
                        format!("figure '{id}': a 'folds' figure takes no 'timedomain' or 'check'"),
                    ));
                }
            }
            if let Some(b) = &fig.backbone {
                self.check_backbone(fig, b, m.as_ref())?;
            }
            if let Some(td) = &fig.timedomain {
                if td.omegas.is_empty() || td.schemes.is_empty() {
                    return Err(self.whole(format!(
                        "figure '{id}': timedomain needs non-empty 'omegas' and 'schemes'"
                    )));
                }
                for &w in &td.omegas {
                    if !(w.is_finite() && w > 0.0) {
                        return Err(self.whole(format!(
                            "figure '{id}': timedomain omega {w} must be > 0 rad/s"
                        )));
                    }
                }
                let min = crate::timedomain::MIN_PERIODS;
                if td.periods.is_some_and(|p| p < min) {
                    return Err(
                        self.whole(format!("figure '{id}': timedomain periods must be >= {min}"))
                    );
                }
                let min_steps = crate::timedomain::MIN_STEPS_PER_PERIOD;
                if td.steps_per_period.is_some_and(|s| !(s.is_finite() && s >= min_steps)) {
                    return Err(self.whole(format!(
                        "figure '{id}': timedomain steps_per_period must be >= {min_steps}"
                    )));
                }
            }
            for c in &fig.checks {
                if let Some(o) = &c.output {
                    m.outputs().iter().find(|x| *x.name == **o).ok_or_else(|| {
                        self.whole(format!(
                            "figure '{id}': check output '{o}' is not an output of model '{}'",
                            m.name()
                        ))
                    })?;
                }
                if let Some([lo, hi]) = c.band {
                    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                        return Err(self.whole(format!(
                            "figure '{id}': check band [{lo}, {hi}] must have lo < hi"
                        )));
                    }
                }
                if c.tol.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
                    return Err(self.whole(format!("figure '{id}': check tol must be > 0")));
                }
                if c.from_value.is_some_and(|v| !v.is_finite()) {
                    return Err(self.whole(format!(
                        "figure '{id}': check from_value must be a finite number"
                    )));
                }
                if c.kind == CheckKind::Timedomain && fig.timedomain.is_none() {
                    return Err(self.whole(format!(
                        "figure '{id}': a 'timedomain' check needs a 'timedomain' table"
                    )));
                }
            }
        }
        Ok(())
    }

    /// A figure's `backbone`: not on a fold figure, and modes the model has (at
    /// least one, none twice).
    fn check_backbone(
        &self,
        fig: &FigureSpec,
        b: &Spanned<BackboneSpec>,
        m: &dyn AnyModel,
    ) -> Result<()> {
        let id = fig.id.get_ref();
        if fig.folds.is_some() {
            return Err(self.at(
                b.span(),
                format!("figure '{id}': a 'folds' figure draws no backbones (no amplitude axis)"),
            ));
        }
        if let BackboneSpec::Modes(modes) = b.get_ref() {
            let ndof = m.dofs().len();
            if modes.is_empty() {
                return Err(self.at(
                    b.span(),
                    format!("figure '{id}': backbone modes is empty (write backbone = false)"),
                ));
            }
            for (i, &k) in modes.iter().enumerate() {
                if k == 0 || k > ndof {
                    return Err(self.at(
                        b.span(),
                        format!(
                            "figure '{id}': backbone mode {k} is not a mode of model '{}' (1 to {ndof}, its DOFs)",
                            m.name()
                        ),
                    ));
                }
                if modes[..i].contains(&k) {
                    return Err(self.at(
                        b.span(),
                        format!("figure '{id}': backbone mode {k} is listed twice"),
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_harmonics(&self, n: usize, fig: Option<&str>) -> Result<()> {
        if n == 0 || n > 1000 {
            let what = fig.map_or(String::new(), |f| format!("figure '{f}': "));
            return Err(self.whole(format!("{what}harmonics = {n} (expected 1 <= N <= 1000)")));
        }
        Ok(())
    }

    fn check_sweep(&self, s: &SweepSettings, fig: Option<&str>) -> Result<()> {
        s.options().map(|_| ()).map_err(|e| {
            let what = fig.map_or(String::new(), |f| format!("figure '{f}': "));
            self.whole(format!("{what}{}", e.study()))
        })
    }

    fn check_range(&self, r: &Range, what: &str) -> Result<()> {
        if !(r.from.is_finite() && r.to.is_finite() && r.from > 0.0 && r.from < r.to) {
            return Err(self.whole(format!(
                "{what} from {} to {}: expected 0 < from < to (rad/s)",
                r.from, r.to
            )));
        }
        Ok(())
    }
}

/// Apply overrides, errors pointing at the parameter name: an unknown name, a value
/// that is not finite, or one outside the model's domain (a fractional order outside
/// [0, 2]), which would otherwise fail only when solved.
fn apply(study: &Study, m: &mut dyn AnyModel, params: &Params) -> Result<()> {
    for (k, &v) in params {
        m.set_param(k.get_ref(), v).map_err(|e| study.at(k.span(), e))?;
        m.validate().map_err(|e| study.at(k.span(), e))?;
    }
    Ok(())
}

fn check_outputs(study: &Study, m: &dyn AnyModel, outs: &[Spanned<String>]) -> Result<()> {
    for o in outs {
        if !m.outputs().iter().any(|x| *x.name == **o.get_ref()) {
            let known: Vec<&str> = m.outputs().iter().map(|x| &*x.name).collect();
            return Err(study.at(
                o.span(),
                format!(
                    "unknown output '{}' for model '{}' (known: {})",
                    o.get_ref(),
                    m.name(),
                    known.join(", ")
                ),
            ));
        }
    }
    Ok(())
}
