//! Continuing the exponents of one point to the next along a curve, and the rules
//! for when that cannot be trusted (book, *Tracking along a curve*).

use super::refinement::{may_witness, normalise, to_upper_half, OFF_CENTRE_MAX};
use super::*;

impl Hill {
    /// Tracking state from the last full analysis (`self.sel.raw`), if its selection is
    /// clean: every selected eigenvalue centred (`|centre| ≤ CENTRE_MAX`), `q_max·ndof`
    /// of them counted with conjugates, none replaced by a spare, and well separated
    /// from each other, their conjugates and copies. (How clearly the eigenvalues left
    /// out rank behind is not asked: near a half-integer `Im λ / Ω` two copies of one
    /// exponent rank alike, and tracking then continues whichever copy stays centred.)
    /// Otherwise no state (the next point is analysed in full too). The polynomial
    /// part of `T` is the one the full analysis left assembled (exact for fractional
    /// models: the state holds their refined roots).
    pub(super) fn start_state(&mut self, params: &[f64], omega: f64) {
        self.tr.state = None;
        let Some(sep) = self.clean_selection(omega) else { return };
        let raw = std::mem::take(&mut self.sel.raw);
        self.tr.state = self.state_from(params, omega, &raw, sep, None);
        self.sel.raw = raw;
    }

    /// Tracking state from a full analysis whose verdict did without some candidates
    /// (they did not refine: [`Floquet::refined`] is `false`): its refined roots, and
    /// what placed its counting contour. Along the low-Ω stretch of a chain, where the
    /// truncated problem spreads the eigenvectors of the fast modes over many harmonics,
    /// point after point has such candidates (on the 10-mass chain at N = 5, 215 of 753
    /// points); the next points then track the refined roots and count the rest
    /// ([`Hill::counted_on`]) rather than repeat the eigensolve. No state if two refined
    /// roots are not apart.
    pub(super) fn start_partial_state(&mut self, params: &[f64], omega: f64) {
        self.tr.state = None;
        let left = self.tr.partial_run;
        self.tr.partial_run = (2 * left).clamp(1, PARTIAL_POINTS);
        if left == 0 {
            return;
        }
        let refined: Vec<Complex64> = (0..self.sel.raw.len())
            .filter(|i| !self.sel.unrefined.contains(i))
            .map(|i| self.sel.raw[i])
            .collect();
        let sep = separations(&refined, omega);
        if sep.iter().any(|&s| s < MIN_SEPARATION * omega) {
            return;
        }
        let partial = Partial { hints: self.sel.found(), left };
        self.tr.state = self.state_from(params, omega, &refined, sep, Some(partial));
    }

    /// The state of the roots `raw` at this point with their eigenvectors, each from a
    /// start vector and Newton's method back to it; `None` if one does not return.
    fn state_from(
        &mut self,
        params: &[f64],
        omega: f64,
        raw: &[Complex64],
        sep: Vec<f64>,
        partial: Option<Partial>,
    ) -> Option<TrackState> {
        let exact = self.op.fractional;
        let mut lambdas = Vec::with_capacity(raw.len());
        let mut vectors = Vec::with_capacity(raw.len());
        for &l0 in raw {
            let v = self.start_vector(params, omega, l0, exact)?;
            match self.newton(params, omega, l0, v, 30, true, exact) {
                Some((l, v, _)) if (l - l0).norm() <= 1e-8 * omega.max(l0.norm()) => {
                    lambdas.push(l);
                    vectors.push(v);
                }
                _ => return None,
            }
        }
        Some(TrackState { omega, lambdas, vectors, sep, prev: None, partial })
    }

    /// The verdict at a point whose tracked set `f` holds only the roots that refined
    /// ([`Hill::start_partial_state`]): unstable if one of them is (a root of `T` right
    /// of the threshold, as the full analysis would find it), otherwise the number of
    /// roots of `det T` in the unstable half of the strip (`count`), its contour placed
    /// by the tracked roots and the `hints` of the last full analysis. `None` if the
    /// count is not resolved (the full analysis decides).
    pub(super) fn counted_on(
        &mut self,
        params: &[f64],
        omega: f64,
        opts: &StabilityOptions,
        mut f: Floquet,
        hints: &[Complex64],
    ) -> Option<Floquet> {
        f.refined = false;
        if !f.stable {
            return Some(f);
        }
        let known: Vec<Complex64> = f.exponents.iter().chain(hints).copied().collect();
        let n = self.count_unstable(params, omega, opts.tol, &known).ok()?;
        f.stable = n == 0;
        f.counted = true;
        Some(f)
    }

    /// The separations of the last full analysis's exponents if its selection is
    /// clean (see [`Hill::start_state`]).
    fn clean_selection(&self, omega: f64) -> Option<Vec<f64>> {
        let n_out: usize = self.sel.raw.iter().map(|&l| if real(l, omega) { 1 } else { 2 }).sum();
        if self.sel.raw.is_empty()
            || self.sel.replaced
            || n_out != self.central_count()
            || self.sel.centres.iter().any(|c| c.centre.abs() > CENTRE_MAX)
        {
            return None;
        }
        let sep = separations(&self.sel.raw, omega);
        sep.iter().all(|&s| s >= MIN_SEPARATION * omega).then_some(sep)
    }

    /// Whether the last full analysis (at the point of `st`) confirms the exponents
    /// of `st`: each is one of its exponents ([`same_exponent`]), no two the same one,
    /// and there are as many. (Its selection need not be clean as for a start: the
    /// exponents it kept are the tracked ones, which passed the tracking rules.)
    ///
    /// Integer orders only. A fractional `T(λ)` has no fixed number of roots on the
    /// principal sheet, and the full analysis keeps `q_max·ndof` of them: where a new
    /// root enters that set (the quarter car at Ω = 22.13 rad/s: −0.032 ± 0.755i, in
    /// place of the wheel mode at −19.6 ± 1.56i) no tracked exponent shows it:
    /// tracking on from confirmed sets disagreed there with the full analyses of
    /// `tests/stability` (the torus bubble, the 5-mass chain at Ω = 0.301).
    pub(super) fn confirms(&self, st: &TrackState, omega: f64) -> bool {
        if self.op.fractional || st.omega != omega || st.lambdas.len() != self.sel.raw.len() {
            return false;
        }
        let mut used = vec![false; self.sel.raw.len()];
        st.lambdas.iter().all(|&l| {
            let found = (0..self.sel.raw.len())
                .find(|&k| !used[k] && same_exponent(l, self.sel.raw[k], omega));
            found.map(|k| used[k] = true).is_some()
        })
    }

    /// Whether the exponents of `st` belong to as many families of copies as there are
    /// of them, each represented by a centred eigenvector: for integer orders then all
    /// of the `q_max·ndof` families (book, *Tracking along a curve*), whatever the
    /// correction rule doubted. No two of them (nor one and its own conjugate) within
    /// [`COPY_GAP`] modulo `iΩ` with eigenvectors [`COPY_OVERLAP`] alike after the
    /// harmonic shift, and every eigenvector ranked within [`CENTRE_MAX`]
    /// ([`Spread::key`]: a spurious eigenvalue of truncation, centre 0 with its energy
    /// at far harmonics, is not a representative).
    fn distinct_families(&self, st: &TrackState, omega: f64) -> bool {
        let (ndof, nh) = (self.op.ndof, self.op.harmonics);
        let n = st.lambdas.len();
        if st.vectors.iter().any(|v| spread(v, ndof, nh).key() > CENTRE_MAX) {
            return false;
        }
        let copies = |i: usize, k: usize, conj: bool| {
            let z = if conj { st.lambdas[k].conj() } else { st.lambdas[k] };
            let (first, second) =
                ((z, &st.vectors[k][..], conj), (st.lambdas[i], &st.vectors[i][..], false));
            copy_shift(first, second, omega, ndof, nh).is_some()
        };
        (0..n).all(|i| {
            let own = !real(st.lambdas[i], omega) && copies(i, i, true);
            !own && (i + 1..n).all(|k| !copies(i, k, false) && !copies(i, k, true))
        })
    }

    /// Continue `st` to the current point; `None` if a fallback rule fires. When only
    /// the correction rule fires (every exponent converged, each stays centred, real or
    /// complex as it was, and apart from the others), an integer-order set that
    /// [`Hill::distinct_families`] certifies is kept; otherwise the continued exponents
    /// are kept in `self.tr.unconfirmed` for the full analysis to confirm.
    pub(super) fn continue_state(
        &mut self,
        params: &[f64],
        omega: f64,
        opts: &StabilityOptions,
        st: TrackState,
    ) -> Option<Floquet> {
        // Integer orders: the polynomial; fractional: its integer part, the fractional
        // signals exact in `eval_t` (the tracked values are the refined roots).
        self.tr.unconfirmed = None;
        let exact = self.op.fractional;
        self.op.assemble_polynomial(params, omega, !exact);
        let predicted = st.predictions(omega);
        let mut lambdas = Vec::with_capacity(st.lambdas.len());
        let mut vectors = Vec::with_capacity(st.lambdas.len());
        let mut preds = Vec::with_capacity(st.lambdas.len());
        // The previous values, moved with the copy each exponent continues as.
        let mut before = st.lambdas.clone();
        // The correction rule fired for some exponent.
        let mut doubted = false;
        for (i, ((&l, v), &pred)) in st.lambdas.iter().zip(&st.vectors).zip(&predicted).enumerate()
        {
            let Continued { l: ln, v: vn, pred, moved, centre } =
                self.continue_one(params, omega, pred, v.clone())?;
            if centre.abs() > CENTRE_MAX {
                return None;
            }
            // A real exponent stays real, a complex one complex.
            if real(l, omega) != real(ln, omega) {
                return None;
            }
            // The iteration's correction, not the motion: an exponent that moves
            // steadily along the curve is predicted (the quarter car's body mode near
            // resonance moves by a third of Ω per step).
            doubted |= (ln - pred).norm() > 0.25 * st.sep[i];
            before[i] = moved.apply(before[i], omega);
            preds.push(pred);
            lambdas.push(ln);
            vectors.push(vn);
        }
        let sep = separations(&lambdas, omega);
        for (i, &s) in sep.iter().enumerate() {
            if s < MIN_SEPARATION * omega {
                return None;
            }
            doubted |= (lambdas[i] - preds[i]).norm() > 0.25 * s;
        }
        let prev = Some((st.omega, before));
        let next = TrackState { omega, lambdas, vectors, sep, prev, partial: None };
        // Integer orders: a doubted set that still holds one exponent of each family
        // holds them all (there are as many families as tracked exponents).
        if doubted && (self.op.fractional || !self.distinct_families(&next, omega)) {
            self.tr.unconfirmed = Some(next);
            return None;
        }
        let mut exps = Vec::with_capacity(2 * next.lambdas.len());
        for &c in &next.lambdas {
            push_central(&mut exps, c, omega);
        }
        self.tr.state = Some(next);
        Some(floquet(exps, omega, opts, true))
    }

    /// One exponent continued from the prediction `pred` with the previous eigenvector
    /// `v`: Newton's method on `T(λ)v = 0`, and if the eigenvector's centre has passed
    /// 1/2, once more as the next copy; the root in the upper half plane. `None` if an
    /// iteration does not converge.
    fn continue_one(
        &mut self,
        params: &[f64],
        omega: f64,
        mut pred: Complex64,
        v: Vec<Complex64>,
    ) -> Option<Continued> {
        let exact = self.op.fractional;
        let (mut ln, mut vn, _) = self.newton(params, omega, pred, v, TRACK_ITER, false, exact)?;
        // The centred copy has moved on (the mode's frequency passed a half-integer
        // multiple of Ω, its energy now sits nearer the next harmonic): continue as
        // the next copy, `λ + ijΩ` with the eigenvector shifted by `j` harmonics,
        // rather than analyse in full.
        let mut centre = spread(&vn, self.op.ndof, self.op.harmonics).centre;
        let mut moved = CopyMove::default();
        if centre.abs() > 0.5 {
            moved.shift = centre.round();
            let w = Complex64::new(0.0, moved.shift * omega);
            shift_harmonics(&mut vn, self.op.ndof, self.op.harmonics, moved.shift as i64);
            normalise(&mut vn)?;
            (ln, vn, _) = self.newton(params, omega, ln + w, vn, TRACK_ITER, false, exact)?;
            pred += w;
            centre = spread(&vn, self.op.ndof, self.op.harmonics).centre;
        }
        // Conjugation negates the centre: its size is unchanged.
        if to_upper_half(&mut ln, &mut vn, omega) {
            pred = pred.conj();
            moved.conj = true;
        }
        Some(Continued { l: ln, v: vn, pred, moved, centre })
    }

    /// Continue a partial set ([`Hill::start_partial_state`]) to the current point.
    /// Its roots only witness instability and place the count's contour, so none of
    /// the rules for a complete set apply but the refinement's own: a root that does
    /// not converge, lands off centre by more than [`OFF_CENTRE_MAX`], off centre and
    /// unstable ([`may_witness`]) or on a root kept already is dropped from the set.
    /// The verdict is then [`Hill::counted_on`]'s.
    pub(super) fn continue_partial(
        &mut self,
        params: &[f64],
        omega: f64,
        opts: &StabilityOptions,
        st: TrackState,
        partial: Partial,
    ) -> Option<Floquet> {
        self.tr.unconfirmed = None;
        self.op.assemble_polynomial(params, omega, false);
        let predicted = st.predictions(omega);
        let mut lambdas: Vec<Complex64> = Vec::with_capacity(st.lambdas.len());
        let mut vectors = Vec::with_capacity(st.lambdas.len());
        let mut before = Vec::with_capacity(st.lambdas.len());
        for ((&l, v), &pred) in st.lambdas.iter().zip(&st.vectors).zip(&predicted) {
            let Some(c) = self.continue_one(params, omega, pred, v.clone()) else { continue };
            if c.centre.abs() > OFF_CENTRE_MAX
                || !may_witness(c.l, c.centre.abs(), opts.tol * omega)
                || lambdas.iter().any(|&k| same_exponent(k, c.l, omega))
            {
                continue;
            }
            before.push(c.moved.apply(l, omega));
            lambdas.push(c.l);
            vectors.push(c.v);
        }
        let mut exps = Vec::with_capacity(2 * lambdas.len());
        for &c in &lambdas {
            push_central(&mut exps, c, omega);
        }
        let f = self.counted_on(
            params,
            omega,
            opts,
            floquet(exps, omega, opts, false),
            &partial.hints,
        )?;
        let sep = separations(&lambdas, omega);
        let partial = Some(Partial { left: partial.left.saturating_sub(1), ..partial });
        let prev = Some((st.omega, before));
        self.tr.state = Some(TrackState { omega, lambdas, vectors, sep, prev, partial });
        Some(f)
    }
}

/// One exponent continued to the next point ([`Hill::continue_one`]): the root and
/// its eigenvector, the prediction and the copy move applied to both, and the
/// eigenvector's centre.
struct Continued {
    l: Complex64,
    v: Vec<Complex64>,
    pred: Complex64,
    moved: CopyMove,
    centre: f64,
}

impl TrackState {
    /// The linear predictor of each exponent at `omega`: its last value plus its last
    /// motion times the ratio of this step to the last (clamped to `[0, 2]`; 1 on the
    /// parameter axis); the last value itself without a last point.
    fn predictions(&self, omega: f64) -> Vec<Complex64> {
        let Some((w0, p)) = &self.prev else { return self.lambdas.clone() };
        let ratio = if (self.omega - w0).abs() > 0.0 && omega != self.omega {
            ((omega - self.omega) / (self.omega - w0)).clamp(0.0, 2.0)
        } else {
            1.0
        };
        self.lambdas.iter().zip(p).map(|(&l, &q)| l + (l - q) * ratio).collect()
    }
}

/// The copy of an exponent tracking continues as: `λ + i·shift·Ω`, conjugated if
/// `conj`.
#[derive(Debug, Clone, Copy, Default)]
struct CopyMove {
    shift: f64,
    conj: bool,
}

impl CopyMove {
    fn apply(self, l: Complex64, omega: f64) -> Complex64 {
        let l = l + Complex64::new(0.0, self.shift * omega);
        if self.conj {
            l.conj()
        } else {
            l
        }
    }
}

/// The eigenvector of the copy `λ + ijΩ` from that of `λ`: the coefficient of
/// `e^{ikΩt}` becomes that of `e^{i(k-j)Ωt}` (its centre moves by `-j`); the harmonics
/// shifted beyond `N` are dropped. Real basis `[a0, a_k, b_k]` per DOF, with
/// `c_{±k} = (a_k ∓ i b_k)/2`.
pub(super) fn shift_harmonics(v: &mut [Complex64], ndof: usize, nh: usize, j: i64) {
    let len = 2 * nh + 1;
    let i1 = Complex64::new(0.0, 1.0);
    let zero = Complex64::new(0.0, 0.0);
    let n = nh as i64;
    let mut c = vec![zero; len];
    for b in v.chunks_exact_mut(len).take(ndof) {
        // c[k + N] is the coefficient of e^{ikΩt}.
        let coeff = |k: i64| -> Complex64 {
            match k {
                0 => b[0],
                k if k > 0 => (b[k as usize] - i1 * b[nh + k as usize]) * 0.5,
                k => (b[(-k) as usize] + i1 * b[nh + (-k) as usize]) * 0.5,
            }
        };
        for k in -n..=n {
            let from = k + j;
            c[(k + n) as usize] = if from.abs() <= n { coeff(from) } else { zero };
        }
        b[0] = c[nh];
        for k in 1..=nh {
            let (plus, minus) = (c[nh + k], c[nh - k]);
            b[k] = plus + minus;
            b[nh + k] = i1 * (plus - minus);
        }
    }
}

/// Iterations allowed to continue one exponent to the next point.
pub(super) const TRACK_ITER: usize = 5;

/// Exponents closer than this (relative to Ω) are not tracked.
pub(super) const MIN_SEPARATION: f64 = 1e-6;

/// A tracked exponent's eigenvector must stay this centred (`|centre|`, after moving
/// to the next copy when it passes 1/2), and so must every exponent a full analysis
/// selects for tracking to start.
pub(super) const CENTRE_MAX: f64 = 0.5;

/// What tracking carries from point to point.
#[derive(Default)]
pub(super) struct Tracker {
    /// Tracking state (see [`Hill::track`]).
    pub(super) state: Option<TrackState>,
    /// Exponents continued to the current point that only the correction rule
    /// doubted, kept for the full analysis there to confirm (see [`Hill::track`]).
    pub(super) unconfirmed: Option<TrackState>,
    pub(super) counts: TrackCounts,
    /// The sign of `det T` on the real axis beyond every root (`true` positive), from
    /// the last full analysis: a tracked point's real-root check needs only the other
    /// end (see [`Hill::real_parity_agrees`]).
    pub(super) sign_right: Option<bool>,
    /// Points the next partial set is tracked ([`Hill::start_partial_state`]): 0
    /// after a full analysis that refined every candidate, so that one that did not
    /// is followed by another full analysis; then 1, doubling with every full analysis
    /// that again did not, up to [`PARTIAL_POINTS`].
    pub(super) partial_run: usize,
}

/// Tracked exponents of the last point.
#[derive(Clone)]
pub(super) struct TrackState {
    pub(super) omega: f64,
    /// Raw exponents (one per conjugate pair) with unit eigenvectors.
    pub(super) lambdas: Vec<Complex64>,
    pub(super) vectors: Vec<Vec<Complex64>>,
    /// Separation of each from the others (see [`separations`]).
    pub(super) sep: Vec<f64>,
    /// The exponents one point earlier (for the linear predictor), and its Ω.
    pub(super) prev: Option<(f64, Vec<Complex64>)>,
    /// The set holds only the roots that refined at its full analysis (`None`: all).
    pub(super) partial: Option<Partial>,
}

/// What a partial tracked set ([`Hill::start_partial_state`]) carries besides its
/// roots.
#[derive(Clone)]
pub(super) struct Partial {
    /// Every exponent the full analysis saw ([`Selection::found`]): with the tracked
    /// roots, they place the counting contour.
    pub(super) hints: Vec<Complex64>,
    /// Points still to be tracked before the next full analysis, which finds out
    /// whether all candidates refine again.
    pub(super) left: usize,
}

/// The most points a partial set is tracked before a full analysis runs again. A
/// count costs a third of a full analysis with its count (10-mass chain, N = 5: 9.6
/// against 30 ms); the curve takes 11.4 s without partial sets, 6.5, 5.2 and 4.8 s
/// with at most 4, 16 and 32 points.
pub(super) const PARTIAL_POINTS: usize = 16;

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit 2-DOF vector at N = 4 with its energy at harmonics `-1..=1`: `a0`,
    /// `a1` and `b1` of each DOF set (indices 0, 1 and N + 1 = 5 of its block).
    fn vector(seed: f64) -> Vec<Complex64> {
        let mut v: Vec<Complex64> = (0..18)
            .map(|i| {
                let x = seed + 1.3 * (i / 9) as f64;
                match i % 9 {
                    0 => Complex64::new(x.sin(), 0.4 * x.cos()),
                    1 => Complex64::new(0.3 * x.cos(), 0.1),
                    5 => Complex64::new(0.2, -0.3 * x.sin()),
                    _ => Complex64::new(0.0, 0.0),
                }
            })
            .collect();
        normalise(&mut v).unwrap();
        v
    }

    fn state(lambdas: Vec<Complex64>, vectors: Vec<Vec<Complex64>>) -> TrackState {
        TrackState {
            omega: 1.0,
            sep: vec![1.0; lambdas.len()],
            lambdas,
            vectors,
            prev: None,
            partial: None,
        }
    }

    #[test]
    fn distinct_families_refuses_two_copies_of_one_exponent() {
        let hill = Hill::new(&crate::models::QuarterCar::default(), 4).unwrap();
        let omega = 1.0;
        let (a, b) = (Complex64::new(-0.05, 0.2), Complex64::new(-0.1, 0.33));
        let (va, vb) = (vector(0.4), vector(2.9));
        assert!(hill.distinct_families(&state(vec![a, b], vec![va.clone(), vb.clone()]), omega));
        // `a + iΩ` (off by rounding) with the shifted eigenvector, and its conjugate.
        let mut copy = va.clone();
        shift_harmonics(&mut copy, 2, 4, 1);
        let near = a + Complex64::new(1e-4, omega);
        let two = state(vec![a, near], vec![va.clone(), copy.clone()]);
        assert!(!hill.distinct_families(&two, omega));
        let conj: Vec<Complex64> = copy.iter().map(|z| z.conj()).collect();
        let two = state(vec![a, near.conj()], vec![va.clone(), conj]);
        assert!(!hill.distinct_families(&two, omega));
        // Close modulo iΩ but with unrelated eigenvectors: two exponents.
        assert!(hill.distinct_families(&state(vec![a, near], vec![va.clone(), vb]), omega));
    }

    #[test]
    fn distinct_families_refuses_an_eigenvector_spread_to_far_harmonics() {
        // Energy at ±3 in equal parts: centre 0, variance 9.
        let hill = Hill::new(&crate::models::QuarterCar::default(), 4).unwrap();
        let (ndof, nh) = (2, 4);
        let mut far = vec![Complex64::new(0.0, 0.0); ndof * (2 * nh + 1)];
        far[3] = Complex64::new(1.0, 0.0);
        assert!(spread(&far, ndof, nh).centre.abs() < 1e-15);
        let st = state(vec![Complex64::new(-0.05, 0.2)], vec![far]);
        assert!(!hill.distinct_families(&st, 1.0));
    }

    #[test]
    fn shifting_harmonics_moves_the_centre_by_the_shift_and_back() {
        // Energy in harmonics -1..=1 of two DOFs at N = 4: a shift by j = 2 keeps all
        // of it (centre exactly -2 away) and shifting back restores the vector.
        let (ndof, nh) = (2, 4);
        let len = 2 * nh + 1;
        let mut v = vec![Complex64::new(0.0, 0.0); ndof * len];
        for d in 0..ndof {
            let b = &mut v[d * len..(d + 1) * len];
            b[0] = Complex64::new(0.3 + d as f64, -0.2);
            b[1] = Complex64::new(0.7, 0.1 * d as f64);
            b[nh + 1] = Complex64::new(-0.4, 0.5);
        }
        let before = spread(&v, ndof, nh).centre;
        let mut w = v.clone();
        shift_harmonics(&mut w, ndof, nh, 2);
        let after = spread(&w, ndof, nh).centre;
        assert!((after - (before - 2.0)).abs() < 1e-14, "{before} → {after}");
        shift_harmonics(&mut w, ndof, nh, -2);
        for (a, b) in v.iter().zip(&w) {
            assert!((a - b).norm() < 1e-14, "{a} vs {b}");
        }
    }
}
