//! The van der Pol oscillator, the classic self-excited model: negative damping at
//! small amplitude, positive at large, and a limit cycle between (`ihbm cycle`).
//!
//! ```text
//! van-der-pol:  m x'' - mu (1 - x^2) x' + k x = 0
//! ```
//! For small `mu` (m = k = 1) the cycle has amplitude 2 and frequency
//! `1 - mu²/16 + O(mu⁴)`.

crate::oscillator! {
    /// Van der Pol oscillator m x'' - mu (1 - x^2) x' + k x = 0 (no forcing).
    pub struct VanDerPol {
        params {
            /// mass, kg
            m = 1.0 in (0, inf),
            /// negative linear / positive cubic damping, N s/m
            mu = 0.2,
            /// stiffness, N/m
            k = 1.0 in "[0, inf)",
        }
        dofs { x }
        equations {
            m * D(x, 2) - mu * (1.0 - x.powi(2)) * D(x, 1) + k * x = 0.0;
        }
        outputs { x }
    }
}
