//! Stability of periodic solutions: Hill's method, extended to fractional orders.
//!
//! # The method
//!
//! A harmonic balance solution `x*(t)` of `r_e(s_1, …, s_S, Ωt) = 0` (one equation per
//! DOF, polynomial in the signals `s_j = D^{q_j}(Σ_d c_{jd} x_d)`) is perturbed,
//! `x = x* + δx`, and the equations are linearised:
//!
//! ```text
//! Σ_j g_{e,j}(Ωt) · D^{q_j}(Σ_d c_{jd} δx_d) = 0,      g_{e,j} = ∂r_e/∂s_j at x*(t),
//! ```
//!
//! a linear system with `T = 2π/Ω`-periodic coefficients. Floquet theory (integer
//! orders) gives solutions `δx = e^{λt} p(t)` with `p` periodic; Hill's method writes
//! `p(t) = Σ_{|k|≤N} v_k e^{ikΩt}` and projects onto the same harmonics (Galerkin).
//! A derivative acts on `e^{(λ+ikΩ)t}` as the factor `(λ + ikΩ)^q`, so
//!
//! ```text
//! T(λ) v = 0,   T(λ)_{(e,l),(d,k)} = Σ_j c_{jd} G_{e,j,l-k} (λ + ikΩ)^{q_j},
//! ```
//!
//! `G_{e,j,m}` the Fourier coefficients of `g_{e,j}`. The projection is the one the
//! harmonic balance Jacobian uses (the same samples, the same weights): indeed
//! `T(0)` *is* that Jacobian. For integer orders `T(λ) = Σ_r λ^r M_r` is a matrix
//! polynomial (quadratic for mechanical models: mass, damping and stiffness blocks)
//! and its eigenvalues come from a companion linearisation. Its `ndof·(2N+1)·q_max`
//! eigenvalues approximate the `q_max·ndof` Floquet exponents and their copies
//! shifted by `ikΩ`; one copy of each is selected (*Which copy* below) and reported
//! folded into the strip `|Im λ| ≤ Ω/2` (the *central* exponents). The solution is
//! asymptotically stable iff every exponent has `Re λ < 0`; we report *unstable* iff
//! some selected exponent has `Re λ > tol·Ω`.
//!
//! # Which copy: eigenvector centring
//!
//! In the infinite Hill matrix the copies `λ + ijΩ` of an exponent are exact, their
//! eigenvectors the same coefficients shifted by `j` harmonics. Truncation at `N`
//! breaks this: a copy whose eigenvector has energy near harmonic `±N` misses its
//! neighbours beyond the cut and is inaccurate; the accurate copy is the one whose
//! eigenvector sits in the middle (Lazarus & Thomas, C. R. Mécanique 338, 2010;
//! Peletan et al., Nonlinear Dyn. 2013; Guillot et al., J. Comput. Phys. 2020). For an
//! eigenvector (displacement block, real basis `[a0, a_k, b_k]`) let
//! `c_{±k} = (a_k ∓ i b_k)/2` be its coefficients of `e^{±ikΩt}`; its *centre* is
//! `Σ_k k |c_k|² / Σ_k |c_k|²` (`k = -N..N`), and shifting the eigenvalue by `ijΩ`
//! shifts the centre by `-j`. We rank the eigenvalues by `|centre|` plus the excess of
//! the variance `Σ_k (k - centre)² |c_k|² / Σ_k |c_k|²` over 1: the copies of one
//! exponent share the variance, so within them this picks the centred copy; the
//! excess demotes mixtures of far harmonics (`c_4` and `c_{-4}` in equal parts, the
//! real eigenvalue of two far copies merged by truncation: centre 0, variance 16) that
//! the centre alone would take for centred. It does not penalise variance up to 1: at
//! `N = 1` the real exponent near a fold of the Duffing oscillator has its energy at
//! `±1` (variance 1) and must win against the `k = 0` block's eigenvalues, which
//! lack the coupling (ranking by the plain second moment lost that fold's
//! instability). The `q_max·ndof` eigenvalues of smallest rank are kept, one per
//! exponent modulo `iΩ`; ties go to the larger real part. The eigenvector of each
//! eigenvalue comes from one step of inverse iteration on `T(λ)` (half of them: a
//! conjugate's eigenvector is the conjugate, its centre negated).
//!
//! Why not the smallest `|Im λ|` (the rule used before): where `NΩ` is well below a
//! mode's frequency the truncation does not reach that mode's copies near the real
//! axis, and the smallest-`|Im|` rule picks two copies of another mode instead — the
//! quarter car below about 14 rad/s at N = 5 reported two copies of the body mode and
//! left the wheel mode (77 rad/s) unchecked. Its centred copy (`c_0` dominant, at
//! `Im λ ≈ 77`) is resolved at any Ω, and `tests/stability_centring.rs` checks the
//! selected exponents against the 2-DOF linearisation's characteristic roots from 1 to
//! 100 rad/s. Limits: the criterion presumes a mode's energy concentrated around one
//! harmonic index; a strongly nonlinear response spreads it (variance ≳ 1) and near
//! `|centre| = 1/2` two copies are nearly as centred (at period doubling exactly:
//! `λ` and `conj λ = λ - iΩ` both have `|centre| = 1/2`, the same exponent, one kept).
//! There the choice between copies is arbitrary; the verdict is not affected as long
//! as both copies are resolved, which is what `N` must ensure anyway.
//!
//! We work in the real basis `[a0, a_k, b_k]` of the harmonic balance: a derivative
//! of order `q` maps the pair `(a_k, b_k)` of `e^{λt}(a_k cos kθ + b_k sin kθ)` by
//! `[[α, -β], [β, α]]` with `α = (f₊ + f₋)/2`, `β = i(f₊ - f₋)/2`,
//! `f± = (λ ± ikΩ)^q`, and the constant by `λ^q`. For real `λ` and integer `q` these
//! are real, which keeps the integer-order problem real.
//!
//! # Fractional orders
//!
//! For a fractional signal (steady-state Liouville–Weyl derivative, the sense in which
//! harmonic balance solves `D^p`), the same ansatz gives the factor
//! `(λ + ikΩ)^p` on the principal branch: `T(λ)` is no longer polynomial, and the
//! Floquet exponents are the roots of a nonlinear eigenvalue problem
//! (Haacker, Leine, Chaudhary, Diethelm, Schmidt, Hashemishahraki, "Hill-type
//! stability analysis of periodic solutions of fractional-order differential
//! equations", arXiv:2509.24639, 2025). We solve it in two stages:
//!
//! 1. *Frozen order*: replace `(λ + ikΩ)^p` by its value at `λ = 0`, `(ikΩ)^p`
//!    (zero for `k = 0`, `p > 0`) — exactly the fractional contribution to the harmonic
//!    balance Jacobian — and solve the resulting polynomial problem as above. Its
//!    selected (centred) eigenvalues, not folded, are the candidates. The frozen factor
//!    is exact only at `λ = 0`, so a centred candidate far from the real axis (the
//!    wheel mode at low Ω) can be off by the fractional term's size; the refinement
//!    corrects it.
//! 2. *Refinement*: each candidate (one of each conjugate pair) is refined by nonlinear
//!    inverse iteration (Ruhe 1973) on the true `T(λ)`:
//!    `T(λ_k) x = T'(λ_k) v_k`, `λ_{k+1} = λ_k - (uᴴ v_k)/(uᴴ x)`, `v_{k+1} = x/(uᴴ x)`,
//!    quadratically convergent for a simple eigenvalue, with `T'` from
//!    `d/dλ (λ + ikΩ)^p = p (λ + ikΩ)^{p-1}`.
//! 3. *Re-centring*: a candidate far from its root (the quarter car's `k = 0` block has
//!    no damping at all when frozen, so at low Ω its candidates are off by more than
//!    `Ω/2`) can converge to a neighbouring copy `λ - ijΩ`, a less accurate root of the
//!    truncated problem. The refined eigenvector's centre says so (near `j`); the
//!    iteration restarts from `λ + ijΩ` (at most 3 times).
//! 4. *No exponent twice*: when a strongly nonlinear response confuses the frozen
//!    selection, two kept candidates can be copies of one exponent and refine to the
//!    same root while another exponent is left out (the quarter car with `k3 = 5e6` on
//!    its large-amplitude branch kept the body mode twice and lost the wheel mode). A
//!    root already found is replaced by the refinement of the best-ranked candidate the
//!    selection left out (up to 4 tries); if none gives a new root, the candidate is
//!    reported unrefined.
//!
//! # Justification and limits (the book should say these)
//!
//! - The branch cuts of `(λ + ikΩ)^p` lie on `λ ∈ -ikΩ + (-∞, 0]`, all in the closed
//!   left half plane, so `T(λ)` is analytic where instability lives (`Re λ > 0`):
//!   an exponentially growing mode is a genuine root there, and refinement of a
//!   growing candidate never meets a cut.
//! - Only exponentially growing perturbations are detected. Fractional systems also
//!   have algebraically decaying modes (the `t^{-p}` tails of the memory), invisible
//!   to any `e^{λt}` ansatz. "Stable" therefore means "no growing mode found", as in
//!   Haacker et al.
//! - Exponents with `Re λ < 0` near a branch cut (overdamped, relaxation-type modes)
//!   may not exist on the principal sheet; their refinement may fail. That does not
//!   change the verdict, but the reported values are then the frozen-order ones
//!   ([`Floquet::refined`] says so).
//! - The frozen-order candidates could in principle miss a growing root of the full
//!   problem that has no counterpart in the polynomial one (strong fractional terms);
//!   the refinement only corrects candidates it is given.
//! - Truncation: the Hill matrix is truncated at `N` harmonics; the centred copies
//!   converge quickly with `N`, the others are not used. Near a stability boundary
//!   the verdict flips at `Re λ = tol·Ω` (default `1e-7·Ω`), not exactly at 0.
//!
//! # Tracking along a curve
//!
//! [`Hill::analyse`] is dominated by the eigensolve of the `q_max·m × q_max·m`
//! companion matrix and the inverse iterations of the selection. [`Hill::track`]
//! reuses the previous point instead: each selected exponent (one per conjugate pair,
//! not folded; for fractional models the refined root of the true `T(λ)`, not the
//! frozen candidate) is continued with its eigenvector by the nonlinear inverse
//! iteration above on the true `T(λ)` (a linear predictor in Ω from the last two
//! points, the previous eigenvector as start, at most 5 iterations; converged when the
//! step is below `1e-12·scale`, or below `1e-7·scale` and `1e-3` times the previous
//! step, so that the quadratic error estimate is below `1e-10·scale`).
//!
//! Each step is followed by a cheap trial of the next one: with `w` from one adjoint
//! solve on the factors at hand (`T(λ_k)ᴴ w = u`, close to the left eigenvector since
//! `λ_k` is close to the root), the two-sided Rayleigh functional step
//! `δ = wᴴT(λ)v / wᴴT'(λ)v` is Newton's step on the scalar `wᴴT(λ)v = 0`, and its
//! error is of the order of the product of the errors of `v` and `w`. It is accepted
//! under the same rule as a full step; along a curve this certifies most points after
//! a single factorisation per exponent. (The same iteration refines the fractional
//! candidates of the full analysis.)
//!
//! The full analysis runs instead (and restarts the tracking) when:
//!
//! - there is no previous point ([`Hill::reset`]: the continuation calls it at the start
//!   of every segment and after a fold inside the step), the previous analysis failed or
//!   a refinement did not converge, or the model is fractional with `refine = false`;
//! - the last full analysis's selection was not clean: some selected eigenvector with
//!   `|centre| > 0.4`, some eigenvalue left out whose rank is not at least `0.2`
//!   above every selected one (a copy nearly as centred), a count other than
//!   `q_max·ndof` with conjugates, or two exponents closer than `1e-6·Ω`;
//! - Newton does not converge in 5 iterations, leaves the real axis or the upper half
//!   plane, ends on an eigenvector with `|centre| > 0.4`, or corrects the predicted
//!   exponent by more than a quarter of its separation `sep` (the distance to every
//!   other exponent, its own conjugate and all their copies shifted by `±iΩ`), before
//!   or after the step; or it ends within `1e-6·Ω` of another. (A real exponent is its
//!   own conjugate: real means an imaginary part below `1e-12·Ω`, the rounding the
//!   complex iteration leaves.)
//!
//! Why the tracked exponents are the full analysis's: the full analysis keeps, per
//! exponent, the copy with `|centre| < 1/2`; the continued eigenvector is checked to
//! stay within `0.4`, so it is still that copy and not a jump to a neighbouring one
//! (whose centre differs by an integer). Newton can only land on another eigenvalue of
//! `T`; a copy shifted by `j ≠ 0` is off centre by about `|j|`, which the check sees;
//! an unshifted other exponent or conjugate, or a copy at `±iΩ` (a pair meeting on the
//! real axis near a fold, at `±Ω/2` in a period-doubling tongue, two modes meeting at a
//! torus) shrinks `sep` and forces the full analysis. Limits: this presumes that the
//! eigenvalues the full analysis leaves out are copies of the selected ones (every
//! eigenvalue of the truncated problem belongs to one exponent's family), which holds
//! when the truncation resolves the modes; where a strongly nonlinear response spreads
//! the eigenvectors (the quarter car with `k3 = 5e6` near its resonances) the selection
//! is unclean and the points are analysed in full. `tests/stability_tracking.rs`
//! compares every point of curves with folds, a torus bubble, period doubling and
//! fractional terms.
//!
//! Which exponent crosses classifies a loss of stability: a real one (`Im λ = 0`,
//! multiplier `+1`: fold or branch point), one at `Im λ = ±Ω/2` (multiplier `-1`:
//! period doubling) or a complex pair elsewhere (Neimark–Sacker: a torus).

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
    /// Constant gradient of each projection (`P = g0·I`), if it is one.
    diag: Vec<Option<f64>>,
    /// `M_0 .. M_degree`, row-major `m × m`.
    coef: Vec<Vec<f64>>,
    /// Nonzero entries `(index, value)` of `M_1 .. M_degree` (index `r - 1`): mass and
    /// damping terms are usually linear, their blocks diagonal in the harmonics, and
    /// `T(λ)` is then `M_0` plus a few entries (see [`Hill::eval_t`]).
    sparse: Vec<Vec<(usize, f64)>>,
    companion: Mat<f64>,
    lead: Mat<f64>,
    s_re: Vec<f64>,
    s_im: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
    signals: Vec<(Vec<(usize, f64)>, Order)>,
    fractional: bool,
    cands: Vec<Complex64>,
    /// [`Spread`] of each selected candidate's eigenvector, and the smallest rank of
    /// an eigenvalue the selection left out (see [`Hill::select_centred`]).
    centres: Vec<Spread>,
    next_rank: f64,
    /// The best-ranked eigenvalues the selection left out (not copies of kept ones, at
    /// most `SPARE_TRIES`): replacements when two kept candidates refine to one root.
    spare: Vec<Complex64>,
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
    counts: TrackCounts,
}

/// Tracked exponents of the last point.
struct TrackState {
    omega: f64,
    /// Raw exponents (one per conjugate pair) with unit eigenvectors.
    lambdas: Vec<Complex64>,
    vectors: Vec<Vec<Complex64>>,
    /// Separation of each from the others (see [`separations`]).
    sep: Vec<f64>,
    /// The exponents one point earlier (for the linear predictor), and its Ω.
    prev: Option<(f64, Vec<Complex64>)>,
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
        if harmonics == 0 {
            return Err(Error::InvalidValue {
                what: "number of harmonics".into(),
                value: "0".into(),
                expected: "at least 1".into(),
            });
        }
        let ndof = model.dofs().len();
        let len = 2 * harmonics + 1;
        let m = ndof * len;
        let samples =
            crate::fourier::sample_count(model.degree(), harmonics, model.max_forcing_harmonic());
        let mut degree = 0usize;
        let mut fractional = false;
        let signals: Vec<_> = model
            .signals()
            .iter()
            .map(|s| {
                match s.order {
                    Order::Int(q) => degree = degree.max(q as usize),
                    Order::Param(_) => fractional = true,
                }
                (s.terms.to_vec(), s.order)
            })
            .collect();
        let degree = degree.max(1);
        let neq = ndof;
        let nsig = signals.len();
        let big = degree * m;
        let scratch =
            faer::linalg::evd::evd_scratch::<f64>(
                big,
                faer::linalg::evd::ComputeEigenvectors::No,
                faer::linalg::evd::ComputeEigenvectors::No,
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
            diag: vec![None; neq * nsig],
            coef: (0..=degree).map(|_| vec![0.0; m * m]).collect(),
            sparse: (0..degree).map(|_| Vec::with_capacity(m * m)).collect(),
            companion: Mat::zeros(big, big),
            lead: Mat::zeros(m, m),
            s_re: vec![0.0; big],
            s_im: vec![0.0; big],
            perm: vec![0; m],
            perm_inv: vec![0; m],
            mem: MemBuffer::new(scratch),
            signals,
            fractional,
            cands: Vec::with_capacity(big),
            centres: Vec::with_capacity(big),
            next_rank: f64::INFINITY,
            spare: Vec::with_capacity(big),
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
        let fractional = (0..self.signals.len()).any(|j| self.integer_order(j, params).is_none());
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
        self.set_orders(bal.params());
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
    /// trusted (module docs, *Tracking along a curve*). Call [`Hill::reset`] when the
    /// next point does not continue the previous one (new segment, a fold in between).
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
        self.set_orders(params);
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
        match &f {
            Ok(fl) if fl.refined => self.start_state(params, omega),
            _ => self.state = None,
        }
        f
    }

    /// Forget the tracked exponents: the next [`Hill::track`] analyses in full.
    pub fn reset(&mut self) {
        self.state = None;
    }

    /// Full analyses and tracked points of [`Hill::track`] so far.
    pub fn counts(&self) -> TrackCounts {
        self.counts
    }

    /// Tracking state from the last full analysis (`self.raw`), if its selection is
    /// clean: every selected eigenvalue centred (`|centre| ≤ CENTRE_MAX`), every one
    /// left out clearly less so (rank larger by `RANK_GAP`), `q_max·ndof` of them
    /// counted with conjugates, and well separated from each other, their conjugates and copies.
    /// Otherwise no state (the next point is analysed in full too). The polynomial
    /// part of `T` is the one the full analysis left assembled (exact for fractional
    /// models: the state holds their refined roots).
    fn start_state(&mut self, params: &[f64], omega: f64) {
        self.state = None;
        let n_out: usize = self.raw.iter().map(|&l| if real(l, omega) { 1 } else { 2 }).sum();
        if self.raw.is_empty()
            || self.replaced
            || n_out != self.central_count()
            || self.centres.iter().any(|c| c.centre.abs() > CENTRE_MAX)
            || self.centres.iter().any(|c| c.key() + RANK_GAP > self.next_rank)
        {
            return;
        }
        let sep = separations(&self.raw, omega);
        if sep.iter().any(|&s| s < MIN_SEPARATION * omega) {
            return;
        }
        let exact = self.fractional;
        let mut lambdas = Vec::with_capacity(self.raw.len());
        let mut vectors = Vec::with_capacity(self.raw.len());
        let raw = std::mem::take(&mut self.raw);
        for &l0 in &raw {
            let Some(v) = self.start_vector(params, omega, l0, exact) else { break };
            match self.newton(params, omega, l0, v, 30, true, exact) {
                Some((l, v, _)) if (l - l0).norm() <= 1e-8 * omega.max(l0.norm()) => {
                    lambdas.push(l);
                    vectors.push(v);
                }
                _ => break,
            }
        }
        let ok = lambdas.len() == raw.len();
        self.raw = raw;
        if ok {
            self.state = Some(TrackState { omega, lambdas, vectors, sep, prev: None });
        }
    }

    /// Continue `st` to the current point; `None` if a fallback rule fires.
    fn continue_state(
        &mut self,
        params: &[f64],
        omega: f64,
        opts: &StabilityOptions,
        st: TrackState,
    ) -> Option<Floquet> {
        // Integer orders: the polynomial; fractional: its integer part, the fractional
        // signals exact in `eval_t` (the tracked values are the refined roots).
        let exact = self.fractional;
        self.assemble_polynomial(params, omega, !exact);
        // Linear predictor in Ω (ratio of the steps, clamped; 1 on the parameter axis).
        let ratio = match &st.prev {
            Some((w0, _)) if (st.omega - w0).abs() > 0.0 && omega != st.omega => {
                ((omega - st.omega) / (st.omega - w0)).clamp(0.0, 2.0)
            }
            Some(_) => 1.0,
            None => 0.0,
        };
        let mut lambdas = Vec::with_capacity(st.lambdas.len());
        let mut vectors = Vec::with_capacity(st.lambdas.len());
        let mut preds = Vec::with_capacity(st.lambdas.len());
        for (i, (&l, v)) in st.lambdas.iter().zip(&st.vectors).enumerate() {
            let pred = match &st.prev {
                Some((_, p)) => l + (l - p[i]) * ratio,
                None => l,
            };
            preds.push(pred);
            let (ln, vn, _) =
                self.newton(params, omega, pred, v.clone(), TRACK_ITER, false, exact)?;
            // Still the centred copy (not a jump to a copy of this or another mode).
            if spread(&vn, self.ndof, self.harmonics).centre.abs() > CENTRE_MAX {
                return None;
            }
            // Stay on the real axis / in the upper half plane as before.
            let (was_real, is_real) = (real(l, omega), real(ln, omega));
            if was_real != is_real || !is_real && ln.im < 0.0 {
                return None;
            }
            // The iteration's correction, not the motion: an exponent that moves
            // steadily along the curve is predicted (the quarter car's body mode near
            // resonance moves by a third of Ω per step).
            if (ln - pred).norm() > 0.25 * st.sep[i] {
                return None;
            }
            lambdas.push(ln);
            vectors.push(vn);
        }
        let sep = separations(&lambdas, omega);
        for (i, &s) in sep.iter().enumerate() {
            let corrected = (lambdas[i] - preds[i]).norm();
            if s < MIN_SEPARATION * omega || corrected > 0.25 * s {
                return None;
            }
        }
        let mut exps = Vec::with_capacity(2 * lambdas.len());
        for &c in &lambdas {
            push_central(&mut exps, c, omega);
        }
        let prev = Some((st.omega, st.lambdas));
        self.state = Some(TrackState { omega, lambdas, vectors, sep, prev });
        Some(floquet(exps, omega, opts, true))
    }

    /// Galerkin projections `P[g_{e,j}]` of the signal gradients at the solution:
    /// from the gradients' spectra `ĝ_m`, `m ≤ 2N`, by the harmonic balance Jacobian's
    /// own block formula with unit spectral factors (the same samples, so the same
    /// projection as a direct quadrature of `g φ_l φ_k`, at `O(N²)` instead of
    /// `O(M N²)`).
    fn project<M: Model>(
        &mut self,
        bal: &mut Balance<'_, M>,
        coeffs: &[f64],
        omega: f64,
    ) -> Result<()> {
        let (len, ns, nh) = (self.len, self.samples, self.harmonics);
        let nsig = self.signals.len();
        if bal.samples() != ns || bal.len() != self.m {
            return Err(Error::Other(format!(
                "Hill's method: workspace for {} samples and {} unknowns used with a balance of {} and {}",
                ns,
                self.m,
                bal.samples(),
                bal.len()
            )));
        }
        bal.signal_gradients(coeffs, omega);
        for e in 0..self.ndof {
            for j in 0..nsig {
                let idx = e * nsig + j;
                let g = &bal.gradients()[idx * ns..][..ns];
                if g.iter().all(|&x| x == g[0]) {
                    // A linear term: multiplication by a constant projects to g0·I.
                    self.diag[idx] = Some(g[0]);
                    continue;
                }
                self.diag[idx] = None;
                bal.gradient_spectrum(e, j, &mut self.ghat);
                let p = &mut self.proj[idx * len * len..(idx + 1) * len * len];
                p.fill(0.0);
                let view = faer::MatMut::from_row_major_slice_mut(p, len, len);
                let (g, ext, ones) = (&self.ghat, &mut self.ext, &self.ones);
                crate::balance::add_block(view, nh, 0, 0, 1.0, g, ext, ones);
            }
        }
        Ok(())
    }

    /// `M_r` of `T(λ) = Σ_r λ^r M_r` from the integer-order signals, plus (if `frozen`)
    /// the fractional ones frozen at `λ = 0`.
    fn assemble_polynomial(&mut self, params: &[f64], omega: f64, frozen: bool) {
        let (len, nh, nsig, m) = (self.len, self.harmonics, self.signals.len(), self.m);
        self.alpha_at = None; // `alpha` is scratch here
        for c in &mut self.coef {
            c.fill(0.0);
        }
        for j in 0..nsig {
            let order = self.signals[j].1;
            let int = self.integer_order(j, params);
            let (rmax, qi) = match int {
                Some(q) => (q, q),
                None if frozen => (0, 0),
                None => continue,
            };
            let q = order.value(params);
            for r in 0..=rmax {
                // Coefficient of λ^r in (λ ± ikΩ)^q: binom(q, r) (±ikΩ)^(q - r); for a
                // frozen fractional order, r = 0 and the factor (±ikΩ)^p.
                let (binom, s) = match int {
                    Some(_) => (binomial(qi, r), qi as f64 - r as f64),
                    None => (1.0, q),
                };
                for k in 0..=nh {
                    let (a, b) = if k == 0 {
                        (if s == 0.0 { binom } else { 0.0 }, 0.0)
                    } else {
                        let z = crate::fourier::spectral_factor(k, omega, s);
                        (binom * z.re, -binom * z.im)
                    };
                    self.alpha[k][0] = Complex64::new(a, 0.0);
                    self.alpha[k][1] = Complex64::new(b, 0.0);
                }
                let ab = &self.alpha;
                for e in 0..self.ndof {
                    let idx = e * nsig + j;
                    let p = &self.proj[idx * len * len..(idx + 1) * len * len];
                    for &(d, c) in &self.signals[j].0 {
                        let dst = &mut self.coef[r];
                        let (r0, c0) = (e * len, d * len);
                        match self.diag[idx] {
                            Some(g) => {
                                add_diag(dst, m, r0, c0, c * g, nh, |k| (ab[k][0].re, ab[k][1].re))
                            }
                            None => add_product(dst, m, r0, c0, c, p, len, nh, |k| {
                                (ab[k][0].re, ab[k][1].re)
                            }),
                        }
                    }
                }
            }
        }
        for (nz, c) in self.sparse.iter_mut().zip(&self.coef[1..]) {
            nz.clear();
            nz.extend(c.iter().enumerate().filter(|z| *z.1 != 0.0).map(|(i, &x)| (i, x)));
        }
    }

    /// Selected (centred) eigenvalues of the matrix polynomial into `self.cands`, not
    /// folded.
    fn candidates(&mut self, params: &[f64], omega: f64) -> Result<()> {
        use faer::linalg::lu::partial_pivoting::{factor, solve};
        let (m, d) = (self.m, self.degree);
        let big = d * m;
        let count = self.central_count();
        let lead = &self.coef[d];
        self.lead = Mat::from_fn(m, m, |i, j| lead[i * m + j]);
        let scale = self.lead.norm_max();
        let (_, perm) = factor::lu_in_place(
            self.lead.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        let min_pivot = (0..m).map(|i| self.lead[(i, i)].abs()).fold(f64::INFINITY, f64::min);
        self.cands.clear();
        if min_pivot.is_nan() || min_pivot <= 1e-12 * scale {
            return self.candidates_generalized(params, omega);
        }
        // Companion: [[0, I, ...], ..., [-L⁻¹M_0, ..., -L⁻¹M_{d-1}]].
        self.companion.fill(0.0);
        for b in 0..d - 1 {
            for i in 0..m {
                self.companion[(b * m + i, (b + 1) * m + i)] = 1.0;
            }
        }
        for r in 0..d {
            for i in 0..m {
                for jj in 0..m {
                    self.companion[((d - 1) * m + i, r * m + jj)] = -self.coef[r][i * m + jj];
                }
            }
        }
        {
            let rows = self.companion.as_mut().subrows_mut((d - 1) * m, m);
            solve::solve_in_place(
                self.lead.as_ref(),
                self.lead.as_ref(),
                perm,
                rows,
                Par::Seq,
                MemStack::new(&mut self.mem),
            );
        }
        faer::linalg::evd::evd_real(
            self.companion.as_ref(),
            faer::diag::DiagMut::from_slice_mut(&mut self.s_re),
            faer::diag::DiagMut::from_slice_mut(&mut self.s_im),
            None,
            None,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        )
        .map_err(|e| {
            Error::Other(format!("Hill's method: eigenvalues failed at Ω = {omega}: {e:?}"))
        })?;
        for i in 0..big {
            self.cands.push(Complex64::new(self.s_re[i], self.s_im[i]));
        }
        self.select_centred(params, omega, count);
        Ok(())
    }

    /// Keep `count` of the eigenvalues in `self.cands`, one per Floquet exponent: the
    /// copies whose eigenvectors are centred in harmonic index (module docs, *Which
    /// copy*), smallest rank ([`Spread::key`]) first; among near-equal ranks the larger
    /// real part first, so that a growing exponent is never the one left out. Values
    /// equal modulo `iΩ` are the same exponent (at `|Im λ| = Ω/2`, period doubling,
    /// `λ` and `conj λ = λ - iΩ` both appear): one is kept. Sets `self.centres` and
    /// `self.next_rank` (the smallest rank left out that is not a copy of a kept
    /// value, infinite if none).
    fn select_centred(&mut self, params: &[f64], omega: f64, count: usize) {
        let tie = 1e-12 * omega;
        let all = std::mem::take(&mut self.cands);
        let mut scored: Vec<(Complex64, Spread)> = Vec::with_capacity(all.len());
        for &l in &all {
            if l.im < -tie {
                continue; // the conjugate's eigenvector is the conjugate: centre negated
            }
            let c = self.spread_at(params, omega, l);
            scored.push((l, c));
            if l.im > tie {
                scored.push((l.conj(), Spread { centre: -c.centre, spread: c.spread }));
            }
        }
        scored.sort_by(|a, b| a.1.key().total_cmp(&b.1.key()));
        let mut start = 0;
        while start < scored.len() {
            let base = scored[start].1.key();
            let end =
                start + scored[start..].iter().take_while(|z| z.1.key() - base <= RANK_TIE).count();
            scored[start..end].sort_by(|a, b| b.0.re.total_cmp(&a.0.re));
            start = end;
        }
        let same_tie = 1e-6 * omega;
        self.cands.clear();
        self.centres.clear();
        self.spare.clear();
        self.next_rank = f64::INFINITY;
        for &(z, c) in &scored {
            let same = self.cands.iter().any(|&k| {
                let d = fold_into_strip(z - k, omega);
                d.re.abs() <= same_tie && d.im.abs() <= same_tie
            });
            if same {
                continue;
            }
            if self.cands.len() == count {
                // Sorted by rank: the first one left out ranks lowest.
                if self.next_rank == f64::INFINITY {
                    self.next_rank = c.key();
                }
                // One per conjugate pair, as the refinement takes them.
                if z.im >= -tie && self.spare.len() < SPARE_TRIES {
                    self.spare.push(z);
                }
                continue;
            }
            self.cands.push(z);
            self.centres.push(c);
        }
    }

    /// [`Spread`] of the eigenvector of the polynomial `T` at its eigenvalue `l` (one
    /// step of inverse iteration; infinite if that fails).
    fn spread_at(&mut self, params: &[f64], omega: f64, l: Complex64) -> Spread {
        // An exactly singular factorisation: step off the eigenvalue a little.
        let v = self
            .start_vector(params, omega, l, false)
            .or_else(|| self.start_vector(params, omega, l + 1e-10 * omega.max(l.norm()), false));
        v.map_or(Spread { centre: f64::INFINITY, spread: f64::INFINITY }, |v| {
            spread(&v, self.ndof, self.harmonics)
        })
    }

    /// Fallback for a singular leading matrix: the companion pencil, QZ.
    fn candidates_generalized(&mut self, params: &[f64], omega: f64) -> Result<()> {
        let (m, d) = (self.m, self.degree);
        let big = d * m;
        let mut a = Mat::<f64>::zeros(big, big);
        let mut b = Mat::<f64>::zeros(big, big);
        for blk in 0..d - 1 {
            for i in 0..m {
                a[(blk * m + i, (blk + 1) * m + i)] = 1.0;
                b[(blk * m + i, blk * m + i)] = 1.0;
            }
        }
        for r in 0..d {
            for i in 0..m {
                for jj in 0..m {
                    a[((d - 1) * m + i, r * m + jj)] = -self.coef[r][i * m + jj];
                }
            }
        }
        for i in 0..m {
            for jj in 0..m {
                b[((d - 1) * m + i, (d - 1) * m + jj)] = self.coef[d][i * m + jj];
            }
        }
        let ge = a.generalized_eigen(&b).map_err(|e| {
            Error::Other(format!(
                "Hill's method: generalized eigenvalues failed at Ω = {omega}: {e:?}"
            ))
        })?;
        let (sa, sb) = (ge.S_a(), ge.S_b());
        for i in 0..big {
            let (x, y) = (sa[i], sb[i]);
            if y.norm() > 1e-12 * x.norm().max(1e-300) {
                self.cands.push(x / y);
            }
        }
        let count = (self.cands.len() / self.len).max(1).min(self.cands.len());
        self.select_centred(params, omega, count);
        Ok(())
    }

    /// `T(λ)` (row-major, into `self.t`): the polynomial `self.coef` (`M_0` in full, the
    /// higher coefficients by their nonzero entries), and, if `exact`, the fractional
    /// signals with their true factors (principal branch; `self.coef` then assembled
    /// with `frozen = false`). `T'(λ)` is only ever applied: [`Hill::apply_t`].
    fn eval_t(&mut self, params: &[f64], omega: f64, lambda: Complex64, exact: bool) {
        let (len, nh, nsig, m, d) =
            (self.len, self.harmonics, self.signals.len(), self.m, self.degree);
        let (pw, _) = powers(lambda, d);
        for (t, &c) in self.t.iter_mut().zip(&self.coef[0]) {
            *t = Complex64::new(c, 0.0);
        }
        for r in 1..=d {
            for &(i, c) in &self.sparse[r - 1] {
                self.t[i] += pw[r] * c;
            }
        }
        if !(self.fractional && exact) {
            return;
        }
        for j in 0..nsig {
            if self.integer_order(j, params).is_some() {
                continue;
            }
            self.fractional_factors(self.signals[j].1.value(params), omega, lambda);
            let ab = &self.alpha;
            for e in 0..self.ndof {
                let idx = e * nsig + j;
                let p = &self.proj[idx * len * len..(idx + 1) * len * len];
                for &(dof, c) in &self.signals[j].0 {
                    let (r0, c0) = (e * len, dof * len);
                    let f = |k: usize| (ab[k][0], ab[k][1]);
                    match self.diag[idx] {
                        Some(g) => add_diag(&mut self.t, m, r0, c0, c * g, nh, f),
                        None => add_product(&mut self.t, m, r0, c0, c, p, len, nh, f),
                    }
                }
            }
        }
    }

    /// `self.alpha[k]` for a fractional order `q` at `λ`: the real-basis factors
    /// `(α_k, β_k)` of `(λ ± ikΩ)^q` (principal branch) and their λ-derivatives.
    fn fractional_factors(&mut self, q: f64, omega: f64, lambda: Complex64) {
        // A Newton step assembles T(λ) and applies T'(λ) at the same point.
        if self.alpha_at == Some((q, omega, lambda)) {
            return;
        }
        self.alpha_at = Some((q, omega, lambda));
        let zero = Complex64::new(0.0, 0.0);
        let i1 = Complex64::new(0.0, 1.0);
        let f = |z: Complex64| -> (Complex64, Complex64) {
            if q == 0.0 {
                (Complex64::new(1.0, 0.0), zero)
            } else if z == zero {
                (zero, Complex64::new(if q == 1.0 { 1.0 } else { 0.0 }, 0.0))
            } else {
                let v = z.powf(q);
                (v, q * v / z)
            }
        };
        // k = 0: f(λ) itself (α = f₊ = f₋).
        for k in 0..=self.harmonics {
            let w = Complex64::new(0.0, k as f64 * omega);
            let (fp, dfp) = f(lambda + w);
            let (fm, dfm) = if k == 0 { (fp, dfp) } else { f(lambda - w) };
            self.alpha[k] =
                [(fp + fm) * 0.5, i1 * (fp - fm) * 0.5, (dfp + dfm) * 0.5, i1 * (dfp - dfm) * 0.5];
        }
    }

    /// `T(λ)v` and `T'(λ)v` into `self.tv`, `self.dtv` without assembling `T` (the
    /// certification step of [`Hill::newton`]): `M_0 v` in full (real times complex),
    /// the higher coefficients by their nonzero entries, and, if `exact`, each
    /// fractional block `c·P·D` applied as `D` then `P`, the operators of
    /// [`Hill::eval_t`]. Without `want_tv` (a Newton step needs `T'(λ)v` only) the
    /// dense `M_0 v` is skipped and `self.tv` is not valid.
    #[allow(clippy::too_many_arguments)] // the iteration's inputs, as in `newton`
    fn apply_t(
        &mut self,
        params: &[f64],
        omega: f64,
        lambda: Complex64,
        exact: bool,
        v: &[Complex64],
        want_tv: bool,
    ) {
        let (len, nh, nsig, m, d) =
            (self.len, self.harmonics, self.signals.len(), self.m, self.degree);
        let zero = Complex64::new(0.0, 0.0);
        let (pw, dpw) = powers(lambda, d);
        if want_tv {
            for (y, row) in self.tv.iter_mut().zip(self.coef[0].chunks_exact(m)) {
                // Real times complex: two real dot products.
                let (mut re, mut im) = (0.0, 0.0);
                for (&a, x) in row.iter().zip(v) {
                    re += a * x.re;
                    im += a * x.im;
                }
                *y = Complex64::new(re, im);
            }
        }
        self.dtv.fill(zero);
        for r in 1..=d {
            for &(i, c) in &self.sparse[r - 1] {
                let x = v[i % m] * c;
                self.tv[i / m] += pw[r] * x;
                self.dtv[i / m] += dpw[r] * x;
            }
        }
        if !(self.fractional && exact) {
            return;
        }
        for j in 0..nsig {
            if self.integer_order(j, params).is_some() {
                continue;
            }
            self.fractional_factors(self.signals[j].1.value(params), omega, lambda);
            for e in 0..self.ndof {
                let idx = e * nsig + j;
                for &(dof, c) in &self.signals[j].0 {
                    // D x and D' x for this block's columns.
                    let x = &v[dof * len..(dof + 1) * len];
                    let (y, dy) = self.block.split_at_mut(len);
                    let a0 = &self.alpha[0];
                    y[0] = a0[0] * x[0];
                    dy[0] = a0[2] * x[0];
                    for k in 1..=nh {
                        let [al, be, dal, dbe] = self.alpha[k];
                        let (xa, xb) = (x[k], x[nh + k]);
                        y[k] = al * xa - be * xb;
                        y[nh + k] = be * xa + al * xb;
                        dy[k] = dal * xa - dbe * xb;
                        dy[nh + k] = dbe * xa + dal * xb;
                    }
                    let (tv, dtv) =
                        (&mut self.tv[e * len..][..len], &mut self.dtv[e * len..][..len]);
                    match self.diag[idx] {
                        Some(g) => {
                            let cg = c * g;
                            for l in 0..len {
                                tv[l] += y[l] * cg;
                                dtv[l] += dy[l] * cg;
                            }
                        }
                        None => {
                            let p = &self.proj[idx * len * len..(idx + 1) * len * len];
                            for (l, row) in p.chunks_exact(len).enumerate() {
                                let (mut a, mut b) = (zero, zero);
                                for ((&pk, &yk), &dyk) in row.iter().zip(y.iter()).zip(dy.iter()) {
                                    a += yk * pk;
                                    b += dyk * pk;
                                }
                                tv[l] += a * c;
                                dtv[l] += b * c;
                            }
                        }
                    }
                }
            }
        }
    }

    /// One step of inverse iteration at `l0` from a fixed start vector: the start of
    /// the nonlinear iteration when no eigenvector is known.
    fn start_vector(
        &mut self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        exact: bool,
    ) -> Option<Vec<Complex64>> {
        self.eval_t(params, omega, l0, exact);
        let mut v: Vec<Complex64> =
            (0..self.m).map(|i| Complex64::new(1.0 + (i as f64 * 0.37).sin(), 0.0)).collect();
        if !lu_solve(&mut self.t, self.m, &mut self.piv, &mut v) {
            return None;
        }
        normalise(&mut v)?;
        Some(v)
    }

    /// Nonlinear inverse iteration from the candidate `l0`, then re-centring: the root
    /// it reaches is returned only if its eigenvector is centred (`|centre| ≤ 1/2`);
    /// otherwise it is a copy `λ - ijΩ` of the centred root (centre near `j`), and the
    /// iteration is restarted from `λ + ijΩ`. `None` if it fails.
    ///
    /// Why: the frozen candidate of a mode whose fractional damping is large (the body
    /// and wheel modes of the quarter car, whose `k = 0` block has no damping at all
    /// when frozen) is off the true root by more than `Ω/2` at low Ω, and Newton then
    /// converges to whichever copy is nearest. That copy is a root of the truncated
    /// `T(λ)` too, but a less accurate one, and tracking from it would leave the
    /// centred copy at the first step.
    fn refine(
        &mut self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        mut v0: Option<Vec<Complex64>>,
        max_iter: usize,
    ) -> Option<Complex64> {
        let tie = 1e-12 * omega;
        let mut start = l0;
        for _ in 0..RECENTRE_TRIES {
            let (v, factored) = match v0.take() {
                Some(v) => (v, false),
                // `self.t` holds the LU of T(start) from the start vector: the first
                // step reuses it.
                None => (self.start_vector(params, omega, start, true)?, true),
            };
            let (mut l, mut v, _) =
                self.newton(params, omega, start, v, max_iter, factored, true)?;
            if l.im < -tie {
                // One per conjugate pair, in the upper half plane.
                l = l.conj();
                v.iter_mut().for_each(|x| *x = x.conj());
            }
            let c = spread(&v, self.ndof, self.harmonics).centre;
            if c.abs() <= 0.5 {
                return Some(l);
            }
            start = l + Complex64::new(0.0, c.round() * omega);
        }
        None
    }

    /// Nonlinear inverse iteration (Ruhe 1973) on `T(λ) v = 0` from `(l0, v)`, `v` of
    /// unit norm: `T(λ) x = T'(λ) v`, `λ ← λ - (uᴴv)/(uᴴx)`, `v ← x/(uᴴx)` with
    /// `u` the start vector. Converged when the step is below `1e-12·scale`, or below
    /// `1e-7·scale` and `1e-3` times the previous one (quadratic convergence observed:
    /// the remaining error is then below `1e-10·scale`). `factored`: `self.t` already
    /// holds the LU of `T(l0)`. The root, its unit eigenvector and the iterations.
    ///
    /// After each step the next one is first tried without a factorisation: with `w`
    /// from one adjoint inverse iteration on the factors at hand (`T(λ_k)ᴴ w = u`, close
    /// to the left eigenvector as `λ_k` is close to the root), the two-sided Rayleigh
    /// functional step `δ = wᴴT(λ)v / wᴴT'(λ)v` (Ostrowski; Schreiber 2008) is the Newton
    /// step on the scalar `wᴴT(λ)v = 0`, and its error is of the order of the product of
    /// the errors of `v` and `w`, both first order in `λ_k`'s. It is accepted under the
    /// same rule as a full step; otherwise the full step follows. Along a curve this
    /// saves the second factorisation of most points.
    #[allow(clippy::too_many_arguments)] // the iteration's inputs, no natural grouping
    fn newton(
        &mut self,
        params: &[f64],
        omega: f64,
        l0: Complex64,
        mut v: Vec<Complex64>,
        max_iter: usize,
        factored: bool,
        exact: bool,
    ) -> Option<(Complex64, Vec<Complex64>, usize)> {
        let m = self.m;
        let u = v.clone();
        let mut lambda = l0;
        let scale = omega.max(l0.norm());
        let mut last = f64::INFINITY;
        let done =
            |s: f64, last: f64| s <= 1e-12 * scale || (s <= 1e-7 * scale && s <= 1e-3 * last);
        for it in 0..max_iter {
            let reuse = factored && it == 0;
            if !reuse {
                self.eval_t(params, omega, lambda, exact);
            }
            self.apply_t(params, omega, lambda, exact, &v, false);
            self.x.copy_from_slice(&self.dtv);
            let solved = if reuse {
                complex_lu_solve(&self.t, m, &self.piv, &mut self.x);
                true
            } else {
                lu_solve(&mut self.t, m, &mut self.piv, &mut self.x)
            };
            if !solved {
                return None;
            }
            let ux: Complex64 = u.iter().zip(&self.x).map(|(a, b)| a.conj() * b).sum();
            let uv: Complex64 = u.iter().zip(&v).map(|(a, b)| a.conj() * b).sum();
            if ux.norm() == 0.0 || !ux.re.is_finite() || !ux.im.is_finite() {
                return None;
            }
            let step = uv / ux;
            lambda -= step;
            for (vi, xi) in v.iter_mut().zip(&self.x) {
                *vi = xi / ux;
            }
            if !lambda.re.is_finite() || !lambda.im.is_finite() {
                return None;
            }
            let s = step.norm();
            // Quadratic convergence: the next error is about s²/last ≤ 1e-3·s.
            if done(s, last) {
                return converged(lambda, v, it + 1);
            }
            last = s;
            // The Rayleigh step at the new λ: w from the factors of T(λ_k), T(λ)v and
            // T'(λ)v without assembling T(λ).
            self.w.copy_from_slice(&u);
            complex_lu_solve_adjoint(&self.t, m, &self.piv, &mut self.w);
            self.apply_t(params, omega, lambda, exact, &v, true);
            let wr: Complex64 = self.w.iter().zip(&self.tv).map(|(a, b)| a.conj() * b).sum();
            let wd: Complex64 = self.w.iter().zip(&self.dtv).map(|(a, b)| a.conj() * b).sum();
            let delta = wr / wd;
            if delta.re.is_finite() && delta.im.is_finite() && done(delta.norm(), last) {
                return converged(lambda - delta, v, it + 1);
            }
        }
        None
    }
}

/// Iterations allowed to continue one exponent to the next point.
const TRACK_ITER: usize = 5;
/// Exponents closer than this (relative to Ω) are not tracked.
const MIN_SEPARATION: f64 = 1e-6;
/// A tracked exponent's eigenvector must stay this centred (`|centre|`), and so must
/// every exponent a full analysis selects for tracking to start.
const CENTRE_MAX: f64 = 0.4;
/// For tracking to start, every eigenvalue a full analysis leaves out must rank
/// ([`Spread::key`]) higher by this than every one it keeps (the next copy of a mode
/// with `|centre| ≤ 0.4` has `|centre|` larger by `1 - 2|centre| ≥ 0.2`).
const RANK_GAP: f64 = 0.2;
/// Spare candidates tried when two kept ones refine to the same root.
const SPARE_TRIES: usize = 4;
/// Restarts of a fractional refinement that lands on an off-centre copy.
const RECENTRE_TRIES: usize = 3;
/// Ranks closer than this are ties in the selection.
const RANK_TIE: f64 = 1e-6;

/// Where the energy of a Hill eigenvector sits in harmonic index.
#[derive(Debug, Clone, Copy)]
struct Spread {
    /// `Σ_k k |c_k|² / Σ_k |c_k|²`, `c_{±k} = (a_k ∓ i b_k)/2` the coefficients of
    /// `e^{±ikΩt}`, `k` over `-N..=N`. Shifting the eigenvalue by `ijΩ` shifts it by
    /// `-j`.
    centre: f64,
    /// `Σ_k k² |c_k|² / Σ_k |c_k|²` = variance + centre²: among the copies of one
    /// exponent (same variance) smallest for the most centred one; unlike the centre,
    /// it also sees a mixture of far harmonics (`c_4` and `c_{-4}` in equal parts: a
    /// real eigenvalue always has centre 0) as off centre.
    spread: f64,
}

impl Spread {
    /// The selection's ranking key: `|centre|`, plus the variance in excess of 1. A
    /// mode's copies differ only in the centre (same variance), so within one exponent
    /// this is `|centre|`; the excess only demotes eigenvectors spread over harmonics
    /// further apart than `±1` around their centre, such as the real eigenvalues of
    /// far copies merged by truncation (energy at `±4`: centre 0, variance 16), which
    /// the centre alone would take for centred. Variance up to 1 is not penalised: a
    /// real exponent near a fold at `N = 1` has its energy at `±1` (variance 1) and is
    /// the best representative there.
    fn key(&self) -> f64 {
        let variance = self.spread - self.centre * self.centre;
        self.centre.abs() + (variance - 1.0).max(0.0)
    }
}

/// [`Spread`] of `v` (real basis `[a0, a_k, b_k]` per DOF, `ndof` blocks, `nh`
/// harmonics).
fn spread(v: &[Complex64], ndof: usize, nh: usize) -> Spread {
    let len = 2 * nh + 1;
    let i1 = Complex64::new(0.0, 1.0);
    let (mut first, mut second, mut den) = (0.0, 0.0, 0.0);
    for d in 0..ndof {
        let b = &v[d * len..(d + 1) * len];
        den += b[0].norm_sqr();
        for k in 1..=nh {
            let plus = (b[k] - i1 * b[nh + k]).norm_sqr() / 4.0;
            let minus = (b[k] + i1 * b[nh + k]).norm_sqr() / 4.0;
            let k = k as f64;
            first += k * (plus - minus);
            second += k * k * (plus + minus);
            den += plus + minus;
        }
    }
    if den > 0.0 {
        Spread { centre: first / den, spread: second / den }
    } else {
        Spread { centre: f64::INFINITY, spread: f64::INFINITY }
    }
}

/// The verdict on a list of exponents.
fn floquet(
    mut exps: Vec<Complex64>,
    omega: f64,
    opts: &StabilityOptions,
    refined: bool,
) -> Floquet {
    exps.sort_by(|a, b| b.re.total_cmp(&a.re));
    let max_real = exps.first().map_or(f64::NEG_INFINITY, |l| l.re);
    Floquet { stable: max_real <= opts.tol * omega, max_real, exponents: exps, refined }
}

/// For each exponent (one per conjugate pair, not folded), the distance to the nearest
/// other one among all exponents, their conjugates and their copies shifted by `±iΩ`
/// (its own conjugate and copies included: a pair meeting on the real axis or at
/// `±Ω/2`). Copies shifted further need no margin: an eigenvalue met there has its
/// eigenvector off centre by at least one, which the centring check sees.
fn separations(l: &[Complex64], omega: f64) -> Vec<f64> {
    let w = Complex64::new(0.0, omega);
    l.iter()
        .enumerate()
        .map(|(i, &a)| {
            let mut best = f64::INFINITY;
            for (j, &b) in l.iter().enumerate() {
                for (c, z) in [b, b.conj()].into_iter().enumerate() {
                    for shift in [-1.0, 0.0, 1.0] {
                        // A real exponent is its own conjugate (an iteration in complex
                        // arithmetic leaves it an imaginary part of rounding size).
                        let itself = j == i && shift == 0.0 && (c == 0 || real(a, omega));
                        if !itself {
                            best = best.min((a - z - w * shift).norm());
                        }
                    }
                }
            }
            best
        })
        .collect()
}

/// Whether `a` and `b` are one exponent: equal, or conjugate, modulo `iΩ` (to the
/// refinement's tolerance).
fn same_exponent(a: Complex64, b: Complex64, omega: f64) -> bool {
    let tol = 1e-8 * omega.max(a.norm());
    [b, b.conj()].into_iter().any(|z| fold_into_strip(a - z, omega).norm() <= tol)
}

/// Append the exponent `l` (one of a conjugate pair, not folded) to `exps` folded into
/// the strip, and its conjugate unless it is real.
fn push_central(exps: &mut Vec<Complex64>, l: Complex64, omega: f64) {
    let l = fold_into_strip(l, omega);
    exps.push(l);
    if !real(l, omega) {
        exps.push(l.conj());
    }
}

/// Whether a (raw) exponent is real: its imaginary part is at rounding level (the
/// refinement and tracking iterate in complex arithmetic).
fn real(l: Complex64, omega: f64) -> bool {
    l.im.abs() <= 1e-12 * omega
}

/// The result of [`Hill::newton`] at convergence: the root, its unit eigenvector and
/// the iterations; `None` at exactly zero (where the fractional factors `λ^q` branch)
/// or for an eigenvector that cannot be normalised.
fn converged(
    lambda: Complex64,
    mut v: Vec<Complex64>,
    its: usize,
) -> Option<(Complex64, Vec<Complex64>, usize)> {
    if lambda == Complex64::new(0.0, 0.0) {
        return None;
    }
    normalise(&mut v)?;
    Some((lambda, v, its))
}

/// Scale `v` to unit 2-norm; `None` if it is zero or not finite.
fn normalise(v: &mut [Complex64]) -> Option<()> {
    let n = v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    v.iter_mut().for_each(|z| *z /= n);
    Some(())
}

/// Factorise `a` (row-major `n × n`) in place and solve `A x = b` (`b` by `x`);
/// `false` on a zero pivot.
fn lu_solve(a: &mut [Complex64], n: usize, piv: &mut [usize], b: &mut [Complex64]) -> bool {
    if complex_lu_factor(a, n, piv, 0.0) != 0 {
        return false;
    }
    complex_lu_solve(a, n, piv, b);
    true
}

/// `λ^r` and `d/dλ λ^r = r λ^{r-1}` for `r = 0..=min(d, 7)`.
fn powers(lambda: Complex64, d: usize) -> ([Complex64; 8], [Complex64; 8]) {
    let zero = Complex64::new(0.0, 0.0);
    let (mut pw, mut dpw) = ([zero; 8], [zero; 8]);
    let mut p = Complex64::new(1.0, 0.0);
    for r in 0..=d.min(7) {
        pw[r] = p;
        dpw[r] = if r == 0 { zero } else { pw[r - 1] * r as f64 };
        p *= lambda;
    }
    (pw, dpw)
}

/// Exponents are defined modulo `iΩ`; bring one into `(-Ω/2, Ω/2]`.
fn fold_into_strip(l: Complex64, omega: f64) -> Complex64 {
    let shift = (l.im / omega).round();
    Complex64::new(l.re, l.im - shift * omega)
}

fn binomial(n: usize, r: usize) -> f64 {
    (0..r).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// `dst[row0.., col0..] += c · P · D` (`dst` row-major with `stride` columns), where
/// `D` is the real-basis operator with constant factor `ab(0).0` and 2×2 blocks
/// `[[α_k, -β_k], [β_k, α_k]]`, `(α_k, β_k) = ab(k)`, on `(a_k, b_k)`; `P` is
/// row-major `len × len`.
#[allow(clippy::too_many_arguments)]
fn add_product<T>(
    dst: &mut [T],
    stride: usize,
    row0: usize,
    col0: usize,
    c: f64,
    p: &[f64],
    len: usize,
    nh: usize,
    ab: impl Fn(usize) -> (T, T),
) where
    T: Copy
        + std::ops::AddAssign
        + std::ops::Add<Output = T>
        + std::ops::Mul<f64, Output = T>
        + std::ops::Neg<Output = T>,
{
    let a0 = ab(0).0;
    for l in 0..len {
        let pl = &p[l * len..(l + 1) * len];
        let row = &mut dst[(row0 + l) * stride + col0..(row0 + l) * stride + col0 + len];
        let pc = pl[0] * c;
        if pc != 0.0 {
            row[0] += a0 * pc;
        }
        for k in 1..=nh {
            let (pa, pb) = (pl[k] * c, pl[nh + k] * c);
            if pa == 0.0 && pb == 0.0 {
                continue;
            }
            let (alpha, beta) = ab(k);
            // (P D)[:, a_k] = P[:, a_k] α + P[:, b_k] β; (P D)[:, b_k] = -P[:, a_k] β + P[:, b_k] α
            row[k] += alpha * pa + beta * pb;
            row[nh + k] += -(beta * pa) + alpha * pb;
        }
    }
}

/// [`add_product`] for `P = g·I` (a constant gradient, `cg = c·g`): only the diagonal
/// 2×2 blocks of `D`.
fn add_diag<T>(
    dst: &mut [T],
    stride: usize,
    row0: usize,
    col0: usize,
    cg: f64,
    nh: usize,
    ab: impl Fn(usize) -> (T, T),
) where
    T: Copy + std::ops::AddAssign + std::ops::Mul<f64, Output = T> + std::ops::Neg<Output = T>,
{
    if cg == 0.0 {
        return;
    }
    let at = |i: usize, j: usize| (row0 + i) * stride + col0 + j;
    dst[at(0, 0)] += ab(0).0 * cg;
    for k in 1..=nh {
        let (alpha, beta) = ab(k);
        dst[at(k, k)] += alpha * cg;
        dst[at(k, nh + k)] += -(beta * cg);
        dst[at(nh + k, k)] += beta * cg;
        dst[at(nh + k, nh + k)] += alpha * cg;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagonal_shortcut_equals_the_dense_product() {
        // P = g·I through the dense path and the diagonal one.
        let (nh, len, m) = (3, 7, 14);
        let g = 2.5;
        let p: Vec<f64> =
            (0..len * len).map(|k| if k / len == k % len { g } else { 0.0 }).collect();
        let ab = |k: usize| (Complex64::new(1.0 + k as f64, 0.3), Complex64::new(-0.2, k as f64));
        let mut dense = vec![Complex64::new(0.0, 0.0); m * m];
        let mut diag = dense.clone();
        add_product(&mut dense, m, 7, 0, 1.5, &p, len, nh, ab);
        add_diag(&mut diag, m, 7, 0, 1.5 * g, nh, ab);
        assert_eq!(dense, diag);
    }

    #[test]
    fn applied_t_equals_the_assembled_matrix_and_its_derivative() {
        // T(λ)v from `apply_t` against the matrix `eval_t` assembles, and T'(λ)v against
        // a central difference of T(λ)v, on the quarter car (fractional, a dense
        // projection) and the Duffing oscillator, at complex λ.
        use crate::corrector::{solve, SolveOptions};
        use crate::models::{Duffing, QuarterCar};
        fn check<M: Model>(model: &M, omega: f64, lambda: Complex64) {
            let nh = 4;
            let so = SolveOptions { harmonics: nh, ..Default::default() };
            let sol = solve(model, omega, &so, None).unwrap();
            let mut bal = Balance::new(model, nh).unwrap();
            let mut hill = Hill::new(model, nh).unwrap();
            hill.project(&mut bal, &sol.coeffs, omega).unwrap();
            let params = bal.params().to_vec();
            hill.assemble_polynomial(&params, omega, false);
            let m = hill.m;
            let v: Vec<Complex64> =
                (0..m).map(|i| Complex64::new((i as f64 * 0.7).sin(), (i as f64).cos())).collect();
            let tv_at = |hill: &mut Hill, l: Complex64| {
                hill.apply_t(&params, omega, l, true, &v, true);
                (hill.tv.clone(), hill.dtv.clone())
            };
            let (tv, dtv) = tv_at(&mut hill, lambda);
            hill.eval_t(&params, omega, lambda, true);
            let scale = hill.t.iter().fold(0.0f64, |a, z| a.max(z.norm()));
            for i in 0..m {
                let dense: Complex64 = (0..m).map(|j| hill.t[i * m + j] * v[j]).sum();
                assert!(
                    (dense - tv[i]).norm() <= 1e-13 * scale * m as f64,
                    "{i}: {dense} vs {}",
                    tv[i]
                );
            }
            let h = 1e-5 * lambda.norm();
            let (tp, _) = tv_at(&mut hill, lambda + h);
            let (tm, _) = tv_at(&mut hill, lambda - h);
            for i in 0..m {
                let fd = (tp[i] - tm[i]) / (2.0 * h);
                let tol = 1e-6 * (dtv[i].norm() + scale / lambda.norm());
                assert!((fd - dtv[i]).norm() <= tol, "{i}: {fd} vs {}", dtv[i]);
            }
        }
        check(
            &QuarterCar { k3: 5e6, F: 0.03, ..Default::default() },
            10.0,
            Complex64::new(-1.3, 9.0),
        );
        check(
            &Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 },
            0.9,
            Complex64::new(-0.2, 1.1),
        );
        // A fractional signal inside a nonlinear term: its projection is dense.
        crate::oscillator! {
            /// x'' + c x' + x + h x² D^p x = F cos Ωt.
            pub struct FracProduct {
                params { c = 0.1, h = 0.3, p = 0.6, F = 0.3 }
                dofs { x }
                equations {
                    D(x, 2) + c * D(x, 1) + x + h * x.powi(2) * D(x, p) = F * cos(omega * t);
                }
            }
        }
        let model = FracProduct::default();
        assert!(model.signals().iter().any(|s| matches!(s.order, Order::Param(_))));
        check(&model, 0.8, Complex64::new(-0.1, 0.9));
    }

    #[test]
    fn spectral_projection_equals_the_sample_quadrature() {
        // P[g]_{lk} = w_l Σ_s φ_l(θ_s) g(θ_s) φ_k(θ_s), directly, against `project` on
        // the cubic spring's gradients of the Duffing oscillator and the quarter car
        // (M samples, fewer than 4N + 1 for the Duffing oscillator at N = 5).
        use crate::corrector::{solve, SolveOptions};
        use crate::models::{Duffing, QuarterCar};
        fn check<M: Model>(model: &M, omega: f64) {
            let nh = 5;
            let sol =
                solve(model, omega, &SolveOptions { harmonics: nh, ..Default::default() }, None)
                    .unwrap();
            let mut bal = Balance::new(model, nh).unwrap();
            let mut hill = Hill::new(model, nh).unwrap();
            hill.project(&mut bal, &sol.coeffs, omega).unwrap();
            let (len, ns) = (hill.len, hill.samples);
            let mut nonconstant = 0;
            for (idx, d) in hill.diag.iter().enumerate() {
                if d.is_some() {
                    continue;
                }
                nonconstant += 1;
                let g = &bal.gradients()[idx * ns..][..ns];
                let phi = |s: usize, l: usize| {
                    let th = 2.0 * std::f64::consts::PI * s as f64 / ns as f64;
                    match l {
                        0 => 1.0,
                        l if l <= nh => (l as f64 * th).cos(),
                        l => ((l - nh) as f64 * th).sin(),
                    }
                };
                let p = &hill.proj[idx * len * len..][..len * len];
                let big = g.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for l in 0..len {
                    let w = if l == 0 { 1.0 } else { 2.0 } / ns as f64;
                    for k in 0..len {
                        let q: f64 = (0..ns).map(|s| w * phi(s, l) * g[s] * phi(s, k)).sum();
                        let d = (p[l * len + k] - q).abs();
                        assert!(d <= 1e-13 * big, "{idx} ({l},{k}): {} vs {q}", p[l * len + k]);
                    }
                }
            }
            assert!(nonconstant > 0);
        }
        check(&Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 }, 0.9);
        check(&QuarterCar { k3: 5e6, F: 0.03, ..Default::default() }, 10.0);
    }
}
