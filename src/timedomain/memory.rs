//! The history part of a convolution quadrature: `H_m = Σ_{k<m} w_{m-k} e_k`.
//!
//! At step `m` the fractional signal is `dt^-q (w_0 e_m + H_m)`: the history `H_m`
//! depends only on finished values, so the implicit step needs it once per step.
//!
//! - [`NaiveHistory`] sums directly: `O(m)` per step, `O(n²)` per run. It is the
//!   reference the fast sum is tested against.
//! - [`FastHistory`] is the Hairer–Lubich–Schlichte fast convolution: the triangle
//!   `{(m, k): k < m}` is tiled by squares `k ∈ [m-b, m)`, `m' ∈ [m, m+b)` with
//!   `b` the lowest set bit of `m` (the recursive halving of the triangle). When step
//!   `m` begins, all sources of its square are known, and their contribution to the
//!   next `b` targets is added to an accumulator at once, by a direct sum for small
//!   squares and by an FFT of length `2b` otherwise. Each square at level `b` costs
//!   `O(b log b)`, there are `n / 2b` of them, so a run costs `O(n log² n)`; the
//!   weight spectra of every level are precomputed (`O(n)` memory in all), and
//!   nothing is allocated while stepping.

use crate::error::Error;
use ihbm_fft::{ComplexToReal, Planner, RealToComplex};
use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// How the history sums are evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Memory {
    /// FFT-based fast convolution, `O(n log² n)` (default).
    #[default]
    Fast,
    /// Direct sum, `O(n²)`: the reference.
    Naive,
}

/// The running history of one fractional signal, evaluated directly or fast.
#[derive(Debug)]
pub enum History {
    /// Direct sum.
    Naive(NaiveHistory),
    /// FFT-accelerated sum.
    Fast(FastHistory),
}

impl History {
    /// A history for `weights` (`w_0 ..= w_n`; at most `weights.len()` values are
    /// pushed in all).
    pub fn new(memory: Memory, weights: Vec<f64>) -> Self {
        match memory {
            Memory::Naive => History::Naive(NaiveHistory::new(weights)),
            Memory::Fast => History::Fast(FastHistory::new(weights)),
        }
    }

    /// The heap a history for `cap` values takes, in bytes (an estimate made before
    /// allocating). Naive: the weights and the values. Fast: weights, values and
    /// accumulators (24 B per value), per FFT level the weights' spectrum and the
    /// forward and inverse plans (measured: about 60 B per unit of square size `b`),
    /// and scratch for the largest level. The levels are those [`FastHistory::new`]
    /// builds, so a `cap` just above a power of two costs ~1.7× one just below it
    /// (measured on the quarter car: 178 against 104 B per step).
    pub fn bytes(memory: Memory, cap: usize) -> f64 {
        let cap_f = cap as f64;
        match memory {
            Memory::Naive => 16.0 * cap_f,
            Memory::Fast => {
                let (sum, max) =
                    level_sizes(cap).fold((0.0, 0.0), |(s, _), b| (s + b as f64, b as f64));
                24.0 * cap_f + 60.0 * sum + 32.0 * max
            }
        }
    }

    /// `H_m = Σ_{k<m} w_{m-k} e_k`, where `m` is the number of values pushed so far.
    pub fn lag_sum(&mut self) -> Result<f64, Error> {
        match self {
            History::Naive(h) => h.lag_sum(),
            History::Fast(h) => h.lag_sum(),
        }
    }

    /// Append the finished value `e_m`.
    pub fn push(&mut self, value: f64) -> Result<(), Error> {
        match self {
            History::Naive(h) => h.push(value),
            History::Fast(h) => h.push(value),
        }
    }

    /// The values pushed so far.
    pub fn values(&self) -> &[f64] {
        match self {
            History::Naive(h) => &h.values,
            History::Fast(h) => &h.values,
        }
    }
}

/// Direct evaluation of the history sum.
#[derive(Debug, Clone)]
pub struct NaiveHistory {
    weights: Vec<f64>,
    values: Vec<f64>,
}

impl NaiveHistory {
    /// Room for `weights.len()` values.
    pub fn new(weights: Vec<f64>) -> Self {
        let values = Vec::with_capacity(weights.len());
        NaiveHistory { weights, values }
    }

    /// `Σ_{k<m} w_{m-k} e_k`, `O(m)`.
    pub fn lag_sum(&self) -> Result<f64, Error> {
        let m = self.values.len();
        if m >= self.weights.len() {
            return Err(Error::HistoryFull { capacity: self.weights.len() });
        }
        // w_m e_0 + w_{m-1} e_1 + ... + w_1 e_{m-1}
        Ok(self.values.iter().zip(self.weights[1..=m].iter().rev()).map(|(e, w)| e * w).sum())
    }

    /// Append `e_m`.
    pub fn push(&mut self, value: f64) -> Result<(), Error> {
        if self.values.len() >= self.weights.len() {
            return Err(Error::HistoryFull { capacity: self.weights.len() });
        }
        self.values.push(value);
        Ok(())
    }
}

/// Squares up to this size are summed directly (cheaper than two FFTs).
const DIRECT_MAX: usize = 32;

/// The square sizes `b` of the FFT levels of a history for `cap` values:
/// `2 DIRECT_MAX · 2^i` below `cap` (squares have size `lowbit(m) <= m < cap`).
fn level_sizes(cap: usize) -> impl Iterator<Item = usize> {
    std::iter::successors(Some(2 * DIRECT_MAX), |b| b.checked_mul(2)).take_while(move |&b| b < cap)
}

/// One FFT level: squares of size `b`, transforms of length `2b`.
struct Level {
    /// Spectrum of `[w_1, ..., w_{2b-1}, 0]` (zero beyond the last weight).
    spectrum: Vec<Complex64>,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
}

impl std::fmt::Debug for Level {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Level").field("len", &self.forward.len()).finish()
    }
}

/// Hairer–Lubich–Schlichte fast history sums (see the module docs).
#[derive(Debug)]
pub struct FastHistory {
    weights: Vec<f64>,
    values: Vec<f64>,
    /// `acc[m]` collects the contributions of all squares whose targets include `m`.
    acc: Vec<f64>,
    /// `levels[i]` serves squares of size `2 DIRECT_MAX · 2^i`.
    levels: Vec<Level>,
    /// The square starting at this many values has been added (`lag_sum` may be
    /// asked twice for one step: a step that failed is tried again).
    added: Option<usize>,
    time: Vec<f64>,
    freq: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

impl FastHistory {
    /// Room for `weights.len()` values; plans and weight spectra for every level.
    pub fn new(weights: Vec<f64>) -> Self {
        let cap = weights.len();
        let mut planner = Planner::new();
        let mut levels = Vec::new();
        let mut scratch_len = 0;
        for b in level_sizes(cap) {
            let n = 2 * b;
            let forward = planner.forward(n);
            let inverse = planner.inverse(n);
            let mut time: Vec<f64> = (0..n)
                .map(|l| if l + 1 < cap && l + 1 < n { weights[l + 1] } else { 0.0 })
                .collect();
            let mut spectrum = forward.make_output_vec();
            scratch_len = scratch_len.max(forward.get_scratch_len()).max(inverse.get_scratch_len());
            let mut scratch = forward.make_scratch_vec();
            // Lengths come from the plan itself, so this cannot fail.
            let _ = forward.process_with_scratch(&mut time, &mut spectrum, &mut scratch);
            // Fold the 1/n of the unnormalised inverse into the weights.
            let scale = 1.0 / n as f64;
            spectrum.iter_mut().for_each(|s| *s *= scale);
            levels.push(Level { spectrum, forward, inverse });
        }
        let max_n = levels.last().map_or(0, |l| l.forward.len());
        FastHistory {
            values: Vec::with_capacity(cap),
            acc: vec![0.0; cap],
            weights,
            levels,
            added: None,
            time: vec![0.0; max_n],
            freq: vec![Complex64::new(0.0, 0.0); max_n / 2 + 1],
            scratch: vec![Complex64::new(0.0, 0.0); scratch_len],
        }
    }

    /// `Σ_{k<m} w_{m-k} e_k`: add the square that starts at `m`, then read `acc[m]`.
    pub fn lag_sum(&mut self) -> Result<f64, Error> {
        let m = self.values.len();
        let cap = self.weights.len();
        if m >= cap {
            return Err(Error::HistoryFull { capacity: cap });
        }
        if m == 0 || self.added == Some(m) {
            return Ok(self.acc[m]);
        }
        self.added = Some(m);
        let b = 1usize << m.trailing_zeros();
        let targets = b.min(cap - m);
        let src = &self.values[m - b..m];
        if b <= DIRECT_MAX {
            // Target m + i, source m - b + j: lag b + i - j in [1, 2b - 1].
            for i in 0..targets {
                let w = &self.weights[i + 1..=b + i];
                let s: f64 = src.iter().zip(w.iter().rev()).map(|(e, w)| e * w).sum();
                self.acc[m + i] += s;
            }
        } else {
            let level = &self.levels[(b / (2 * DIRECT_MAX)).trailing_zeros() as usize];
            let n = 2 * b;
            let time = &mut self.time[..n];
            time[..b].copy_from_slice(src);
            time[b..].fill(0.0);
            let freq = &mut self.freq[..b + 1];
            level
                .forward
                .process_with_scratch(time, freq, &mut self.scratch)
                .map_err(|e| Error::HistoryFft { reason: e.to_string() })?;
            freq.iter_mut().zip(&level.spectrum).for_each(|(f, w)| *f *= w);
            // The product of two real spectra is real at DC and Nyquist up to rounding;
            // the inverse real FFT insists on exactly real.
            freq[0].im = 0.0;
            freq[b].im = 0.0;
            level
                .inverse
                .process_with_scratch(freq, time, &mut self.scratch)
                .map_err(|e| Error::HistoryFft { reason: e.to_string() })?;
            // Linear convolution index b - 1 + i is target m + i, free of wrap-around.
            for (a, c) in self.acc[m..m + targets].iter_mut().zip(&time[b - 1..b - 1 + targets]) {
                *a += c;
            }
        }
        Ok(self.acc[m])
    }

    /// Append `e_m`.
    pub fn push(&mut self, value: f64) -> Result<(), Error> {
        if self.values.len() >= self.weights.len() {
            return Err(Error::HistoryFull { capacity: self.weights.len() });
        }
        self.values.push(value);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timedomain::Scheme;

    #[test]
    fn fast_equals_naive_on_a_smooth_sequence() {
        let n = 3000;
        let w = Scheme::Bdf2.weights(0.5, n + 1);
        let mut fast = FastHistory::new(w.clone());
        let mut naive = NaiveHistory::new(w);
        for m in 0..=n {
            let a = fast.lag_sum().unwrap();
            let b = naive.lag_sum().unwrap();
            // Asked again for the same step (a failed step tried again): the same sum.
            assert_eq!(fast.lag_sum().unwrap(), a, "m {m}");
            let scale = naive.values.iter().map(|v| v.abs()).fold(1e-300, f64::max);
            assert!((a - b).abs() <= 1e-13 * scale, "m {m}: {a} vs {b}");
            let e = (m as f64 * 0.01).sin() * (1.0 + 0.001 * m as f64);
            fast.push(e).unwrap();
            naive.push(e).unwrap();
        }
        assert!(fast.push(0.0).is_err() && naive.lag_sum().is_err());
    }
}
