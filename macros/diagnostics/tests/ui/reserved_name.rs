// `omega` is the forcing frequency and cannot be redeclared.
ihbm_macros::oscillator! {
    pub struct Bad {
        params { m = 1.0, omega = 1.0, F = 1.0 }
        dofs { x }
        equations {
            m * D(x, 2) + x = F * cos(omega * t);
        }
    }
}

fn main() {}
