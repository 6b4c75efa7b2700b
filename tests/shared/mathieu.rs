//! The forced damped Mathieu equation `m x'' + c x' + k (1 + ε cos Ωt) x = F cos Ωt`
//! written by hand, and its monodromy matrix integrated by RK4: the independent
//! reference of the stability tests (`tests/stability/mathieu.rs`) and of the DSL's
//! parametric excitation (`tests/dsl/parametric.rs`), shared so that both check
//! against one model. A test fixture, not shipped in the library.
#![allow(dead_code)]

use ihbm::bifurcation::{fold_curves, Boundary, FoldCurveOptions};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::model::{Domain, Model, Order, Output, OutputKind, ParamInfo, Signal, Text};
use ihbm::results::BifurcationKind;
use num_dual::DualNum;
use std::borrow::Cow::Borrowed;

/// The hand-written model (parameters as named in `params_info`).
#[derive(Clone)]
pub struct Mathieu {
    pub m: f64,
    pub c: f64,
    pub k: f64,
    pub eps: f64,
    pub f: f64,
}

const X: &[(usize, f64)] = &[(0, 1.0)];

impl Model for Mathieu {
    fn name(&self) -> &str {
        "mathieu"
    }
    fn dofs(&self) -> &[Text] {
        const DOFS: &[Text] = &[Borrowed("x")];
        DOFS
    }
    fn params_info(&self) -> &[ParamInfo] {
        const P: &[ParamInfo] = &[
            ParamInfo { name: Borrowed("m"), default: 1.0, doc: Borrowed(""), domain: Domain::ANY },
            ParamInfo {
                name: Borrowed("c"),
                default: 0.05,
                doc: Borrowed(""),
                domain: Domain::ANY,
            },
            ParamInfo { name: Borrowed("k"), default: 1.0, doc: Borrowed(""), domain: Domain::ANY },
            ParamInfo {
                name: Borrowed("eps"),
                default: 0.4,
                doc: Borrowed(""),
                domain: Domain::ANY,
            },
            ParamInfo { name: Borrowed("F"), default: 0.1, doc: Borrowed(""), domain: Domain::ANY },
        ];
        P
    }
    fn param_value(&self, i: usize) -> f64 {
        [self.m, self.c, self.k, self.eps, self.f][i]
    }
    fn set_param_value(&mut self, i: usize, v: f64) {
        *[&mut self.m, &mut self.c, &mut self.k, &mut self.eps, &mut self.f][i] = v;
    }
    fn signals(&self) -> &[Signal] {
        const S: &[Signal] = &[
            Signal { terms: Borrowed(X), order: Order::Int(0) },
            Signal { terms: Borrowed(X), order: Order::Int(1) },
            Signal { terms: Borrowed(X), order: Order::Int(2) },
        ];
        S
    }
    fn outputs(&self) -> &[Output] {
        const O: &[Output] = &[Output { name: Borrowed("x"), kind: OutputKind::Dofs(Borrowed(X)) }];
        O
    }
    /// The parametric term `cos(Ωt) x` doubles the harmonic content like a square.
    fn degree(&self) -> usize {
        2
    }
    fn residual<D: DualNum<Primitive = f64> + Copy>(
        &self,
        p: &[D],
        _omega: D,
        phase: f64,
        s: &[D],
        out: &mut [D],
    ) {
        out[0] = p[0] * s[2] + p[1] * s[1] + p[2] * (p[3] * phase.cos() + 1.0) * s[0]
            - p[4] * phase.cos();
    }
}

/// The parameters of the tests: the principal tongue lies in Ω ∈ (1.5, 2.6).
pub const MODEL: Mathieu = Mathieu { m: 1.0, c: 0.05, k: 1.0, eps: 0.4, f: 0.1 };

/// Monodromy matrix of the homogeneous equation of [`MODEL`] with parametric
/// amplitude `eps`, by RK4 over one period 2π/w: (trace, determinant).
pub fn monodromy_at(w: f64, eps: f64) -> (f64, f64) {
    let Mathieu { m, c, k, .. } = MODEL;
    let rhs =
        |t: f64, y: [f64; 2]| [y[1], -(c * y[1] + k * (1.0 + eps * (w * t).cos()) * y[0]) / m];
    let steps = 4000;
    let dt = 2.0 * std::f64::consts::PI / w / steps as f64;
    let mut cols = [[1.0, 0.0], [0.0, 1.0]];
    for y in cols.iter_mut() {
        let mut t = 0.0;
        for _ in 0..steps {
            let k1 = rhs(t, *y);
            let k2 = rhs(t + dt / 2.0, [y[0] + dt / 2.0 * k1[0], y[1] + dt / 2.0 * k1[1]]);
            let k3 = rhs(t + dt / 2.0, [y[0] + dt / 2.0 * k2[0], y[1] + dt / 2.0 * k2[1]]);
            let k4 = rhs(t + dt, [y[0] + dt * k3[0], y[1] + dt * k3[1]]);
            for i in 0..2 {
                y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            t += dt;
        }
    }
    (cols[0][0] + cols[1][1], cols[0][0] * cols[1][1] - cols[1][0] * cols[0][1])
}

/// `1 + trace + det` of the monodromy matrix at parametric amplitude `eps`: zero where
/// a multiplier is −1 (a tongue edge).
fn edge_function(eps: f64) -> impl Fn(f64) -> f64 {
    move |w| {
        let (tr, det) = monodromy_at(w, eps);
        1.0 + tr + det
    }
}

/// The root of `g` in `[a, b]` (a sign change), by 60 bisections.
fn bisect(g: &impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    for _ in 0..60 {
        let mid = 0.5 * (a + b);
        if g(mid).signum() == g(a).signum() {
            a = mid;
        } else {
            b = mid;
        }
    }
    0.5 * (a + b)
}

/// The edges of the principal tongue of [`MODEL`] in Ω ∈ [1.5, 2.6]: a multiplier -1,
/// i.e. 1 + trace + det = 0, by bisection.
pub fn tongue() -> Vec<f64> {
    let g = edge_function(MODEL.eps);
    let mut edges = Vec::new();
    let n = 200;
    let (lo, hi) = (1.5, 2.6);
    let mut prev = (lo, g(lo));
    for i in 1..=n {
        let w = lo + (hi - lo) * i as f64 / n as f64;
        let gw = g(w);
        if gw.signum() != prev.1.signum() {
            edges.push(bisect(&g, prev.0, w));
        }
        prev = (w, gw);
    }
    edges
}

/// The tongue edge within 2e-3 of `w` at parametric amplitude `e` (panics if there is
/// none, a test setup error).
fn edge_near(w: f64, e: f64) -> f64 {
    let g = edge_function(e);
    let (a, b) = (w - 2e-3, w + 2e-3);
    assert!(g(a) * g(b) < 0.0, "no edge near Ω = {w} at ε = {e}");
    bisect(&g, a, b)
}

/// A sweep of `model` (the Mathieu equation with [`MODEL`]'s parameters, however
/// written) through the tongue at N = 12: no fold, and two period-doubling points,
/// each located to 1e-8 at the monodromy edges ([`tongue`]).
pub fn assert_period_doubles_on_the_edges<M: Model>(model: &M) {
    let edges = tongue();
    assert_eq!(edges.len(), 2, "test setup: one tongue in range, got {edges:?}");
    let opts = SweepOptions { harmonics: 12, ..Default::default() };
    let curve = sweep(model, 1.5, 2.6, &opts).unwrap();
    assert!(curve.folds.is_empty());
    let pd: Vec<f64> = curve
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::PeriodDoubling && b.located)
        .map(|b| b.omega)
        .collect();
    assert_eq!(pd.len(), 2, "{:?}", curve.bifurcations);
    for (g, e) in pd.iter().zip(&edges) {
        assert!((g - e).abs() < 1e-8 * e, "period doubling at {g}, monodromy says {e}");
    }
}

/// The period-doubling boundary of `model` (as for [`assert_period_doubles_on_the_edges`])
/// continued in (Ω, ε) for ε from 0.3 to 0.6 is the tongue's edge — the damped
/// Ince–Strutt diagram: at points of each curve, the monodromy matrix at that ε has a
/// multiplier −1 at that Ω ([`edge_near`]), to 1e-8.
pub fn assert_period_doubling_curves_on_the_edges<M: Model + Clone>(model: &M) {
    let mut opts =
        FoldCurveOptions { boundary: Boundary::PeriodDoubling, ..FoldCurveOptions::default() };
    opts.sweep.harmonics = 12;
    opts.omega = (1.5, 2.6);
    let eps = model.param_index("eps").unwrap();
    let res = fold_curves(model, eps, 0.3, 0.6, &opts).unwrap();
    assert_eq!(res.start_folds, (2, 2), "two edges at both ends");
    assert_eq!(
        res.curves.len(),
        2,
        "{:?}",
        res.curves.iter().map(|c| &c.ended).collect::<Vec<_>>()
    );
    for c in &res.curves {
        assert_eq!(c.ended.to_string(), "reached end");
        let n = c.points.len();
        for p in [&c.points[n / 4], &c.points[n / 2], &c.points[3 * n / 4]] {
            let e = edge_near(p.omega, p.value);
            assert!(
                (p.omega - e).abs() < 1e-8 * e,
                "ε = {}: Ω = {} vs monodromy {e}",
                p.value,
                p.omega
            );
        }
    }
}
