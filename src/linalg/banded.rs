//! Band matrices: storage a Jacobian can be assembled into ([`Band`]) and an LU
//! factorisation with partial pivoting that keeps to the band ([`BandLu`]).
//!
//! A chain's harmonic balance Jacobian, its unknowns ordered DOF by DOF, is block
//! tridiagonal with dense `(2N+1)`-blocks: `kl = ku = 2(2N+1) − 1`. Partial pivoting
//! widens the upper band to `kl + ku` and never the lower one (LAPACK's `gbtf2`), so
//! the factors fit in `2kl + ku + 1` stored diagonals and cost `≈ 2n·kl·(kl + ku)`
//! flops against the dense `⅔n³`.

/// An `n × n` band matrix: `kl` diagonals below the main one, `ku` above, stored by
/// columns (entry `(i, j)` at `ku + i − j + j·(kl + ku + 1)`, LAPACK's layout), so a
/// column's rows within the band are contiguous.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    n: usize,
    kl: usize,
    ku: usize,
    data: Vec<f64>,
}

impl Band {
    /// A zero band matrix.
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let (kl, ku) = (kl.min(n.saturating_sub(1)), ku.min(n.saturating_sub(1)));
        Band { n, kl, ku, data: vec![0.0; n * (kl + ku + 1)] }
    }

    /// The dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The diagonals below and above the main one.
    pub fn bandwidths(&self) -> (usize, usize) {
        (self.kl, self.ku)
    }

    fn ld(&self) -> usize {
        self.kl + self.ku + 1
    }

    /// Rows `row0..row0 + len` of column `col`, or `None` if any lies outside the band.
    pub fn segment(&mut self, col: usize, row0: usize, len: usize) -> Option<&mut [f64]> {
        if col >= self.n || row0 + len > self.n || row0 + self.ku < col {
            return None;
        }
        if len > 0 && row0 + len - 1 > col + self.kl {
            return None;
        }
        let start = self.ku + row0 - col + col * self.ld();
        Some(&mut self.data[start..start + len])
    }

    /// Entry `(i, j)` (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i >= self.n || j >= self.n || i + self.ku < j || i > j + self.kl {
            return 0.0;
        }
        self.data[self.ku + i - j + j * self.ld()]
    }

    /// Set every stored entry to 0.
    pub fn clear(&mut self) {
        self.data.fill(0.0);
    }

    /// Multiply every entry by `s`.
    pub fn scale(&mut self, s: f64) {
        self.data.iter_mut().for_each(|v| *v *= s);
    }

    /// The rows of column `j` inside the band and their first row index.
    fn column(&self, j: usize) -> (usize, &[f64]) {
        let (lo, hi) = (j.saturating_sub(self.ku), (j + self.kl).min(self.n - 1));
        let start = self.ku + lo - j + j * self.ld();
        (lo, &self.data[start..start + hi + 1 - lo])
    }

    /// `y += A x`.
    pub fn mul_add(&self, x: &[f64], y: &mut [f64]) {
        for (j, &xj) in x.iter().enumerate().take(self.n) {
            if xj != 0.0 {
                let (lo, col) = self.column(j);
                for (yi, &a) in y[lo..].iter_mut().zip(col) {
                    *yi += a * xj;
                }
            }
        }
    }
}

/// LU factorisation with partial pivoting of a [`Band`] (`P A = L U`, `L` unit lower
/// with `kl` subdiagonals, `U` upper with `kl + ku` superdiagonals).
///
/// Hand-written: faer has no band LU, and its sparse LU's symbolic analysis and
/// supernode bookkeeping are built for general patterns. On the block-tridiagonal
/// Jacobian of a 40-mass chain at N = 11 (920 unknowns, `kl = ku = 45`) it factorises
/// in 1.74 ms against the dense LU's 24.4 ms; [`crate::linalg::BorderedLu`] has the
/// other sizes measured and the choice between the two.
#[derive(Debug, Clone)]
pub struct BandLu {
    n: usize,
    kl: usize,
    ku: usize,
    /// `2kl + ku + 1` stored diagonals per column: `U` on and above, `L`'s
    /// multipliers below (entry `(i, j)` at `kl + ku + i − j + j·ld`).
    ab: Vec<f64>,
    piv: Vec<usize>,
}

impl BandLu {
    /// A workspace for band matrices of dimension `n` and bandwidths `kl`, `ku`.
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let (kl, ku) = (kl.min(n.saturating_sub(1)), ku.min(n.saturating_sub(1)));
        BandLu { n, kl, ku, ab: vec![0.0; n * (2 * kl + ku + 1)], piv: vec![0; n] }
    }

    fn ld(&self) -> usize {
        2 * self.kl + self.ku + 1
    }

    /// Factorise `a` (a workspace made for another shape is resized). Returns the
    /// ratio of the smallest to the largest pivot magnitude (0 if a pivot is exactly
    /// zero: the factors do not solve then; NaN if the matrix holds NaN).
    pub fn factor(&mut self, a: &Band) -> f64 {
        if (a.n, a.kl, a.ku) != (self.n, self.kl, self.ku) {
            *self = BandLu::new(a.n, a.kl, a.ku);
        }
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let ld = self.ld();
        let kv = kl + ku;
        // copy, with the kl fill-in diagonals above U's own zeroed
        for j in 0..n {
            let dst = &mut self.ab[j * ld..(j + 1) * ld];
            dst[..kl].fill(0.0);
            dst[kl..].copy_from_slice(&a.data[j * a.ld()..(j + 1) * a.ld()]);
        }
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        // the last column the row swaps and updates so far reach
        let mut ju = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let base = kv + j * ld;
            let mut p = 0;
            let mut best = self.ab[base].abs();
            for i in 1..=km {
                let v = self.ab[base + i].abs();
                if v > best || v.is_nan() {
                    best = v;
                    p = i;
                }
            }
            if best.is_nan() {
                return f64::NAN;
            }
            self.piv[j] = j + p;
            lo = lo.min(best);
            hi = hi.max(best);
            if best == 0.0 {
                continue;
            }
            ju = ju.max((j + ku + p).min(n - 1));
            if p != 0 {
                // rows j and j + p, columns j..=ju: stride ld − 1 along a row
                for c in j..=ju {
                    let r = kv + j - c + c * ld;
                    self.ab.swap(r, r + p);
                }
            }
            let inv = 1.0 / self.ab[base];
            for v in &mut self.ab[base + 1..=base + km] {
                *v *= inv;
            }
            for c in j + 1..=ju {
                let top = kv + j - c + c * ld;
                let x = self.ab[top];
                if x != 0.0 && km > 0 {
                    let (head, tail) = self.ab.split_at_mut(top + 1);
                    let l = &head[base + 1..=base + km];
                    for (t, &m) in tail[..km].iter_mut().zip(l) {
                        *t -= m * x;
                    }
                }
            }
        }
        if hi == 0.0 {
            0.0
        } else {
            lo / hi
        }
    }

    /// Solve `A x = b` in place with the factors of [`BandLu::factor`].
    pub fn solve(&self, b: &mut [f64]) {
        let (n, kl) = (self.n, self.kl);
        let ld = self.ld();
        let kv = kl + self.ku;
        for j in 0..n {
            let p = self.piv[j];
            if p != j {
                b.swap(j, p);
            }
            let km = kl.min(n - 1 - j);
            let bj = b[j];
            if bj != 0.0 {
                let l = &self.ab[kv + 1 + j * ld..=kv + km + j * ld];
                for (x, &m) in b[j + 1..=j + km].iter_mut().zip(l) {
                    *x -= m * bj;
                }
            }
        }
        for j in (0..n).rev() {
            b[j] /= self.ab[kv + j * ld];
            let bj = b[j];
            let lo = j.saturating_sub(kv);
            if bj != 0.0 && lo < j {
                let u = &self.ab[kv + lo - j + j * ld..kv + j * ld];
                for (x, &v) in b[lo..j].iter_mut().zip(u) {
                    *x -= v * bj;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tests::xorshift;
    use crate::linalg::DenseLu;

    /// A random band matrix whose diagonal is small (with an upper band: without one,
    /// pivoting would make the factors as ill-conditioned as a lower triangle with
    /// 1/100 on its diagonal is), so that pivoting swaps rows.
    fn random_band(n: usize, kl: usize, ku: usize, seed: &mut u64) -> Band {
        let mut a = Band::new(n, kl, ku);
        for j in 0..n {
            let lo = j.saturating_sub(ku);
            let hi = (j + kl).min(n - 1);
            let seg = a.segment(j, lo, hi + 1 - lo).unwrap();
            for (k, v) in seg.iter_mut().enumerate() {
                *v = xorshift(seed) * if lo + k == j && ku > 0 { 0.01 } else { 1.0 };
            }
        }
        a
    }

    #[test]
    fn band_lu_matches_the_dense_solution() {
        let mut seed = 0x1234_5678_9abc_def1_u64;
        for &(n, kl, ku) in &[(1, 0, 0), (7, 0, 0), (9, 2, 1), (30, 5, 7), (46, 45, 45), (60, 3, 0)]
        {
            let a = random_band(n, kl, ku, &mut seed);
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() + 0.1).collect();
            let mut lu = BandLu::new(n, kl, ku);
            let ratio = lu.factor(&a);
            assert!(ratio > 0.0, "n {n}: singular test matrix");
            if n > 1 && kl > 0 {
                assert!(lu.piv.iter().enumerate().any(|(i, &p)| p != i), "n {n}: no pivoting");
            }
            let mut x = b.clone();
            lu.solve(&mut x);
            // the residual of the band product, and the dense LU's solution
            let mut r = vec![0.0; n];
            a.mul_add(&x, &mut r);
            let mut dense = DenseLu::new(n);
            {
                let mut m = dense.matrix_mut();
                for j in 0..n {
                    for i in 0..n {
                        m[(i, j)] = a.get(i, j);
                    }
                }
            }
            assert!(dense.factor() > 0.0);
            let mut y = b.clone();
            dense.solve(&mut y);
            let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                assert!((r[i] - b[i]).abs() < 1e-11 * scale, "n {n} row {i}: {} vs {}", r[i], b[i]);
                assert!((x[i] - y[i]).abs() < 1e-9 * scale, "n {n} x{i}: {} vs {}", x[i], y[i]);
            }
        }
    }

    #[test]
    fn a_zero_pivot_is_reported() {
        // a zero column: the ratio is 0
        let mut a = Band::new(4, 1, 1);
        for j in [0, 1, 3] {
            a.segment(j, j, 1).unwrap()[0] = 1.0;
        }
        assert_eq!(BandLu::new(4, 1, 1).factor(&a), 0.0);
        a.segment(2, 2, 1).unwrap()[0] = f64::NAN;
        assert!(BandLu::new(4, 1, 1).factor(&a).is_nan());
    }

    #[test]
    fn segments_outside_the_band_are_refused() {
        let mut a = Band::new(10, 2, 3);
        assert!(a.segment(5, 2, 6).is_some()); // rows 2..=7 of column 5: 5−3 ..= 5+2
        assert!(a.segment(5, 1, 3).is_none());
        assert!(a.segment(5, 3, 6).is_none());
        assert!(a.segment(9, 8, 3).is_none()); // past the last row
        a.segment(4, 6, 1).unwrap()[0] = 2.5;
        assert_eq!(a.get(6, 4), 2.5);
        assert_eq!(a.get(7, 4), 0.0);
    }
}
