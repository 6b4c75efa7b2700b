//! The hand-written models the DSL replaced, kept as an independent reference: the
//! tests compare the `oscillator!` twins against them sample by sample and harmonic by
//! harmonic, and `benches/dsl.rs` times both. A test fixture, not shipped in the library.

/// Hand-written quarter car (reference paper, eq. 4).
pub mod quarter_car {

    use ihbm::model::{Bound, Domain, Model, Order, Output, OutputKind, ParamInfo, Signal, Text};
    use num_dual::DualNum;
    use std::borrow::Cow::Borrowed;

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

    const PARAMS: &[ParamInfo] = &[
        ParamInfo {
            name: Borrowed("m1"),
            default: 240.0,
            doc: Borrowed("body (sprung) mass, kg"),
            domain: Domain { lower: Bound::Open(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("m2"),
            default: 30.0,
            doc: Borrowed("wheel (unsprung) mass, kg"),
            domain: Domain { lower: Bound::Open(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("k1"),
            default: 16_000.0,
            doc: Borrowed("linear suspension stiffness, N/m"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("k3"),
            default: 10_000.0,
            doc: Borrowed("cubic suspension stiffness, N/m^3"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("kt"),
            default: 160_000.0,
            doc: Borrowed("tyre stiffness, N/m"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("c"),
            default: 1_000.0,
            doc: Borrowed("viscous suspension damping, N s/m"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("h"),
            default: 1_000.0,
            doc: Borrowed("fractional damping coefficient, N s^p/m"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("p"),
            default: 0.5,
            doc: Borrowed("fractional order"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Closed(2.0) },
        },
        ParamInfo {
            name: Borrowed("F"),
            default: 0.01,
            doc: Borrowed("road amplitude, m"),
            domain: Domain::ANY,
        },
    ];

    const Z1: &[(usize, f64)] = &[(0, 1.0)];
    const Z2: &[(usize, f64)] = &[(1, 1.0)];
    const Y: &[(usize, f64)] = &[(0, 1.0), (1, -1.0)];
    const SIGNALS: &[Signal] = &[
        Signal { terms: Borrowed(Z1), order: Order::Int(0) },
        Signal { terms: Borrowed(Z2), order: Order::Int(0) },
        Signal { terms: Borrowed(Z1), order: Order::Int(2) },
        Signal { terms: Borrowed(Z2), order: Order::Int(2) },
        Signal { terms: Borrowed(Y), order: Order::Int(1) },
        Signal { terms: Borrowed(Y), order: Order::Param(7) },
    ];
    const OUTPUTS: &[Output] = &[
        Output { name: Borrowed("z1"), kind: OutputKind::Dofs(Borrowed(Z1)) },
        Output { name: Borrowed("z2"), kind: OutputKind::Dofs(Borrowed(Z2)) },
        Output { name: Borrowed("y"), kind: OutputKind::Dofs(Borrowed(Y)) },
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
        fn name(&self) -> &str {
            "quarter-car"
        }
        fn description(&self) -> &str {
            "Quarter-car suspension with a metal-rubber (fractional) element (reference paper, eq. 4)"
        }
        fn dofs(&self) -> &[Text] {
            const DOFS: &[Text] = &[Borrowed("z1"), Borrowed("z2")];
            DOFS
        }
        fn params_info(&self) -> &[ParamInfo] {
            PARAMS
        }
        fn param_value(&self, index: usize) -> f64 {
            [self.m1, self.m2, self.k1, self.k3, self.kt, self.c, self.h, self.p, self.F][index]
        }
        fn set_param_value(&mut self, index: usize, value: f64) {
            *self.fields()[index] = value;
        }
        fn signals(&self) -> &[Signal] {
            SIGNALS
        }
        fn outputs(&self) -> &[Output] {
            OUTPUTS
        }
        fn degree(&self) -> usize {
            3
        }
        fn equations(&self) -> &[Text] {
            const EQUATIONS: &[Text] = &[
                Borrowed("m1 * D(z1, 2) + fs = 0"),
                Borrowed("m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - fs = 0"),
                Borrowed("where y = z1 - z2, fs = k1 * y + k3 * y^3 + c * D(y, 1) + h * D(y, p)"),
            ];
            EQUATIONS
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
}

/// Hand-written Duffing and fractional Duffing oscillators.
pub mod duffing {

    use ihbm::model::{Bound, Domain, Model, Order, Output, OutputKind, ParamInfo, Signal, Text};
    use num_dual::DualNum;
    use std::borrow::Cow::Borrowed;

    const X: &[(usize, f64)] = &[(0, 1.0)];
    const OUTPUTS: &[Output] =
        &[Output { name: Borrowed("x"), kind: OutputKind::Dofs(Borrowed(X)) }];

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

    const DUFFING_PARAMS: &[ParamInfo] = &[
        ParamInfo {
            name: Borrowed("m"),
            default: 1.0,
            doc: Borrowed("mass, kg"),
            domain: Domain { lower: Bound::Open(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("c"),
            default: 0.1,
            doc: Borrowed("viscous damping, N s/m"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("k"),
            default: 1.0,
            doc: Borrowed("linear stiffness, N/m"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("k3"),
            default: 1.0,
            doc: Borrowed("cubic stiffness, N/m^3"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("F"),
            default: 0.5,
            doc: Borrowed("force amplitude, N"),
            domain: Domain::ANY,
        },
    ];
    const DUFFING_SIGNALS: &[Signal] = &[
        Signal { terms: Borrowed(X), order: Order::Int(0) },
        Signal { terms: Borrowed(X), order: Order::Int(1) },
        Signal { terms: Borrowed(X), order: Order::Int(2) },
    ];

    impl Default for Duffing {
        fn default() -> Self {
            Duffing { m: 1.0, c: 0.1, k: 1.0, k3: 1.0, F: 0.5 }
        }
    }

    impl Model for Duffing {
        fn name(&self) -> &str {
            "duffing"
        }
        fn description(&self) -> &str {
            "Duffing oscillator m x'' + c x' + k x + k3 x^3 = F cos(Ωt)"
        }
        fn dofs(&self) -> &[Text] {
            const DOFS: &[Text] = &[Borrowed("x")];
            DOFS
        }
        fn params_info(&self) -> &[ParamInfo] {
            DUFFING_PARAMS
        }
        fn param_value(&self, index: usize) -> f64 {
            [self.m, self.c, self.k, self.k3, self.F][index]
        }
        fn set_param_value(&mut self, index: usize, value: f64) {
            *[&mut self.m, &mut self.c, &mut self.k, &mut self.k3, &mut self.F][index] = value;
        }
        fn signals(&self) -> &[Signal] {
            DUFFING_SIGNALS
        }
        fn outputs(&self) -> &[Output] {
            OUTPUTS
        }
        fn degree(&self) -> usize {
            3
        }
        fn equations(&self) -> &[Text] {
            const EQUATIONS: &[Text] =
                &[Borrowed("m * D(x, 2) + c * D(x, 1) + k * x + k3 * x^3 = F * cos(omega * t)")];
            EQUATIONS
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

    const FRAC_PARAMS: &[ParamInfo] = &[
        ParamInfo {
            name: Borrowed("m"),
            default: 1.0,
            doc: Borrowed("mass, kg"),
            domain: Domain { lower: Bound::Open(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("c"),
            default: 0.05,
            doc: Borrowed("viscous damping, N s/m"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("k"),
            default: 1.0,
            doc: Borrowed("linear stiffness, N/m"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("k3"),
            default: 1.0,
            doc: Borrowed("cubic stiffness, N/m^3"),
            domain: Domain::ANY,
        },
        ParamInfo {
            name: Borrowed("h"),
            default: 0.1,
            doc: Borrowed("fractional damping coefficient, N s^p/m"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Unbounded },
        },
        ParamInfo {
            name: Borrowed("p"),
            default: 0.5,
            doc: Borrowed("fractional order"),
            domain: Domain { lower: Bound::Closed(0.0), upper: Bound::Closed(2.0) },
        },
        ParamInfo {
            name: Borrowed("F"),
            default: 0.5,
            doc: Borrowed("force amplitude, N"),
            domain: Domain::ANY,
        },
    ];
    const FRAC_SIGNALS: &[Signal] = &[
        Signal { terms: Borrowed(X), order: Order::Int(0) },
        Signal { terms: Borrowed(X), order: Order::Int(1) },
        Signal { terms: Borrowed(X), order: Order::Int(2) },
        Signal { terms: Borrowed(X), order: Order::Param(5) },
    ];

    impl Default for FractionalDuffing {
        fn default() -> Self {
            FractionalDuffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.1, p: 0.5, F: 0.5 }
        }
    }

    impl Model for FractionalDuffing {
        fn name(&self) -> &str {
            "fractional-duffing"
        }
        fn description(&self) -> &str {
            "Fractional Duffing oscillator m x'' + c x' + k x + k3 x^3 + h D^p x = F cos(Ωt)"
        }
        fn dofs(&self) -> &[Text] {
            const DOFS: &[Text] = &[Borrowed("x")];
            DOFS
        }
        fn params_info(&self) -> &[ParamInfo] {
            FRAC_PARAMS
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
        fn signals(&self) -> &[Signal] {
            FRAC_SIGNALS
        }
        fn outputs(&self) -> &[Output] {
            OUTPUTS
        }
        fn degree(&self) -> usize {
            3
        }
        fn equations(&self) -> &[Text] {
            const EQUATIONS: &[Text] = &[Borrowed(
                "m * D(x, 2) + c * D(x, 1) + k * x + k3 * x^3 + h * D(x, p) = F * cos(omega * t)",
            )];
            EQUATIONS
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
}

pub use duffing::{Duffing, FractionalDuffing};
pub use quarter_car::QuarterCar;
