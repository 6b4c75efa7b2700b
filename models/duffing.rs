//! The Duffing oscillator and its fractional twin, the test models with closed forms.
//!
//! ```text
//! duffing:             m x'' + c x' + k x + k3 x^3            = F cos Ωt
//! fractional-duffing:  m x'' + c x' + k x + k3 x^3 + h D^p x  = F cos Ωt
//! ```
//! Units are the user's (consistent SI by default: kg, N s/m, N/m, N/m^3, N s^p/m, N).

crate::oscillator! {
    /// Duffing oscillator m x'' + c x' + k x + k3 x^3 = F cos(Ωt).
    pub struct Duffing {
        params {
            /// mass, kg
            m = 1.0 in (0, inf),
            /// viscous damping, N s/m
            c = 0.1,
            /// linear stiffness, N/m
            k = 1.0,
            /// cubic stiffness, N/m^3
            k3 = 1.0,
            /// force amplitude, N
            F = 0.5,
        }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3) = F * cos(omega * t);
        }
        outputs { x }
    }
}

crate::oscillator! {
    /// Fractional Duffing oscillator m x'' + c x' + k x + k3 x^3 + h D^p x = F cos(Ωt).
    pub struct FractionalDuffing {
        params {
            /// mass, kg
            m = 1.0 in (0, inf),
            /// viscous damping, N s/m
            c = 0.05,
            /// linear stiffness, N/m
            k = 1.0,
            /// cubic stiffness, N/m^3
            k3 = 1.0,
            /// fractional damping coefficient, N s^p/m
            h = 0.1 in "[0, inf)",
            /// fractional order (dimensionless, in [0, 2])
            p = 0.5 in [0, 2],
            /// force amplitude, N
            F = 0.5,
        }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3) + h * D(x, p) = F * cos(omega * t);
        }
        outputs { x }
    }
}
