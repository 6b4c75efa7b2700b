// A domain whose lower end is above its upper end.
ihbm_macros::oscillator! {
    pub struct Bad {
        params {
            m = 1.0,
            k = 1.0 in [2, 0],
        }
        dofs { x }
        equations { m * D(x, 2) + k * x = 0.0; }
    }
}

fn main() {}
