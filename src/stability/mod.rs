//! Stability of periodic solutions: Hill's method, extended to fractional orders.
//!
//! A solution is perturbed and the equations linearised; a perturbation `e^{λt} p(t)`,
//! `p` periodic in `N` harmonics, solves the nonlinear eigenproblem
//! `T(λ) v = 0` whose factors `(λ + ikΩ)^q` are polynomial for integer orders and
//! fractional powers otherwise. The `q_max · ndof` central exponents decide stability
//! (unstable iff one has `Re λ > tol · Ω`). The derivation, the choice of one copy of
//! each exponent, the fractional refinement and the tracking along a curve with its
//! fallback rules are in the book's *Continuation* chapter (*Stability*).
//!
//! One idea per part, each with its own workspace: `operator` (`T(λ)`, `T'(λ)`:
//! `Operator`), `eigensolve` (companion eigenvalues and eigenvectors: `Companion`),
//! `selection` (one copy of each exponent: `Selection`), `refinement` (roots of the
//! nonlinear problem: `Scratch`), `tracking` (along a curve: `Tracker`),
//! `exponents` (arithmetic modulo `iΩ`, the verdict), `count` (roots of `det T` by the
//! argument principle and by sign changes on the real axis: the verdict where a
//! refinement failed, and the real exponent a fractional fold leaves). [`Hill`] holds
//! one of each and runs them in order; the complex LU is [`crate::linalg`]'s, shared
//! with balance.

mod count;
mod eigensolve;
mod exponents;
mod operator;
mod refinement;
mod selection;
mod tracking;

use exponents::*;
use selection::*;

use crate::balance::Balance;
use crate::error::{Error, Result};
use crate::model::{DynModel, Model, Order};
use crate::results::BifurcationKind;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::{Mat, Par};
use num_complex::Complex64;

/// Settings of the stability analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilityOptions {
    /// A solution is unstable iff some central exponent has `Re λ > tol · Ω`.
    pub tol: f64,
    /// Refine fractional-order candidates on the nonlinear eigenproblem.
    pub refine: bool,
    /// Iteration limit of the refinement (per exponent).
    pub max_refine_iter: usize,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions { tol: 1e-7, refine: true, max_refine_iter: 30 }
    }
}

/// How a solution loses (or gains) stability: the exponent that crosses `Re λ = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Crossing {
    /// A real exponent (Floquet multiplier +1): fold or branch point.
    Real,
    /// An exponent at `Im λ = ±Ω/2` (multiplier -1): period doubling.
    PeriodDoubling,
    /// A complex pair elsewhere (multipliers on the unit circle): Neimark–Sacker.
    Torus,
}

// The mapping lives with `Crossing`: the result vocabulary imports no solver.
impl BifurcationKind {
    /// The kind of a change of stability off a fold, from how the unstable side's
    /// leading exponent lies ([`Floquet::leading_crossing`]);
    /// `None` where no exponent shows the root that crossed (a counted verdict):
    /// [`BifurcationKind::StabilityChange`].
    ///
    /// ```
    /// use ihbm::results::BifurcationKind;
    /// use ihbm::stability::Crossing;
    ///
    /// assert_eq!(BifurcationKind::of_crossing(Some(Crossing::Real)), BifurcationKind::BranchPoint);
    /// assert_eq!(BifurcationKind::of_crossing(None).to_string(), "stability-change");
    /// ```
    pub fn of_crossing(crossing: Option<Crossing>) -> BifurcationKind {
        match crossing {
            Some(Crossing::Real) => BifurcationKind::BranchPoint,
            Some(Crossing::PeriodDoubling) => BifurcationKind::PeriodDoubling,
            Some(Crossing::Torus) => BifurcationKind::Torus,
            None => BifurcationKind::StabilityChange,
        }
    }
}

/// The central Floquet exponents of one periodic solution and the verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Floquet {
    /// Central exponents (`|Im λ| ≤ Ω/2`), sorted by decreasing real part.
    pub exponents: Vec<Complex64>,
    /// Largest real part (`-inf` if there are none).
    pub max_real: f64,
    /// `true` iff no exponent has `Re λ > tol · Ω`.
    pub stable: bool,
    /// `false` if some fractional candidate did not converge in the refinement: a full
    /// analysis reports its frozen-order value; a point [`Hill::track`] continued from
    /// such an analysis (a *partial set*) reports only the roots that did refine, and
    /// its verdict is [`counted`](Floquet::counted) unless one of them is unstable.
    /// Always `true` for integer-order models.
    pub refined: bool,
    /// The verdict `stable` comes from counting the roots of `det T(λ)` with
    /// `Re λ > tol · Ω` in the central strip (the argument principle), not from
    /// `exponents`: a candidate did not refine, so the largest real part is not known,
    /// and no refined exponent was unstable. `max_real` then says nothing about the
    /// distance to the threshold.
    pub counted: bool,
}

impl Floquet {
    /// The kind of the exponent with the largest real part, relative to Ω.
    pub fn leading_crossing(&self, omega: f64) -> Option<Crossing> {
        let l = self.exponents.first()?;
        let im = l.im.abs();
        Some(if im < 1e-6 * omega {
            Crossing::Real
        } else if (im - omega / 2.0).abs() < 1e-6 * omega {
            Crossing::PeriodDoubling
        } else {
            Crossing::Torus
        })
    }
}

/// Reusable workspace for Hill's method on one model and harmonic count.
///
/// ```
/// use ihbm::balance::Balance;
/// use ihbm::corrector::{solve, SolveOptions};
/// use ihbm::models::Duffing;
/// use ihbm::stability::{Hill, StabilityOptions};
///
/// // Far below resonance a damped Duffing oscillator is stable.
/// let model = Duffing::default();
/// let opts = SolveOptions { harmonics: 3, ..Default::default() };
/// let sol = solve(&model, 0.3, &opts, None).unwrap();
/// let mut bal = Balance::new(&model, 3).unwrap();
/// let mut hill = Hill::new(&model, 3).unwrap();
/// let f = hill.analyse(&mut bal, &sol.coeffs, 0.3, &StabilityOptions::default()).unwrap();
/// assert!(f.stable);
/// assert_eq!(f.exponents.len(), 2);
/// // Linear limit: the exponents of m x'' + c x' + k_eff x are -c/2m ± i(...)
/// assert!((f.exponents[0].re + 0.05).abs() < 1e-3);
/// ```
pub struct Hill {
    /// `T(λ)` and what it is made of (see [`operator::Operator`]).
    op: operator::Operator,
    /// The companion eigensolve's matrices and workspace.
    eig: eigensolve::Companion,
    /// The full analysis's candidates, the kept ones and their refined roots.
    sel: selection::Selection,
    /// Scratch of the nonlinear iteration (pivots, solution, adjoint vector).
    nw: refinement::Scratch,
    /// The exponents carried along a curve and the counts.
    tr: tracking::Tracker,
}

/// How many points [`Hill::track`] analysed in full and how many it tracked.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TrackCounts {
    /// Points with the full eigensolve (first points, fallbacks).
    pub full: usize,
    /// Points whose exponents were tracked from the previous point.
    pub tracked: usize,
}

impl Hill {
    /// A workspace for `model` truncated at `harmonics` harmonics.
    pub fn new(model: &dyn DynModel, harmonics: usize) -> Result<Hill> {
        Self::with_period(model, harmonics, 1)
    }

    /// [`Hill::new`] for the balance of solutions of `period` forcing periods
    /// ([`Balance::with_period`](crate::balance::Balance::with_period)), whose samples it
    /// shares.
    pub fn with_period(model: &dyn DynModel, harmonics: usize, period: usize) -> Result<Hill> {
        crate::fourier::check_harmonics(harmonics)?;
        crate::fourier::check_samples(model, harmonics, period)?;
        let ndof = model.dofs().len();
        crate::balance::check_size(ndof, harmonics)?;
        check_size(model, harmonics)?;
        let op = operator::Operator::new(model, harmonics, period, degree(model));
        let (m, big) = (op.m, op.degree * op.m);
        Ok(Hill {
            eig: eigensolve::Companion::new(m, big),
            sel: selection::Selection::new(big),
            nw: refinement::Scratch::new(m),
            tr: tracking::Tracker::default(),
            op,
        })
    }

    /// The projections at the solution `coeffs` ([`operator::Operator::project_gradients`]);
    /// a change between integer and fractional orders forgets the tracked exponents
    /// (they were of the other kind of problem).
    fn project(&mut self, bal: &mut Balance<'_>, coeffs: &[f64], omega: f64) -> Result<()> {
        if self.op.project_gradients(bal, coeffs, omega)? {
            self.tr.state = None;
        }
        Ok(())
    }

    /// Number of central exponents (`degree · ndof`).
    pub fn central_count(&self) -> usize {
        self.op.degree * self.op.ndof
    }

    /// Floquet exponents and stability of the solution `coeffs` at frequency `omega`
    /// (parameters as currently set in `bal`): the full analysis, a companion
    /// eigensolve at every call. Along a curve, [`Hill::track`] is much cheaper.
    pub fn analyse(
        &mut self,
        bal: &mut Balance<'_>,
        coeffs: &[f64],
        omega: f64,
        opts: &StabilityOptions,
    ) -> Result<Floquet> {
        self.project(bal, coeffs, omega)?;
        self.full(bal.params(), omega, opts)
    }

    /// The full analysis on the current projections.
    fn full(&mut self, params: &[f64], omega: f64, opts: &StabilityOptions) -> Result<Floquet> {
        self.tr.sign_right = None;
        self.op.assemble_polynomial(params, omega, true);
        self.candidates(params, omega)?;
        let tie = 1e-12 * omega;
        let mut refined = true;
        // The largest real part among the refined roots (not the frozen values of
        // candidates that did not refine).
        let mut top_refined = f64::NEG_INFINITY;
        let mut exps: Vec<Complex64> = Vec::with_capacity(self.sel.cands.len());
        self.sel.raw.clear();
        self.sel.unrefined.clear();
        self.sel.replaced = false;
        if self.op.fractional && opts.refine {
            // Each candidate's eigenvector of the frozen problem: a start that is
            // already an eigenvector, not the one step from a generic vector on the true
            // T(λ), which at low Ω mixes in the copies of other modes (spaced by Ω) and
            // sent the iteration to another mode's root. The companion eigensolve gave
            // it; after the pencil's (no vectors), one inverse iteration at the
            // eigenvalue, nearly singular there.
            let m = self.op.m;
            let starts: Vec<Complex64> =
                self.sel.cands.iter().chain(self.sel.spare.iter()).copied().collect();
            let frozen_vectors: Vec<Option<Vec<Complex64>>> = starts
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    if c.im < -tie {
                        return None;
                    }
                    self.sel.frozen_vector(i, m).or_else(|| {
                        self.start_vector(params, omega, c, false).or_else(|| {
                            let off = c + 1e-10 * omega.max(c.norm());
                            self.start_vector(params, omega, off, false)
                        })
                    })
                })
                .collect();
            let ncand = self.sel.cands.len();
            // The exact (not frozen) polynomial part for the refinement.
            self.op.assemble_polynomial(params, omega, false);
            let cands = std::mem::take(&mut self.sel.cands);
            let mut spare = 0;
            for (ci, &c) in cands.iter().enumerate() {
                if c.im < -tie {
                    continue; // its conjugate is refined
                }
                let mut start = frozen_vectors[ci].clone();
                // Two candidates refined to one root (two copies of one exponent kept by
                // a selection confused by a strongly nonlinear response, or an iteration
                // that wandered to another exponent): the next spare candidate replaces
                // the second, rather than one exponent counted twice and one lost. If
                // none refines to a new root, the candidate is reported unrefined.
                let mut cand = c;
                let l = loop {
                    match self.refine(params, omega, cand, start.take(), opts.max_refine_iter) {
                        // A new root; an unstable one only if centred (an unstable
                        // root off centre does not decide the verdict: like a second
                        // copy, it sends the next spare, and if none refines, the count
                        // decides).
                        Some((l, centre))
                            if refinement::may_witness(l, centre, opts.tol * omega)
                                && !self.sel.raw.iter().any(|&r| same_exponent(l, r, omega)) =>
                        {
                            top_refined = top_refined.max(l.re);
                            break l;
                        }
                        Some(_) if spare < self.sel.spare.len() => {
                            cand = self.sel.spare[spare];
                            start = frozen_vectors[ncand + spare].clone();
                            spare += 1;
                            self.sel.replaced = true;
                        }
                        _ => {
                            refined = false;
                            self.sel.unrefined.push(self.sel.raw.len());
                            break c;
                        }
                    }
                };
                self.sel.raw.push(l);
                push_central(&mut exps, l, omega);
            }
            self.sel.cands = cands;
            if !refined && top_refined <= opts.tol * omega {
                return self.counted(params, omega, opts, exps);
            }
            if refined {
                let hi = count::right_edge(&self.sel.found(), omega);
                if let Some(r) =
                    self.missed_real_root(params, omega, opts.tol * omega, hi, &exps)?
                {
                    let r = Complex64::new(r, 0.0);
                    self.sel.raw.push(r);
                    exps.push(r);
                    // Not a selection to track from: the root has no frozen candidate.
                    self.sel.replaced = true;
                }
            }
        } else {
            self.sel.raw.extend(self.sel.cands.iter().filter(|c| c.im >= -tie));
            exps.extend(self.sel.cands.iter().map(|&c| fold_into_strip(c, omega)));
        }
        Ok(floquet(exps, omega, opts, refined))
    }

    /// The verdict where a fractional candidate did not refine and no refined root is
    /// unstable: the frozen value in `exps` is no root, so the number of unstable
    /// roots of `det T` decides (`count`; the exact polynomial part is assembled), in
    /// a strip placed away from every exponent found.
    fn counted(
        &mut self,
        params: &[f64],
        omega: f64,
        opts: &StabilityOptions,
        exps: Vec<Complex64>,
    ) -> Result<Floquet> {
        let n = self.count_unstable(params, omega, opts.tol, &self.sel.found())?;
        let mut f = floquet(exps, omega, opts, false);
        f.stable = n == 0;
        f.counted = true;
        Ok(f)
    }

    /// The number of roots of `T(λ)` with `Re λ > tol · Ω` in the central strip of
    /// height Ω, counted by the argument principle on `det T(λ)` along the strip's
    /// unstable half (no refinement, no selection of copies): the solution is unstable
    /// iff it is not zero. An independent check of [`Hill::analyse`]'s verdict, at the
    /// cost of a few hundred factorisations of `T`; the companion eigensolve only
    /// places the contour (its right edge beyond every eigenvalue, its horizontal edges
    /// away from them). Fails with the reason if the winding is not resolved (a root on
    /// the contour).
    ///
    /// ```
    /// use ihbm::balance::Balance;
    /// use ihbm::models::Duffing;
    /// use ihbm::stability::{Hill, StabilityOptions};
    ///
    /// // x'' + c x' + x = 0 at rest: the exponents -c/2 ± i·sqrt(1 - c²/4) are both
    /// // in the strip |Im λ| < Ω/2 for Ω = 3, and unstable iff c < 0.
    /// let opts = StabilityOptions::default();
    /// for (c, unstable) in [(0.1, 0), (-0.1, 2)] {
    ///     let model = Duffing { m: 1.0, c, k: 1.0, k3: 0.0, F: 0.0 };
    ///     let mut bal = Balance::new(&model, 2).unwrap();
    ///     let mut hill = Hill::new(&model, 2).unwrap();
    ///     let rest = vec![0.0; 5];
    ///     assert_eq!(hill.unstable_roots(&mut bal, &rest, 3.0, &opts).unwrap(), unstable);
    /// }
    /// ```
    pub fn unstable_roots(
        &mut self,
        bal: &mut Balance<'_>,
        coeffs: &[f64],
        omega: f64,
        opts: &StabilityOptions,
    ) -> Result<usize> {
        self.project(bal, coeffs, omega)?;
        let params = bal.params();
        self.op.assemble_polynomial(params, omega, true);
        self.candidates(params, omega)?;
        self.sel.raw.clear();
        self.sel.unrefined.clear();
        let known = self.sel.found();
        self.op.assemble_polynomial(params, omega, false);
        self.count_unstable(params, omega, opts.tol, &known)
    }

    /// Like [`Hill::analyse`], but along a curve: the selected exponents of the
    /// previous point are continued to this one by Newton's method on the true
    /// `T(λ) v = 0` (from the previous eigenvalue and eigenvector; for fractional models
    /// the refined roots themselves), and the full analysis runs only when that cannot be
    /// trusted (book, *Continuation*, *Tracking the exponents along a curve*). Call
    /// [`Hill::reset`] when the next point does not continue the previous one (new
    /// segment, a fold in between).
    /// The result is the full analysis's, to the iterations' tolerance (`1e-10·Ω`).
    pub fn track(
        &mut self,
        bal: &mut Balance<'_>,
        coeffs: &[f64],
        omega: f64,
        opts: &StabilityOptions,
    ) -> Result<Floquet> {
        self.project(bal, coeffs, omega)?;
        let params = bal.params();
        if self.op.fractional && !opts.refine {
            // Frozen-order exponents are not roots of T(λ): nothing to track.
            self.tr.state = None;
            self.tr.counts.full += 1;
            return self.full(params, omega, opts);
        }
        // A partial set runs out after `PARTIAL_POINTS`: the full analysis finds out
        // whether every candidate refines again.
        if let Some(mut st) =
            self.tr.state.take().filter(|st| st.partial.as_ref().is_none_or(|p| p.left > 0))
        {
            let f = match st.partial.take() {
                Some(partial) => self.continue_partial(params, omega, opts, st, partial),
                // A real root that the tracked set lacks (one left the branch point λ = 0
                // of a fractional factor) sends the point to the full analysis.
                None => self.continue_state(params, omega, opts, st).filter(|f| {
                    let hi = count::right_edge(&f.exponents, omega);
                    !self.op.fractional
                        || self.real_parity_agrees(
                            params,
                            omega,
                            opts.tol * omega,
                            hi,
                            &f.exponents,
                        )
                }),
            };
            if let Some(f) = f {
                self.tr.counts.tracked += 1;
                return Ok(f);
            }
        }
        self.tr.counts.full += 1;
        let f = self.full(params, omega, opts);
        let doubted = self.tr.unconfirmed.take();
        match &f {
            // Exponents tracked here whose correction was doubted, and which the full
            // analysis confirms one by one: tracking goes on from them, with the motion
            // from the last point for the predictor (a start from the full analysis
            // has none, and an exponent moving steadily then fails the correction rule
            // at the next point again).
            Ok(fl) if fl.refined => {
                self.tr.partial_run = 0;
                match doubted {
                    Some(st) if self.confirms(&st, omega) => self.tr.state = Some(st),
                    _ => self.start_state(params, omega),
                }
            }
            // Some candidate did not refine: the next points track those that did and
            // count the rest.
            Ok(_) => self.start_partial_state(params, omega),
            Err(_) => self.tr.state = None,
        }
        f
    }

    /// Prepare the exact operator `T(λ)` at the solution `coeffs` (parameters as set
    /// in `bal`): the projections and the polynomial part with fractional orders
    /// left to [`Hill::operator`]'s exact factors. For test functions that need `T`
    /// at a given `λ` rather than its roots (the torus curves of
    /// [`crate::bifurcation`]).
    pub(crate) fn prepare_operator(
        &mut self,
        bal: &mut Balance<'_>,
        coeffs: &[f64],
        omega: f64,
    ) -> Result<()> {
        self.project(bal, coeffs, omega)?;
        self.op.assemble_polynomial(bal.params(), omega, false);
        Ok(())
    }

    /// `T(λ)` after [`Hill::prepare_operator`]: row-major, `n × n` (`n` the balance's
    /// unknowns; `T(0)` is the balance Jacobian).
    pub(crate) fn operator(
        &mut self,
        params: &[f64],
        omega: f64,
        lambda: Complex64,
    ) -> &[Complex64] {
        self.op.eval_t(params, omega, lambda, true);
        &self.op.t
    }

    /// `T'(λ) v` after [`Hill::prepare_operator`].
    pub(crate) fn derivative_applied(
        &mut self,
        params: &[f64],
        omega: f64,
        lambda: Complex64,
        v: &[Complex64],
    ) -> &[Complex64] {
        self.op.apply_t(params, omega, lambda, true, v, false);
        &self.op.dtv
    }

    /// Forget the tracked exponents: the next [`Hill::track`] analyses in full.
    pub fn reset(&mut self) {
        self.tr.state = None;
    }

    /// Take over `other`'s tracked exponents (a workspace for the same model and
    /// harmonics, else nothing is taken): the next [`Hill::track`] here continues from
    /// `other`'s last point. A root finder
    /// on a step of the curve starts from the step's end this way rather than with a
    /// full analysis.
    pub fn follow(&mut self, other: &Hill) {
        let same = self.op.m == other.op.m
            && self.op.degree == other.op.degree
            && self.op.ndof == other.op.ndof;
        self.tr.state = if same { other.tr.state.clone() } else { None };
    }

    /// Keep the tracked exponents but forget how they moved: the next [`Hill::track`]
    /// starts from them without the linear predictor. For a point near the last one
    /// that does not continue it in order (the iterates of a root finder go back and
    /// forth).
    pub fn forget_motion(&mut self) {
        if let Some(st) = self.tr.state.as_mut() {
            st.prev = None;
        }
    }

    /// Full analyses and tracked points of [`Hill::track`] so far.
    pub fn counts(&self) -> TrackCounts {
        self.tr.counts
    }
}

/// The degree of Hill's matrix polynomial: the model's highest integer derivative
/// order, at least 1 (fractional orders are not in the polynomial).
fn degree(model: &dyn DynModel) -> usize {
    let orders = model.signals().iter().filter_map(|s| match s.order {
        Order::Int(q) => Some(q as usize),
        Order::Param(_) => None,
    });
    orders.max().unwrap_or(0).max(1)
}

/// Bytes Hill's method takes for `harmonics` (in floating point, so nothing
/// overflows): with `m = ndof (2N + 1)` and the companion size `d m` (`d` the highest
/// derivative order), the projections `ndof · nsig · (2N + 1)²`, the coefficient
/// matrices `(d + 1) m²`, the companion matrix, its eigenvectors and the
/// eigensolver's workspace (measured on the quarter car: about `6.6 (d m)²`) and the
/// pencil of the singular fallback (`2 (d m)²`), all `f64`, and complex: `T(λ)`
/// (`m²`) and, for fractional models, the frozen eigenvectors the selection keeps
/// for its copy test (`d m · m`). Counted heap of a full analysis of the quarter car
/// without the fallback: 0.78–0.80 of it before the copy test's vectors.
pub fn hill_bytes(ndof: usize, nsig: usize, degree: usize, harmonics: usize) -> f64 {
    let len = 2.0 * harmonics as f64 + 1.0;
    let m = ndof as f64 * len;
    let big = degree.max(1) as f64 * m;
    8.0 * (ndof as f64 * nsig as f64 * len * len + (degree as f64 + 1.0) * m * m + 9.0 * big * big)
        + 16.0 * (m * m + big * m)
}

/// Refuse a harmonic count whose Hill matrices for `model` would not fit in
/// [`crate::balance::MEMORY_LIMIT`], naming the largest N that does (harmonic
/// balance alone needs less: a sweep without stability may still fit). Checked by
/// [`Hill::new`], and by a continuation with stability before anything else.
pub fn check_size(model: &dyn DynModel, harmonics: usize) -> Result<()> {
    let ndof = model.dofs().len();
    let nsig = model.signals().len();
    let degree = degree(model);
    let limit = crate::balance::MEMORY_LIMIT;
    let bytes = |n: usize| hill_bytes(ndof, nsig, degree, n);
    if bytes(harmonics) <= limit {
        return Ok(());
    }
    let lo = crate::balance::size::largest_fitting(harmonics, |n| bytes(n) <= limit);
    Err(Error::TooLarge {
        harmonics,
        dofs: ndof,
        what: "Hill stability matrices (without stability the harmonic balance needs less)".into(),
        needed: crate::balance::size::readable_bytes(bytes(harmonics)),
        limit: crate::balance::size::readable_bytes(limit),
        largest: lo,
    })
}
