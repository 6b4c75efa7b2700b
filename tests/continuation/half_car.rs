//! The half car (`half-car`): bounce, pitch and two suspensions, the rear road input
//! delayed by τ = (a + b)/v.
//!
//! Evidence, each from a source other than the model's own equations:
//! - the linear car against its closed-form 4×4 frequency response, written here in
//!   the physical coordinates (z, θ, zf, zr) from each body's Newton equation, with
//!   the fractional factor (iΩ)^p = Ω^p e^{ipπ/2} (to 1e-12);
//! - the nonlinear car against a twin declared in those physical coordinates (the
//!   built-in uses Lagrange's equations in (z, θ, yf, yr)), delayed and with τ = 0
//!   (the in-phase road), on the same branch;
//! - the wheelbase filtering of a symmetric car (a = b, equal front and rear): where
//!   Ωτ = 2πk both wheels meet the same road and the pitch vanishes, where
//!   Ωτ = (2k+1)π they meet opposite roads and the bounce vanishes — with strong cubic
//!   springs, by the symmetry of the equations;
//! - a speed sweep (`sweep_param` in v) of the linear car against the superposition
//!   law X(v) = A + B e^{−iΩ(a+b)/v}, A and B the responses to each wheel's input.

use ihbm::continuation::{sweep_param, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::fourier::coeff_len;
use ihbm::models::HalfCar;
use ihbm::Model;
use num_complex::Complex64;
use std::f64::consts::{FRAC_PI_2, PI};

ihbm::oscillator! {
    /// The half car in physical coordinates, each body's Newton equation, the delay a
    /// parameter.
    pub struct Physical {
        params {
            m = 690.0, I = 1222.0, mf = 40.0, mr = 45.0, kf = 18_000.0, kr = 22_000.0,
            k3f = 10_000.0, k3r = 10_000.0, cf = 1_000.0, cr = 1_000.0, hf = 1_000.0,
            hr = 1_000.0, p = 0.5, ktf = 200_000.0, ktr = 200_000.0, a = 1.3, b = 1.5,
            tau = 0.14, F = 0.01,
        }
        dofs { z, theta, zf, zr }
        let yf = z + a * theta - zf;
        let yr = z - b * theta - zr;
        let fsf = kf * yf + k3f * yf.powi(3) + cf * D(yf, 1) + hf * D(yf, p);
        let fsr = kr * yr + k3r * yr.powi(3) + cr * D(yr, 1) + hr * D(yr, p);
        equations {
            m * D(z, 2) + fsf + fsr = 0.0;
            I * D(theta, 2) + a * fsf - b * fsr = 0.0;
            mf * D(zf, 2) + ktf * zf - fsf = ktf * F * cos(omega * t);
            mr * D(zr, 2) + ktr * zr - fsr
                = ktr * F * cos(omega * tau) * cos(omega * t) + ktr * F * sin(omega * tau) * sin(omega * t);
        }
    }
}

/// The physical twin of `car` with delay `tau`.
fn twin(car: &HalfCar, tau: f64) -> Physical {
    let c = car;
    Physical {
        m: c.m,
        I: c.I,
        mf: c.mf,
        mr: c.mr,
        kf: c.kf,
        kr: c.kr,
        k3f: c.k3f,
        k3r: c.k3r,
        cf: c.cf,
        cr: c.cr,
        hf: c.hf,
        hr: c.hr,
        p: c.p,
        ktf: c.ktf,
        ktr: c.ktr,
        a: c.a,
        b: c.b,
        tau,
        F: c.F,
    }
}

fn opts(harmonics: usize) -> SolveOptions {
    SolveOptions { harmonics, tol: 1e-12, ..Default::default() }
}

/// DOF `d`'s coefficient block.
fn block(coeffs: &[f64], d: usize, n: usize) -> &[f64] {
    &coeffs[d * coeff_len(n)..(d + 1) * coeff_len(n)]
}

/// Harmonic 1 of DOF `d` as a complex amplitude X (x = Re X e^{iΩt} = a1 cos − Im X sin).
fn first(coeffs: &[f64], d: usize, n: usize) -> Complex64 {
    let b = block(coeffs, d, n);
    Complex64::new(b[1], -b[1 + n])
}

/// Gaussian elimination with partial pivoting on a small complex system.
fn solve_complex(mut a: Vec<Vec<Complex64>>, mut rhs: Vec<Complex64>) -> Vec<Complex64> {
    let n = rhs.len();
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| a[i][col].norm().total_cmp(&a[j][col].norm())).unwrap();
        a.swap(col, piv);
        rhs.swap(col, piv);
        let (top, below) = a.split_at_mut(col + 1);
        let pivot = &top[col];
        for (i, r) in below.iter_mut().enumerate() {
            let f = r[col] / pivot[col];
            for (x, p) in r[col..].iter_mut().zip(&pivot[col..]) {
                *x -= f * p;
            }
            let v = rhs[col];
            rhs[col + 1 + i] -= f * v;
        }
    }
    let mut x = vec![Complex64::new(0.0, 0.0); n];
    for row in (0..n).rev() {
        let s: Complex64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (rhs[row] - s) / a[row][row];
    }
    x
}

/// The linear car's complex amplitudes (Z, Θ, Zf, Zr) for road amplitudes `rf`, `rr`
/// at the front and rear wheel, from the bodies' Newton equations.
fn frf(c: &HalfCar, omega: f64, rf: Complex64, rr: Complex64) -> Vec<Complex64> {
    let s = Complex64::new(0.0, omega);
    let sp = Complex64::from_polar(omega.powf(c.p), c.p * FRAC_PI_2);
    let sf = c.kf + c.cf * s + c.hf * sp;
    let sr = c.kr + c.cr * s + c.hr * sp;
    let w2 = Complex64::from(omega * omega);
    // yf = z + a θ − zf, yr = z − b θ − zr as rows over (z, θ, zf, zr)
    let yf = [1.0, c.a, -1.0, 0.0];
    let yr = [1.0, -c.b, 0.0, -1.0];
    let mut rows = vec![vec![Complex64::from(0.0); 4]; 4];
    for k in 0..4 {
        rows[0][k] = sf * yf[k] + sr * yr[k];
        rows[1][k] = c.a * sf * yf[k] - c.b * sr * yr[k];
        rows[2][k] = -sf * yf[k];
        rows[3][k] = -sr * yr[k];
    }
    rows[0][0] -= c.m * w2;
    rows[1][1] -= c.I * w2;
    rows[2][2] += c.ktf - c.mf * w2;
    rows[3][3] += c.ktr - c.mr * w2;
    let rhs = vec![Complex64::from(0.0), Complex64::from(0.0), c.ktf * rf, c.ktr * rr];
    solve_complex(rows, rhs)
}

/// (Z, Θ, Yf, Yr) of the linear car: the closed form in the built-in's coordinates.
fn frf_deflections(c: &HalfCar, omega: f64) -> [Complex64; 4] {
    let tau = (c.a + c.b) / c.v;
    let rr = Complex64::from_polar(c.F, -omega * tau);
    let x = frf(c, omega, Complex64::from(c.F), rr);
    [x[0], x[1], x[0] + c.a * x[1] - x[2], x[0] - c.b * x[1] - x[3]]
}

fn linear() -> HalfCar {
    HalfCar { k3f: 0.0, k3r: 0.0, ..Default::default() }
}

#[test]
fn linear_half_car_is_its_closed_form_frequency_response() {
    // Below, between and above the body modes, at a bounce zero of the wheelbase
    // filter, near wheel hop; the default car and a slow one (v = 5 m/s).
    for v in [20.0, 5.0] {
        let car = HalfCar { v, ..linear() };
        let n = 5;
        for omega in [0.5, 6.0, 8.5, 22.4, 45.0, 70.0, 150.0] {
            let sol = solve(&car, omega, &opts(n), None).unwrap();
            let exact = frf_deflections(&car, omega);
            let scale = exact.iter().map(|x| x.norm()).fold(0.0, f64::max);
            for (d, x) in exact.iter().enumerate() {
                let hb = first(&sol.coeffs, d, n);
                let err = (hb - x).norm() / scale;
                assert!(err < 1e-12, "v {v} Ω {omega} dof {d}: {hb} vs {x} ({err:.1e})");
                // a linear response has no other harmonic
                let other = block(&sol.coeffs, d, n)
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != 1 && i != 1 + n)
                    .map(|(_, c)| c.abs())
                    .fold(0.0, f64::max);
                assert!(other < 1e-12 * scale, "v {v} Ω {omega} dof {d}: {other:e}");
            }
        }
    }
}

/// Solve the built-in and its physical twin on the same branch (the twin started from
/// the built-in's solution) and compare every coefficient of z, θ, yf, yr.
fn agree_with_twin(car: &HalfCar, tau: f64, omega: f64) -> f64 {
    let n = 7;
    let len = coeff_len(n);
    let sol = solve(car, omega, &opts(n), None).unwrap();
    let c = &sol.coeffs;
    let (z, th, yf, yr) = (block(c, 0, n), block(c, 1, n), block(c, 2, n), block(c, 3, n));
    let zf: Vec<f64> = (0..len).map(|i| z[i] + car.a * th[i] - yf[i]).collect();
    let zr: Vec<f64> = (0..len).map(|i| z[i] - car.b * th[i] - yr[i]).collect();
    let guess = [z, th, &zf, &zr].concat();
    let phys = twin(car, tau);
    let other = solve(&phys, omega, &opts(n), Some(&guess)).unwrap();
    let o = &other.coeffs;
    let (oz, oth, ozf, ozr) = (block(o, 0, n), block(o, 1, n), block(o, 2, n), block(o, 3, n));
    let scale = c.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for i in 0..len {
        let oyf = oz[i] + car.a * oth[i] - ozf[i];
        let oyr = oz[i] - car.b * oth[i] - ozr[i];
        for (x, y) in [(z[i], oz[i]), (th[i], oth[i]), (yf[i], oyf), (yr[i], oyr)] {
            worst = worst.max((x - y).abs() / scale);
        }
    }
    // the cubic springs must matter, or the comparison says nothing about them
    let h3 = yf[3].hypot(yf[3 + n]) / yf[1].hypot(yf[1 + n]);
    assert!(h3 > 1e-4, "Ω {omega}: harmonic 3 of yf only {h3:e} of harmonic 1");
    worst
}

#[test]
fn nonlinear_half_car_equals_its_physical_twin_delayed_and_in_phase() {
    let strong = HalfCar { k3f: 5e6, k3r: 5e6, F: 0.02, ..Default::default() };
    for omega in [5.0, 8.0, 12.0, 30.0, 60.0] {
        let tau = (strong.a + strong.b) / strong.v;
        let err = agree_with_twin(&strong, tau, omega);
        println!("delayed Ω {omega}: {err:.1e}");
        assert!(err < 1e-11, "delayed, Ω {omega}: {err:e}");
        // τ → 0: at v = 1e30 m/s, Ωτ < 1e-28, below rounding of the forcing; the twin
        // with τ = 0 exactly is the car on an in-phase road.
        let fast = HalfCar { v: 1e30, ..strong.clone() };
        let err = agree_with_twin(&fast, 0.0, omega);
        println!("in phase Ω {omega}: {err:.1e}");
        assert!(err < 1e-11, "in phase, Ω {omega}: {err:e}");
    }
}

/// A symmetric car: a = b, equal wheels, springs, dampers and tyres front and rear,
/// strong cubic springs.
fn symmetric() -> HalfCar {
    HalfCar {
        a: 1.4,
        b: 1.4,
        mr: 40.0,
        kr: 18_000.0,
        k3f: 5e6,
        k3r: 5e6,
        F: 0.03,
        ..Default::default()
    }
}

#[test]
fn symmetric_car_filters_pitch_and_bounce_by_the_wheelbase() {
    let car = symmetric();
    let n = 7;
    let len = coeff_len(n);
    let tau = (car.a + car.b) / car.v;
    for k in 1..=2 {
        for (phase, bounce_zero) in [(2.0 * PI * k as f64, false), ((2 * k - 1) as f64 * PI, true)]
        {
            let omega = phase / tau;
            let sol = solve(&car, omega, &opts(n), None).unwrap();
            let c = &sol.coeffs;
            let (z, th, yf, yr) = (block(c, 0, n), block(c, 1, n), block(c, 2, n), block(c, 3, n));
            let size = |v: &[f64], f: f64| v.iter().map(|x| (f * x).abs()).fold(0.0, f64::max);
            // the pitch in metres at the axle, comparable with the bounce
            let (zs, ths, ys) = (size(z, 1.0), size(th, car.a), size(yf, 1.0));
            let sign = if bounce_zero { -1.0 } else { 1.0 };
            let h3 = yf[3].hypot(yf[3 + n]) / yf[1].hypot(yf[1 + n]);
            let mismatch = (0..len).map(|i| (yf[i] - sign * yr[i]).abs()).fold(0.0, f64::max);
            println!("Ωτ = {phase:.4}: bounce {zs:.2e} pitch {ths:.2e} mismatch {mismatch:.1e} h3 {h3:.1e}");
            if bounce_zero {
                assert!(zs < 1e-12 * ths, "Ωτ = {phase}: bounce {zs:e}, pitch {ths:e}");
            } else {
                assert!(ths < 1e-12 * zs, "Ωτ = {phase}: pitch {ths:e}, bounce {zs:e}");
            }
            assert!(mismatch < 1e-12 * ys, "Ωτ = {phase}: yf ≠ {sign} yr by {mismatch:e}");
            assert!(h3 > 1e-4, "Ωτ = {phase}: harmonic 3 only {h3:e} of harmonic 1");
            // where the filter is not at a zero both motions are there
            let off = solve(&car, omega * 1.1, &opts(n), None).unwrap();
            let (z, th) = (block(&off.coeffs, 0, n), block(&off.coeffs, 1, n));
            assert!(size(z, 1.0) > 1e-3 * size(th, car.a) && size(th, car.a) > 1e-3 * size(z, 1.0));
        }
    }
}

#[test]
fn speed_sweep_of_the_linear_car_is_the_superposition_of_its_wheels() {
    let car = linear();
    let omega = 10.0;
    let so = SweepOptions { harmonics: 3, tol: 1e-12, ..Default::default() };
    let curve = sweep_param(&car, "v", 5.0, 40.0, omega, &so).unwrap();
    assert!(curve.points.len() > 10, "{} points", curve.points.len());
    let last = curve.points.last().unwrap();
    assert!((last.param - 40.0).abs() < 1e-9, "ended at v = {}", last.param);
    // A: the response to the front wheel's road alone, B: to the rear's
    let f = Complex64::from(car.F);
    let zero = Complex64::from(0.0);
    let front = frf(&car, omega, f, zero);
    let rear = frf(&car, omega, zero, f);
    let defl =
        |x: &[Complex64]| [x[0], x[1], x[0] + car.a * x[1] - x[2], x[0] - car.b * x[1] - x[3]];
    let (a, b) = (defl(&front), defl(&rear));
    let mut worst = 0.0f64;
    for pt in &curve.points {
        let delay = Complex64::from_polar(1.0, -omega * (car.a + car.b) / pt.param);
        let scale = (0..4).map(|d| (a[d] + b[d] * delay).norm()).fold(0.0, f64::max);
        for d in 0..4 {
            let exact = a[d] + b[d] * delay;
            let hb = first(&pt.coeffs, d, so.harmonics);
            worst = worst.max((hb - exact).norm() / scale);
        }
    }
    println!("{} points, worst {worst:.1e}", curve.points.len());
    // points are corrected to a residual of 1e-12 N on forces of order kt F = 2e3 N
    assert!(worst < 1e-10, "worst {worst:e}");
}

#[test]
fn half_car_is_a_registered_model_with_units() {
    let car = HalfCar::default();
    assert_eq!(car.name(), "half-car");
    assert_eq!(car.dofs().len(), 4);
    let outputs: Vec<&str> = car.outputs().iter().map(|o| &*o.name).collect();
    assert_eq!(outputs, ["z", "theta", "yf", "yr"]);
    for p in car.params_info() {
        assert!(p.doc.contains(", "), "parameter {} documents no unit: {:?}", p.name, p.doc);
    }
}
