//! Dense LU with a reusable workspace (faer's allocation-free kernels).
//!
//! Newton and continuation solve many small systems of the same size; keeping the
//! permutation and scratch buffers between solves keeps the hot loop allocation-free.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Mat, MatMut, Par};

/// LU factorisation with partial pivoting, factor and solve in place.
pub struct DenseLu {
    n: usize,
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    buffer: MemBuffer,
}

impl std::fmt::Debug for DenseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "DenseLu {{ n: {} }}", self.n)
    }
}

impl DenseLu {
    /// A workspace for `n × n` systems.
    pub fn new(n: usize) -> Self {
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())
            .or(solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq));
        DenseLu {
            n,
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            buffer: MemBuffer::new(req),
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
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let n = self.n;
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let rhs = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        solve::solve_in_place(
            self.lu.as_ref(),
            self.lu.as_ref(),
            perm,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.buffer),
        );
    }
}
