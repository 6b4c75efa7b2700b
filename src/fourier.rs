//! Fourier coefficients, time samples and the spectral derivative operators.
//!
//! Layout per DOF: `[a0, a1..aN, b1..bN]` (length `2N + 1`), for
//! `x(θ) = a0 + Σ_k a_k cos kθ + b_k sin kθ` with `θ = Ωt`. In complex form
//! `x = Re Σ X_k e^{ikθ}` with `X_0 = a0`, `X_k = a_k - i b_k`.
//!
//! The derivative of order `q` (integer or fractional, steady-state Weyl sense)
//! multiplies `X_k` by `(ikΩ)^q = (kΩ)^q e^{iqπ/2}`; the constant part is kept only
//! for `q = 0`. This is the rule the reference paper's eq. (28)/(29) encode (its
//! eq. (27a) swaps `cos(pπ/2)` and `sin(pπ/2)`, and `0^p` is 1 only for p = 0).

use crate::error::{Error, Result};
use crate::model::{DynModel, Model};
use ihbm_fft::{ComplexToReal, Planner, RealToComplex};
use num_complex::Complex64;
use std::f64::consts::PI;
use std::sync::Arc;

/// Number of coefficients per DOF for `n` harmonics.
#[inline]
pub fn coeff_len(harmonics: usize) -> usize {
    2 * harmonics + 1
}

/// Smallest `2^a 3^b 5^c` at least `n` (sizes the FFT is fastest for).
pub fn fast_size(n: usize) -> usize {
    // No FFT of such a size is ever planned (`balance::check_size` refuses far
    // smaller problems); returning `n` keeps the search from running off the end.
    if n > 1 << 48 {
        return n;
    }
    let mut m = n.max(1);
    loop {
        let mut r = m;
        for f in [2, 3, 5] {
            while r % f == 0 {
                r /= f;
            }
        }
        if r == 1 {
            return m;
        }
        m += 1;
    }
}

/// The alias-free sample count: products of `degree` signals with `N` harmonics have
/// harmonics up to `degree·N`; with `M >= (degree + 1) N + 1` samples none of them
/// folds back onto harmonics `0..=N`, and the forcing (up to harmonic `max_forcing`)
/// is represented exactly. Rounded up to a fast FFT size.
///
/// ```
/// // the cubic quarter car with 5 harmonics: at least 21 samples -> 24
/// assert_eq!(ihbm::fourier::sample_count(3, 5, 1), 24);
/// ```
pub fn sample_count(degree: usize, harmonics: usize, max_forcing: usize) -> usize {
    samples(degree, harmonics, max_forcing, 0)
}

/// The alias-free sample count of `model`'s balance with `harmonics` harmonics of
/// `Ω / period`: [`sample_count`], and with parametric excitation
/// ([`Model::parametric_harmonic`] `= k`) products of degree `d` that have harmonics up
/// to `d·N + k` need `M >= (d + 1) N + k + 1`. The harmonic balance and Hill's method
/// both take it, so that they sample alike.
///
/// ```
/// # use ihbm::fourier::{model_sample_count, sample_count};
/// use ihbm::models::Duffing;
/// // no parametric term: the same as sample_count
/// assert_eq!(model_sample_count(&Duffing::default(), 5, 1), sample_count(3, 5, 1));
/// ```
pub fn model_sample_count(model: &dyn DynModel, harmonics: usize, period: usize) -> usize {
    match model.aft_samples() {
        Some(m) => m.saturating_mul(period.max(1)),
        None => derived_count(model, model.degree(), model.smooth(), harmonics, period),
    }
}

/// The count terms of `degree` in the signals of `model` need at `harmonics`
/// harmonics of `Ω / period`: alias-free where they are `smooth`, else
/// [`KINK_OVERSAMPLING`] times the coefficients (or the alias-free count if larger).
fn derived_count(
    model: &dyn DynModel,
    degree: usize,
    smooth: bool,
    harmonics: usize,
    period: usize,
) -> usize {
    let period = period.max(1);
    let alias_free = samples(
        degree,
        harmonics,
        model.max_forcing_harmonic().saturating_mul(period),
        model.parametric_harmonic().saturating_mul(period),
    );
    if smooth {
        alias_free
    } else {
        fast_size(alias_free.max(KINK_OVERSAMPLING.saturating_mul(coeff_len(harmonics))))
    }
}

/// The samples a non-smooth model's transform takes per coefficient of a DOF (`M >=
/// 16 (2N + 1)`, where the alias-free count asks no more). A kink (`max`, `min`,
/// `abs`) of a smooth signal has harmonics that fall like `k⁻²`, so what folds back
/// onto the kept harmonics falls like `M⁻²`; a jump (`sign`) like `M⁻¹`. The book
/// ("Non-smooth terms") measures both; `--aft-samples` sets another count.
pub const KINK_OVERSAMPLING: usize = 16;

/// Check a sample count a model asks for ([`Model::aft_samples`](crate::model::Model::aft_samples))
/// at `harmonics` harmonics of `Ω / period`: it must resolve every harmonic (`M >= 2N +
/// 1` per solution period), and for a smooth model it may not fall below the
/// alias-free count, which would make the projection alias without a word.
pub fn check_samples(model: &dyn DynModel, harmonics: usize, period: usize) -> Result<()> {
    let Some(m) = model.aft_samples() else { return Ok(()) };
    let period = period.max(1);
    let total = m.saturating_mul(period);
    let needed = coeff_len(harmonics);
    if total < needed {
        return Err(Error::InvalidValue {
            what: "samples per period of the transform".into(),
            value: m.to_string(),
            expected: format!(
                "at least 2N + 1 = {} per period{}",
                needed.div_ceil(period),
                if period > 1 {
                    format!(" ({needed} over the {period} periods)")
                } else {
                    String::new()
                }
            ),
        });
    }
    if model.smooth() {
        let alias_free = derived_count(model, model.degree(), true, harmonics, period);
        if total < alias_free {
            return Err(Error::InvalidValue {
                what: "samples per period of the transform".into(),
                value: m.to_string(),
                expected: format!(
                    "at least {} for model '{}' at N = {harmonics}: it is smooth, and fewer \
                     samples would alias its degree-{} terms onto the kept harmonics",
                    alias_free.div_ceil(period),
                    model.name(),
                    model.degree()
                ),
            });
        }
    }
    Ok(())
}

/// The sample count of `model`'s expression outputs
/// ([`Model::output_signals`](crate::model::Model::output_signals)) at `harmonics`
/// harmonics of `Ω / period`: [`model_sample_count`]'s rule with the outputs' degree
/// and smoothness ([`Model::output_degree`](crate::model::Model::output_degree),
/// [`Model::outputs_smooth`](crate::model::Model::outputs_smooth)) in place of the
/// residual's, and no fewer than [`Model::aft_samples`](crate::model::Model::aft_samples).
pub fn output_sample_count(model: &dyn DynModel, harmonics: usize, period: usize) -> usize {
    let own =
        derived_count(model, model.output_degree(), model.outputs_smooth(), harmonics, period);
    match model.aft_samples() {
        Some(m) => own.max(m.saturating_mul(period.max(1))),
        None => own,
    }
}

/// `M >= max((d + 1) N + k_p + 1, N + k_f + 1, 2N + 1)`, rounded up to a fast size.
fn samples(degree: usize, harmonics: usize, max_forcing: usize, parametric: usize) -> usize {
    // Saturating: an absurd N must not wrap around into a small sample count.
    let alias_free =
        (degree.max(1) + 1).saturating_mul(harmonics).saturating_add(parametric).saturating_add(1);
    let forced = harmonics.saturating_add(max_forcing).saturating_add(1);
    fast_size(alias_free.max(forced).max(harmonics.saturating_mul(2).saturating_add(1)))
}

/// `e^{iqπ/2}` with exact values for integer `q` (so that `D^1` and `D^2` carry no
/// rounding from `cos(π/2)`).
fn rotation(q: f64) -> Complex64 {
    if q.fract() == 0.0 {
        match (q.rem_euclid(4.0)) as u32 {
            0 => Complex64::new(1.0, 0.0),
            1 => Complex64::new(0.0, 1.0),
            2 => Complex64::new(-1.0, 0.0),
            _ => Complex64::new(0.0, -1.0),
        }
    } else {
        let a = q * PI / 2.0;
        Complex64::new(a.cos(), a.sin())
    }
}

/// The multiplier `(ikΩ)^q` of harmonic `k` under `D^q` (steady state). For `k = 0`
/// it is 1 when `q = 0` and 0 otherwise.
///
/// ```
/// use ihbm::fourier::spectral_factor;
/// let l = spectral_factor(2, 3.0, 1.0); // d/dt of e^{i 2 Ω t} with Ω = 3
/// assert_eq!((l.re, l.im), (0.0, 6.0));
/// assert_eq!(spectral_factor(0, 3.0, 0.5).norm(), 0.0);
/// ```
pub fn spectral_factor(k: usize, omega: f64, order: f64) -> Complex64 {
    if k == 0 {
        return Complex64::new(if order == 0.0 { 1.0 } else { 0.0 }, 0.0);
    }
    let w = k as f64 * omega;
    let mag = if order.fract() == 0.0 { w.powi(order as i32) } else { w.powf(order) };
    rotation(order) * mag
}

/// `∂/∂q` of the multiplier `(ikΩ)^q`: `(ikΩ)^q ln(ikΩ)`, with `ln(ikΩ) = ln(kΩ) +
/// iπ/2`; 0 for `k = 0`. How a signal moves with its fractional order.
///
/// ```
/// use ihbm::fourier::{order_rate, spectral_factor};
/// let (k, w, q, h) = (3, 2.0, 0.5, 1e-6);
/// let fd = (spectral_factor(k, w, q + h) - spectral_factor(k, w, q - h)) / (2.0 * h);
/// assert!((order_rate(k, w, q) - fd).norm() < 1e-8);
/// ```
pub fn order_rate(k: usize, omega: f64, order: f64) -> Complex64 {
    if k == 0 {
        return Complex64::new(0.0, 0.0);
    }
    spectral_factor(k, omega, order)
        * Complex64::new((k as f64 * omega).ln(), std::f64::consts::FRAC_PI_2)
}

/// Multiply harmonic `k` of `coeffs` (one DOF) by `factor(k)`, writing into `out`.
/// `factor(0)` must be real (it is, for every operator used here).
pub fn apply_factor(coeffs: &[f64], out: &mut [f64], factor: impl Fn(usize) -> Complex64) {
    let n = (coeffs.len() - 1) / 2;
    out[0] = factor(0).re * coeffs[0];
    for k in 1..=n {
        let (a, b) = (coeffs[k], coeffs[n + k]);
        let l = factor(k);
        // (l_re + i l_im)(a - i b) = (l_re a + l_im b) - i (l_re b - l_im a)
        out[k] = l.re * a + l.im * b;
        out[n + k] = l.re * b - l.im * a;
    }
}

/// `D^q` (steady state) applied to one coefficient vector.
///
/// ```
/// use ihbm::fourier::apply_order;
/// // x = cos θ with Ω = 2: x' = -2 sin θ
/// let mut d = [0.0; 3];
/// apply_order(&[0.0, 1.0, 0.0], 1.0, 2.0, &mut d);
/// assert_eq!(d, [0.0, 0.0, -2.0]);
/// ```
pub fn apply_order(coeffs: &[f64], order: f64, omega: f64, out: &mut [f64]) {
    apply_factor(coeffs, out, |k| spectral_factor(k, omega, order));
}

/// `x(θ)` for one coefficient vector.
pub fn eval(coeffs: &[f64], theta: f64) -> f64 {
    eval_d2(coeffs, theta).0
}

/// `(x, x', x'')` with respect to θ. `cos kθ`, `sin kθ` come from the angle-addition
/// recurrence (one `sin_cos` per call); its rounding grows like `k·ε`, far below the
/// 1e-12 asked of [`max_abs`] for the harmonic counts used here.
fn eval_d2(coeffs: &[f64], theta: f64) -> (f64, f64, f64) {
    let n = (coeffs.len() - 1) / 2;
    let (s1, c1) = theta.sin_cos();
    let (mut s, mut c) = (0.0, 1.0);
    let (mut x, mut d1, mut d2) = (coeffs[0], 0.0, 0.0);
    for k in 1..=n {
        (s, c) = (s * c1 + c * s1, c * c1 - s * s1);
        let kf = k as f64;
        let (a, b) = (coeffs[k], coeffs[n + k]);
        x += a * c + b * s;
        d1 += kf * (b * c - a * s);
        d2 -= kf * kf * (a * c + b * s);
    }
    (x, d1, d2)
}

/// The largest `|x(θ)|` over one period, to about 1e-12 relative.
///
/// A grid of `8 (N + 1)` points puts a grid point within `π/(8N)` of every local
/// extremum (closer than a quarter of the shortest period, so Newton on `x'(θ) = 0`
/// started there converges to it). Only grid maxima that could still beat the best
/// grid value are polished: between grid points `|x|` exceeds its grid value by at
/// most `B h²/8` with `B = Σ k² |c_k| ≥ |x''|`. For many calls with one `N`, keep a
/// [`MaxAbs`] (its grid table is computed once).
///
/// ```
/// use ihbm::fourier::max_abs;
/// // 3 cos θ + 4 sin θ has amplitude 5
/// assert!((max_abs(&[0.0, 3.0, 4.0]) - 5.0).abs() < 1e-12);
/// ```
pub fn max_abs(coeffs: &[f64]) -> f64 {
    MaxAbs::new(coeffs.len().saturating_sub(1) / 2).eval(coeffs)
}

/// [`max_abs`] for one harmonic count, with `cos kθ_g`, `sin kθ_g` of the grid
/// tabulated: the grid values are then a small matrix-vector product instead of a
/// serial angle-addition recurrence per point (the continuation evaluates every output
/// of every point).
///
/// ```
/// use ihbm::fourier::{max_abs, MaxAbs};
/// let peaks = MaxAbs::new(2);
/// let x = [0.1, 1.0, 0.0, 0.0, 0.3]; // 0.1 + cos θ + 0.3 sin 2θ
/// assert_eq!(peaks.eval(&x), max_abs(&x));
/// // Another harmonic count still works: 0.5 + 3 cos θ + 4 sin θ peaks at 0.5 + 5.
/// assert!((peaks.eval(&[0.5, 3.0, 4.0]) - 5.5).abs() < 1e-12);
/// assert_eq!(max_abs(&[]), 0.0);
/// ```
#[derive(Debug, Clone)]
pub struct MaxAbs {
    n: usize,
    /// Column-major by coefficient: `table[(i - 1) * grid + g]` is basis function `i`
    /// (`cos kθ`, then `sin kθ`, as the coefficients are laid out) at grid point `g`, so
    /// that the grid values accumulate one contiguous (vectorisable) column at a time.
    table: Vec<f64>,
}

impl MaxAbs {
    /// The grid table for `harmonics` harmonics.
    pub fn new(harmonics: usize) -> MaxAbs {
        let n = harmonics;
        let grid = 8 * (n + 1);
        let h = 2.0 * PI / grid as f64;
        // cos kθ_g, sin kθ_g by the angle-addition recurrence (as `eval_d2`): one
        // `sin_cos` per grid point, so that a one-off `max_abs` stays cheap.
        let mut table = vec![0.0; grid * 2 * n];
        for g in 0..grid {
            let (s1, c1) = (g as f64 * h).sin_cos();
            let (mut s, mut c) = (0.0, 1.0);
            for k in 1..=n {
                (s, c) = (s * c1 + c * s1, c * c1 - s * s1);
                table[(k - 1) * grid + g] = c;
                table[(n + k - 1) * grid + g] = s;
            }
        }
        MaxAbs { n, table }
    }

    /// The largest `|x(θ)|` of `coeffs` (`2N + 1` of them, `N` as in [`MaxAbs::new`];
    /// another count is evaluated with a table of its own, a trailing odd coefficient
    /// ignored, none gives 0; a NaN coefficient gives NaN and an infinite one
    /// infinity, never a finite value that hides them).
    pub fn eval(&self, coeffs: &[f64]) -> f64 {
        if !coeffs.iter().all(|c| c.is_finite()) {
            return coeffs.iter().map(|c| c.abs()).sum();
        }
        let n = self.n;
        if coeffs.len() != 2 * n + 1 {
            let other = coeffs.len().saturating_sub(1) / 2;
            return match coeffs.len() {
                0 => 0.0,
                _ => MaxAbs::new(other).eval(&coeffs[..2 * other + 1]),
            };
        }
        if n == 0 {
            return coeffs[0].abs();
        }
        self.tabulated(coeffs, |vals| self.polished(coeffs, vals, f64::abs).0)
    }

    /// The least and the largest `x(θ)` of `coeffs` (counts as in [`MaxAbs::eval`],
    /// found the same way: the extremes of the truncated series, to rounding). A NaN
    /// coefficient gives NaN, an infinite one infinite bounds.
    ///
    /// ```
    /// use ihbm::fourier::MaxAbs;
    /// // 0.5 + 3 cos θ + 4 sin θ swings 5 about its mean
    /// let (lo, hi) = MaxAbs::new(1).range(&[0.5, 3.0, 4.0]);
    /// assert!((lo + 4.5).abs() < 1e-12 && (hi - 5.5).abs() < 1e-12);
    /// ```
    pub fn range(&self, coeffs: &[f64]) -> (f64, f64) {
        let e = self.extremes(coeffs);
        (e.min, e.max)
    }

    /// The least and largest `x(θ)` and the instants `θ` where they are reached, from
    /// one tabulation ([`MaxAbs::range`] with the places): `max_abs` is the larger of
    /// `max` and `-min`, and the derivative of an extreme with respect to the
    /// coefficients is the basis at its instant.
    pub fn extremes(&self, coeffs: &[f64]) -> Extremes {
        let flat = |v: f64| Extremes { min: v, max: v, at_min: 0.0, at_max: 0.0 };
        if !coeffs.iter().all(|c| c.is_finite()) {
            let s: f64 = coeffs.iter().map(|c| c.abs()).sum();
            return Extremes { min: -s, ..flat(s) };
        }
        let n = self.n;
        if coeffs.len() != 2 * n + 1 {
            let other = coeffs.len().saturating_sub(1) / 2;
            return match coeffs.len() {
                0 => flat(0.0),
                _ => MaxAbs::new(other).extremes(&coeffs[..2 * other + 1]),
            };
        }
        if n == 0 {
            return flat(coeffs[0]);
        }
        self.tabulated(coeffs, |vals| {
            let (max, at_max) = self.polished(coeffs, vals, |x| x);
            let (neg, at_min) = self.polished(coeffs, vals, |x| -x);
            Extremes { min: -neg, max, at_min, at_max }
        })
    }

    /// `f` of `x(θ_g)` at every grid point (`8(N + 1)` of them): on the stack up to
    /// N = 16 (zeroing a larger array costs more than the work).
    fn tabulated<R>(&self, coeffs: &[f64], f: impl FnOnce(&[f64]) -> R) -> R {
        let grid = 8 * (self.n + 1);
        let mut stack = [0.0f64; 8 * 17];
        let mut heap = Vec::new();
        let vals: &mut [f64] = if grid <= stack.len() {
            &mut stack[..grid]
        } else {
            heap.resize(grid, 0.0);
            &mut heap
        };
        let grid = vals.len();
        vals.fill(coeffs[0]);
        for (&c, col) in coeffs[1..].iter().zip(self.table.chunks_exact(grid)) {
            for (v, t) in vals.iter_mut().zip(col) {
                *v += c * t;
            }
        }
        f(vals)
    }

    /// The largest `f(x(θ))` (`f` is `|x|`, `x` or `-x`) and where: the grid's best,
    /// and every grid peak of `f` that could still beat it polished by Newton on `x'`.
    fn polished(&self, coeffs: &[f64], vals: &[f64], f: impl Fn(f64) -> f64) -> (f64, f64) {
        let n = self.n;
        let grid = vals.len();
        let h = 2.0 * PI / grid as f64;
        let (mut best, mut at) = (f64::NEG_INFINITY, 0.0);
        for (j, &v) in vals.iter().enumerate() {
            if f(v) > best {
                (best, at) = (f(v), j as f64 * h);
            }
        }
        let curvature: f64 =
            (1..=n).map(|k| (k * k) as f64 * (coeffs[k].abs() + coeffs[n + k].abs())).sum();
        let slack = curvature * h * h / 8.0;
        let grid_best = best;
        for j in 0..grid {
            let prev = vals[if j == 0 { grid - 1 } else { j - 1 }];
            let next = vals[if j + 1 == grid { 0 } else { j + 1 }];
            let here = vals[j];
            let is_peak = f(here) >= f(prev) && f(here) >= f(next) && here != 0.0;
            if !is_peak || f(here) + slack < grid_best {
                continue;
            }
            // Start at the vertex of the parabola through the three grid values.
            let curv = prev - 2.0 * here + next;
            let offset =
                if curv != 0.0 { (0.5 * (prev - next) / curv).clamp(-1.0, 1.0) } else { 0.0 };
            let mut theta = (j as f64 + offset) * h;
            for _ in 0..30 {
                let (_, d1, d2) = eval_d2(coeffs, theta);
                if d2 == 0.0 {
                    break;
                }
                let step = (d1 / d2).clamp(-h, h);
                theta -= step;
                // Quadratic convergence: θ is then good to ~1e-20, |x| to rounding.
                if step.abs() < 1e-10 {
                    break;
                }
            }
            let v = f(eval(coeffs, theta));
            if v > best {
                (best, at) = (v, theta);
            }
        }
        (best, at)
    }
}

/// The least and largest value of a truncated Fourier series over one period, and
/// where ([`MaxAbs::extremes`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extremes {
    /// The least `x(θ)`.
    pub min: f64,
    /// The largest `x(θ)`.
    pub max: f64,
    /// A `θ` where `min` is reached.
    pub at_min: f64,
    /// A `θ` where `max` is reached.
    pub at_max: f64,
}

impl Extremes {
    /// The largest `|x(θ)|`, and the sign of `x` and the `θ` where it is reached.
    pub fn max_abs(&self) -> (f64, f64, f64) {
        if self.max >= -self.min {
            (self.max, 1.0, self.at_max)
        } else {
            (-self.min, -1.0, self.at_min)
        }
    }
}

/// The root mean square of `x(θ)` over one period, its mean included, from the
/// coefficients `[a0, a1..aN, b1..bN]` by Parseval: `sqrt(a0² + Σ (ak² + bk²) / 2)`.
///
/// ```
/// // 3 cos θ + 4 sin θ: amplitude 5, RMS 5/√2
/// assert!((ihbm::fourier::rms(&[0.0, 3.0, 4.0]) - 5.0 / 2f64.sqrt()).abs() < 1e-15);
/// ```
pub fn rms(coeffs: &[f64]) -> f64 {
    let Some((a0, rest)) = coeffs.split_first() else { return 0.0 };
    (a0 * a0 + 0.5 * rest.iter().map(|c| c * c).sum::<f64>()).sqrt()
}

/// FFT plans and buffers for one harmonic count and sample count.
#[derive(Clone)]
pub struct Fourier {
    n: usize,
    m: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    spec: Vec<Complex64>,
    buf: Vec<f64>,
    scratch_fwd: Vec<Complex64>,
    scratch_inv: Vec<Complex64>,
}

impl std::fmt::Debug for Fourier {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Fourier {{ harmonics: {}, samples: {} }}", self.n, self.m)
    }
}

/// The number of harmonics N when none is given (CLI, studies, solver options).
pub const DEFAULT_HARMONICS: usize = 5;

/// Check a harmonic count (N >= 1): the one place every entry point asks.
pub fn check_harmonics(harmonics: usize) -> Result<()> {
    if harmonics == 0 {
        return Err(Error::InvalidValue {
            what: "number of harmonics".into(),
            value: "0".into(),
            expected: "at least 1".into(),
        });
    }
    Ok(())
}

impl Fourier {
    /// Plans for `harmonics` harmonics on `samples` samples per period
    /// (`samples > 2 · harmonics`, so every kept harmonic is resolved).
    pub fn new(harmonics: usize, samples: usize) -> Result<Self> {
        check_harmonics(harmonics)?;
        if samples <= 2 * harmonics {
            return Err(Error::InvalidValue {
                what: "number of time samples".into(),
                value: samples.to_string(),
                expected: format!("more than 2N = {}", 2 * harmonics),
            });
        }
        let mut planner = Planner::new();
        let r2c = planner.forward(samples);
        let c2r = planner.inverse(samples);
        let scratch_fwd = r2c.make_scratch_vec();
        let scratch_inv = c2r.make_scratch_vec();
        Ok(Fourier {
            n: harmonics,
            m: samples,
            r2c,
            c2r,
            spec: vec![Complex64::new(0.0, 0.0); samples / 2 + 1],
            buf: vec![0.0; samples],
            scratch_fwd,
            scratch_inv,
        })
    }

    /// Number of harmonics N.
    pub fn harmonics(&self) -> usize {
        self.n
    }

    /// Number of samples per period M.
    pub fn samples(&self) -> usize {
        self.m
    }

    /// The sample phases `θ_j = 2π j / M`.
    pub fn phases(&self) -> Vec<f64> {
        (0..self.m).map(|j| 2.0 * PI * j as f64 / self.m as f64).collect()
    }

    /// Coefficients (`2N + 1`) to `M` time samples.
    pub fn synthesize(&mut self, coeffs: &[f64], samples: &mut [f64]) {
        let n = self.n;
        self.spec.fill(Complex64::new(0.0, 0.0));
        self.spec[0] = Complex64::new(coeffs[0], 0.0);
        for k in 1..=n {
            self.spec[k] = Complex64::new(0.5 * coeffs[k], -0.5 * coeffs[n + k]);
        }
        let res = self.c2r.process_with_scratch(&mut self.spec, samples, &mut self.scratch_inv);
        debug_assert!(res.is_ok(), "buffer sizes are fixed at construction");
    }

    /// `M` time samples to the coefficients (`2N + 1`) of harmonics `0..=N`.
    pub fn analyze(&mut self, samples: &[f64], coeffs: &mut [f64]) {
        let (n, scale) = (self.n, 1.0 / self.m as f64);
        self.forward(samples);
        coeffs[0] = self.spec[0].re * scale;
        for k in 1..=n {
            coeffs[k] = 2.0 * scale * self.spec[k].re;
            coeffs[n + k] = -2.0 * scale * self.spec[k].im;
        }
    }

    /// Complex coefficients `ĝ_m` (with `g = Σ_m ĝ_m e^{imθ}`) for `m = 0..out.len()`;
    /// harmonics above `M/2` are not resolved and are set to zero.
    pub fn spectrum(&mut self, samples: &[f64], out: &mut [Complex64]) {
        let scale = 1.0 / self.m as f64;
        self.forward(samples);
        let top = self.m / 2;
        for (k, o) in out.iter_mut().enumerate() {
            *o = if k <= top { self.spec[k] * scale } else { Complex64::new(0.0, 0.0) };
        }
    }

    fn forward(&mut self, samples: &[f64]) {
        self.buf.copy_from_slice(samples);
        let res =
            self.r2c.process_with_scratch(&mut self.buf, &mut self.spec, &mut self.scratch_fwd);
        debug_assert!(res.is_ok(), "buffer sizes are fixed at construction");
    }
}
