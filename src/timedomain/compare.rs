//! Harmonic balance against time integration at a list of frequencies (the paper's
//! Fig. 6): the periodic solution's `max_abs` against the steady `max_abs` of a run
//! from rest.

use super::{simulate, SimOptions};
use crate::corrector::{solve, SolveOptions};
use crate::error::Error;
use crate::model::{DynModel, Model};
use serde::Serialize;

/// One output at one frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareOutput {
    /// Output name.
    pub name: String,
    /// `max_abs` of the harmonic-balance solution (NaN if it failed).
    pub hb_max_abs: f64,
    /// `max_abs` over the last 10 periods of the time integration (NaN if it failed).
    pub td_max_abs: f64,
    /// `|td - hb| / |hb|`.
    pub rel_diff: f64,
    /// The time run's drift figure (see [`super::SteadyOutput::drift`]).
    pub td_drift: f64,
}

/// One frequency of the comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareRow {
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Per output, in model order.
    pub outputs: Vec<CompareOutput>,
    /// Why a method failed at this frequency (its values are then NaN); the other
    /// frequencies are still computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// Solve by harmonic balance (from the linearized guess) and integrate from rest at
/// every `omega`, and compare `max_abs` output by output.
///
/// Errors only for unusable input (an empty list, a non-positive or non-finite Ω);
/// a failure at one frequency is recorded in its row.
///
/// ```
/// use ihbm::corrector::SolveOptions;
/// use ihbm::models::QuarterCar;
/// use ihbm::timedomain::{compare, SimOptions};
/// let sim = SimOptions { periods: 40, ..Default::default() };
/// let rows = compare(&QuarterCar::default(), &[8.0], &sim, &SolveOptions::default()).unwrap();
/// assert!(rows[0].outputs[0].rel_diff < 1e-3);
/// ```
pub fn compare(
    model: &dyn DynModel,
    omegas: &[f64],
    sim: &SimOptions,
    hb: &SolveOptions,
) -> Result<Vec<CompareRow>, Error> {
    if omegas.is_empty() {
        return Err(Error::InvalidValue {
            what: "frequency list".into(),
            value: "[]".into(),
            expected: "at least one frequency".into(),
        });
    }
    if let Some(w) = omegas.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
        return Err(Error::InvalidValue {
            what: "omega".into(),
            value: w.to_string(),
            expected: "a finite frequency > 0 in rad/s".into(),
        });
    }
    Ok(omegas.iter().map(|&omega| compare_at(model, omega, sim, hb)).collect())
}

/// The comparison at one frequency (`omega` checked by the caller, or reported as
/// the methods' failure in the row).
pub fn compare_at(
    model: &dyn DynModel,
    omega: f64,
    sim: &SimOptions,
    hb: &SolveOptions,
) -> CompareRow {
    let names = model.outputs();
    let mut failure = Vec::new();
    let hb_max: Vec<f64> = match solve(model, omega, hb, None) {
        Ok(sol) => sol.outputs(model).iter().map(|o| o.max_abs).collect(),
        Err(e) => {
            failure.push(format!("harmonic balance: {e}"));
            vec![f64::NAN; names.len()]
        }
    };
    let (td_max, td_drift): (Vec<f64>, Vec<f64>) = match simulate(model, omega, sim) {
        Ok(s) => s.outputs.iter().map(|o| (o.max_abs, o.drift)).unzip(),
        Err(e) => {
            failure.push(format!("time integration: {e}"));
            (vec![f64::NAN; names.len()], vec![f64::NAN; names.len()])
        }
    };
    let outputs = names
        .iter()
        .enumerate()
        .map(|(i, o)| CompareOutput {
            name: o.name.to_string(),
            hb_max_abs: hb_max[i],
            td_max_abs: td_max[i],
            rel_diff: (td_max[i] - hb_max[i]).abs() / hb_max[i].abs(),
            td_drift: td_drift[i],
        })
        .collect();
    CompareRow { omega, outputs, failure: (!failure.is_empty()).then(|| failure.join("; ")) }
}
