// In a quoted interval (a half-open one), the same checks apply; a proc-macro cannot point inside the string, so the span is the literal.
ihbm_macros::oscillator! {
    pub struct Bad {
        params {
            m = 1.0,
            k = 1.0 in "(0, inf]",
        }
        dofs { x }
        equations { m * D(x, 2) + k * x = 0.0; }
    }
}

fn main() {}
