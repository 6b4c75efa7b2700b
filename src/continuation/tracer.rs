//! The bordered Newton corrector and tangent in scaled variables.
//!
//! Unknowns are `y = [a / s_a, λ / s_λ]`: Fourier coefficients divided by a reference
//! amplitude and the continuation parameter divided by the length of its range, so
//! that a step of 0.05 means "5 % of the range" in λ and "5 % of the reference
//! response" in amplitude, whether amplitudes are micrometres or metres. Over a
//! positive range of three decades or more the parameter is continued as `ln λ`
//! divided by `ln 10`: 5 % is then 5 % of a decade (the largest step, 0.1 by default,
//! gives at least ten points per decade), and a sweep from 10⁻⁶ to 10⁶ no longer
//! takes steps of 10⁵ rad/s at its low end. Residuals are
//! divided by a reference force (the residual at zero response, i.e. the forcing).
//!
//! One LU of the `(n+1)×(n+1)` bordered matrix per Newton iteration (banded where
//! the model's coupling makes the Jacobian so: [`BorderedLu`]); the LU of the
//! last iteration also gives the tangent (`K t = e_{n+1}`), whose orientation follows
//! the border row automatically (`border · t > 0`). All buffers live here and are
//! reused across steps: the stepping loop does not allocate.

use crate::balance::Balance;
use crate::error::{Matrix, Quantity};
use crate::linalg::{BorderedLu, DenseLu};
use crate::results::Stall;

/// What is continued.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Axis {
    /// The forcing frequency.
    Omega,
    /// A model parameter (by index) at a fixed frequency.
    Param { index: usize, omega: f64 },
}

pub(crate) struct Tracer<'m> {
    pub bal: Balance<'m>,
    pub axis: Axis,
    /// Number of Fourier coefficients.
    pub n: usize,
    pub sa: f64,
    /// The unit of the continued coordinate: the range `hi - lo`, or with `log` one
    /// decade, `ln 10`.
    pub sl: f64,
    /// Continue in `ln λ` rather than `λ` (a range over many decades, where a step
    /// that suits one end is absurd at the other).
    pub log: bool,
    pub sr: f64,
    /// The range of the continuation parameter: nothing is evaluated outside it.
    pub range: (f64, f64),
    pub tol: f64,
    pub max_iter: usize,
    /// Newton iterations, all calls together.
    pub iterations: usize,
    /// Chord updates (residual only), all calls together.
    pub chord_steps: usize,
    lu: BorderedLu,
    rhs: Vec<f64>,
    r: Vec<f64>,
    dl: Vec<f64>,
    a: Vec<f64>,
}

impl<'m> Tracer<'m> {
    pub fn new(bal: Balance<'m>, axis: Axis, tol: f64, max_iter: usize) -> Self {
        let n = bal.len();
        let band = bal.jacobian_band();
        Tracer {
            bal,
            axis,
            n,
            sa: 1.0,
            sl: 1.0,
            log: false,
            sr: 1.0,
            range: (f64::NEG_INFINITY, f64::INFINITY),
            tol,
            max_iter,
            iterations: 0,
            chord_steps: 0,
            lu: BorderedLu::new(n, 1, Some(band)),
            rhs: vec![0.0; n + 1],
            r: vec![0.0; n],
            dl: vec![0.0; n],
            a: vec![0.0; n],
        }
    }

    /// The continuation parameter at `y`.
    pub fn lambda(&self, y: &[f64]) -> f64 {
        let u = y[self.n] * self.sl;
        if !self.log {
            return u;
        }
        // exp(ln lo) is lo only to rounding: the ends of the range are kept exact.
        let (lo, hi) = self.range;
        for end in [lo, hi] {
            if (u - end.ln()).abs() <= 4.0 * f64::EPSILON * end.ln().abs().max(1.0) {
                return end;
            }
        }
        u.exp()
    }

    /// The scaled coordinate `y[n]` of the parameter value `lam` (inverse of
    /// [`Tracer::lambda`]).
    pub fn scaled(&self, lam: f64) -> f64 {
        if self.log {
            lam.ln() / self.sl
        } else {
            lam / self.sl
        }
    }

    /// `dλ / dy[n]` at `y`.
    fn d_lambda(&self, y: &[f64]) -> f64 {
        if self.log {
            self.lambda(y) * self.sl
        } else {
            self.sl
        }
    }

    /// The forcing frequency at `y`.
    pub fn omega(&self, y: &[f64]) -> f64 {
        match self.axis {
            Axis::Omega => self.lambda(y),
            Axis::Param { omega, .. } => omega,
        }
    }

    /// The model's parameter values at `y` (the continued one's included).
    pub fn params_at(&self, y: &[f64]) -> Vec<f64> {
        let mut p = self.bal.params().to_vec();
        if let Axis::Param { index, .. } = self.axis {
            p[index] = self.lambda(y);
        }
        p
    }

    /// How `ω` and the continued parameter change as `y` moves along `t`:
    /// `(dω, Some((index, dθ)))` (coefficients aside, which [`Tracer::coeffs`] unscales).
    pub fn rates(&self, y: &[f64], t: &[f64]) -> (f64, Option<(usize, f64)>) {
        let dl = t[self.n] * self.d_lambda(y);
        match self.axis {
            Axis::Omega => (dl, None),
            Axis::Param { index, .. } => (0.0, Some((index, dl))),
        }
    }

    /// Unscaled coefficients of `y`.
    pub fn coeffs(&self, y: &[f64], out: &mut [f64]) {
        for (o, &v) in out.iter_mut().zip(&y[..self.n]) {
            *o = v * self.sa;
        }
    }

    /// Make `bal` evaluate at the parameter of `y` (parameter continuation only).
    pub fn set_point(&mut self, y: &[f64]) {
        if let Axis::Param { index, .. } = self.axis {
            let l = self.lambda(y);
            self.bal.set_param(index, l);
        }
    }

    /// Residual max-norm at zero response (the forcing): the reference force.
    pub fn reference_force(&mut self, lambda: f64) -> f64 {
        let omega = match self.axis {
            Axis::Omega => lambda,
            Axis::Param { index, omega } => {
                self.bal.set_param(index, lambda);
                omega
            }
        };
        self.a.fill(0.0);
        self.bal.residual(&self.a, omega, &mut self.r);
        self.r.iter().fold(0.0, |m: f64, v| m.max(v.abs()))
    }

    /// Unscaled coefficients of `y` into `self.a`, the parameter into `bal`; Ω. A
    /// parameter outside the range being traced (an iterate that overshoots, or Ω
    /// that would turn negative), or a point where a coefficient of the model is not
    /// finite, is an error: the model is never evaluated there.
    fn unscale(&mut self, y: &[f64]) -> Result<f64, Stall> {
        let n = self.n;
        for (a, &v) in self.a.iter_mut().zip(&y[..n]) {
            *a = v * self.sa;
        }
        let lam = self.lambda(y);
        let (lo, hi) = self.range;
        // The landing on the range end corrects onto it from inside; allow rounding.
        let slack = 1e-9 * (hi - lo);
        if !(lam >= lo - slack && lam <= hi + slack) {
            return Err(Stall::LeftRange { lo, hi, at: lam });
        }
        let omega = match self.axis {
            Axis::Omega => lam,
            Axis::Param { index, omega } => {
                self.bal.set_param(index, lam);
                omega
            }
        };
        // A coefficient that is not finite here ends the segment, naming it.
        self.bal.check_coefficients(omega)?;
        Ok(omega)
    }

    /// `y -= rhs` (the solved update); its max-norm, which must be finite. (`f64::max`
    /// ignores a NaN, so every component is checked: a NaN update once passed for a
    /// converged step and put NaN points on the curve.)
    fn apply(&self, y: &mut [f64], what: Quantity) -> Result<f64, Stall> {
        let mut dn = 0.0f64;
        let mut finite = true;
        for (yi, &d) in y.iter_mut().zip(&self.rhs) {
            *yi -= d;
            finite &= yi.is_finite();
            dn = dn.max(d.abs());
        }
        if !(finite && dn.is_finite()) {
            return Err(Stall::NonFinite { quantity: what, omega: self.omega(y) });
        }
        Ok(dn)
    }

    /// Fill the bordered matrix and the scaled residual at `y`.
    fn assemble(&mut self, y: &[f64], border: &[f64], target: f64) -> Result<(), Stall> {
        let n = self.n;
        let omega = self.unscale(y)?;
        let (cs, cl) = (self.sa / self.sr, self.d_lambda(y) / self.sr);
        if !self.bal.jacobian_into(&self.a, omega, &mut self.r, &mut self.lu.a_mut()) {
            // a parameter made the Jacobian wider than the band probed at the start
            self.lu.make_dense();
            self.bal.jacobian_into(&self.a, omega, &mut self.r, &mut self.lu.a_mut());
        }
        self.lu.a_mut().scale(cs);
        match self.axis {
            Axis::Omega => self.bal.d_omega(&self.a, omega, &mut self.dl),
            Axis::Param { index, .. } => self.bal.d_param(&self.a, omega, index, &mut self.dl),
        }
        self.dl.iter_mut().for_each(|v| *v *= cl);
        self.lu.set_border_column(0, &self.dl);
        self.lu.set_border_row(0, &border[..n]);
        self.lu.set_corner(0, 0, border[n]);
        for i in 0..n {
            self.rhs[i] = self.r[i] / self.sr;
        }
        self.rhs[n] = dot(border, y) - target;
        Ok(())
    }

    /// One bordered Newton step at `y` (updated in place); the max-norm of the step.
    pub fn newton_step(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
    ) -> Result<f64, Stall> {
        let n = self.n;
        self.iterations += 1;
        self.assemble(y, border, target)?;
        let res = self.rhs[..n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !res.is_finite() {
            return Err(Stall::NonFinite { quantity: Quantity::Residual, omega: self.omega(y) });
        }
        let pivots = self.lu.factor();
        if pivots.is_nan() || pivots <= 1e-15 {
            return Err(Stall::Singular { matrix: Matrix::Bordered, omega: self.omega(y) });
        }
        self.lu.solve(&mut self.rhs);
        self.apply(y, Quantity::NewtonStep)
    }

    /// One chord update at `y` with the LU of the last Newton step (residual only).
    fn chord_step(&mut self, y: &mut [f64], border: &[f64], target: f64) -> Result<f64, Stall> {
        let n = self.n;
        self.chord_steps += 1;
        let omega = self.unscale(y)?;
        self.bal.residual(&self.a, omega, &mut self.r);
        for i in 0..n {
            self.rhs[i] = self.r[i] / self.sr;
        }
        self.rhs[n] = dot(border, y) - target;
        self.lu.solve(&mut self.rhs);
        self.apply(y, Quantity::ChordStep)
    }

    /// Bordered Newton from `y` (overwritten) on `R = 0`, `border · y = target`.
    /// Returns the Newton iterations (Jacobians) used, or why it failed.
    ///
    /// After a Newton step of length `dn`, the LU at hand belongs to a point about
    /// `dn` from the solution, so *chord* updates with it (the residual solved with
    /// that LU: one residual evaluation, no Jacobian, no factorisation) contract the
    /// error by about `C·dn` each. From a good predictor one Newton step is then
    /// followed by a chord step or two; when a chord step contracts by less than a
    /// factor 10, Newton resumes. Converged when an update is below `tol`, so the
    /// error left is far below it. The tangent comes from that LU, off by about
    /// `dn`: harmless for prediction and step control ([`Tracer::locate_exact`] is
    /// for where it is not). At most `budget` Newton iterations (the path's step
    /// passes `max_iter`: a failure halves the step).
    pub fn correct(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
        budget: usize,
    ) -> Result<usize, Stall> {
        self.correct_to(y, border, target, true, budget)
    }

    /// [`Tracer::correct`] for a point that is located rather than stepped to (the
    /// first point, a stability change, a jump's landing): from an interpolated guess,
    /// with at least [`LOCATE_ITER`] iterations whatever `max_iter` is (a user may set
    /// that low to force small steps; a location has no smaller step to fall back on).
    pub fn locate(&mut self, y: &mut [f64], border: &[f64], target: f64) -> Result<usize, Stall> {
        self.correct_to(y, border, target, true, self.max_iter.max(LOCATE_ITER))
    }

    /// [`Tracer::locate`] with Newton steps only, so that the LU (and the tangent)
    /// belong to the converged point: for locating folds, where the tangent's
    /// λ-component is the unknown, and landing on the end of the range.
    pub fn locate_exact(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
    ) -> Result<usize, Stall> {
        self.correct_to(y, border, target, false, self.max_iter.max(LOCATE_ITER))
    }

    fn correct_to(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
        chord: bool,
        budget: usize,
    ) -> Result<usize, Stall> {
        let mut prev = f64::INFINITY;
        for it in 1..=budget {
            let dn = self.newton_step(y, border, target)?;
            if dn <= self.tol {
                return Ok(it);
            }
            if chord && dn < 1e-2 {
                let mut last = dn;
                for _ in 0..4 {
                    let dc = self.chord_step(y, border, target)?;
                    if dc <= self.tol {
                        return Ok(it);
                    }
                    if dc > 0.1 * last {
                        break;
                    }
                    last = dc;
                }
            }
            if let Some(why) = stalling(it, dn, prev, self.omega(y)) {
                return Err(why);
            }
            prev = dn;
        }
        Err(Stall::NoConvergence { iterations: budget, omega: self.omega(y) })
    }

    /// The unit tangent from the LU of the last `correct` (oriented along its border).
    pub fn tangent(&mut self, t: &mut [f64]) {
        let n = self.n;
        self.rhs.fill(0.0);
        self.rhs[n] = 1.0;
        self.lu.solve(&mut self.rhs);
        let norm = dot(&self.rhs, &self.rhs).sqrt();
        for (ti, &v) in t.iter_mut().zip(&self.rhs) {
            *ti = v / norm;
        }
    }
}

/// Why a Newton run at Ω stops early: from its third step on, an update `dn` more
/// than half the one before (`prev`) is not the quadratic convergence a correct
/// Jacobian gives near a solution, and more iterations will not help.
pub(crate) fn stalling(it: usize, dn: f64, prev: f64, omega: f64) -> Option<Stall> {
    (it >= 3 && dn > 0.5 * prev).then_some(Stall::NotContracting {
        omega,
        step: dn,
        previous: prev,
    })
}

/// Newton iterations allowed to the solves that locate a point (see
/// [`Tracer::locate`]); a run that stops contracting fails after 3 anyway.
pub const LOCATE_ITER: usize = 30;

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The Newton update of an extended system whose matrix is in `lu` and residual in
/// `rhs` (overwritten by the step): factor, solve, `y -= step`; the step's max-norm,
/// or why not (a singular matrix, a non-finite step) at Ω = `omega`.
pub(crate) fn newton_update(
    lu: &mut DenseLu,
    rhs: &mut [f64],
    y: &mut [f64],
    omega: f64,
) -> Result<f64, Stall> {
    if !rhs.iter().all(|v| v.is_finite()) {
        return Err(Stall::NonFinite { quantity: Quantity::Residual, omega });
    }
    let pivots = lu.factor();
    if pivots.is_nan() || pivots <= 1e-15 {
        return Err(Stall::Singular { matrix: Matrix::Extended, omega });
    }
    lu.solve(rhs);
    let mut dn = 0.0f64;
    for (yi, &d) in y.iter_mut().zip(rhs.iter()) {
        *yi -= d;
        dn = dn.max(d.abs());
    }
    if !(dn.is_finite() && y.iter().all(|v| v.is_finite())) {
        return Err(Stall::NonFinite { quantity: Quantity::NewtonStep, omega });
    }
    Ok(dn)
}

/// Newton's iteration of an extended system: `step(it, prev)` takes one step and
/// returns its max-norm, Ω there and whether the iterate has settled by a criterion of
/// its own; converged when the step is at most `tol` or settled, refused when it
/// stalls ([`stalling`]) or the budget runs out. The iterations used.
pub(crate) fn iterate(
    budget: usize,
    tol: f64,
    mut step: impl FnMut(usize, f64) -> Result<(f64, f64, bool), Stall>,
) -> Result<usize, Stall> {
    let (mut prev, mut omega) = (f64::INFINITY, f64::NAN);
    for it in 1..=budget {
        let (dn, w, settled) = step(it, prev)?;
        omega = w;
        if dn <= tol || settled {
            return Ok(it);
        }
        if let Some(why) = stalling(it, dn, prev, omega) {
            return Err(why);
        }
        prev = dn;
    }
    Err(Stall::NoConvergence { iterations: budget, omega })
}

/// The unit tangent of a curve, into `t` (of the matrix's order), from the LU (in
/// `lu`) of its last Newton matrix, whose last row is the arc-length condition.
pub(crate) fn unit_tangent(lu: &mut DenseLu, t: &mut [f64]) {
    let dim = t.len();
    t.fill(0.0);
    t[dim - 1] = 1.0;
    lu.solve(t);
    let norm = dot(t, t).sqrt();
    t.iter_mut().for_each(|v| *v /= norm);
}

/// The unit vector along the parameter axis (`n` coefficients, then the parameter).
pub(super) fn unit(n: usize) -> Vec<f64> {
    let mut e = vec![0.0; n + 1];
    e[n] = 1.0;
    e
}
