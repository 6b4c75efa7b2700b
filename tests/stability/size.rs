//! The memory of Hill's method: the estimate made before allocating against the heap
//! an analysis takes (counted per thread), and the refusal, naming the largest N that
//! fits, of a harmonic count whose matrices would not.

use crate::heap::peak_of;
use ihbm::balance::{Balance, MEMORY_LIMIT};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::QuarterCar;
use ihbm::stability::{hill_bytes, Hill, StabilityOptions};
use ihbm::Model;

#[test]
fn the_estimate_bounds_the_heap_of_a_full_analysis() {
    let q = QuarterCar::default();
    let nsig = q.signals().len();
    for n in [20, 40] {
        let sol =
            solve(&q, 8.0, &SolveOptions { harmonics: n, ..Default::default() }, None).unwrap();
        let mut bal = Balance::new(&q, n).unwrap();
        let used = peak_of(|| {
            let mut hill = Hill::new(&q, n).unwrap();
            hill.analyse(&mut bal, &sol.coeffs, 8.0, &StabilityOptions::default()).unwrap();
        });
        let est = hill_bytes(2, nsig, 2, n);
        let r = used / est;
        assert!(
            (0.7..=1.0).contains(&r),
            "N = {n}: heap {used:.3e} B, estimate {est:.3e} B ({r:.3})"
        );
    }
}

#[test]
fn hill_beyond_the_memory_limit_is_refused_naming_the_largest_n() {
    let q = QuarterCar::default();
    let nsig = q.signals().len();
    let used = peak_of(|| {
        let Err(e) = Hill::new(&q, 3000) else { panic!("N = 3000 accepted") };
        let e = e.to_string();
        assert!(e.contains("Hill stability matrices"), "{e}");
        let largest: usize = e
            .rsplit("the largest N that fits is ")
            .next()
            .and_then(|t| t.trim().parse().ok())
            .unwrap_or_else(|| panic!("no N in: {e}"));
        let bytes = |n| hill_bytes(2, nsig, 2, n);
        assert!(bytes(largest) <= MEMORY_LIMIT && bytes(largest + 1) > MEMORY_LIMIT, "{e}");
    });
    assert!(used < 1e6, "{used} B allocated before refusing");
}
