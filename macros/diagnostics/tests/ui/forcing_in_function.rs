// A function of forcing is not a sum of harmonics.
ihbm_macros::oscillator! {
    pub struct Bad {
        params { m = 1.0, k = 1.0, p = 0.5, F = 1.0, tau = 0.1 }
        dofs { z1, z2 }
        let y = z1 - z2;
        equations {
            m * D(z1, 2) + k * y = F * exp(cos(omega * t));
            m * D(z2, 2) + k * z2 = F * cos(omega * t);
        }
    }
}

fn main() {}
