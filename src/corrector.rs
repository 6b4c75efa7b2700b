//! The IHBM corrector: Newton on the Fourier coefficients at fixed Ω.
//!
//! Each increment solves `J ΔA = -R` with a dense LU (faer). When a full step makes
//! the residual grow, the step is halved (backtracking) so that a poor initial guess
//! does not throw the iteration away. Failure is an error value that keeps the last
//! iterate and the iteration history.

use crate::balance::{check_inputs, linearized_on, Balance};
use crate::error::{Error, IterationRecord, Result};
use crate::linalg::DenseLu;
use crate::model::{DynModel, Model};
use crate::outputs::{At, OutputEval};
use crate::results::OutputSummary;

/// Options of the Newton corrector.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveOptions {
    /// Number of harmonics N (default 5).
    pub harmonics: usize,
    /// Converged when the Newton step is below `tol` times the coefficient norm, or
    /// the residual below `tol` times the forcing norm (default 1e-10).
    pub tol: f64,
    /// Iteration cap (default 50).
    pub max_iter: usize,
    /// Step halvings allowed per iteration when the residual grows (default 12).
    pub max_halvings: usize,
    /// Solutions that repeat every `period` forcing periods (default 1): `omega` is
    /// then `Ω/period` and the coefficients are in its harmonics
    /// ([`Balance::with_period`](crate::balance::Balance::with_period)).
    pub period: usize,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            harmonics: crate::fourier::DEFAULT_HARMONICS,
            tol: 1e-10,
            max_iter: 50,
            max_halvings: 12,
            period: 1,
        }
    }
}

/// A converged periodic solution at one frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Forcing frequency Ω, rad/s.
    pub omega: f64,
    /// Number of harmonics N.
    pub harmonics: usize,
    /// Forcing periods per solution period ([`SolveOptions::period`]).
    pub period: usize,
    /// Fourier coefficients, `[a0, a1..aN, b1..bN]` per DOF.
    pub coeffs: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// 2-norm of the residual at the solution.
    pub residual_norm: f64,
    /// Residual and step norms of every iteration.
    pub history: Vec<IterationRecord>,
}

/// The Euclidean norm (of residuals and steps).
pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Newton iterations on an existing [`Balance`], reusing its buffers and `lu`.
///
/// `a` holds the initial guess on entry and the last iterate on exit (converged or
/// not). `scale` is the residual scale for the residual test (the forcing norm).
pub fn newton(
    hb: &mut Balance<'_>,
    lu: &mut DenseLu,
    a: &mut [f64],
    omega: f64,
    opts: &SolveOptions,
    scale: f64,
) -> Result<(usize, f64, Vec<IterationRecord>)> {
    let len = hb.len();
    let mut r = vec![0.0; len];
    let mut trial = vec![0.0; len];
    let mut r_trial = vec![0.0; len];
    let mut step = vec![0.0; len];
    let mut history = Vec::new();
    let mut rn = f64::NAN;
    let mut last_step = 0.0;
    let mut damping = 1.0;
    for it in 0..=opts.max_iter {
        hb.jacobian(a, omega, &mut r, lu.matrix_mut());
        rn = norm(&r);
        history.push(IterationRecord {
            iteration: it,
            residual_norm: rn,
            step_norm: last_step,
            damping,
        });
        if !rn.is_finite() {
            break;
        }
        let an = norm(a);
        let step_ok = it > 0 && last_step <= opts.tol * an && damping == 1.0;
        if rn <= opts.tol * scale || step_ok {
            return Ok((it, rn, history));
        }
        if it == opts.max_iter {
            break;
        }
        let pivot_ratio = lu.factor();
        if pivot_ratio.is_nan() || pivot_ratio <= 1e-15 {
            return Err(Error::SingularJacobian {
                omega,
                detail: format!(
                    "pivot ratio {pivot_ratio:.2e} at iteration {it} (a fold in Ω, or a \
                     model without stiffness at some harmonic); use continuation"
                ),
            });
        }
        for (s, x) in step.iter_mut().zip(&r) {
            *s = -x;
        }
        lu.solve(&mut step);
        // backtracking: accept the first step length that does not increase ‖R‖
        damping = 1.0;
        for _ in 0..=opts.max_halvings {
            for ((t, x), s) in trial.iter_mut().zip(a.iter()).zip(&step) {
                *t = x + damping * s;
            }
            hb.residual(&trial, omega, &mut r_trial);
            let rt = norm(&r_trial);
            if rt.is_finite() && rt <= rn {
                break;
            }
            damping *= 0.5;
        }
        a.copy_from_slice(&trial);
        last_step = damping * norm(&step);
    }
    Err(Error::NotConverged {
        omega,
        iterations: history.len().saturating_sub(1),
        residual_norm: rn,
        last: a.to_vec(),
        history,
    })
}

/// Solve for the periodic steady state at `omega`, starting from `guess` or from the
/// linearized solution ([`linearized_guess`](crate::balance::linearized_guess)).
///
/// ```
/// use ihbm::corrector::{solve, SolveOptions};
/// use ihbm::models::QuarterCar;
/// let car = QuarterCar::default();
/// let sol = solve(&car, 8.0, &SolveOptions::default(), None).unwrap();
/// let z1 = &sol.outputs(&car)[0];
/// assert!((z1.max_abs - 0.02297).abs() < 1e-4);
/// ```
pub fn solve(
    model: &dyn DynModel,
    omega: f64,
    opts: &SolveOptions,
    guess: Option<&[f64]>,
) -> Result<Solution> {
    check_inputs(opts.harmonics, omega)?;
    if !(opts.tol > 0.0 && opts.tol.is_finite()) {
        return Err(Error::InvalidValue {
            what: "tolerance".into(),
            value: opts.tol.to_string(),
            expected: "a finite value > 0".into(),
        });
    }
    let mut hb = Balance::with_period(model, opts.harmonics, opts.period)?;
    hb.check_coefficients(omega)?;
    let len = hb.len();
    // the linearized guess computes R(0) on the way; with a user guess it costs one
    // residual evaluation
    let (mut a, r0) = match guess {
        Some(g) if g.len() != len => {
            return Err(Error::InvalidValue {
                what: "initial guess length".into(),
                value: g.len().to_string(),
                expected: format!("{len} = dofs x (2N + 1)"),
            })
        }
        Some(g) => {
            let mut r0 = vec![0.0; len];
            hb.residual(&vec![0.0; len], omega, &mut r0);
            (g.to_vec(), r0)
        }
        None => linearized_on(&mut hb, omega)?,
    };
    let scale = norm(&r0);
    let mut lu = DenseLu::new(len);
    let (iterations, residual_norm, history) =
        newton(&mut hb, &mut lu, &mut a, omega, opts, scale)?;
    Ok(Solution {
        omega,
        harmonics: opts.harmonics,
        period: opts.period,
        coeffs: a,
        iterations,
        residual_norm,
        history,
    })
}

/// The coefficient vector (`2N + 1`) of output `output` of the solution `coeffs` at
/// `at`.
pub fn output_coeffs(at: &At, coeffs: &[f64], harmonics: usize, output: usize) -> Vec<f64> {
    OutputEval::new(at.model, harmonics, at.period).coeffs(at, coeffs, output).to_vec()
}

/// Summaries (`max_abs`, mean, first-harmonic amplitude, RMS, extremes, coefficients)
/// of every output of the solution `coeffs` at `at`.
pub fn output_summaries(at: &At, coeffs: &[f64], harmonics: usize) -> Vec<OutputSummary> {
    OutputEval::new(at.model, harmonics, at.period).summaries(at, coeffs)
}

/// How the solution's coefficients move with each parameter of `params` (indices):
/// `dA/dθ = −J⁻¹ ∂R/∂θ`, the implicit derivative of `R(A, Ω, θ) = 0` at fixed Ω, with
/// the Jacobian factorised once and one back-substitution per parameter (`∂R/∂θ` from
/// dual numbers, through a fractional order's `(ikΩ)^p` too). `None` where the
/// Jacobian is singular (a fold in θ: the derivative does not exist there).
pub fn coefficient_rates(
    model: &dyn DynModel,
    sol: &Solution,
    params: &[usize],
) -> Result<Option<Vec<Vec<f64>>>> {
    let mut hb = Balance::with_period(model, sol.harmonics, sol.period)?;
    let n = hb.len();
    let mut lu = DenseLu::new(n);
    let mut r = vec![0.0; n];
    hb.jacobian(&sol.coeffs, sol.omega, &mut r, lu.matrix_mut());
    let pivots = lu.factor();
    if pivots.is_nan() || pivots <= 1e-15 {
        return Ok(None);
    }
    let mut rates = Vec::with_capacity(params.len());
    for &i in params {
        let mut d = vec![0.0; n];
        hb.d_param(&sol.coeffs, sol.omega, i, &mut d);
        d.iter_mut().for_each(|v| *v = -*v);
        lu.solve(&mut d);
        rates.push(d);
    }
    Ok(Some(rates))
}

impl Solution {
    /// The design sensitivities of every output's statistics: per parameter of
    /// `params` (indices), per output, the rates of change as the parameter moves and
    /// the solution follows it at fixed Ω ([`coefficient_rates`]); every rate `None`
    /// on a fold.
    ///
    /// ```
    /// use ihbm::corrector::{solve, SolveOptions};
    /// use ihbm::models::Duffing;
    /// use ihbm::Model;
    /// // Without its cubic spring the response is proportional to the force.
    /// let d = Duffing { k3: 0.0, ..Default::default() };
    /// let sol = solve(&d, 0.5, &SolveOptions::default(), None).unwrap();
    /// let f = d.param_index("F").unwrap();
    /// let rates = sol.output_rates(&d, &[f]).unwrap();
    /// let da = rates[0][0].amp1.unwrap();
    /// assert!((da - sol.outputs(&d)[0].amp1 / d.F).abs() < 1e-9 * da);
    /// ```
    pub fn output_rates(
        &self,
        model: &dyn DynModel,
        params: &[usize],
    ) -> Result<Vec<Vec<crate::results::OutputRates>>> {
        let values = model.param_values();
        let at = At { model, params: &values, omega: self.omega, period: self.period };
        let mut eval = OutputEval::new(model, self.harmonics, self.period);
        let outputs = model.outputs().len();
        let Some(rates) = coefficient_rates(model, self, params)? else {
            return Ok(vec![vec![crate::results::OutputRates::NONE; outputs]; params.len()]);
        };
        Ok(params
            .iter()
            .zip(&rates)
            .map(|(&i, dc)| {
                let dir =
                    crate::outputs::Direction { coeffs: dc, omega: 0.0, param: Some((i, 1.0)) };
                eval.rates(&at, &self.coeffs, &dir)
            })
            .collect())
    }

    /// Summaries of every output of `model` (the model this solution came from).
    pub fn outputs(&self, model: &dyn DynModel) -> Vec<OutputSummary> {
        let params = model.param_values();
        let at = At { model, params: &params, omega: self.omega, period: self.period };
        output_summaries(&at, &self.coeffs, self.harmonics)
    }
}
