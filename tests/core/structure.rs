//! The structure shortcuts of the harmonic balance (`Model::affine_signals`,
//! `Model::explicit_omega`, `Model::signal_reads`): what the macro derives from the
//! equations, that the shortcut derivatives equal the general ones (grouped dual
//! passes and band storage against one pass per signal and a dense matrix), and that a
//! wrong hand-written claim is refused instead of silently giving wrong Jacobians.

use ihbm::balance::Balance;
use ihbm::linalg::Band;
use ihbm::model::{Domain, Model, Order, Output, OutputKind, ParamInfo, Signal, Text};
use ihbm::models::{BaseExcited, Duffing, FractionalDuffing, QuarterCar, TwoMassChain};
use num_dual::DualNum;
use std::borrow::Cow::Borrowed;

#[test]
fn the_macro_reads_the_structure_off_the_equations() {
    // Quarter car: m1 z1'' + k1 y + k3 y³ + c y' + h D^p y, y = z1 - z2; the cubic makes
    // z1 and z2 (the signals y³ is built from) non-affine, every derivative enters
    // linearly with a parameter coefficient, and Ω appears only in the forcing.
    let car = QuarterCar::default();
    let affine: Vec<(bool, Order)> =
        car.signals().iter().zip(car.affine_signals()).map(|(s, &a)| (a, s.order)).collect();
    for (a, order) in &affine {
        assert_eq!(*a, *order != Order::Int(0), "{affine:?}");
    }
    assert!(!car.explicit_omega());
    // Base excitation m U Ω² cos Ωt uses Ω as a coefficient.
    assert!(BaseExcited::default().explicit_omega());
    let duffing = Duffing::default();
    for (s, &a) in duffing.signals().iter().zip(duffing.affine_signals()) {
        assert_eq!(a, s.order != Order::Int(0));
    }
}

/// `∂R/∂Ω` right after `jacobian` (from the signal gradients, for models without
/// explicit Ω) against a cold evaluation (one dual pass with Ω seeded).
fn d_omega_shortcut_matches<M: Model>(model: &M, harmonics: usize, omega: f64) {
    let mut warm = Balance::new(model, harmonics).unwrap();
    let mut cold = Balance::new(model, harmonics).unwrap();
    let n = warm.len();
    let a: Vec<f64> = (0..n).map(|i| 0.01 * ((i * 7 + 3) as f64).sin()).collect();
    let mut r = vec![0.0; n];
    let mut jac = faer::Mat::<f64>::zeros(n, n);
    warm.jacobian(&a, omega, &mut r, jac.as_mut());
    let (mut d1, mut d2) = (vec![0.0; n], vec![0.0; n]);
    warm.d_omega(&a, omega, &mut d1);
    cold.d_omega(&a, omega, &mut d2);
    let scale = d2.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    for (x, y) in d1.iter().zip(&d2) {
        assert!((x - y).abs() <= 1e-12 * scale, "{}: {x} vs {y}", model.name());
    }
}

#[test]
fn d_omega_from_gradients_equals_the_dual_pass() {
    d_omega_shortcut_matches(&QuarterCar { k3: 5e6, ..Default::default() }, 5, 13.0);
    d_omega_shortcut_matches(&Duffing::default(), 4, 1.3);
    d_omega_shortcut_matches(&FractionalDuffing::default(), 3, 0.7);
    d_omega_shortcut_matches(&TwoMassChain::default(), 3, 2.1);
    // explicit Ω: the shortcut is not taken, the two must agree trivially
    d_omega_shortcut_matches(&BaseExcited::default(), 3, 5.0);
}

/// A cubic oscillator written by hand, with structure claims set per instance.
#[derive(Clone)]
struct Claims {
    affine: &'static [bool],
    reads: &'static [bool],
    explicit_omega: bool,
    omega_in_forcing_amplitude: bool,
}

impl Model for Claims {
    fn name(&self) -> &str {
        "claims"
    }
    fn dofs(&self) -> &[Text] {
        const DOFS: &[Text] = &[Borrowed("x")];
        DOFS
    }
    fn params_info(&self) -> &[ParamInfo] {
        const P: &[ParamInfo] = &[ParamInfo {
            name: Borrowed("k3"),
            default: 1.0,
            doc: Borrowed("cubic"),
            domain: Domain::ANY,
        }];
        P
    }
    fn param_value(&self, _: usize) -> f64 {
        1.0
    }
    fn set_param_value(&mut self, _: usize, _: f64) {}
    fn signals(&self) -> &[Signal] {
        const X: &[(usize, f64)] = &[(0, 1.0)];
        const S: &[Signal] = &[
            Signal { terms: Borrowed(X), order: Order::Int(0) },
            Signal { terms: Borrowed(X), order: Order::Int(1) },
            Signal { terms: Borrowed(X), order: Order::Int(2) },
        ];
        S
    }
    fn outputs(&self) -> &[Output] {
        const O: &[Output] =
            &[Output { name: Borrowed("x"), kind: OutputKind::Dofs(Borrowed(&[(0, 1.0)])) }];
        O
    }
    fn degree(&self) -> usize {
        3
    }
    fn affine_signals(&self) -> &[bool] {
        self.affine
    }
    fn signal_reads(&self) -> &[bool] {
        self.reads
    }
    fn explicit_omega(&self) -> bool {
        self.explicit_omega
    }
    fn residual<D: DualNum<Primitive = f64> + Copy>(
        &self,
        p: &[D],
        omega: D,
        phase: f64,
        s: &[D],
        r: &mut [D],
    ) {
        let amp = if self.omega_in_forcing_amplitude { omega * omega } else { D::one() };
        r[0] = s[2] + s[1] * 0.1 + s[0] + p[0] * s[0].powi(3) - amp * phase.cos();
    }
}

#[test]
fn wrong_structure_claims_are_refused() {
    let honest = Claims {
        affine: &[false, true, true],
        reads: &[true, true, true],
        explicit_omega: false,
        omega_in_forcing_amplitude: false,
    };
    assert!(Balance::new(&honest, 3).is_ok());
    let cubic_claimed_affine = Claims { affine: &[true, true, true], ..honest.clone() };
    let err = Balance::new(&cubic_claimed_affine, 3).unwrap_err().to_string();
    assert!(err.contains("affine") && err.contains("signal 0"), "{err}");
    let wrong_length = Claims { affine: &[true], ..honest.clone() };
    let err = Balance::new(&wrong_length, 3).unwrap_err().to_string();
    assert!(err.contains("1 entries for 3 signals"), "{err}");
    // the equation reads x' (0.1 x'): a claim that it does not is refused
    let damping_unread = Claims { reads: &[true, false, true], ..honest.clone() };
    let err = Balance::new(&damping_unread, 3).unwrap_err().to_string();
    assert!(err.contains("does not read signal 1"), "{err}");
    let reads_short = Claims { reads: &[true, true], ..honest.clone() };
    let err = Balance::new(&reads_short, 3).unwrap_err().to_string();
    assert!(err.contains("2 entries for 1 equations × 3 signals"), "{err}");
    let hidden_omega = Claims { omega_in_forcing_amplitude: true, ..honest };
    let err = Balance::new(&hidden_omega, 3).unwrap_err().to_string();
    assert!(err.contains("explicit_omega"), "{err}");
}

proptest::proptest! {
    /// `Domain::contains` against the bounds: an end is in exactly when it is closed,
    /// every number strictly between the ends is in, every number beyond an end is out,
    /// an unbounded side holds every finite number, and NaN is never in.
    #[test]
    fn domain_contains_agrees_with_its_bounds(
        a in -1e6..1e6f64,
        width in 1e-6..1e6f64,
        t in 0.0..1.0f64,
        beyond in 1e-6..1e6f64,
        kinds in (0..3u8, 0..3u8),
    ) {
        use ihbm::model::Bound;
        let b = a + width;
        let end = |k: u8, v: f64| match k { 0 => Bound::Unbounded, 1 => Bound::Open(v), _ => Bound::Closed(v) };
        let d = Domain { lower: end(kinds.0, a), upper: end(kinds.1, b) };
        let inner = a + t * width;
        if inner > a && inner < b {
            proptest::prop_assert!(d.contains(inner), "{d} {inner}");
        }
        proptest::prop_assert_eq!(d.contains(a), kinds.0 != 1, "{} at {}", d, a);
        proptest::prop_assert_eq!(d.contains(b), kinds.1 != 1, "{} at {}", d, b);
        proptest::prop_assert_eq!(d.contains(a - beyond), kinds.0 == 0, "{} below", d);
        proptest::prop_assert_eq!(d.contains(b + beyond), kinds.1 == 0, "{} above", d);
        proptest::prop_assert!(!d.contains(f64::NAN));
        proptest::prop_assert!(Domain::ANY.contains(a) && Domain::ANY.contains(-1e300));
    }
}

ihbm::oscillator! {
    /// Four masses in a row (the band and grouping tests): linear + cubic links.
    pub struct Row4 {
        params { m = 1.0, k = 1.0, k3 = 0.5, c = 0.02 }
        dofs { x1, x2, x3, x4 }
        let y1 = x1;
        let s1 = k * y1 + k3 * y1.powi(3) + c * D(y1, 1);
        let y2 = x2 - x1;
        let s2 = k * y2 + k3 * y2.powi(3) + c * D(y2, 1);
        let y3 = x3 - x2;
        let s3 = k * y3 + k3 * y3.powi(3) + c * D(y3, 1);
        let y4 = x4 - x3;
        let s4 = k * y4 + k3 * y4.powi(3) + c * D(y4, 1);
        equations {
            m * D(x1, 2) + s1 - s2 = 0.0;
            m * D(x2, 2) + s2 - s3 = 0.0;
            m * D(x3, 2) + s3 - s4 = 0.0;
            m * D(x4, 2) + s4 = cos(omega * t);
        }
        outputs { x4 }
    }
}

/// `M` with its `signal_reads` claim hidden: the solvers then seed one signal per
/// dual pass, the reference the grouped passes are compared with.
struct Unclaimed<M>(M);

impl<M: Model> Model for Unclaimed<M> {
    fn name(&self) -> &str {
        self.0.name()
    }
    fn dofs(&self) -> &[Text] {
        self.0.dofs()
    }
    fn params_info(&self) -> &[ParamInfo] {
        self.0.params_info()
    }
    fn param_value(&self, i: usize) -> f64 {
        self.0.param_value(i)
    }
    fn set_param_value(&mut self, i: usize, v: f64) {
        self.0.set_param_value(i, v)
    }
    fn signals(&self) -> &[Signal] {
        self.0.signals()
    }
    fn outputs(&self) -> &[Output] {
        self.0.outputs()
    }
    fn degree(&self) -> usize {
        self.0.degree()
    }
    fn affine_signals(&self) -> &[bool] {
        self.0.affine_signals()
    }
    fn explicit_omega(&self) -> bool {
        self.0.explicit_omega()
    }
    fn residual<D: ihbm::model::Scalar>(
        &self,
        p: &[D],
        omega: D,
        phase: f64,
        s: &[D],
        r: &mut [D],
    ) {
        self.0.residual(p, omega, phase, s, r)
    }
}

#[test]
fn a_row_of_masses_has_a_block_tridiagonal_jacobian_assembled_in_grouped_passes() {
    let model = Row4::default();
    let nh = 3;
    let l = 2 * nh + 1;
    // each equation reads its own link and the next: DOFs i - 1, i, i + 1
    let nsig = model.signals().len();
    let reads = model.signal_reads();
    assert_eq!(reads.len(), 4 * nsig);
    let mut grouped = Balance::new(&model, nh).unwrap();
    assert_eq!(grouped.jacobian_band(), (2 * l - 1, 2 * l - 1));
    let hidden = Unclaimed(Row4::default());
    let mut single = Balance::new(&hidden, nh).unwrap();
    // the probe finds the same band without the claim
    assert_eq!(single.jacobian_band(), (2 * l - 1, 2 * l - 1));
    let n = grouped.len();
    let a: Vec<f64> = (0..n).map(|i| 0.3 * ((i * 5 + 1) as f64).sin()).collect();
    let omega = 1.3;
    let (mut r1, mut r2) = (vec![0.0; n], vec![0.0; n]);
    let mut dense = faer::Mat::<f64>::zeros(n, n);
    single.jacobian(&a, omega, &mut r1, dense.as_mut());
    let mut band = Band::new(n, 2 * l - 1, 2 * l - 1);
    assert!(grouped.jacobian_into(&a, omega, &mut r2, &mut band));
    let scale = (0..n).fold(0.0f64, |m, j| m.max(dense[(j, j)].abs()));
    for j in 0..n {
        assert!((r1[j] - r2[j]).abs() <= 1e-14 * scale, "residual {j}");
        for i in 0..n {
            let (d, b) = (dense[(i, j)], band.get(i, j));
            assert!((d - b).abs() <= 1e-13 * scale, "({i}, {j}): one per pass {d}, grouped {b}");
            if i.abs_diff(j) > 2 * l - 1 {
                assert_eq!(d, 0.0, "({i}, {j}) outside the band");
            }
        }
    }
    // a band too narrow for the Jacobian is reported, not filled in part
    let mut narrow = Band::new(n, l - 1, l - 1);
    assert!(!grouped.jacobian_into(&a, omega, &mut r2, &mut narrow));
    // so is a dense matrix of the wrong size, and a transposed view is filled whole
    let mut small = faer::Mat::<f64>::zeros(n - 1, n - 1);
    grouped.jacobian(&a, omega, &mut r2, small.as_mut());
    assert!((0..n - 1).all(|j| (0..n - 1).all(|i| small[(i, j)].is_nan())));
    let mut t = faer::Mat::<f64>::zeros(n, n);
    grouped.jacobian(&a, omega, &mut r2, t.as_mut().transpose_mut());
    for j in 0..n {
        for i in 0..n {
            assert!((t[(j, i)] - dense[(i, j)]).abs() <= 1e-13 * scale, "transposed ({i}, {j})");
        }
    }
}
