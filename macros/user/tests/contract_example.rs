//! The exact example of the DSL reference, in a crate that depends on `ihbm` and
//! nothing else the generated code could lean on: the macro's output must name
//! everything through `ihbm`.

ihbm::oscillator! {
    /// Quarter-car suspension with a metal-rubber (fractional) element.
    pub struct QuarterCar {
        params {
            m1 = 240.0, m2 = 30.0, k1 = 16_000.0, k3 = 10_000.0,
            kt = 160_000.0, c = 1_000.0, h = 1_000.0, p = 0.5, F = 0.01,
        }
        dofs { z1, z2 }
        let y = z1 - z2;
        let fs = k1 * y + k3 * y.powi(3) + c * D(y, 1) + h * D(y, p);
        equations {
            m1 * D(z1, 2) + fs = 0.0;
            m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - fs = 0.0;
        }
        outputs { z1, z2, y }
    }
}

#[test]
fn the_reference_example_compiles_and_describes_itself() {
    use ihbm::Model;
    let mut car = QuarterCar::default();
    assert_eq!(car.name(), "quarter-car");
    assert_eq!(car.m1, 240.0);
    car.set_param("F", 0.02).unwrap();
    assert_eq!(car.F, 0.02);
    assert_eq!(car.dofs(), &["z1", "z2"]);
    assert_eq!(car.outputs().len(), 3);
    assert_eq!(car.degree(), 3);
}
