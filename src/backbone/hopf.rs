//! The Hopf point of an equilibrium: where a pair of eigenvalues of its linearisation
//! crosses the imaginary axis as a parameter moves.
//!
//! The eigenvalues of the linearised model at rest are the roots of
//! `det Z(λ) = 0` ([`Linearisation::z`]), fractional factors `λ^p` included (the
//! principal branch, cut along the negative real axis: an oscillatory pair is far
//! from it). The pair of mode K is found by Newton's method on the determinant from
//! `λ ≈ -ξ/2 + iω` of the linear mode ([`linear_mode`]: `ξ` is the damping the
//! mode needs to be periodic, so the equilibrium's own is `-ξ`), followed from value
//! to value of the parameter, and the value where `Re λ` changes sign is located by
//! the Illinois variant of regula falsi to 1e-12 relative (1e-12 absolute near 0).

use super::{linear_mode, Hopf, Linearisation};
use crate::model::{DynModel, WithParams};
use num_complex::Complex64;

/// The Hopf point of mode `mode` (1-based) of `model` between consecutive `values`
/// of parameter `index` (in the order given: the pair is followed along them), or
/// `None` when `Re λ` keeps its sign (or the pair is lost).
pub(crate) fn locate(
    model: &dyn DynModel,
    index: usize,
    mode: usize,
    values: &[f64],
) -> Option<Hopf> {
    let mut guess: Option<Complex64> = None;
    let mut prev: Option<(f64, Complex64)> = None;
    for &v in values {
        let lam = eigenvalue(model, index, mode, v, guess)?;
        if let Some((pv, pl)) = prev {
            if pl.re == 0.0 {
                return Some(Hopf { value: pv, omega: pl.im });
            }
            if pl.re * lam.re <= 0.0 {
                return bisect(model, index, mode, (pv, pl), (v, lam));
            }
        }
        prev = Some((v, lam));
        guess = Some(lam);
    }
    None
}

/// `Re λ(P) = 0` between `a` and `b` (values with their eigenvalues, of opposite
/// signs), by the Illinois method.
fn bisect(
    model: &dyn DynModel,
    index: usize,
    mode: usize,
    a: (f64, Complex64),
    b: (f64, Complex64),
) -> Option<Hopf> {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (a.1.re, b.1.re);
    for _ in 0..200 {
        let x = if fb != fa { b.0 - fb * (b.0 - a.0) / (fb - fa) } else { 0.5 * (a.0 + b.0) };
        let near = if (x - a.0).abs() < (x - b.0).abs() { a.1 } else { b.1 };
        let lam = eigenvalue(model, index, mode, x, Some(near))?;
        let fx = lam.re;
        if fx == 0.0 || (b.0 - a.0).abs() <= 1e-12 * x.abs().max(1.0) {
            return Some(Hopf { value: x, omega: lam.im });
        }
        if fx * fb < 0.0 {
            a = b;
            fa = fb;
        } else {
            // the end kept again: halve its weight (Illinois)
            fa *= 0.5;
        }
        b = (x, lam);
        fb = fx;
        if (b.0 - a.0).abs() <= 1e-12 * x.abs().max(1.0) {
            return Some(Hopf { value: x, omega: lam.im });
        }
    }
    None
}

/// The eigenvalue of mode `mode` at parameter value `v`, by Newton on `det Z(λ)`
/// from `guess` (or the linear mode's estimate).
fn eigenvalue(
    model: &dyn DynModel,
    index: usize,
    mode: usize,
    v: f64,
    guess: Option<Complex64>,
) -> Option<Complex64> {
    let m = WithParams::with(model, index, v);
    let mut lam = match guess {
        Some(g) => g,
        None => {
            let lm = linear_mode(&m, mode).ok()?;
            Complex64::new(-0.5 * lm.xi, lm.omega)
        }
    };
    let lin = Linearisation::at_rest(&m, lam.im.abs().max(1e-300));
    let f = |l: Complex64| det(lin.z(l), lin.ndof);
    for _ in 0..60 {
        let d = 1e-7 * lam.norm().max(1e-300);
        let (fp, fm) = (f(lam + d), f(lam - d));
        let df = (fp - fm) / (2.0 * d);
        let step = f(lam) / df;
        if !(step.re.is_finite() && step.im.is_finite()) {
            return None;
        }
        lam -= step;
        if step.norm() <= 1e-15 * lam.norm() {
            return Some(lam);
        }
    }
    // converged to rounding, or not at all
    let r = f(lam).norm();
    (r.is_finite() && lam.im > 0.0).then_some(lam)
}

/// The determinant of a row-major `n × n` complex matrix (elimination with partial
/// pivoting).
fn det(mut a: Vec<Complex64>, n: usize) -> Complex64 {
    let mut d = Complex64::new(1.0, 0.0);
    for c in 0..n {
        let Some(p) = (c..n).max_by(|&i, &j| a[i * n + c].norm().total_cmp(&a[j * n + c].norm()))
        else {
            return Complex64::new(0.0, 0.0);
        };
        if a[p * n + c].norm() == 0.0 {
            return Complex64::new(0.0, 0.0);
        }
        if p != c {
            for j in 0..n {
                a.swap(p * n + j, c * n + j);
            }
            d = -d;
        }
        let piv = a[c * n + c];
        d *= piv;
        for i in c + 1..n {
            let f = a[i * n + c] / piv;
            for j in c..n {
                let v = a[c * n + j];
                a[i * n + j] -= f * v;
            }
        }
    }
    d
}
