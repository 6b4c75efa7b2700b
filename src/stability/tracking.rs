//! Continuing the exponents of one point to the next along a curve, and the rules
//! for when that cannot be trusted (book, *Tracking along a curve*).

use super::*;

impl Hill {
    /// Tracking state from the last full analysis (`self.raw`), if its selection is
    /// clean: every selected eigenvalue centred (`|centre| ≤ CENTRE_MAX`), every one
    /// left out clearly less so (rank larger by `RANK_GAP`), `q_max·ndof` of them
    /// counted with conjugates, and well separated from each other, their conjugates and copies.
    /// Otherwise no state (the next point is analysed in full too). The polynomial
    /// part of `T` is the one the full analysis left assembled (exact for fractional
    /// models: the state holds their refined roots).
    pub(super) fn start_state(&mut self, params: &[f64], omega: f64) {
        self.state = None;
        let n_out: usize = self.raw.iter().map(|&l| if real(l, omega) { 1 } else { 2 }).sum();
        if self.raw.is_empty()
            || self.replaced
            || n_out != self.central_count()
            || self.centres.iter().any(|c| c.centre.abs() > CENTRE_MAX)
            || self.centres.iter().any(|c| c.key() + RANK_GAP > self.next_rank)
        {
            return;
        }
        let sep = separations(&self.raw, omega);
        if sep.iter().any(|&s| s < MIN_SEPARATION * omega) {
            return;
        }
        let exact = self.fractional;
        let mut lambdas = Vec::with_capacity(self.raw.len());
        let mut vectors = Vec::with_capacity(self.raw.len());
        let raw = std::mem::take(&mut self.raw);
        for &l0 in &raw {
            let Some(v) = self.start_vector(params, omega, l0, exact) else { break };
            match self.newton(params, omega, l0, v, 30, true, exact) {
                Some((l, v, _)) if (l - l0).norm() <= 1e-8 * omega.max(l0.norm()) => {
                    lambdas.push(l);
                    vectors.push(v);
                }
                _ => break,
            }
        }
        let ok = lambdas.len() == raw.len();
        self.raw = raw;
        if ok {
            self.state = Some(TrackState { omega, lambdas, vectors, sep, prev: None });
        }
    }

    /// Continue `st` to the current point; `None` if a fallback rule fires.
    pub(super) fn continue_state(
        &mut self,
        params: &[f64],
        omega: f64,
        opts: &StabilityOptions,
        st: TrackState,
    ) -> Option<Floquet> {
        // Integer orders: the polynomial; fractional: its integer part, the fractional
        // signals exact in `eval_t` (the tracked values are the refined roots).
        let exact = self.fractional;
        self.assemble_polynomial(params, omega, !exact);
        // Linear predictor in Ω (ratio of the steps, clamped; 1 on the parameter axis).
        let ratio = match &st.prev {
            Some((w0, _)) if (st.omega - w0).abs() > 0.0 && omega != st.omega => {
                ((omega - st.omega) / (st.omega - w0)).clamp(0.0, 2.0)
            }
            Some(_) => 1.0,
            None => 0.0,
        };
        let mut lambdas = Vec::with_capacity(st.lambdas.len());
        let mut vectors = Vec::with_capacity(st.lambdas.len());
        let mut preds = Vec::with_capacity(st.lambdas.len());
        for (i, (&l, v)) in st.lambdas.iter().zip(&st.vectors).enumerate() {
            let pred = match &st.prev {
                Some((_, p)) => l + (l - p[i]) * ratio,
                None => l,
            };
            preds.push(pred);
            let (ln, vn, _) =
                self.newton(params, omega, pred, v.clone(), TRACK_ITER, false, exact)?;
            // Still the centred copy (not a jump to a copy of this or another mode).
            if spread(&vn, self.ndof, self.harmonics).centre.abs() > CENTRE_MAX {
                return None;
            }
            // Stay on the real axis / in the upper half plane as before.
            let (was_real, is_real) = (real(l, omega), real(ln, omega));
            if was_real != is_real || !is_real && ln.im < 0.0 {
                return None;
            }
            // The iteration's correction, not the motion: an exponent that moves
            // steadily along the curve is predicted (the quarter car's body mode near
            // resonance moves by a third of Ω per step).
            if (ln - pred).norm() > 0.25 * st.sep[i] {
                return None;
            }
            lambdas.push(ln);
            vectors.push(vn);
        }
        let sep = separations(&lambdas, omega);
        for (i, &s) in sep.iter().enumerate() {
            let corrected = (lambdas[i] - preds[i]).norm();
            if s < MIN_SEPARATION * omega || corrected > 0.25 * s {
                return None;
            }
        }
        let mut exps = Vec::with_capacity(2 * lambdas.len());
        for &c in &lambdas {
            push_central(&mut exps, c, omega);
        }
        let prev = Some((st.omega, st.lambdas));
        self.state = Some(TrackState { omega, lambdas, vectors, sep, prev });
        Some(floquet(exps, omega, opts, true))
    }
}

/// Iterations allowed to continue one exponent to the next point.
pub(super) const TRACK_ITER: usize = 5;

/// Exponents closer than this (relative to Ω) are not tracked.
pub(super) const MIN_SEPARATION: f64 = 1e-6;

/// A tracked exponent's eigenvector must stay this centred (`|centre|`), and so must
/// every exponent a full analysis selects for tracking to start.
pub(super) const CENTRE_MAX: f64 = 0.4;

/// For tracking to start, every eigenvalue a full analysis leaves out must rank
/// ([`Spread::key`]) higher by this than every one it keeps (the next copy of a mode
/// with `|centre| ≤ 0.4` has `|centre|` larger by `1 - 2|centre| ≥ 0.2`).
pub(super) const RANK_GAP: f64 = 0.2;

/// Tracked exponents of the last point.
pub(super) struct TrackState {
    pub(super) omega: f64,
    /// Raw exponents (one per conjugate pair) with unit eigenvectors.
    pub(super) lambdas: Vec<Complex64>,
    pub(super) vectors: Vec<Vec<Complex64>>,
    /// Separation of each from the others (see [`separations`]).
    pub(super) sep: Vec<f64>,
    /// The exponents one point earlier (for the linear predictor), and its Ω.
    pub(super) prev: Option<(f64, Vec<Complex64>)>,
}
