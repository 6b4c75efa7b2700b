//! A base-excited oscillator with a fractional element of order p in (1, 2) (between a
//! damper, p = 1, and an inertia-like term, p = 2), written in the relative coordinate
//! y = x - u of a mass on a moving base u = U cos Ωt:
//!
//! ```text
//! m y'' + c y' + k y + k3 y^3 + h D^p y = m U Ω^2 cos Ωt
//! ```
//! The forcing amplitude grows with Ω^2 (`omega` used as a coefficient). SI units:
//! y and U in m, forces in N.

crate::oscillator! {
    /// Base-excited mass with a cubic spring and a fractional element of order p in (1, 2),
    /// in the relative coordinate y = x - u, base motion u = U cos(Ωt).
    pub struct BaseExcited {
        params {
            /// mass, kg
            m = 1.0 in (0, inf),
            /// viscous damping, N s/m
            c = 0.05 in "[0, inf)",
            /// linear stiffness, N/m
            k = 1.0 in "[0, inf)",
            /// cubic stiffness, N/m^3
            k3 = 0.5,
            /// fractional element coefficient, N s^p/m
            h = 0.05 in "[0, inf)",
            /// fractional order (dimensionless, in (1, 2) for this model)
            p = 1.5 in (1, 2),
            /// base displacement amplitude, m
            U = 0.1,
        }
        dofs { y }
        equations {
            m * D(y, 2) + c * D(y, 1) + k * y + k3 * y.powi(3) + h * D(y, p)
                = m * U * omega.powi(2) * cos(omega * t);
        }
        outputs { y }
    }
}
