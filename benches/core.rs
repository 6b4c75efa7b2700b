//! Core costs: one residual + Jacobian evaluation and one full Newton solve of the
//! quarter car at N = 5 (the sweep goal needs a Newton iteration in microseconds).

use criterion::{criterion_group, criterion_main, Criterion};
use ihbm::balance::{linearized_guess, Balance};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::QuarterCar;
use std::hint::black_box;

fn core(c: &mut Criterion) {
    let car = QuarterCar { k3: 8e6, ..QuarterCar::default() };
    let a = linearized_guess(&car, 9.0, 5).expect("linear guess");
    let mut hb = Balance::new(&car, 5).expect("balance");
    let len = hb.len();
    let mut r = vec![0.0; len];
    let mut jac = faer::Mat::<f64>::zeros(len, len);
    c.bench_function("quarter_car_residual_n5", |b| {
        b.iter(|| hb.residual(black_box(&a), black_box(9.0), &mut r))
    });
    c.bench_function("quarter_car_residual_jacobian_n5", |b| {
        b.iter(|| hb.jacobian(black_box(&a), black_box(9.0), &mut r, jac.as_mut()))
    });
    let opts = SolveOptions::default();
    c.bench_function("quarter_car_newton_solve_n5_k3_8e6", |b| {
        b.iter(|| solve(black_box(&car), black_box(9.0), &opts, None).expect("converges"))
    });
}

criterion_group!(benches, core);
criterion_main!(benches);
