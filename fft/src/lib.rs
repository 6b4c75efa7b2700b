//! Real FFT plans in `f64`, behind functions that are not generic.
//!
//! `realfft` and `rustfft` are generic over the float type, so their planners (every
//! butterfly, in scalar, SSE and AVX variants) are compiled by whichever crate plans an
//! FFT. Planned from `ihbm`, that code was 55 % of the LLVM IR of its library
//! (435 000 of 799 000 lines, measured with `cargo llvm-lines`), compiled twice by
//! `cargo test` (the library and its unit tests). Planned here, it is compiled once,
//! beside the other dependencies; `ihbm` calls the plans through their trait objects,
//! as it did before.
//!
//! ```
//! use ihbm_fft::Planner;
//!
//! // cos θ sampled at 8 points: the spectrum has 4 (= 8/2) at k = 1 and 0 elsewhere.
//! let mut planner = Planner::new();
//! let forward = planner.forward(8);
//! let mut x: Vec<f64> = (0..8).map(|j| (std::f64::consts::TAU * j as f64 / 8.0).cos()).collect();
//! let mut spectrum = forward.make_output_vec();
//! forward.process(&mut x, &mut spectrum).unwrap();
//! assert!((spectrum[1].re - 4.0).abs() < 1e-12 && spectrum[1].im.abs() < 1e-12);
//! assert!(spectrum.iter().enumerate().all(|(k, c)| k == 1 || c.norm() < 1e-12));
//! ```

use std::sync::Arc;

pub use realfft::{ComplexToReal, FftError, RealToComplex};

/// Plans for real-to-complex and complex-to-real transforms of any length, reused
/// across calls of the same length.
pub struct Planner(realfft::RealFftPlanner<f64>);

impl Planner {
    /// An empty planner.
    pub fn new() -> Self {
        Planner(realfft::RealFftPlanner::new())
    }

    /// The forward transform of `len` real samples into `len / 2 + 1` complex values.
    pub fn forward(&mut self, len: usize) -> Arc<dyn RealToComplex<f64>> {
        self.0.plan_fft_forward(len)
    }

    /// The inverse transform of `len / 2 + 1` complex values into `len` real samples
    /// (unnormalised: the forward transform followed by it multiplies by `len`).
    pub fn inverse(&mut self, len: usize) -> Arc<dyn ComplexToReal<f64>> {
        self.0.plan_fft_inverse(len)
    }
}

impl Default for Planner {
    fn default() -> Self {
        Planner::new()
    }
}
