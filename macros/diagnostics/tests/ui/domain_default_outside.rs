// A default outside its own domain (the base-excited order p in (1, 2) at 0.5).
ihbm_macros::oscillator! {
    pub struct Bad {
        params {
            m = 1.0,
            k = 0.5 in (1, 2),
        }
        dofs { x }
        equations { m * D(x, 2) + k * x = 0.0; }
    }
}

fn main() {}
