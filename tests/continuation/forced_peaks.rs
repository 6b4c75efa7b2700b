//! The forced peak of a lightly damped sweep lies on the backbone, to O(ζ²).
//!
//! For `x'' + c x' + k x + k3 x³ = F cos Ωt` with one harmonic, the response curve is
//! `G(Ω, A) = [(ω_b(A)² - Ω²)² + c² Ω²] A² - F² = 0`, `ω_b(A)` the backbone. At the
//! peak `dA/dΩ = 0`, so `∂G/∂Ω = 0`: `Ω_p² = ω_b(A_p)² - c²/2`, i.e.
//! `Ω_p / ω_b(A_p) = √(1 - 2ζ_b²)` with `ζ_b = c / (2 ω_b)`: the peak sits on the
//! backbone to a relative `ζ_b²`. More harmonics change that by a fraction of it (the
//! damping force's third harmonic is in quadrature with the motion and moves the
//! frequency at second order in c only, times the small ratio `a3/a1`), so the
//! computed peak must be within `2 ζ_b²` of the backbone — and, as a check that the
//! comparison means something, far from the linear natural frequency.

use ihbm::backbone::{backbone, BackboneOptions, End};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::Duffing;

/// The peak `(Ω, max |x|)` of a curve: the vertex of the parabola through the
/// largest point and its neighbours (in the point index; the steps there are nearly
/// equal).
fn peak(points: &[(f64, f64)]) -> (f64, f64) {
    let k = (1..points.len() - 1)
        .max_by(|&i, &j| points[i].1.total_cmp(&points[j].1))
        .expect("three points");
    let (w, a) = (|i: usize| points[i].0, |i: usize| points[i].1);
    let (am, a0, ap) = (a(k - 1), a(k), a(k + 1));
    let t = 0.5 * (am - ap) / (am - 2.0 * a0 + ap);
    let quad =
        |fm: f64, f0: f64, fp: f64| f0 + 0.5 * (fp - fm) * t + 0.5 * (fp - 2.0 * f0 + fm) * t * t;
    (quad(w(k - 1), w(k), w(k + 1)), quad(am, a0, ap))
}

#[test]
fn the_peak_of_a_lightly_damped_duffing_sweep_lies_on_its_backbone() {
    let model = Duffing { c: 0.02, F: 0.026, ..Default::default() };
    let harmonics = 7;
    let opts = SweepOptions {
        harmonics,
        max_step: 2e-4,
        initial_step: 1e-4,
        max_steps: 200_000,
        stability: None,
        ..Default::default()
    };
    let curve = sweep(&model, 1.0, 1.6, &opts).unwrap();
    let pts: Vec<(f64, f64)> =
        curve.points.iter().map(|p| (p.omega, p.outputs[0].max_abs)).collect();
    let (wp, ap) = peak(&pts);
    let b = backbone(&model, &BackboneOptions { to: ap, harmonics, ..Default::default() }).unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    let wb = b.points.last().unwrap().omega;
    let zeta = model.c / (2.0 * wb);
    let dev = wp / wb - 1.0;
    assert!(
        dev.abs() <= 2.0 * zeta * zeta,
        "Ω_p = {wp}, ω_b({ap}) = {wb}: {dev:e} vs ζ² = {:e}",
        zeta * zeta
    );
    // the one-harmonic prediction, for the record of the sign
    assert!(dev < 0.0, "the peak is below the backbone: {dev:e}");
    assert!(wp - 1.0 > 0.1, "the peak has left the linear frequency: Ω_p = {wp}");
}
