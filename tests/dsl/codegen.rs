//! Every code path of the generator at once (f64 and dual kinds, aliases of constants
//! and forcing, division, powers 0..5, parameter coefficients pulled out of `D`,
//! literal factors normalised out of a signal, sin/cos at several harmonics, `omega`
//! as a coefficient), checked against the same equations written out by hand.

use ihbm::model::{Model, Order, OutputKind, Signal};
use num_dual::Dual64;
use proptest::prelude::*;

ihbm::oscillator! {
    /// Exercises the generator.
    #[name = "kitchen-sink"]
    pub struct Sink {
        params {
            /// a coefficient
            a = 2.0,
            /// a negative default
            b = -0.5,
            /// a fractional order
            p = 0.7,
        }
        dofs { x, y }
        let half = 0.5;
        let f1 = cos(omega * t);
        let w = a * x - 2.0 * y;
        equations {
            D(x, 2) + (half * x).powi(2) + 3.0 / a * D(w, 1) + D(a * x + b * y, p) + x / a
                = half * f1 + b * sin(2 * omega * t) + omega.powi(2) * a * cos(3 * omega * t);
            D(y, 2) + 1.0 / a * y + (x - y).powi(5) + y.powi(0) - 1.0 - D(2.0 * x - 2.0 * y, 1)
                = 0.0;
        }
        outputs { x, y, d = 0.5 * x - y }
    }
}

fn find(model: &Sink, terms: &[(usize, f64)], order: Order) -> usize {
    model
        .signals()
        .iter()
        .position(|s| s.terms == terms && s.order == order)
        .unwrap_or_else(|| panic!("no signal {terms:?} {order:?} in {:?}", model.signals()))
}

#[test]
fn metadata() {
    let m = Sink::default();
    assert_eq!(m.name(), "kitchen-sink");
    assert_eq!(m.description(), "Exercises the generator.");
    assert_eq!(m.b, -0.5);
    assert_eq!(m.degree(), 5);
    assert_eq!(m.max_forcing_harmonic(), 3);
    assert_eq!(m.outputs()[2].kind, OutputKind::Dofs([(0, 0.5), (1, -1.0)].to_vec().into()));
    assert_eq!(m.params_info()[1].doc, "a negative default");
    // x, y, D²x, D²y, Dx, Dy, D^p x, D^p y, D(x - y): nine distinct signals
    assert_eq!(m.signals().len(), 9);
    let _: &[Signal] = m.signals();
}

proptest! {
    #[test]
    fn residual_matches_hand_expansion(
        sig in prop::collection::vec(-1.5f64..1.5, 9),
        a in 0.5f64..3.0,
        b in -2.0f64..2.0,
        omega in 0.1f64..4.0,
        th in 0.0f64..6.3,
    ) {
        let m = Sink { a, b, ..Sink::default() };
        let pi = m.param_index("p").unwrap();
        let s = |t: &[(usize, f64)], o: Order| sig[find(&m, t, o)];
        let (x, y) = (s(&[(0, 1.0)], Order::Int(0)), s(&[(1, 1.0)], Order::Int(0)));
        let r0 = s(&[(0, 1.0)], Order::Int(2)) + (0.5 * x).powi(2)
            + 3.0 / a * (a * s(&[(0, 1.0)], Order::Int(1)) - 2.0 * s(&[(1, 1.0)], Order::Int(1)))
            + a * s(&[(0, 1.0)], Order::Param(pi)) + b * s(&[(1, 1.0)], Order::Param(pi))
            + x / a
            - (0.5 * th.cos() + b * (2.0 * th).sin() + omega * omega * a * (3.0 * th).cos());
        let r1 = s(&[(1, 1.0)], Order::Int(2)) + y / a + (x - y).powi(5)
            - 2.0 * s(&[(0, 1.0), (1, -1.0)], Order::Int(1));
        let params: Vec<Dual64> = m.param_values().into_iter().map(Dual64::from).collect();
        let sd: Vec<Dual64> = sig.iter().map(|&v| Dual64::from(v)).collect();
        let mut out = [Dual64::from(0.0); 2];
        m.residual(&params, Dual64::from(omega), th, &sd, &mut out);
        prop_assert!((out[0].re - r0).abs() < 1e-12 * (1.0 + r0.abs()), "{} vs {r0}", out[0].re);
        prop_assert!((out[1].re - r1).abs() < 1e-12 * (1.0 + r1.abs()), "{} vs {r1}", out[1].re);
        let mut outf = [0.0; 2];
        m.residual(&m.param_values(), omega, th, &sig, &mut outf);
        // the f64 instantiation agrees with the dual one
        for e in 0..2 {
            prop_assert!((outf[e] - out[e].re).abs() <= 1e-14 * (1.0 + outf[e].abs()));
        }
    }
}
