//! The one step-size rule of every path: frequency and parameter sweeps, fold,
//! period-doubling and torus curves, backbones and cycle families.
//!
//! A corrector failure halves the step (down to the smallest, where the path
//! stalls); so does a step whose tangent turned by more than twice the allowed turn.
//! After an accepted point the next step grows or shrinks by the corrector's effort,
//! and is kept from turning the tangent by more than the allowed turn.

/// Step-size control of a predictor–corrector path.
///
/// ```
/// use ihbm::continuation::StepSize;
///
/// let s = StepSize { min: 1e-6, max: 0.1, max_turn: 0.12, easy: 2 };
/// // An easy corrector (two iterations) on a straight path: grow by 1.6.
/// assert!((s.after(0.01, 2, 0.0, 1.0) - 0.016).abs() < 1e-15);
/// // A tangent that turned by the allowed turn: no growth.
/// assert_eq!(s.after(0.01, 2, 0.12, 1.0), 0.01);
/// // Never above the largest step (here scaled by a response ten times the reference).
/// assert_eq!(s.after(0.9, 1, 0.0, 10.0), 1.0);
/// assert!(s.rejects_turn(0.25, 0.01) && !s.rejects_turn(0.25, 1e-6));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSize {
    /// Smallest step: a corrector failure below it stalls the path.
    pub min: f64,
    /// Largest step (times the `scale` given to [`StepSize::after`]).
    pub max: f64,
    /// Largest turn of the tangent per step, radians: the next step shrinks to
    /// respect it, and a step that turns by more than twice as much is rejected.
    pub max_turn: f64,
    /// Corrector iterations that count as no effort: up to these the next step grows
    /// by 1.6, one more by 1.25, two more keep it, beyond that it shrinks by 0.6. A
    /// corrector that finishes with chord steps (the sweep's) reports one iteration
    /// fewer for the same work than one that does not.
    pub easy: usize,
}

impl StepSize {
    /// Whether a step of length `h` whose tangent turned by `angle` is rejected (and
    /// halved): more than twice the allowed turn, while the step can still halve.
    pub fn rejects_turn(&self, angle: f64, h: f64) -> bool {
        angle > 2.0 * self.max_turn && h > 2.0 * self.min
    }

    /// The step after a point accepted with step `h`, in `iterations` corrector
    /// iterations, its tangent turned by `angle` from the last; the largest step is
    /// `max · scale` (a sweep far above its reference amplitude takes relative steps).
    pub fn after(&self, h: f64, iterations: usize, angle: f64, scale: f64) -> f64 {
        let e = self.easy;
        let mut factor: f64 = if iterations <= e {
            1.6
        } else if iterations == e + 1 {
            1.25
        } else if iterations == e + 2 {
            1.0
        } else {
            0.6
        };
        if angle > 0.0 {
            factor = factor.min(self.max_turn / angle);
        }
        (h * factor.clamp(0.25, 2.0)).clamp(self.min, self.max * scale)
    }
}
