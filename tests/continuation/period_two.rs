//! The period-2 branch opened by period doubling, against time integration of the
//! equation of motion (a different method: RK4 from the harmonic balance's state).

use ihbm::bifurcation::period_two;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::Quadratic;
use ihbm::results::{BifurcationKind, Curve};

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

/// A stable point of the period-2 branch integrated from its own state for 40 forcing
/// periods: the motion stays on the harmonic-balance waveform, which repeats after
/// two forcing periods and not after one.
#[test]
fn a_period_two_solution_repeats_every_two_periods_in_time_integration() {
    let (_, p2) = branch();
    let p = p2
        .points
        .iter()
        .filter(|p| p.stability.is_stable())
        .min_by(|a, b| (a.omega - 1.95).abs().total_cmp(&(b.omega - 1.95).abs()))
        .unwrap();
    let (omega, w) = (p.omega, p.omega / 2.0);
    let m = Quadratic::default();
    let f = |t: f64, y: [f64; 2]| {
        [y[1], (m.F * (omega * t).cos() - m.c * y[1] - m.k * y[0] - m.k2 * y[0] * y[0]) / m.m]
    };
    let period = std::f64::consts::TAU / omega;
    let steps = 2000;
    let dt = period / steps as f64;
    let mut y = [series(&p.coeffs, w, 0.0), d_series(&p.coeffs, w, 0.0)];
    let scale = (0..400)
        .map(|j| series(&p.coeffs, w, j as f64 * 2.0 * period / 400.0).abs())
        .fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    let mut t = 0.0;
    for i in 0..40 * steps {
        let k1 = f(t, y);
        let k2 = f(t + dt / 2.0, [y[0] + dt / 2.0 * k1[0], y[1] + dt / 2.0 * k1[1]]);
        let k3 = f(t + dt / 2.0, [y[0] + dt / 2.0 * k2[0], y[1] + dt / 2.0 * k2[1]]);
        let k4 = f(t + dt, [y[0] + dt * k3[0], y[1] + dt * k3[1]]);
        for j in 0..2 {
            y[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        }
        t = (i + 1) as f64 * dt;
        if i >= 38 * steps {
            worst = worst.max((y[0] - series(&p.coeffs, w, t)).abs());
        }
    }
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
