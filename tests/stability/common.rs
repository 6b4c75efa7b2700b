//! Shared by the stability tests: tracking vs the full analysis along a curve.

use ihbm::balance::Balance;
use ihbm::model::{Model, Order};
use ihbm::results::Curve;
use ihbm::stability::{Hill, StabilityOptions, TrackCounts};

/// Track along `curve` as the continuation does (reset at segment starts and after a
/// fold) and compare every point with a fresh full analysis.
pub fn compare<M: Model>(model: &M, curve: &Curve, n: usize) -> TrackCounts {
    let so = StabilityOptions::default();
    let mut bal = Balance::new(model, n).unwrap();
    let mut hill = Hill::new(model, n).unwrap();
    let mut full = Hill::new(model, n).unwrap();
    let integer = model.signals().iter().all(|s| matches!(s.order, Order::Int(_)));
    for (i, p) in curve.points.iter().enumerate() {
        let continues = i > 0
            && p.segment == curve.points[i - 1].segment
            && !curve.folds.iter().any(|f| f.after + 1 == i);
        if !continues {
            hill.reset();
        }
        let t = hill.track(&mut bal, &p.coeffs, p.omega, &so).unwrap();
        let f = full.analyse(&mut bal, &p.coeffs, p.omega, &so).unwrap();
        assert_eq!(t.stable, f.stable, "point {i} Ω = {}: {t:?} vs {f:?}", p.omega);
        assert_eq!(t.stable, p.stability.is_stable(), "point {i}: the sweep's verdict");
        assert!(
            (t.max_real - f.max_real).abs() <= 1e-8 * p.omega,
            "point {i} Ω = {}: {} vs {} ({:?} vs {:?})",
            p.omega,
            t.max_real,
            f.max_real,
            t.exponents,
            f.exponents
        );
        assert_eq!(t.exponents.len(), f.exponents.len(), "point {i} Ω = {} {t:?} {f:?}", p.omega);
        // No exponent counted twice (modulo iΩ; a conjugate pair is two exponents, and
        // at period doubling λ and conj λ = λ - iΩ are listed as such a pair).
        let e = &f.exponents;
        for a in 0..e.len() {
            for b in a + 1..e.len() {
                let d = e[a] - e[b];
                let im = d.im - (d.im / p.omega).round() * p.omega;
                let conj_pair = (e[a] - e[b].conj()).norm() <= 1e-12 * p.omega;
                assert!(
                    conj_pair || d.re.hypot(im) > 1e-8 * p.omega,
                    "point {i} Ω = {}: {} twice in {e:?}",
                    p.omega,
                    e[a]
                );
            }
        }
        // Integer orders: one exponent per state variable (q_max · ndof), none counted
        // twice. (A fractional model has as many as the nonlinear eigenproblem has roots
        // on the principal sheet.)
        if integer {
            assert_eq!(f.exponents.len(), full.central_count(), "point {i} Ω = {}: {f:?}", p.omega);
        }
        assert_eq!(
            t.leading_crossing(p.omega),
            f.leading_crossing(p.omega),
            "point {i} Ω = {}",
            p.omega
        );
    }
    let c = hill.counts();
    assert_eq!(c.full + c.tracked, curve.points.len());
    assert!(c.tracked > 0, "tracking never used: {c:?}");
    c
}
