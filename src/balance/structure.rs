//! A hand-written model's structure claims ([`Model::affine_signals`],
//! [`Model::explicit_omega`]) tested before the solvers rely on them.

use super::Balance;
use crate::error::{Error, Result};
use crate::model::Model;
use num_dual::Dual64;

impl<M: Model> Balance<'_, M> {
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
            return Err(Error::Other(format!(
                "model '{}': affine_signals() has {} entries for {} signals",
                model.name(),
                claimed.len(),
                self.nsig
            )));
        }
        let (nsig, ndof) = (self.nsig, self.ndof);
        let params: Vec<Dual64> = self.params.iter().map(|&p| Dual64::from_re(p)).collect();
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut rand = move || {
            // xorshift: reproducible states in [-1, 1]
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
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
                    return Err(Error::Other(format!(
                        "model '{}' says explicit_omega() == false, but equation {e} changes with Ω at \
                         fixed signals; return true (the default)",
                        model.name()
                    )));
                }
            }
            for s0 in (0..nsig).filter(|&s| claimed.get(s) == Some(&true)) {
                for (s, (d, &v)) in sig.iter_mut().zip(&values).enumerate() {
                    *d = Dual64::new(v, if s == s0 { 1.0 } else { 0.0 });
                }
                model.residual(&params, Dual64::from_re(omega), phase, &sig, &mut out);
                for e in 0..ndof {
                    let (g, g0) = (out[e].eps, &mut first[e * nsig + s0]);
                    if probe == 0 {
                        *g0 = g;
                    } else if (g - *g0).abs() > 1e-12 * g.abs().max(g0.abs()) {
                        return Err(Error::Other(format!(
                            "model '{}' says signal {s0} is affine (affine_signals), but \
                             ∂r{e}/∂s{s0} is {} at one state and {g} at another; mark it \
                             false or return &[] (the default)",
                            model.name(),
                            *g0
                        )));
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
