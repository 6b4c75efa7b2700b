//! Non-smooth terms (`max`, `min`, `abs`, `sign`): exact Jacobians through the active
//! branch (the macro and a model file alike), a bilinear spring's amplitude-independent
//! frequency on the backbone with the error's fall in N and in the samples, a forced
//! oscillator against a one-sided stop against an integration written here with exact
//! smooth pieces and located contact instants, and a tyre that leaves the road where
//! the linear closed form says it must.

use crate::equivalence::sample_check;
use ihbm::backbone::{backbone, BackboneOptions};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::model::{BoxedModel, DynModel, Model, WithSamples};
use ihbm::runtime::RuntimeModel;
use ihbm::timedomain::newmark::{PeriodicStart, Stepper, StepperOptions};
use num_complex::Complex64;

ihbm::oscillator! {
    /// Every non-smooth function, of DOFs, derivatives and forcing.
    pub struct Kinks {
        params {
            /// a
            k1 = 1.0,
            /// a
            k2 = 4.0,
            /// a
            cr = 0.3,
            /// a
            cc = 0.1,
            /// a
            f = 0.2,
            /// a
            g = 0.5,
        }
        dofs { x, y }
        equations {
            D(x, 2) + k1 * min(x, 0.0) + k2 * max(x, 0.0) + cr * max(0.0, D(x - y, 1))
                + cc * min(0.0, D(x - y, 1)) + f * sign(D(x, 1)) = cos(omega * t);
            D(y, 2) + abs(y - g) * y + max(0.0, x - f * cos(omega * t)) - sign(g - 1.0) * y = 0.0;
        }
        outputs { x, push = max(0.0, x - f * cos(omega * t)), s = sign(D(x, 1)) }
    }
}

const KINKS: &str = "
    /// Every non-smooth function, of DOFs, derivatives and forcing.
    pub struct Kinks {
        params {
            /// a
            k1 = 1.0,
            /// a
            k2 = 4.0,
            /// a
            cr = 0.3,
            /// a
            cc = 0.1,
            /// a
            f = 0.2,
            /// a
            g = 0.5,
        }
        dofs { x, y }
        equations {
            D(x, 2) + k1 * min(x, 0.0) + k2 * max(x, 0.0) + cr * max(0.0, D(x - y, 1))
                + cc * min(0.0, D(x - y, 1)) + f * sign(D(x, 1)) = cos(omega * t);
            D(y, 2) + abs(y - g) * y + max(0.0, x - f * cos(omega * t)) - sign(g - 1.0) * y = 0.0;
        }
        outputs { x, push = max(0.0, x - f * cos(omega * t)), s = sign(D(x, 1)) }
    }";

#[test]
fn kinks_are_differentiated_through_the_branch_the_macro_and_a_file_alike() {
    let (m, file) = (Kinks::default(), RuntimeModel::from_text(KINKS, "k.ihbm").unwrap());
    assert!(!m.smooth() && !file.smooth() && !m.outputs_smooth());
    // `sign(g - 1.0)` is a coefficient (-1 here); the rest switch with the state.
    let mut seed = 7u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0
    };
    for _ in 0..50 {
        let sig: Vec<f64> = (0..m.signals().len()).map(|_| next()).collect();
        sample_check(&m, &file, &sig, 1.3, next());
    }
    // On a branch the derivative is the branch's: d/dx of k2 max(x, 0) at x > 0.
    let p: Vec<num_dual::Dual64> =
        m.param_values().iter().map(|&v| num_dual::Dual64::from(v)).collect();
    let sx = m
        .signals()
        .iter()
        .position(|s| *s.terms == [(0, 1.0)] && s.order == ihbm::model::Order::Int(0));
    let sx = sx.unwrap();
    let mut s = vec![num_dual::Dual64::from(0.1); m.signals().len()];
    s[sx] = num_dual::Dual64::new(0.7, 1.0);
    let mut r = vec![num_dual::Dual64::from(0.0); 2];
    m.residual(&p, num_dual::Dual64::from(1.0), 0.0, &s, &mut r);
    assert_eq!(r[0].eps, 4.0);
    // Outputs too: `s` is the sign of the velocity, a constant.
    let mut o = vec![num_dual::Dual64::from(0.0); 2];
    let os = vec![num_dual::Dual64::new(-0.3, 1.0); m.output_signals().len()];
    m.output_values(&p, num_dual::Dual64::from(1.0), 0.0, &os, &mut o);
    assert_eq!((o[1].re, o[1].eps), (-1.0, 0.0));
}

/// `x'' + k1 min(x, 0) + k2 max(x, 0) = 0`: a half period on each spring, so the
/// frequency is `2√k1√k2 / (√k1 + √k2)` at every amplitude.
const BILINEAR: &str = "struct Bilinear { params { k1 = 1.0, k2 = 4.0 } dofs { x }
    equations { D(x, 2) + k1 * min(x, 0.0) + k2 * max(x, 0.0) = 0.0; } }";

/// The largest error of the backbone's frequency at `nh` harmonics (and `samples`).
fn bilinear_error(nh: usize, samples: Option<usize>) -> f64 {
    let m = BoxedModel::new(RuntimeModel::from_text(BILINEAR, "b.ihbm").unwrap());
    let m = match samples {
        Some(s) => BoxedModel::new(WithSamples::new(m, s)),
        None => m,
    };
    let exact = 2.0 * 1.0 * 2.0 / (1.0 + 2.0);
    let b =
        backbone(&m, &BackboneOptions { harmonics: nh, to: 1.0, ..Default::default() }).unwrap();
    assert!(b.points.len() > 10, "{:?}", b.ended);
    b.points.iter().map(|p| (p.omega - exact).abs() / exact).fold(0.0, f64::max)
}

#[test]
fn a_bilinear_spring_has_one_frequency_at_every_amplitude_on_the_backbone() {
    // The error falls fast with N (measured: 7.8e-5, 6.4e-7, 6.8e-8, 5.4e-9 at N = 3,
    // 9, 15, 25), as long as the samples keep up: 64 samples stop it near 6e-6.
    let errors: Vec<f64> = [3, 9, 15, 25].iter().map(|&n| bilinear_error(n, None)).collect();
    assert!(errors[0] < 2e-4 && errors[2] < 2e-7 && errors[3] < 2e-8, "{errors:?}");
    assert!(errors.windows(2).all(|w| w[1] < w[0] / 5.0), "{errors:?}");
    let coarse = bilinear_error(25, Some(64));
    assert!(coarse > 100.0 * errors[3], "{coarse:e} vs {:e}", errors[3]);
}

/// `m x'' + c x' + k x + ks max(0, x - g) = F cos Ωt`, integrated exactly piece by
/// piece: on each side of the stop the equation is linear with constant
/// coefficients, so a piece is its particular solution plus a damped oscillation;
/// the contact instants are the roots of `x(t) = g`, found by a scan and bisection.
struct Stop {
    c: f64,
    k: f64,
    ks: f64,
    g: f64,
    f: f64,
    w: f64,
}

/// One piece: from `t0`, on the stop or off it, with its oscillation's constants.
struct Piece {
    t0: f64,
    contact: bool,
    a: f64,
    b: f64,
}

impl Stop {
    /// Stiffness and constant load of a side.
    fn side(&self, contact: bool) -> (f64, f64) {
        if contact {
            (self.k + self.ks, self.ks * self.g)
        } else {
            (self.k, 0.0)
        }
    }

    /// The particular solution and its rate at `t`.
    fn particular(&self, contact: bool, t: f64) -> (f64, f64) {
        let (kk, load) = self.side(contact);
        let d = (kk - self.w * self.w).powi(2) + (self.c * self.w).powi(2);
        let (p, q) = (self.f * (kk - self.w * self.w) / d, self.f * self.c * self.w / d);
        let (s, co) = (self.w * t).sin_cos();
        (load / kk + p * co + q * s, self.w * (q * co - p * s))
    }

    fn decay(&self, contact: bool) -> (f64, f64) {
        let (kk, _) = self.side(contact);
        let sigma = 0.5 * self.c;
        (sigma, (kk - sigma * sigma).sqrt())
    }

    /// The piece that starts at `t0` from `(x0, v0)`.
    fn piece(&self, contact: bool, t0: f64, x0: f64, v0: f64) -> Piece {
        let (xp, vp) = self.particular(contact, t0);
        let (sigma, wd) = self.decay(contact);
        let a = x0 - xp;
        Piece { t0, contact, a, b: (v0 - vp + sigma * a) / wd }
    }

    fn state(&self, p: &Piece, t: f64) -> (f64, f64) {
        let (xp, vp) = self.particular(p.contact, t);
        let (sigma, wd) = self.decay(p.contact);
        let tau = t - p.t0;
        let (s, c) = (wd * tau).sin_cos();
        let e = (-sigma * tau).exp();
        let u = e * (p.a * c + p.b * s);
        let du = e * (-sigma * (p.a * c + p.b * s) + wd * (-p.a * s + p.b * c));
        (xp + u, vp + du)
    }

    /// Every piece from rest at `t = 0` to `t_end`.
    fn integrate(&self, t_end: f64) -> Vec<Piece> {
        let h = (std::f64::consts::TAU / self.w).min(std::f64::consts::TAU / self.decay(true).1)
            / 2000.0;
        let mut pieces = vec![self.piece(false, 0.0, 0.0, 0.0)];
        loop {
            let p = pieces.last().unwrap();
            let gap = |t: f64| self.state(p, t).0 - self.g;
            let outside = |v: f64| if p.contact { v < 0.0 } else { v > 0.0 };
            let mut t = p.t0;
            let crossing = loop {
                let next = t + h;
                if next > t_end {
                    break None;
                }
                if outside(gap(next)) {
                    break Some((t, next));
                }
                t = next;
            };
            let Some((mut lo, mut hi)) = crossing else { return pieces };
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if outside(gap(mid)) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let (x, v) = self.state(p, hi);
            let contact = !p.contact;
            pieces.push(self.piece(contact, hi, x, v));
        }
    }
}

#[test]
fn a_one_sided_stop_matches_an_integration_with_located_contacts() {
    let stop = Stop { c: 0.1, k: 1.0, ks: 10.0, g: 0.5, f: 0.4, w: 0.8 };
    let period = std::f64::consts::TAU / stop.w;
    // 400 periods: the start-up decays by e^{-0.05 · 3140}.
    let (n0, samples) = (400, 200_000);
    let pieces = stop.integrate((n0 + 1) as f64 * period);
    let (mut lo, mut hi, mut sum, mut k) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0);
    for j in 0..samples {
        let t = n0 as f64 * period + period * j as f64 / samples as f64;
        while k + 1 < pieces.len() && pieces[k + 1].t0 <= t {
            k += 1;
        }
        let x = stop.state(&pieces[k], t).0;
        (lo, hi, sum) = (lo.min(x), hi.max(x), sum + x);
    }
    let mean = sum / samples as f64;
    assert!(hi > stop.g, "the stop is hit: max {hi}");
    let text = "struct Stop { params { c = 0.1, k = 1.0, ks = 10.0, g = 0.5, F = 0.4 } dofs { x }
        equations { D(x, 2) + c * D(x, 1) + k * x + ks * max(0.0, x - g) = F * cos(omega * t); } }";
    let model = RuntimeModel::from_text(text, "stop.ihbm").unwrap();
    // Newton from rest at this frequency does not find the motion on the stop (the
    // contact it starts without is too far from the one it must reach): it says so and
    // keeps its last iterate, whole and finite. Traced up from below, where the stop is
    // not reached, continuation does.
    match solve(&model, stop.w, &SolveOptions { harmonics: 40, ..Default::default() }, None) {
        Err(ihbm::Error::NotConverged { last, iterations, .. }) => {
            assert_eq!(last.len(), 81);
            assert!(iterations == 50 && last.iter().all(|v| v.is_finite()));
        }
        other => panic!("expected no convergence from rest: {other:?}"),
    }
    let opts = SweepOptions { harmonics: 40, stability: None, ..Default::default() };
    let curve = sweep(&model, 0.3, stop.w, &opts).unwrap();
    let x = &curve.points.last().unwrap().outputs[0];
    assert_eq!(curve.points.last().unwrap().omega, stop.w);
    let scale = hi - lo;
    for (what, hb, exact) in [("max", x.max, hi), ("min", x.min, lo), ("mean", x.mean, mean)] {
        assert!((hb - exact).abs() < 1e-5 * scale, "{what}: {hb} vs {exact}");
    }
}

/// The linear quarter car's wheel and road amplitudes `(Z2, F)` per unit road, from
/// the 2×2 frequency response written out here.
fn wheel_per_road(w: f64) -> Complex64 {
    let (m1, m2, k1, kt, c, h, p) = (240.0, 30.0, 16000.0, 160000.0, 1000.0, 1000.0, 0.5);
    let iw = Complex64::new(0.0, w);
    let k = k1 + c * iw + h * iw.powf(p);
    let (a11, a12, a21, a22) = (k - m1 * w * w, -k, -k, k + kt - m2 * w * w);
    a11 * kt / (a11 * a22 - a12 * a21)
}

const LIFT_OFF: &str = "struct Car {
    params { m1 = 240.0, m2 = 30.0, k1 = 16000.0, kt = 160000.0, c = 1000.0, h = 1000.0,
             p = 0.5, F = 0.01, g = 9.81 }
    dofs { z1, z2 }
    let y = z1 - z2;
    let fs = k1 * y + c * D(y, 1) + h * D(y, p);
    let load = (m1 + m2) * g;
    equations {
        m1 * D(z1, 2) + fs = 0.0;
        m2 * D(z2, 2) + load - max(0.0, load - kt * (z2 - F * cos(omega * t))) - fs = 0.0;
    }
    outputs { z1, z2, tyre = max(0.0, load - kt * (z2 - F * cos(omega * t))) }
}";

#[test]
fn the_tyre_leaves_the_road_where_the_linear_closed_form_says() {
    // In contact the car is linear: the tyre's load swings by kt |Z2 - F| about the
    // static load (m1 + m2) g, so the wheel lifts off from F = (m1 + m2) g / (kt |Z2/F - 1|).
    let w = 60.0;
    let onset = 270.0 * 9.81 / (160000.0 * (wheel_per_road(w) - 1.0).norm());
    let mut model = RuntimeModel::from_text(LIFT_OFF, "car.ihbm").unwrap();
    let opts = SolveOptions { harmonics: 20, ..Default::default() };
    let wheel = |model: &RuntimeModel| -> (f64, Vec<f64>) {
        let sol = solve(model, w, &opts, None).unwrap();
        let f = model.param("F").unwrap();
        (sol.outputs(model)[1].amp1 / f, sol.coeffs)
    };
    let linear = wheel_per_road(w).norm();
    // Below the onset the solution is the linear one; above, it departs from it.
    let departs = |model: &mut RuntimeModel, f: f64| {
        model.set_param("F", f).unwrap();
        (wheel(model).0 - linear).abs() > 1e-9 * linear
    };
    assert!(!departs(&mut model, 0.999 * onset) && departs(&mut model, 1.001 * onset));
    let (mut lo, mut hi) = (0.999 * onset, 1.001 * onset);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if departs(&mut model, mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    assert!((hi / onset - 1.0).abs() < 1e-4, "lift-off at F = {hi}, closed form {onset}");

    // Beyond it, the harmonic-balance solution is a periodic motion of the time
    // integration started on it (which does not locate the lift-off instants).
    model.set_param("F", 1.5 * onset).unwrap();
    let (_, coeffs) = wheel(&model);
    let nh = opts.harmonics;
    let sol = solve(&model, w, &opts, Some(&coeffs)).unwrap();
    let out = sol.outputs(&model);
    assert!(out[2].min < 1e-3 * out[2].max, "the wheel is in the air: {:?}", out[2]);
    let period = std::f64::consts::TAU / w;
    let per = 4000;
    let dyn_model: &dyn DynModel = &model;
    let start = PeriodicStart::new(sol.coeffs.clone(), nh);
    let so = StepperOptions::new(period / per as f64, 2 * per);
    let mut s = Stepper::on_periodic(dyn_model, w, &start, &so).unwrap();
    let mut worst: f64 = 0.0;
    for step in 0..2 * per {
        s.step().unwrap();
        if step % 37 == 0 {
            let mut c = out[1].cos.clone();
            c.extend_from_slice(&out[1].sin[1..]);
            let hb = ihbm::fourier::eval(&c, w * s.time());
            worst = worst.max((s.output(1) - hb).abs() / out[1].max_abs);
        }
    }
    assert!(worst < 1e-3, "wheel: time integration vs harmonic balance {worst:e}");
}

#[test]
fn misused_kinks_are_refused_where_they_are_written() {
    let model = |eq: &str| {
        format!("struct S {{ params {{ k = 1.0 }} dofs {{ x }}\n equations {{ {eq} = 0.0; }} }}")
    };
    // (equation, where the error points, message)
    let cases = [
        ("D(x, 2) + max(x)", "max", "`max` takes two arguments: `max(a, b)`"),
        ("D(x, 2) + sign(x, k)", "sign", "`sign` takes one argument: `sign(e)`"),
        ("D(x, 2) + D(max(x, 0.0), 1)", "max", "`max(a, b)` is not allowed inside `D(e, n)`"),
        ("D(x, 2) + D(x.abs(), 1)", "x.abs", "`abs(e)` is not allowed inside `D(e, n)`"),
    ];
    for (eq, at, message) in cases {
        // Line 2 is ` equations { <eq> = 0.0; } }`.
        let column = " equations { ".len() + 1 + eq.find(at).unwrap();
        let e = RuntimeModel::from_text(&model(eq), "s.ihbm").err().unwrap().to_string();
        assert!(e.contains(&format!("s.ihbm:2:{column}: {message}")), "{eq}: {e}");
    }
    // A function of constants is a coefficient: the model stays smooth.
    let m =
        RuntimeModel::from_text(&model("D(x, 2) + sign(k - 2.0) * max(k, 0.5) * x"), "s").unwrap();
    assert!(m.smooth());
    // A sample count a smooth model would alias with is refused, naming the count.
    let duffing = BoxedModel::new(ihbm::models::Duffing::default());
    let few = WithSamples::new(duffing.clone(), 16);
    let e = solve(&few, 1.0, &SolveOptions::default(), None).unwrap_err().to_string();
    assert!(e.contains("at least 24 for model 'duffing' at N = 5"), "{e}");
    let e = solve(&WithSamples::new(duffing, 8), 1.0, &SolveOptions::default(), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("at least 2N + 1 = 11"), "{e}");
}
