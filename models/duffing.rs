//! The Duffing oscillator and its fractional twin, the test models with closed forms.
//!
//! ```text
//! duffing:             m x'' + c x' + k x + k3 x^3            = F cos Ωt
//! fractional-duffing:  m x'' + c x' + k x + k3 x^3 + h D^p x  = F cos Ωt
//! ```
//! Units are the user's (consistent SI by default: kg, N s/m, N/m, N/m^3, N s^p/m, N).

use crate::model::{Model, Order, Output, ParamInfo, Signal};
use num_dual::DualNum;

const X: &[(usize, f64)] = &[(0, 1.0)];
const OUTPUTS: [Output; 1] = [Output { name: "x", terms: X }];

/// `m x'' + c x' + k x + k3 x^3 = F cos Ωt`.
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)] // `F` as in the paper and the DSL
pub struct Duffing {
    /// Mass.
    pub m: f64,
    /// Viscous damping.
    pub c: f64,
    /// Linear stiffness.
    pub k: f64,
    /// Cubic stiffness.
    pub k3: f64,
    /// Force amplitude.
    pub F: f64,
}

const DUFFING_PARAMS: [ParamInfo; 5] = [
    ParamInfo { name: "m", default: 1.0, doc: "mass, kg" },
    ParamInfo { name: "c", default: 0.1, doc: "viscous damping, N s/m" },
    ParamInfo { name: "k", default: 1.0, doc: "linear stiffness, N/m" },
    ParamInfo { name: "k3", default: 1.0, doc: "cubic stiffness, N/m^3" },
    ParamInfo { name: "F", default: 0.5, doc: "force amplitude, N" },
];
const DUFFING_SIGNALS: [Signal; 3] = [
    Signal { terms: X, order: Order::Int(0) },
    Signal { terms: X, order: Order::Int(1) },
    Signal { terms: X, order: Order::Int(2) },
];

impl Default for Duffing {
    fn default() -> Self {
        Duffing { m: 1.0, c: 0.1, k: 1.0, k3: 1.0, F: 0.5 }
    }
}

impl Model for Duffing {
    fn name(&self) -> &'static str {
        "duffing"
    }
    fn description(&self) -> &'static str {
        "Duffing oscillator m x'' + c x' + k x + k3 x^3 = F cos(Ωt)"
    }
    fn dofs(&self) -> &'static [&'static str] {
        &["x"]
    }
    fn params_info(&self) -> &'static [ParamInfo] {
        &DUFFING_PARAMS
    }
    fn param_value(&self, index: usize) -> f64 {
        [self.m, self.c, self.k, self.k3, self.F][index]
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        *[&mut self.m, &mut self.c, &mut self.k, &mut self.k3, &mut self.F][index] = value;
    }
    fn signals(&self) -> &'static [Signal] {
        &DUFFING_SIGNALS
    }
    fn outputs(&self) -> &'static [Output] {
        &OUTPUTS
    }
    fn degree(&self) -> usize {
        3
    }
    fn equations(&self) -> &'static [&'static str] {
        &["m * D(x, 2) + c * D(x, 1) + k * x + k3 * x^3 = F * cos(omega * t)"]
    }
    #[inline]
    fn residual<D: DualNum<Primitive = f64> + Copy>(
        &self,
        p: &[D],
        _omega: D,
        phase: f64,
        s: &[D],
        out: &mut [D],
    ) {
        let x = s[0];
        out[0] = p[0] * s[2] + p[1] * s[1] + p[2] * x + p[3] * x * x * x - p[4] * phase.cos();
    }
}

/// `m x'' + c x' + k x + k3 x^3 + h D^p x = F cos Ωt`.
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)] // `F` as in the paper and the DSL
pub struct FractionalDuffing {
    /// Mass.
    pub m: f64,
    /// Viscous damping.
    pub c: f64,
    /// Linear stiffness.
    pub k: f64,
    /// Cubic stiffness.
    pub k3: f64,
    /// Fractional damping coefficient.
    pub h: f64,
    /// Fractional order.
    pub p: f64,
    /// Force amplitude.
    pub F: f64,
}

const FRAC_PARAMS: [ParamInfo; 7] = [
    ParamInfo { name: "m", default: 1.0, doc: "mass, kg" },
    ParamInfo { name: "c", default: 0.05, doc: "viscous damping, N s/m" },
    ParamInfo { name: "k", default: 1.0, doc: "linear stiffness, N/m" },
    ParamInfo { name: "k3", default: 1.0, doc: "cubic stiffness, N/m^3" },
    ParamInfo { name: "h", default: 0.1, doc: "fractional damping coefficient, N s^p/m" },
    ParamInfo { name: "p", default: 0.5, doc: "fractional order" },
    ParamInfo { name: "F", default: 0.5, doc: "force amplitude, N" },
];
const FRAC_SIGNALS: [Signal; 4] = [
    Signal { terms: X, order: Order::Int(0) },
    Signal { terms: X, order: Order::Int(1) },
    Signal { terms: X, order: Order::Int(2) },
    Signal { terms: X, order: Order::Param(5) },
];

impl Default for FractionalDuffing {
    fn default() -> Self {
        FractionalDuffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.1, p: 0.5, F: 0.5 }
    }
}

impl Model for FractionalDuffing {
    fn name(&self) -> &'static str {
        "fractional-duffing"
    }
    fn description(&self) -> &'static str {
        "Fractional Duffing oscillator m x'' + c x' + k x + k3 x^3 + h D^p x = F cos(Ωt)"
    }
    fn dofs(&self) -> &'static [&'static str] {
        &["x"]
    }
    fn params_info(&self) -> &'static [ParamInfo] {
        &FRAC_PARAMS
    }
    fn param_value(&self, index: usize) -> f64 {
        [self.m, self.c, self.k, self.k3, self.h, self.p, self.F][index]
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        *[
            &mut self.m,
            &mut self.c,
            &mut self.k,
            &mut self.k3,
            &mut self.h,
            &mut self.p,
            &mut self.F,
        ][index] = value;
    }
    fn signals(&self) -> &'static [Signal] {
        &FRAC_SIGNALS
    }
    fn outputs(&self) -> &'static [Output] {
        &OUTPUTS
    }
    fn degree(&self) -> usize {
        3
    }
    fn equations(&self) -> &'static [&'static str] {
        &["m * D(x, 2) + c * D(x, 1) + k * x + k3 * x^3 + h * D(x, p) = F * cos(omega * t)"]
    }
    #[inline]
    fn residual<D: DualNum<Primitive = f64> + Copy>(
        &self,
        p: &[D],
        _omega: D,
        phase: f64,
        s: &[D],
        out: &mut [D],
    ) {
        let x = s[0];
        out[0] = p[0] * s[2] + p[1] * s[1] + p[2] * x + p[3] * x * x * x + p[4] * s[3]
            - p[6] * phase.cos();
    }
}
