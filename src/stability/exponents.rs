//! Exponent arithmetic: modulo `iΩ`, conjugates, separations, the verdict.

use super::*;

/// The verdict on a list of exponents.
pub(super) fn floquet(
    mut exps: Vec<Complex64>,
    omega: f64,
    opts: &StabilityOptions,
    refined: bool,
) -> Floquet {
    exps.sort_by(|a, b| b.re.total_cmp(&a.re));
    let max_real = exps.first().map_or(f64::NEG_INFINITY, |l| l.re);
    Floquet {
        stable: max_real <= opts.tol * omega,
        max_real,
        exponents: exps,
        refined,
        counted: false,
    }
}

/// For each exponent (one per conjugate pair, not folded), the distance to the nearest
/// other one among all exponents, their conjugates and their copies shifted by `±iΩ`
/// (its own conjugate and copies included: a pair meeting on the real axis or at
/// `±Ω/2`). Copies shifted further need no margin: an eigenvalue met there has its
/// eigenvector off centre by at least one, which the centring check sees.
pub(super) fn separations(l: &[Complex64], omega: f64) -> Vec<f64> {
    let w = Complex64::new(0.0, omega);
    l.iter()
        .enumerate()
        .map(|(i, &a)| {
            let mut best = f64::INFINITY;
            for (j, &b) in l.iter().enumerate() {
                for (c, z) in [b, b.conj()].into_iter().enumerate() {
                    for shift in [-1.0, 0.0, 1.0] {
                        // A real exponent is its own conjugate (an iteration in complex
                        // arithmetic leaves it an imaginary part of rounding size).
                        let itself = j == i && shift == 0.0 && (c == 0 || real(a, omega));
                        if !itself {
                            best = best.min((a - z - w * shift).norm());
                        }
                    }
                }
            }
            best
        })
        .collect()
}

/// Whether `a` and `b` are one exponent: equal, or conjugate, modulo `iΩ` (to the
/// refinement's tolerance).
pub(super) fn same_exponent(a: Complex64, b: Complex64, omega: f64) -> bool {
    let tol = 1e-8 * omega.max(a.norm());
    [b, b.conj()].into_iter().any(|z| fold_into_strip(a - z, omega).norm() <= tol)
}

/// Append the exponent `l` (one of a conjugate pair, not folded) to `exps` folded into
/// the strip, and its conjugate unless it is real.
pub(super) fn push_central(exps: &mut Vec<Complex64>, l: Complex64, omega: f64) {
    let l = fold_into_strip(l, omega);
    exps.push(l);
    if !real(l, omega) {
        exps.push(l.conj());
    }
}

/// Whether a (raw) exponent is real: its imaginary part is at rounding level (the
/// refinement and tracking iterate in complex arithmetic).
pub(super) fn real(l: Complex64, omega: f64) -> bool {
    l.im.abs() <= 1e-12 * omega
}

/// Exponents are defined modulo `iΩ`; bring one into `(-Ω/2, Ω/2]`.
pub(super) fn fold_into_strip(l: Complex64, omega: f64) -> Complex64 {
    let shift = (l.im / omega).round();
    Complex64::new(l.re, l.im - shift * omega)
}
