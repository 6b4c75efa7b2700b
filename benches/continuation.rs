//! The whole quarter-car curve, Ω from 1 to 100 rad/s, N = 5: with Hill stability at
//! every point (the goal: about 1 ms on one core), and without it.
use criterion::{criterion_group, criterion_main, Criterion};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::QuarterCar;
use std::hint::black_box;

fn quarter_car_curve(c: &mut Criterion) {
    let car = QuarterCar::default();
    let with = SweepOptions::default();
    let without = SweepOptions { stability: None, ..Default::default() };
    let curve = sweep(&car, 1.0, 100.0, &with).expect("reference curve");
    eprintln!("quarter car 1..100 rad/s, N = 5: {} points, {:?}", curve.points.len(), curve.stats);
    let mut g = c.benchmark_group("continuation");
    g.sample_size(20);
    g.bench_function("quarter_car_1_100_N5_with_stability", |b| {
        b.iter(|| sweep(black_box(&car), 1.0, 100.0, &with).expect("curve"))
    });
    g.bench_function("quarter_car_1_100_N5_no_stability", |b| {
        b.iter(|| sweep(black_box(&car), 1.0, 100.0, &without).expect("curve"))
    });
    g.finish();
}

criterion_group!(benches, quarter_car_curve);
criterion_main!(benches);
