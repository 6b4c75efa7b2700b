//! A user crate gets the whole `ihbm` command line for its own models in three lines.
//!
//! ```text
//! cargo run --example user_cli -- models
//! cargo run --example user_cli -- solve base-isolator --omega 3 --json
//! ```

use ihbm::model::{Model, Order, Output, ParamInfo, Signal};
use ihbm::num_dual::DualNum;

/// A base-isolated mass: m x'' + c x' + h D^p x + k x + k3 x^3 = F cos(Ωt).
#[derive(Debug, Clone, PartialEq)]
pub struct BaseIsolator {
    /// Mass, kg.
    pub m: f64,
    /// Viscous damping, N s/m.
    pub c: f64,
    /// Fractional damping coefficient, N s^p/m.
    pub h: f64,
    /// Fractional order.
    pub p: f64,
    /// Linear stiffness, N/m.
    pub k: f64,
    /// Cubic stiffness, N/m^3.
    pub k3: f64,
    /// Force amplitude, N.
    pub f: f64,
}

impl Default for BaseIsolator {
    fn default() -> Self {
        BaseIsolator { m: 1.0, c: 0.05, h: 0.2, p: 0.5, k: 4.0, k3: 0.0, f: 1.0 }
    }
}

const PARAMS: [ParamInfo; 7] = [
    ParamInfo { name: "m", default: 1.0, doc: "mass, kg" },
    ParamInfo { name: "c", default: 0.05, doc: "viscous damping, N s/m" },
    ParamInfo { name: "h", default: 0.2, doc: "fractional damping coefficient, N s^p/m" },
    ParamInfo { name: "p", default: 0.5, doc: "fractional order" },
    ParamInfo { name: "k", default: 4.0, doc: "linear stiffness, N/m" },
    ParamInfo { name: "k3", default: 0.0, doc: "cubic stiffness, N/m^3" },
    ParamInfo { name: "F", default: 1.0, doc: "force amplitude, N" },
];
const X: &[(usize, f64)] = &[(0, 1.0)];
const SIGNALS: [Signal; 4] = [
    Signal { terms: X, order: Order::Int(0) },
    Signal { terms: X, order: Order::Int(1) },
    Signal { terms: X, order: Order::Int(2) },
    Signal { terms: X, order: Order::Param(3) },
];
const OUTPUTS: [Output; 1] = [Output { name: "x", terms: X }];

impl Model for BaseIsolator {
    fn name(&self) -> &'static str {
        "base-isolator"
    }
    fn description(&self) -> &'static str {
        "Base-isolated mass m x'' + c x' + h D^p x + k x + k3 x^3 = F cos(Ωt)"
    }
    fn dofs(&self) -> &'static [&'static str] {
        &["x"]
    }
    fn params_info(&self) -> &'static [ParamInfo] {
        &PARAMS
    }
    fn param_value(&self, i: usize) -> f64 {
        [self.m, self.c, self.h, self.p, self.k, self.k3, self.f][i]
    }
    fn set_param_value(&mut self, i: usize, v: f64) {
        *[
            &mut self.m,
            &mut self.c,
            &mut self.h,
            &mut self.p,
            &mut self.k,
            &mut self.k3,
            &mut self.f,
        ][i] = v;
    }
    fn signals(&self) -> &'static [Signal] {
        &SIGNALS
    }
    fn outputs(&self) -> &'static [Output] {
        &OUTPUTS
    }
    fn degree(&self) -> usize {
        3
    }
    fn equations(&self) -> &'static [&'static str] {
        &["m * D(x, 2) + c * D(x, 1) + h * D(x, p) + k * x + k3 * x^3 = F * cos(omega * t)"]
    }
    fn residual<D: DualNum<Primitive = f64> + Copy>(
        &self,
        q: &[D],
        _omega: D,
        phase: f64,
        s: &[D],
        r: &mut [D],
    ) {
        r[0] = q[0] * s[2] + q[1] * s[1] + q[2] * s[3] + q[4] * s[0] + q[5] * s[0].powi(3)
            - q[6] * phase.cos();
    }
}

/// The command line: this crate's model plus the paper's quarter car under a new name.
pub fn cli() -> ihbm::Cli {
    ihbm::Cli::new()
        .model::<BaseIsolator>("base-isolator")
        .model::<ihbm::models::QuarterCar>("my-quarter-car")
}

fn main() -> std::process::ExitCode {
    cli().run()
}
