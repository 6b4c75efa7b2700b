//! A stability change without a fold: the forced damped Mathieu equation
//! `m x'' + c x' + k (1 + ε cos Ωt) x = F cos Ωt` is linear, so its periodic response
//! is unique and its curve never folds, yet inside the principal parametric tongue
//! (Ω ≈ 2√(k/m)) a Floquet multiplier leaves the unit circle through -1. Hill's method
//! must report that as period doubling, where the monodromy matrix (integrated here
//! independently with RK4) has a multiplier -1.

use crate::common as stability_common;

use ihbm::balance::Balance;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::model::{Model, Order, Output, ParamInfo, Signal, Text};
use ihbm::results::BifurcationKind;
use ihbm::stability::{Hill, StabilityOptions};
use num_dual::DualNum;
use std::borrow::Cow::Borrowed;

#[derive(Clone)]
struct Mathieu {
    m: f64,
    c: f64,
    k: f64,
    eps: f64,
    f: f64,
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
            ParamInfo { name: Borrowed("m"), default: 1.0, doc: Borrowed("") },
            ParamInfo { name: Borrowed("c"), default: 0.05, doc: Borrowed("") },
            ParamInfo { name: Borrowed("k"), default: 1.0, doc: Borrowed("") },
            ParamInfo { name: Borrowed("eps"), default: 0.4, doc: Borrowed("") },
            ParamInfo { name: Borrowed("F"), default: 0.1, doc: Borrowed("") },
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
        const O: &[Output] = &[Output { name: Borrowed("x"), terms: Borrowed(X) }];
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

const MODEL: Mathieu = Mathieu { m: 1.0, c: 0.05, k: 1.0, eps: 0.4, f: 0.1 };

/// Monodromy matrix of the homogeneous equation by RK4: (trace, determinant).
fn monodromy(w: f64) -> (f64, f64) {
    monodromy_at(w, MODEL.eps)
}

/// [`monodromy`] for another parametric amplitude `eps`.
fn monodromy_at(w: f64, eps: f64) -> (f64, f64) {
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

/// Largest Floquet exponent real part from the monodromy multipliers.
fn growth(w: f64) -> f64 {
    let (tr, det) = monodromy(w);
    let disc = tr * tr - 4.0 * det;
    let mu = if disc >= 0.0 { (tr.abs() + disc.sqrt()) / 2.0 } else { det.sqrt() };
    mu.ln() * w / (2.0 * std::f64::consts::PI)
}

/// The tongue edges: multiplier -1, i.e. 1 + trace + det = 0.
fn tongue() -> Vec<f64> {
    let g = |w: f64| {
        let (tr, det) = monodromy(w);
        1.0 + tr + det
    };
    let mut edges = Vec::new();
    let n = 200;
    let (lo, hi) = (1.5, 2.6);
    let mut prev = (lo, g(lo));
    for i in 1..=n {
        let w = lo + (hi - lo) * i as f64 / n as f64;
        let gw = g(w);
        if gw.signum() != prev.1.signum() {
            let (mut a, mut b) = (prev.0, w);
            for _ in 0..60 {
                let mid = 0.5 * (a + b);
                if g(mid).signum() == g(a).signum() {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            edges.push(0.5 * (a + b));
        }
        prev = (w, gw);
    }
    edges
}

#[test]
fn mathieu_tongue_is_period_doubling_without_fold() {
    let edges = tongue();
    assert_eq!(edges.len(), 2, "test setup: one tongue in range, got {edges:?}");
    let opts = SweepOptions { harmonics: 6, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
    assert!(curve.folds.is_empty());
    let pd: Vec<f64> = curve
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::PeriodDoubling)
        .map(|b| b.omega)
        .collect();
    assert_eq!(curve.all_bifurcations().len(), 2, "{:?}", curve.all_bifurcations());
    assert_eq!(pd.len(), 2, "{:?}", curve.all_bifurcations());
    assert!(curve.all_bifurcations().iter().all(|b| b.located));
    for (g, e) in pd.iter().zip(&edges) {
        assert!((g - e).abs() < 1e-6 * e, "period doubling at {g}, monodromy says {e}");
    }
    for p in &curve.points {
        let inside = p.omega > edges[0] && p.omega < edges[1];
        let margin = edges.iter().map(|e| (p.omega - e).abs()).fold(f64::INFINITY, f64::min);
        if margin > 1e-6 {
            assert_eq!(p.stability.is_stable(), !inside, "Ω = {}", p.omega);
        }
    }
}

/// The period-doubling points are the roots of max Re λ, not of the verdict's
/// tolerance: located to 1e-8 against the monodromy edges once N resolves them.
#[test]
fn period_doubling_is_located_to_1e_8_with_enough_harmonics() {
    let edges = tongue();
    let opts = SweepOptions { harmonics: 12, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
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

#[test]
fn hill_exponents_match_monodromy_multipliers() {
    let opts = SweepOptions { harmonics: 6, stability: None, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
    let mut bal = Balance::new(&MODEL, 6).unwrap();
    let mut hill = Hill::new(&MODEL, 6).unwrap();
    for p in &curve.points {
        let f = hill.analyse(&mut bal, &p.coeffs, p.omega, &StabilityOptions::default()).unwrap();
        let g = growth(p.omega);
        assert!(
            (f.max_real - g).abs() < 1e-7,
            "Ω = {}: Hill {} vs monodromy {g}",
            p.omega,
            f.max_real
        );
        assert_eq!(f.exponents.len(), 2);
    }
}

#[test]
fn tracking_agrees_with_the_full_analysis_through_the_tongue() {
    let opts = SweepOptions { harmonics: 6, ..Default::default() };
    let curve = sweep(&MODEL, 1.5, 2.6, &opts).unwrap();
    let k = stability_common::compare(&MODEL, &curve, 6);
    eprintln!("mathieu: {} points, {k:?}", curve.points.len());
}

/// The period-doubling boundary continued in (Ω, ε) is the tongue's edge: at points
/// of each curve, the monodromy matrix at that ε has a multiplier −1 at that Ω (the
/// edge found by bisection on `1 + tr + det`), to 1e-8.
#[test]
fn period_doubling_curves_are_the_tongue_edges_of_the_monodromy() {
    use ihbm::bifurcation::{fold_curves, Boundary, FoldCurveOptions};
    let mut opts =
        FoldCurveOptions { boundary: Boundary::PeriodDoubling, ..FoldCurveOptions::default() };
    opts.sweep.harmonics = 12;
    opts.omega = (1.5, 2.6);
    let eps = MODEL.param_index("eps").unwrap();
    let res = fold_curves(&MODEL, eps, 0.3, 0.6, &opts).unwrap();
    assert_eq!(res.start_folds, (2, 2), "two edges at both ends");
    assert_eq!(
        res.curves.len(),
        2,
        "{:?}",
        res.curves.iter().map(|c| &c.ended).collect::<Vec<_>>()
    );
    let edge = |w: f64, e: f64| {
        let g = |w: f64| {
            let (tr, det) = monodromy_at(w, e);
            1.0 + tr + det
        };
        let (mut a, mut b) = (w - 2e-3, w + 2e-3);
        assert!(g(a) * g(b) < 0.0, "no edge near Ω = {w} at ε = {e}");
        for _ in 0..60 {
            let mid = 0.5 * (a + b);
            if g(mid).signum() == g(a).signum() {
                a = mid;
            } else {
                b = mid;
            }
        }
        0.5 * (a + b)
    };
    for c in &res.curves {
        assert_eq!(c.ended.to_string(), "reached end");
        let n = c.points.len();
        for p in [&c.points[n / 4], &c.points[n / 2], &c.points[3 * n / 4]] {
            let e = edge(p.omega, p.value);
            assert!(
                (p.omega - e).abs() < 1e-8 * e,
                "ε = {}: Ω = {} vs monodromy {e}",
                p.value,
                p.omega
            );
        }
    }
}
