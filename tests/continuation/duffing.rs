//! Duffing and fractional Duffing with one harmonic against the closed-form
//! amplitude equation
//! `[(k + h Ω^p cos(pπ/2) - m Ω²) a + (3/4) k3 a³]² + [(c Ω + h Ω^p sin(pπ/2)) a]² = F²`,
//! whose folds are the double roots of the cubic in `s = a²` (zero discriminant).

use ihbm::continuation::{sweep, sweep_param, SweepOptions};
use ihbm::models::{Duffing, FractionalDuffing};
use ihbm::results::{BifurcationKind, Curve, Direction, End};
use std::f64::consts::PI;

/// The one-harmonic problem: coefficients of the cubic in s = a².
#[derive(Clone, Copy)]
struct OneHarmonic {
    m: f64,
    c: f64,
    k: f64,
    k3: f64,
    h: f64,
    p: f64,
    f: f64,
}

impl OneHarmonic {
    fn kd(&self, w: f64) -> (f64, f64) {
        let wp = if self.h == 0.0 { 0.0 } else { self.h * w.powf(self.p) };
        (
            self.k + wp * (self.p * PI / 2.0).cos() - self.m * w * w,
            self.c * w + wp * (self.p * PI / 2.0).sin(),
        )
    }
    /// Relative residual of the amplitude equation at (Ω, a).
    fn residual(&self, w: f64, a: f64) -> f64 {
        let (k0, d) = self.kd(w);
        let lhs = (k0 * a + 0.75 * self.k3 * a.powi(3)).powi(2) + (d * a).powi(2);
        (lhs - self.f * self.f) / (self.f * self.f)
    }
    /// s [(k0 + β s)² + d²] - F² = β² s³ + 2 k0 β s² + (k0² + d²) s - F².
    fn discriminant(&self, w: f64) -> f64 {
        let (k0, d) = self.kd(w);
        let beta = 0.75 * self.k3;
        let (a, b, c, e) = (beta * beta, 2.0 * k0 * beta, k0 * k0 + d * d, -self.f * self.f);
        18.0 * a * b * c * e - 4.0 * b.powi(3) * e + b * b * c * c
            - 4.0 * a * c.powi(3)
            - 27.0 * a * a * e * e
    }
    /// Fold frequencies: sign changes of the discriminant, refined by bisection.
    fn folds(&self, lo: f64, hi: f64) -> Vec<f64> {
        let n = 20_000;
        let mut out = Vec::new();
        let mut prev = (lo, self.discriminant(lo));
        for i in 1..=n {
            let w = lo + (hi - lo) * i as f64 / n as f64;
            let dw = self.discriminant(w);
            if dw.signum() != prev.1.signum() {
                let (mut a, mut b, fa) = (prev.0, w, prev.1);
                for _ in 0..200 {
                    let mid = 0.5 * (a + b);
                    if self.discriminant(mid).signum() == fa.signum() {
                        a = mid;
                    } else {
                        b = mid;
                    }
                }
                out.push(0.5 * (a + b));
            }
            prev = (w, dw);
        }
        out
    }
    /// Real roots a of the amplitude equation at Ω (sorted).
    fn amplitudes(&self, w: f64) -> Vec<f64> {
        // Bracket the roots of g(s) = s[(k0 + β s)² + d²] - F² on a fine log grid.
        let (k0, d) = self.kd(w);
        let beta = 0.75 * self.k3;
        let g = |s: f64| s * ((k0 + beta * s).powi(2) + d * d) - self.f * self.f;
        let mut roots = Vec::new();
        let grid: Vec<f64> =
            (0..=4000).map(|i| 10f64.powf(-8.0 + 12.0 * i as f64 / 4000.0)).collect();
        for win in grid.windows(2) {
            let (mut a, mut b) = (win[0], win[1]);
            if g(a).signum() == g(b).signum() {
                continue;
            }
            for _ in 0..200 {
                let mid = 0.5 * (a + b);
                if g(mid).signum() == g(a).signum() {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            roots.push((0.5 * (a + b)).sqrt());
        }
        roots
    }
}

fn one_harmonic_opts() -> SweepOptions {
    SweepOptions { harmonics: 1, ..Default::default() }
}

/// Every point on the equation, folds at its turning points, stability and jumps.
fn check_curve(curve: &Curve, eq: &OneHarmonic, lo: f64, hi: f64) {
    assert_eq!(curve.segments.len(), 1, "{:?}", curve.segments);
    assert_eq!(curve.segments[0].ended, End::ReachedEnd);
    assert!((curve.points.last().unwrap().omega - hi).abs() < 1e-12 * hi);
    assert!((curve.points[0].omega - lo).abs() < 1e-12 * lo);
    let mut worst = 0.0f64;
    for p in &curve.points {
        let (a0, a1, b1) = (p.coeffs[0], p.coeffs[1], p.coeffs[2]);
        assert!(a0.abs() < 1e-12, "odd response expected, a0 = {a0}");
        worst = worst.max(eq.residual(p.omega, a1.hypot(b1)).abs());
    }
    assert!(worst < 1e-10, "amplitude equation violated by {worst:.3e}");
    for f in &curve.folds {
        assert!(f.located);
        assert!(eq.residual(f.omega, f.coeffs[1].hypot(f.coeffs[2])).abs() < 1e-10);
    }
    let expected = eq.folds(lo, hi);
    assert_eq!(expected.len(), 2, "test setup: the equation should have two folds");
    let mut got: Vec<f64> = curve.folds.iter().map(|f| f.omega).collect();
    got.sort_by(f64::total_cmp);
    assert_eq!(got.len(), 2, "folds {got:?}, expected {expected:?}");
    for (g, e) in got.iter().zip(&expected) {
        assert!(
            (g - e).abs() < 1e-8 * e,
            "fold at {g}, expected {e} (rel {:.2e})",
            (g - e).abs() / e
        );
    }
    let errs: Vec<String> =
        got.iter().zip(&expected).map(|(g, e)| format!("{:.1e}", (g - e).abs() / e)).collect();
    eprintln!("worst amplitude-equation residual {worst:.1e}; relative fold errors {errs:?}");
    // Hill: unstable exactly between the folds.
    let (f0, f1) = (curve.folds[0].after, curve.folds[1].after);
    for (i, p) in curve.points.iter().enumerate() {
        let between = i > f0 && i <= f1;
        assert_eq!(
            p.stability.is_stable(),
            !between,
            "point {i} at Ω = {} (folds after {f0}, {f1})",
            p.omega
        );
    }
    assert!(curve.all_bifurcations().iter().all(|b| b.located));
    let kinds: Vec<_> = curve.all_bifurcations().iter().map(|b| b.kind).collect();
    assert_eq!(kinds, vec![BifurcationKind::Fold, BifurcationKind::Fold]);
    // Jumps: up at the upper fold to the lower branch, down at the lower fold up.
    assert_eq!(curve.jumps.len(), 2, "{:?}", curve.jumps);
    let up = curve.jumps.iter().find(|j| j.direction == Direction::Up).unwrap();
    let down = curve.jumps.iter().find(|j| j.direction == Direction::Down).unwrap();
    assert!((up.at - expected[1]).abs() < 1e-8 * expected[1]);
    assert!((down.at - expected[0]).abs() < 1e-8 * expected[0]);
    let roots_up = eq.amplitudes(up.at);
    let roots_down = eq.amplitudes(down.at);
    assert!(up.from > up.to && down.from < down.to);
    // Landing amplitudes: the other root of the equation (solved there, not read off
    // the polyline).
    assert!((up.to - roots_up[0]).abs() < 1e-9 * roots_up[0], "{up:?} vs {roots_up:?}");
    assert!(
        (down.to - roots_down.last().unwrap()).abs() < 1e-9 * down.to,
        "{down:?} vs {roots_down:?}"
    );
}

#[test]
fn duffing_one_harmonic_matches_amplitude_equation() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let eq = OneHarmonic { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.0, p: 0.0, f: 0.2 };
    let curve = sweep(&model, 0.5, 2.5, &one_harmonic_opts()).unwrap();
    check_curve(&curve, &eq, 0.5, 2.5);
}

#[test]
fn fractional_duffing_one_harmonic_matches_amplitude_equation() {
    let model = FractionalDuffing { m: 1.0, c: 0.02, k: 1.0, k3: 1.0, h: 0.05, p: 0.5, F: 0.2 };
    let eq = OneHarmonic { m: 1.0, c: 0.02, k: 1.0, k3: 1.0, h: 0.05, p: 0.5, f: 0.2 };
    let curve = sweep(&model, 0.5, 2.5, &one_harmonic_opts()).unwrap();
    check_curve(&curve, &eq, 0.5, 2.5);
}

#[test]
fn secant_predictor_traces_the_same_curve() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let eq = OneHarmonic { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.0, p: 0.0, f: 0.2 };
    let opts =
        SweepOptions { predictor: ihbm::continuation::Predictor::Secant, ..one_harmonic_opts() };
    let curve = sweep(&model, 0.5, 2.5, &opts).unwrap();
    check_curve(&curve, &eq, 0.5, 2.5);
}

/// A small corrector budget (a user forcing small steps) limits the steps only: the
/// folds, the end of the range and the jump landings are located with a budget of
/// their own. (With the step's budget of 1, fold locations were off by 1e-3 and the
/// range end was missed, so the curve was traced twice, once from each end.)
#[test]
fn a_small_corrector_budget_still_locates_folds_and_the_range_end() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let eq = OneHarmonic { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.0, p: 0.0, f: 0.2 };
    for max_iter in [1, 2] {
        let curve =
            sweep(&model, 0.5, 2.5, &SweepOptions { max_iter, ..one_harmonic_opts() }).unwrap();
        assert!(curve.folds.iter().all(|f| f.located), "max_iter {max_iter}");
        check_curve(&curve, &eq, 0.5, 2.5);
    }
}

#[test]
fn parameter_continuation_in_force_amplitude() {
    // At Ω = 1.6 the response to F has an S-shaped curve (two folds in F).
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let curve = sweep_param(&model, "F", 0.01, 1.0, 1.6, &one_harmonic_opts()).unwrap();
    assert_eq!(curve.parameter.name(), "F");
    assert_eq!(curve.segments[0].ended, End::ReachedEnd);
    for p in &curve.points {
        let eq = OneHarmonic { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.0, p: 0.0, f: p.param };
        let r = eq.residual(1.6, p.coeffs[1].hypot(p.coeffs[2]));
        assert!(r.abs() < 1e-10, "F = {}: residual {r:.2e}", p.param);
        assert_eq!(p.omega, 1.6);
    }
    // Folds in F: where the cubic in s has a double root as F varies, i.e. where
    // dF²/ds = 0 for F²(s) = s[(k0 + βs)² + d²]: 3β² s² + 4 k0 β s + k0² + d² = 0.
    let (k0, d, beta) = (1.0 - 1.6f64 * 1.6, 0.05 * 1.6, 0.75);
    let disc = (4.0 * k0 * beta).powi(2) - 12.0 * beta * beta * (k0 * k0 + d * d);
    let mut expected: Vec<f64> = [-1.0, 1.0]
        .iter()
        .map(|sg| {
            let s = (-4.0 * k0 * beta + sg * disc.sqrt()) / (6.0 * beta * beta);
            (s * ((k0 + beta * s).powi(2) + d * d)).sqrt()
        })
        .collect();
    expected.sort_by(f64::total_cmp);
    let mut got: Vec<f64> = curve.folds.iter().map(|f| f.param).collect();
    got.sort_by(f64::total_cmp);
    assert_eq!(got.len(), 2, "{got:?} vs {expected:?}");
    for (g, e) in got.iter().zip(&expected) {
        assert!((g - e).abs() < 1e-8 * e, "fold at F = {g}, expected {e}");
    }
}

/// Ends where Newton from the linearised response does not converge (a branch past
/// a fold, a resonance) are started along Ω instead: at Ω = 1.2 the Duffing response to
/// F = 0.5 is the one root of the amplitude equation there, on the branch the trace
/// from F = 0.1 cannot reach (it turns back at the fold near F = 0.14); the fractional
/// Duffing at Ω = 1 is found at p = 0 and followed to p = 2. Every point is on the
/// amplitude equation (with its own F or p).
#[test]
fn parameter_sweeps_start_where_newton_from_rest_fails() {
    let model = Duffing::default();
    let (w, (m, c, k, k3)) = (1.2, (model.m, model.c, model.k, model.k3));
    let curve = sweep_param(&model, "F", 0.1, 0.5, w, &one_harmonic_opts()).unwrap();
    assert_eq!(curve.segments.len(), 2, "{:?}", curve.segments);
    assert!(curve.segments.iter().all(|s| s.ended == End::ReachedEnd), "{:?}", curve.segments);
    let amplitude = |p: &ihbm::results::CurvePoint| p.coeffs[1].hypot(p.coeffs[2]);
    for p in &curve.points {
        let eq = OneHarmonic { m, c, k, k3, h: 0.0, p: 0.0, f: p.param };
        let r = eq.residual(w, amplitude(p));
        assert!(r.abs() < 1e-10, "F = {}: residual {r:.2e}", p.param);
    }
    let at_end = OneHarmonic { m, c, k, k3, h: 0.0, p: 0.0, f: 0.5 }.amplitudes(w);
    assert_eq!(at_end.len(), 1, "test setup: one response at F = 0.5, {at_end:?}");
    let start = curve.points.iter().find(|p| p.segment == 1).unwrap();
    assert_eq!(start.param, 0.5);
    assert!((amplitude(start) - at_end[0]).abs() < 1e-8 * at_end[0]);

    let frac = FractionalDuffing::default();
    let curve = sweep_param(&frac, "p", 0.0, 2.0, 1.0, &one_harmonic_opts()).unwrap();
    assert_eq!(curve.segments[0].ended, End::ReachedEnd, "{:?}", curve.segments);
    let (first, last) = (curve.points[0].param, curve.points.last().unwrap().param);
    assert_eq!((first, last), (0.0, 2.0));
    for p in &curve.points {
        let eq = OneHarmonic {
            m: frac.m,
            c: frac.c,
            k: frac.k,
            k3: frac.k3,
            h: frac.h,
            p: p.param,
            f: frac.F,
        };
        let r = eq.residual(1.0, amplitude(p));
        assert!(r.abs() < 1e-10, "p = {}: residual {r:.2e}", p.param);
    }
}

#[test]
fn bad_input_is_an_error_naming_the_value() {
    let model = Duffing::default();
    let o = SweepOptions::default();
    let msg = |r: ihbm::Result<Curve>| r.map(|_| ()).expect_err("should fail").to_string();
    assert!(msg(sweep(&model, 2.0, 1.0, &o)).contains("2 .. 1"));
    assert!(msg(sweep(&model, 0.0, 1.0, &o)).contains('0'));
    assert!(msg(sweep(&model, -1.0, 1.0, &o)).contains("-1"));
    assert!(msg(sweep(&model, f64::NAN, 1.0, &o)).contains("NaN"));
    assert!(msg(sweep(&model, 1.0, f64::INFINITY, &o)).contains("inf"));
    let n0 = SweepOptions { harmonics: 0, ..Default::default() };
    assert!(msg(sweep(&model, 1.0, 2.0, &n0)).contains("harmonics"));
    assert!(msg(sweep_param(&model, "nope", 1.0, 2.0, 1.0, &o)).contains("nope"));
    assert!(msg(sweep_param(&model, "F", 1.0, 2.0, 0.0, &o)).contains("frequency"));
    let frac = FractionalDuffing::default();
    assert!(msg(sweep_param(&frac, "p", 0.5, 2.5, 1.0, &o)).contains("2.5"));
}

/// Driving the continuation step by step is the same computation as `sweep`: the
/// events name every point, fold and bifurcation exactly once and in order, and a run
/// stopped at its first fold keeps a prefix of the full curve, bit for bit, with the
/// fold located where the closed form puts it.
#[test]
fn stepping_gives_the_sweep_and_a_stop_keeps_a_prefix() {
    use ihbm::continuation::{Continuation, Event};
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let eq = OneHarmonic { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, h: 0.0, p: 0.0, f: 0.2 };
    let opts = one_harmonic_opts();
    let whole = sweep(&model, 0.5, 2.5, &opts).unwrap();

    let mut run = Continuation::omega(&model, 0.5, 2.5, &opts).unwrap();
    let mut events = Vec::new();
    loop {
        let e = run.step();
        if e == Event::Finished {
            break;
        }
        events.push(e);
    }
    let (mut points, mut folds, mut segments) = (Vec::new(), Vec::new(), Vec::new());
    let mut peaks = Vec::new();
    // The first point reported after an event, with only events of its step between.
    let next_point = |rest: &[Event]| {
        rest.iter().skip(1).find_map(|e| match e {
            Event::Point(i) => Some(*i),
            Event::Fold(_) | Event::Peak(_) => None,
            _ => Some(usize::MAX),
        })
    };
    for (k, e) in events.iter().enumerate() {
        match *e {
            Event::Point(i) => points.push(i),
            Event::Fold(i) => {
                // reported before the point after it (with a peak in the same step)
                let after = run.trace().folds[i].after;
                assert_eq!(next_point(&events[k..]), Some(after + 1), "{events:?}");
                folds.push(i);
            }
            Event::Peak(i) => {
                let after = run.trace().peaks[i].after;
                assert_eq!(next_point(&events[k..]), Some(after + 1), "{events:?}");
                peaks.push(i);
            }
            Event::Bifurcation(_) => panic!("the Duffing curve changes stability at folds only"),
            Event::SegmentEnd(i) => segments.push(i),
            Event::Finished => unreachable!(),
        }
    }
    assert_eq!(run.step(), Event::Finished, "finished stays finished");
    let stepped = run.finish();
    assert_eq!(stepped, whole);
    assert_eq!(points, (0..whole.points.len()).collect::<Vec<_>>());
    assert_eq!(folds, (0..whole.folds.len()).collect::<Vec<_>>());
    assert_eq!(peaks, (0..whole.peaks.len()).collect::<Vec<_>>());
    assert_eq!(segments, (0..whole.segments.len()).collect::<Vec<_>>());

    let mut run = Continuation::omega(&model, 0.5, 2.5, &opts).unwrap();
    while !matches!(run.step(), Event::Fold(_) | Event::Finished) {}
    let part = run.finish();
    assert_eq!(part.folds.len(), 1);
    assert_eq!(part.folds[0], whole.folds[0]);
    assert_eq!(part.points[..], whole.points[..part.points.len()]);
    assert_eq!(part.segments.last().map(|s| &s.ended), Some(&End::Stopped));
    let expected = eq.folds(0.5, 2.5);
    let upper = expected.iter().cloned().fold(f64::MIN, f64::max);
    assert!((part.folds[0].omega - upper).abs() < 1e-8 * upper, "{:?} vs {upper}", part.folds[0]);
}

/// What an observer that may have to abandon a run keeps: a copy brought up to date
/// at every event equals the trace itself, and the curve made from it when the run is
/// abandoned has the points, folds and segments (the open one ended "stopped") that
/// `finish` gives when the run is stopped at the same event; only the jumps' landings
/// are not refined, so the jumps agree in number and direction.
#[test]
fn a_copy_updated_at_every_event_is_the_trace_and_ends_as_finish_would() {
    use ihbm::continuation::{Continuation, Event, Trace};
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let opts = one_harmonic_opts();
    for stop_after in [1, 7, 20, usize::MAX] {
        let mut run = Continuation::omega(&model, 0.5, 2.5, &opts).unwrap();
        let mut copy: Option<Trace> = None;
        let mut seen = 0;
        loop {
            let e = run.step();
            match &mut copy {
                Some(c) => run.trace().update(c),
                None => copy = Some(run.trace().clone()),
            }
            assert_eq!(copy.as_ref(), Some(run.trace()));
            seen += 1;
            if e == Event::Finished || seen == stop_after {
                break;
            }
        }
        let kept = copy.unwrap().into_stopped_curve("duffing", true);
        let finished = run.finish();
        assert_eq!(kept.points, finished.points);
        assert_eq!(kept.folds, finished.folds);
        assert_eq!(kept.segments, finished.segments, "stopped after {stop_after} events");
        assert_eq!(kept.jumps.len(), finished.jumps.len());
        for (a, b) in kept.jumps.iter().zip(&finished.jumps) {
            assert_eq!((a.direction, a.at, &a.output), (b.direction, b.at, &b.output));
        }
    }
}

/// The resonance peak of `m x'' + c x' + k x + k3 x³ = F cos Ωt` with one harmonic, in
/// closed form: along the curve `G(A, Ω) = (k - mΩ² + ¾k3A²)² A² + (cΩA)² - F² = 0` the
/// amplitude is largest where `∂G/∂Ω = 0`, that is `k - mΩ² + ¾k3A² = c²/(2m)`; then
/// `c²A² (c²/(4m²) + Ω²) = F²` fixes A (bisection on this increasing function of A).
/// `k3 = 0` is the linear resonance, `Ω² = k/m - c²/(2m²)`, exact at any N.
fn one_harmonic_peak(m: f64, c: f64, k: f64, k3: f64, f: f64) -> (f64, f64) {
    let w2 = |a: f64| (k + 0.75 * k3 * a * a - c * c / (2.0 * m)) / m;
    let g = |a: f64| c * c * a * a * (c * c / (4.0 * m * m) + w2(a)) - f * f;
    let (mut lo, mut hi) = (0.0, 1.0);
    while g(hi) < 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let a = 0.5 * (lo + hi);
    (w2(a).sqrt(), a)
}

/// Every sweep reports its resonance peaks, located to 1e-8: the hardening Duffing's
/// top (just before its upper fold, on the stable branch) and the linear oscillator's
/// (N = 5: the response is one harmonic), against the closed form; a sweep that
/// stops before the top has no peak.
#[test]
fn resonance_peaks_are_located_against_the_closed_form() {
    for (k3, harmonics) in [(1.0, 1), (0.0, 5)] {
        let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3, F: 0.2 };
        let opts = SweepOptions { harmonics, ..Default::default() };
        let curve = sweep(&model, 0.5, 2.5, &opts).unwrap();
        let (w, a) = one_harmonic_peak(1.0, 0.05, 1.0, k3, 0.2);
        assert_eq!(curve.peaks.len(), 1, "k3 = {k3}: {:?}", curve.peaks);
        let p = &curve.peaks[0];
        assert!(p.located && p.output == 0);
        assert!((p.omega - w).abs() < 1e-8 * w, "k3 = {k3}: Ω {} vs {w}", p.omega);
        assert!((p.value - a).abs() < 1e-8 * a, "k3 = {k3}: A {} vs {a}", p.value);
        // it lies between the points around it, and above both
        let (l, r) = (&curve.points[p.after], &curve.points[p.after + 1]);
        assert!(p.value >= l.outputs[0].max_abs && p.value >= r.outputs[0].max_abs);
        if k3 > 0.0 {
            // before the upper fold, on the upper branch
            assert!(p.omega < curve.folds[0].omega && p.after <= curve.folds[0].after);
        }
        let short = sweep(&model, 0.5, 0.9 * w, &opts).unwrap();
        assert!(short.peaks.is_empty(), "{:?}", short.peaks);
    }
}

/// Locating the peaks changes nothing else: without them (`peaks: false`) the curve
/// is the same point for point, at fewer corrector iterations.
#[test]
fn skipping_the_peaks_leaves_the_curve_as_it_is() {
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let with = sweep(&model, 0.5, 2.5, &one_harmonic_opts()).unwrap();
    let opts = SweepOptions { peaks: false, ..one_harmonic_opts() };
    let without = sweep(&model, 0.5, 2.5, &opts).unwrap();
    assert_eq!((with.peaks.len(), without.peaks.len()), (1, 0));
    assert_eq!(with.points, without.points);
    assert_eq!((with.folds, with.jumps), (without.folds, without.jumps));
    assert!(with.stats.corrector_iterations > without.stats.corrector_iterations);
}
