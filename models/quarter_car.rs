//! The quarter car of the reference paper (its eq. 4), dimensional, SI units.
//!
//! ```text
//! m1 z1'' + k1 y + k3 y^3 + c y' + h D^p y = 0
//! m2 z2'' + kt (z2 - F cos Ωt) - (k1 y + k3 y^3 + c y' + h D^p y) = 0
//! y = z1 - z2
//! ```
//! z1 is the body (sprung mass m1), z2 the wheel (m2); the road input is F cos Ωt.

use crate::model::{Model, Order, Output, ParamInfo, Signal};
use num_dual::DualNum;

/// Quarter-car suspension with a metal-rubber (fractional) element; Table 1 defaults.
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)] // `F` as in the paper and the DSL
pub struct QuarterCar {
    /// Body (sprung) mass, kg.
    pub m1: f64,
    /// Wheel/tyre (unsprung) mass, kg.
    pub m2: f64,
    /// Linear suspension stiffness, N/m.
    pub k1: f64,
    /// Cubic suspension stiffness, N/m^3.
    pub k3: f64,
    /// Tyre stiffness, N/m.
    pub kt: f64,
    /// Viscous suspension damping, N s/m.
    pub c: f64,
    /// Fractional damping coefficient, N s^p/m.
    pub h: f64,
    /// Fractional order.
    pub p: f64,
    /// Road amplitude, m.
    pub F: f64,
}

const PARAMS: [ParamInfo; 9] = [
    ParamInfo { name: "m1", default: 240.0, doc: "body (sprung) mass, kg" },
    ParamInfo { name: "m2", default: 30.0, doc: "wheel (unsprung) mass, kg" },
    ParamInfo { name: "k1", default: 16_000.0, doc: "linear suspension stiffness, N/m" },
    ParamInfo { name: "k3", default: 10_000.0, doc: "cubic suspension stiffness, N/m^3" },
    ParamInfo { name: "kt", default: 160_000.0, doc: "tyre stiffness, N/m" },
    ParamInfo { name: "c", default: 1_000.0, doc: "viscous suspension damping, N s/m" },
    ParamInfo { name: "h", default: 1_000.0, doc: "fractional damping coefficient, N s^p/m" },
    ParamInfo { name: "p", default: 0.5, doc: "fractional order" },
    ParamInfo { name: "F", default: 0.01, doc: "road amplitude, m" },
];

const Z1: &[(usize, f64)] = &[(0, 1.0)];
const Z2: &[(usize, f64)] = &[(1, 1.0)];
const Y: &[(usize, f64)] = &[(0, 1.0), (1, -1.0)];
const SIGNALS: [Signal; 6] = [
    Signal { terms: Z1, order: Order::Int(0) },
    Signal { terms: Z2, order: Order::Int(0) },
    Signal { terms: Z1, order: Order::Int(2) },
    Signal { terms: Z2, order: Order::Int(2) },
    Signal { terms: Y, order: Order::Int(1) },
    Signal { terms: Y, order: Order::Param(7) },
];
const OUTPUTS: [Output; 3] = [
    Output { name: "z1", terms: Z1 },
    Output { name: "z2", terms: Z2 },
    Output { name: "y", terms: Y },
];

impl Default for QuarterCar {
    fn default() -> Self {
        QuarterCar {
            m1: 240.0,
            m2: 30.0,
            k1: 16_000.0,
            k3: 10_000.0,
            kt: 160_000.0,
            c: 1_000.0,
            h: 1_000.0,
            p: 0.5,
            F: 0.01,
        }
    }
}

impl QuarterCar {
    fn fields(&mut self) -> [&mut f64; 9] {
        [
            &mut self.m1,
            &mut self.m2,
            &mut self.k1,
            &mut self.k3,
            &mut self.kt,
            &mut self.c,
            &mut self.h,
            &mut self.p,
            &mut self.F,
        ]
    }
}

impl Model for QuarterCar {
    fn name(&self) -> &'static str {
        "quarter-car"
    }
    fn description(&self) -> &'static str {
        "Quarter-car suspension with a metal-rubber (fractional) element (reference paper, eq. 4)"
    }
    fn dofs(&self) -> &'static [&'static str] {
        &["z1", "z2"]
    }
    fn params_info(&self) -> &'static [ParamInfo] {
        &PARAMS
    }
    fn param_value(&self, index: usize) -> f64 {
        [self.m1, self.m2, self.k1, self.k3, self.kt, self.c, self.h, self.p, self.F][index]
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        *self.fields()[index] = value;
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
        &[
            "m1 * D(z1, 2) + fs = 0",
            "m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - fs = 0",
            "where y = z1 - z2, fs = k1 * y + k3 * y^3 + c * D(y, 1) + h * D(y, p)",
        ]
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
        let (m1, m2, k1, k3, kt, c, h, f) = (p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[8]);
        let y = s[0] - s[1];
        let fs = k1 * y + k3 * y * y * y + c * s[4] + h * s[5];
        out[0] = m1 * s[2] + fs;
        out[1] = m2 * s[3] + kt * (s[1] - f * phase.cos()) - fs;
    }
}
