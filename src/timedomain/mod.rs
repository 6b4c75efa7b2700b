//! Time-domain verification: integrate a model from rest and compare with harmonic
//! balance.
pub mod memory;
pub mod newmark;
pub mod weights;

pub use memory::{FastHistory, History, Memory, NaiveHistory};
pub use newmark::{Stepper, StepperOptions};
pub use weights::Scheme;
