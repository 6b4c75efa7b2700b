// An open interval with equal ends holds no number.
ihbm_macros::oscillator! {
    pub struct Bad {
        params {
            m = 1.0,
            k = 1.0 in (1, 1),
        }
        dofs { x }
        equations { m * D(x, 2) + k * x = 0.0; }
    }
}

fn main() {}
