use ihbm::balance::Balance;
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::QuarterCar;
use ihbm::stability::{Hill, StabilityOptions};
fn main() {
    let car = QuarterCar::default();
    let c = sweep(&car, 1.0, 100.0, &SweepOptions::default()).unwrap();
    let mut bal = Balance::new(&car, 5).unwrap();
    let mut hill = Hill::new(&car, 5).unwrap();
    for p in &c.points {
        let f = hill.analyse(&mut bal, &p.coeffs, p.omega, &StabilityOptions::default()).unwrap();
        println!(
            "{:8.3} {} {:?}",
            p.omega,
            f.stable,
            f.exponents.iter().map(|z| format!("{:.4}{:+.4}i", z.re, z.im)).collect::<Vec<_>>()
        );
    }
}
