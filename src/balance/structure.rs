//! A model's structure: its claims ([`Model::affine_signals`],
//! [`Model::explicit_omega`]) tested before the solvers rely on them, and which
//! equation reads which signal (the Jacobian's block pattern).

use super::Balance;
use crate::error::{Claim, Error, Result};
use crate::model::{DynModel, Model};
use num_dual::Dual64;

fn wrong(model: &str, claim: Claim, detail: String) -> Error {
    Error::WrongClaim { model: model.to_string(), claim, detail }
}

/// Reproducible pseudo-random numbers in [-1, 1) for the probes.
fn states(mut seed: u64) -> impl FnMut() -> f64 {
    move || crate::xorshift::next(&mut seed)
}

/// A state at which the structure tests differentiate the residual.
struct Probe<'a> {
    params: &'a [Dual64],
    omega: Dual64,
    phase: f64,
}

impl Probe<'_> {
    /// `∂r_e/∂s0` for every equation (the dual parts of `out`) with the signals at
    /// `values`, seeding only signal `s0` (`sig` is scratch).
    fn derivative(
        &self,
        model: &dyn DynModel,
        values: &[f64],
        s0: usize,
        sig: &mut [Dual64],
        out: &mut [Dual64],
    ) {
        for (s, (d, &v)) in sig.iter_mut().zip(values).enumerate() {
            *d = Dual64::new(v, if s == s0 { 1.0 } else { 0.0 });
        }
        model.residual(self.params, self.omega, self.phase, sig, out);
    }
}

impl Balance<'_> {
    /// Adopt the model's structure claims ([`Model::affine_signals`],
    /// [`Model::explicit_omega`]) after testing them at a few pseudo-random states: a
    /// wrong claim would silently give wrong Jacobians, so it is an error here.
    pub(super) fn check_structure(&mut self) -> Result<()> {
        let model = self.model;
        let claimed = model.affine_signals();
        if claimed.is_empty() && self.explicit_omega {
            return Ok(());
        }
        if !claimed.is_empty() && claimed.len() != self.nsig {
            return Err(wrong(
                model.name(),
                Claim::AffineSignals,
                format!("{} entries for {} signals", claimed.len(), self.nsig),
            ));
        }
        let (nsig, ndof) = (self.nsig, self.ndof);
        let params: Vec<Dual64> = self.params.iter().map(|&p| Dual64::from_re(p)).collect();
        let mut rand = states(0x2545_f491_4f6c_dd1d);
        let mut sig = vec![Dual64::from_re(0.0); nsig];
        let mut out = vec![Dual64::from_re(0.0); ndof];
        let mut first: Vec<f64> = vec![f64::NAN; ndof * nsig];
        for probe in 0..3 {
            let values: Vec<f64> = (0..nsig).map(|_| 2.0 * rand()).collect();
            let phase = std::f64::consts::PI * (1.0 + rand());
            let omega = 1.7;
            if !self.explicit_omega {
                for (d, &v) in sig.iter_mut().zip(&values) {
                    *d = Dual64::from_re(v);
                }
                model.residual(&params, Dual64::new(omega, 1.0), phase, &sig, &mut out);
                // A NaN is no evidence either way: a coefficient undefined at these
                // parameters, which `Model::check_coefficients` reports by name.
                if let Some(e) = (0..ndof).find(|&e| out[e].eps != 0.0 && !out[e].eps.is_nan()) {
                    return Err(wrong(
                        model.name(),
                        Claim::ExplicitOmega,
                        format!(
                            "it says false, but equation {e} changes with Ω at fixed signals; \
                             return true (the default)"
                        ),
                    ));
                }
            }
            let probe_at = Probe { params: &params, omega: Dual64::from_re(omega), phase };
            for s0 in (0..nsig).filter(|&s| claimed.get(s) == Some(&true)) {
                probe_at.derivative(model, &values, s0, &mut sig, &mut out);
                for e in 0..ndof {
                    let (g, g0) = (out[e].eps, &mut first[e * nsig + s0]);
                    if probe == 0 {
                        *g0 = g;
                    } else if (g - *g0).abs() > 1e-12 * g.abs().max(g0.abs()) {
                        return Err(wrong(
                            model.name(),
                            Claim::AffineSignals,
                            format!(
                                "it says signal {s0} is affine, but ∂r{e}/∂s{s0} is {} at one \
                                 state and {g} at another; mark it false or return &[] (the \
                                 default)",
                                *g0
                            ),
                        ));
                    }
                }
            }
        }
        // Gradients may depend on parameters and Ω (fixed across probes above): the
        // probe tests the structure; `jacobian` evaluates them at the current point.
        for (a, &c) in self.affine.iter_mut().zip(claimed) {
            *a = c;
        }
        Ok(())
    }
}

impl Balance<'_> {
    /// Which equation reads which signal: the model's claim
    /// ([`Model::signal_reads`]), tested against [`Balance::probe_reads`], or without
    /// one the probe itself; and from it the groups of signals one dual pass seeds.
    /// Only a claim groups signals: a probe can miss a derivative that is zero at
    /// all its states (a dead zone), which would then be added to another's.
    pub(super) fn adopt_reads(&mut self) -> Result<()> {
        let (nsig, ndof) = (self.nsig, self.ndof);
        let probed = self.probe_reads();
        let claimed = self.model.signal_reads();
        let varying: Vec<usize> = (0..nsig).filter(|&s| !self.affine[s]).collect();
        if claimed.is_empty() {
            self.reads = probed;
            self.groups = varying.iter().map(|&s| vec![s]).collect();
            self.group_reader =
                varying.iter().flat_map(|&s| std::iter::repeat_n(Some(s), ndof)).collect();
            return Ok(());
        }
        let name = self.model.name();
        if claimed.len() != ndof * nsig {
            return Err(wrong(
                name,
                Claim::SignalReads,
                format!("{} entries for {ndof} equations × {nsig} signals", claimed.len()),
            ));
        }
        if let Some(i) = (0..ndof * nsig).find(|&i| probed[i] && !claimed[i]) {
            return Err(wrong(
                name,
                Claim::SignalReads,
                format!(
                    "it says equation {} does not read signal {}, but its derivative there is \
                     not zero; mark it true or return &[] (the default)",
                    i / nsig,
                    i % nsig
                ),
            ));
        }
        self.reads = claimed.to_vec();
        // greedy colouring: a signal joins the first group none of whose equations it
        // shares
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut taken: Vec<Vec<bool>> = Vec::new();
        for &s in &varying {
            let readers: Vec<usize> = (0..ndof).filter(|&e| claimed[e * nsig + s]).collect();
            let g = match taken.iter().position(|t| readers.iter().all(|&e| !t[e])) {
                Some(g) => g,
                None => {
                    groups.push(Vec::new());
                    taken.push(vec![false; ndof]);
                    groups.len() - 1
                }
            };
            groups[g].push(s);
            for &e in &readers {
                taken[g][e] = true;
            }
        }
        self.group_reader = groups
            .iter()
            .flat_map(|group| {
                (0..ndof).map(move |e| group.iter().copied().find(|&s| claimed[e * nsig + s]))
            })
            .collect();
        self.groups = groups;
        Ok(())
    }

    /// Which equation reads which signal (`e * nsig + s`): `∂r_e/∂s` non-zero (or not
    /// a number) at any of three pseudo-random states, each with every parameter moved
    /// off its value (so that a term whose coefficient is 0 now still counts: a
    /// continuation may change it). For the analytic expressions models are made of,
    /// a derivative that vanishes at all three is zero everywhere, but the solvers do
    /// not rely on it: [`Balance::jacobian_into`] reports a derivative outside the
    /// pattern's band instead of dropping it.
    fn probe_reads(&self) -> Vec<bool> {
        let (nsig, ndof) = (self.nsig, self.ndof);
        let mut rand = states(0x9e6c_63d0_676a_9a99);
        let mut reads = vec![false; ndof * nsig];
        let mut sig = vec![Dual64::from_re(0.0); nsig];
        let mut out = vec![Dual64::from_re(0.0); ndof];
        for _ in 0..3 {
            let params: Vec<Dual64> = self
                .params
                .iter()
                .map(|&p| Dual64::from_re(p + (p.abs() + 1.0) * 0.5 * rand()))
                .collect();
            let values: Vec<f64> = (0..nsig).map(|_| 2.0 * rand()).collect();
            let phase = std::f64::consts::PI * (1.0 + rand());
            let omega = Dual64::from_re(1.0 + 0.5 * rand());
            let probe = Probe { params: &params, omega, phase };
            for s0 in 0..nsig {
                probe.derivative(self.model, &values, s0, &mut sig, &mut out);
                for (e, o) in out.iter().enumerate() {
                    if o.eps != 0.0 {
                        reads[e * nsig + s0] = true;
                    }
                }
            }
        }
        reads
    }
}
