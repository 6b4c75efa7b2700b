//! The half car: body bounce and pitch on a front and a rear suspension with
//! fractional (metal-rubber) elements and cubic springs, each wheel on its tyre, the
//! rear wheel meeting the road `τ = (a + b) / v` after the front one.
//!
//! DOFs: bounce `z` (m, up) and pitch `theta` (rad, nose up) at the centre of mass,
//! and the suspension deflections `yf`, `yr` (body minus wheel, m). The wheels are at
//! `zf = z + a θ − yf` and `zr = z − b θ − yr`. With the suspension forces
//! `fs = k y + k3 y³ + c y' + h D^p y` and the tyre forces `kt (zw − road)`:
//!
//! ```text
//! m z'' + mf zf'' + mr zr'' + ktf (zf − rf) + ktr (zr − rr) = 0
//! I θ'' + a mf zf'' − b mr zr'' + a ktf (zf − rf) − b ktr (zr − rr) = 0
//! fsf − mf zf'' − ktf (zf − rf) = 0
//! fsr − mr zr'' − ktr (zr − rr) = 0
//! rf = F cos Ωt,   rr = F cos(Ωt − Ωτ) = F cos Ωτ cos Ωt + F sin Ωτ sin Ωt
//! ```
//!
//! These are Lagrange's equations in `(z, θ, yf, yr)` (sums of the bodies' Newton
//! equations), so the mass and stiffness matrices are symmetric, as the linear modes
//! and the backbones assume. The masses, inertia, springs, viscous dampers, tyres and
//! the wheelbase split are the passive half car of H. Du and N. Zhang (2008), a set
//! reused across the active-suspension literature; the fractional elements and
//! cubic springs are the reference quarter car's (`h = 1000 N s^p/m`, `p = 0.5`,
//! `k3 = 1e4 N/m³`).

crate::oscillator! {
    /// Half car: bounce, pitch, front and rear suspension, rear road input delayed by (a+b)/v.
    pub struct HalfCar {
        params {
            /// body (sprung) mass, kg
            m = 690.0 in (0, inf),
            /// body pitch moment of inertia, kg m^2
            I = 1222.0 in (0, inf),
            /// front wheel (unsprung) mass, kg
            mf = 40.0 in (0, inf),
            /// rear wheel (unsprung) mass, kg
            mr = 45.0 in (0, inf),
            /// front suspension stiffness, N/m
            kf = 18_000.0 in "[0, inf)",
            /// rear suspension stiffness, N/m
            kr = 22_000.0 in "[0, inf)",
            /// front cubic suspension stiffness, N/m^3
            k3f = 10_000.0,
            /// rear cubic suspension stiffness, N/m^3
            k3r = 10_000.0,
            /// front viscous damping, N s/m
            cf = 1_000.0 in "[0, inf)",
            /// rear viscous damping, N s/m
            cr = 1_000.0 in "[0, inf)",
            /// front fractional damping coefficient, N s^p/m
            hf = 1_000.0 in "[0, inf)",
            /// rear fractional damping coefficient, N s^p/m
            hr = 1_000.0 in "[0, inf)",
            /// fractional order of both elements (dimensionless, in [0, 2])
            p = 0.5 in [0, 2],
            /// front tyre stiffness, N/m
            ktf = 200_000.0 in "[0, inf)",
            /// rear tyre stiffness, N/m
            ktr = 200_000.0 in "[0, inf)",
            /// centre of mass to front axle, m
            a = 1.3 in (0, inf),
            /// centre of mass to rear axle, m
            b = 1.5 in (0, inf),
            /// vehicle speed, m/s (the rear wheel meets the road (a+b)/v later)
            v = 20.0 in (0, inf),
            /// road amplitude, m
            F = 0.01,
        }
        dofs { z, theta, yf, yr }
        let zf = z + a * theta - yf;
        let zr = z - b * theta - yr;
        let fsf = kf * yf + k3f * yf.powi(3) + cf * D(yf, 1) + hf * D(yf, p);
        let fsr = kr * yr + k3r * yr.powi(3) + cr * D(yr, 1) + hr * D(yr, p);
        let tau = (a + b) / v;
        let tf = ktf * (zf - F * cos(omega * t));
        let tr = ktr * (zr - F * cos(omega * tau) * cos(omega * t) - F * sin(omega * tau) * sin(omega * t));
        equations {
            m * D(z, 2) + mf * D(zf, 2) + mr * D(zr, 2) + tf + tr = 0.0;
            I * D(theta, 2) + a * mf * D(zf, 2) - b * mr * D(zr, 2) + a * tf - b * tr = 0.0;
            fsf - mf * D(zf, 2) - tf = 0.0;
            fsr - mr * D(zr, 2) - tr = 0.0;
        }
        outputs { z, theta, yf, yr }
    }
}
