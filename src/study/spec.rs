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

use crate::engine::registry::{NamedModel, Registry};
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
    /// The model files read so far, by name as written: each is read and parsed
    /// once, so validation, planning and the run all use one text of it.
    #[serde(skip)]
    loaded: ModelCache,
}

/// Models read from files, by the name the study gives them.
#[derive(Default)]
struct ModelCache(std::sync::Mutex<BTreeMap<String, NamedModel>>);

impl ModelCache {
    fn get_or_read(
        &self,
        name: &str,
        read: impl FnOnce() -> Result<NamedModel>,
    ) -> Result<NamedModel> {
        let mut map = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(m) = map.get(name) {
            return Ok(m.clone());
        }
        let m = read()?;
        map.insert(name.to_string(), m.clone());
        Ok(m)
    }
}

impl Clone for ModelCache {
    fn clone(&self) -> Self {
        let map = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        ModelCache(std::sync::Mutex::new(map.iter().map(|(k, v)| (k.clone(), v.clone())).collect()))
    }
}

impl std::fmt::Debug for ModelCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let map = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        f.debug_list().entries(map.keys()).finish()
    }
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
    /// What is varied over `values`: a parameter, or `"harmonics"` (N).
    pub vary: Option<Spanned<Vary>>,
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

/// What a figure varies over its `values`, one curve each: `vary = "harmonics"` (the
/// number of harmonics N, a convergence study) or any other name (that model
/// parameter).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Vary {
    /// The number of harmonics N.
    Harmonics,
    /// A model parameter, by name.
    Param(String),
}

impl Vary {
    /// As the study file spells it: `"harmonics"` or the parameter's name.
    pub fn as_str(&self) -> &str {
        match self {
            Vary::Harmonics => "harmonics",
            Vary::Param(name) => name,
        }
    }
}

impl std::fmt::Display for Vary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Vary {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Ok(if name == "harmonics" { Vary::Harmonics } else { Vary::Param(name) })
    }
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

/// Most values of `vary` in one figure: each is a curve (and a file pair), and a
/// figure of more would be neither drawn legibly nor finished in reasonable time.
pub const MAX_VALUES: usize = 1000;

/// One step of a path to a value in the study file: a key or an array index.
#[derive(Debug, Clone, Copy)]
enum Key<'a> {
    Name(&'a str),
    Index(usize),
}

/// The path of figure `f`'s key `key` (`[[figure]]` tables are an array).
fn fig_key<'a>(f: usize, key: &'a str) -> [Key<'a>; 3] {
    [Key::Name("figure"), Key::Index(f), Key::Name(key)]
}

/// 1-based line and column of byte offset `at` in `text`.
pub fn line_col(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = text.get(..at).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// 1-based line and column where a TOML text nests deepest (brackets, braces and the
/// dots of dotted keys and table headers, outside strings and comments), if it nests
/// at all.
fn deepest_nesting(text: &str) -> Option<(usize, usize)> {
    let (mut depth, mut dots, mut best, mut at) = (0usize, 0usize, 0usize, None);
    let (mut line, mut col) = (1usize, 0usize);
    let (mut quote, mut comment, mut prev) = (None::<char>, false, '\n');
    let mut chars = text.chars().peekable();
    while let Some(ch) = chars.next() {
        col += 1;
        if ch == '\n' {
            (line, col, dots, comment) = (line + 1, 0, 0, false);
        } else if comment {
        } else if let Some(q) = quote {
            if ch == q {
                quote = None;
            } else if ch == '\\' && q == '"' {
                chars.next();
                col += 1;
            }
        } else {
            match ch {
                '"' | '\'' => quote = Some(ch),
                '#' => comment = true,
                '[' | '{' => depth += 1,
                ']' | '}' => depth = depth.saturating_sub(1),
                '=' => dots = 0,
                // a dot between digits is a number's, not a key's
                '.' if !(prev.is_ascii_digit()
                    && chars.peek().is_some_and(char::is_ascii_digit)) =>
                {
                    dots += 1
                }
                _ => {}
            }
            if depth + dots > best {
                (best, at) = (depth + dots, Some((line, col)));
            }
        }
        prev = ch;
    }
    at
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
                // The parser's recursion limit comes without a place: point at the
                // deepest nesting, which is where it was passed.
                None => match deepest_nesting(text) {
                    Some((l, c)) => Error::Study(format!("{file}:{l}:{c}: {msg}")),
                    None => Error::Study(format!("{file}: {msg}")),
                },
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

    /// `file:line:col: msg` at the value `path` names in the file (`["figure", 2,
    /// "timedomain", "omegas", 0]`), or `file: msg` when it is not written there (a
    /// default).
    fn at_path(&self, path: &[Key], msg: impl std::fmt::Display) -> Error {
        match self.locate(path) {
            Some(span) => self.at(span, msg),
            None => self.whole(msg),
        }
    }

    /// The span of the value at `path` in the study's text.
    fn locate(&self, path: &[Key]) -> Option<std::ops::Range<usize>> {
        use toml::de::{DeArray, DeTable, DeValue};
        let (_, text) = self.source.as_ref()?;
        let root = DeTable::parse(text).ok()?;
        let mut span = root.span();
        let mut table = Some(root.get_ref());
        let mut array: Option<&DeArray> = None;
        for key in path {
            let value = match (*key, table, array) {
                (Key::Name(k), Some(t), _) => t.get(k)?,
                (Key::Index(i), _, Some(a)) => a.get(i)?,
                _ => return None,
            };
            span = value.span();
            (table, array) = match value.get_ref() {
                DeValue::Table(t) => (Some(t), None),
                DeValue::Array(a) => (None, Some(a)),
                _ => (None, None),
            };
        }
        Some(span)
    }

    /// `file: msg`.
    fn whole(&self, msg: impl std::fmt::Display) -> Error {
        match &self.source {
            Some((file, _)) => Error::Study(format!("{file}: {msg}")),
            None => Error::Study(msg.to_string()),
        }
    }

    /// The study's model with the study-level overrides applied.
    pub fn base_model(&self, reg: &Registry) -> Result<NamedModel> {
        let mut m = self.model_named(&self.model, reg)?;
        apply(self, &mut m, &self.params)?;
        Ok(m)
    }

    /// The registered model `name`, or the model file it names (relative to the study
    /// file's directory), errors pointing at the name.
    fn model_named(&self, name: &Spanned<String>, reg: &Registry) -> Result<NamedModel> {
        let dir = self.source.as_ref().and_then(|(f, _)| std::path::Path::new(f).parent());
        let read = || reg.get_in(name.get_ref(), dir).map_err(|e| self.at(name.span(), e));
        if crate::engine::registry::is_model_file(name.get_ref()) {
            self.loaded.get_or_read(name.get_ref(), read)
        } else {
            read()
        }
    }

    /// The model of figure `fig` with its overrides applied: the study's model (with
    /// the study's overrides) or the figure's own `model` (from its defaults).
    pub fn figure_model(&self, fig: &FigureSpec, reg: &Registry) -> Result<NamedModel> {
        let mut m = match &fig.model {
            None => self.base_model(reg)?,
            Some(name) => self.model_named(name, reg)?,
        };
        apply(self, &mut m, &fig.params)?;
        Ok(m)
    }

    /// The panels of figure `fig` whose model is `m`: the figure's `outputs`, else the
    /// study's (for the study's model), else every output of `m`.
    pub fn figure_outputs(&self, fig: &FigureSpec, m: &NamedModel) -> Vec<String> {
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
        self.check_range(&self.frequency, None)?;
        check_outputs(self, &base, &self.outputs)?;
        let mut models = vec![base];
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
                return Err(self.at_path(
                    &[Key::Name("labels"), Key::Name(name)],
                    format!(
                        "labels: '{name}' is not an output of model '{}' (known: {})",
                        names.join("' or '"),
                        known.join(", ")
                    ),
                ));
            }
        }
        let mut ids: Vec<&str> = Vec::new();
        for (f, fig) in self.figures.iter().enumerate() {
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
                self.check_harmonics(n, Some((f, id)))?;
            }
            if fig.sweep.is_some() {
                self.check_sweep(&self.sweep.merged(fig.sweep.as_ref()), Some((f, id)))?;
            }
            if let Some(r) = &fig.frequency {
                self.check_range(r, Some((f, id)))?;
            }
            if let Some(outs) = &fig.outputs {
                check_outputs(self, &m, outs)?;
            }
            self.check_fits(f, fig, &m)?;
            match &fig.vary {
                None if !fig.values.is_empty() => {
                    return Err(self.at(
                        fig.id.span(),
                        format!("figure '{id}': 'values' given without 'vary'"),
                    ));
                }
                None => {}
                Some(v) => {
                    if fig.values.len() > MAX_VALUES {
                        return Err(self.at_path(
                            &fig_key(f, "values"),
                            format!(
                                "figure '{id}': {} values (at most {MAX_VALUES} curves a figure: \
                                 split the family over figures or studies)",
                                fig.values.len()
                            ),
                        ));
                    }
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
                        match v.get_ref() {
                            Vary::Harmonics => {
                                if !(x >= 1.0 && x.fract() == 0.0 && x <= 1000.0) {
                                    return Err(self.at(
                                        v.span(),
                                        format!(
                                            "figure '{id}': harmonics value {x} is not an integer >= 1"
                                        ),
                                    ));
                                }
                            }
                            Vary::Param(name) => {
                                let mut mv = m.clone();
                                mv.set_param(name, x).and_then(|_| mv.validate()).map_err(|e| {
                                    self.at(v.span(), format!("figure '{id}': {e}"))
                                })?;
                            }
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
                m.clone()
                    .set_param(name, fs.from)
                    .and_then(|_| m.clone().set_param(name, fs.to))
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
                self.check_backbone(fig, b, &m)?;
            }
            if let Some(td) = &fig.timedomain {
                let at = |key: &str, msg: String| {
                    let [a, b, c] = fig_key(f, "timedomain");
                    self.at_path(&[a, b, c, Key::Name(key)], msg)
                };
                if td.omegas.is_empty() || td.schemes.is_empty() {
                    return Err(self.at_path(
                        &fig_key(f, "timedomain"),
                        format!("figure '{id}': timedomain needs non-empty 'omegas' and 'schemes'"),
                    ));
                }
                for (j, &w) in td.omegas.iter().enumerate() {
                    if !(w.is_finite() && w > 0.0) {
                        let [a, b, c] = fig_key(f, "timedomain");
                        return Err(self.at_path(
                            &[a, b, c, Key::Name("omegas"), Key::Index(j)],
                            format!("figure '{id}': timedomain omega {w} must be > 0 rad/s"),
                        ));
                    }
                }
                let min = crate::timedomain::MIN_PERIODS;
                if td.periods.is_some_and(|p| p < min) {
                    return Err(at(
                        "periods",
                        format!("figure '{id}': timedomain periods must be >= {min}"),
                    ));
                }
                let min_steps = crate::timedomain::MIN_STEPS_PER_PERIOD;
                if td.steps_per_period.is_some_and(|s| !(s.is_finite() && s >= min_steps)) {
                    return Err(at(
                        "steps_per_period",
                        format!(
                            "figure '{id}': timedomain steps_per_period must be >= {min_steps}"
                        ),
                    ));
                }
            }
            for (k, c) in fig.checks.iter().enumerate() {
                let at = |key: &str, msg: String| {
                    let [a, b, _] = fig_key(f, "");
                    self.at_path(&[a, b, Key::Name("check"), Key::Index(k), Key::Name(key)], msg)
                };
                if let Some(o) = &c.output {
                    m.outputs().iter().find(|x| *x.name == **o).ok_or_else(|| {
                        at(
                            "output",
                            format!(
                                "figure '{id}': check output '{o}' is not an output of model '{}'",
                                m.name()
                            ),
                        )
                    })?;
                }
                if let Some([lo, hi]) = c.band {
                    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                        return Err(at(
                            "band",
                            format!("figure '{id}': check band [{lo}, {hi}] must have lo < hi"),
                        ));
                    }
                }
                if c.tol.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
                    return Err(at("tol", format!("figure '{id}': check tol must be > 0")));
                }
                if c.from_value.is_some_and(|v| !v.is_finite()) {
                    return Err(at(
                        "from_value",
                        format!("figure '{id}': check from_value must be a finite number"),
                    ));
                }
                if c.kind == CheckKind::Timedomain && fig.timedomain.is_none() {
                    return Err(at(
                        "kind",
                        format!("figure '{id}': a 'timedomain' check needs a 'timedomain' table"),
                    ));
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
        m: &NamedModel,
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

    /// `key` of the study, or of figure `fig` (its index and id): the path to it in
    /// the file, and the prefix of its messages.
    fn place<'a>(fig: Option<(usize, &'a str)>, key: &'a str) -> (Vec<Key<'a>>, String) {
        match fig {
            None => (vec![Key::Name(key)], String::new()),
            Some((f, id)) => (fig_key(f, key).to_vec(), format!("figure '{id}': ")),
        }
    }

    /// Every harmonic count of figure `f` fits in memory for its model (with Hill's
    /// matrices when its sweeps check stability), refused at the count: a part too
    /// large would otherwise fail only when run.
    fn check_fits(&self, f: usize, fig: &FigureSpec, m: &NamedModel) -> Result<()> {
        let id = fig.id.get_ref();
        let stability =
            self.sweep.merged(fig.sweep.as_ref()).stability != Some(false) && fig.folds.is_none();
        let fits = |n: usize, path: &[Key]| {
            m.check_size(n, stability)
                .map_err(|e| self.at_path(path, format!("figure '{id}': {e}")))
        };
        match &fig.vary {
            Some(v) if *v.get_ref() == Vary::Harmonics => {
                for &x in &fig.values {
                    fits(x as usize, &fig_key(f, "vary"))?;
                }
                Ok(())
            }
            _ => match fig.harmonics {
                Some(n) => fits(n, &fig_key(f, "harmonics")),
                None => fits(self.harmonics, &[Key::Name("harmonics")]),
            },
        }
    }

    fn check_harmonics(&self, n: usize, fig: Option<(usize, &str)>) -> Result<()> {
        if n == 0 || n > 1000 {
            let (path, what) = Self::place(fig, "harmonics");
            return Err(
                self.at_path(&path, format!("{what}harmonics = {n} (expected 1 <= N <= 1000)"))
            );
        }
        Ok(())
    }

    /// The merged settings of the study or a figure; the error points at the key
    /// where it is written (the figure's table, else the study's).
    fn check_sweep(&self, s: &SweepSettings, fig: Option<(usize, &str)>) -> Result<()> {
        s.options().map(|_| ()).map_err(|e| {
            let (mut path, what) = Self::place(fig, "sweep");
            path.push(Key::Name(e.key));
            let global = [Key::Name("sweep"), Key::Name(e.key)];
            let span = self.locate(&path).or_else(|| self.locate(&global));
            let msg = format!("{what}{}", e.study());
            match span {
                Some(span) => self.at(span, msg),
                None => self.at_path(&path[..path.len() - 1], msg),
            }
        })
    }

    fn check_range(&self, r: &Range, fig: Option<(usize, &str)>) -> Result<()> {
        if !(r.from.is_finite() && r.to.is_finite() && r.from > 0.0 && r.from < r.to) {
            let (path, what) = Self::place(fig, "frequency");
            return Err(self.at_path(
                &path,
                format!(
                    "{what}frequency from {} to {}: expected 0 < from < to (rad/s)",
                    r.from, r.to
                ),
            ));
        }
        Ok(())
    }
}

/// Apply overrides, errors pointing at the parameter name: an unknown name, a value
/// that is not finite, or one outside the model's domain (a fractional order outside
/// [0, 2]), which would otherwise fail only when solved.
fn apply(study: &Study, m: &mut NamedModel, params: &Params) -> Result<()> {
    for (k, &v) in params {
        m.set_param(k.get_ref(), v).map_err(|e| study.at(k.span(), e))?;
        m.validate().map_err(|e| study.at(k.span(), e))?;
    }
    Ok(())
}

fn check_outputs(study: &Study, m: &NamedModel, outs: &[Spanned<String>]) -> Result<()> {
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
