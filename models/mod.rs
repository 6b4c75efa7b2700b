//! The built-in models: the quarter car of the reference paper and the test models,
//! all declared with [`oscillator!`](crate::oscillator).
//!
//! These files live in `models/` beside their study files and are compiled into the
//! `ihbm` crate itself, so the `ihbm` binary ships them while user crates still
//! depend on `ihbm` alone (no crate cycle: `models` is a module, not a package).

pub mod base_excited;
pub mod chain;
pub mod duffing;
#[doc(hidden)]
pub mod handwritten;
pub mod quarter_car;

pub use base_excited::BaseExcited;
pub use chain::TwoMassChain;
pub use duffing::{Duffing, FractionalDuffing};
pub use quarter_car::QuarterCar;
