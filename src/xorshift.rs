//! Reproducible pseudo-random numbers (Marsaglia's xorshift64, shifts 13, 7, 17): the
//! states at which [`crate::balance`] tests a model's structure claims, and the test
//! matrices of [`crate::linalg`]. Not for statistics: only spread-out values that are
//! the same on every run.

/// The next number in `[-1, 1)` from `seed` (any non-zero value), which it advances.
pub(crate) fn next(seed: &mut u64) -> f64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_cover_the_interval_evenly() {
        // 10⁴ draws: mean 0 and variance 1/3 of the uniform law on [-1, 1], to a few
        // standard errors (σ/√n = 0.0058 for the mean).
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let xs: Vec<f64> = (0..10_000).map(|_| next(&mut seed)).collect();
        assert!(xs.iter().all(|x| (-1.0..1.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.02, "{mean}");
        assert!((var - 1.0 / 3.0).abs() < 0.01, "{var}");
    }
}
