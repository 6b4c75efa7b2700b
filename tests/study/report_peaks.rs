//! The peak `summary.md` reports, against the one-harmonic amplitude equation of a
//! Duffing oscillator without folds (its maximum over Ω found by golden section).

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::Duffing;

/// Amplitude A(Ω) of m x'' + c x' + k x + k3 x³ = F cos Ωt at N = 1 (one real root).
fn amplitude(d: &Duffing, w: f64) -> f64 {
    let (k0, dd, beta) = (d.k - d.m * w * w, d.c * w, 0.75 * d.k3);
    let g = |s: f64| s * ((k0 + beta * s).powi(2) + dd * dd) - d.F * d.F;
    let (mut a, mut b) = (0.0, 1.0);
    while g(b) < 0.0 {
        b *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (a + b);
        if g(mid) < 0.0 {
            a = mid;
        } else {
            b = mid;
        }
    }
    (0.5 * (a + b)).sqrt()
}

#[test]
fn reported_peak_is_the_amplitude_equations_maximum() {
    // Weak forcing: the resonance bends a little but does not fold.
    let d = Duffing { m: 1.0, c: 0.1, k: 1.0, k3: 1.0, F: 0.05 };
    let curve = sweep(&d, 0.5, 1.5, &SweepOptions { harmonics: 1, ..Default::default() }).unwrap();
    assert!(curve.folds.is_empty());
    let (mut lo, mut hi) = (0.9, 1.2);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if amplitude(&d, x1) < amplitude(&d, x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    let (w_peak, a_peak) = (0.5 * (lo + hi), amplitude(&d, 0.5 * (lo + hi)));
    let facts = ihbm::report::curve_facts(&curve, "x", None).unwrap();
    // The largest point alone is off by up to half the point spacing; the parabola
    // through it and its neighbours by O(h³).
    let best = curve
        .points
        .iter()
        .max_by(|a, b| a.outputs[0].max_abs.total_cmp(&b.outputs[0].max_abs))
        .unwrap();
    let (naive_w, naive_a) =
        ((best.omega - w_peak).abs(), (best.outputs[0].max_abs - a_peak).abs());
    let (err_w, err_a) = ((facts.peak_omega - w_peak).abs(), (facts.peak - a_peak).abs());
    eprintln!("peak Ω error {err_w:.2e} (largest point {naive_w:.2e}), amplitude {err_a:.2e} ({naive_a:.2e})");
    assert!(err_w < 1e-3 * w_peak, "{} vs {w_peak}", facts.peak_omega);
    assert!(err_a < 1e-4 * a_peak, "{} vs {a_peak}", facts.peak);
    assert!(err_w < naive_w && err_a < naive_a, "no better than the largest point");
}
