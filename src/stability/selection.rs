//! One copy of each exponent: the eigenvalues whose eigenvectors are centred in
//! harmonic index (book, chapter *Continuation*, *Which copy*).

use super::*;

/// The full analysis's eigenvalues, the ones it keeps and what it keeps them by.
pub(super) struct Selection {
    /// All eigenvalues, then the kept ones (`count`, conjugates included).
    pub(super) cands: Vec<Complex64>,
    /// [`Spread`] of each kept candidate's eigenvector (see [`Hill::select_centred`]).
    pub(super) centres: Vec<Spread>,
    /// The best-ranked eigenvalues the selection left out (not copies of kept ones, at
    /// most `SPARE_TRIES`): replacements when two kept candidates refine to one root.
    pub(super) spare: Vec<Complex64>,
    /// For fractional models, the frozen eigenvector (first companion block) of each
    /// eigenvalue in `cands` before the selection, `m` entries each: the selection's
    /// copy test ([`Hill::select_centred`]).
    pub(super) cand_vectors: Vec<Complex64>,
    /// Where each kept candidate, then each spare, came from: its index among all
    /// eigenvalues and whether it is that one's conjugate (its frozen eigenvector in
    /// `cand_vectors`, see [`Selection::frozen_vector`]).
    sources: Vec<(usize, bool)>,
    /// The last full analysis replaced a candidate by a spare (its selection was not
    /// clean: tracking does not start from it).
    pub(super) replaced: bool,
    /// Exponents of the last full analysis, one per conjugate pair, not folded: the
    /// selected eigenvalues (integer orders) or their refined roots (fractional).
    pub(super) raw: Vec<Complex64>,
    /// Indices in `raw` of the candidates that did not refine (their frozen values).
    pub(super) unrefined: Vec<usize>,
}

impl Selection {
    /// Every exponent the last analysis saw: refined roots, kept candidates, spares
    /// (what places the counting contour, `count`).
    pub(super) fn found(&self) -> Vec<Complex64> {
        self.raw.iter().chain(&self.cands).chain(&self.spare).copied().collect()
    }

    /// The frozen eigenvector (unit norm) of kept candidate `i`, or of spare
    /// `i - count` beyond the kept ones, if the eigensolve gave the vectors (the
    /// companion's, not the pencil's).
    pub(super) fn frozen_vector(&self, i: usize, m: usize) -> Option<Vec<Complex64>> {
        let &(idx, conj) = self.sources.get(i)?;
        let v = self.cand_vectors.get(idx * m..(idx + 1) * m)?;
        let mut v: Vec<Complex64> = v.iter().map(|&z| if conj { z.conj() } else { z }).collect();
        super::refinement::normalise(&mut v)?;
        Some(v)
    }

    /// For `big` eigenvalues.
    pub(super) fn new(big: usize) -> Selection {
        Selection {
            cands: Vec::with_capacity(big),
            centres: Vec::with_capacity(big),
            spare: Vec::with_capacity(big),
            cand_vectors: Vec::new(),
            sources: Vec::with_capacity(big),
            replaced: false,
            raw: Vec::with_capacity(big),
            unrefined: Vec::new(),
        }
    }
}

impl Hill {
    /// Keep `count` of the eigenvalues in `self.sel.cands`, one per Floquet exponent: the
    /// copies whose eigenvectors are centred in harmonic index (book, *Continuation*,
    /// *Which copy*), smallest rank ([`Spread::key`]) first; among near-equal ranks the larger
    /// real part first, so that a growing exponent is never the one left out. Values
    /// equal modulo `iΩ` are the same exponent (at `|Im λ| = Ω/2`, period doubling,
    /// `λ` and `conj λ = λ - iΩ` both appear): one is kept. Sets `self.sel.centres`.
    pub(super) fn select_centred(
        &mut self,
        params: &[f64],
        omega: f64,
        count: usize,
        known: Option<&[Spread]>,
    ) {
        let tie = 1e-12 * omega;
        let all = std::mem::take(&mut self.sel.cands);
        // (eigenvalue, spread, index in `all`, conjugated)
        let mut scored: Vec<(Complex64, Spread, usize, bool)> = Vec::with_capacity(all.len());
        for (idx, &l) in all.iter().enumerate() {
            if l.im < -tie {
                continue; // the conjugate's eigenvector is the conjugate: centre negated
            }
            let c = match known.and_then(|k| k.get(idx)) {
                Some(&c) => c,
                None => self.spread_at(params, omega, l),
            };
            scored.push((l, c, idx, false));
            if l.im > tie {
                scored.push((l.conj(), Spread { centre: -c.centre, spread: c.spread }, idx, true));
            }
        }
        scored.sort_by(|a, b| a.1.key().total_cmp(&b.1.key()));
        let mut start = 0;
        while start < scored.len() {
            let base = scored[start].1.key();
            let end =
                start + scored[start..].iter().take_while(|z| z.1.key() - base <= RANK_TIE).count();
            scored[start..end].sort_by(|a, b| b.0.re.total_cmp(&a.0.re));
            start = end;
        }
        let same_tie = 1e-6 * omega;
        self.sel.cands.clear();
        self.sel.centres.clear();
        self.sel.spare.clear();
        let vectors = std::mem::take(&mut self.sel.cand_vectors);
        let has_vectors = vectors.len() == all.len() * self.op.m;
        // The kept candidates' sources while the spares are chosen, then the spares'.
        self.sel.sources.clear();
        let mut spare_sources: Vec<(usize, bool)> = Vec::with_capacity(SPARE_TRIES);
        for &(z, c, idx, conj) in &scored {
            let same = self.sel.cands.iter().any(|&k| {
                let d = fold_into_strip(z - k, omega);
                d.re.abs() <= same_tie && d.im.abs() <= same_tie
            });
            if same {
                continue;
            }
            if self.sel.cands.len() == count {
                // One per conjugate pair, as the refinement takes them; not a copy of a
                // kept one, which would refine to the same root as it.
                if z.im >= -tie
                    && self.sel.spare.len() < SPARE_TRIES
                    && !(has_vectors && self.copies_kept(&vectors, z, idx, conj, omega))
                {
                    self.sel.spare.push(z);
                    spare_sources.push((idx, conj));
                }
                continue;
            }
            self.sel.cands.push(z);
            self.sel.centres.push(c);
            self.sel.sources.push((idx, conj));
        }
        self.sel.cand_vectors = vectors;
        self.sel.sources.extend(spare_sources);
    }

    /// Whether the frozen eigenvalue `z` (`all[idx]`, conjugated if `conj`) is a copy
    /// of a kept one (`self.sel.cands`, from `self.sel.sources`), off by more than rounding: the
    /// frozen fractional factors `(±ikΩ)^q` do not shift with `λ` as the true ones do,
    /// so copies of one exponent are not `iΩ` apart exactly (by up to 5e-3·Ω on the
    /// 5-mass chain at its resonance), but their eigenvectors still are the harmonic
    /// shifts of each other. Two distinct exponents about to collide look the same
    /// (the quarter car at 23.28 rad/s), so this only keeps copies out of the spares:
    /// a spare is used when two kept candidates refined to one root.
    fn copies_kept(
        &self,
        vectors: &[Complex64],
        z: Complex64,
        idx: usize,
        conj: bool,
        omega: f64,
    ) -> bool {
        let m = self.op.m;
        self.sel.cands.iter().zip(&self.sel.sources).any(|(&k, &(ik, ck))| {
            let (vk, vz) = (&vectors[ik * m..(ik + 1) * m], &vectors[idx * m..(idx + 1) * m]);
            let (ndof, nh) = (self.op.ndof, self.op.harmonics);
            copy_shift((k, vk, ck), (z, vz, conj), omega, ndof, nh).is_some_and(|j| j != 0)
        })
    }

    /// [`Spread`] of the eigenvector of the polynomial `T` at its eigenvalue `l` (one
    /// step of inverse iteration; infinite if that fails).
    pub(super) fn spread_at(&mut self, params: &[f64], omega: f64, l: Complex64) -> Spread {
        // An exactly singular factorisation: step off the eigenvalue a little.
        let v = self
            .start_vector(params, omega, l, false)
            .or_else(|| self.start_vector(params, omega, l + 1e-10 * omega.max(l.norm()), false));
        v.map_or(Spread { centre: f64::INFINITY, spread: f64::INFINITY }, |v| {
            spread(&v, self.op.ndof, self.op.harmonics)
        })
    }
}

/// Ranks closer than this are ties in the selection.
pub(super) const RANK_TIE: f64 = 1e-6;

/// Frozen eigenvalues this close to a kept one modulo `iΩ` (relative to Ω), with
/// eigenvectors [`COPY_OVERLAP`] alike after the harmonic shift, are its copies.
pub(super) const COPY_GAP: f64 = 0.05;

/// See [`COPY_GAP`]. Measured on the 5-mass chain (N = 5) over its whole curve: of the
/// 917 eigenvalues within `COPY_GAP` of a kept one and ranked among the `count` best,
/// 78 % overlap by 0.94 or more after the shift, the others by 0.12 or less.
pub(super) const COPY_OVERLAP: f64 = 0.9;

/// Spare candidates tried when two kept ones refine to the same root. Each costs one
/// refinement, a point with none left the count of its unstable roots (hundreds of
/// factorisations): on the 5-mass chain at N = 11 the points with an unrefined
/// exponent are 57 of 301 with 4 spares, 42 with 8, 16 with 16, and the curve with
/// 16 takes 0.85–0.9 of the time with 4 (on the 10-mass chain at N = 5: 254 → 215
/// of 753, the same time).
pub(super) const SPARE_TRIES: usize = 16;

/// Where the energy of a Hill eigenvector sits in harmonic index.
#[derive(Debug, Clone, Copy)]
pub(super) struct Spread {
    /// `Σ_k k |c_k|² / Σ_k |c_k|²`, `c_{±k} = (a_k ∓ i b_k)/2` the coefficients of
    /// `e^{±ikΩt}`, `k` over `-N..=N`. Shifting the eigenvalue by `ijΩ` shifts it by
    /// `-j`.
    pub(super) centre: f64,
    /// `Σ_k k² |c_k|² / Σ_k |c_k|²` = variance + centre²: among the copies of one
    /// exponent (same variance) smallest for the most centred one; unlike the centre,
    /// it also sees a mixture of far harmonics (`c_4` and `c_{-4}` in equal parts: a
    /// real eigenvalue always has centre 0) as off centre.
    pub(super) spread: f64,
}

impl Spread {
    /// The selection's ranking key: `|centre|`, plus the variance in excess of 1. A
    /// mode's copies differ only in the centre (same variance), so within one exponent
    /// this is `|centre|`; the excess only demotes eigenvectors spread over harmonics
    /// further apart than `±1` around their centre, such as the real eigenvalues of
    /// far copies merged by truncation (energy at `±4`: centre 0, variance 16), which
    /// the centre alone would take for centred. Variance up to 1 is not penalised: a
    /// real exponent near a fold at `N = 1` has its energy at `±1` (variance 1) and is
    /// the best representative there.
    pub(super) fn key(&self) -> f64 {
        let variance = self.spread - self.centre * self.centre;
        self.centre.abs() + (variance - 1.0).max(0.0)
    }
}

/// [`Spread`] of `v` (real basis `[a0, a_k, b_k]` per DOF, `ndof` blocks, `nh`
/// harmonics).
pub(super) fn spread(v: &[Complex64], ndof: usize, nh: usize) -> Spread {
    let len = 2 * nh + 1;
    let i1 = Complex64::new(0.0, 1.0);
    let (mut first, mut second, mut den) = (0.0, 0.0, 0.0);
    for d in 0..ndof {
        let b = &v[d * len..(d + 1) * len];
        den += b[0].norm_sqr();
        for k in 1..=nh {
            let plus = (b[k] - i1 * b[nh + k]).norm_sqr() / 4.0;
            let minus = (b[k] + i1 * b[nh + k]).norm_sqr() / 4.0;
            let k = k as f64;
            first += k * (plus - minus);
            second += k * k * (plus + minus);
            den += plus + minus;
        }
    }
    if den > 0.0 {
        Spread { centre: first / den, spread: second / den }
    } else {
        Spread { centre: f64::INFINITY, spread: f64::INFINITY }
    }
}

/// The shift `j` if `z = k + ijΩ` is a copy of `k`: within [`COPY_GAP`] of it modulo
/// `iΩ`, with eigenvectors [`COPY_OVERLAP`] alike after the harmonic shift. Each of
/// `k`, `z` comes with its eigenvector and whether that is to be conjugated.
pub(super) fn copy_shift(
    (k, vk, ck): (Complex64, &[Complex64], bool),
    (z, vz, cz): (Complex64, &[Complex64], bool),
    omega: f64,
    ndof: usize,
    nh: usize,
) -> Option<i64> {
    let d = z - k;
    let j = (d.im / omega).round() as i64;
    (fold_into_strip(d, omega).norm() <= COPY_GAP * omega
        && copy_overlap(vk, ck, vz, cz, j, ndof, nh) >= COPY_OVERLAP)
        .then_some(j)
}

/// `|⟨S_j a, b⟩| / (‖S_j a‖ ‖b‖)`, `S_j` the harmonic shift of
/// [`shift_harmonics`](super::tracking::shift_harmonics) from an eigenvector of `λ` to
/// one of its copy `λ + ijΩ`, `a` and `b` conjugated first if `ca`, `cb`: near 1 when
/// `b` is the eigenvector of a copy of `a`'s eigenvalue.
pub(super) fn copy_overlap(
    a: &[Complex64],
    ca: bool,
    b: &[Complex64],
    cb: bool,
    j: i64,
    ndof: usize,
    nh: usize,
) -> f64 {
    let cj = |z: Complex64, c: bool| if c { z.conj() } else { z };
    let mut s: Vec<Complex64> = a.iter().map(|&z| cj(z, ca)).collect();
    super::tracking::shift_harmonics(&mut s, ndof, nh, j);
    let (mut dot, mut ns, mut nb) = (Complex64::new(0.0, 0.0), 0.0, 0.0);
    for (x, &y) in s.iter().zip(b) {
        let y = cj(y, cb);
        dot += x.conj() * y;
        ns += x.norm_sqr();
        nb += y.norm_sqr();
    }
    let den = (ns * nb).sqrt();
    if den > 0.0 {
        dot.norm() / den
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stability::tracking::shift_harmonics;

    /// An eigenvector-like vector of 3 DOFs at N = 6 with its energy at harmonics
    /// `-2..=2` (none lost by a shift of up to 4).
    fn vector(seed: f64) -> Vec<Complex64> {
        let (ndof, nh) = (3, 6);
        let len = 2 * nh + 1;
        let mut v = vec![Complex64::new(0.0, 0.0); ndof * len];
        for d in 0..ndof {
            let b = &mut v[d * len..(d + 1) * len];
            let x = seed + d as f64;
            b[0] = Complex64::new(x.sin(), 0.3 * x.cos());
            for k in 1..=2 {
                b[k] = Complex64::new((x * k as f64).cos(), 0.2);
                b[nh + k] = Complex64::new(-0.5, (x + k as f64).sin());
            }
        }
        v
    }

    #[test]
    fn a_shifted_eigenvector_is_a_copy_and_its_conjugate_too() {
        let (ndof, nh) = (3, 6);
        let a = vector(0.4);
        for j in [-2i64, 1, 3] {
            let mut b = a.clone();
            shift_harmonics(&mut b, ndof, nh, j);
            // Scaled by a complex factor: an eigenvector is defined up to one.
            b.iter_mut().for_each(|z| *z *= Complex64::new(0.3, -1.7));
            let o = copy_overlap(&a, false, &b, false, j, ndof, nh);
            assert!((o - 1.0).abs() < 1e-12, "j = {j}: {o}");
            // The conjugates, as the selection scores them (the stored vectors with
            // the flag): conj(λ + ijΩ) is the copy of conj(λ) shifted by -j.
            let o = copy_overlap(&a, true, &b, true, -j, ndof, nh);
            assert!((o - 1.0).abs() < 1e-12, "conjugates, j = {j}: {o}");
        }
    }

    #[test]
    fn an_unshifted_or_unrelated_vector_is_no_copy() {
        let (ndof, nh) = (3, 6);
        let a = vector(0.4);
        let mut b = a.clone();
        shift_harmonics(&mut b, ndof, nh, 2);
        // The wrong shift: the energy lands two harmonics off.
        assert!(copy_overlap(&a, false, &b, false, 1, ndof, nh) < 0.9);
        let c = vector(2.9);
        let mut cs = c.clone();
        shift_harmonics(&mut cs, ndof, nh, 1);
        let o = copy_overlap(&a, false, &cs, false, 1, ndof, nh);
        assert!(o < 0.9, "{o}");
    }
}
