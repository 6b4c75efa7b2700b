//! The implicit stepper: Newmark average acceleration for the integer-order signals,
//! convolution quadrature for the fractional ones, Newton with a dual-number Jacobian.
//!
//! Unknowns of step `n → n+1` are the accelerations `a_{n+1}` of all DOFs. With
//! `β = 1/4`, `γ = 1/2` (trapezoidal rule, unconditionally stable, second order, no
//! numerical damping):
//!
//! ```text
//! x_{n+1} = x_n + dt v_n + dt²/4 a_n + dt²/4 a_{n+1}
//! v_{n+1} = v_n + dt/2 a_n + dt/2 a_{n+1}
//! D^q e(t_{n+1}) ≈ dt^-q (w_0 e_{n+1} + Σ_{k≤n} w_{n+1-k} e_k),   e = Σ c_d x_d
//! ```
//!
//! so every signal is `base + slope · Σ c_d a_{n+1,d}` with a scalar `slope` per signal
//! type (`dt²/4` for a displacement, `dt/2` for a velocity, `1` for an acceleration,
//! `dt^-q w_0 dt²/4` for a fractional derivative). Seeding the dual part of each
//! signal with `slope · c_d` and evaluating [`Model::residual`] once per DOF `d` gives
//! column `d` of the Jacobian `∂r/∂a_{n+1}` by the chain rule: no model derivative
//! is written by hand.
//!
//! **A start on a periodic solution** ([`Stepper::on_periodic`]): `x`, `v` at `t = 0`
//! are the solution's (plus a chosen displacement), and every fractional signal's
//! quadrature adds the part of its sum that lies before `t = 0`, the solution's own
//! past ([`PeriodicPast`]): unperturbed, the run stays on the discrete scheme's
//! periodic motion instead of starting a transient.
//!
//! **Caputo from rest** ([`Stepper::new`]). Integration starts at `t = 0` with `x = v = 0`. For
//! `0 < q < 2` the Caputo derivative subtracts the Taylor polynomial of degree
//! `⌈q⌉ - 1 ≤ 1` at 0, i.e. `e(0)` and `e'(0)` — both zero from rest — so Caputo and
//! Riemann–Liouville derivatives coincide and the plain convolution quadrature of the
//! displacement history (with `e_0 = 0`) needs no starting correction. The initial
//! acceleration solves the equations at `t = 0`, where every signal but the
//! accelerations vanishes (`D^q e(0) = 0` because `e ~ t²`).

use super::memory::{History, Memory};
use super::past::PeriodicPast;
use super::weights::Scheme;
use crate::error::Error;
use crate::fourier::{apply_order, eval};
use crate::model::{combine, combine_blocks, DynModel, Model, Order, OutputKind, Signal};
use num_dual::Dual64;

/// Newmark average acceleration parameters.
const BETA: f64 = 0.25;
const GAMMA: f64 = 0.5;

/// How one signal depends on the step's unknowns.
#[derive(Debug, Clone, Copy)]
enum Kind {
    Displacement,
    Velocity,
    Acceleration,
    /// Index into the histories; `scale = dt^-q`, `w0` the first weight.
    Fractional {
        history: usize,
        scale: f64,
        w0: f64,
    },
}

/// Settings of the stepper itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepperOptions {
    /// Time step, s.
    pub dt: f64,
    /// Largest number of steps this stepper will take (sizes the history buffers).
    pub steps: usize,
    /// Convolution-quadrature rule.
    pub scheme: Scheme,
    /// History evaluation.
    pub memory: Memory,
    /// Newton stops when the increment is below `newton_tol` times the acceleration
    /// scale (largest |a| seen).
    pub newton_tol: f64,
    /// Newton iterations allowed per step before the run is declared diverged.
    pub max_newton: usize,
}

impl StepperOptions {
    /// Defaults for everything but `dt` and `steps`.
    pub fn new(dt: f64, steps: usize) -> Self {
        StepperOptions {
            dt,
            steps,
            scheme: Scheme::default(),
            memory: Memory::default(),
            newton_tol: 1e-12,
            max_newton: 30,
        }
    }
}

/// A periodic solution to start a run on ([`Stepper::on_periodic`]), moved at `t = 0`
/// by `dx` and `dv`: the solution is taken to have run for all time before, so a
/// perturbation's growth or decay is the solution's stability, with no start-up
/// transient mixed in.
///
/// ```
/// use ihbm::timedomain::PeriodicStart;
/// // A harmonic-balance point's coefficients (here x = 0.1 cos Ωt, one DOF, N = 1),
/// // displaced by 1e-4.
/// let start = PeriodicStart { dx: vec![1e-4], ..PeriodicStart::new(vec![0.0, 0.1, 0.0], 1) };
/// assert_eq!(start.displacements(2.0, 0.0), vec![0.1]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicStart {
    /// Fourier coefficients, `[a0, a1..aN, b1..bN]` per DOF, of `ω = Ω/period` (a
    /// curve point's `coeffs`).
    pub coeffs: Vec<f64>,
    /// The number of harmonics N of `coeffs`.
    pub harmonics: usize,
    /// Forcing periods per period of the solution (1; 2 on a period-doubled branch).
    pub period: usize,
    /// Displacement added to each DOF at `t = 0` (empty: none).
    pub dx: Vec<f64>,
    /// Velocity added to each DOF at `t = 0` (empty: none).
    pub dv: Vec<f64>,
}

impl PeriodicStart {
    /// The solution `coeffs` with `harmonics` harmonics of the forcing frequency,
    /// unperturbed.
    pub fn new(coeffs: Vec<f64>, harmonics: usize) -> Self {
        PeriodicStart { coeffs, harmonics, period: 1, dx: Vec::new(), dv: Vec::new() }
    }

    /// Each DOF's displacement on the periodic solution at time `t` (forcing
    /// frequency `omega`): what a run started on it is measured against.
    pub fn displacements(&self, omega: f64, t: f64) -> Vec<f64> {
        let len = self.harmonics.saturating_mul(2).saturating_add(1);
        let theta = omega / self.period.max(1) as f64 * t;
        self.coeffs.chunks_exact(len).map(|b| eval(b, theta)).collect()
    }

    /// Refuse a start that does not fit `ndof` DOFs or is not finite.
    pub(super) fn check(&self, ndof: usize) -> Result<(), Error> {
        let invalid = |what: &str, value: String, expected: String| Error::InvalidValue {
            what: what.into(),
            value,
            expected,
        };
        let len = self.harmonics.checked_mul(2).and_then(|n| (n + 1).checked_mul(ndof));
        if Some(self.coeffs.len()) != len {
            let len = len.map_or("more than memory holds".into(), |l| l.to_string());
            return Err(invalid(
                "periodic start coefficients",
                format!("{} values", self.coeffs.len()),
                format!("{len}: {ndof} DOFs × (2·{} + 1) harmonics coefficients", self.harmonics),
            ));
        }
        if self.period == 0 {
            return Err(invalid("periodic start period", "0".into(), "at least 1".into()));
        }
        for (what, v) in [("periodic start dx", &self.dx), ("periodic start dv", &self.dv)] {
            if !v.is_empty() && v.len() != ndof {
                return Err(invalid(
                    what,
                    format!("{} values", v.len()),
                    format!("none, or one per DOF ({ndof})"),
                ));
            }
        }
        if let Some(bad) =
            self.coeffs.iter().chain(&self.dx).chain(&self.dv).find(|v| !v.is_finite())
        {
            return Err(invalid(
                "periodic start",
                bad.to_string(),
                "finite coefficients and displacements".into(),
            ));
        }
        Ok(())
    }
}

/// A time integrator for one model at one forcing frequency, started from rest
/// ([`Stepper::new`]) or on a periodic solution ([`Stepper::on_periodic`]).
///
/// ```
/// use ihbm::models::FractionalDuffing;
/// use ihbm::timedomain::{Stepper, StepperOptions};
/// let model = FractionalDuffing::default();
/// let mut s = Stepper::new(&model, 1.0, &StepperOptions::new(0.01, 1000)).unwrap();
/// for _ in 0..1000 { s.step().unwrap(); }
/// assert!((s.time() - 10.0).abs() < 1e-12);
/// assert!(s.displacements()[0].abs() < 2.0);
/// ```
pub struct Stepper<'m> {
    model: &'m dyn DynModel,
    params: Vec<Dual64>,
    omega: f64,
    dt: f64,
    steps: usize,
    step: usize,
    newton_tol: f64,
    max_newton: usize,
    x: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    kinds: Vec<Kind>,
    histories: Vec<History>,
    /// Per history, the part of its sum before `t = 0` (a start on a periodic solution).
    pasts: Vec<Option<PeriodicPast>>,
    /// Per signal: value at zero acceleration, and slope w.r.t. its combination of a.
    base: Vec<f64>,
    slope: Vec<f64>,
    sig: Vec<Dual64>,
    res: Vec<Dual64>,
    jac: Vec<f64>,
    r: Vec<f64>,
    a_new: Vec<f64>,
    x_new: Vec<f64>,
    v_new: Vec<f64>,
    a_scale: f64,
    newton_total: usize,
    newton_max: usize,
    /// The parameter values (plain numbers, for the outputs).
    params_f: Vec<f64>,
    /// The output signals: how each is obtained, the memory of the fractional ones,
    /// and their values at the current state.
    out_kinds: Vec<Kind>,
    out_histories: Vec<History>,
    out_pasts: Vec<Option<PeriodicPast>>,
    out_sig: Vec<f64>,
    /// The expression outputs at the current state.
    expressions: Vec<f64>,
}

/// The memories of a list of fractional signals.
#[derive(Default)]
struct Memories {
    histories: Vec<History>,
    pasts: Vec<Option<PeriodicPast>>,
}

/// What every signal list is set up from: the parameters, the options, the periodic
/// start (its coefficients, `ω`, and coefficient length) and the displacements at `t = 0`.
struct Start<'a> {
    params: &'a [f64],
    opts: &'a StepperOptions,
    base: Option<(&'a PeriodicStart, f64, usize)>,
    x0: &'a [f64],
}

impl Start<'_> {
    /// How each of `signals` is obtained, with a memory (in `mem`) for each
    /// fractional one, `e_0` in it; `what` names the list in errors.
    fn kinds(
        &self,
        signals: &[Signal],
        what: &str,
        mem: &mut Memories,
    ) -> Result<Vec<Kind>, Error> {
        let (dt, opts) = (self.opts.dt, self.opts);
        let mut kinds = Vec::with_capacity(signals.len());
        for s in signals {
            let kind = match s.order {
                Order::Int(0) => Kind::Displacement,
                Order::Int(1) => Kind::Velocity,
                Order::Int(2) => Kind::Acceleration,
                Order::Int(n) => {
                    return Err(Error::InvalidValue {
                        what: format!("{what} derivative order"),
                        value: n.to_string(),
                        expected: "0, 1, 2 or a fractional order: the time integrator \
                                   (Newmark) carries no state for higher derivatives"
                            .into(),
                    })
                }
                Order::Param(i) => {
                    let q = self.params[i];
                    let w = opts.scheme.weights(q, opts.steps + 1);
                    let w0 = w[0];
                    mem.pasts.push(self.base.map(|(p, w_base, len)| {
                        let mut e = vec![0.0; len];
                        combine_blocks(&s.terms, &p.coeffs, &mut e);
                        PeriodicPast::new(&e, w_base, dt, q, opts.scheme, opts.memory, w.clone())
                    }));
                    let mut h = History::new(opts.memory, w);
                    h.push(combine(&s.terms, self.x0))?; // e_0 (0 from rest)
                    mem.histories.push(h);
                    Kind::Fractional { history: mem.histories.len() - 1, scale: dt.powf(-q), w0 }
                }
            };
            kinds.push(kind);
        }
        Ok(kinds)
    }
}

impl std::fmt::Debug for Stepper<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stepper")
            .field("model", &self.model.name())
            .field("omega", &self.omega)
            .field("dt", &self.dt)
            .field("step", &self.step)
            .finish()
    }
}

impl<'m> Stepper<'m> {
    /// Set up the integrator and solve for the initial acceleration at `t = 0`.
    ///
    /// Errors: an integer signal order above 2 (Newmark has no state for it),
    /// a fractional order outside `[0, 2]`, a non-finite or non-positive `dt`, or an
    /// initial acceleration that cannot be solved for.
    pub fn new(model: &'m dyn DynModel, omega: f64, opts: &StepperOptions) -> Result<Self, Error> {
        Self::start(model, omega, opts, None)
    }

    /// Set up the integrator on the periodic solution `start` (moved by its `dx`,
    /// `dv`), as if it had run for all time before `t = 0`, and solve for the
    /// acceleration at `t = 0`. Unmoved, the run stays on the solution to the scheme's
    /// consistency error (for a linear model on the scheme's own periodic motion,
    /// exactly); moved, the distance grows at an unstable solution and fades at a
    /// stable one.
    ///
    /// Errors: those of [`Stepper::new`], and a start whose coefficients do not fit
    /// the model's DOFs and harmonics, or are not finite.
    ///
    /// ```
    /// use ihbm::corrector::{solve, SolveOptions};
    /// use ihbm::models::FractionalDuffing;
    /// use ihbm::timedomain::{PeriodicStart, Stepper, StepperOptions};
    /// let model = FractionalDuffing::default();
    /// let (omega, nh) = (1.0, 5);
    /// let sol = solve(&model, omega, &SolveOptions { harmonics: nh, ..Default::default() }, None).unwrap();
    /// let start = PeriodicStart::new(sol.coeffs.clone(), nh);
    /// let dt = std::f64::consts::TAU / omega / 400.0;
    /// let mut s = Stepper::on_periodic(&model, omega, &start, &StepperOptions::new(dt, 4000)).unwrap();
    /// for _ in 0..4000 { s.step().unwrap(); }
    /// // Ten periods on, still on the harmonic-balance solution (no start-up transient).
    /// let on = start.displacements(omega, s.time())[0];
    /// assert!((s.displacements()[0] - on).abs() < 1e-4 * on.abs().max(0.1));
    /// ```
    pub fn on_periodic(
        model: &'m dyn DynModel,
        omega: f64,
        start: &PeriodicStart,
        opts: &StepperOptions,
    ) -> Result<Self, Error> {
        start.check(model.dofs().len())?;
        Self::start(model, omega, opts, Some(start))
    }

    fn start(
        model: &'m dyn DynModel,
        omega: f64,
        opts: &StepperOptions,
        periodic: Option<&PeriodicStart>,
    ) -> Result<Self, Error> {
        model.validate()?;
        if !(opts.dt.is_finite() && opts.dt > 0.0) {
            return Err(Error::InvalidValue {
                what: "time step dt".into(),
                value: opts.dt.to_string(),
                expected: "a finite number > 0 (s)".into(),
            });
        }
        if !(opts.newton_tol.is_finite() && opts.newton_tol > 0.0) {
            return Err(Error::InvalidValue {
                what: "Newton tolerance".into(),
                value: opts.newton_tol.to_string(),
                expected: "a finite number > 0 (relative, default 1e-12)".into(),
            });
        }
        if !omega.is_finite() {
            return Err(Error::InvalidValue {
                what: "omega".into(),
                value: omega.to_string(),
                expected: "a finite frequency in rad/s".into(),
            });
        }
        let params_f = model.param_values();
        model.check_coefficients(&params_f, omega)?;
        let dt = opts.dt;
        let n = model.dofs().len();
        // The state at t = 0: rest, or the periodic solution's (moved).
        let (mut x0, mut v0) = (vec![0.0; n], vec![0.0; n]);
        let base = periodic.map(|p| (p, omega / p.period as f64, 2 * p.harmonics + 1));
        if let Some((p, w, len)) = base {
            let mut d = vec![0.0; len];
            for (i, b) in p.coeffs.chunks_exact(len).enumerate() {
                apply_order(b, 1.0, w, &mut d);
                x0[i] = eval(b, 0.0) + p.dx.get(i).copied().unwrap_or(0.0);
                v0[i] = eval(&d, 0.0) + p.dv.get(i).copied().unwrap_or(0.0);
            }
        }
        let start = Start { params: &params_f, opts, base, x0: &x0 };
        let mut eq = Memories::default();
        let kinds = start.kinds(model.signals(), "signal", &mut eq)?;
        let mut out = Memories::default();
        let out_kinds = start.kinds(model.output_signals(), "output signal", &mut out)?;
        let nsig = kinds.len();
        let expressions = model
            .outputs()
            .iter()
            .filter_map(|o| match o.kind {
                OutputKind::Expression(i) => Some(i + 1),
                OutputKind::Dofs(_) => None,
            })
            .max()
            .unwrap_or(0);
        let mut s = Stepper {
            model,
            params: params_f.iter().map(|&p| Dual64::new(p, 0.0)).collect(),
            out_sig: vec![0.0; out_kinds.len()],
            out_kinds,
            out_histories: out.histories,
            out_pasts: out.pasts,
            expressions: vec![0.0; expressions],
            params_f,
            omega,
            dt,
            steps: opts.steps,
            step: 0,
            newton_tol: opts.newton_tol,
            max_newton: opts.max_newton.max(1),
            x: x0,
            v: v0,
            a: vec![0.0; n],
            kinds,
            histories: eq.histories,
            pasts: eq.pasts,
            base: vec![0.0; nsig],
            slope: vec![0.0; nsig],
            sig: vec![Dual64::new(0.0, 0.0); nsig],
            res: vec![Dual64::new(0.0, 0.0); n],
            jac: vec![0.0; n * n],
            r: vec![0.0; n],
            a_new: vec![0.0; n],
            x_new: vec![0.0; n],
            v_new: vec![0.0; n],
            a_scale: 0.0,
            newton_total: 0,
            newton_max: 0,
        };
        // t = 0: every signal but the accelerations is known (from rest, zero).
        for (i, sig) in model.signals().iter().enumerate() {
            let (base, slope) = match s.kinds[i] {
                Kind::Displacement => (combine(&sig.terms, &s.x), 0.0),
                Kind::Velocity => (combine(&sig.terms, &s.v), 0.0),
                Kind::Acceleration => (0.0, 1.0),
                Kind::Fractional { history, scale, w0 } => {
                    let past = match s.pasts[history].as_mut() {
                        Some(p) => p.tail()?,
                        None => 0.0,
                    };
                    (scale * (w0 * combine(&sig.terms, &s.x) + past), 0.0)
                }
            };
            s.base[i] = base;
            s.slope[i] = slope;
        }
        s.solve(0.0, true)?;
        for p in s.pasts.iter_mut().flatten() {
            p.advance()?;
        }
        s.record_outputs(true)?;
        Ok(s)
    }

    /// The output signals and the expression outputs at the state just committed
    /// (`initial`: at `t = 0`, whose fractional values the start set up).
    fn record_outputs(&mut self, initial: bool) -> Result<(), Error> {
        if self.expressions.is_empty() {
            return Ok(());
        }
        for (i, s) in self.model.output_signals().iter().enumerate() {
            let comb = |y: &[f64]| combine(&s.terms, y);
            self.out_sig[i] = match self.out_kinds[i] {
                Kind::Displacement => comb(&self.x),
                Kind::Velocity => comb(&self.v),
                Kind::Acceleration => comb(&self.a),
                Kind::Fractional { history, scale, w0 } => {
                    let e = comb(&self.x);
                    // The lag sum over e_0 .. e_{n-1}, before e_n joins it (at t = 0 the
                    // history holds e_0 alone and there is no lag).
                    let mut h =
                        if initial { 0.0 } else { self.out_histories[history].lag_sum()? };
                    if let Some(p) = self.out_pasts[history].as_mut() {
                        h += p.tail()?;
                        p.advance()?;
                    }
                    if !initial {
                        self.out_histories[history].push(e)?;
                    }
                    scale * (w0 * e + h)
                }
            };
        }
        let phase = self.omega * self.time();
        self.model.output_values::<f64>(
            &self.params_f,
            self.omega,
            phase,
            &self.out_sig,
            &mut self.expressions,
        );
        Ok(())
    }

    /// Advance one step (allocation-free). On failure the state is left at the last
    /// good step and the error is [`Error::Diverged`] with the time it happened.
    pub fn step(&mut self) -> Result<(), Error> {
        let m = self.step + 1;
        let t = m as f64 * self.dt;
        if m > self.steps {
            return Err(Error::Diverged {
                time: t,
                detail: format!("more than the {} steps the integrator was set up for", self.steps),
            });
        }
        let (dt, dt2) = (self.dt, self.dt * self.dt);
        // Predictors (the part of x_{n+1}, v_{n+1} known before a_{n+1}).
        for d in 0..self.x.len() {
            self.x_new[d] = self.x[d] + dt * self.v[d] + (0.5 - BETA) * dt2 * self.a[d];
            self.v_new[d] = self.v[d] + (1.0 - GAMMA) * dt * self.a[d];
        }
        let signals = self.model.signals();
        for (i, s) in signals.iter().enumerate() {
            let comb = |y: &[f64]| combine(&s.terms, y);
            let (base, slope) = match self.kinds[i] {
                Kind::Displacement => (comb(&self.x_new), BETA * dt2),
                Kind::Velocity => (comb(&self.v_new), GAMMA * dt),
                Kind::Acceleration => (0.0, 1.0),
                Kind::Fractional { history, scale, w0 } => {
                    let mut h = self.histories[history].lag_sum()?;
                    if let Some(p) = self.pasts[history].as_mut() {
                        h += p.tail()?;
                    }
                    (scale * (w0 * comb(&self.x_new) + h), scale * w0 * BETA * dt2)
                }
            };
            self.base[i] = base;
            self.slope[i] = slope;
        }
        self.solve(t, false)?;
        self.record_outputs(false)
    }

    /// Newton on `a_{n+1}` for the current `base`/`slope`, then commit the step
    /// (`initial`: the acceleration at t = 0, nothing to commit but `a`).
    fn solve(&mut self, t: f64, initial: bool) -> Result<(), Error> {
        let n = self.x.len();
        let signals = self.model.signals();
        let phase = self.omega * t;
        let omega = Dual64::new(self.omega, 0.0);
        // Predictor for the unknown: the previous acceleration.
        self.a_new.copy_from_slice(&self.a);
        let mut converged = false;
        let mut iterations = 0;
        let mut last_step = f64::NAN;
        while iterations < self.max_newton {
            iterations += 1;
            for d in 0..n {
                for (i, s) in signals.iter().enumerate() {
                    let mut comb = 0.0;
                    let mut dcomb = 0.0;
                    for &(k, c) in s.terms.iter() {
                        comb += c * self.a_new[k];
                        if k == d {
                            dcomb += c;
                        }
                    }
                    self.sig[i] =
                        Dual64::new(self.base[i] + self.slope[i] * comb, self.slope[i] * dcomb);
                }
                self.model.residual(&self.params, omega, phase, &self.sig, &mut self.res);
                for e in 0..n {
                    self.jac[e * n + d] = self.res[e].eps;
                }
            }
            for (r, res) in self.r.iter_mut().zip(&self.res) {
                *r = res.re;
            }
            if self.r.iter().any(|r| !r.is_finite()) {
                return Err(Error::Diverged {
                    time: t,
                    detail: "the residual is not finite: the state overflowed".into(),
                });
            }
            if !solve_dense(&mut self.jac, &mut self.r, n) {
                let detail = if initial {
                    "the equations at t = 0 do not determine the initial accelerations \
                     (singular Jacobian): every DOF needs an inertia term D(x, 2)"
                } else {
                    "singular or non-finite Jacobian of the step equations"
                };
                return Err(Error::Diverged { time: t, detail: detail.into() });
            }
            let mut step_norm = 0.0f64;
            let mut a_norm = 0.0f64;
            for (a, r) in self.a_new.iter_mut().zip(&self.r) {
                *a -= r;
                step_norm = step_norm.max(r.abs());
                a_norm = a_norm.max(a.abs());
            }
            last_step = step_norm;
            if !(step_norm.is_finite() && a_norm.is_finite()) {
                break;
            }
            if step_norm <= self.newton_tol * a_norm.max(self.a_scale) {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(Error::Diverged {
                time: t,
                detail: format!(
                    "Newton did not converge in {iterations} iterations (last increment \
                     {last_step:.3e}): the response is escaping or dt is too large"
                ),
            });
        }
        // Commit (the Newmark relations), unless the new state is not finite.
        let (dt, dt2) = (self.dt, self.dt * self.dt);
        if !initial {
            for d in 0..n {
                self.x_new[d] = self.x[d]
                    + dt * self.v[d]
                    + (0.5 - BETA) * dt2 * self.a[d]
                    + BETA * dt2 * self.a_new[d];
                self.v_new[d] =
                    self.v[d] + (1.0 - GAMMA) * dt * self.a[d] + GAMMA * dt * self.a_new[d];
            }
            if self.x_new.iter().chain(&self.v_new).any(|v| !v.is_finite()) {
                return Err(Error::Diverged { time: t, detail: "non-finite state".into() });
            }
            self.x.copy_from_slice(&self.x_new);
            self.v.copy_from_slice(&self.v_new);
        }
        self.a.copy_from_slice(&self.a_new);
        self.a_scale = self.a.iter().fold(self.a_scale, |m, a| m.max(a.abs()));
        self.newton_total += iterations;
        self.newton_max = self.newton_max.max(iterations);
        if !initial {
            for (kind, s) in self.kinds.iter().zip(signals) {
                if let Kind::Fractional { history, .. } = *kind {
                    let e = combine(&s.terms, &self.x);
                    self.histories[history].push(e)?;
                    if let Some(p) = self.pasts[history].as_mut() {
                        p.advance()?;
                    }
                }
            }
            self.step += 1;
        }
        Ok(())
    }

    /// Time of the current state, s.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    /// Steps taken so far.
    pub fn steps_taken(&self) -> usize {
        self.step
    }

    /// DOF displacements of the current state.
    pub fn displacements(&self) -> &[f64] {
        &self.x
    }

    /// DOF velocities of the current state.
    pub fn velocities(&self) -> &[f64] {
        &self.v
    }

    /// DOF accelerations of the current state.
    pub fn accelerations(&self) -> &[f64] {
        &self.a
    }

    /// The value of output `index` at the current state.
    pub fn output(&self, index: usize) -> f64 {
        match &self.model.outputs()[index].kind {
            OutputKind::Dofs(terms) => combine(terms, &self.x),
            OutputKind::Expression(i) => self.expressions[*i],
        }
    }

    /// Newton iterations: total over all steps, and the most in one step.
    pub fn newton_iterations(&self) -> (usize, usize) {
        (self.newton_total, self.newton_max)
    }

    /// The displacement histories `e_0 ..= e_n` of the fractional signals, in signal order.
    pub fn fractional_histories(&self) -> impl Iterator<Item = &[f64]> {
        self.histories.iter().map(|h| h.values())
    }
}

/// Solve `J x = r` in place (`J` row-major `n × n`, overwritten; `r` becomes `x`) by
/// Gaussian elimination with partial pivoting. `false` if singular or not finite.
fn solve_dense(j: &mut [f64], r: &mut [f64], n: usize) -> bool {
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..n {
            if j[row * n + col].abs() > j[piv * n + col].abs() {
                piv = row;
            }
        }
        let p = j[piv * n + col];
        if p == 0.0 || !p.is_finite() {
            return false;
        }
        if piv != col {
            for k in 0..n {
                j.swap(col * n + k, piv * n + k);
            }
            r.swap(col, piv);
        }
        for row in col + 1..n {
            let f = j[row * n + col] / p;
            if f != 0.0 {
                for k in col..n {
                    j[row * n + k] -= f * j[col * n + k];
                }
                r[row] -= f * r[col];
            }
        }
    }
    for col in (0..n).rev() {
        let mut s = r[col];
        for k in col + 1..n {
            s -= j[col * n + k] * r[k];
        }
        r[col] = s / j[col * n + col];
    }
    r.iter().all(|v| v.is_finite())
}
