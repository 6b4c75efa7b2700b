//! `ihbm._native`: the ihbm engine behind the Python package `ihbm`.
//!
//! Each analysis returns the JSON text the command line writes (the same
//! `ihbm::report` functions), which the pure-Python layer (`ihbm/__init__.py`) turns
//! into dicts and NumPy columns. Continuation settings arrive as a JSON object and are
//! read by the same `serde` definitions as a study file's `sweep` table, so unknown
//! keys and bad values get the study's messages. Every computation runs with the GIL
//! released. Errors are `ihbm.IhbmError` with the library's message.

use ihbm::backbone::FamilyOptions;
use ihbm::bifurcation::Boundary;
use ihbm::engine::registry::{AnyModel, Registered, Registry};
use ihbm::engine::{
    BackboneSettings, FoldRange, ParamRange, SimSettings, SolveSettings, SweepSettings,
};
use ihbm::runtime::RuntimeModel;
use ihbm::{report, Cli, Error};
use pyo3::prelude::*;

pyo3::create_exception!(
    _native,
    IhbmError,
    pyo3::exceptions::PyValueError,
    "An error of the ihbm library (bad input, a model file it refuses, no convergence)."
);

fn py_err(e: Error) -> PyErr {
    IhbmError::new_err(e.to_string())
}

/// A model: built in, read from a model file, or from text.
#[pyclass(frozen, module = "ihbm._native")]
struct NativeModel {
    model: Box<dyn AnyModel>,
}

impl NativeModel {
    /// A copy of the model with the parameter values `set` applied.
    fn configured(&self, set: &[(String, f64)]) -> PyResult<Box<dyn AnyModel>> {
        let mut m = self.model.clone_box();
        for (name, value) in set {
            m.set_param(name, *value).map_err(py_err)?;
        }
        Ok(m)
    }
}

fn json_text(v: &serde_json::Value) -> String {
    v.to_string()
}

/// A curve's sweep JSON and its CSV (whose columns the Python layer turns into NumPy
/// arrays, so their names have one source).
fn curve_texts(curve: &ihbm::results::Curve) -> (String, String) {
    (json_text(&report::sweep_json(curve)), report::curve_csv(curve))
}

/// Continuation settings from a JSON object (the study file's `sweep` keys).
fn sweep_settings(harmonics: usize, settings: &str) -> PyResult<SweepSettings> {
    let s: SweepSettings = serde_json::from_str(settings)
        .map_err(|e| IhbmError::new_err(format!("invalid continuation settings: {e}")))?;
    s.options().map_err(|e| IhbmError::new_err(e.study()))?;
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
        Ok(NativeModel { model: Box::new(Registered::new(&name, m)) })
    }

    /// A built-in model by name.
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        Ok(NativeModel { model: Cli::builtin().registry().get(name).map_err(py_err)? })
    }

    /// A model file (`*.ihbm`).
    #[staticmethod]
    fn file(path: &str) -> PyResult<Self> {
        let m = RuntimeModel::from_file(std::path::Path::new(path)).map_err(py_err)?;
        let name = ihbm::Model::name(&m).to_string();
        Ok(NativeModel { model: Box::new(Registered::new(&name, m)) })
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
        let rec = py.detach(|| m.solve(omega, &SolveSettings { harmonics })).map_err(py_err)?;
        Ok(json_text(&report::solve_json(&rec)))
    }

    /// The sweep JSON and CSV of a frequency sweep.
    fn sweep(
        &self,
        py: Python<'_>,
        omega_from: f64,
        omega_to: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        settings: &str,
    ) -> PyResult<(String, String)> {
        let m = self.configured(&set)?;
        let s = sweep_settings(harmonics, settings)?;
        let curve = py.detach(|| m.sweep(omega_from, omega_to, &s, &mut ())).map_err(py_err)?;
        Ok(curve_texts(&curve))
    }

    /// The sweep JSON and CSV of a parameter sweep at fixed Ω.
    #[allow(clippy::too_many_arguments)]
    fn sweep_param(
        &self,
        py: Python<'_>,
        param: &str,
        value_from: f64,
        value_to: f64,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
        settings: &str,
    ) -> PyResult<(String, String)> {
        let m = self.configured(&set)?;
        let s = sweep_settings(harmonics, settings)?;
        let r = ParamRange { param, from: value_from, to: value_to, omega };
        let curve = py.detach(|| m.sweep_param(&r, &s, &mut ())).map_err(py_err)?;
        Ok(curve_texts(&curve))
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
        let rec = py.detach(|| m.simulate(omega, &s)).map_err(py_err)?;
        Ok(json_text(&report::simulate_json(&rec)))
    }

    /// The backbone JSON of mode `mode`, continued until max|output| = `to`.
    #[pyo3(signature = (to, mode, harmonics, set, output=None))]
    fn backbone(
        &self,
        py: Python<'_>,
        to: f64,
        mode: usize,
        harmonics: usize,
        set: Vec<(String, f64)>,
        output: Option<String>,
    ) -> PyResult<String> {
        let m = self.configured(&set)?;
        let s = BackboneSettings { mode, output, to, harmonics };
        let b = py.detach(|| m.backbone(&s)).map_err(py_err)?;
        Ok(json_text(&report::backbone_json(&b)))
    }

    /// The folds JSON: every fold (or period-doubling / torus point, `boundary`) of the
    /// Ω-curve over `omega_from..omega_to` continued in `param` from `value_from` to
    /// `value_to`, with the cusps.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (param, value_from, value_to, omega_from, omega_to, harmonics, set, settings, boundary=None))]
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
    ) -> PyResult<String> {
        let m = self.configured(&set)?;
        let s = sweep_settings(harmonics, settings)?;
        let boundary: Boundary = match boundary {
            None => Boundary::default(),
            Some(b) => keyword(b, "boundary")?,
        };
        let r = FoldRange {
            param,
            from: value_from,
            to: value_to,
            omega: (omega_from, omega_to),
            boundary,
        };
        let f = py
            .detach(|| m.fold_curves(&r, &s, &mut |_, _| ihbm::continuation::Control::Continue))
            .map_err(py_err)?;
        Ok(json_text(&report::folds_json(&f)))
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
        let c = py.detach(|| m.cycle(omega, harmonics)).map_err(py_err)?;
        Ok(json_text(&report::cycle_json(&c)))
    }

    /// The cycles JSON: the limit cycle near `omega` continued in `param`, with its
    /// Hopf point.
    #[allow(clippy::too_many_arguments)]
    fn cycles(
        &self,
        py: Python<'_>,
        param: &str,
        value_from: f64,
        value_to: f64,
        omega: f64,
        harmonics: usize,
        set: Vec<(String, f64)>,
    ) -> PyResult<String> {
        let m = self.configured(&set)?;
        let opts = FamilyOptions {
            param: param.to_string(),
            from: value_from,
            to: value_to,
            omega,
            harmonics,
            ..Default::default()
        };
        let f = py.detach(|| m.cycles(&opts)).map_err(py_err)?;
        Ok(json_text(&report::cycles_json(&f)))
    }
}

/// The built-in models' names.
#[pyfunction]
fn builtin_names() -> Vec<String> {
    let cli = Cli::builtin();
    let reg: &Registry = cli.registry();
    reg.names().into_iter().map(String::from).collect()
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeModel>()?;
    m.add_function(wrap_pyfunction!(builtin_names, m)?)?;
    m.add("IhbmError", m.py().get_type::<IhbmError>())?;
    m.add("DEFAULT_HARMONICS", ihbm::fourier::DEFAULT_HARMONICS)?;
    Ok(())
}
