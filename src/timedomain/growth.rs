//! The growth of a perturbation of a periodic solution, measured in time: a check of
//! a stability verdict by a method that shares nothing with Hill's but the model.
//!
//! Two runs start on the solution with its periodic past ([`Stepper::on_periodic`]),
//! one of them displaced. Their difference, not the distance of the displaced run to
//! the harmonic balance motion, measures the perturbation: the scheme's own periodic
//! motion is off that one by the time step's error (and by the harmonic balance's
//! truncation), the same in both runs. While the difference is small it grows or
//! decays like `e^{σt}`, `σ` the largest real part of the Floquet exponents, once that
//! exponent leads the others and the fractional memory's algebraic tail.

use super::newmark::{PeriodicStart, Stepper};
use super::{budget, invalid, plan, stepper_options, RunPlan, SimOptions};
use crate::error::Error;
use crate::model::{DynModel, Model};
use serde::Serialize;

/// How a perturbation of a periodic solution evolved ([`growth`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Growth {
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Time step, s.
    pub dt: f64,
    /// Once per period of the solution: the time and the largest difference of a DOF
    /// displacement between the displaced run and the undisplaced one.
    pub gaps: Vec<(f64, f64)>,
    /// The least-squares slope of `ln gap` over time from the fifth period of the
    /// solution on, 1/s: the largest real part of the Floquet exponents where that
    /// exponent leads the others. `None` if the runs did not differ.
    pub rate: Option<f64>,
}

/// Start two runs of `opts.periods` forcing periods on the periodic solution `start`
/// (one as given, displaced by its `dx`/`dv`, the other not) and follow their
/// difference ([`Growth`]). `opts.dt` (default `T/400`), the rule and the memory are
/// those of [`super::simulate`]; `record` plays no part.
///
/// Errors: those of [`super::simulate`] (memory counted for both runs and the
/// solution's past), a start that does not fit the model
/// ([`Stepper::on_periodic`]), a start without a displacement, fewer than 6
/// periods of the solution; [`Error::Diverged`] if a run fails.
///
/// ```
/// use ihbm::balance::Balance;
/// use ihbm::corrector::{solve, SolveOptions};
/// use ihbm::models::FractionalDuffing;
/// use ihbm::stability::{Hill, StabilityOptions};
/// use ihbm::timedomain::{growth, PeriodicStart, SimOptions};
/// let model = FractionalDuffing::default();
/// let (omega, nh) = (1.0, 7);
/// let sol = solve(&model, omega, &SolveOptions { harmonics: nh, ..Default::default() }, None)?;
/// let mut bal = Balance::new(&model, nh)?;
/// let hill = Hill::new(&model, nh)?.analyse(&mut bal, &sol.coeffs, omega, &StabilityOptions::default())?;
/// let start = PeriodicStart { dx: vec![1e-6], ..PeriodicStart::new(sol.coeffs, nh) };
/// let g = growth(&model, omega, &start, &SimOptions { periods: 20, ..Default::default() })?;
/// // Stable, and the perturbation decays at the largest real part of the exponents.
/// let rate = g.rate.unwrap();
/// assert!(hill.stable && rate < 0.0);
/// assert!((rate / hill.max_real - 1.0).abs() < 0.1, "{rate} vs {}", hill.max_real);
/// # Ok::<(), ihbm::Error>(())
/// ```
pub fn growth(
    model: &dyn DynModel,
    omega: f64,
    start: &PeriodicStart,
    opts: &SimOptions,
) -> Result<Growth, Error> {
    // The start first: nothing is planned or reserved for one that does not fit.
    start.check(model.dofs().len())?;
    if start.dx.iter().chain(&start.dv).all(|&v| v == 0.0) {
        return Err(invalid(
            "periodic start",
            "no displacement",
            "a non-zero dx or dv to follow (the undisplaced run is the reference)",
        ));
    }
    // Two runs, each with its histories and as many for the solution's past.
    let RunPlan { period, dt, steps, bytes } = plan(model, omega, opts, 4.0)?;
    let solution_period = period * start.period as f64;
    let samples = (steps as f64 * dt / solution_period + 1e-9).floor() as usize;
    if samples < 6 {
        return Err(invalid(
            "number of periods",
            opts.periods,
            format!(
                "at least {} here: 6 periods of the solution (it repeats every {} forcing \
                 periods)",
                start.period.saturating_mul(6),
                start.period
            ),
        ));
    }
    let _held = budget::reserve(bytes);
    let step_opts = stepper_options(opts, dt, steps);
    let reference = PeriodicStart { dx: Vec::new(), dv: Vec::new(), ..start.clone() };
    let mut on = Stepper::on_periodic(model, omega, &reference, &step_opts)?;
    let mut off = Stepper::on_periodic(model, omega, start, &step_opts)?;
    let mut gaps = Vec::with_capacity(samples);
    for n in 1..=steps {
        on.step()?;
        off.step()?;
        let next = (gaps.len() + 1) as f64 * solution_period;
        if n as f64 * dt >= next - 0.5 * dt && gaps.len() < samples {
            let (a, b) = (on.displacements(), off.displacements());
            let gap = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            gaps.push((on.time(), gap));
        }
    }
    let rate = log_slope(&gaps[4.min(gaps.len())..]);
    Ok(Growth { omega, dt, gaps, rate })
}

/// The least-squares slope of `ln y` against `t` over the points with `y > 0`;
/// `None` with fewer than two.
fn log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> =
        points.iter().filter(|p| p.1 > 0.0 && p.1.is_finite()).map(|&(t, y)| (t, y.ln())).collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let (mt, my) = logs.iter().fold((0.0, 0.0), |(t, y), p| (t + p.0 / n, y + p.1 / n));
    let (num, den) = logs
        .iter()
        .fold((0.0, 0.0), |(u, v), p| (u + (p.0 - mt) * (p.1 - my), v + (p.0 - mt).powi(2)));
    Some(num / den)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_log_slope_of_an_exponential_is_its_rate() {
        let pts: Vec<(f64, f64)> =
            (0..10).map(|k| (k as f64, 3.0 * (-0.25 * k as f64).exp())).collect();
        assert!((log_slope(&pts).unwrap() + 0.25).abs() < 1e-14);
        assert_eq!(log_slope(&[(0.0, 0.0), (1.0, 0.0)]), None);
    }
}
