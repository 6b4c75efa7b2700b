//! The part of a convolution quadrature that lies before `t = 0`, for a signal that
//! was periodic for all time: what a run started on a periodic solution needs so that
//! its fractional derivatives are those of the steady state (Weyl), not of a motion
//! that began at `t = 0` (Caputo, whose missing past leaves a `t^-q` tail).
//!
//! Over an infinite past the quadrature of `D^q e` at step `m` is
//! `dt^-q Σ_{j≥0} w_j e_{m-j}`; the stepper sums `j ≤ m` (its own history). The rest,
//! `P_m = Σ_{j>m} w_j e_p(t_{m-j})`, is known when `e_p(t) = Re Σ E_k e^{ikωt}` is:
//! the whole sum of a sampled harmonic is the rule's symbol
//! ([`Scheme::symbol`]), `Σ_{j≥0} w_j e^{ikω(t_m - j dt)} = δ(e^{-ikωdt})^q e^{ikωt_m}`,
//! so `P_m = Re Σ E_k δ(e^{-ikωdt})^q e^{ikωt_m} - Σ_{j≤m} w_j e_p(t_{m-j})`, the
//! second sum convolved as the stepper's own history is ([`History`]).

use super::memory::{History, Memory};
use super::weights::Scheme;
use crate::error::Error;
use crate::fourier::{apply_factor, eval};
use num_complex::Complex64;

/// The past of one fractional signal `e_p` (Fourier coefficients `[a0, a_k, b_k]` of
/// `ω`), stepped along with the run.
///
/// ```
/// use ihbm::timedomain::{Memory, PeriodicPast, Scheme};
/// // e_p = cos t, q = 1/2, dt = 0.01: the past part of step 0 is the whole sum but
/// // its first term, and it fades as the run's own history takes over.
/// let (dt, q) = (0.01, 0.5);
/// let w = Scheme::Bdf2.weights(q, 2001);
/// let mut past = PeriodicPast::new(&[0.0, 1.0, 0.0], 1.0, dt, q, Scheme::Bdf2, Memory::Fast, w);
/// let first = past.tail().unwrap();
/// for _ in 0..2000 { past.advance().unwrap(); }
/// assert!(past.tail().unwrap().abs() < 0.05 * first.abs());
/// ```
#[derive(Debug)]
pub struct PeriodicPast {
    /// `e_p`'s coefficients.
    signal: Vec<f64>,
    /// The whole sum `Σ_{j≥0} w_j e_p(t - j dt)` as a Fourier series in `t`.
    whole: Vec<f64>,
    /// `ω dt`.
    phase_step: f64,
    w0: f64,
    /// The samples `e_p(t_0), e_p(t_1), …` so far, convolved with the weights.
    finite: History,
    /// `P_m` of the current step once computed (a step tried again asks twice).
    current: Option<f64>,
}

impl PeriodicPast {
    /// The past of `signal` (one coefficient vector, `2N + 1` long, of frequency
    /// `omega`) for `D^q` by `scheme` with step `dt`; `weights` are the rule's
    /// (`w_0 ..`, as many as the run has steps plus one). An empty `signal` is zero.
    pub fn new(
        signal: &[f64],
        omega: f64,
        dt: f64,
        q: f64,
        scheme: Scheme,
        memory: Memory,
        weights: Vec<f64>,
    ) -> Self {
        let signal: &[f64] = if signal.is_empty() { &[0.0] } else { signal };
        let mut whole = vec![0.0; signal.len()];
        let theta = omega * dt;
        apply_factor(signal, &mut whole, |k| {
            scheme.symbol(Complex64::new(0.0, -(k as f64) * theta).exp(), q)
        });
        let w0 = weights.first().copied().unwrap_or(0.0);
        PeriodicPast {
            signal: signal.to_vec(),
            whole,
            phase_step: theta,
            w0,
            finite: History::new(memory, weights),
            current: None,
        }
    }

    /// The phase `ω t_m` of the current step, reduced to one period.
    fn phase(&self) -> f64 {
        (self.finite.values().len() as f64 * self.phase_step).rem_euclid(std::f64::consts::TAU)
    }

    /// `P_m = Σ_{j>m} w_j e_p(t_{m-j})` for the current step `m`.
    pub fn tail(&mut self) -> Result<f64, Error> {
        if let Some(p) = self.current {
            return Ok(p);
        }
        let theta = self.phase();
        let e = eval(&self.signal, theta);
        let p = eval(&self.whole, theta) - (self.w0 * e + self.finite.lag_sum()?);
        self.current = Some(p);
        Ok(p)
    }

    /// On to the next step (the current one is done).
    pub fn advance(&mut self) -> Result<(), Error> {
        self.tail()?;
        let e = eval(&self.signal, self.phase());
        self.finite.push(e)?;
        self.current = None;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `P_m` against the tail summed term by term over a million steps of the past
    /// (its remainder is of order `J^{-1-q}` for a signal without mean), for both rules,
    /// a sub- and a super-unit order and a signal of two harmonics.
    #[test]
    fn the_tail_is_the_sum_over_the_past() {
        let signal = [0.0, 0.7, -0.2, 0.3, 0.45]; // N = 2: a1, a2, b1, b2
        let (omega, dt, steps) = (1.3, 0.02, 300);
        let e = |t: f64| eval(&signal, omega * t);
        for scheme in [Scheme::Gl, Scheme::Bdf2] {
            for q in [0.5, 1.5] {
                let past_len = 1_000_000;
                let w = scheme.weights(q, steps + past_len + 1);
                let mut past = PeriodicPast::new(
                    &signal,
                    omega,
                    dt,
                    q,
                    scheme,
                    Memory::Fast,
                    w[..=steps].to_vec(),
                );
                for m in 0..steps {
                    let got = past.tail().unwrap();
                    if m % 37 == 0 {
                        let sum: f64 = (m + 1..m + past_len)
                            .map(|j| w[j] * e((m as f64 - j as f64) * dt))
                            .sum();
                        assert!((got - sum).abs() < 1e-7, "{scheme} q {q} m {m}: {got} vs {sum}");
                    }
                    past.advance().unwrap();
                }
            }
        }
    }

    /// An empty signal is the zero signal: no past, nothing to fail on.
    #[test]
    fn an_empty_signal_has_no_past() {
        let w = Scheme::Gl.weights(0.5, 4);
        let mut past = PeriodicPast::new(&[], 1.0, 0.1, 0.5, Scheme::Gl, Memory::Fast, w);
        for _ in 0..3 {
            assert_eq!(past.tail().unwrap(), 0.0);
            past.advance().unwrap();
        }
    }

    /// A constant has no past (`D^q` of a constant is 0 in the steady state): the
    /// weights sum to `δ(1)^q = 0`, so the tail is minus the finite sum.
    #[test]
    fn a_constant_signal_has_a_vanishing_derivative() {
        let (dt, q) = (0.05, 0.5);
        let w = Scheme::Bdf2.weights(q, 101);
        let mut past =
            PeriodicPast::new(&[2.0, 0.0, 0.0], 1.0, dt, q, Scheme::Bdf2, Memory::Naive, w.clone());
        for m in 0..100 {
            let finite: f64 = w[..=m].iter().sum::<f64>() * 2.0;
            // The quadrature over all time: finite part plus tail.
            assert!((past.tail().unwrap() + finite).abs() < 1e-13, "m {m}");
            past.advance().unwrap();
        }
    }
}
