//! `ihbm._native`: the ihbm engine behind the Python package `ihbm`.
//!
//! Each analysis returns the JSON text the command line writes (the same
//! `ihbm::report` functions), which the pure-Python layer (`ihbm/__init__.py`) turns
//! into dicts; a sweep also returns its columns as NumPy arrays built here from the
//! curve's points. Continuation settings arrive as a JSON object and are read by the
//! same `serde` definitions as a study file's `sweep` table. The engine's checks name
//! arguments by their Python keywords ([`PY_NAMES`]). Every computation runs with the
//! GIL released; continuations run on a thread of their own, re-acquiring the GIL now
//! and then to report progress ([`Watch`]), while the calling thread looks for Ctrl-C
//! and stops them within a fraction of a second ([`stoppable`]). Errors are `ihbm.IhbmError` with the library's
//! message.

use ihbm::backbone::FamilyOptions;
use ihbm::bifurcation::Boundary;
use ihbm::bifurcation::FoldCurves;
use ihbm::continuation::{Control, Event, Observer, Trace};
use ihbm::engine::detach::{self, Detached, Latest, TraceCopy};
use ihbm::engine::progress;
use ihbm::engine::registry::{NamedModel, Registry};
use ihbm::engine::{
    self, ArgNames, BackboneSettings, FoldRange, ParamRange, SimSettings, SolveSettings,
    SweepSettings,
};
use ihbm::model::BoxedModel;
use ihbm::results::Curve;
use ihbm::runtime::RuntimeModel;
use ihbm::{report, Error};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
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

/// Watches a continuation running without the GIL: every [`CHECK_EVERY`] it takes the
/// GIL to call the progress callback `(points, value)` (and to run Python's signal
/// handlers, which only does something on the main thread: off it, [`stoppable`]
/// looks for Ctrl-C). The first exception either raises stops the run; it is kept so
/// that the caller gets the partial result with it.
struct Watch {
    progress: Option<Py<PyAny>>,
    last: Option<Instant>,
    stopped_by: Option<PyErr>,
}

impl Watch {
    fn new(progress: Option<Py<PyAny>>) -> Self {
        Watch { progress, last: None, stopped_by: None }
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

impl Observer for &mut Watch {
    fn observe(&mut self, event: &Event, trace: &Trace) -> Control {
        (**self).observe(event, trace)
    }
}

impl Observer for Watch {
    fn observe(&mut self, event: &Event, trace: &Trace) -> Control {
        let value = match *event {
            Event::Point(i) => trace.points.get(i).map_or(f64::NAN, |p| p.param),
            _ => trace.points.last().map_or(f64::NAN, |p| p.param),
        };
        self.check(trace.points.len(), value)
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
/// where there is no verdict, `{output}_{max_abs,mean,amp1}`) and then `segment`,
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

/// Run `work` on a thread of its own while this one, without the GIL, looks for
/// Python's signals every few milliseconds (signal handlers run on the main thread
/// only): Ctrl-C sets the flag `work`'s observer stops at, and when the work does not
/// return within the grace period (one point of a large problem can take minutes),
/// `salvage` gives what it had published. `work` gets the [`Watch`] that reports its
/// progress. The result, and the exception that stopped it.
fn stoppable<R, F>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    work: F,
    salvage: impl FnOnce() -> Option<R>,
) -> PyResult<(R, Option<Py<PyAny>>)>
where
    R: Send + 'static,
    F: FnOnce(&mut Watch, &AtomicBool) -> ihbm::Result<R> + Send + 'static,
{
    let stop = Arc::new(AtomicBool::new(false));
    let run = {
        let stop = Arc::clone(&stop);
        move || {
            let mut watch = Watch::new(progress);
            let r = work(&mut watch, &stop);
            (r, watch.stopped_by)
        }
    };
    let mut caught: Option<PyErr> = None;
    let ran = py.detach(|| {
        detach::run_polled(
            || {
                if caught.is_none() {
                    caught = Python::attach(|py| py.check_signals()).err();
                    stop.store(caught.is_some(), Ordering::Relaxed);
                }
                caught.is_some()
            },
            run,
        )
    });
    // A Ctrl-C after the last look counts too: the whole result then goes with it
    // instead of being lost to a KeyboardInterrupt raised after the call.
    let value = |e: PyErr| Some(e.into_value(py).into_any());
    match ran {
        Detached::Returned((r, by)) => {
            let r = r.map_err(py_err)?;
            Ok((r, by.or(caught).or_else(|| py.check_signals().err()).and_then(value)))
        }
        Detached::Abandoned => match salvage() {
            Some(r) => Ok((r, caught.and_then(value))),
            None => {
                Err(caught.unwrap_or_else(|| IhbmError::new_err("stopped before the first point")))
            }
        },
        Detached::Panicked(why) => Err(pyo3::exceptions::PyRuntimeError::new_err(why)),
    }
}

/// [`stoppable`] for a computation with nothing to keep part way (a solve, a time
/// integration, one limit cycle): Ctrl-C raises `KeyboardInterrupt` within a fraction
/// of a second instead of when the computation is done (it is left to finish on its
/// own thread, and its result is dropped).
fn interruptible<R, F>(py: Python<'_>, work: F) -> PyResult<R>
where
    R: Send + 'static,
    F: FnOnce() -> ihbm::Result<R> + Send + 'static,
{
    match stoppable(py, None, move |_, _| work(), || None)? {
        (r, None) => Ok(r),
        (_, Some(stopped_by)) => Err(PyErr::from_value(stopped_by.into_bound(py))),
    }
}

/// [`stoppable`] for an analysis whose observer sees the whole result so far (fold
/// curves, a backbone, a family of limit cycles): `progress` gives the points and
/// the value shown, and what is kept after an abandoned run is its last event's copy.
fn watched<E, T, F>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    analysis: F,
    shown: fn(&T) -> (usize, f64),
) -> PyResult<(T, Option<Py<PyAny>>)>
where
    E: 'static,
    T: Clone + Send + 'static,
    F: FnOnce(&mut dyn Observer<E, T>) -> ihbm::Result<T> + Send + 'static,
{
    let latest = Latest::default();
    let published = latest.clone();
    stoppable(
        py,
        progress,
        move |watch, stop| {
            let mut check = |_: &E, t: &T| {
                if stop.load(Ordering::Relaxed) {
                    return Control::Stop;
                }
                let (points, value) = shown(t);
                watch.check(points, value)
            };
            let mut observer = published.watching(&mut check);
            analysis(&mut observer)
        },
        || latest.take(),
    )
}

/// [`stoppable`] for a curve of `model`: what is kept after an abandoned run is the
/// curve as far as its last point.
fn traced<F>(
    py: Python<'_>,
    model: NamedModel,
    stability_checked: bool,
    progress: Option<Py<PyAny>>,
    trace: F,
) -> PyResult<(Curve, Option<Py<PyAny>>)>
where
    F: FnOnce(&NamedModel, &mut dyn Observer) -> ihbm::Result<Curve> + Send + 'static,
{
    let name = model.name().to_string();
    let copy = TraceCopy::default();
    let published = copy.clone();
    stoppable(
        py,
        progress,
        move |watch, stop| {
            let mut observer = published.watching(progress::Stoppable { inner: watch, stop });
            trace(&model, &mut observer)
        },
        || copy.stopped_curve(&name, stability_checked),
    )
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
    fn solve(
        &self,
        py: Python<'_>,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
    ) -> PyResult<String> {
        let m = self.configured(&set)?;
        let rec = interruptible(py, move || m.solve(omega, &SolveSettings { harmonics }))?;
        Ok(json_text(&report::solve_json(&rec)))
    }

    /// The sweep JSON, the columns and what stopped it early, of a frequency sweep.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (omega_from, omega_to, harmonics, set, settings, progress=None))]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        omega_from: f64,
        omega_to: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        settings: &str,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<SweepOut<'py>> {
        let m = self.configured(&set)?;
        let s = sweep_settings(harmonics, settings)?;
        // The engine checks again inside; this run of its checks names the keywords.
        engine::sweep_options(&PY_NAMES, omega_from, omega_to, &s).map_err(py_err)?;
        let checked = s.checks_stability();
        let (curve, stopped_by) = traced(py, m, checked, progress, move |m, watch| {
            m.sweep(omega_from, omega_to, &s, watch)
        })?;
        sweep_out(py, &curve, stopped_by)
    }

    /// As `sweep`, for a parameter sweep at fixed Ω.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (param, value_from, value_to, omega, harmonics, set, settings, progress=None))]
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
    ) -> PyResult<SweepOut<'py>> {
        let m = self.configured(&set)?;
        let s = sweep_settings(harmonics, settings)?;
        engine::sweep_param_options(&PY_NAMES, omega, &s).map_err(py_err)?;
        let (checked, param) = (s.checks_stability(), param.to_string());
        let (curve, stopped_by) = traced(py, m, checked, progress, move |m, watch| {
            let r = ParamRange { param: &param, from: value_from, to: value_to, omega };
            m.sweep_param(&r, &s, watch)
        })?;
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
        let s = SimSettings { dt, periods: periods.unwrap_or(defaults.periods), scheme };
        let rec = interruptible(py, move || m.simulate(omega, &s))?;
        Ok(json_text(&report::simulate_json(&rec)))
    }

    /// The backbone JSON of mode `mode`, continued until max|output| = `to`, and the
    /// exception that stopped it early, if any.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (to, mode, harmonics, set, output=None, progress=None))]
    fn backbone(
        &self,
        py: Python<'_>,
        to: f64,
        mode: usize,
        harmonics: usize,
        set: Vec<(String, f64)>,
        output: Option<String>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(String, Option<Py<PyAny>>)> {
        let m = self.configured(&set)?;
        let s = BackboneSettings { mode, output, to, harmonics };
        let (b, stopped_by) = watched(
            py,
            progress,
            move |obs| m.backbone(&s, obs),
            |b| {
                let size = b.points.last().and_then(|p| p.outputs.get(b.output));
                (b.points.len(), size.map_or(f64::NAN, |o| o.max_abs))
            },
        )?;
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
        let s = sweep_settings(harmonics, settings)?;
        engine::fold_options(&PY_NAMES, (omega_from, omega_to), &s).map_err(py_err)?;
        let boundary: Boundary = match boundary {
            None => Boundary::default(),
            Some(b) => keyword(b, "boundary")?,
        };
        let param = param.to_string();
        let (f, stopped_by) = watched(
            py,
            progress,
            move |obs| {
                let omega = (omega_from, omega_to);
                let r =
                    FoldRange { param: &param, from: value_from, to: value_to, omega, boundary };
                m.fold_curves(&r, &s, obs)
            },
            |f: &FoldCurves| {
                let points = f.curves.iter().map(|c| c.points.len()).sum();
                let value = f.curves.iter().rev().find_map(|c| c.points.last()).map(|p| p.value);
                (points, value.unwrap_or(f64::NAN))
            },
        )?;
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
        let c = interruptible(py, move || m.cycle(omega, harmonics))?;
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
        let (f, stopped_by) = watched(
            py,
            progress,
            move |obs| m.cycles(&opts, obs),
            |f| (f.points.len(), f.points.last().map_or(f64::NAN, |p| p.value)),
        )?;
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
