//! An oscillator with a quadratic spring, the simplest model whose response doubles its
//! period: near Ω = 2√(k/m) the term `k2 x²` excites the natural frequency
//! parametrically, and beyond a force threshold the period-1 solution loses stability
//! through a Floquet multiplier −1 (chapter "Where jumps begin", *The period-2 branch*).
//!
//! ```text
//! quadratic:  m x'' + c x' + k x + k2 x^2 = F cos Ωt
//! ```

crate::oscillator! {
    /// Quadratic oscillator m x'' + c x' + k x + k2 x^2 = F cos(Ωt).
    pub struct Quadratic {
        params {
            /// mass, kg
            m = 1.0 in (0, inf),
            /// viscous damping, N s/m
            c = 0.05,
            /// linear stiffness, N/m
            k = 1.0,
            /// quadratic stiffness, N/m^2
            k2 = 1.0,
            /// force amplitude, N
            F = 0.5,
        }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + k * x + k2 * x.powi(2) = F * cos(omega * t);
        }
        outputs { x }
    }
}
