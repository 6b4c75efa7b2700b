//! Internal resonances and turns met by a backbone are flagged, and the backbone is
//! followed through them: a Duffing oscillator with a second, linear oscillator whose
//! frequency is 3.3 (so that the third harmonic of the first mode meets it at
//! ω = 1.1, well inside the first mode's stiffening from 1 to 1.32 at max |x1| = 1).

use crate::elliptic::duffing_omega;
use ihbm::backbone::{backbone, BackboneOptions, End, EventKind};

ihbm::oscillator! {
    /// x1'' + x1 + k3 x1³ + e (x1 - x2) = 0, x2'' + w2² x2 + e (x2 - x1) = 0.
    pub struct ThreeToOne {
        params {
            /// cubic stiffness of the first oscillator
            k3 = 1.0,
            /// the second oscillator's frequency
            w2 = 3.3,
            /// coupling stiffness
            e = 0.0,
            /// cubic stiffness of the second oscillator
            k3b = 0.0,
        }
        dofs { x1, x2 }
        equations {
            D(x1, 2) + x1 + k3 * x1.powi(3) + e * (x1 - x2) = 0.0;
            D(x2, 2) + w2 * w2 * x2 + k3b * x2.powi(3) + e * (x2 - x1) = 0.0;
        }
        outputs { x1, x2 }
    }
}

/// The amplitude where the exact backbone has frequency `w` (bisection).
fn duffing_amplitude(k3: f64, w: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 10.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if duffing_omega(k3, mid) < w {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Uncoupled (e = 0), mode 1 is the exact Duffing backbone and mode 2 stays at
/// rest: the 3:1 event is at ω = w2/3 (by definition of the crossing) and at the
/// amplitude where the elliptic closed form has that frequency, to the error of the
/// linear interpolation between the two points around it, `Δω²/8 · max |A''(ω)|`
/// (A'' from the closed form, sampled at the two points and the crossing, with half
/// as much again for what lies between).
#[test]
fn the_third_harmonic_meeting_the_second_mode_is_flagged_at_the_closed_form_amplitude() {
    let model = ThreeToOne::default();
    let opts = BackboneOptions { to: 1.0, harmonics: 9, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    // odd harmonics only (a symmetric model): 3ω = w2 is the one crossing on the way
    let [ev] = b.events.as_slice() else { panic!("one event: {:?}", b.events) };
    assert_eq!(ev.kind, EventKind::InternalResonance { mode: 2, ratio: 3 });
    let w = model.w2 / 3.0;
    assert!((ev.omega - w).abs() < 1e-12, "ω = {} vs {w}", ev.omega);
    let (wa, wb) = (b.points[ev.after].omega, b.points[ev.after + 1].omega);
    assert!(wa < w && w <= wb, "[{wa}, {wb}]");
    let a = |w: f64| duffing_amplitude(model.k3, w);
    let d = 1e-3 * (wb - wa).max(1e-4);
    let curv = [wa, w, wb]
        .iter()
        .map(|&x| ((a(x + d) - 2.0 * a(x) + a(x - d)) / (d * d)).abs())
        .fold(0.0f64, f64::max);
    let tol = (wb - wa).powi(2) / 8.0 * 1.5 * curv + 1e-9;
    let exact = a(w);
    assert!(
        (ev.amplitude - exact).abs() <= tol,
        "A = {} vs {exact} (tolerance {tol:e})",
        ev.amplitude
    );
}

/// Coupled, with a stiffening second oscillator: the backbone is followed through the
/// 3:1 resonance to the amplitude asked for, and the event is at a third of the
/// coupled linear model's second frequency, the closed form of the 2×2 eigenproblem
/// `ω² = (1 + w2² + 2e ± √((w2² - 1)² + 4e²)) / 2`.
#[test]
fn a_coupled_backbone_is_followed_through_its_three_to_one_resonance() {
    let model = ThreeToOne { e: 0.05, k3b: 1.0, ..Default::default() };
    let opts = BackboneOptions { to: 1.0, harmonics: 9, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert_eq!(b.ended, End::ReachedAmplitude);
    let (e, w2) = (model.e, model.w2);
    let w2_lin =
        (0.5 * (1.0 + w2 * w2 + 2.0 * e + ((w2 * w2 - 1.0).powi(2) + 4.0 * e * e).sqrt())).sqrt();
    let ir: Vec<_> = b.events.iter().filter(|e| e.kind != EventKind::Turn).collect();
    let [ev] = ir.as_slice() else { panic!("one internal resonance: {:?}", b.events) };
    assert_eq!(ev.kind, EventKind::InternalResonance { mode: 2, ratio: 3 });
    assert!(
        (ev.omega - w2_lin / 3.0).abs() < 1e-9 * w2_lin,
        "ω = {} vs {}",
        ev.omega,
        w2_lin / 3.0
    );
    assert!((b.points.last().unwrap().outputs[0].max_abs - 1.0).abs() < 1e-9);
}

/// Coupled to a linear second oscillator, the branch climbs the resonance's tongue
/// (ω pinned near w2/3 while the second oscillator's third harmonic grows) and turns
/// back and forth in max |x1|: every turn is flagged there, and the backbone goes on
/// past them (until its step limit).
#[test]
fn turns_in_amplitude_are_flagged_and_followed() {
    let model = ThreeToOne { e: 0.05, ..Default::default() };
    let opts = BackboneOptions { to: 1.0, harmonics: 9, max_steps: 700, ..Default::default() };
    let b = backbone(&model, &opts).unwrap();
    assert!(matches!(b.ended, End::Stalled(_)), "{:?}", b.ended);
    let turns: Vec<_> = b.events.iter().filter(|e| e.kind == EventKind::Turn).collect();
    assert!(turns.len() >= 2, "{:?}", b.events);
    let amp = |i: usize| b.points[i].outputs[0].max_abs;
    for t in &turns {
        let i = t.after;
        assert!(i + 1 < b.points.len(), "followed past the turn");
        assert!((amp(i) - amp(i - 1)) * (amp(i + 1) - amp(i)) < 0.0, "an extremum at point {i}");
        assert!((t.omega - model.w2 / 3.0).abs() < 0.01, "ω = {} in the tongue", t.omega);
    }
}

/// A backbone driven step by step is the backbone: the same points and events, each
/// event reported after the point before it and before the point after it; stopped
/// part way it keeps exactly the points and events traced so far.
#[test]
fn a_stepped_backbone_is_the_backbone_and_a_stop_keeps_what_was_traced() {
    use ihbm::backbone::{BackboneContinuation, BackboneEvent};
    let model = ThreeToOne { e: 0.05, ..Default::default() };
    let opts = BackboneOptions { to: 1.0, harmonics: 9, max_steps: 120, ..Default::default() };
    let whole = backbone(&model, &opts).unwrap();
    assert!(!whole.events.is_empty(), "a turn to report");

    let mut run = BackboneContinuation::new(&model, &opts).unwrap();
    let (mut points, mut events) = (0, 0);
    loop {
        match run.step() {
            BackboneEvent::Point(i) => {
                assert_eq!(i, points);
                points += 1;
            }
            BackboneEvent::Event(i) => {
                assert_eq!(i, events);
                assert_eq!(run.traced().events[i].after + 1, points, "event {i}");
                events += 1;
            }
            BackboneEvent::Finished => break,
        }
    }
    assert_eq!(run.step(), BackboneEvent::Finished);
    assert_eq!((points, events), (whole.points.len(), whole.events.len()));
    assert_eq!(run.finish(), whole);

    let stop_at = whole.events[0].after + 3;
    let mut run = BackboneContinuation::new(&model, &opts).unwrap();
    while run.step() != BackboneEvent::Point(stop_at) {}
    let part = run.finish();
    assert_eq!(part.ended, End::Stopped);
    assert_eq!(part.points, whole.points[..=stop_at]);
    let before: Vec<_> = whole.events.iter().filter(|e| e.after < stop_at).cloned().collect();
    assert_eq!(part.events, before);
}
