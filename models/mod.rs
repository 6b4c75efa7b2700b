//! The built-in models: the quarter car of the reference paper and the test models,
//! all declared with [`oscillator!`](crate::oscillator).
//!
//! These files live in `models/` beside their study files and are compiled into the
//! `ihbm` crate itself, so the `ihbm` binary ships them while user crates still
//! depend on `ihbm` alone (no crate cycle: `models` is a module, not a package).
//!
//! A user model is declared the same way:
//!
//! ```
//! use ihbm::Model;
//!
//! ihbm::oscillator! {
//!     /// Unbalanced rotor on a cubic spring: m x'' + c x' + k x + k3 x^3 = me Ω² cos Ωt.
//!     pub struct Rotor {
//!         params {
//!             /// total mass, kg
//!             m = 2.0,
//!             /// damping, N s/m
//!             c = 0.4,
//!             /// stiffness, N/m
//!             k = 100.0,
//!             /// cubic stiffness, N/m^3
//!             k3 = 1e4,
//!             /// unbalance (mass times eccentricity), kg m
//!             me = 1e-3,
//!         }
//!         dofs { x }
//!         equations {
//!             m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3)
//!                 = me * omega.powi(2) * cos(omega * t);
//!         }
//!     }
//! }
//!
//! let mut rotor = Rotor::default();
//! rotor.set_param("c", 0.8).unwrap();
//! assert_eq!(rotor.c, 0.8);
//! assert_eq!(rotor.name(), "rotor");
//! assert_eq!(rotor.degree(), 3);
//! let sol = ihbm::corrector::solve(&rotor, 5.0, &Default::default(), None).unwrap();
//! assert!(sol.residual_norm < 1e-9);
//! ```

pub mod base_excited;
pub mod chain;
pub mod duffing;
pub mod half_car;
pub mod quadratic;
pub mod quarter_car;
pub mod quarter_car_ride;
pub mod van_der_pol;

pub use base_excited::BaseExcited;
pub use chain::TwoMassChain;
pub use duffing::{Duffing, FractionalDuffing};
pub use half_car::HalfCar;
pub use quadratic::Quadratic;
pub use quarter_car::QuarterCar;
pub use quarter_car_ride::QuarterCarRide;
pub use van_der_pol::VanDerPol;

use crate::model::BoxedModel;

/// Every built-in model with its default parameters, in the order `ihbm models` lists
/// them, each under its own [`Model::name`](crate::Model::name): the one list the
/// command line, studies and Python take the built-in models from.
///
/// ```
/// use ihbm::Model;
///
/// let names: Vec<String> = ihbm::models::builtin().iter().map(|m| m.name().to_string()).collect();
/// assert_eq!(names[0], "quarter-car");
/// assert!(names.iter().any(|n| n == "half-car"));
/// ```
pub fn builtin() -> Vec<BoxedModel> {
    vec![
        BoxedModel::new(QuarterCar::default()),
        BoxedModel::new(QuarterCarRide::default()),
        BoxedModel::new(Duffing::default()),
        BoxedModel::new(FractionalDuffing::default()),
        BoxedModel::new(TwoMassChain::default()),
        BoxedModel::new(BaseExcited::default()),
        BoxedModel::new(Quadratic::default()),
        BoxedModel::new(VanDerPol::default()),
        BoxedModel::new(HalfCar::default()),
    ]
}
