//! Output summaries of a periodic solution: the named observables of
//! [`Model::outputs`] that results report, each as a truncated Fourier series with its
//! statistics. A combination of DOFs is combined from the coefficients exactly; an
//! expression (an acceleration, a spring force, a tyre force that cannot pull) is
//! evaluated on a time grid from its signals and projected onto the solution's
//! harmonics, as the harmonic balance evaluates the residual. One reusable evaluator
//! serves the corrector's one-off summaries and the continuation's per-point ones.

use crate::fourier::{
    apply_factor, apply_order, coeff_len, order_rate, output_sample_count, rms, spectral_factor,
    Fourier, MaxAbs,
};
use crate::model::{combine_blocks, DynModel, Model, Order, OutputKind};
use crate::results::{OutputRates, OutputSummary, PointOutput};
use num_dual::Dual64;

/// Where a solution's outputs are evaluated: the model, its parameter values, and the
/// frequency in the balance's convention (`omega` is the solution's own frequency
/// `Ω / period`; the model sees `Ω = period · omega`).
#[derive(Clone, Copy)]
pub struct At<'a> {
    /// The model the solution belongs to.
    pub model: &'a dyn DynModel,
    /// Its parameter values, in `params_info` order.
    pub params: &'a [f64],
    /// The solution's frequency `ω = Ω / period` (rad/s).
    pub omega: f64,
    /// Forcing periods per solution period (1, or 2 on a period-doubled branch).
    pub period: usize,
}

impl<'a> At<'a> {
    /// A period-1 solution of `model` at its own parameter values.
    pub fn model(model: &'a dyn DynModel, params: &'a [f64], omega: f64) -> Self {
        At { model, params, omega, period: 1 }
    }
}

/// A direction in which a solution moves (along a curve, or with a parameter): the
/// rates of change of its coefficients, of `ω`, and of one parameter.
#[derive(Debug, Clone, Copy)]
pub struct Direction<'a> {
    /// `d(coefficients)`, in the solution's layout.
    pub coeffs: &'a [f64],
    /// `dω` (the balance's frequency, as [`At::omega`]).
    pub omega: f64,
    /// `(index, dθ)` of the parameter that moves, if one does.
    pub param: Option<(usize, f64)>,
}

/// What one output is, as the evaluator keeps it.
#[derive(Debug, Clone)]
enum Kind {
    Dofs(Vec<(usize, f64)>),
    Expression(usize),
}

/// Evaluates every output of one model at `N` harmonics.
#[derive(Debug, Clone)]
pub struct OutputEval {
    harmonics: usize,
    peaks: MaxAbs,
    buf: Vec<f64>,
    outputs: Vec<(String, Kind)>,
    /// Per output, of the solution [`OutputEval::points`] saw last: the sign of `x`
    /// and the instant where `|x|` is largest.
    argmax: Vec<(f64, f64)>,
    /// The transform of the expression outputs (`None` when there are none).
    exprs: Option<Exprs>,
}

/// The time-grid evaluation of the expression outputs.
#[derive(Debug, Clone)]
struct Exprs {
    fourier: Fourier,
    /// `(terms, order)` per output signal.
    signals: Vec<(Vec<(usize, f64)>, Order)>,
    /// The number of results of [`Model::output_values`].
    count: usize,
    /// The coefficients of the solution evaluated last (the base of [`Exprs::derive`]).
    last: Vec<f64>,
    /// The expressions' coefficients of that solution, `i * len ..`.
    coeffs: Vec<f64>,
    /// Their rates of change along the last direction, `i * len ..`.
    dcoeffs: Vec<f64>,
    /// Signal samples and their rates of change, `s * M + j`.
    sig: Vec<f64>,
    dsig: Vec<f64>,
    /// Result samples and their rates of change, `i * M + j`.
    vals: Vec<f64>,
    dvals: Vec<f64>,
    comb: Vec<f64>,
    op: Vec<f64>,
}

impl OutputEval {
    /// The outputs of `model` at `harmonics` harmonics of its solutions' frequency, for
    /// solutions that repeat every `period` forcing periods.
    pub fn new(model: &dyn DynModel, harmonics: usize, period: usize) -> Self {
        let outputs: Vec<(String, Kind)> = model
            .outputs()
            .iter()
            .map(|o| {
                let kind = match &o.kind {
                    OutputKind::Dofs(t) => Kind::Dofs(t.to_vec()),
                    OutputKind::Expression(i) => Kind::Expression(*i),
                };
                (o.name.to_string(), kind)
            })
            .collect();
        let count = outputs
            .iter()
            .filter_map(|(_, k)| match k {
                Kind::Expression(i) => Some(i + 1),
                Kind::Dofs(_) => None,
            })
            .max()
            .unwrap_or(0);
        let exprs = (count > 0).then(|| Exprs::new(model, harmonics, period, count)).flatten();
        OutputEval {
            harmonics,
            peaks: MaxAbs::new(harmonics),
            buf: vec![0.0; coeff_len(harmonics)],
            argmax: vec![(0.0, 0.0); outputs.len()],
            outputs,
            exprs,
        }
    }

    /// The samples per period on which the expression outputs are evaluated (`None`
    /// when every output is a combination of DOFs).
    pub fn samples(&self) -> Option<usize> {
        self.exprs.as_ref().map(|e| e.fourier.samples())
    }

    /// Evaluate the expression outputs of the solution `coeffs` (a no-op without any).
    fn evaluate(&mut self, at: &At, coeffs: &[f64]) {
        if let Some(e) = &mut self.exprs {
            e.evaluate(at, coeffs);
        }
    }

    /// Output `k`'s coefficients into the buffer: `coeffs` combined, or its
    /// expression's as [`OutputEval::evaluate`] left them.
    fn load(&mut self, coeffs: &[f64], k: usize) {
        match &self.outputs[k].1 {
            Kind::Dofs(t) => combine_blocks(t, coeffs, &mut self.buf),
            Kind::Expression(i) => {
                let len = self.buf.len();
                // `exprs` exists whenever an output is an expression and its transform
                // could be planned (the balance of the same model refuses first).
                match &self.exprs {
                    Some(e) => self.buf.copy_from_slice(&e.coeffs[i * len..(i + 1) * len]),
                    None => self.buf.fill(f64::NAN),
                }
            }
        }
    }

    /// The expression outputs' rates of change along `dir` (after
    /// [`OutputEval::evaluate`] of the solution it starts from; a no-op without any).
    fn derive(&mut self, at: &At, dir: &Direction) {
        if let Some(e) = &mut self.exprs {
            e.derive(at, dir);
        }
    }

    /// Output `k`'s rate of change along `dir` into the buffer (after
    /// [`OutputEval::derive`]).
    fn load_rate(&mut self, dir: &Direction, k: usize) {
        match &self.outputs[k].1 {
            Kind::Dofs(t) => combine_blocks(t, dir.coeffs, &mut self.buf),
            Kind::Expression(i) => {
                let len = self.buf.len();
                match &self.exprs {
                    Some(e) => self.buf.copy_from_slice(&e.dcoeffs[i * len..(i + 1) * len]),
                    None => self.buf.fill(f64::NAN),
                }
            }
        }
    }

    /// The coefficients `[a0, a1..aN, b1..bN]` of output `k` of the solution `coeffs`.
    pub fn coeffs(&mut self, at: &At, coeffs: &[f64], k: usize) -> &[f64] {
        self.evaluate(at, coeffs);
        self.load(coeffs, k);
        &self.buf
    }

    /// The rate of change of output `k`'s `max_abs` as the solution `coeffs` moves
    /// along `dir`: `sign x(θ*) · dx(θ*)` at the instant `θ*` of the maximum (the
    /// envelope theorem; where the maximum is reached at two instants at once the
    /// derivative does not exist, and this is one of the one-sided ones).
    pub fn slope(&mut self, at: &At, coeffs: &[f64], dir: &Direction, k: usize) -> f64 {
        self.evaluate(at, coeffs);
        self.load(coeffs, k);
        let (_, sign, theta) = self.peaks.extremes(&self.buf).max_abs();
        self.derive(at, dir);
        self.load_rate(dir, k);
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
    pub fn points(&mut self, at: &At, coeffs: &[f64], out: &mut Vec<PointOutput>) {
        out.clear();
        self.evaluate(at, coeffs);
        for k in 0..self.outputs.len() {
            self.load(coeffs, k);
            let (p, sign, theta) = self.stats();
            self.argmax[k] = (sign, theta);
            out.push(p);
        }
    }

    /// The rates of change of every output's `max_abs` as the solution last given to
    /// [`OutputEval::points`] moves along `dir`, into `out` (as [`OutputEval::slope`],
    /// at the instants of the maxima found there: one series evaluation each).
    pub fn slopes(&mut self, at: &At, dir: &Direction, out: &mut Vec<f64>) {
        out.clear();
        self.derive(at, dir);
        for k in 0..self.outputs.len() {
            self.load_rate(dir, k);
            let (sign, theta) = self.argmax[k];
            out.push(sign * crate::fourier::eval(&self.buf, theta));
        }
    }

    /// The rates of change of every output's statistics as the solution `coeffs` moves
    /// along `dir` (per unit of whatever `dir` is the rate of: a parameter, for design
    /// sensitivities). The extremes move with the value at the instant they are
    /// reached (the envelope theorem); the amplitude and the RMS as their formulas
    /// say, and not at all where they are zero (no derivative there).
    pub fn rates(&mut self, at: &At, coeffs: &[f64], dir: &Direction) -> Vec<OutputRates> {
        let nh = self.harmonics;
        self.evaluate(at, coeffs);
        self.derive(at, dir);
        (0..self.outputs.len())
            .map(|k| {
                self.load(coeffs, k);
                let x = self.buf.clone();
                let e = self.peaks.extremes(&x);
                let (_, sign, theta) = e.max_abs();
                let (amp1, rms) = (x[1].hypot(x[nh + 1]), rms(&x));
                self.load_rate(dir, k);
                let dx = &self.buf;
                let at_instant = |t: f64| crate::fourier::eval(dx, t);
                let power: f64 = x[0] * dx[0]
                    + 0.5 * x[1..].iter().zip(&dx[1..]).map(|(a, b)| a * b).sum::<f64>();
                OutputRates {
                    max_abs: Some(sign * at_instant(theta)),
                    mean: Some(dx[0]),
                    amp1: (amp1 > 0.0).then(|| (x[1] * dx[1] + x[nh + 1] * dx[nh + 1]) / amp1),
                    rms: (rms > 0.0).then(|| power / rms),
                    min: Some(at_instant(e.at_min)),
                    max: Some(at_instant(e.at_max)),
                }
            })
            .collect()
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
    pub fn summaries(&mut self, at: &At, coeffs: &[f64]) -> Vec<OutputSummary> {
        let nh = self.harmonics;
        self.evaluate(at, coeffs);
        (0..self.outputs.len())
            .map(|k| {
                self.load(coeffs, k);
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

impl Exprs {
    /// The transform for `count` expression results of `model` (`None` if the sample
    /// count cannot be planned, which the balance of the same model refuses first).
    fn new(model: &dyn DynModel, harmonics: usize, period: usize, count: usize) -> Option<Self> {
        let m = output_sample_count(model, harmonics, period);
        let fourier = Fourier::new(harmonics, m).ok()?;
        let signals: Vec<(Vec<(usize, f64)>, Order)> =
            model.output_signals().iter().map(|s| (s.terms.to_vec(), s.order)).collect();
        let (len, nsig) = (coeff_len(harmonics), signals.len());
        Some(Exprs {
            fourier,
            signals,
            count,
            last: Vec::new(),
            coeffs: vec![0.0; count * len],
            dcoeffs: vec![0.0; count * len],
            sig: vec![0.0; nsig * m],
            dsig: vec![0.0; nsig * m],
            vals: vec![0.0; count * m],
            dvals: vec![0.0; count * m],
            comb: vec![0.0; len],
            op: vec![0.0; len],
        })
    }

    /// The model's phase `Ω t` at sample `j`.
    fn phase(&self, at: &At, j: usize) -> f64 {
        let m = self.fourier.samples();
        std::f64::consts::TAU * j as f64 / m as f64 * at.period.max(1) as f64
    }

    /// The expressions' coefficients of the solution `coeffs`.
    fn evaluate(&mut self, at: &At, coeffs: &[f64]) {
        let (m, len) = (self.fourier.samples(), self.comb.len());
        self.last.clear();
        self.last.extend_from_slice(coeffs);
        for (s, (terms, order)) in self.signals.iter().enumerate() {
            combine_blocks(terms, coeffs, &mut self.comb);
            apply_order(&self.comb, order.value(at.params), at.omega, &mut self.op);
            self.fourier.synthesize(&self.op, &mut self.sig[s * m..(s + 1) * m]);
        }
        let nsig = self.signals.len();
        let (mut s, mut out) = (vec![0.0; nsig], vec![0.0; self.count]);
        let big_omega = at.omega * at.period.max(1) as f64;
        for j in 0..m {
            for (k, v) in s.iter_mut().enumerate() {
                *v = self.sig[k * m + j];
            }
            at.model.output_values::<f64>(at.params, big_omega, self.phase(at, j), &s, &mut out);
            for (i, v) in out.iter().enumerate() {
                self.vals[i * m + j] = *v;
            }
        }
        for i in 0..self.count {
            self.fourier
                .analyze(&self.vals[i * m..(i + 1) * m], &mut self.coeffs[i * len..(i + 1) * len]);
        }
    }

    /// The expressions' rates of change along `dir` from the solution evaluated last:
    /// one pass in dual numbers, each signal seeded with its own rate of change
    /// (through the coefficients, through `ω` in `(ikω)^q`, and through a fractional
    /// order that is the moving parameter).
    fn derive(&mut self, at: &At, dir: &Direction) {
        let (m, len) = (self.fourier.samples(), self.comb.len());
        for (s, (terms, order)) in self.signals.iter().enumerate() {
            let q = order.value(at.params);
            combine_blocks(terms, dir.coeffs, &mut self.comb);
            apply_order(&self.comb, q, at.omega, &mut self.op);
            // Plus the operator's own change: d(ikω)^q = (ikω)^q (q dω/ω + dq ln(ikω)).
            let dq = match (order, dir.param) {
                (Order::Param(i), Some((p, d))) if *i == p => d,
                _ => 0.0,
            };
            if (dir.omega != 0.0 || dq != 0.0) && at.omega > 0.0 {
                combine_blocks(terms, &self.last, &mut self.comb);
                let mut moved = vec![0.0; len];
                let dw = q * dir.omega / at.omega;
                apply_factor(&self.comb, &mut moved, |k| {
                    spectral_factor(k, at.omega, q) * dw + order_rate(k, at.omega, q) * dq
                });
                for (o, v) in self.op.iter_mut().zip(&moved) {
                    *o += v;
                }
            }
            self.fourier.synthesize(&self.op, &mut self.dsig[s * m..(s + 1) * m]);
        }
        let nsig = self.signals.len();
        let period = at.period.max(1) as f64;
        let params: Vec<Dual64> = (0..at.params.len())
            .map(|i| {
                let d = match dir.param {
                    Some((p, d)) if p == i => d,
                    _ => 0.0,
                };
                Dual64::new(at.params[i], d)
            })
            .collect();
        let omega = Dual64::new(at.omega * period, dir.omega * period);
        let (mut s, mut out) = (vec![Dual64::from(0.0); nsig], vec![Dual64::from(0.0); self.count]);
        for j in 0..m {
            for (k, v) in s.iter_mut().enumerate() {
                *v = Dual64::new(self.sig[k * m + j], self.dsig[k * m + j]);
            }
            at.model.output_values::<Dual64>(&params, omega, self.phase(at, j), &s, &mut out);
            for (i, v) in out.iter().enumerate() {
                self.dvals[i * m + j] = v.eps;
            }
        }
        for i in 0..self.count {
            self.fourier.analyze(
                &self.dvals[i * m..(i + 1) * m],
                &mut self.dcoeffs[i * len..(i + 1) * len],
            );
        }
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
        let mut eval = OutputEval::new(&model, 1, 1);
        let coeffs = [1.0, 3.0, 4.0, 0.0, 2.0, 0.0];
        let params = model.param_values();
        let at = At::model(&model, &params, 1.0);
        let names: Vec<&str> = model.outputs().iter().map(|o| &*o.name).collect();
        let s = eval.summaries(&at, &coeffs);
        let mut pts = Vec::new();
        eval.points(&at, &coeffs, &mut pts);
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
