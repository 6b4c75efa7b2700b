//! The eigenvalues of the (frozen-order) matrix polynomial with their eigenvectors:
//! companion linearisation and a real eigendecomposition, QZ on the companion pencil
//! when the leading matrix is singular.

use super::*;
use crate::error::HillFailure;

/// The companion eigensolve's matrices and workspace.
pub(super) struct Companion {
    companion: Mat<f64>,
    /// Right eigenvectors of the companion matrix (a complex pair in two columns).
    vectors: Mat<f64>,
    /// The leading coefficient, then its LU.
    lead: Mat<f64>,
    s_re: Vec<f64>,
    s_im: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
}

impl Companion {
    /// For a polynomial of `m × m` coefficients and a companion of size `big`.
    pub(super) fn new(m: usize, big: usize) -> Companion {
        use faer::linalg::{evd, lu::partial_pivoting as lu};
        let scratch = evd::evd_scratch::<f64>(
            big,
            evd::ComputeEigenvectors::No,
            evd::ComputeEigenvectors::Yes,
            Par::Seq,
            Default::default(),
        )
        .or(lu::factor::lu_in_place_scratch::<usize, f64>(m, m, Par::Seq, Default::default()))
        .or(lu::solve::solve_in_place_scratch::<usize, f64>(m, big, Par::Seq));
        Companion {
            companion: Mat::zeros(big, big),
            vectors: Mat::zeros(big, big),
            lead: Mat::zeros(m, m),
            s_re: vec![0.0; big],
            s_im: vec![0.0; big],
            perm: vec![0; m],
            perm_inv: vec![0; m],
            mem: MemBuffer::new(scratch),
        }
    }
}

impl Hill {
    /// Selected (centred) eigenvalues of the matrix polynomial into `self.sel.cands`, not
    /// folded.
    pub(super) fn candidates(&mut self, params: &[f64], omega: f64) -> Result<()> {
        use faer::linalg::lu::partial_pivoting::{factor, solve};
        let (m, d) = (self.op.m, self.op.degree);
        let big = d * m;
        let count = self.central_count();
        let lead = &self.op.coef[d];
        self.eig.lead = Mat::from_fn(m, m, |i, j| lead[i * m + j]);
        let scale = self.eig.lead.norm_max();
        let (_, perm) = factor::lu_in_place(
            self.eig.lead.as_mut(),
            &mut self.eig.perm,
            &mut self.eig.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.eig.mem),
            Default::default(),
        );
        let min_pivot = (0..m).map(|i| self.eig.lead[(i, i)].abs()).fold(f64::INFINITY, f64::min);
        self.sel.cands.clear();
        if min_pivot.is_nan() || min_pivot <= 1e-12 * scale {
            return self.candidates_generalized(params, omega);
        }
        // Companion: [[0, I, ...], ..., [-L⁻¹M_0, ..., -L⁻¹M_{d-1}]].
        self.eig.companion.fill(0.0);
        for b in 0..d - 1 {
            for i in 0..m {
                self.eig.companion[(b * m + i, (b + 1) * m + i)] = 1.0;
            }
        }
        for r in 0..d {
            for i in 0..m {
                for jj in 0..m {
                    self.eig.companion[((d - 1) * m + i, r * m + jj)] =
                        -self.op.coef[r][i * m + jj];
                }
            }
        }
        {
            let rows = self.eig.companion.as_mut().subrows_mut((d - 1) * m, m);
            solve::solve_in_place(
                self.eig.lead.as_ref(),
                self.eig.lead.as_ref(),
                perm,
                rows,
                Par::Seq,
                MemStack::new(&mut self.eig.mem),
            );
        }
        faer::linalg::evd::evd_real(
            self.eig.companion.as_ref(),
            faer::diag::DiagMut::from_slice_mut(&mut self.eig.s_re),
            faer::diag::DiagMut::from_slice_mut(&mut self.eig.s_im),
            None,
            Some(self.eig.vectors.as_mut()),
            Par::Seq,
            MemStack::new(&mut self.eig.mem),
            Default::default(),
        )
        .map_err(|e| Error::Hill { omega, failure: HillFailure::Eigensolve(format!("{e:?}")) })?;
        // The eigenvectors come with the decomposition: the first block of a companion
        // eigenvector `[v, λv, …]` is `v`. (One inverse iteration per eigenvalue, as
        // before, cost `m` factorisations of size `m`: O(m⁴), the bulk of a full
        // analysis beyond two DOFs.) A complex pair is stored as the real and
        // imaginary parts in two consecutive columns.
        let mut spreads = Vec::with_capacity(big);
        let mut v = vec![Complex64::new(0.0, 0.0); m];
        let keep_vectors = self.op.fractional;
        self.sel.cand_vectors.clear();
        let mut i = 0;
        while i < big {
            let im = self.eig.s_im[i];
            let pair = im != 0.0 && i + 1 < big;
            for (r, z) in v.iter_mut().enumerate() {
                let b = if pair { self.eig.vectors[(r, i + 1)] } else { 0.0 };
                *z = Complex64::new(self.eig.vectors[(r, i)], b);
            }
            let sp = spread(&v, self.op.ndof, self.op.harmonics);
            self.sel.cands.push(Complex64::new(self.eig.s_re[i], im));
            spreads.push(sp);
            if keep_vectors {
                self.sel.cand_vectors.extend_from_slice(&v);
            }
            if pair {
                self.sel.cands.push(Complex64::new(self.eig.s_re[i + 1], self.eig.s_im[i + 1]));
                spreads.push(Spread { centre: -sp.centre, spread: sp.spread });
                if keep_vectors {
                    self.sel.cand_vectors.extend(v.iter().map(|z| z.conj()));
                }
                i += 2;
            } else {
                i += 1;
            }
        }
        self.select_centred(params, omega, count, Some(&spreads));
        Ok(())
    }

    /// Fallback for a singular leading matrix: the companion pencil, QZ.
    pub(super) fn candidates_generalized(&mut self, params: &[f64], omega: f64) -> Result<()> {
        self.sel.cand_vectors.clear();
        let (m, d) = (self.op.m, self.op.degree);
        let big = d * m;
        let mut a = Mat::<f64>::zeros(big, big);
        let mut b = Mat::<f64>::zeros(big, big);
        for blk in 0..d - 1 {
            for i in 0..m {
                a[(blk * m + i, (blk + 1) * m + i)] = 1.0;
                b[(blk * m + i, blk * m + i)] = 1.0;
            }
        }
        for r in 0..d {
            for i in 0..m {
                for jj in 0..m {
                    a[((d - 1) * m + i, r * m + jj)] = -self.op.coef[r][i * m + jj];
                }
            }
        }
        for i in 0..m {
            for jj in 0..m {
                b[((d - 1) * m + i, (d - 1) * m + jj)] = self.op.coef[d][i * m + jj];
            }
        }
        let ge = a.generalized_eigen(&b).map_err(|e| Error::Hill {
            omega,
            failure: HillFailure::GeneralizedEigensolve(format!("{e:?}")),
        })?;
        let (sa, sb) = (ge.S_a(), ge.S_b());
        for i in 0..big {
            let (x, y) = (sa[i], sb[i]);
            if y.norm() > 1e-12 * x.norm().max(1e-300) {
                self.sel.cands.push(x / y);
            }
        }
        let count = (self.sel.cands.len() / self.op.len).max(1).min(self.sel.cands.len());
        self.select_centred(params, omega, count, None);
        Ok(())
    }
}
