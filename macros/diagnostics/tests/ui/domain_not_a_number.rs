// A bound must be a number, `inf` or `-inf`.
ihbm_macros::oscillator! {
    pub struct Bad {
        params {
            m = 1.0,
            k = 1.0 in (0, k3),
        }
        dofs { x }
        equations { m * D(x, 2) + k * x = 0.0; }
    }
}

fn main() {}
