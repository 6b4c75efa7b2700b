//! Branches switched onto: the period-2 branch opened by period doubling and the
//! branch that breaks a symmetric curve's symmetry, against time integration of the
//! equation of motion (a different method: RK4 from the harmonic balance's state).

use ihbm::bifurcation::{break_symmetry, period_two};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{Duffing, Quadratic};
use ihbm::results::{BifurcationKind, Curve, CurvePoint};

const N2: usize = 8;

fn branch() -> (Curve, Curve) {
    let model = Quadratic::default();
    // the period-1 curve traced on its own, not the one the switch used
    let p1 =
        sweep(&model, 1.5, 2.6, &SweepOptions { harmonics: N2 / 2, ..Default::default() }).unwrap();
    let both = period_two(&model, 1.5, 2.6, &SweepOptions { harmonics: N2, ..Default::default() })
        .unwrap();
    (p1, both.period_two)
}

/// `x(t)` of coefficients in harmonics of `w` (one DOF: `[a0, a1..aN, b1..bN]`).
fn series(c: &[f64], w: f64, t: f64) -> f64 {
    let n = (c.len() - 1) / 2;
    c[0] + (1..=n)
        .map(|k| c[k] * (k as f64 * w * t).cos() + c[n + k] * (k as f64 * w * t).sin())
        .sum::<f64>()
}

fn d_series(c: &[f64], w: f64, t: f64) -> f64 {
    let n = (c.len() - 1) / 2;
    (1..=n)
        .map(|k| {
            let kw = k as f64 * w;
            -c[k] * kw * (kw * t).sin() + c[n + k] * kw * (kw * t).cos()
        })
        .sum()
}

#[test]
fn the_period_two_branch_starts_at_the_period_doubling_of_the_period_one_curve() {
    let (p1, p2) = branch();
    let pd = p1.bifurcations.iter().find(|b| b.kind == BifurcationKind::PeriodDoubling).unwrap();
    let first = &p2.points[0];
    assert!((first.omega - pd.omega).abs() < 1e-5 * pd.omega, "{} vs {}", first.omega, pd.omega);
    // at the start the odd harmonics of Ω/2 are the switching step, then they grow
    let odd = |c: &[f64]| -> f64 {
        let n = (c.len() - 1) / 2;
        (1..=n).filter(|k| k % 2 == 1).map(|k| c[k].hypot(c[n + k])).fold(0.0, f64::max)
    };
    let amp = |c: &[f64]| c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(odd(&first.coeffs) < 1e-2 * amp(&first.coeffs));
    assert!(p2.points.iter().any(|p| odd(&p.coeffs) > 0.3 * amp(&p.coeffs)));
    assert!(p2.points.len() > 10);
}

/// The stable point of the period-2 branch nearest Ω = 1.95, and the model.
fn stable_period_two_point() -> (CurvePoint, Quadratic) {
    let (_, p2) = branch();
    let p = p2
        .points
        .into_iter()
        .filter(|p| p.stability.is_stable())
        .min_by(|a, b| (a.omega - 1.95).abs().total_cmp(&(b.omega - 1.95).abs()))
        .unwrap();
    (p, Quadratic::default())
}

/// The quadratic oscillator's `x''` as a function of `(t, [x, x'])`.
fn quadratic_rhs(m: &Quadratic, omega: f64) -> impl Fn(f64, [f64; 2]) -> [f64; 2] + '_ {
    move |t, y| {
        [y[1], (m.F * (omega * t).cos() - m.c * y[1] - m.k * y[0] - m.k2 * y[0] * y[0]) / m.m]
    }
}

/// A stable point of the period-2 branch integrated from its own state for 40 forcing
/// periods: the motion stays on the harmonic-balance waveform, which repeats after
/// two forcing periods and not after one.
#[test]
fn a_period_two_solution_repeats_every_two_periods_in_time_integration() {
    let (p, m) = stable_period_two_point();
    let (omega, w) = (p.omega, p.omega / 2.0);
    let f = quadratic_rhs(&m, omega);
    let period = std::f64::consts::TAU / omega;
    let scale = (0..400)
        .map(|j| series(&p.coeffs, w, j as f64 * 2.0 * period / 400.0).abs())
        .fold(0.0, f64::max);
    // over the last two forcing periods of forty
    let worst = rk4_off_series(f, omega, &p.coeffs, w, 40, 2);
    assert!(worst < 1e-6 * scale, "Ω = {omega}: time integration {worst:e} off the HB waveform");
    // period 2T, not T
    let shift = (0..200)
        .map(|j| {
            let s = j as f64 * period / 200.0;
            (series(&p.coeffs, w, s + period) - series(&p.coeffs, w, s)).abs()
        })
        .fold(0.0, f64::max);
    assert!(shift > 0.1 * scale, "x(t + T) = x(t): not period 2 ({shift:e})");
}

/// Samples per forcing period of [`rk4`].
const STEPS: usize = 2000;

/// RK4 of `x'' = f(t, x, x')` (as `f(t, [x, x'])`) from `y0` for `periods` forcing
/// periods of `2π/omega`, [`STEPS`] steps each; `x` at the ends of the steps of the
/// last `last` periods.
fn rk4(
    f: impl Fn(f64, [f64; 2]) -> [f64; 2],
    omega: f64,
    mut y: [f64; 2],
    periods: usize,
    last: usize,
) -> Vec<f64> {
    let dt = std::f64::consts::TAU / omega / STEPS as f64;
    let mut out = Vec::with_capacity(last * STEPS);
    for i in 0..periods * STEPS {
        let t = i as f64 * dt;
        let k1 = f(t, y);
        let k2 = f(t + dt / 2.0, [y[0] + dt / 2.0 * k1[0], y[1] + dt / 2.0 * k1[1]]);
        let k3 = f(t + dt / 2.0, [y[0] + dt / 2.0 * k2[0], y[1] + dt / 2.0 * k2[1]]);
        let k4 = f(t + dt, [y[0] + dt * k3[0], y[1] + dt * k3[1]]);
        for j in 0..2 {
            y[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        }
        if i >= (periods - last) * STEPS {
            out.push(y[0]);
        }
    }
    out
}

/// [`rk4`] from the state of the series `c` (harmonics of `w`): the largest distance
/// from the series over the last `last` periods.
fn rk4_off_series(
    f: impl Fn(f64, [f64; 2]) -> [f64; 2],
    omega: f64,
    c: &[f64],
    w: f64,
    periods: usize,
    last: usize,
) -> f64 {
    let dt = std::f64::consts::TAU / omega / STEPS as f64;
    let start = (periods - last) * STEPS;
    rk4(f, omega, [series(c, w, 0.0), d_series(c, w, 0.0)], periods, last)
        .iter()
        .enumerate()
        .map(|(j, x)| (x - series(c, w, (start + j + 1) as f64 * dt)).abs())
        .fold(0.0, f64::max)
}

/// The hardening Duffing oscillator (F = 2, c = 0.05) loses its symmetric response's
/// stability at a branch point without a fold; the branch that leaves there has a
/// mean and even harmonics, is a solution of the equation of motion, and ends where
/// it crosses back through the symmetric curve at the other branch point.
#[test]
fn the_symmetry_breaking_branch_is_asymmetric_and_solves_the_equation_of_motion() {
    let d = Duffing { F: 2.0, c: 0.05, ..Duffing::default() };
    let opts = SweepOptions { harmonics: 16, ..Default::default() };
    let res = break_symmetry(&d, 0.2, 4.0, &opts).unwrap();
    let bps: Vec<f64> = res
        .symmetric
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::BranchPoint)
        .map(|b| b.omega)
        .collect();
    assert_eq!(bps.len(), 2, "{:?}", res.symmetric.bifurcations);
    let b = &res.broken;
    assert!((b.points[0].omega - bps[0]).abs() < 1e-5 * bps[0]);
    assert_eq!(b.segments[0].ended.to_string(), "rejoined the curve it branched from");
    let last = b.points.last().unwrap();
    assert!(
        (last.omega - bps[1]).abs() < 1e-2 * bps[1],
        "ends at {} not near {}",
        last.omega,
        bps[1]
    );
    // the symmetric curve has no mean; the branch has one
    assert!(res.symmetric.points.iter().all(|p| p.outputs[0].mean.abs() < 1e-9));
    let p = b
        .points
        .iter()
        .filter(|p| p.stability.is_stable())
        .max_by(|x, y| x.outputs[0].mean.abs().total_cmp(&y.outputs[0].mean.abs()))
        .unwrap();
    assert!(p.outputs[0].mean.abs() > 0.1, "mean {}", p.outputs[0].mean);
    let scale = p.outputs[0].max_abs;
    // N = 16: with N = 6 the truncation alone is 7e-3 of the amplitude at x ≈ 1.9
    let omega = p.omega;
    let f = |t: f64, y: [f64; 2]| {
        [y[1], (d.F * (omega * t).cos() - d.c * y[1] - d.k * y[0] - d.k3 * y[0].powi(3)) / d.m]
    };
    let off = rk4_off_series(f, omega, &p.coeffs, omega, 20, 1);
    assert!(off < 1e-5 * scale, "Ω = {}: RK4 {off:e} off the harmonic balance", p.omega);
    // x(t + T/2) = -x(t) holds for the symmetric response, not for this one
    let period = std::f64::consts::TAU / p.omega;
    let asym = (0..200)
        .map(|j| {
            let t = j as f64 * period / 200.0;
            (series(&p.coeffs, p.omega, t + 0.5 * period) + series(&p.coeffs, p.omega, t)).abs()
        })
        .fold(0.0, f64::max);
    assert!(asym > 0.1 * scale, "half-period antisymmetric ({asym:e})");
}

/// A harmonic balance in Ω/2 started independently — from the Fourier coefficients of
/// the attractor that RK4 reaches from rest-near initial conditions after 300 forcing
/// periods, not from the branch — converges to the branch's point at that Ω.
#[test]
fn a_balance_in_half_the_frequency_started_from_time_integration_finds_the_branch() {
    use ihbm::corrector::{solve, SolveOptions};
    let (p, m) = stable_period_two_point();
    let (omega, w) = (p.omega, p.omega / 2.0);
    let f = quadratic_rhs(&m, omega);
    // integrate from a small state (not the branch's) until the transient has decayed
    let samples = rk4(f, omega, [0.05, 0.0], 300, 2);
    // its coefficients in harmonics of Ω/2 over the last two forcing periods
    let ns = samples.len() as f64;
    let mut guess = vec![0.0; 2 * N2 + 1];
    for (j, x) in samples.iter().enumerate() {
        let th = std::f64::consts::TAU * (j + 1) as f64 / ns; // phase ωt of the sample, mod 2π
        guess[0] += x / ns;
        for k in 1..=N2 {
            guess[k] += 2.0 * x * (k as f64 * th).cos() / ns;
            guess[N2 + k] += 2.0 * x * (k as f64 * th).sin() / ns;
        }
    }
    let so = SolveOptions { harmonics: N2, period: 2, ..Default::default() };
    let sol = solve(&m, w, &so, Some(&guess)).unwrap();
    // the attractor may be the branch or its copy shifted by T (odd harmonics negated)
    let same = |sign: f64| {
        sol.coeffs
            .iter()
            .zip(&p.coeffs)
            .enumerate()
            .map(|(i, (a, b))| {
                let k = if i <= N2 { i } else { i - N2 };
                let s = if k % 2 == 1 { sign } else { 1.0 };
                (a - s * b).abs()
            })
            .fold(0.0, f64::max)
    };
    let scale = p.coeffs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let d = same(1.0).min(same(-1.0));
    assert!(d < 1e-8 * scale, "independent balance {d:e} from the branch at Ω = {omega}");
}
