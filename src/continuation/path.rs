//! The predictor–corrector step that fold (period-doubling, torus) curves,
//! backbones and families of limit cycles share: each is an extended system
//! ([`Extended`]: `n` equations in `n + 1` unknowns, corrected with one more row),
//! and [`advance`] takes one pseudo-arclength step along it.
//!
//! A step predicts along the unit tangent, corrects on the row `t · y = t · y₀ + h`,
//! and takes the new tangent; it halves `h` when the corrector fails or the tangent
//! turns by more than [`StepSize::rejects_turn`] allows, and gives up below the
//! smallest step with the corrector's reason. What happens to an accepted point
//! (its events, the next step's size, the end of the path) is the caller's.

use super::tracer::dot;
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
    /// The unit tangent at the point of the last Newton step.
    fn tangent(&mut self) -> Vec<f64>;
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

/// One accepted step.
#[derive(Debug, Clone)]
pub(crate) struct Stepped {
    /// The corrected point and its tangent.
    pub point: Vec<f64>,
    /// See `point`.
    pub tangent: Vec<f64>,
    /// Newton iterations of the corrector.
    pub iterations: usize,
    /// The turn of the tangent from the step's start, radians.
    pub turn: f64,
    /// The step length taken.
    pub h: f64,
}

/// What [`advance`] did.
#[derive(Debug, Clone)]
pub(crate) enum Advance<L> {
    /// A point was accepted.
    Accepted(Stepped),
    /// The predicted point left the path's domain (`leaves` said where: `at`); it is
    /// not corrected.
    Left {
        /// What `leaves` returned.
        at: L,
        /// The predicted point.
        point: Vec<f64>,
    },
    /// The corrector failed below the smallest step: its reason.
    Stalled(Stall),
}

/// One pseudo-arclength step of `sys` from `y` along `t`, with the step length `h`
/// (halved in place on every rejection, each counted in `rejected`). `leaves` looks
/// at each predicted point before it is corrected and may end the step there.
#[allow(clippy::too_many_arguments)]
pub(crate) fn advance<S: Extended + ?Sized, L>(
    sys: &mut S,
    y: &[f64],
    t: &[f64],
    h: &mut f64,
    size: &StepSize,
    budget: usize,
    orientation: Orientation,
    rejected: &mut usize,
    mut leaves: impl FnMut(&[f64]) -> Option<L>,
) -> Advance<L> {
    loop {
        let step = *h;
        let mut z: Vec<f64> = y.iter().zip(t).map(|(a, b)| a + step * b).collect();
        if let Some(at) = leaves(&z) {
            return Advance::Left { at, point: z };
        }
        let target = dot(t, y) + step;
        let iterations = match sys.correct(&mut z, t, target, budget) {
            Ok(it) => it,
            Err(why) => {
                *rejected += 1;
                *h *= 0.5;
                if *h < size.min {
                    return Advance::Stalled(why);
                }
                continue;
            }
        };
        let mut tn = sys.tangent();
        if orientation == Orientation::AlongLast && dot(&tn, t) < 0.0 {
            tn.iter_mut().for_each(|v| *v = -*v);
        }
        let turn = dot(&tn, t).clamp(-1.0, 1.0).acos();
        if size.rejects_turn(turn, step) {
            *rejected += 1;
            *h *= 0.5;
            continue;
        }
        return Advance::Accepted(Stepped { point: z, tangent: tn, iterations, turn, h: step });
    }
}
