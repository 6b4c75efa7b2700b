//! Shared by the stability tests: tracking vs the full analysis along a curve.

use ihbm::balance::Balance;
use ihbm::model::{Model, Order};
use ihbm::results::Curve;
use ihbm::stability::{Hill, StabilityOptions, TrackCounts};
use num_complex::Complex64;

/// Track along `curve` as the continuation does (reset at segment starts and after a
/// fold) and compare every point with a fresh full analysis; the counts, and the
/// points tracked as a partial set.
pub fn compare<M: Model>(model: &M, curve: &Curve, n: usize) -> (TrackCounts, usize) {
    let so = StabilityOptions::default();
    let mut bal = Balance::new(model, n).unwrap();
    let mut hill = Hill::new(model, n).unwrap();
    let mut full = Hill::new(model, n).unwrap();
    let integer = model.signals().iter().all(|s| matches!(s.order, Order::Int(_)));
    let mut partial = 0;
    for (i, p) in curve.points.iter().enumerate() {
        let continues = i > 0
            && p.segment == curve.points[i - 1].segment
            && !curve.folds.iter().any(|f| f.after + 1 == i);
        if !continues {
            hill.reset();
        }
        let tracked = hill.counts().tracked;
        let t = hill.track(&mut bal, &p.coeffs, p.omega, &so).unwrap();
        let f = full.analyse(&mut bal, &p.coeffs, p.omega, &so).unwrap();
        assert_eq!(t.stable, f.stable, "point {i} Ω = {}: {t:?} vs {f:?}", p.omega);
        assert_eq!(t.stable, p.stability.is_stable(), "point {i}: the sweep's verdict");
        if hill.counts().tracked > tracked && !t.refined {
            // A partial set (only the roots that refined at an earlier full analysis,
            // the rest counted): the verdict counted, or an unstable root that the
            // full analysis has too (or counts: a real root that left the branch
            // point λ = 0, which no candidate refines to).
            assert!(t.counted || !t.stable, "point {i} Ω = {}: {t:?}", p.omega);
            if !t.stable {
                let l = t.exponents[0];
                assert!(
                    f.exponents.iter().any(|k| same_modulo_omega(l, *k, p.omega, 1e-8))
                        || (f.counted && l.im == 0.0),
                    "point {i} Ω = {}: {l} of {t:?} not in {f:?}",
                    p.omega
                );
            }
            partial += 1;
            continue;
        }
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
                let conj_pair = (e[a] - e[b].conj()).norm() <= 1e-12 * p.omega;
                assert!(
                    conj_pair || !same_modulo_omega(e[a], e[b], p.omega, 1e-8),
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
    (c, partial)
}

/// `a` and `b` are one exponent: equal within `tol · Ω` modulo `iΩ` (copies).
fn same_modulo_omega(a: Complex64, b: Complex64, omega: f64, tol: f64) -> bool {
    let d = a - b;
    let im = d.im - (d.im / omega).round() * omega;
    d.re.hypot(im) <= tol * omega
}
