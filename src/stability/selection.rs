//! One copy of each exponent: the eigenvalues whose eigenvectors are centred in
//! harmonic index (book, chapter *Continuation*, *Which copy*).

use super::*;

impl Hill {
    /// Keep `count` of the eigenvalues in `self.cands`, one per Floquet exponent: the
    /// copies whose eigenvectors are centred in harmonic index (book, *Continuation*,
    /// *Which copy*), smallest rank ([`Spread::key`]) first; among near-equal ranks the larger
    /// real part first, so that a growing exponent is never the one left out. Values
    /// equal modulo `iΩ` are the same exponent (at `|Im λ| = Ω/2`, period doubling,
    /// `λ` and `conj λ = λ - iΩ` both appear): one is kept. Sets `self.centres`.
    pub(super) fn select_centred(
        &mut self,
        params: &[f64],
        omega: f64,
        count: usize,
        known: Option<&[Spread]>,
    ) {
        let tie = 1e-12 * omega;
        let all = std::mem::take(&mut self.cands);
        let mut scored: Vec<(Complex64, Spread)> = Vec::with_capacity(all.len());
        for (idx, &l) in all.iter().enumerate() {
            if l.im < -tie {
                continue; // the conjugate's eigenvector is the conjugate: centre negated
            }
            let c = match known.and_then(|k| k.get(idx)) {
                Some(&c) => c,
                None => self.spread_at(params, omega, l),
            };
            scored.push((l, c));
            if l.im > tie {
                scored.push((l.conj(), Spread { centre: -c.centre, spread: c.spread }));
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
        self.cands.clear();
        self.centres.clear();
        self.spare.clear();
        for &(z, c) in &scored {
            let same = self.cands.iter().any(|&k| {
                let d = fold_into_strip(z - k, omega);
                d.re.abs() <= same_tie && d.im.abs() <= same_tie
            });
            if same {
                continue;
            }
            if self.cands.len() == count {
                // One per conjugate pair, as the refinement takes them.
                if z.im >= -tie && self.spare.len() < SPARE_TRIES {
                    self.spare.push(z);
                }
                continue;
            }
            self.cands.push(z);
            self.centres.push(c);
        }
    }

    /// [`Spread`] of the eigenvector of the polynomial `T` at its eigenvalue `l` (one
    /// step of inverse iteration; infinite if that fails).
    pub(super) fn spread_at(&mut self, params: &[f64], omega: f64, l: Complex64) -> Spread {
        // An exactly singular factorisation: step off the eigenvalue a little.
        let v = self
            .start_vector(params, omega, l, false)
            .or_else(|| self.start_vector(params, omega, l + 1e-10 * omega.max(l.norm()), false));
        v.map_or(Spread { centre: f64::INFINITY, spread: f64::INFINITY }, |v| {
            spread(&v, self.ndof, self.harmonics)
        })
    }
}

/// Ranks closer than this are ties in the selection.
pub(super) const RANK_TIE: f64 = 1e-6;

/// Spare candidates tried when two kept ones refine to the same root.
pub(super) const SPARE_TRIES: usize = 4;

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
