//! How much of the start-up transient can be left at the end of a run from rest.
//!
//! A run from rest excites the free modes; the statistics describe the steady state
//! only once those have decayed. The last two windows of 10 forcing periods show a
//! transient that changes over 10 periods (the drift), but not one whose own period is
//! far longer: at Ω = 10⁶ rad/s the quarter car's 200 periods last 1.3 ms, while its
//! body mode needs seconds to decay, and its start-up amplitude there is 600× the
//! steady one without any drift between the windows. The free modes of the
//! linearisation at rest decay like `e^{-ξ t / 2}` (`ξ` the EPMC damping that makes
//! the mode periodic, `c/m` for one mass); what is left after the run is known
//! before looking at the signal.

use crate::linearisation::linear_mode;
use crate::model::{DynModel, Model};
pub use crate::results::StartUp;

/// The slowest-decaying free mode of `model` at rest after `duration` seconds, or
/// `None` when the linearisation has no oscillatory mode to speak of (no mass, or
/// unstable at rest: the drift is then all there is to go by).
pub fn start_up(model: &dyn DynModel, duration: f64) -> Option<StartUp> {
    let modes = (1..=model.dofs().len()).filter_map(|k| linear_mode(model, k).ok());
    let slowest = modes.min_by(|a, b| a.xi.total_cmp(&b.xi))?;
    let decay_time = if slowest.xi > 0.0 { 2.0 / slowest.xi } else { f64::INFINITY };
    Some(StartUp { omega: slowest.omega, decay_time, left: (-duration / decay_time).exp() })
}
