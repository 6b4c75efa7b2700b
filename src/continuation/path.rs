//! The predictor–corrector step every path takes — a frequency or parameter sweep,
//! fold (period-doubling, torus) curves, backbones, families of limit cycles: each
//! is an extended system ([`Extended`]: `n` equations in `n + 1` unknowns, corrected
//! with one more row), and [`advance_with`] takes one pseudo-arclength step along it.
//!
//! A step predicts with the path's own predictor (the sweep's second-order tangent
//! or secant; `y + h t` for the others, [`advance`]), corrects on the row
//! `border · y = border · y₀ + h`, and takes the new tangent; it halves `h` when the
//! corrector fails or the tangent turns by more than [`StepSize::rejects_turn`]
//! allows, and gives up below the smallest step with the corrector's reason. What
//! happens to an accepted point (its events, the next step's size, the end of the
//! path) is the caller's.

use super::tracer::{dot, Tracer};
use super::StepSize;
use crate::results::Stall;

/// A system a path follows: Newton's method with one extra row, and the tangent.
pub(crate) trait Extended {
    /// Newton from `y` on the system and the row `border · y = target`, in at most
    /// `budget` iterations: the iterations used, or why it failed.
    fn correct(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
        budget: usize,
    ) -> Result<usize, Stall>;
    /// The unit tangent at the point of the last Newton step, into `t`.
    fn tangent(&mut self, t: &mut [f64]);
}

/// How a new tangent's sign is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Orientation {
    /// Along the last tangent (flipped when it points back).
    AlongLast,
    /// As the system gives it (its bordering fixes the sign); a tangent that points
    /// back then turns by more than π/2 and the step is halved.
    AsGiven,
}

/// Where a step starts and how it is controlled.
pub(crate) struct Step<'a> {
    /// The border of the corrector's extra row: the unit direction of the predictor.
    pub border: &'a [f64],
    /// `border · y` at the last point (the step of length `h` corrects onto
    /// `border · y = base + h`).
    pub base: f64,
    /// The last point's tangent: a new tangent's turn is measured from it.
    pub tangent: &'a [f64],
    /// The step-size rule (its smallest step, its largest turn).
    pub size: StepSize,
    /// Newton iterations per attempt.
    pub budget: usize,
    /// How a new tangent's sign is chosen.
    pub orientation: Orientation,
}

/// One accepted step (its point and tangent are in the buffers given to
/// [`advance_with`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stepped {
    /// Newton iterations of the corrector.
    pub iterations: usize,
    /// The turn of the tangent from the step's start, radians.
    pub turn: f64,
    /// The step length taken.
    pub h: f64,
}

/// What a step did.
#[derive(Debug, Clone)]
pub(crate) enum Advance<L> {
    /// A point was accepted.
    Accepted(Stepped),
    /// The predicted point (left in the point buffer, not corrected) left the path's
    /// domain; `leaves` said where.
    Left(L),
    /// The corrector failed below the smallest step: its reason.
    Stalled(Stall),
}

/// One pseudo-arclength step of `sys` with step length `h` (halved in place on every
/// rejection, each counted in `rejected`): `predict(h, point)` writes the predicted
/// point, `leaves` looks at it before it is corrected and may end the step there;
/// the corrected point is left in `point` and its tangent in `tangent`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn advance_with<S: Extended + ?Sized, L>(
    sys: &mut S,
    step: &Step<'_>,
    h: &mut f64,
    rejected: &mut usize,
    mut predict: impl FnMut(f64, &mut [f64]),
    mut leaves: impl FnMut(&[f64]) -> Option<L>,
    point: &mut [f64],
    tangent: &mut [f64],
) -> Advance<L> {
    loop {
        let length = *h;
        predict(length, point);
        if let Some(at) = leaves(point) {
            return Advance::Left(at);
        }
        let iterations = match sys.correct(point, step.border, step.base + length, step.budget) {
            Ok(it) => it,
            Err(why) => {
                *rejected += 1;
                *h *= 0.5;
                if *h < step.size.min {
                    return Advance::Stalled(why);
                }
                continue;
            }
        };
        sys.tangent(tangent);
        if step.orientation == Orientation::AlongLast && dot(tangent, step.tangent) < 0.0 {
            tangent.iter_mut().for_each(|v| *v = -*v);
        }
        let turn = dot(step.tangent, tangent).clamp(-1.0, 1.0).acos();
        if step.size.rejects_turn(turn, length) {
            *rejected += 1;
            *h *= 0.5;
            continue;
        }
        return Advance::Accepted(Stepped { iterations, turn, h: length });
    }
}

/// [`advance_with`] along the tangent `t` from `y` (the predictor `y + h t`, the
/// border `t`), with fresh buffers: the corrected point and its tangent.
#[allow(clippy::too_many_arguments)]
pub(crate) fn advance<S: Extended + ?Sized, L>(
    sys: &mut S,
    y: &[f64],
    t: &[f64],
    h: &mut f64,
    size: StepSize,
    budget: usize,
    orientation: Orientation,
    rejected: &mut usize,
    leaves: impl FnMut(&[f64]) -> Option<L>,
) -> (Advance<L>, Vec<f64>, Vec<f64>) {
    let step = Step { border: t, base: dot(t, y), tangent: t, size, budget, orientation };
    let (mut point, mut tangent) = (vec![0.0; y.len()], vec![0.0; y.len()]);
    let predict = |h: f64, z: &mut [f64]| {
        for ((z, a), b) in z.iter_mut().zip(y).zip(t) {
            *z = a + h * b;
        }
    };
    let r = advance_with(sys, &step, h, rejected, predict, leaves, &mut point, &mut tangent);
    (r, point, tangent)
}

/// The sweep's corrector: chord steps after the first Newton step.
impl Extended for Tracer<'_> {
    fn correct(
        &mut self,
        y: &mut [f64],
        border: &[f64],
        target: f64,
        budget: usize,
    ) -> Result<usize, Stall> {
        Tracer::correct(self, y, border, target, budget)
    }

    fn tangent(&mut self, t: &mut [f64]) {
        Tracer::tangent(self, t)
    }
}
