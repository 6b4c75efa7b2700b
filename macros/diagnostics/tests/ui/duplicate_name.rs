// A let alias that reuses a parameter name.
ihbm_macros::oscillator! {
    pub struct Bad {
        params { m = 1.0, k = 1.0, F = 1.0 }
        dofs { x }
        let k = x;
        equations {
            m * D(x, 2) + k = F * cos(omega * t);
        }
    }
}

fn main() {}
