//! The quarter car of the reference paper (its eq. 4), dimensional, SI units, written
//! in the DSL as the README and the book show it (plus parameter docs for the units).
//!
//! ```text
//! m1 z1'' + k1 y + k3 y^3 + c y' + h D^p y = 0
//! m2 z2'' + kt (z2 - F cos Ωt) - (k1 y + k3 y^3 + c y' + h D^p y) = 0
//! y = z1 - z2
//! ```
//! z1 is the body (sprung mass m1), z2 the wheel (m2); the road input is F cos Ωt.
//! Defaults are the paper's Table 1 (the book's chapter "The method" lists the
//! paper's slips).

crate::oscillator! {
    /// Quarter-car suspension with a metal-rubber (fractional) element.
    pub struct QuarterCar {
        params {
            /// body (sprung) mass, kg
            m1 = 240.0 in (0, inf),
            /// wheel (unsprung) mass, kg
            m2 = 30.0 in (0, inf),
            /// linear suspension stiffness, N/m
            k1 = 16_000.0 in "[0, inf)",
            /// cubic suspension stiffness, N/m^3
            k3 = 10_000.0,
            /// tyre stiffness, N/m
            kt = 160_000.0 in "[0, inf)",
            /// viscous suspension damping, N s/m
            c = 1_000.0 in "[0, inf)",
            /// fractional damping coefficient, N s^p/m
            h = 1_000.0 in "[0, inf)",
            /// fractional order (dimensionless, in [0, 2])
            p = 0.5 in [0, 2],
            /// road amplitude, m
            F = 0.01,
        }
        dofs { z1, z2 }
        let y = z1 - z2;
        let fs = k1 * y + k3 * y.powi(3) + c * D(y, 1) + h * D(y, p);
        equations {
            m1 * D(z1, 2) + fs = 0.0;
            m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - fs = 0.0;
        }
        outputs { z1, z2, y }
    }
}
