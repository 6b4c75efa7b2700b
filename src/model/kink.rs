//! The non-smooth functions a model may apply to any expression (DOFs, derivatives,
//! forcing): `max`, `min`, `abs` and `sign`, for every scalar the solvers use. Each is
//! differentiated through the branch that is active, so dual numbers carry exact
//! Jacobians everywhere but at a switch. There the value is continuous and the
//! derivative is fixed by convention: at a tie, `max`/`min` take the mean of the two
//! sides' derivatives; `abs` has derivative 0 at 0; `sign` has derivative 0 everywhere
//! and `sign(0) = 0`.
//!
//! ```
//! use ihbm::model::kink::{abs, max, min, sign};
//! use num_dual::Dual64;
//! let x = Dual64::new(2.0, 1.0);
//! assert_eq!(max(x, Dual64::from(0.0)), x);
//! assert_eq!(min(x, Dual64::from(0.0)).eps, 0.0);
//! assert_eq!(abs(-x).eps, 1.0);
//! assert_eq!(sign(-x), Dual64::from(-1.0));
//! // A tie: the mean of the two slopes.
//! assert_eq!(max(Dual64::new(1.0, 2.0), Dual64::new(1.0, 0.0)).eps, 1.0);
//! assert_eq!(abs(Dual64::new(0.0, 5.0)).eps, 0.0);
//! assert_eq!(sign(0.0), 0.0);
//! ```

use num_dual::DualNum;

/// The larger of `a` and `b` (at a tie, the mean: same value, mean derivative).
pub fn max<D: DualNum<Primitive = f64> + Copy>(a: D, b: D) -> D {
    let (x, y) = (a.re(), b.re());
    if x > y {
        a
    } else if x < y {
        b
    } else {
        (a + b) * 0.5
    }
}

/// The smaller of `a` and `b` (at a tie, the mean: same value, mean derivative).
pub fn min<D: DualNum<Primitive = f64> + Copy>(a: D, b: D) -> D {
    let (x, y) = (a.re(), b.re());
    if x < y {
        a
    } else if x > y {
        b
    } else {
        (a + b) * 0.5
    }
}

/// `|a|`, with derivative 0 at 0.
pub fn abs<D: DualNum<Primitive = f64> + Copy>(a: D) -> D {
    let x = a.re();
    if x > 0.0 {
        a
    } else if x < 0.0 {
        -a
    } else {
        D::from(0.0)
    }
}

/// `-1`, `0` or `1` as `a` is negative, zero or positive (NaN stays NaN), a constant.
pub fn sign<D: DualNum<Primitive = f64> + Copy>(a: D) -> D {
    let x = a.re();
    D::from(if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else if x == 0.0 {
        0.0
    } else {
        f64::NAN
    })
}
