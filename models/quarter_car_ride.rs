//! The quarter car as a suspension engineer meets it: the static load, a progressive
//! bump stop, a damper stiffer in rebound than in compression, the fractional rubber
//! element of the reference paper, and a tyre that cannot pull the wheel down.
//! Coordinates are measured from the static equilibrium, so the linear parts carry no
//! preload; the tyre's total load `(m1 + m2) g - kt (z2 - z0)` is clipped at 0.
//!
//! ```text
//! m1 z1'' + fs = 0
//! m2 z2'' + (m1 + m2) g - tyre - fs = 0
//! fs   = k1 y - kb max(0, -y - gap)^2 + cr max(0, y') + cc min(0, y') + h D^p y,  y = z1 - z2
//! tyre = max(0, (m1 + m2) g - kt (z2 - F cos Ωt))
//! ```
//! Outputs: the body's acceleration, the suspension travel, the tyre's load and how
//! high the wheel is above the road (0 while it touches it). The book's chapter
//! "A quarter car with stops and lift-off" traces it.

crate::oscillator! {
    /// Quarter car with gravity, a progressive bump stop, an asymmetric damper and a tyre
    /// that can leave the road.
    pub struct QuarterCarRide {
        params {
            /// body (sprung) mass, kg
            m1 = 240.0 in (0, inf),
            /// wheel (unsprung) mass, kg
            m2 = 30.0 in (0, inf),
            /// suspension spring stiffness, N/m
            k1 = 16_000.0 in "[0, inf)",
            /// tyre stiffness, N/m
            kt = 160_000.0 in (0, inf),
            /// damping in rebound (extension), N s/m
            cr = 1_500.0 in "[0, inf)",
            /// damping in compression, N s/m
            cc = 500.0 in "[0, inf)",
            /// fractional (rubber) damping coefficient, N s^p/m
            h = 1_000.0 in "[0, inf)",
            /// fractional order (dimensionless, in [0, 2])
            p = 0.5 in [0, 2],
            /// compression travel before the bump stop engages, m
            gap = 0.03 in "[0, inf)",
            /// progressive bump-stop stiffness (force kb s^2 at s beyond the gap), N/m^2
            kb = 2.0e7 in "[0, inf)",
            /// gravitational acceleration, m/s^2
            g = 9.81 in "[0, inf)",
            /// road amplitude, m
            F = 0.01,
        }
        dofs { z1, z2 }
        let y = z1 - z2;
        let fs = k1 * y - kb * max(0.0, -y - gap).powi(2) + cr * max(0.0, D(y, 1))
            + cc * min(0.0, D(y, 1)) + h * D(y, p);
        let load = (m1 + m2) * g;
        let tyre = max(0.0, load - kt * (z2 - F * cos(omega * t)));
        equations {
            m1 * D(z1, 2) + fs = 0.0;
            m2 * D(z2, 2) + load - tyre - fs = 0.0;
        }
        outputs {
            z1, travel = z1 - z2, acc = D(z1, 2), tyre,
            air = max(0.0, z2 - F * cos(omega * t) - load / kt)
        }
    }
}
