//! Design sensitivities at one frequency (implicit differentiation of the balance,
//! `dA/dθ = −J⁻¹ ∂R/∂θ`), against the derivative of the linear quarter car's closed
//! form (Richardson-extrapolated central differences of the 2×2 frequency response
//! written out here), the fractional order included, and against central differences
//! of the library's own solves for a nonlinear model.

use ihbm::corrector::{solve, SolveOptions};
use ihbm::model::Model;
use ihbm::models::{Duffing, QuarterCar};
use num_complex::Complex64;

/// `|Z1|` of the linear quarter car at Ω with its parameters `q` (QuarterCar's order).
fn body_amplitude(q: &[f64], w: f64) -> f64 {
    let (m1, m2, k1, kt, c, h, p, f) = (q[0], q[1], q[2], q[4], q[5], q[6], q[7], q[8]);
    let iw = Complex64::new(0.0, w);
    let k = k1 + c * iw + h * iw.powf(p);
    let (a11, a12, a22) = (k - m1 * w * w, -k, k + kt - m2 * w * w);
    (-a12 * kt * f / (a11 * a22 - a12 * a12)).norm()
}

/// `d f / d q[i]` by central differences extrapolated (error O(h⁴)).
fn derivative(f: impl Fn(&[f64]) -> f64, q: &[f64], i: usize) -> f64 {
    let central = |h: f64| {
        let (mut up, mut down) = (q.to_vec(), q.to_vec());
        up[i] += h;
        down[i] -= h;
        (f(&up) - f(&down)) / (2.0 * h)
    };
    let h = 1e-3 * q[i].abs().max(1e-3);
    (4.0 * central(0.5 * h) - central(h)) / 3.0
}

#[test]
fn sensitivities_of_the_linear_quarter_car_are_its_closed_forms_derivatives() {
    let car = QuarterCar { k3: 0.0, ..Default::default() };
    let q = car.param_values();
    let names = ["m1", "k1", "kt", "c", "h", "p", "F"];
    let indices: Vec<usize> = names.iter().map(|n| car.param_index(n).unwrap()).collect();
    for w in [4.0, 8.5, 30.0, 70.0] {
        let sol =
            solve(&car, w, &SolveOptions { harmonics: 3, ..Default::default() }, None).unwrap();
        let rates = sol.output_rates(&car, &indices).unwrap();
        for (k, &i) in indices.iter().enumerate() {
            let want = derivative(|q| body_amplitude(q, w), &q, i);
            let z1 = rates[k][0];
            let scale = want.abs().max(1e-9 * body_amplitude(&q, w) / q[i].abs().max(1e-3));
            // A pure harmonic: amp1 and max_abs move alike, the RMS at 1/√2 of it.
            for (what, got) in [("amp1", z1.amp1), ("max_abs", z1.max_abs)] {
                let got = got.unwrap();
                assert!(
                    (got - want).abs() < 1e-8 * scale,
                    "d{what}/d{} at {w}: {got} vs {want}",
                    names[k]
                );
            }
            let rms = z1.rms.unwrap();
            assert!((rms - want / 2f64.sqrt()).abs() < 1e-8 * scale, "drms/d{}", names[k]);
            assert!(z1.mean.unwrap().abs() < 1e-12 * scale);
        }
    }
}

#[test]
fn sensitivities_of_a_nonlinear_model_are_the_differences_of_its_solves() {
    let d = Duffing { k3: 2.0, F: 0.4, ..Default::default() };
    let opts = SolveOptions { harmonics: 7, ..Default::default() };
    let w = 1.3;
    let sol = solve(&d, w, &opts, None).unwrap();
    for name in ["k3", "c", "F"] {
        let i = d.param_index(name).unwrap();
        let rates = sol.output_rates(&d, &[i]).unwrap()[0][0];
        let stat = |v: f64| {
            let mut m = d.clone();
            m.set_param(name, v).unwrap();
            let s = solve(&m, w, &opts, Some(&sol.coeffs)).unwrap();
            let o = s.outputs(&m)[0].clone();
            [o.amp1, o.rms, o.max_abs, o.max, o.min]
        };
        let v = d.param(name).unwrap();
        let h = 1e-5 * v.abs();
        let (up, down) = (stat(v + h), stat(v - h));
        let got = [rates.amp1, rates.rms, rates.max_abs, rates.max, rates.min];
        for (j, what) in ["amp1", "rms", "max_abs", "max", "min"].iter().enumerate() {
            let fd = (up[j] - down[j]) / (2.0 * h);
            let g = got[j].unwrap();
            // The differences' truncation is O(h²) of a smooth function: far below this.
            assert!((g - fd).abs() < 1e-6 * fd.abs().max(1e-3), "d{what}/d{name}: {g} vs {fd}");
        }
    }
}
