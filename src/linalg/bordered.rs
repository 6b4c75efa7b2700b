//! Bordered systems `K = [A B; C D]`: a Jacobian `A` with `k` extra rows and columns
//! (continuation's parameter and arc-length condition), factorised densely or, when
//! `A` is banded enough to pay, by block elimination around a [`BandLu`].
//!
//! Block elimination alone is unstable when `A` is nearly singular (at a fold in Ω,
//! where `K` itself is fine); one step of iterative refinement with `K`'s own
//! residual makes it stable (Govaerts & Pryce 1993), and below a pivot ratio of
//! [`DENSE_BELOW`] the system is factorised densely instead.

use super::banded::{Band, BandLu};
use super::DenseLu;
use faer::prelude::ReborrowMut;
use faer::MatMut;

/// `A`'s pivot ratio below which a banded [`BorderedLu`] factorises the whole of `K`
/// densely (block elimination's error grows with `A`'s condition number; one
/// refinement step recovers full accuracy while that is far below `1/ε`).
pub const DENSE_BELOW: f64 = 1e-9;

/// Where a Jacobian is assembled: column segments, contiguous, or `None` where the
/// target stores nothing (outside a band).
pub trait Columns {
    /// Rows `row0..row0 + len` of column `col`.
    fn segment(&mut self, col: usize, row0: usize, len: usize) -> Option<&mut [f64]>;
    /// Set every stored entry to 0.
    fn clear(&mut self);
}

impl Columns for Band {
    fn segment(&mut self, col: usize, row0: usize, len: usize) -> Option<&mut [f64]> {
        Band::segment(self, col, row0, len)
    }
    fn clear(&mut self) {
        Band::clear(self)
    }
}

impl Columns for MatMut<'_, f64> {
    fn segment(&mut self, col: usize, row0: usize, len: usize) -> Option<&mut [f64]> {
        if col >= self.ncols() || row0 + len > self.nrows() {
            return None;
        }
        let c = self.rb_mut().col_mut(col).subrows_mut(row0, len);
        c.try_as_col_major_mut().map(|c| c.as_slice_mut())
    }
    fn clear(&mut self) {
        self.fill(0.0)
    }
}

/// The `A` block of a [`BorderedLu`], to assemble into.
pub enum BlockA<'a> {
    /// Dense storage (a view of `K`'s leading block).
    Dense(MatMut<'a, f64>),
    /// Band storage.
    Band(&'a mut Band),
}

impl Columns for BlockA<'_> {
    fn segment(&mut self, col: usize, row0: usize, len: usize) -> Option<&mut [f64]> {
        match self {
            BlockA::Dense(m) => m.segment(col, row0, len),
            BlockA::Band(b) => b.segment(col, row0, len),
        }
    }
    fn clear(&mut self) {
        match self {
            BlockA::Dense(m) => m.clear(),
            BlockA::Band(b) => b.clear(),
        }
    }
}

impl BlockA<'_> {
    /// Multiply every entry by `s`.
    pub fn scale(&mut self, s: f64) {
        match self {
            BlockA::Dense(m) => {
                for j in 0..m.ncols() {
                    for i in 0..m.nrows() {
                        m[(i, j)] *= s;
                    }
                }
            }
            BlockA::Band(b) => b.scale(s),
        }
    }
}

/// Whether band storage with `kl`, `ku` pays for an `na × na` block with `k`
/// borders: its LU's flops, `2·na·kl·(kl + ku)`, times the dense kernel's advantage
/// per flop, against the dense `⅔(na + k)³`.
fn band_pays(na: usize, k: usize, kl: usize, ku: usize) -> bool {
    // faer's blocked dense LU does 2.8–5× more flops per second than the band loop
    // at these sizes (measured: see `BorderedLu`).
    const DENSE_ADVANTAGE: f64 = 4.0;
    let band = 2.0 * na as f64 * kl as f64 * (kl + ku) as f64;
    let dense = 2.0 / 3.0 * ((na + k) as f64).powi(3);
    DENSE_ADVANTAGE * band < dense
}

/// LU of a bordered matrix `K = [A B; C D]` (`A` is `na × na`, `D` is `k × k`),
/// solved for many right-hand sides. With a band given and narrow enough, `A` is
/// stored and factorised as a band and `K` solved by block elimination and one step
/// of iterative refinement; otherwise `K` is one [`DenseLu`].
///
/// Measured (release, the `bordered_lu` group of `cargo bench --bench stability`:
/// fill and factorise a block-tridiagonal `A` with one border): `na` = 920 with
/// `kl = ku = 45` (a 40-mass chain at N = 11) 1.74 ms banded against 24.4 ms dense;
/// `na` = 460, 0.75 against 3.39 ms; `na` = 230, 0.38 against 0.53 ms; `na` = 110
/// with `kl = ku = 21`, 73 against 121 µs. Per flop the dense kernel is 2.8× (at
/// 110) to 5× (at 920) faster, hence the factor 4 in the choice: every case above
/// takes the band, and a 5-mass chain at N = 11 (`na` = 115, `kl` = 45) stays dense.
///
/// ```
/// use ihbm::linalg::{BorderedLu, Columns};
/// // A = tridiag(-1, 2, -1) (4 × 4), bordered by B = 1, C = 1, D = 0
/// let mut lu = BorderedLu::new(4, 1, Some((1, 1)));
/// {
///     let mut a = lu.a_mut();
///     for j in 0..4 {
///         a.segment(j, j, 1).unwrap()[0] = 2.0;
///         if j > 0 {
///             a.segment(j, j - 1, 1).unwrap()[0] = -1.0;
///             a.segment(j - 1, j, 1).unwrap()[0] = -1.0;
///         }
///     }
/// }
/// lu.set_border_column(0, &[1.0; 4]);
/// lu.set_border_row(0, &[1.0; 4]);
/// lu.set_corner(0, 0, 0.0);
/// assert!(lu.factor() > 0.0);
/// let mut x = vec![0.0, 0.0, 0.0, 0.0, 1.0];
/// lu.solve(&mut x);
/// // the unknowns sum to 1 (the border row) and A x + y·1 = 0
/// assert!((x[..4].iter().sum::<f64>() - 1.0).abs() < 1e-14);
/// assert!((2.0 * x[0] - x[1] + x[4]).abs() < 1e-14);
/// ```
#[derive(Debug)]
pub struct BorderedLu {
    na: usize,
    k: usize,
    kind: Kind,
}

#[derive(Debug)]
enum Kind {
    Dense(DenseLu),
    Banded(Box<Banded>),
}

#[derive(Debug)]
struct Banded {
    a: Band,
    lu: BandLu,
    /// `B`, column-major (`na × k`)
    b: Vec<f64>,
    /// `C`, row-major (`k × na`)
    c: Vec<f64>,
    /// `D`, row-major
    d: Vec<f64>,
    /// `A⁻¹ B`, column-major
    v: Vec<f64>,
    schur: DenseLu,
    /// `K` densely, when `A` is too near singular for block elimination
    dense: Option<DenseLu>,
    use_dense: bool,
    rhs: Vec<f64>,
    res: Vec<f64>,
}

impl BorderedLu {
    /// A workspace for `A` of size `na` with `k` borders; `band` (`kl`, `ku`): `A`'s
    /// bandwidths, if it is known to be banded.
    pub fn new(na: usize, k: usize, band: Option<(usize, usize)>) -> Self {
        let kind = match band {
            Some((kl, ku)) if band_pays(na, k, kl, ku) => Kind::Banded(Box::new(Banded {
                a: Band::new(na, kl, ku),
                lu: BandLu::new(na, kl, ku),
                b: vec![0.0; na * k],
                c: vec![0.0; na * k],
                d: vec![0.0; k * k],
                v: vec![0.0; na * k],
                schur: DenseLu::new(k),
                dense: None,
                use_dense: false,
                rhs: vec![0.0; na + k],
                res: vec![0.0; na + k],
            })),
            _ => Kind::Dense(DenseLu::new(na + k)),
        };
        BorderedLu { na, k, kind }
    }

    /// Whether `A` is stored as a band.
    pub fn is_banded(&self) -> bool {
        matches!(self.kind, Kind::Banded(_))
    }

    /// The dimension of `K`.
    pub fn dim(&self) -> usize {
        self.na + self.k
    }

    /// Store `A` densely from now on (a Jacobian that turned out wider than its band).
    pub fn make_dense(&mut self) {
        if self.is_banded() {
            self.kind = Kind::Dense(DenseLu::new(self.na + self.k));
        }
    }

    /// The `A` block, to fill before [`BorderedLu::factor`].
    pub fn a_mut(&mut self) -> BlockA<'_> {
        match &mut self.kind {
            Kind::Dense(lu) => BlockA::Dense(lu.matrix_mut().submatrix_mut(0, 0, self.na, self.na)),
            Kind::Banded(b) => BlockA::Band(&mut b.a),
        }
    }

    /// Set border column `j` of `B` (length `na`).
    pub fn set_border_column(&mut self, j: usize, values: &[f64]) {
        let na = self.na;
        match &mut self.kind {
            Kind::Dense(lu) => {
                let mut m = lu.matrix_mut();
                for (i, &v) in values.iter().enumerate().take(na) {
                    m[(i, na + j)] = v;
                }
            }
            Kind::Banded(b) => b.b[j * na..(j + 1) * na].copy_from_slice(&values[..na]),
        }
    }

    /// Set border row `i` of `C` (length `na`).
    pub fn set_border_row(&mut self, i: usize, values: &[f64]) {
        let na = self.na;
        match &mut self.kind {
            Kind::Dense(lu) => {
                let mut m = lu.matrix_mut();
                for (j, &v) in values.iter().enumerate().take(na) {
                    m[(na + i, j)] = v;
                }
            }
            Kind::Banded(b) => b.c[i * na..(i + 1) * na].copy_from_slice(&values[..na]),
        }
    }

    /// Set entry `(i, j)` of `D`.
    pub fn set_corner(&mut self, i: usize, j: usize, value: f64) {
        let (na, k) = (self.na, self.k);
        match &mut self.kind {
            Kind::Dense(lu) => lu.matrix_mut()[(na + i, na + j)] = value,
            Kind::Banded(b) => b.d[i * k + j] = value,
        }
    }

    /// Factorise `K`. Returns a pivot ratio: dense, that of [`DenseLu::factor`];
    /// banded, the smallest pivot of the Schur complement `D − C A⁻¹ B` relative to
    /// the size of the terms it is the difference of (0 for a singular `K`, NaN if
    /// it holds NaN).
    pub fn factor(&mut self) -> f64 {
        let (na, k) = (self.na, self.k);
        let bd = match &mut self.kind {
            Kind::Dense(lu) => return lu.factor(),
            Kind::Banded(b) => b,
        };
        let ratio_a = bd.lu.factor(&bd.a);
        bd.use_dense = ratio_a.is_nan() || ratio_a < DENSE_BELOW;
        if ratio_a.is_nan() {
            return f64::NAN;
        }
        if bd.use_dense {
            let dense = bd.dense.get_or_insert_with(|| DenseLu::new(na + k));
            let mut m = dense.matrix_mut();
            for j in 0..na {
                for i in 0..na {
                    m[(i, j)] = bd.a.get(i, j);
                }
            }
            for l in 0..k {
                for i in 0..na {
                    m[(i, na + l)] = bd.b[l * na + i];
                    m[(na + l, i)] = bd.c[l * na + i];
                }
                for j in 0..k {
                    m[(na + l, na + j)] = bd.d[l * k + j];
                }
            }
            return dense.factor();
        }
        if k == 0 {
            return ratio_a;
        }
        bd.v.copy_from_slice(&bd.b);
        for col in bd.v.chunks_exact_mut(na.max(1)).take(k) {
            bd.lu.solve(col);
        }
        let mut scale = 0.0f64;
        {
            let mut s = bd.schur.matrix_mut();
            for i in 0..k {
                for j in 0..k {
                    let c = &bd.c[i * na..(i + 1) * na];
                    let v = &bd.v[j * na..(j + 1) * na];
                    let (mut dot, mut size) = (0.0, bd.d[i * k + j].abs());
                    for (x, y) in c.iter().zip(v) {
                        dot += x * y;
                        size += (x * y).abs();
                    }
                    s[(i, j)] = bd.d[i * k + j] - dot;
                    scale = scale.max(size);
                }
            }
        }
        bd.schur.factor();
        let m = bd.schur.matrix_mut();
        let smallest = (0..k).fold(f64::INFINITY, |lo, i| lo.min(m[(i, i)].abs()));
        if smallest.is_nan() || scale.is_nan() {
            f64::NAN
        } else if scale == 0.0 {
            0.0
        } else {
            smallest / scale
        }
    }

    /// Solve `K x = b` in place with the factors of [`BorderedLu::factor`].
    pub fn solve(&mut self, x: &mut [f64]) {
        let bd = match &mut self.kind {
            Kind::Dense(lu) => return lu.solve(x),
            Kind::Banded(b) => b,
        };
        if bd.use_dense {
            if let Some(d) = bd.dense.as_mut() {
                d.solve(x);
            }
            return;
        }
        let n = self.na + self.k;
        bd.rhs[..n].copy_from_slice(&x[..n]);
        bd.eliminate(self.na, self.k, x);
        // one step of refinement: r = b − K x, x += K⁻¹ r (by elimination again)
        bd.res[..n].copy_from_slice(&bd.rhs[..n]);
        bd.residual(self.na, self.k, x);
        let mut r = std::mem::take(&mut bd.res);
        bd.eliminate(self.na, self.k, &mut r);
        for (xi, ri) in x.iter_mut().zip(&r) {
            *xi += ri;
        }
        bd.res = r;
    }
}

impl Banded {
    /// Block elimination: `x₀ = A⁻¹f`, `y = S⁻¹(g − C x₀)`, `x = x₀ − A⁻¹B y`.
    fn eliminate(&mut self, na: usize, k: usize, x: &mut [f64]) {
        let (f, g) = x.split_at_mut(na);
        self.lu.solve(f);
        for (i, gi) in g.iter_mut().enumerate().take(k) {
            *gi -=
                self.c[i * na..(i + 1) * na].iter().zip(f.iter()).map(|(c, x)| c * x).sum::<f64>();
        }
        if k == 0 {
            return;
        }
        self.schur.solve(&mut g[..k]);
        for (j, &yj) in g.iter().enumerate().take(k) {
            for (fi, &v) in f.iter_mut().zip(&self.v[j * na..(j + 1) * na]) {
                *fi -= v * yj;
            }
        }
    }

    /// `self.res −= K x` (`self.res` holds `b` on entry).
    fn residual(&mut self, na: usize, k: usize, x: &[f64]) {
        let (xa, xb) = x.split_at(na);
        let (ra, rb) = self.res.split_at_mut(na);
        for v in ra.iter_mut() {
            *v = -*v;
        }
        self.a.mul_add(xa, ra);
        for (j, &y) in xb.iter().enumerate().take(k) {
            for (r, &b) in ra.iter_mut().zip(&self.b[j * na..(j + 1) * na]) {
                *r += b * y;
            }
        }
        for v in ra.iter_mut() {
            *v = -*v;
        }
        for i in 0..k {
            let cx: f64 = self.c[i * na..(i + 1) * na].iter().zip(xa).map(|(c, x)| c * x).sum();
            let dy: f64 = (0..k).map(|j| self.d[i * k + j] * xb[j]).sum();
            rb[i] -= cx + dy;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tests::xorshift;

    /// `K` with a block-tridiagonal `A` (blocks of `l`, `nb` of them) and `k` dense
    /// borders, filled into a banded and a dense workspace alike; with `shift`, `A`
    /// is made singular (null vector `(1, …, 1)`, a fold's Jacobian) and then moved
    /// by `shift · I`, while `K` stays regular.
    fn pair(
        nb: usize,
        l: usize,
        k: usize,
        shift: Option<f64>,
        seed: &mut u64,
    ) -> (BorderedLu, BorderedLu, Vec<Vec<f64>>) {
        let na = nb * l;
        let band = (2 * l - 1, 2 * l - 1);
        let mut full = vec![vec![0.0; na + k]; na + k];
        for (i, row) in full.iter_mut().enumerate().take(na) {
            for (j, v) in row.iter_mut().enumerate().take(na) {
                if (i / l).abs_diff(j / l) <= 1 {
                    *v = xorshift(seed);
                }
            }
        }
        if let Some(shift) = shift {
            for (i, row) in full.iter_mut().enumerate().take(na) {
                let off: f64 = (0..na).filter(|&j| j != i).map(|j| row[j]).sum();
                row[i] = shift - off;
            }
        }
        for i in 0..na {
            for l in 0..k {
                full[i][na + l] = xorshift(seed);
                full[na + l][i] = xorshift(seed) + 1.0;
            }
        }
        for i in 0..k {
            for j in 0..k {
                full[na + i][na + j] = xorshift(seed);
            }
        }
        let mut banded = BorderedLu::new(na, k, Some(band));
        let mut dense = BorderedLu::new(na, k, None);
        for lu in [&mut banded, &mut dense] {
            {
                let mut a = lu.a_mut();
                a.clear();
                for j in 0..na {
                    let lo = (j / l).saturating_sub(1) * l;
                    let hi = ((j / l + 2) * l).min(na);
                    let seg = a.segment(j, lo, hi - lo).expect("inside the band");
                    for (t, v) in seg.iter_mut().enumerate() {
                        *v = full[lo + t][j];
                    }
                }
            }
            for l in 0..k {
                let col: Vec<f64> = (0..na).map(|i| full[i][na + l]).collect();
                lu.set_border_column(l, &col);
                lu.set_border_row(l, &full[na + l][..na]);
                for j in 0..k {
                    lu.set_corner(l, j, full[na + l][na + j]);
                }
            }
        }
        (banded, dense, full)
    }

    #[test]
    fn banded_elimination_matches_the_dense_lu() {
        let mut seed = 0x0bad_cafe_1234_5678_u64;
        // (blocks, block size, borders, shift of a singular A, dense path expected)
        let cases = [
            (40, 5, 1, None, false),
            (40, 5, 2, None, false),
            (30, 7, 0, None, false),
            (40, 5, 1, Some(0.0), true),
            (40, 5, 1, Some(1e-6), false),
        ];
        for (nb, l, k, shift, dense_path) in cases {
            let case = format!("{nb} blocks of {l}, {k} borders, shift {shift:?}");
            let (mut banded, mut dense, full) = pair(nb, l, k, shift, &mut seed);
            assert!(banded.is_banded() && !dense.is_banded(), "{case}");
            let n = banded.dim();
            assert!(banded.factor() > 1e-12, "{case}");
            assert!(dense.factor() > 1e-12, "{case}");
            let Kind::Banded(b) = &banded.kind else { unreachable!() };
            assert_eq!(b.use_dense, dense_path, "{case}: which path");
            let rhs: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos()).collect();
            let (mut x, mut y) = (rhs.clone(), rhs.clone());
            banded.solve(&mut x);
            dense.solve(&mut y);
            let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                let r: f64 = (0..n).map(|j| full[i][j] * x[j]).sum::<f64>() - rhs[i];
                assert!(r.abs() < 1e-11 * scale, "{case}: row {i} residual {r}");
                assert!((x[i] - y[i]).abs() < 1e-10 * scale, "{case}: x{i} {} vs {}", x[i], y[i]);
            }
        }
    }

    #[test]
    fn a_narrow_problem_stays_dense() {
        // 22 unknowns in two blocks (the quarter car at N = 5): the band would be all
        assert!(!BorderedLu::new(22, 1, Some((21, 21))).is_banded());
        assert!(BorderedLu::new(920, 1, Some((45, 45))).is_banded());
    }
}
