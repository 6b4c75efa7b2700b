//! Helpers shared by the `dsl_*` tests: harmonic-balance residual/Jacobian in plain
//! vectors, central finite differences, and a small random-number source.
#![allow(dead_code)]

use ihbm::balance::Balance;
use ihbm::Model;

/// Residual and dense Jacobian (row-major) of the harmonic balance equations.
pub fn residual_jacobian<M: Model>(
    model: &M,
    harmonics: usize,
    a: &[f64],
    omega: f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut hb = Balance::new(model, harmonics).unwrap();
    let n = hb.len();
    let mut r = vec![0.0; n];
    let mut jac = faer::Mat::<f64>::zeros(n, n);
    hb.jacobian(a, omega, &mut r, jac.as_mut());
    let mut j = vec![0.0; n * n];
    for row in 0..n {
        for col in 0..n {
            j[row * n + col] = jac[(row, col)];
        }
    }
    (r, j)
}

/// The harmonic balance residual alone.
pub fn residual<M: Model>(model: &M, harmonics: usize, a: &[f64], omega: f64) -> Vec<f64> {
    let mut hb = Balance::new(model, harmonics).unwrap();
    let mut r = vec![0.0; hb.len()];
    hb.residual(a, omega, &mut r);
    r
}

/// Central finite-difference Jacobian (row-major), step `h` per coefficient.
pub fn fd_jacobian<M: Model>(
    model: &M,
    harmonics: usize,
    a: &[f64],
    omega: f64,
    h: f64,
) -> Vec<f64> {
    let mut hb = Balance::new(model, harmonics).unwrap();
    let n = hb.len();
    let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
    let mut j = vec![0.0; n * n];
    let mut x = a.to_vec();
    for col in 0..n {
        x[col] = a[col] + h;
        hb.residual(&x, omega, &mut rp);
        x[col] = a[col] - h;
        hb.residual(&x, omega, &mut rm);
        x[col] = a[col];
        for row in 0..n {
            j[row * n + col] = (rp[row] - rm[row]) / (2.0 * h);
        }
    }
    j
}

/// max |x - y| / max(max |y|, floor).
pub fn rel_diff(x: &[f64], y: &[f64], floor: f64) -> f64 {
    assert_eq!(x.len(), y.len());
    let scale = y.iter().fold(floor, |m, v| m.max(v.abs()));
    x.iter().zip(y).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

/// Set every parameter to its default times a factor from `factors` (cycled), keeping
/// the parameters named in `keep` (e.g. fractional orders set by the caller).
pub fn scale_params<M: Model>(model: &mut M, factors: &[f64], keep: &[&str]) {
    let info = model.params_info().to_vec();
    for (i, p) in info.iter().enumerate() {
        if keep.contains(&&*p.name) {
            continue;
        }
        let f = factors[i % factors.len()];
        model.set_param_value(i, p.default * f);
    }
}
