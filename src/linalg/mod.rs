//! LU factorisations: real dense ([`DenseLu`], faer's allocation-free kernels), band
//! ([`BandLu`]) and bordered ([`BorderedLu`]: continuation's Jacobian plus its
//! borders, banded when that pays), and complex on row-major slices, dense or kept
//! to a band ([`complex_lu_factor`], [`complex_band_lu_factor`]: the Hill operator).
//!
//! Newton and continuation solve many systems of the same size; keeping the
//! permutation and scratch buffers between solves keeps the hot loop allocation-free.

mod banded;
mod bordered;

pub use banded::{Band, BandLu};
pub use bordered::{BlockA, BorderedLu, Columns, DENSE_BELOW};

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, MatMut, Par};
use num_complex::Complex64;

/// LU factorisation with partial pivoting, factor and solve in place.
pub struct DenseLu {
    n: usize,
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    buffer: MemBuffer,
    tmp: Vec<f64>,
}

impl std::fmt::Debug for DenseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "DenseLu {{ n: {} }}", self.n)
    }
}

impl DenseLu {
    /// A workspace for `n × n` systems.
    pub fn new(n: usize) -> Self {
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default());
        DenseLu {
            n,
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            buffer: MemBuffer::new(req),
            tmp: vec![0.0; n],
        }
    }

    /// The matrix to be factorised: fill it, then call [`DenseLu::factor`].
    pub fn matrix_mut(&mut self) -> MatMut<'_, f64> {
        self.lu.as_mut()
    }

    /// Factorise the matrix in place. Returns the ratio of the smallest to the largest
    /// pivot magnitude (0 for an exactly singular matrix, NaN if it holds NaN).
    pub fn factor(&mut self) -> f64 {
        factor::lu_in_place(
            self.lu.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.buffer),
            Default::default(),
        );
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for i in 0..self.n {
            let d = self.lu[(i, i)].abs();
            if d.is_nan() {
                return f64::NAN;
            }
            lo = lo.min(d);
            hi = hi.max(d);
        }
        if hi == 0.0 {
            0.0
        } else {
            lo / hi
        }
    }

    /// Solve `A x = b` in place (`rhs` holds b on entry and x on exit).
    ///
    /// The triangular solves are written out here: at the sizes harmonic balance
    /// uses (tens of unknowns) faer's general kernels spend more on dispatch than on
    /// the `n²` flops (measured 7.7k instructions for n = 23, against ~1.5k here).
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let n = self.n;
        for (t, &p) in self.tmp.iter_mut().zip(&self.perm) {
            *t = rhs[p];
        }
        let x = &mut self.tmp;
        // L y = P b, L unit lower triangular (column-oriented: contiguous columns)
        for k in 0..n {
            let xk = x[k];
            if xk != 0.0 {
                let col = &self.lu.col_as_slice(k)[k + 1..n];
                for (xi, &l) in x[k + 1..n].iter_mut().zip(col) {
                    *xi -= l * xk;
                }
            }
        }
        // U x = y
        for k in (0..n).rev() {
            let col = self.lu.col_as_slice(k);
            x[k] /= col[k];
            let xk = x[k];
            if xk != 0.0 {
                for (xi, &u) in x[..k].iter_mut().zip(&col[..k]) {
                    *xi -= u * xk;
                }
            }
        }
        rhs[..n].copy_from_slice(x);
    }

    /// Solve `Aᵀ x = b` in place with the same factors (`P A = L U`, so
    /// `Aᵀ = Uᵀ Lᵀ P`): the left null vectors a fold's test function needs.
    pub fn solve_transpose(&mut self, rhs: &mut [f64]) {
        let n = self.n;
        let x = &mut self.tmp;
        x.copy_from_slice(&rhs[..n]);
        // Uᵀ z = b (lower triangular; column k of U is row k of Uᵀ)
        for k in 0..n {
            let col = self.lu.col_as_slice(k);
            let s: f64 = col[..k].iter().zip(&x[..k]).map(|(u, z)| u * z).sum();
            x[k] = (x[k] - s) / col[k];
        }
        // Lᵀ y = z (unit upper triangular)
        for k in (0..n).rev() {
            let col = &self.lu.col_as_slice(k)[k + 1..n];
            let s: f64 = col.iter().zip(&x[k + 1..n]).map(|(l, y)| l * y).sum();
            x[k] -= s;
        }
        // x = Pᵀ y
        for (i, &p) in self.perm.iter().enumerate() {
            rhs[p] = x[i];
        }
    }
}

/// LU factorisation with partial pivoting of the row-major complex `n × n` matrix `a`
/// in place (`P·A = L·U`, `L` unit lower triangular below the diagonal, `U` on and
/// above it; `piv[k]` the row swapped into row `k`). A pivot of magnitude not above
/// `tiny` (or not finite) is *singular*: its column is left uneliminated (multipliers
/// zero). Returns the number of singular pivots; the factors solve only if it is 0,
/// except through [`complex_lu_solve_consistent`].
///
/// Hand-written rather than faer's: the systems are small (the Hill matrices of a few
/// DOFs, `n` ≲ 100; the per-harmonic `ndof × ndof` systems of the linearised start),
/// and a plain loop allocates nothing and needs no setup. Its row update is written
/// with `pulp`'s complex SIMD operations (faer's own layer), dispatched to the
/// instruction set found at run time: the curve of the 5-mass chain with stability
/// (about 30 factorisations of size 55 or 115 per full analysis) took 0.79 → 0.59 s at
/// N = 5 and 4.3 → 2.8 s at N = 11 against the scalar loop.
pub fn complex_lu_factor(a: &mut [Complex64], n: usize, piv: &mut [usize], tiny: f64) -> usize {
    let full = n.saturating_sub(1);
    complex_band_lu_factor(a, n, (full, full), piv, tiny)
}

/// [`complex_lu_factor`] of a matrix with `kl` nonzero diagonals below the main one
/// and `ku` above (`band = (kl, ku)`), still stored dense: the pivot search and the
/// row updates keep to the band, as LAPACK's `gbtrf` does (pivoting widens `U` to
/// `kl + ku` superdiagonals, never `L` beyond `kl`), so the cost is
/// `≈ 2n·kl·(kl + ku)` instead of `⅔n³`. Solve with [`complex_band_lu_solve`] and
/// [`complex_band_lu_solve_adjoint`] and `upper = kl + ku` (the full-width
/// solves are correct too: entries outside the band stay zero). Stored dense rather
/// than by diagonals: the rows stay contiguous for the SIMD update, the solves and
/// `det` read the factors as the dense ones, and `T(λ)` is assembled as before. The
/// Hill operator of a chain is block-tridiagonal as its Jacobian is; one factorisation
/// (`cargo bench --bench stability -- hill_lu`) took 205 → 42 µs at 10 masses and
/// N = 5 (110 unknowns, `kl = ku = 21`), 1.68 → 0.33 ms at N = 11 (230, 45), and
/// 15.0 → 1.02 ms at 20 masses and N = 11 (460, 45).
pub fn complex_band_lu_factor(
    a: &mut [Complex64],
    n: usize,
    band: (usize, usize),
    piv: &mut [usize],
    tiny: f64,
) -> usize {
    pulp::Arch::new().dispatch(ComplexLu { a, n, band, piv, tiny })
}

/// [`complex_band_lu_factor`]'s elimination, generic over the SIMD instruction set.
struct ComplexLu<'a> {
    a: &'a mut [Complex64],
    n: usize,
    band: (usize, usize),
    piv: &'a mut [usize],
    tiny: f64,
}

impl pulp::WithSimd for ComplexLu<'_> {
    type Output = usize;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> usize {
        let ComplexLu { a, n, band: (kl, ku), piv, tiny } = self;
        let zero = Complex64::new(0.0, 0.0);
        let mut singular = 0;
        for k in 0..n {
            // Rows below k + kl are untouched rows of A, zero in column k; the pivot
            // row reaches column k + kl + ku at most.
            let last_row = (k + kl).min(n - 1);
            let last_col = (k + kl + ku).min(n - 1);
            let mut p = k;
            let mut best = a[k * n + k].norm_sqr();
            for i in k + 1..=last_row {
                let v = a[i * n + k].norm_sqr();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            piv[k] = p;
            if p != k {
                let (top, rest) = a.split_at_mut(p * n);
                top[k * n..(k + 1) * n].swap_with_slice(&mut rest[..n]);
            }
            if !(best.sqrt() > tiny && best.is_finite()) {
                singular += 1;
                for row in a[(k + 1) * n..(last_row + 1) * n].chunks_exact_mut(n) {
                    row[k] = zero;
                }
                continue;
            }
            let inv = a[k * n + k].inv();
            let (top, rest) = a.split_at_mut((k + 1) * n);
            let rowk = &top[k * n + k + 1..k * n + last_col + 1];
            let (yh, yt) = S::as_simd_c64s(rowk);
            for row in rest[..(last_row - k) * n].chunks_exact_mut(n) {
                let f = row[k] * inv;
                row[k] = f;
                if f == zero {
                    continue;
                }
                // row -= f · rowk
                let (xh, xt) = S::as_mut_simd_c64s(&mut row[k + 1..last_col + 1]);
                let nf = simd.splat_c64s(-f);
                for (x, &y) in xh.iter_mut().zip(yh) {
                    *x = simd.mul_add_c64s(nf, y, *x);
                }
                for (x, &y) in xt.iter_mut().zip(yt) {
                    *x -= f * y;
                }
            }
        }
        singular
    }
}

/// `b ← L⁻¹ P b` with the factors of [`complex_lu_factor`].
fn complex_forward(a: &[Complex64], n: usize, piv: &[usize], b: &mut [Complex64]) {
    // The factors are those of P·A (rows swapped in full): all swaps first.
    for (k, &p) in piv.iter().enumerate().take(n) {
        b.swap(k, p);
    }
    // Row-wise dot products (contiguous rows of L), not column updates.
    for i in 1..n {
        let row = &a[i * n..i * n + i];
        let s: Complex64 = row.iter().zip(&b[..i]).map(|(x, y)| x * y).sum();
        b[i] -= s;
    }
}

/// Solve `A x = b` in place with the factors of [`complex_lu_factor`] (no singular
/// pivot).
pub fn complex_lu_solve(a: &[Complex64], n: usize, piv: &[usize], b: &mut [Complex64]) {
    complex_band_lu_solve(a, n, n.saturating_sub(1), piv, b);
}

/// [`complex_lu_solve`] with the factors of [`complex_band_lu_factor`], whose `U` has
/// `upper = kl + ku` superdiagonals.
pub fn complex_band_lu_solve(
    a: &[Complex64],
    n: usize,
    upper: usize,
    piv: &[usize],
    b: &mut [Complex64],
) {
    complex_forward(a, n, piv, b);
    for k in (0..n).rev() {
        let end = (k + upper + 1).min(n);
        let row = &a[k * n..k * n + end];
        let s: Complex64 = row[k + 1..].iter().zip(&b[k + 1..end]).map(|(x, y)| x * y).sum();
        b[k] = (b[k] - s) / row[k];
    }
}

/// Solve `A x = b` where `A` may be singular but the system consistent: an unknown
/// whose pivot is singular (magnitude not above `tiny`) gets 0 if its equation's
/// residual is at rounding level (`1e-14` relative), `Err(k)` (the unknown) if not.
pub fn complex_lu_solve_consistent(
    a: &[Complex64],
    n: usize,
    piv: &[usize],
    tiny: f64,
    b: &mut [Complex64],
) -> std::result::Result<(), usize> {
    complex_forward(a, n, piv, b);
    for k in (0..n).rev() {
        let row = &a[k * n..(k + 1) * n];
        let s = b[k] - row[k + 1..].iter().zip(&b[k + 1..]).map(|(x, y)| x * y).sum::<Complex64>();
        if row[k].norm() <= tiny || row[k].norm().is_nan() {
            if s.norm() <= 1e-14 * (1.0 + b.iter().fold(0.0f64, |m, z| m.max(z.norm()))) {
                b[k] = Complex64::new(0.0, 0.0);
                continue;
            }
            return Err(k);
        }
        b[k] = s / row[k];
    }
    Ok(())
}

/// Solve `Aᴴ w = b` in place with the factors of [`complex_lu_factor`] (`P A = L U`,
/// so `Aᴴ = Uᴴ Lᴴ P`).
pub fn complex_lu_solve_adjoint(a: &[Complex64], n: usize, piv: &[usize], b: &mut [Complex64]) {
    complex_band_lu_solve_adjoint(a, n, n.saturating_sub(1), piv, b);
}

/// [`complex_lu_solve_adjoint`] with the factors of [`complex_band_lu_factor`], whose
/// `U` has `upper = kl + ku` superdiagonals.
pub fn complex_band_lu_solve_adjoint(
    a: &[Complex64],
    n: usize,
    upper: usize,
    piv: &[usize],
    b: &mut [Complex64],
) {
    // Uᴴ is lower triangular with the rows of U as its columns: column updates read
    // contiguous rows.
    for k in 0..n {
        let end = (k + upper + 1).min(n);
        let row = &a[k * n..k * n + end];
        let bk = b[k] / row[k].conj();
        b[k] = bk;
        for (x, u) in b[k + 1..end].iter_mut().zip(&row[k + 1..]) {
            *x -= u.conj() * bk;
        }
    }
    for k in (0..n).rev() {
        let bk = b[k];
        for i in 0..k {
            b[i] -= a[k * n + i].conj() * bk;
        }
    }
    for (k, &p) in piv.iter().enumerate().take(n).rev() {
        b.swap(k, p);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use faer::linalg::lu::partial_pivoting::solve as faer_solve;
    use faer::perm::PermRef;

    pub(crate) use crate::xorshift::next as xorshift;

    #[test]
    fn solve_matches_faer_on_a_pivoting_matrix() {
        let n = 23;
        // a generic (pseudo-random) matrix: partial pivoting swaps rows
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let vals: Vec<f64> = (0..n * n).map(|_| xorshift(&mut seed)).collect();
        let a = |i: usize, j: usize| vals[i * n + j];
        let mut lu = DenseLu::new(n);
        {
            let mut m = lu.matrix_mut();
            for j in 0..n {
                for i in 0..n {
                    m[(i, j)] = a(i, j);
                }
            }
        }
        let ratio = lu.factor();
        assert!(ratio > 1e-8, "test setup: near-singular matrix ({ratio})");
        assert!(lu.perm.iter().enumerate().any(|(i, &p)| i != p), "test setup: no pivoting");
        let b: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let mut x = b.clone();
        lu.solve(&mut x);
        // residual of the original system
        for i in 0..n {
            let r: f64 = (0..n).map(|j| a(i, j) * x[j]).sum::<f64>() - b[i];
            assert!(r.abs() < 1e-12, "row {i}: {r}");
        }
        // and faer's own solve gives the same vector
        let mut y = b.clone();
        let perm = PermRef::new_checked(&lu.perm, &lu.perm_inv, n);
        faer_solve::solve_in_place(
            lu.lu.as_ref(),
            lu.lu.as_ref(),
            perm,
            faer::MatMut::from_column_major_slice_mut(&mut y, n, 1),
            Par::Seq,
            MemStack::new(&mut MemBuffer::new(faer_solve::solve_in_place_scratch::<usize, f64>(
                n,
                1,
                Par::Seq,
            ))),
        );
        for (p, q) in x.iter().zip(&y) {
            assert!((p - q).abs() < 1e-13 * (1.0 + q.abs()));
        }
        // the transposed solve with the same factors: residual of Aᵀ x = b
        let mut xt = b.clone();
        lu.solve_transpose(&mut xt);
        for i in 0..n {
            let r: f64 = (0..n).map(|j| a(j, i) * xt[j]).sum::<f64>() - b[i];
            assert!(r.abs() < 1e-12, "column {i}: {r}");
        }
    }

    #[test]
    fn complex_lu_solves_with_pivoting() {
        // A matrix whose first pivot is zero: pivoting is required.
        let n = 7;
        let a: Vec<Complex64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                if i == 0 && j == 0 {
                    Complex64::new(0.0, 0.0)
                } else {
                    let re = ((i * 7 + j * 3) % 11) as f64 - 5.0;
                    Complex64::new(re, ((i + 2 * j) % 3) as f64)
                }
            })
            .collect();
        let x: Vec<Complex64> = (0..n).map(|i| Complex64::new(i as f64 - 2.0, 0.5)).collect();
        let mut b: Vec<Complex64> =
            (0..n).map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum()).collect();
        let mut lu = a.clone();
        let mut piv = vec![0; n];
        assert_eq!(complex_lu_factor(&mut lu, n, &mut piv, 0.0), 0);
        complex_lu_solve(&lu, n, &piv, &mut b);
        for (bi, xi) in b.iter().zip(&x) {
            assert!((bi - xi).norm() < 1e-12, "{bi} vs {xi}");
        }
        // The stored factors solve another right-hand side (the reuse in stability's `newton`).
        let y: Vec<Complex64> = (0..n).map(|i| Complex64::new(0.3, i as f64)).collect();
        let mut c: Vec<Complex64> =
            (0..n).map(|i| (0..n).map(|j| a[i * n + j] * y[j]).sum()).collect();
        complex_lu_solve(&lu, n, &piv, &mut c);
        for (ci, yi) in c.iter().zip(&y) {
            assert!((ci - yi).norm() < 1e-12, "{ci} vs {yi}");
        }
        assert!(piv.iter().enumerate().filter(|&(k, &p)| p != k).count() >= 2, "{piv:?}");
        // And the adjoint system Aᴴ y = d (the Rayleigh step in stability's `newton`).
        let mut d: Vec<Complex64> =
            (0..n).map(|i| (0..n).map(|j| a[j * n + i].conj() * y[j]).sum()).collect();
        complex_lu_solve_adjoint(&lu, n, &piv, &mut d);
        for (di, yi) in d.iter().zip(&y) {
            assert!((di - yi).norm() < 1e-12, "{di} vs {yi}");
        }
    }

    #[test]
    fn complex_band_lu_equals_the_dense_one_on_a_band_matrix() {
        // Block-tridiagonal as a chain's Hill operator (blocks of 5, so kl = ku = 9),
        // with a small diagonal so that pivoting swaps rows and widens U: the factors
        // kept to the band solve as the dense ones do, forward and adjoint, and give
        // the same determinant (the product of the pivots, the swaps' sign).
        let (n, len): (usize, usize) = (40, 5);
        let (kl, ku) = (2 * len - 1, 2 * len - 1);
        let mut seed = 0x5eed_0fba_4d00_u64;
        let a: Vec<Complex64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                if (i / len).abs_diff(j / len) > 1 {
                    return Complex64::new(0.0, 0.0);
                }
                let z = Complex64::new(xorshift(&mut seed), xorshift(&mut seed));
                if i == j {
                    z * 0.01
                } else {
                    z
                }
            })
            .collect();
        assert!((0..n * n).all(|k| {
            let (i, j) = (k / n, k % n);
            a[k] == Complex64::new(0.0, 0.0) || (i <= j + kl && j <= i + ku)
        }));
        let (mut dense, mut band) = (a.clone(), a.clone());
        let (mut pd, mut pb) = (vec![0; n], vec![0; n]);
        assert_eq!(complex_lu_factor(&mut dense, n, &mut pd, 0.0), 0);
        assert_eq!(complex_band_lu_factor(&mut band, n, (kl, ku), &mut pb, 0.0), 0);
        assert!(pb.iter().enumerate().filter(|&(k, &p)| p != k).count() > n / 4, "{pb:?}");
        // The same pivots: the band search skips only zeros.
        assert_eq!(pd, pb);
        let det = |lu: &[Complex64], piv: &[usize]| {
            let swaps = piv.iter().enumerate().filter(|&(k, &p)| p != k).count();
            let d: Complex64 = (0..n).map(|k| lu[k * n + k]).product();
            if swaps % 2 == 1 {
                -d
            } else {
                d
            }
        };
        let (dd, db) = (det(&dense, &pd), det(&band, &pb));
        assert!((dd - db).norm() <= 1e-12 * dd.norm(), "{dd} vs {db}");
        let x: Vec<Complex64> = (0..n).map(|i| Complex64::new((i as f64).sin(), 0.3)).collect();
        let product = |adjoint: bool| -> Vec<Complex64> {
            (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| if adjoint { a[j * n + i].conj() } else { a[i * n + j] } * x[j])
                        .sum()
                })
                .collect()
        };
        let mut b = product(false);
        complex_band_lu_solve(&band, n, kl + ku, &pb, &mut b);
        let mut c = product(true);
        complex_band_lu_solve_adjoint(&band, n, kl + ku, &pb, &mut c);
        for i in 0..n {
            assert!((b[i] - x[i]).norm() < 1e-10, "x{i}: {} vs {}", b[i], x[i]);
            assert!((c[i] - x[i]).norm() < 1e-10, "adjoint x{i}: {} vs {}", c[i], x[i]);
        }
    }

    #[test]
    fn complex_consistent_solve_zeroes_a_free_unknown() {
        // Unknown 1 has no equation of its own (a zero column and row): consistent
        // right-hand side gives it 0, an inconsistent one names it.
        let z = Complex64::new(0.0, 0.0);
        let a = [
            Complex64::new(2.0, 1.0),
            z,
            Complex64::new(1.0, 0.0),
            z,
            z,
            z,
            Complex64::new(1.0, 0.0),
            z,
            Complex64::new(3.0, 0.0),
        ];
        let mut lu = a;
        let mut piv = [0; 3];
        assert_eq!(complex_lu_factor(&mut lu, 3, &mut piv, 1e-14), 1);
        let x = [Complex64::new(1.0, -1.0), z, Complex64::new(0.5, 2.0)];
        let mut b: Vec<Complex64> =
            (0..3).map(|i| (0..3).map(|j| a[i * 3 + j] * x[j]).sum()).collect();
        assert_eq!(complex_lu_solve_consistent(&lu, 3, &piv, 1e-14, &mut b), Ok(()));
        for (bi, xi) in b.iter().zip(&x) {
            assert!((bi - xi).norm() < 1e-14, "{bi} vs {xi}");
        }
        let mut bad = vec![z, Complex64::new(1.0, 0.0), z];
        assert_eq!(complex_lu_solve_consistent(&lu, 3, &piv, 1e-14, &mut bad), Err(1));
    }
}
