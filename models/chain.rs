//! A two-mass chain that exercises everything the DSL offers at once: quadratic and
//! cubic springs, cubic damping, a fractional damper between the masses, and forcing at
//! two harmonics. The quadratic spring makes the response asymmetric, so the mean `a0`
//! and the even harmonics are non-zero even at small forcing.
//!
//! ```text
//! m1 x1'' + c1 x1' + cc (x1')^3 + k1 x1 + kq x1^2 + k3 x1^3 + fc = F1 cos Ωt + F2 sin 2Ωt
//! m2 x2'' + c2 x2' + k2 x2 - fc = 0
//! fc = kc (x1 - x2) + hc D^p (x1 - x2)      (coupling spring and fractional damper)
//! ```
//! SI units: masses kg, displacements m, forces N.

crate::oscillator! {
    /// Two-mass chain: quadratic/cubic spring and cubic damper on mass 1, a spring and a
    /// fractional damper coupling the masses, forcing at Ω and 2Ω on mass 1.
    pub struct TwoMassChain {
        params {
            /// first mass, kg
            m1 = 1.0 in (0, inf),
            /// second mass, kg
            m2 = 0.5 in (0, inf),
            /// viscous damping of mass 1 to ground, N s/m
            c1 = 0.02 in "[0, inf)",
            /// cubic damping of mass 1 to ground, N s^3/m^3
            cc = 0.01 in "[0, inf)",
            /// linear stiffness of mass 1 to ground, N/m
            k1 = 1.0 in "[0, inf)",
            /// quadratic stiffness of mass 1 to ground, N/m^2
            kq = 0.3,
            /// cubic stiffness of mass 1 to ground, N/m^3
            k3 = 0.5,
            /// coupling stiffness between the masses, N/m
            kc = 0.5 in "[0, inf)",
            /// fractional damping coefficient between the masses, N s^p/m
            hc = 0.05 in "[0, inf)",
            /// fractional order of the coupling damper (dimensionless, in [0, 2])
            p = 0.5 in [0, 2],
            /// viscous damping of mass 2 to ground, N s/m
            c2 = 0.02 in "[0, inf)",
            /// linear stiffness of mass 2 to ground, N/m
            k2 = 0.8 in "[0, inf)",
            /// force amplitude at Ω on mass 1, N
            F1 = 0.1,
            /// force amplitude at 2Ω on mass 1, N
            F2 = 0.05,
        }
        dofs { x1, x2 }
        let rel = x1 - x2;
        let fc = kc * rel + hc * D(rel, p);
        equations {
            m1 * D(x1, 2) + c1 * D(x1, 1) + cc * D(x1, 1).powi(3)
                + k1 * x1 + kq * x1.powi(2) + k3 * x1.powi(3) + fc
                = F1 * cos(omega * t) + F2 * sin(2 * omega * t);
            m2 * D(x2, 2) + c2 * D(x2, 1) + k2 * x2 - fc = 0.0;
        }
        outputs { x1, x2, rel }
    }
}
