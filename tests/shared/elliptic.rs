//! The undamped Duffing oscillator's exact backbone, the closed form the backbone
//! tests of several binaries check against (shared by `continuation` and `study`).
#![allow(dead_code)]

use std::f64::consts::PI;

/// The complete elliptic integral of the first kind K(m), by the arithmetic–geometric
/// mean.
pub fn ellip_k(m: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - m).sqrt());
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// x'' + x + k3 x³ = 0 with max |x| = a oscillates at
/// ω(a) = π √(1 + k3 a²) / (2 K(m)), m = k3 a² / (2 (1 + k3 a²)).
pub fn duffing_omega(k3: f64, a: f64) -> f64 {
    let s = k3 * a * a;
    PI * (1.0 + s).sqrt() / (2.0 * ellip_k(s / (2.0 * (1.0 + s))))
}
