//! Identities of the spectral operators and the dual-number Jacobian (proptest).

use ihbm::balance::Balance;
use ihbm::fourier::{apply_order, coeff_len, max_abs, rms, sample_count, Fourier, MaxAbs};
use ihbm::models::{FractionalDuffing, QuarterCar};
use ihbm::Model;
use proptest::prelude::*;
use std::f64::consts::PI;

/// Gauss–Legendre nodes and weights on [-1, 1] (Newton on P_n).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (1..=n)
        .map(|i| {
            let mut x = (PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Basis function `index` of the layout [1, cos kθ.., sin kθ..] as (k, phase α):
/// φ = cos(kΩt + α).
fn basis(index: usize, n: usize) -> (f64, f64) {
    if index <= n {
        (index as f64, 0.0)
    } else {
        ((index - n) as f64, -PI / 2.0)
    }
}

/// ∫_u^T cos(w t + c) dt.
fn int_cos(w: f64, c: f64, u: f64, t: f64) -> f64 {
    if w == 0.0 {
        (t - u) * c.cos()
    } else {
        ((w * t + c).sin() - (w * u + c).sin()) / w
    }
}

/// The Galerkin average of eq. (20) with the Caputo derivative from 0, by quadrature:
/// w_i/T ∫_0^T φ_i(t) C D^p φ_j(t) dt with C D^p φ(t) = 1/Γ(1-p) ∫_0^t φ'(t-u) u^{-p} du.
/// Exchanging the integrals leaves 1/Γ(1-p) ∫_0^T u^{-p} H(u) du, where
/// H(u) = ∫_u^T φ_i(t) φ_j'(t-u) dt is elementary; the outer integral is done with
/// Gauss–Legendre panels (v = u^{1-p} on the first panel removes the singularity).
fn caputo_average(i: usize, j: usize, n: usize, p: f64, omega: f64, periods: usize) -> f64 {
    let (ki, ai) = basis(i, n);
    let (kj, aj) = basis(j, n);
    if kj == 0.0 {
        return 0.0; // φ_0 is constant: its Caputo derivative vanishes
    }
    let t_end = 2.0 * PI * periods as f64 / omega;
    let (wi, wj) = (ki * omega, kj * omega);
    // φ_j'(s) = wj cos(wj s + aj + π/2)
    let b = aj + PI / 2.0;
    let h = |u: f64| {
        // cos(A)cos(B) = [cos(A - B) + cos(A + B)]/2, A = wi t + ai, B = wj (t - u) + b
        0.5 * wj
            * (int_cos(wi - wj, ai + wj * u - b, u, t_end)
                + int_cos(wi + wj, ai - wj * u + b, u, t_end))
    };
    let gl = gauss_legendre(12);
    let width = (0.25 / (wi + wj + 1.0)).min(0.25);
    let mut total = 0.0;
    // first panel [0, width] in v = u^{1-p}: u^{-p} du = dv / (1 - p)
    let vmax = width.powf(1.0 - p);
    for &(x, w) in &gl {
        let v = 0.5 * vmax * (x + 1.0);
        total += 0.5 * vmax * w * h(v.powf(1.0 / (1.0 - p))) / (1.0 - p);
    }
    let panels = ((t_end - width) / width).ceil() as usize;
    let step = (t_end - width) / panels as f64;
    for k in 0..panels {
        let a = width + k as f64 * step;
        for &(x, w) in &gl {
            let u = a + 0.5 * step * (x + 1.0);
            total += 0.5 * step * w * u.powf(-p) * h(u);
        }
    }
    let weight = if i == 0 { 1.0 } else { 2.0 };
    weight * total / (t_end * libm_gamma(1.0 - p))
}

/// Γ(x) for x in (0, 1] by the Lanczos approximation (g = 7), independent of the crate.
fn libm_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return PI / ((PI * x).sin() * libm_gamma(1.0 - x));
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (k, g) in G.iter().enumerate().skip(1) {
        a += g / (x + k as f64);
    }
    (2.0 * PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * a
}

/// Column j of the spectral D^q matrix.
fn spectral_column(j: usize, n: usize, q: f64, omega: f64) -> Vec<f64> {
    let mut e = vec![0.0; coeff_len(n)];
    e[j] = 1.0;
    let mut out = vec![0.0; coeff_len(n)];
    apply_order(&e, q, omega, &mut out);
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// (i) The spectral D^p matrix is the T → ∞ limit of the Caputo Galerkin average.
    /// At finite T the Caputo derivative from 0 differs from the steady state by its
    /// initial-condition tail, -φ(0) t^{-p}/Γ(1-p) + O(t^{-p-1}): averaged against an
    /// oscillating test function (rows i >= 1) that costs O(1/T); in the mean row
    /// (i = 0) it does not oscillate and contributes -φ(0) T^{-p}/Γ(2-p), which decays
    /// only like T^{-p}. The tolerance is that tail plus C/T, C = 0.25 (measured
    /// C <= 0.13 over p in [0.05, 0.9]).
    #[test]
    fn spectral_matrix_is_the_long_time_caputo_average(
        p in 0.05f64..0.95, omega in 0.5f64..3.0, i in 0usize..5, j in 1usize..5,
    ) {
        let n = 2;
        let exact = spectral_column(j, n, p, omega)[i];
        let scale = (2.0 * omega).powf(p);
        let phi0 = basis(j, n).1.cos();
        let mut errors = Vec::new();
        for periods in [8usize, 64] {
            let t = 2.0 * PI * periods as f64 / omega;
            let tail = if i == 0 { -phi0 * t.powf(-p) / libm_gamma(2.0 - p) } else { 0.0 };
            let v = caputo_average(i, j, n, p, omega, periods);
            let off = (v - exact - tail).abs() / scale;
            prop_assert!(off <= 0.25 / periods as f64, "{periods} periods: {off:.2e} beyond the tail");
            errors.push((v - exact).abs() / scale);
        }
        // and the plain error shrinks as T grows
        prop_assert!(errors[1] < errors[0], "errors {errors:?}");
    }

    /// (ii) D^a D^b = D^(a+b) on trigonometric polynomials.
    #[test]
    fn fractional_orders_compose(
        a in 0.0f64..1.0, b in 0.0f64..1.0, omega in 0.1f64..50.0,
        c in prop::collection::vec(-1.0f64..1.0, 11),
    ) {
        let (mut ab, mut tmp, mut direct) = (vec![0.0; 11], vec![0.0; 11], vec![0.0; 11]);
        apply_order(&c, b, omega, &mut tmp);
        apply_order(&tmp, a, omega, &mut ab);
        apply_order(&c, a + b, omega, &mut direct);
        let scale = (5.0 * omega).powf(a + b).max(1.0);
        for (x, y) in ab.iter().zip(&direct) {
            prop_assert!((x - y).abs() <= 1e-12 * scale, "{x} vs {y}");
        }
    }

    /// (iii) p = 1 is the derivative, p = 0 the identity on harmonics k >= 1.
    #[test]
    fn integer_limits(omega in 0.1f64..50.0, c in prop::collection::vec(-1.0f64..1.0, 11)) {
        let n = 5;
        let (mut d1, mut d0) = (vec![0.0; 11], vec![0.0; 11]);
        apply_order(&c, 1.0, omega, &mut d1);
        apply_order(&c, 0.0, omega, &mut d0);
        prop_assert_eq!(d1[0], 0.0);
        for k in 1..=n {
            let w = k as f64 * omega;
            // d/dt (a cos + b sin) = w b cos - w a sin
            prop_assert!((d1[k] - w * c[n + k]).abs() < 1e-12 * w);
            prop_assert!((d1[n + k] + w * c[k]).abs() < 1e-12 * w);
            prop_assert_eq!(d0[k], c[k]);
            prop_assert_eq!(d0[n + k], c[n + k]);
        }
        // and fractional orders approach them continuously
        let mut near = vec![0.0; 11];
        apply_order(&c, 1.0 - 1e-9, omega, &mut near);
        for (x, y) in near.iter().zip(&d1) {
            prop_assert!((x - y).abs() < 1e-6 * (1.0 + y.abs()) * (5.0 * omega).max(1.0));
        }
    }

    /// (iv) Mean power of a fractional damper: mean of D^p x · x' over a period equals
    /// Σ_k (kΩ)^(p+1) sin(pπ/2) |X_k|²/2 and is never negative.
    #[test]
    fn fractional_damper_power(
        p in 0.0f64..1.0, omega in 0.1f64..20.0, c in prop::collection::vec(-1.0f64..1.0, 11),
    ) {
        let n = 5;
        let m = sample_count(2, n, 1);
        let mut f = Fourier::new(n, m).unwrap();
        let (mut dp, mut d1) = (vec![0.0; 11], vec![0.0; 11]);
        apply_order(&c, p, omega, &mut dp);
        apply_order(&c, 1.0, omega, &mut d1);
        let (mut sp, mut s1) = (vec![0.0; m], vec![0.0; m]);
        f.synthesize(&dp, &mut sp);
        f.synthesize(&d1, &mut s1);
        let mean: f64 = sp.iter().zip(&s1).map(|(a, b)| a * b).sum::<f64>() / m as f64;
        let formula: f64 = (1..=n)
            .map(|k| {
                let w = k as f64 * omega;
                w.powf(p + 1.0) * (p * PI / 2.0).sin() * (c[k] * c[k] + c[n + k] * c[n + k]) / 2.0
            })
            .sum();
        let scale = (5.0 * omega).powf(p + 1.0) * 5.0;
        prop_assert!((mean - formula).abs() <= 1e-12 * scale, "{mean} vs {formula}");
        prop_assert!(formula >= 0.0 && mean >= -1e-12 * scale);
    }

    /// (v) The dual-number Jacobian (and ∂R/∂Ω, ∂R/∂θ) equals central finite differences.
    #[test]
    fn jacobian_matches_finite_differences(
        omega in 1.0f64..60.0, p in 0.05f64..1.95, k3 in 0.0f64..1e7,
        c in prop::collection::vec(-0.02f64..0.02, 22),
    ) {
        let car = QuarterCar { p, k3, ..QuarterCar::default() };
        let mut hb = Balance::new(&car, 5).unwrap();
        let len = hb.len();
        let mut r = vec![0.0; len];
        let mut jac = faer::Mat::<f64>::zeros(len, len);
        hb.jacobian(&c, omega, &mut r, jac.as_mut());
        let (mut rp, mut rm) = (vec![0.0; len], vec![0.0; len]);
        let rscale = r.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for col in 0..len {
            let h = 1e-6;
            let mut a = c.clone();
            a[col] += h;
            hb.residual(&a, omega, &mut rp);
            a[col] -= 2.0 * h;
            hb.residual(&a, omega, &mut rm);
            for row in 0..len {
                let fd = (rp[row] - rm[row]) / (2.0 * h);
                let tol = 1e-6 * (1.0 + fd.abs()) + 1e-9 * rscale / h;
                prop_assert!((jac[(row, col)] - fd).abs() < tol, "J[{row},{col}] = {} vs {fd}", jac[(row, col)]);
            }
        }
        // ∂R/∂Ω
        let mut dw = vec![0.0; len];
        hb.d_omega(&c, omega, &mut dw);
        let h = 1e-6 * omega;
        hb.residual(&c, omega + h, &mut rp);
        hb.residual(&c, omega - h, &mut rm);
        for row in 0..len {
            let fd = (rp[row] - rm[row]) / (2.0 * h);
            prop_assert!((dw[row] - fd).abs() < 1e-6 * (1.0 + fd.abs()) + 1e-9 * rscale / h);
        }
        // ∂R/∂θ for every parameter, the fractional order p included
        for (i, info) in car.params_info().iter().enumerate() {
            let mut dp = vec![0.0; len];
            hb.d_param(&c, omega, i, &mut dp);
            let v = car.param_value(i);
            let h = 1e-6 * v.abs().max(1e-3);
            hb.set_param(i, v + h);
            hb.residual(&c, omega, &mut rp);
            hb.set_param(i, v - h);
            hb.residual(&c, omega, &mut rm);
            hb.set_param(i, v);
            for row in 0..len {
                let fd = (rp[row] - rm[row]) / (2.0 * h);
                prop_assert!(
                    (dp[row] - fd).abs() < 1e-5 * (1.0 + fd.abs()) + 1e-9 * rscale / h,
                    "dR/d{} row {row}: {} vs {fd}", info.name, dp[row]
                );
            }
        }
    }
}

/// The Jacobian of a single-DOF fractional model too (one signal of order Param).
#[test]
fn fractional_duffing_jacobian_matches_finite_differences() {
    let model = FractionalDuffing { p: 0.7, ..FractionalDuffing::default() };
    let mut hb = Balance::new(&model, 4).unwrap();
    let len = hb.len();
    let a: Vec<f64> = (0..len).map(|i| 0.3 * ((i as f64) * 1.3).sin()).collect();
    let mut r = vec![0.0; len];
    let mut jac = faer::Mat::<f64>::zeros(len, len);
    hb.jacobian(&a, 1.7, &mut r, jac.as_mut());
    let (mut rp, mut rm) = (vec![0.0; len], vec![0.0; len]);
    for col in 0..len {
        let mut b = a.clone();
        b[col] += 1e-6;
        hb.residual(&b, 1.7, &mut rp);
        b[col] -= 2e-6;
        hb.residual(&b, 1.7, &mut rm);
        for row in 0..len {
            let fd = (rp[row] - rm[row]) / 2e-6;
            assert!((jac[(row, col)] - fd).abs() < 1e-7 * (1.0 + fd.abs()));
        }
    }
}

/// A non-finite coefficient is never summarised as a finite maximum (a diverged
/// iterate once reported `max_abs` 0 beside `null` means).
#[test]
fn max_abs_of_non_finite_coefficients_is_not_finite() {
    assert!(max_abs(&[0.0, f64::NAN, 1.0]).is_nan());
    assert_eq!(max_abs(&[0.0, f64::INFINITY, 1.0, 0.0, 0.0]), f64::INFINITY);
    assert!(max_abs(&[f64::NEG_INFINITY, 0.0, f64::NAN]).is_nan());
}

/// max_abs on signals whose maximum is known in closed form.
#[test]
fn max_abs_closed_forms() {
    // a cos θ + b sin θ: sqrt(a² + b²)
    for (a, b) in [(3.0, 4.0), (-1.0, 1e-3), (0.0, -2.5), (1e-7, 2e-7)] {
        let m = max_abs(&[0.0, a, b]);
        assert!((m - f64::hypot(a, b)).abs() <= 1e-12 * f64::hypot(a, b), "{m}");
    }
    // c0 + A cos(3θ + φ): |c0| + A
    let (a3, b3): (f64, f64) = (0.6 * 0.3f64.cos(), -0.6 * 0.3f64.sin());
    let m = max_abs(&[0.25, 0.0, 0.0, a3, 0.0, 0.0, b3]);
    assert!((m - 0.85).abs() < 1e-12, "{m}");
    // cos θ + cos 2θ / 4: on [0, π], x' = -sin θ (1 + cos θ) vanishes only at 0 and π;
    // the maximum 1.25 is at θ = 0, the minimum -0.75 at θ = π.
    let m = max_abs(&[0.0, 1.0, 0.25, 0.0, 0.0]);
    assert!((m - 1.25).abs() < 1e-12, "{m}");
    // cos θ - cos 2θ / 2 + 0.1: x' = 0 at cos θ = 1/2, x = 1/2 - (-1/2)/2 + 0.1 = 0.85; at
    // θ = π, x = -1 - 1/2 + 0.1 = -1.4: the max of |x| is 1.4 (an off-grid maximum would
    // also be caught: the grid has no point at θ = π/3)
    let m = max_abs(&[0.1, 1.0, -0.5, 0.0, 0.0]);
    assert!((m - 1.4).abs() < 1e-12, "{m}");
    // an interior maximum not on the grid: cos(θ - 0.123456) with higher harmonics
    // shifted alike keeps its max 1 + 0.3 at θ = 0.123456
    let s = 0.123456f64;
    let c = [0.0, s.cos(), 0.3 * (2.0 * s).cos(), s.sin(), 0.3 * (2.0 * s).sin()];
    let m = max_abs(&c);
    assert!((m - 1.3).abs() < 1e-12, "{m}");
}

proptest! {
    /// max_abs against brute force: 20 000 samples bound the true maximum from below,
    /// and from above within B h²/8 (B = Σ k²|c_k| bounds |x''|).
    #[test]
    fn max_abs_matches_dense_sampling(n in 1usize..9, seed in prop::collection::vec(-1.0f64..1.0, 17)) {
        let c: Vec<f64> = seed[..2 * n + 1].to_vec();
        let dense_n = 20_000;
        let h = 2.0 * PI / dense_n as f64;
        let dense = (0..dense_n)
            .map(|j| {
                let t = j as f64 * h;
                let mut x = c[0];
                for k in 1..=n {
                    x += c[k] * (k as f64 * t).cos() + c[n + k] * (k as f64 * t).sin();
                }
                x.abs()
            })
            .fold(0.0f64, f64::max);
        let b: f64 = (1..=n).map(|k| (k * k) as f64 * (c[k].abs() + c[n + k].abs())).sum();
        let m = max_abs(&c);
        prop_assert!(m >= dense - 1e-12, "{m} below sampled {dense}");
        prop_assert!(m <= dense + b * h * h / 8.0 + 1e-12, "{m} above the bound of {dense}");
    }
}

/// The least and largest x(θ), and the RMS, where they are known in closed form.
#[test]
fn range_and_rms_closed_forms() {
    // cos θ - cos 2θ / 2 + 0.1: largest 0.85 at cos θ = 1/2 (off the grid), least -1.4
    // at θ = π; RMS sqrt(0.1² + (1 + 1/4) / 2) by Parseval.
    let c = [0.1, 1.0, -0.5, 0.0, 0.0];
    let (lo, hi) = MaxAbs::new(2).range(&c);
    assert!((lo + 1.4).abs() < 1e-12 && (hi - 0.85).abs() < 1e-12, "{lo} {hi}");
    assert!((rms(&c) - (0.01f64 + 0.625).sqrt()).abs() < 1e-15);
    // A constant is its own extremes and RMS (of its magnitude).
    assert_eq!(MaxAbs::new(0).range(&[-2.0]), (-2.0, -2.0));
    assert_eq!(rms(&[-2.0]), 2.0);
    // Wholly negative: 1 below a mean of -3 is -4 at the least, -2 at the largest.
    let (lo, hi) = MaxAbs::new(1).range(&[-3.0, 0.6, 0.8]);
    assert!((lo + 4.0).abs() < 1e-12 && (hi + 2.0).abs() < 1e-12, "{lo} {hi}");
    // Non-finite coefficients are never summarised as finite bounds.
    let (lo, hi) = MaxAbs::new(1).range(&[0.0, f64::NAN, 1.0]);
    assert!(lo.is_nan() && hi.is_nan());
}

proptest! {
    /// The range against brute force as `max_abs_matches_dense_sampling` (the least
    /// and largest values bound the samples', within B h²/8), `max_abs` is the larger
    /// of their magnitudes, and the RMS is the samples' (the trapezoidal rule is exact
    /// for a trigonometric polynomial of degree below the sample count).
    #[test]
    fn range_and_rms_match_dense_sampling(n in 1usize..9, seed in prop::collection::vec(-1.0f64..1.0, 17)) {
        let c: Vec<f64> = seed[..2 * n + 1].to_vec();
        let dense_n = 20_000;
        let h = 2.0 * PI / dense_n as f64;
        let x: Vec<f64> = (0..dense_n)
            .map(|j| {
                let t = j as f64 * h;
                let mut x = c[0];
                for k in 1..=n {
                    x += c[k] * (k as f64 * t).cos() + c[n + k] * (k as f64 * t).sin();
                }
                x
            })
            .collect();
        let (dlo, dhi) = x.iter().fold((f64::MAX, f64::MIN), |(l, u), &v| (l.min(v), u.max(v)));
        let b: f64 = (1..=n).map(|k| (k * k) as f64 * (c[k].abs() + c[n + k].abs())).sum();
        let slack = b * h * h / 8.0 + 1e-12;
        let (lo, hi) = MaxAbs::new(n).range(&c);
        prop_assert!(hi >= dhi - 1e-12 && hi <= dhi + slack, "{hi} vs sampled {dhi}");
        prop_assert!(lo <= dlo + 1e-12 && lo >= dlo - slack, "{lo} vs sampled {dlo}");
        prop_assert!((max_abs(&c) - hi.max(-lo)).abs() <= 1e-15 * hi.abs().max(lo.abs()));
        let dense_rms = (x.iter().map(|v| v * v).sum::<f64>() / dense_n as f64).sqrt();
        prop_assert!((rms(&c) - dense_rms).abs() <= 1e-12 * dense_rms.max(1e-300));
    }
}
