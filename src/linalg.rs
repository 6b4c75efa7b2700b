//! Dense LU with a reusable workspace (faer's allocation-free kernels).
//!
//! Newton and continuation solve many small systems of the same size; keeping the
//! permutation and scratch buffers between solves keeps the hot loop allocation-free.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, MatMut, Par};

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
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::lu::partial_pivoting::solve as faer_solve;
    use faer::perm::PermRef;

    #[test]
    fn solve_matches_faer_on_a_pivoting_matrix() {
        let n = 23;
        // a generic (pseudo-random) matrix: partial pivoting swaps rows
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let vals: Vec<f64> = (0..n * n)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect();
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
    }
}
