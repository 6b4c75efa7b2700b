//! Hill stability at scale: chains of 5 and 10 masses (each link a linear + cubic spring
//! with a viscous and a fractional damper, forced at the last mass).
//!
//! - Integer orders (`p = 1`: the "fractional" damper is a second viscous one, and Hill's
//!   method treats the order parameter as the integer it is): the Floquet multipliers of
//!   the linearised equations come independently from the monodromy matrix, integrated
//!   over one period by RK4 in this file; they must be `exp(λT)` of the Hill exponents
//!   at points on every branch, the unstable middle ones included, and the curve's
//!   verdicts must be theirs.
//! - Fractional orders (`p = 0.5`): the tracked exponents against a full analysis at
//!   every point of the curve.
//! - Continuation on the band (chains of 20 masses, whose block-tridiagonal Jacobian
//!   is factorised as a band): the linear chain's closed form, and the dense corrector
//!   confirming the nonlinear chain's points. The 10-mass chain at N = 11 above is on
//!   the band too.

use crate::common as stability_common;

use ihbm::balance::Balance;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::fourier::eval;
use ihbm::model::Model;
use ihbm::results::Curve;
use ihbm::stability::{Hill, StabilityOptions};
use num_complex::Complex64;

#[path = "../../benches/chains/mod.rs"]
pub(crate) mod chains;
use chains::{Chain10, Chain20, Chain5};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::linalg::BorderedLu;

/// The parameters every chain here shares (those of the generated models).
struct Link {
    m: f64,
    k: f64,
    k3: f64,
    damping: f64,
}

/// Monodromy matrix (row-major `2n × 2n`, state `[δx, δx']`) of the chain linearised
/// about the periodic solution `coeffs` at `omega`, integer-order damping `damping` on
/// each link (`c + h` with `p = 1`): RK4 with `steps` steps over one period.
fn monodromy(l: &Link, n: usize, coeffs: &[f64], omega: f64, steps: usize) -> Vec<f64> {
    let len = coeffs.len() / n;
    let period = 2.0 * std::f64::consts::PI / omega;
    let h = period / steps as f64;
    // Link stiffness k + 3 k3 y_i² along the orbit, at every half step.
    let stiff: Vec<Vec<f64>> = (0..=2 * steps)
        .map(|s| {
            let theta = omega * h * s as f64 / 2.0;
            let x: Vec<f64> =
                (0..n).map(|d| eval(&coeffs[d * len..(d + 1) * len], theta)).collect();
            (0..n)
                .map(|i| {
                    let y = if i == 0 { x[0] } else { x[i] - x[i - 1] };
                    l.k + 3.0 * l.k3 * y * y
                })
                .collect()
        })
        .collect();
    let rhs = |ks: &[f64], z: &[f64], out: &mut [f64]| {
        let (x, v) = z.split_at(n);
        // Link forces f_i = k_i δy_i + c δy_i', δy_i = δx_i - δx_{i-1}.
        let f = |i: usize| {
            let (y, yd) = if i == 0 { (x[0], v[0]) } else { (x[i] - x[i - 1], v[i] - v[i - 1]) };
            ks[i] * y + l.damping * yd
        };
        for i in 0..n {
            out[i] = v[i];
            let next = if i + 1 < n { f(i + 1) } else { 0.0 };
            out[n + i] = -(f(i) - next) / l.m;
        }
    };
    let dim = 2 * n;
    let mut phi = vec![0.0; dim * dim];
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) =
        (vec![0.0; dim], vec![0.0; dim], vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]);
    for col in 0..dim {
        let mut z = vec![0.0; dim];
        z[col] = 1.0;
        for s in 0..steps {
            let (a, b, c) = (&stiff[2 * s], &stiff[2 * s + 1], &stiff[2 * s + 2]);
            rhs(a, &z, &mut k1);
            tmp.iter_mut().zip(&z).zip(&k1).for_each(|((t, z), k)| *t = z + 0.5 * h * k);
            rhs(b, &tmp, &mut k2);
            tmp.iter_mut().zip(&z).zip(&k2).for_each(|((t, z), k)| *t = z + 0.5 * h * k);
            rhs(b, &tmp, &mut k3);
            tmp.iter_mut().zip(&z).zip(&k3).for_each(|((t, z), k)| *t = z + h * k);
            rhs(c, &tmp, &mut k4);
            for i in 0..dim {
                z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        for i in 0..dim {
            phi[i * dim + col] = z[i];
        }
    }
    phi
}

/// Eigenvalues of a real row-major square matrix.
fn eigenvalues(a: &[f64], dim: usize) -> Vec<Complex64> {
    let m = faer::Mat::<f64>::from_fn(dim, dim, |i, j| a[i * dim + j]);
    m.eigenvalues().unwrap().into_iter().map(|z| Complex64::new(z.re, z.im)).collect()
}

/// Indices of one point inside every branch of `curve`: the middle point between
/// consecutive folds (and the ends) of each segment.
fn branch_points(curve: &Curve) -> Vec<usize> {
    let mut cuts: Vec<usize> = curve.folds.iter().map(|f| f.after + 1).collect();
    for i in 1..curve.points.len() {
        if curve.points[i].segment != curve.points[i - 1].segment {
            cuts.push(i);
        }
    }
    cuts.push(0);
    cuts.push(curve.points.len());
    cuts.sort_unstable();
    cuts.dedup();
    cuts.windows(2).filter(|w| w[1] > w[0]).map(|w| (w[0] + w[1]) / 2).collect()
}

/// The integer-order check on the chain `model` with `n` masses at `nh` harmonics, Ω
/// from `from` to `to`. From 0.4 up the primary resonances (which fold) are resolved
/// (at N = 11 Hill and monodromy agree to a few 1e-9 in λ); below, where the first mode
/// resonates and the others sit near multiples of Ω, they differ by up to 1e-2 in λ at
/// N = 5: truncation, not the method.
fn monodromy_check<M: Model>(model: &M, n: usize, nh: usize, from: f64, to: f64) {
    let link = Link { m: 1.0, k: 1.0, k3: 0.5, damping: 0.02 + 0.02 };
    let opts = SweepOptions { harmonics: nh, ..Default::default() };
    let curve = sweep(model, from, to, &opts).unwrap();
    assert!(!curve.folds.is_empty(), "the resonance should fold: {:?}", curve.stats);
    let so = StabilityOptions::default();
    let mut bal = Balance::new(model, nh).unwrap();
    let mut hill = Hill::new(model, nh).unwrap();
    let mut unstable = 0;
    for i in branch_points(&curve) {
        let p = &curve.points[i];
        let period = 2.0 * std::f64::consts::PI / p.omega;
        // Steps: 400 per period of the fastest mode (≈ 2.5 rad/s here), at least 2000.
        let steps = ((period * 2.5 * 400.0 / (2.0 * std::f64::consts::PI)) as usize).max(2000);
        let phi = monodromy(&link, n, &p.coeffs, p.omega, steps);
        let mut mu = eigenvalues(&phi, 2 * n);
        // RK4's own error: the same with half the steps differs by 16 times it.
        let coarse = eigenvalues(&monodromy(&link, n, &p.coeffs, p.omega, steps / 2), 2 * n);
        let f = hill.analyse(&mut bal, &p.coeffs, p.omega, &so).unwrap();
        assert_eq!(f.exponents.len(), 2 * n, "Ω = {}: {f:?}", p.omega);
        let big = mu.iter().fold(1.0f64, |a, z| a.max(z.norm()));
        for lambda in &f.exponents {
            let want = (lambda * period).exp();
            let (j, d) = mu
                .iter()
                .enumerate()
                .map(|(j, z)| (j, (z - want).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            let rk = coarse.iter().map(|z| (z - mu[j]).norm()).fold(f64::INFINITY, f64::min);
            assert!(
                d <= 1e-6 * big + rk,
                "point {i}, Ω = {}: Hill λ = {lambda}, exp(λT) = {want}, nearest multiplier {} \
                 (off by {d:e}, RK4 error ~{rk:e}); multipliers {mu:?}",
                p.omega,
                mu[j]
            );
            mu.remove(j);
        }
        // The curve's verdict is the multipliers' (|μ| > 1 iff Re λ > 0), away from 1.
        let growth = eigenvalues(&phi, 2 * n)
            .iter()
            .map(|z| z.norm().ln() / period)
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(growth.abs() > 1e-6 * p.omega, "point {i} too close to a boundary: {growth}");
        assert_eq!(
            p.stability.is_stable(),
            growth < 0.0,
            "point {i}, Ω = {}: growth {growth}",
            p.omega
        );
        unstable += usize::from(!p.stability.is_stable());
    }
    assert!(unstable > 0, "no unstable middle branch checked");
}

#[test]
fn chain5_multipliers_are_the_monodromy_ones_on_every_branch() {
    monodromy_check(&Chain5 { p: 1.0, ..Default::default() }, 5, 11, 0.4, 2.5);
}

#[test]
fn chain10_multipliers_are_the_monodromy_ones_on_every_branch() {
    // this curve is continued on the band (230 unknowns, kl = ku = 45)
    let chain = Chain10::default();
    let bal = Balance::new(&chain, 11).unwrap();
    assert!(BorderedLu::new(bal.len(), 1, Some(bal.jacobian_band())).is_banded());
    monodromy_check(&Chain10 { p: 1.0, ..Default::default() }, 10, 11, 0.4, 2.5);
}

#[test]
fn chain5_fractional_tracking_agrees_with_full_analyses() {
    let model = Chain5::default();
    let opts = SweepOptions { harmonics: 5, ..Default::default() };
    let curve = sweep(&model, 0.05, 2.5, &opts).unwrap();
    let (k, partial) = stability_common::compare(&model, &curve, 5);
    assert_eq!(curve.stats.stability_full, k.full);
    assert!(partial > 0, "no partial set tracked (the low-Ω stretch has them)");
    assert!(
        curve.points.iter().any(|p| !p.stability.is_stable()),
        "the middle branches are unstable"
    );
}

/// Fractional orders, by another method: at every point of the curve the verdict is
/// whether `det T(λ)` has roots in the unstable half of the central strip, counted by
/// the argument principle (no eigensolve, no refinement, no choice of copies). Past the
/// folds of the resonance the real exponent that crossed zero is small and positive
/// (about 1e-3 to 1e-2, right of the branch point of `λ^p`): the analysis must find it
/// on the middle branch, and the verdict may change only at a fold there.
#[test]
fn chain5_fractional_verdicts_are_the_root_count() {
    let model = Chain5::default();
    let nh = 5;
    let opts = SweepOptions { harmonics: nh, ..Default::default() };
    let curve = sweep(&model, 0.05, 2.5, &opts).unwrap();
    let so = StabilityOptions::default();
    let mut bal = Balance::new(&model, nh).unwrap();
    let mut hill = Hill::new(&model, nh).unwrap();
    let mut counted_unstable = 0;
    for p in &curve.points {
        let Some(stable) = p.stability.verdict() else { continue };
        let n = hill.unstable_roots(&mut bal, &p.coeffs, p.omega, &so).unwrap();
        assert_eq!(stable, n == 0, "Ω = {}: verdict {stable}, {n} unstable roots", p.omega);
        counted_unstable += usize::from(n > 0);
    }
    assert!(counted_unstable > 0, "the middle branches are unstable");
    // In the primary resonance (Ω < 0.4) every change of verdict is at a fold.
    for (i, w) in curve.points.windows(2).enumerate() {
        let (a, b) = (w[0].stability.verdict(), w[1].stability.verdict());
        if w[1].omega < 0.4 && a.is_some() && b.is_some() && a != b {
            assert!(
                curve.folds.iter().any(|f| f.after == i),
                "a change at Ω = {} off a fold",
                w[0].omega
            );
        }
    }
}

/// Integer orders: where the correction rule doubts a tracked set whose exponents
/// still stand for as many distinct families of copies, tracking goes on without a
/// full analysis (about a dozen points of this curve, in its multi-fold resonance).
#[test]
fn chain5_integer_tracking_agrees_with_full_analyses() {
    let model = Chain5 { p: 1.0, ..Default::default() };
    let opts = SweepOptions { harmonics: 5, ..Default::default() };
    let curve = sweep(&model, 0.05, 2.5, &opts).unwrap();
    let (k, partial) = stability_common::compare(&model, &curve, 5);
    assert_eq!(curve.stats.stability_full, k.full);
    assert_eq!(partial, 0, "integer orders refine every candidate");
    assert!(curve.points.iter().any(|p| !p.stability.is_stable()));
}

/// The unknowns `X_i` of the linear chain (`k3 = 0`) forced by `F cos Ωt` at its last
/// mass: `(−mΩ² I + κ L) X = F e_n`, `κ = k + c iΩ + h (iΩ)^p` per link, `L` the
/// grounded chain's tridiagonal (2 on the diagonal but 1 at the free end, −1 beside
/// it); `x_i = Re(X_i e^{iΩt})`. Thomas's algorithm.
fn linear_chain(chain: &Chain20, omega: f64) -> Vec<Complex64> {
    let Chain20 { m, k, c, h, p, F: f, .. } = *chain;
    let n = chain.dofs().len();
    let iw = Complex64::new(0.0, omega);
    let kappa = k + c * iw + h * iw.powf(p);
    let diag = |i: usize| -m * omega * omega + kappa * if i + 1 < n { 2.0 } else { 1.0 };
    let off = -kappa;
    let (mut cp, mut dp) = (vec![Complex64::new(0.0, 0.0); n], vec![Complex64::new(0.0, 0.0); n]);
    let rhs = |i: usize| Complex64::new(if i + 1 == n { f } else { 0.0 }, 0.0);
    cp[0] = off / diag(0);
    dp[0] = rhs(0) / diag(0);
    for i in 1..n {
        let den = diag(i) - off * cp[i - 1];
        cp[i] = off / den;
        dp[i] = (rhs(i) - off * dp[i - 1]) / den;
    }
    let mut x = dp;
    for i in (0..n - 1).rev() {
        let next = x[i + 1];
        x[i] -= cp[i] * next;
    }
    x
}

/// The curve continues on the band ([`BorderedLu`] with the Jacobian's bandwidths):
/// for a chain of 20 masses at N = 3 (140 unknowns) the Jacobian is block tridiagonal
/// with `kl = ku = 13`, which pays, and with `k3 = 0` every point must be the closed
/// form of the linear chain (first harmonic; the others zero).
#[test]
fn a_linear_chain_continued_on_the_band_is_its_closed_form() {
    let model = Chain20 { k3: 0.0, ..Default::default() };
    let nh = 3;
    let l = 2 * nh + 1;
    let bal = Balance::new(&model, nh).unwrap();
    assert_eq!(bal.jacobian_band(), (2 * l - 1, 2 * l - 1));
    assert!(BorderedLu::new(bal.len(), 1, Some(bal.jacobian_band())).is_banded());
    let opts = SweepOptions { harmonics: nh, stability: None, ..Default::default() };
    let curve = sweep(&model, 0.05, 2.5, &opts).unwrap();
    assert!(curve.points.len() > 100, "{:?}", curve.stats);
    for p in &curve.points {
        let x = linear_chain(&model, p.omega);
        let big = x.iter().fold(0.0f64, |a, z| a.max(z.norm()));
        for (i, xi) in x.iter().enumerate() {
            let c = &p.coeffs[i * l..(i + 1) * l];
            let got = Complex64::new(c[1], -c[1 + nh]);
            assert!((got - xi).norm() <= 1e-8 * big, "Ω = {}, x{}: {got} vs {xi}", p.omega, i + 1);
            for (j, v) in c.iter().enumerate().filter(|&(j, _)| j != 1 && j != 1 + nh) {
                assert!(v.abs() <= 1e-10 * big, "Ω = {}, x{} coefficient {j}: {v}", p.omega, i + 1);
            }
        }
    }
}

/// A nonlinear chain of 20 masses at N = 5 (220 unknowns, band 21 + 21) continued on
/// the band through its folds: every tenth point, and every fold, is confirmed by the
/// dense Newton corrector ([`ihbm::corrector::solve`], its own LU) started there.
#[test]
fn a_nonlinear_chain_on_the_band_gives_points_the_dense_corrector_confirms() {
    let model = Chain20::default();
    let nh = 5;
    let bal = Balance::new(&model, nh).unwrap();
    assert!(BorderedLu::new(bal.len(), 1, Some(bal.jacobian_band())).is_banded());
    let opts = SweepOptions { harmonics: nh, stability: None, ..Default::default() };
    let curve = sweep(&model, 0.05, 1.0, &opts).unwrap();
    assert!(!curve.folds.is_empty(), "the resonances should fold: {:?}", curve.stats);
    let so = SolveOptions { harmonics: nh, ..Default::default() };
    let checked = curve.points.iter().step_by(10).map(|p| (p.omega, &p.coeffs));
    let folds = curve.folds.iter().map(|f| (f.omega, &f.coeffs));
    for (omega, coeffs) in checked.chain(folds) {
        let norm = coeffs.iter().map(|v| v * v).sum::<f64>().sqrt();
        match solve(&model, omega, &so, Some(coeffs)) {
            Ok(sol) => {
                let d = sol.coeffs.iter().zip(coeffs).map(|(a, b)| (a - b).powi(2)).sum::<f64>();
                assert!(sol.iterations <= 1, "Ω = {omega}: {} iterations", sol.iterations);
                assert!(d.sqrt() <= 1e-8 * norm, "Ω = {omega}: moved by {}", d.sqrt());
            }
            // at a fold the dense Jacobian is singular: the point must then already
            // be a solution, which the corrector's residual at its start shows
            Err(ihbm::Error::SingularJacobian { .. }) => {
                let mut hb = Balance::new(&model, nh).unwrap();
                let (mut r, mut r0) = (vec![0.0; hb.len()], vec![0.0; hb.len()]);
                hb.residual(coeffs, omega, &mut r);
                hb.residual(&vec![0.0; hb.len()], omega, &mut r0);
                let (rn, scale) = (norm_of(&r), norm_of(&r0));
                assert!(rn <= 1e-9 * scale, "Ω = {omega}: residual {rn:e} of {scale:e}");
            }
            Err(e) => panic!("Ω = {omega}: {e}"),
        }
    }
}

fn norm_of(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}
