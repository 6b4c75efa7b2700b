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
//! One idea per part: [`operator`] (`T(λ)`, `T'(λ)`), [`eigensolve`] (companion
//! eigenvalues and eigenvectors), [`selection`] (one copy of each exponent),
//! [`refinement`] (roots of the nonlinear problem), [`tracking`] (along a curve),
//! [`exponents`] (arithmetic modulo `iΩ`, the verdict).

mod eigensolve;
mod exponents;
mod operator;
mod refinement;
mod selection;
mod tracking;

use exponents::*;
use selection::*;
use tracking::*;

use crate::balance::Balance;
use crate::error::{Error, Result};
use crate::linalg::{complex_lu_factor, complex_lu_solve, complex_lu_solve_adjoint};
use crate::model::{Model, Order};
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

/// The central Floquet exponents of one periodic solution and the verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Floquet {
    /// Central exponents (`|Im λ| ≤ Ω/2`), sorted by decreasing real part.
    pub exponents: Vec<Complex64>,
    /// Largest real part (`-inf` if there are none).
    pub max_real: f64,
    /// `true` iff no exponent has `Re λ > tol · Ω`.
    pub stable: bool,
    /// `false` if some fractional candidate did not converge in the refinement (its
    /// frozen-order value is reported). Always `true` for integer-order models.
    pub refined: bool,
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
    ndof: usize,
    harmonics: usize,
    len: usize,
    m: usize,
    samples: usize,
    /// Highest integer order, the degree of the matrix polynomial.
    degree: usize,
    /// Projection matrices `P[g_{e,j}]`, row-major len×len, index (e * nsig + j).
    proj: Vec<f64>,
    /// Gradient spectrum `ĝ_m`, `m = 0..=2N`, the scratch of the block formula, and its
    /// unit spectral factors (`N + 1` ones).
    ghat: Vec<Complex64>,
    ext: Vec<Complex64>,
    ones: Vec<Complex64>,
    /// One projection assembled column-major (the block formula writes columns)
    proj_block: faer::Mat<f64>,
    /// Constant gradient of each projection (`P = g0·I`), if it is one.
    diag: Vec<Option<f64>>,
    /// `M_0 .. M_degree`, row-major `m × m`.
    coef: Vec<Vec<f64>>,
    /// Nonzero entries `(index, value)` of `M_1 .. M_degree` (index `r - 1`): mass and
    /// damping terms are usually linear, their blocks diagonal in the harmonics, and
    /// `T(λ)` is then `M_0` plus a few entries (see [`Hill::eval_t`]).
    sparse: Vec<Vec<(usize, f64)>>,
    companion: Mat<f64>,
    /// Right eigenvectors of the companion matrix (a complex pair in two columns).
    vectors: Mat<f64>,
    lead: Mat<f64>,
    s_re: Vec<f64>,
    s_im: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
    signals: Vec<(Vec<(usize, f64)>, Order)>,
    fractional: bool,
    /// The signals whose order is fractional at the current parameters.
    fractional_signals: Vec<usize>,
    cands: Vec<Complex64>,
    /// [`Spread`] of each selected candidate's eigenvector (see [`Hill::select_centred`]).
    centres: Vec<Spread>,
    /// The best-ranked eigenvalues the selection left out (not copies of kept ones, at
    /// most `SPARE_TRIES`): replacements when two kept candidates refine to one root.
    spare: Vec<Complex64>,
    /// For fractional models, the frozen eigenvector (first companion block) of each
    /// eigenvalue in `cands` before the selection, `m` entries each: the selection's
    /// copy test ([`Hill::select_centred`]).
    cand_vectors: Vec<Complex64>,
    /// The last full analysis replaced a candidate by a spare (its selection was not
    /// clean: tracking does not start from it).
    replaced: bool,
    /// Exponents of the last full analysis, one per conjugate pair, not folded: the
    /// selected eigenvalues (integer orders) or their refined roots (fractional).
    raw: Vec<Complex64>,
    /// Complex kernels of the nonlinear iteration: `T` (then its LU), pivots, a vector.
    t: Vec<Complex64>,
    piv: Vec<usize>,
    x: Vec<Complex64>,
    /// `T(λ)v`, `T'(λ)v` of [`Hill::apply_t`], and its per-block scratch (`2·len`);
    /// the adjoint vector of the certification step.
    tv: Vec<Complex64>,
    w: Vec<Complex64>,
    dtv: Vec<Complex64>,
    block: Vec<Complex64>,
    alpha: Vec<[Complex64; 4]>,
    /// `(q, Ω, λ)` of the fractional factors in `alpha` (`None`: not fractional ones).
    alpha_at: Option<(f64, f64, Complex64)>,
    /// Tracking state (see [`Hill::track`]).
    state: Option<TrackState>,
    /// Exponents continued to the current point that only the correction rule
    /// doubted, kept for the full analysis there to confirm (see [`Hill::track`]).
    unconfirmed: Option<TrackState>,
    counts: TrackCounts,
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
    pub fn new<M: Model>(model: &M, harmonics: usize) -> Result<Hill> {
        Self::with_period(model, harmonics, 1)
    }

    /// [`Hill::new`] for the balance of solutions of `period` forcing periods
    /// ([`Balance::with_period`](crate::balance::Balance::with_period)), whose samples it
    /// shares.
    pub fn with_period<M: Model>(model: &M, harmonics: usize, period: usize) -> Result<Hill> {
        crate::fourier::check_harmonics(harmonics)?;
        let ndof = model.dofs().len();
        crate::balance::check_size(ndof, harmonics)?;
        let len = 2 * harmonics + 1;
        let m = ndof * len;
        let samples = crate::fourier::model_sample_count(model, harmonics, period);
        let degree = degree(model);
        let fractional = model.signals().iter().any(|s| matches!(s.order, Order::Param(_)));
        let signals: Vec<_> = model.signals().iter().map(|s| (s.terms.to_vec(), s.order)).collect();
        let neq = ndof;
        let nsig = signals.len();
        let big = degree * m;
        check_size(model, harmonics)?;
        let scratch =
            faer::linalg::evd::evd_scratch::<f64>(
                big,
                faer::linalg::evd::ComputeEigenvectors::No,
                faer::linalg::evd::ComputeEigenvectors::Yes,
                Par::Seq,
                Default::default(),
            )
            .or(faer::linalg::lu::partial_pivoting::factor::lu_in_place_scratch::<usize, f64>(
                m,
                m,
                Par::Seq,
                Default::default(),
            ))
            .or(faer::linalg::lu::partial_pivoting::solve::solve_in_place_scratch::<
                usize,
                f64,
            >(m, big, Par::Seq));
        Ok(Hill {
            ndof,
            harmonics,
            len,
            m,
            samples,
            degree,
            proj: vec![0.0; neq * nsig * len * len],
            ghat: vec![Complex64::new(0.0, 0.0); 2 * harmonics + 1],
            ext: vec![Complex64::new(0.0, 0.0); 4 * harmonics + 1],
            ones: vec![Complex64::new(1.0, 0.0); harmonics + 1],
            proj_block: faer::Mat::zeros(len, len),
            diag: vec![None; neq * nsig],
            coef: (0..=degree).map(|_| vec![0.0; m * m]).collect(),
            sparse: (0..degree).map(|_| Vec::with_capacity(m * m)).collect(),
            companion: Mat::zeros(big, big),
            vectors: Mat::zeros(big, big),
            lead: Mat::zeros(m, m),
            s_re: vec![0.0; big],
            s_im: vec![0.0; big],
            perm: vec![0; m],
            perm_inv: vec![0; m],
            mem: MemBuffer::new(scratch),
            signals,
            fractional,
            fractional_signals: Vec::new(),
            cands: Vec::with_capacity(big),
            centres: Vec::with_capacity(big),
            spare: Vec::with_capacity(big),
            cand_vectors: Vec::new(),
            replaced: false,
            raw: Vec::with_capacity(big),
            t: vec![Complex64::new(0.0, 0.0); m * m],
            piv: vec![0; m],
            x: vec![Complex64::new(0.0, 0.0); m],
            tv: vec![Complex64::new(0.0, 0.0); m],
            w: vec![Complex64::new(0.0, 0.0); m],
            dtv: vec![Complex64::new(0.0, 0.0); m],
            block: vec![Complex64::new(0.0, 0.0); 2 * len],
            alpha: vec![[Complex64::new(0.0, 0.0); 4]; harmonics + 1],
            alpha_at: None,
            state: None,
            unconfirmed: None,
            counts: TrackCounts::default(),
        })
    }

    /// The order of signal `j` if it is an integer at `params` (a parameter order such
    /// as `p = 1` included, up to the polynomial's degree): its factor `(λ + ikΩ)^q`
    /// is then polynomial, exact in the companion linearisation, with nothing to refine.
    fn integer_order(&self, j: usize, params: &[f64]) -> Option<usize> {
        match self.signals[j].1 {
            Order::Int(q) => Some(q as usize),
            order => {
                let q = order.value(params);
                (q >= 0.0 && q.fract() == 0.0 && q <= self.degree as f64).then_some(q as usize)
            }
        }
    }

    /// Whether some order is fractional at `params`; a change forgets the tracking
    /// state (its exponents were of the other kind of problem).
    fn set_orders(&mut self, params: &[f64]) {
        self.fractional_signals.clear();
        for j in 0..self.signals.len() {
            if self.integer_order(j, params).is_none() {
                self.fractional_signals.push(j);
            }
        }
        let fractional = !self.fractional_signals.is_empty();
        if fractional != self.fractional {
            self.state = None;
        }
        self.fractional = fractional;
    }

    /// Number of central exponents (`degree · ndof`).
    pub fn central_count(&self) -> usize {
        self.degree * self.ndof
    }

    /// Floquet exponents and stability of the solution `coeffs` at frequency `omega`
    /// (parameters as currently set in `bal`): the full analysis, a companion
    /// eigensolve at every call. Along a curve, [`Hill::track`] is much cheaper.
    pub fn analyse<M: Model>(
        &mut self,
        bal: &mut Balance<'_, M>,
        coeffs: &[f64],
        omega: f64,
        opts: &StabilityOptions,
    ) -> Result<Floquet> {
        self.project(bal, coeffs, omega)?;
        self.full(bal.params(), omega, opts)
    }

    /// The full analysis on the current projections.
    fn full(&mut self, params: &[f64], omega: f64, opts: &StabilityOptions) -> Result<Floquet> {
        self.assemble_polynomial(params, omega, true);
        self.candidates(params, omega)?;
        let tie = 1e-12 * omega;
        let mut refined = true;
        let mut exps: Vec<Complex64> = Vec::with_capacity(self.cands.len());
        self.raw.clear();
        self.replaced = false;
        if self.fractional && opts.refine {
            // Each candidate's eigenvector of the frozen problem (one inverse iteration
            // at its eigenvalue, nearly singular there): a start that is already an
            // eigenvector, not the one step from a generic vector on the true T(λ),
            // which at low Ω mixes in the copies of other modes (spaced by Ω) and sent
            // the iteration to another mode's root.
            let frozen_vectors: Vec<Option<Vec<Complex64>>> = self
                .cands
                .clone()
                .iter()
                .chain(self.spare.clone().iter())
                .map(|&c| {
                    if c.im < -tie {
                        return None;
                    }
                    self.start_vector(params, omega, c, false).or_else(|| {
                        self.start_vector(params, omega, c + 1e-10 * omega.max(c.norm()), false)
                    })
                })
                .collect();
            let ncand = self.cands.len();
            // The exact (not frozen) polynomial part for the refinement.
            self.assemble_polynomial(params, omega, false);
            let cands = std::mem::take(&mut self.cands);
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
                        Some(l) if !self.raw.iter().any(|&r| same_exponent(l, r, omega)) => {
                            break l
                        }
                        Some(_) if spare < self.spare.len() => {
                            cand = self.spare[spare];
                            start = frozen_vectors[ncand + spare].clone();
                            spare += 1;
                            self.replaced = true;
                        }
                        _ => {
                            refined = false;
                            break c;
                        }
                    }
                };
                self.raw.push(l);
                push_central(&mut exps, l, omega);
            }
            self.cands = cands;
        } else {
            self.raw.extend(self.cands.iter().filter(|c| c.im >= -tie));
            exps.extend(self.cands.iter().map(|&c| fold_into_strip(c, omega)));
        }
        Ok(floquet(exps, omega, opts, refined))
    }

    /// Like [`Hill::analyse`], but along a curve: the selected exponents of the
    /// previous point are continued to this one by Newton's method on the true
    /// `T(λ) v = 0` (from the previous eigenvalue and eigenvector; for fractional models
    /// the refined roots themselves), and the full analysis runs only when that cannot be
    /// trusted (book, *Continuation*, *Tracking the exponents along a curve*). Call
    /// [`Hill::reset`] when the next point does not continue the previous one (new
    /// segment, a fold in between).
    /// The result is the full analysis's, to the iterations' tolerance (`1e-10·Ω`).
    pub fn track<M: Model>(
        &mut self,
        bal: &mut Balance<'_, M>,
        coeffs: &[f64],
        omega: f64,
        opts: &StabilityOptions,
    ) -> Result<Floquet> {
        self.project(bal, coeffs, omega)?;
        let params = bal.params();
        if self.fractional && !opts.refine {
            // Frozen-order exponents are not roots of T(λ): nothing to track.
            self.state = None;
            self.counts.full += 1;
            return self.full(params, omega, opts);
        }
        if let Some(st) = self.state.take() {
            if let Some(f) = self.continue_state(params, omega, opts, st) {
                self.counts.tracked += 1;
                return Ok(f);
            }
        }
        self.counts.full += 1;
        let f = self.full(params, omega, opts);
        let doubted = self.unconfirmed.take();
        match &f {
            // Exponents tracked here whose correction was doubted, and which the full
            // analysis confirms one by one: tracking goes on from them, with the motion
            // from the last point for the predictor (a start from the full analysis
            // has none, and an exponent moving steadily then fails the correction rule
            // at the next point again).
            Ok(fl) if fl.refined => match doubted {
                Some(st) if self.confirms(&st, omega) => self.state = Some(st),
                _ => self.start_state(params, omega),
            },
            _ => self.state = None,
        }
        f
    }

    /// Prepare the exact operator `T(λ)` at the solution `coeffs` (parameters as set
    /// in `bal`): the projections and the polynomial part with fractional orders
    /// left to [`Hill::operator`]'s exact factors. For test functions that need `T`
    /// at a given `λ` rather than its roots (the torus curves of
    /// [`crate::bifurcation`]).
    pub(crate) fn prepare_operator<M: Model>(
        &mut self,
        bal: &mut Balance<'_, M>,
        coeffs: &[f64],
        omega: f64,
    ) -> Result<()> {
        self.project(bal, coeffs, omega)?;
        self.assemble_polynomial(bal.params(), omega, false);
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
        self.eval_t(params, omega, lambda, true);
        &self.t
    }

    /// `T'(λ) v` after [`Hill::prepare_operator`].
    pub(crate) fn derivative_applied(
        &mut self,
        params: &[f64],
        omega: f64,
        lambda: Complex64,
        v: &[Complex64],
    ) -> &[Complex64] {
        self.apply_t(params, omega, lambda, true, v, false);
        &self.dtv
    }

    /// Forget the tracked exponents: the next [`Hill::track`] analyses in full.
    pub fn reset(&mut self) {
        self.state = None;
    }

    /// Take over `other`'s tracked exponents (a workspace for the same model and
    /// harmonics, else nothing is taken): the next [`Hill::track`] here continues from
    /// `other`'s last point. A root finder
    /// on a step of the curve starts from the step's end this way rather than with a
    /// full analysis.
    pub fn follow(&mut self, other: &Hill) {
        let same = self.m == other.m && self.degree == other.degree && self.ndof == other.ndof;
        self.state = if same { other.state.clone() } else { None };
    }

    /// Keep the tracked exponents but forget how they moved: the next [`Hill::track`]
    /// starts from them without the linear predictor. For a point near the last one
    /// that does not continue it in order (the iterates of a root finder go back and
    /// forth).
    pub fn forget_motion(&mut self) {
        if let Some(st) = self.state.as_mut() {
            st.prev = None;
        }
    }

    /// Full analyses and tracked points of [`Hill::track`] so far.
    pub fn counts(&self) -> TrackCounts {
        self.counts
    }
}

/// The degree of Hill's matrix polynomial: the model's highest integer derivative
/// order, at least 1 (fractional orders are not in the polynomial).
fn degree<M: Model>(model: &M) -> usize {
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
pub fn check_size<M: Model>(model: &M, harmonics: usize) -> Result<()> {
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
