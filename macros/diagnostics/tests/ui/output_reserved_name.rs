// An output may be any expression, but not take a name the language keeps for itself.
ihbm_macros::oscillator! {
    pub struct Bad {
        params { m = 1.0, k = 1.0, F = 1.0 }
        dofs { x }
        let fk = k * x;
        equations {
            m * D(x, 2) + fk = F * cos(omega * t);
        }
        outputs { x, fk, omega = D(x, 1) }
    }
}

fn main() {}
