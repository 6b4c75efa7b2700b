//! How large a harmonic-balance problem may be: its dense Jacobians estimated before
//! anything is allocated.

use crate::error::{Error, Result};

/// Memory the dense harmonic-balance solvers may take: the Jacobians of the corrector
/// and of the continuation (with its LU workspace) are `L × L` with
/// `L = ndof (2N + 1)` unknowns, about `3 · 8 L²` bytes together.
pub const MEMORY_LIMIT: f64 = 4.0 * (1u64 << 30) as f64;

/// Refuse a harmonic count whose dense Jacobians would not fit in [`MEMORY_LIMIT`]
/// (estimated before anything is allocated, in floating point so that no size
/// overflows), naming the largest N that fits.
///
/// ```
/// use ihbm::balance::check_size;
/// assert!(check_size(2, 5).is_ok());
/// let e = check_size(2, 100_000).unwrap_err().to_string();
/// assert!(e.contains("the largest N that fits is 3343"), "{e}");
/// assert!(check_size(2, usize::MAX).is_err());
/// ```
pub fn check_size(ndof: usize, harmonics: usize) -> Result<()> {
    let bytes = |n: usize| {
        let l = ndof as f64 * (2.0 * n as f64 + 1.0) + 1.0;
        24.0 * l * l
    };
    if bytes(harmonics) <= MEMORY_LIMIT {
        return Ok(());
    }
    // 24 (ndof (2N + 1) + 1)² <= limit
    let lmax = (MEMORY_LIMIT / 24.0).sqrt() - 1.0;
    let largest = ((lmax / ndof.max(1) as f64 - 1.0) / 2.0).floor().max(0.0) as usize;
    Err(Error::TooLarge {
        harmonics,
        dofs: ndof,
        what: "harmonic-balance Jacobians".into(),
        needed: readable_bytes(bytes(harmonics)),
        limit: readable_bytes(MEMORY_LIMIT),
        largest,
    })
}

/// The largest `n <= hi` for which `fits(n)`, given that `fits` holds up to some
/// size and fails beyond it (0 if it fails everywhere): bisection, for estimates
/// without a closed-form inverse.
pub(crate) fn largest_fitting(hi: usize, fits: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0usize, hi);
    while lo + 1 < hi {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// `1.3 TB`, `4 GiB`-style sizes for messages.
pub(crate) fn readable_bytes(b: f64) -> String {
    const UNITS: [&str; 7] = ["B", "kB", "MB", "GB", "TB", "PB", "EB"];
    let mut v = b;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < UNITS.len() {
        v /= 1000.0;
        u += 1;
    }
    if u + 1 == UNITS.len() && v >= 1000.0 {
        return format!("{b:.1e} B");
    }
    format!("{v:.1} {}", UNITS[u])
}
