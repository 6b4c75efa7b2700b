//! Convolution-quadrature weights: the power-series coefficients of `δ(ζ)^q`.
//!
//! A convolution quadrature (Lubich) approximates `D^q e(t_n)` by
//! `dt^-q Σ_{j=0}^{n} w_j e_{n-j}`, where `w_j` are the Taylor coefficients of
//! `δ(ζ)^q` and `δ` is the generating polynomial of a linear multistep method:
//!
//! - Grünwald–Letnikov (backward Euler), `δ(ζ) = 1 - ζ`: first order — the paper's
//!   "power series expansion method";
//! - BDF2, `δ(ζ) = (3 - 4ζ + ζ²)/2`: second order.
//!
//! Both are computed by J. C. P. Miller's recurrence for powers of a polynomial,
//! `b_n = 1/(n a_0) Σ_{k≥1} ((q + 1) k - n) a_k b_{n-k}`, which is forward-stable here:
//! the wanted solution decays like `n^(-q-1)` while the parasitic one (from the root
//! ζ = 3 of the BDF2 polynomial) decays like `3^-n`.

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// The convolution-quadrature rule for fractional derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Scheme {
    /// Grünwald–Letnikov weights, coefficients of `(1 - ζ)^q`: first order (the paper's).
    Gl,
    /// Lubich's BDF2 weights, coefficients of `((3 - 4ζ + ζ²)/2)^q`: second order.
    #[default]
    Bdf2,
}

impl Scheme {
    /// The name used on the command line and in JSON: `"gl"` or `"bdf2"`.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Gl => "gl",
            Scheme::Bdf2 => "bdf2",
        }
    }

    /// The coefficients `a_0, a_1, ...` of the generating polynomial `δ(ζ)`.
    fn polynomial(self) -> &'static [f64] {
        match self {
            Scheme::Gl => &[1.0, -1.0],
            Scheme::Bdf2 => &[1.5, -2.0, 0.5],
        }
    }

    /// The first `len` weights of `D^q` for this rule (`w_0 .. w_{len-1}`).
    ///
    /// ```
    /// use ihbm::timedomain::Scheme;
    /// // (1 - ζ)^1 = 1 - ζ: the backward difference.
    /// assert_eq!(Scheme::Gl.weights(1.0, 3), vec![1.0, -1.0, 0.0]);
    /// // BDF2 with q = 1: (3 e_n - 4 e_{n-1} + e_{n-2}) / 2.
    /// let w = Scheme::Bdf2.weights(1.0, 4);
    /// assert!((w[0] - 1.5).abs() < 1e-15 && (w[1] + 2.0).abs() < 1e-15);
    /// assert!((w[2] - 0.5).abs() < 1e-15 && w[3].abs() < 1e-15);
    /// ```
    pub fn weights(self, q: f64, len: usize) -> Vec<f64> {
        power_series(self.polynomial(), q, len)
    }

    /// The rule's symbol `δ(ζ)^q`, the sum of `w_j ζ^j` for `|ζ| ≤ 1`: what the
    /// quadrature makes of `D^q` applied to `e^{iωt}` sampled over an infinite past,
    /// `dt^-q δ(e^{-iωdt})^q e^{iωt}` (the continuous `(iω)^q` as `dt → 0`). The
    /// principal power is the series' sum: on the closed unit disk `arg δ` stays within
    /// `±π/2` (GL) and `±(π/2 + asin(1/3))` (BDF2, `δ = (1 - ζ)(3 - ζ)/2`), never `π`.
    ///
    /// ```
    /// use ihbm::timedomain::Scheme;
    /// use num_complex::Complex64;
    /// // q = 1 at ζ = e^{-iθ}: GL is the backward difference 1 - e^{-iθ}.
    /// let z = Complex64::new(0.0, -0.3).exp();
    /// assert!((Scheme::Gl.symbol(z, 1.0) - (1.0 - z)).norm() < 1e-15);
    /// ```
    pub fn symbol(self, zeta: Complex64, q: f64) -> Complex64 {
        let delta: Complex64 =
            self.polynomial().iter().rev().fold(Complex64::new(0.0, 0.0), |acc, &a| acc * zeta + a);
        if delta == Complex64::new(0.0, 0.0) {
            return Complex64::new(if q == 0.0 { 1.0 } else { 0.0 }, 0.0);
        }
        delta.powf(q)
    }
}

impl std::fmt::Display for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Scheme {
    type Err = crate::Error;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "gl" => Ok(Scheme::Gl),
            "bdf2" => Ok(Scheme::Bdf2),
            _ => Err(crate::Error::InvalidValue {
                what: "scheme".into(),
                value: s.to_string(),
                expected: "gl or bdf2".into(),
            }),
        }
    }
}

/// Taylor coefficients of `P(ζ)^q` (`P(0) = a[0] > 0`), by Miller's recurrence.
fn power_series(a: &[f64], q: f64, len: usize) -> Vec<f64> {
    let mut b = Vec::with_capacity(len);
    if len == 0 {
        return b;
    }
    b.push(a[0].powf(q));
    for n in 1..len {
        let mut s = 0.0;
        for (k, &ak) in a.iter().enumerate().skip(1).take(n) {
            s += ((q + 1.0) * k as f64 - n as f64) * ak * b[n - k];
        }
        b.push(s / (n as f64 * a[0]));
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    /// BDF2 weights equal the Cauchy product of (3/2)^q (1-ζ)^q and (1-ζ/3)^q, an
    /// independent factorisation of the same generating function.
    #[test]
    fn bdf2_is_product_of_factors() {
        for &q in &[0.3, 0.5, 1.0, 1.5, 1.9] {
            let n = 200;
            let gl = Scheme::Gl.weights(q, n);
            let third = power_series(&[1.0, -1.0 / 3.0], q, n);
            let w = Scheme::Bdf2.weights(q, n);
            for i in 0..n {
                let prod: f64 = (0..=i).map(|j| gl[j] * third[i - j]).sum::<f64>() * 1.5f64.powf(q);
                assert!((prod - w[i]).abs() <= 1e-13 * (1.0 + w[i].abs()), "q {q} i {i}");
            }
        }
    }

    /// The symbol is the weights' generating function: on the unit circle their
    /// partial sums `Σ_{j≤J} w_j e^{-ijθ}` approach `δ(e^{-iθ})^q` (the remainder of
    /// the oscillating tail is of order `J^{-1-q}`), inside it they converge fast.
    #[test]
    fn symbol_is_the_sum_of_the_weights() {
        for scheme in [Scheme::Gl, Scheme::Bdf2] {
            for &q in &[0.3, 0.5, 1.5] {
                let w = scheme.weights(q, 200_001);
                for (zeta, tol) in [
                    (Complex64::new(0.0, -0.7).exp(), 1e-6),
                    (Complex64::new(0.0, -2.9).exp(), 1e-6),
                    (Complex64::new(0.5, 0.4), 1e-12),
                ] {
                    let mut z = Complex64::new(1.0, 0.0);
                    let mut sum = Complex64::new(0.0, 0.0);
                    for wj in &w {
                        sum += wj * z;
                        z *= zeta;
                    }
                    let symbol = scheme.symbol(zeta, q);
                    assert!(
                        (sum - symbol).norm() < tol,
                        "{scheme} q {q} ζ {zeta}: {sum} vs {symbol}"
                    );
                }
            }
        }
    }

    /// GL weights are the generalized binomial coefficients (-1)^j C(q, j).
    #[test]
    fn gl_matches_binomial() {
        let q = 0.7;
        let w = Scheme::Gl.weights(q, 6);
        let mut c = 1.0;
        for (j, wj) in w.iter().enumerate() {
            assert!((wj - c).abs() < 1e-15);
            c *= -(q - j as f64) / (j as f64 + 1.0);
        }
    }
}
