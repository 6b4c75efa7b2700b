//! Output summaries of a periodic solution: the named linear combinations of DOFs
//! ([`Model::outputs`]) that results report, evaluated from the Fourier coefficients
//! with one reusable buffer and one tabulated grid for `max|x(t)|`
//! ([`MaxAbs`](crate::fourier::MaxAbs)). The corrector's one-off summaries and the
//! continuation's per-point ones are the same computation.

use crate::fourier::{coeff_len, rms, MaxAbs};
use crate::model::{DynModel, Model};
use crate::results::{OutputSummary, PointOutput};

/// Evaluates every output of one model at `N` harmonics.
#[derive(Debug, Clone)]
pub struct OutputEval {
    harmonics: usize,
    peaks: MaxAbs,
    buf: Vec<f64>,
    outputs: Vec<(String, Vec<(usize, f64)>)>,
    /// Per output, of the solution [`OutputEval::points`] saw last: the sign of `x`
    /// and the instant where `|x|` is largest.
    argmax: Vec<(f64, f64)>,
}

impl OutputEval {
    /// The outputs of `model` at `harmonics` harmonics.
    pub fn new(model: &dyn DynModel, harmonics: usize) -> Self {
        OutputEval {
            harmonics,
            peaks: MaxAbs::new(harmonics),
            buf: vec![0.0; coeff_len(harmonics)],
            argmax: vec![(0.0, 0.0); model.outputs().len()],
            outputs: model
                .outputs()
                .iter()
                .map(|o| (o.name.to_string(), o.terms.to_vec()))
                .collect(),
        }
    }

    /// The coefficients `[a0, a1..aN, b1..bN]` of output `k` of the solution `coeffs`.
    pub fn coeffs(&mut self, coeffs: &[f64], k: usize) -> &[f64] {
        crate::model::combine_blocks(&self.outputs[k].1, coeffs, &mut self.buf);
        &self.buf
    }

    /// The rate of change of output `k`'s `max_abs` as the solution `coeffs` moves
    /// along `dcoeffs`: `sign x(θ*) · dx(θ*)` at the instant `θ*` of the maximum
    /// (the envelope theorem; where the maximum is reached at two instants at once the
    /// derivative does not exist, and this is one of the one-sided ones).
    pub fn slope(&mut self, coeffs: &[f64], dcoeffs: &[f64], k: usize) -> f64 {
        let terms = &self.outputs[k].1;
        crate::model::combine_blocks(terms, coeffs, &mut self.buf);
        let (_, sign, theta) = self.peaks.extremes(&self.buf).max_abs();
        crate::model::combine_blocks(terms, dcoeffs, &mut self.buf);
        sign * crate::fourier::eval(&self.buf, theta)
    }

    /// The number of outputs.
    pub fn len(&self) -> usize {
        self.outputs.len()
    }

    /// Whether the model has no outputs.
    pub fn is_empty(&self) -> bool {
        self.outputs.is_empty()
    }

    /// The statistics of every output ([`PointOutput`]), into `out`.
    pub fn points(&mut self, coeffs: &[f64], out: &mut Vec<PointOutput>) {
        out.clear();
        for k in 0..self.outputs.len() {
            self.coeffs(coeffs, k);
            let (p, sign, theta) = self.stats();
            self.argmax[k] = (sign, theta);
            out.push(p);
        }
    }

    /// The rates of change of every output's `max_abs` as the solution last given to
    /// [`OutputEval::points`] moves along `dcoeffs`, into `out` (as [`OutputEval::slope`],
    /// at the instants of the maxima found there: one series evaluation each).
    pub fn slopes(&mut self, dcoeffs: &[f64], out: &mut Vec<f64>) {
        out.clear();
        for k in 0..self.outputs.len() {
            crate::model::combine_blocks(&self.outputs[k].1, dcoeffs, &mut self.buf);
            let (sign, theta) = self.argmax[k];
            out.push(sign * crate::fourier::eval(&self.buf, theta));
        }
    }

    /// The statistics of the output in the buffer, the sign of `x` and the instant
    /// where `|x|` is largest.
    fn stats(&self) -> (PointOutput, f64, f64) {
        let (nh, x) = (self.harmonics, &self.buf);
        let e = self.peaks.extremes(x);
        let (max_abs, sign, theta) = e.max_abs();
        let p = PointOutput {
            max_abs,
            mean: x[0],
            amp1: x[1].hypot(x[nh + 1]),
            rms: rms(x),
            min: e.min,
            max: e.max,
        };
        (p, sign, theta)
    }

    /// The full summaries (with every harmonic's coefficients) of every output.
    pub fn summaries(&mut self, coeffs: &[f64]) -> Vec<OutputSummary> {
        let nh = self.harmonics;
        (0..self.outputs.len())
            .map(|k| {
                self.coeffs(coeffs, k);
                let (p, ..) = self.stats();
                let x = &self.buf;
                let mut sin = vec![0.0];
                sin.extend_from_slice(&x[nh + 1..]);
                OutputSummary {
                    name: self.outputs[k].0.clone(),
                    max_abs: p.max_abs,
                    mean: p.mean,
                    amp1: p.amp1,
                    rms: p.rms,
                    min: p.min,
                    max: p.max,
                    cos: x[..=nh].to_vec(),
                    sin,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::TwoMassChain;

    #[test]
    fn summaries_are_the_linear_combinations_of_the_dofs() {
        // Two DOFs at N = 1: x1 = 1 + 3 cos θ + 4 sin θ, x2 = 2 cos θ.
        let model = TwoMassChain::default();
        let mut eval = OutputEval::new(&model, 1);
        let coeffs = [1.0, 3.0, 4.0, 0.0, 2.0, 0.0];
        let names: Vec<&str> = model.outputs().iter().map(|o| &*o.name).collect();
        let s = eval.summaries(&coeffs);
        let mut pts = Vec::new();
        eval.points(&coeffs, &mut pts);
        for ((o, p), out) in s.iter().zip(&pts).zip(model.outputs()) {
            assert_eq!(o.name, *out.name);
            assert_eq!((o.max_abs, o.mean, o.amp1), (p.max_abs, p.mean, p.amp1));
            assert_eq!((o.rms, o.min, o.max), (p.rms, p.min, p.max));
        }
        // x1 itself: its peak is 1 + 5 (closed form of a0 + |a1 + i b1|), its trough
        // 1 - 5, its RMS sqrt(1 + 25/2) (Parseval).
        let k = names.iter().position(|n| *n == "x1").unwrap();
        assert!((s[k].max_abs - 6.0).abs() < 1e-9, "{}", s[k].max_abs);
        assert_eq!((s[k].mean, s[k].amp1), (1.0, 5.0));
        assert!((s[k].max - 6.0).abs() < 1e-12 && (s[k].min + 4.0).abs() < 1e-12);
        assert!((s[k].rms - 13.5f64.sqrt()).abs() < 1e-15);
        assert_eq!((s[k].cos.clone(), s[k].sin.clone()), (vec![1.0, 3.0], vec![0.0, 4.0]));
    }
}
