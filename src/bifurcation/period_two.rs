//! Branch switching: the branch that period doubling opens (solutions of period
//! `2T = 2·(2π/Ω)`, a harmonic balance in `Ω/2`:
//! [`Balance::with_period`](crate::balance::Balance::with_period)), and the branch that
//! breaks a symmetric curve's symmetry.
//!
//! In the harmonics of `Ω/2` a period-1 solution has only even harmonics, and its
//! Jacobian couples even with even and odd with odd. At period doubling the odd block
//! turns singular (a Floquet multiplier −1): its null vector `v` is the direction of
//! the new branch, which leaves the period-1 solution `a*` like a pitchfork (the
//! branch and its copy shifted by `T` are `a* ± εv + ...`). The first point is
//! corrected with Ω free on the condition `vᵀ(a − a*) = ε`, which the period-1
//! solution cannot satisfy; the branch is then traced like any curve, and ends where
//! its odd harmonics vanish again: where it rejoins the period-1 curve at another
//! period-doubling point.

use crate::balance::Balance;
use crate::continuation::{self, SweepOptions};
use crate::corrector::{self, SolveOptions};
use crate::error::{DirectionFailure, Error, Result};
use crate::linalg::DenseLu;
use crate::model::{DynModel, Model};
use crate::results::{BifurcationKind, Curve, End};
use faer::prelude::ReborrowMut;

/// The largest even-harmonic content (relative to the odd) of a solution counted as
/// symmetric.
const SYMMETRIC: f64 = 1e-4;

/// Relative size of the first step off the period-1 solution along the critical
/// direction (of the largest coefficient of that solution).
const SWITCH_STEP: f64 = 1e-3;

/// A period-1 curve and the period-2 branches switched onto at its period doublings.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodDoubled {
    /// The period-1 curve (`⌈N/2⌉` harmonics of Ω), with its stability.
    pub period_one: Curve,
    /// The period-2 branches (`N` harmonics of Ω/2), one segment or more each, in the
    /// order of the period doublings they start at; Ω values are forcing frequencies,
    /// coefficients are in the harmonics of Ω/2 (a balance with period 2).
    pub period_two: Curve,
    /// The forcing frequency of each period doubling a branch was switched onto at.
    pub switched_at: Vec<f64>,
}

/// The period-2 branches of `model` for Ω from `from` to `to`: the period-1 curve is
/// traced with `⌈N/2⌉` harmonics, and a branch starts at each of its located
/// period-doubling points, except those where a branch already traced came back (a
/// branch that rejoins the period-1 curve ends at the next doubling); `opts.harmonics`
/// counts harmonics of `Ω/2`.
///
/// Errors for bad input, and when the period-1 curve has no located period doubling
/// in the range ([`Error::NoPeriodDoubling`]).
///
/// ```
/// use ihbm::bifurcation::period_two;
/// use ihbm::continuation::SweepOptions;
/// use ihbm::models::Quadratic;
/// let opts = SweepOptions { harmonics: 8, ..Default::default() };
/// let both = period_two(&Quadratic::default(), 1.5, 2.6, &opts).unwrap();
/// // the branch leaves the period-1 curve where it doubles its period
/// assert!((both.period_two.points[0].omega - both.switched_at[0]).abs() < 1e-4);
/// ```
pub fn period_two(
    model: &dyn DynModel,
    from: f64,
    to: f64,
    opts: &SweepOptions,
) -> Result<PeriodDoubled> {
    let n2 = opts.harmonics;
    let n1 = n2.div_ceil(2);
    let mut o1 = opts.clone();
    o1.harmonics = n1;
    o1.convergence = None;
    if o1.stability.is_none() {
        o1.stability = Some(Default::default());
    }
    let curve1 = continuation::sweep(model, from, to, &o1)?;
    let doublings: Vec<_> = curve1
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::PeriodDoubling && b.located)
        .collect();
    if doublings.is_empty() {
        return Err(Error::NoPeriodDoubling { from, to });
    }
    let mut branches: Option<Curve> = None;
    let mut switched_at = Vec::new();
    let mut rejoined_at: Vec<f64> = Vec::new();
    for pd in doublings {
        // The doubling where a traced branch came back starts that same branch again.
        if rejoined_at.iter().any(|&w| (w - pd.omega).abs() <= REJOIN_GAP * pd.omega) {
            continue;
        }
        let curve = branch_at(model, &curve1, pd.omega, pd.after, from, to, opts)?;
        let last = curve.points.last().map(|p| p.omega);
        for (seg, end) in curve.segments.iter().enumerate() {
            if end.ended == End::Rejoined {
                let at = curve.points.iter().rev().find(|p| p.segment == seg).map(|p| p.omega);
                rejoined_at.extend(at.or(last));
            }
        }
        switched_at.push(pd.omega);
        match branches.as_mut() {
            Some(all) => all.append(curve),
            None => branches = Some(curve),
        }
    }
    let period_two = branches.ok_or(Error::NoPeriodDoubling { from, to })?;
    Ok(PeriodDoubled { period_one: curve1, period_two, switched_at })
}

/// How close (relative in Ω) the end of a rejoining branch comes to the doubling it
/// rejoins at: the branch ends on the step that crosses back, within a step of it.
const REJOIN_GAP: f64 = 1e-2;

/// The period-2 branch that leaves `curve1` at its period doubling `omega_pd` (between
/// points `after` and `after + 1`), traced in `[from, to]`, with forcing frequencies.
fn branch_at(
    model: &dyn DynModel,
    curve1: &Curve,
    omega_pd: f64,
    after: usize,
    from: f64,
    to: f64,
    opts: &SweepOptions,
) -> Result<Curve> {
    let (n2, n1) = (opts.harmonics, curve1.harmonics);
    // The period-1 solution at the point, from the nearest point of the curve.
    let near = &curve1.points[after];
    let so = SolveOptions { harmonics: n1, ..Default::default() };
    let sol = corrector::solve(model, omega_pd, &so, Some(&near.coeffs))?;
    let ndof = model.dofs().len();
    let a_star = embed(&sol.coeffs, ndof, n1, n2);
    let w = omega_pd / 2.0;
    let mask = odd_harmonics(ndof, n2);
    let v = critical_direction(model, n2, 2, &a_star, w, &mask)?;
    let opts2 = SweepOptions { period: 2, ..opts.clone() };
    let mut curve = continuation::sweep_branch(
        model,
        from / 2.0,
        to / 2.0,
        &opts2,
        &a_star,
        w,
        &v,
        &mask,
        SWITCH_STEP,
    )?;
    double_frequencies(&mut curve);
    Ok(curve)
}

/// Period-1 coefficients (`n1` harmonics of Ω) as coefficients in `n2` harmonics of
/// `Ω/2`: harmonic `k` becomes harmonic `2k`.
pub fn embed(a: &[f64], ndof: usize, n1: usize, n2: usize) -> Vec<f64> {
    let mut out = vec![0.0; ndof * (2 * n2 + 1)];
    for (&x, to) in a.iter().zip(embedding(ndof, n1, n2)) {
        if let Some(i) = to {
            out[i] = x;
        }
    }
    out
}

/// Where each period-1 coefficient (`n1` harmonics of Ω, `ndof` blocks) goes among the
/// coefficients in `n2` harmonics of Ω/2: harmonic `k` to `2k` (`None` beyond `n2`).
pub(super) fn embedding(ndof: usize, n1: usize, n2: usize) -> Vec<Option<usize>> {
    let l2 = 2 * n2 + 1;
    let to = |d: usize, h: usize, sin: bool| {
        (2 * h <= n2).then(|| d * l2 + if sin { n2 } else { 0 } + 2 * h)
    };
    let mut out = Vec::with_capacity(ndof * (2 * n1 + 1));
    for d in 0..ndof {
        out.push(Some(d * l2));
        out.extend((1..=n1).map(|k| to(d, k, false)));
        out.extend((1..=n1).map(|k| to(d, k, true)));
    }
    out
}

/// A curve and the branch switched onto where it breaks a symmetry.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetryBroken {
    /// The symmetric curve (odd harmonics only), with its stability.
    pub symmetric: Curve,
    /// The branch with even harmonics (a mean and 2Ω, 4Ω, ... components), traced from
    /// the branch point.
    pub broken: Curve,
    /// The forcing frequency of the branch point it was switched onto at.
    pub switched_at: f64,
}

/// The branch that leaves the curve of a symmetric model (odd in its DOFs, forced at
/// odd harmonics: its response has odd harmonics only) at its first located
/// branch point, where a real Floquet multiplier +1 lets even harmonics in without a
/// fold. The direction is the null vector of the Jacobian's even-harmonic block
/// (which the symmetry keeps apart from the odd one).
///
/// Errors for bad input, when the curve has no located branch point in the range
/// ([`Error::NoBranchPoint`]), and when the solution there is not symmetric.
pub fn break_symmetry(
    model: &dyn DynModel,
    from: f64,
    to: f64,
    opts: &SweepOptions,
) -> Result<SymmetryBroken> {
    let mut o = opts.clone();
    o.convergence = None;
    if o.stability.is_none() {
        o.stability = Some(Default::default());
    }
    let curve = continuation::sweep(model, from, to, &o)?;
    let Some(bp) =
        curve.bifurcations.iter().find(|b| b.kind == BifurcationKind::BranchPoint && b.located)
    else {
        return Err(Error::NoBranchPoint { from, to });
    };
    let n = opts.harmonics;
    let so = SolveOptions { harmonics: n, ..Default::default() };
    let near = &curve.points[bp.after];
    let a = corrector::solve(model, bp.omega, &so, Some(&near.coeffs))?.coeffs;
    let ndof = model.dofs().len();
    let even: Vec<bool> = odd_harmonics(ndof, n).into_iter().map(|o| !o).collect();
    let size = |mask: bool| {
        a.iter().zip(&even).filter(|&(_, &e)| e == mask).fold(0.0f64, |m, (x, _)| m.max(x.abs()))
    };
    // Near the branch point the even block is nearly singular and amplifies rounding
    // in the even harmonics (measured 1e-7 of the odd ones at N = 16); a solution
    // that broke the symmetry would have them of order one.
    if size(true) > SYMMETRIC * size(false) {
        return Err(Error::NotSymmetric { omega: bp.omega, ratio: size(true) / size(false) });
    }
    let a: Vec<f64> = a.iter().zip(&even).map(|(&x, &e)| if e { 0.0 } else { x }).collect();
    let v = critical_direction(model, n, 1, &a, bp.omega, &even)?;
    let broken =
        continuation::sweep_branch(model, from, to, opts, &a, bp.omega, &v, &even, SWITCH_STEP)?;
    let switched_at = bp.omega;
    Ok(SymmetryBroken { symmetric: curve, broken, switched_at })
}

/// Which coefficients (`ndof` blocks of `2n + 1`) belong to odd harmonics.
pub(super) fn odd_harmonics(ndof: usize, n: usize) -> Vec<bool> {
    let l = 2 * n + 1;
    (0..ndof * l)
        .map(|i| {
            let k = i % l;
            let h = if k <= n { k } else { k - n };
            h % 2 == 1
        })
        .collect()
}

/// The null vector of the block of the Jacobian at `a` (harmonics of `w`) on the
/// coefficients `odd` marks: inverse iteration from a vector in them, which the
/// Jacobian keeps apart from the others (the odd harmonics of Ω/2 at a period-1
/// solution; the even harmonics of Ω at a symmetric one).
fn critical_direction(
    model: &dyn DynModel,
    n2: usize,
    period: usize,
    a: &[f64],
    w: f64,
    odd: &[bool],
) -> Result<Vec<f64>> {
    let mut bal = Balance::with_period(model, n2, period)?;
    let len = bal.len();
    debug_assert_eq!(len, odd.len());
    let mut lu = DenseLu::new(len);
    let mut r = vec![0.0; len];
    bal.jacobian(a, w, &mut r, lu.matrix_mut().rb_mut());
    if lu.factor().is_nan() {
        return Err(Error::NoCriticalDirection {
            omega: w,
            failure: DirectionFailure::NonFiniteJacobian,
        });
    }
    let mut v: Vec<f64> = odd.iter().map(|&o| if o { 1.0 } else { 0.0 }).collect();
    for _ in 0..3 {
        lu.solve(&mut v);
        // rounding aside the other components stay zero: keep them so
        v.iter_mut().zip(odd).filter(|&(_, &o)| !o).for_each(|(x, _)| *x = 0.0);
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(Error::NoCriticalDirection {
                omega: w,
                failure: DirectionFailure::Vanished,
            });
        }
        v.iter_mut().for_each(|x| *x /= norm);
    }
    Ok(v)
}

/// Ω in the curve's own units (`Ω/2` of the balance with period 2) back to the
/// forcing frequency.
fn double_frequencies(c: &mut Curve) {
    for p in &mut c.points {
        p.omega *= 2.0;
        p.param *= 2.0;
    }
    for f in &mut c.folds {
        f.omega *= 2.0;
        f.param *= 2.0;
    }
    for b in &mut c.bifurcations {
        b.omega *= 2.0;
        b.param *= 2.0;
    }
    for j in &mut c.jumps {
        j.at *= 2.0;
    }
    for s in &mut c.segments {
        s.from *= 2.0;
        s.to *= 2.0;
    }
}
