//! `ihbm._native`: the ihbm engine behind the Python package `ihbm`.
//!
//! Each analysis returns the JSON text the command line writes (the same
//! `ihbm::report` functions), which the pure-Python layer (`ihbm/__init__.py`) turns
//! into dicts; a sweep also returns its columns as NumPy arrays built here from the
//! curve's points. Continuation settings arrive as a JSON object and are read by the
//! same `serde` definitions as a study file's `sweep` table. The engine's checks name
//! arguments by their Python keywords ([`PY_NAMES`]). Every method builds the
//! engine's `Analysis` and runs it with the GIL released on a thread of its own,
//! which re-acquires the GIL now and then to report progress ([`Reporter`]), while
//! the calling thread looks for Ctrl-C and stops it within a fraction of a second
//! ([`run`]). Errors are `ihbm.IhbmError` with the library's message.

use ihbm::backbone::FamilyOptions;
use ihbm::bifurcation::Boundary;
use ihbm::continuation::Control;
use ihbm::engine::analysis::{Analysis, Outcome, Progress, Watch};
use ihbm::engine::detach::{self, Ran};
use ihbm::engine::registry::{NamedModel, Registry};
use ihbm::engine::{ArgNames, BackboneSettings, SimSettings, SolveSettings, SweepSettings};
use ihbm::model::BoxedModel;
use ihbm::results::Curve;
use ihbm::runtime::RuntimeModel;
use ihbm::{report, Error};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::time::{Duration, Instant};

pyo3::create_exception!(
    _native,
    IhbmError,
    pyo3::exceptions::PyValueError,
    "An error of the ihbm library (bad input, a model file it refuses, no convergence)."
);

fn py_err(e: Error) -> PyErr {
    IhbmError::new_err(e.to_string())
}

/// A continuation setting is named by its key, which is also its Python keyword.
fn keyword_name(key: &str) -> String {
    key.to_string()
}

/// The names the engine's checks use in messages: the keywords of `ihbm.Model`'s
/// methods, not the command line's flags.
const PY_NAMES: ArgNames = ArgNames {
    from: "omega_from",
    to: "omega_to",
    omega: "omega",
    omega_from: "omega_from",
    omega_to: "omega_to",
    setting: keyword_name,
};

/// How often a running continuation takes the GIL back to report progress: often
/// enough to feel live, rarely enough that other Python threads are not slowed.
const CHECK_EVERY: Duration = Duration::from_millis(50);

/// Watches an analysis running without the GIL: every [`CHECK_EVERY`] it takes the
/// GIL to call the progress callback `(points, value)` (and to run Python's signal
/// handlers, which only does something on the main thread: off it, [`run`]
/// looks for Ctrl-C). The first exception either raises stops the run; it is kept so
/// that the caller gets the partial result with it.
struct Reporter {
    progress: Option<Py<PyAny>>,
    last: Option<Instant>,
    stopped_by: Option<PyErr>,
}

impl Reporter {
    fn new(progress: Option<Py<PyAny>>) -> Self {
        Reporter { progress, last: None, stopped_by: None }
    }

    /// `points` traced so far, the last at parameter `value`.
    fn check(&mut self, points: usize, value: f64) -> Control {
        if self.stopped_by.is_some() {
            return Control::Stop;
        }
        // The first event is checked at once, so a pending Ctrl-C stops the run early.
        if self.last.is_some_and(|t| t.elapsed() < CHECK_EVERY) {
            return Control::Continue;
        }
        self.last = Some(Instant::now());
        let result = Python::attach(|py| {
            py.check_signals()?;
            if let Some(f) = &self.progress {
                f.call1(py, (points, value))?;
            }
            Ok::<_, PyErr>(())
        });
        match result {
            Ok(()) => Control::Continue,
            Err(e) => {
                self.stopped_by = Some(e);
                Control::Stop
            }
        }
    }
}

impl Watch for Reporter {
    fn watch(&mut self, progress: &Progress<'_>) -> Control {
        self.check(progress.points(), progress.value())
    }
}

/// A NumPy array of `values`, made by NumPy from their bytes (`dtype` is the NumPy
/// name of `T`, native byte order as `to_ne_bytes` writes it).
fn array<'py, const B: usize>(
    np: &Bound<'py, PyModule>,
    values: impl Iterator<Item = [u8; B]>,
    dtype: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let bytes: Vec<u8> = values.flatten().collect();
    // A bytearray, not bytes: the array over it is writable without another copy.
    let buffer = PyByteArray::new(np.py(), &bytes);
    np.call_method1("frombuffer", (buffer, dtype))
}

/// A curve's columns, named as its CSV's (the parameter, `stable` as 1.0, 0.0 or NaN
/// where there is no verdict, `{output}_{max_abs,mean,amp1,rms,min,max}`) and then `segment`,
/// the index of the piece of the curve (`segments` in the JSON) each point belongs to.
fn curve_columns<'py>(py: Python<'py>, c: &Curve) -> PyResult<Bound<'py, PyDict>> {
    let np = py.import("numpy")?;
    let cols = PyDict::new(py);
    let by_param = !c.parameter.is_omega();
    let f = |g: &dyn Fn(&ihbm::results::CurvePoint) -> f64| {
        array(&np, c.points.iter().map(|p| g(p).to_ne_bytes()), "float64")
    };
    cols.set_item(c.parameter.name(), f(&|p| if by_param { p.param } else { p.omega })?)?;
    let verdict = |p: &ihbm::results::CurvePoint| match p.stability.verdict() {
        Some(true) => 1.0,
        Some(false) => 0.0,
        None => f64::NAN,
    };
    cols.set_item("stable", f(&verdict)?)?;
    for (k, name) in c.output_names.iter().enumerate() {
        let out = |p: &ihbm::results::CurvePoint, g: fn(&ihbm::results::PointOutput) -> f64| {
            p.outputs.get(k).map_or(f64::NAN, g)
        };
        cols.set_item(format!("{name}_max_abs"), f(&|p| out(p, |o| o.max_abs))?)?;
        cols.set_item(format!("{name}_mean"), f(&|p| out(p, |o| o.mean))?)?;
        cols.set_item(format!("{name}_amp1"), f(&|p| out(p, |o| o.amp1))?)?;
        cols.set_item(format!("{name}_rms"), f(&|p| out(p, |o| o.rms))?)?;
        cols.set_item(format!("{name}_min"), f(&|p| out(p, |o| o.min))?)?;
        cols.set_item(format!("{name}_max"), f(&|p| out(p, |o| o.max))?)?;
    }
    // Segment indices are small; i64 is NumPy's default integer.
    let segment = c.points.iter().map(|p| i64::try_from(p.segment).unwrap_or(i64::MAX));
    cols.set_item("segment", array(&np, segment.map(i64::to_ne_bytes), "int64")?)?;
    Ok(cols)
}

/// What a sweep returns to the Python layer: the sweep JSON, the columns, and the
/// exception that stopped it early (Ctrl-C, or the progress callback's), if any.
type SweepOut<'py> = (String, Bound<'py, PyDict>, Option<Py<PyAny>>);

fn sweep_out<'py>(
    py: Python<'py>,
    curve: &Curve,
    stopped_by: Option<Py<PyAny>>,
) -> PyResult<SweepOut<'py>> {
    Ok((json_text(&report::sweep_json(curve)), curve_columns(py, curve)?, stopped_by))
}

/// Run `analysis` on `model` on a thread of its own while this one, without the GIL,
/// looks for Python's signals every few milliseconds (signal handlers run on the main
/// thread only): Ctrl-C stops the analysis at its next event, and when it does not
/// return within the grace period (one point of a large problem can take minutes),
/// what it had traced is kept ([`detach::run_analysis`]). `progress` is called with
/// the points so far and where the last is. The outcome, and the exception that
/// stopped it (Ctrl-C, or the progress callback's), if any.
fn run(
    py: Python<'_>,
    model: &NamedModel,
    analysis: &Analysis,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Outcome, Option<Py<PyAny>>)> {
    let mut caught: Option<PyErr> = None;
    let ran = py.detach(|| {
        let stopped = || {
            if caught.is_none() {
                caught = Python::attach(|py| py.check_signals()).err();
            }
            caught.is_some()
        };
        detach::run_analysis(model, analysis, PY_NAMES, stopped, Reporter::new(progress))
    });
    // A Ctrl-C after the last look counts too: the whole result then goes with it
    // instead of being lost to a KeyboardInterrupt raised after the call.
    let value = |e: PyErr| Some(e.into_value(py).into_any());
    match ran {
        Ran::Returned(r, reporter) => {
            let r = r.map_err(py_err)?;
            let by = reporter.stopped_by.or(caught).or_else(|| py.check_signals().err());
            Ok((r, by.and_then(value)))
        }
        Ran::Abandoned(Some(r)) => Ok((r, caught.and_then(value))),
        Ran::Abandoned(None) => {
            Err(caught.unwrap_or_else(|| IhbmError::new_err("stopped before the first point")))
        }
        Ran::Panicked(why) => Err(pyo3::exceptions::PyRuntimeError::new_err(why)),
    }
}

/// [`run`] for an analysis with nothing to keep part way (a solve, a time
/// integration, one limit cycle): Ctrl-C raises `KeyboardInterrupt` within a fraction
/// of a second instead of when the computation is done (it is left to finish on its
/// own thread, and its result is dropped).
fn whole(py: Python<'_>, model: &NamedModel, analysis: &Analysis) -> PyResult<Outcome> {
    match run(py, model, analysis, None)? {
        (r, None) => Ok(r),
        (_, Some(stopped_by)) => Err(PyErr::from_value(stopped_by.into_bound(py))),
    }
}

/// An outcome of another kind than the analysis gives (a bug).
fn mismatch(analysis: &Analysis) -> PyErr {
    pyo3::exceptions::PyRuntimeError::new_err(format!(
        "internal error: the {} gave a result of another kind",
        analysis.noun()
    ))
}

/// A model: built in, read from a model file, or from text.
#[pyclass(frozen, module = "ihbm._native")]
struct NativeModel {
    model: NamedModel,
}

impl NativeModel {
    /// A copy of the model with the parameter values `set` applied.
    fn configured(&self, set: &[(String, f64)]) -> PyResult<NamedModel> {
        let mut m = self.model.clone();
        for (name, value) in set {
            m.set_param(name, *value).map_err(py_err)?;
        }
        Ok(m)
    }

    /// [`NativeModel::configured`], with the transform taking `aft_samples` samples per
    /// period if given (checked at `harmonics`).
    fn sampled(
        &self,
        set: &[(String, f64)],
        aft_samples: Option<usize>,
        harmonics: usize,
    ) -> PyResult<NamedModel> {
        let mut m = self.configured(set)?;
        if let Some(s) = aft_samples {
            m.set_aft_samples(s, harmonics, "aft_samples").map_err(py_err)?;
        }
        Ok(m)
    }
}

fn json_text(v: &serde_json::Value) -> String {
    v.to_string()
}

/// Continuation settings from a JSON object (the study file's `sweep` keys, which are
/// the Python keywords); their values are checked by the engine with the rest.
fn sweep_settings(harmonics: usize, settings: &str) -> PyResult<SweepSettings> {
    let s: SweepSettings = serde_json::from_str(settings)
        .map_err(|e| IhbmError::new_err(format!("invalid continuation settings: {e}")))?;
    Ok(SweepSettings { harmonics, ..s })
}

/// A keyword (`"bdf2"`, `"torus"`) read by the enum's own `serde` names, as a study
/// file's value is.
fn keyword<T: serde::de::DeserializeOwned>(value: &str, what: &str) -> PyResult<T> {
    serde_json::from_value(serde_json::Value::String(value.to_string()))
        .map_err(|e| IhbmError::new_err(format!("invalid {what} '{value}': {e}")))
}

#[pymethods]
impl NativeModel {
    /// A model from the text of one `oscillator!` body; `origin` names it in errors.
    #[new]
    fn new(text: &str, origin: &str) -> PyResult<Self> {
        let m = RuntimeModel::from_text(text, origin).map_err(py_err)?;
        let name = ihbm::Model::name(&m).to_string();
        Ok(NativeModel { model: NamedModel::new(&name, BoxedModel::new(m)) })
    }

    /// A built-in model by name.
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        Ok(NativeModel { model: Registry::builtin().get(name).map_err(py_err)? })
    }

    /// A model file (`*.ihbm`).
    #[staticmethod]
    fn file(path: &str) -> PyResult<Self> {
        let m = RuntimeModel::from_file(std::path::Path::new(path)).map_err(py_err)?;
        let name = ihbm::Model::name(&m).to_string();
        Ok(NativeModel { model: NamedModel::new(&name, BoxedModel::new(m)) })
    }

    #[getter]
    fn name(&self) -> String {
        self.model.name().to_string()
    }

    #[getter]
    fn description(&self) -> String {
        self.model.description().to_string()
    }

    #[getter]
    fn dofs(&self) -> Vec<String> {
        self.model.dofs().iter().map(|d| d.to_string()).collect()
    }

    #[getter]
    fn outputs(&self) -> Vec<String> {
        self.model.outputs().iter().map(|o| o.name.to_string()).collect()
    }

    #[getter]
    fn equations(&self) -> Vec<String> {
        self.model.equations().iter().map(|e| e.to_string()).collect()
    }

    /// `(name, default, doc)` per parameter.
    #[getter]
    fn params(&self) -> Vec<(String, f64, String)> {
        self.model
            .params_info()
            .iter()
            .map(|p| (p.name.to_string(), p.default, p.doc.to_string()))
            .collect()
    }

    /// The solve JSON.
    #[pyo3(signature = (omega, harmonics, set, aft_samples=None, sensitivity=Vec::new()))]
    fn solve(
        &self,
        py: Python<'_>,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        aft_samples: Option<usize>,
        sensitivity: Vec<String>,
    ) -> PyResult<String> {
        let m = self.sampled(&set, aft_samples, harmonics)?;
        let analysis =
            Analysis::Solve { omega, settings: SolveSettings { harmonics, sensitivity } };
        let Outcome::Solved(rec) = whole(py, &m, &analysis)? else {
            return Err(mismatch(&analysis));
        };
        let mut v = report::solve_json(&rec);
        v["aft_samples"] = m.samples(harmonics).into();
        Ok(json_text(&v))
    }

    /// The sweep JSON, the columns and what stopped it early, of a frequency sweep.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (omega_from, omega_to, harmonics, set, settings, progress=None, aft_samples=None))]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        omega_from: f64,
        omega_to: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        settings: &str,
        progress: Option<Py<PyAny>>,
        aft_samples: Option<usize>,
    ) -> PyResult<SweepOut<'py>> {
        let m = self.sampled(&set, aft_samples, harmonics)?;
        let settings = sweep_settings(harmonics, settings)?;
        let analysis = Analysis::Sweep { from: omega_from, to: omega_to, settings };
        let (Outcome::Curve(curve), stopped_by) = run(py, &m, &analysis, progress)? else {
            return Err(mismatch(&analysis));
        };
        sweep_out(py, &curve, stopped_by)
    }

    /// As `sweep`, for a parameter sweep at fixed Ω.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (param, value_from, value_to, omega, harmonics, set, settings, progress=None, aft_samples=None))]
    fn sweep_param<'py>(
        &self,
        py: Python<'py>,
        param: &str,
        value_from: f64,
        value_to: f64,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        settings: &str,
        progress: Option<Py<PyAny>>,
        aft_samples: Option<usize>,
    ) -> PyResult<SweepOut<'py>> {
        let m = self.sampled(&set, aft_samples, harmonics)?;
        let settings = sweep_settings(harmonics, settings)?;
        let param = param.to_string();
        let analysis =
            Analysis::SweepParam { param, from: value_from, to: value_to, omega, settings };
        let (Outcome::Curve(curve), stopped_by) = run(py, &m, &analysis, progress)? else {
            return Err(mismatch(&analysis));
        };
        sweep_out(py, &curve, stopped_by)
    }

    /// The simulate JSON: time integration from rest.
    #[pyo3(signature = (omega, set, periods=None, dt=None, scheme=None))]
    fn simulate(
        &self,
        py: Python<'_>,
        omega: f64,
        set: Vec<(String, f64)>,
        periods: Option<usize>,
        dt: Option<f64>,
        scheme: Option<&str>,
    ) -> PyResult<String> {
        let m = self.configured(&set)?;
        let defaults = SimSettings::default();
        let scheme = match scheme {
            None => defaults.scheme,
            Some(s) => keyword(s, "scheme")?,
        };
        let settings = SimSettings { dt, periods: periods.unwrap_or(defaults.periods), scheme };
        let analysis = Analysis::Simulate { omega, settings };
        let Outcome::Simulated(rec) = whole(py, &m, &analysis)? else {
            return Err(mismatch(&analysis));
        };
        Ok(json_text(&report::simulate_json(&rec)))
    }

    /// The backbone JSON of mode `mode`, continued until max|output| = `to`, and the
    /// exception that stopped it early, if any.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (to, mode, harmonics, set, output=None, progress=None, aft_samples=None))]
    fn backbone(
        &self,
        py: Python<'_>,
        to: f64,
        mode: usize,
        harmonics: usize,
        set: Vec<(String, f64)>,
        output: Option<String>,
        progress: Option<Py<PyAny>>,
        aft_samples: Option<usize>,
    ) -> PyResult<(String, Option<Py<PyAny>>)> {
        let m = self.sampled(&set, aft_samples, harmonics)?;
        let analysis = Analysis::Backbone(BackboneSettings { mode, output, to, harmonics });
        let (Outcome::Backbone(b), stopped_by) = run(py, &m, &analysis, progress)? else {
            return Err(mismatch(&analysis));
        };
        Ok((json_text(&report::backbone_json(&b)), stopped_by))
    }

    /// The folds JSON: every fold (or period-doubling / torus point, `boundary`) of the
    /// Ω-curve over `omega_from..omega_to` continued in `param` from `value_from` to
    /// `value_to`, with the cusps; and the exception that stopped it early, if any.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (param, value_from, value_to, omega_from, omega_to, harmonics, set, settings, boundary=None, progress=None))]
    fn folds(
        &self,
        py: Python<'_>,
        param: &str,
        value_from: f64,
        value_to: f64,
        omega_from: f64,
        omega_to: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        settings: &str,
        boundary: Option<&str>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(String, Option<Py<PyAny>>)> {
        let m = self.configured(&set)?;
        let settings = sweep_settings(harmonics, settings)?;
        let boundary: Boundary = match boundary {
            None => Boundary::default(),
            Some(b) => keyword(b, "boundary")?,
        };
        let analysis = Analysis::Folds {
            param: param.to_string(),
            from: value_from,
            to: value_to,
            omega: (omega_from, omega_to),
            boundary,
            settings,
        };
        let (Outcome::Folds(f), stopped_by) = run(py, &m, &analysis, progress)? else {
            return Err(mismatch(&analysis));
        };
        Ok((json_text(&report::folds_json(&f)), stopped_by))
    }

    /// The cycle JSON: a limit cycle of an autonomous model near the frequency `omega`.
    fn cycle(
        &self,
        py: Python<'_>,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
    ) -> PyResult<String> {
        let m = self.configured(&set)?;
        let analysis = Analysis::Cycle { omega, harmonics };
        let Outcome::Cycle(c) = whole(py, &m, &analysis)? else {
            return Err(mismatch(&analysis));
        };
        Ok(json_text(&report::cycle_json(&c)))
    }

    /// The cycles JSON: the limit cycle near `omega` continued in `param`, with its
    /// Hopf point, and the exception that stopped it early, if any.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (param, value_from, value_to, omega, harmonics, set, progress=None))]
    fn cycles(
        &self,
        py: Python<'_>,
        param: &str,
        value_from: f64,
        value_to: f64,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(String, Option<Py<PyAny>>)> {
        let m = self.configured(&set)?;
        let opts = FamilyOptions {
            param: param.to_string(),
            from: value_from,
            to: value_to,
            omega,
            harmonics,
            ..Default::default()
        };
        let analysis = Analysis::Cycles(opts);
        let (Outcome::Cycles(f), stopped_by) = run(py, &m, &analysis, progress)? else {
            return Err(mismatch(&analysis));
        };
        Ok((json_text(&report::cycles_json(&f)), stopped_by))
    }
}

/// The built-in models' names.
#[pyfunction]
fn builtin_names() -> Vec<String> {
    Registry::builtin().names().into_iter().map(String::from).collect()
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeModel>()?;
    m.add_function(wrap_pyfunction!(builtin_names, m)?)?;
    m.add("IhbmError", m.py().get_type::<IhbmError>())?;
    m.add("DEFAULT_HARMONICS", ihbm::fourier::DEFAULT_HARMONICS)?;
    Ok(())
}
