//! Time-domain benches: the quarter car with full fractional memory.
//!
//! - `quarter_car_1e5_steps/fast`: 1e5 steps (250 periods at Ω = 8 rad/s, T/400),
//!   FFT history (goal: < 0.3 s on one core);
//! - `quarter_car_naive/N`: the direct O(n²) sum at smaller n, to extrapolate to 1e5;
//! - `crossover/{fast,naive}/N`: both at short runs, to find where fast wins.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ihbm::models::QuarterCar;
use ihbm::timedomain::{Memory, Stepper, StepperOptions};
use std::hint::black_box;

fn run(model: &QuarterCar, steps: usize, memory: Memory) -> f64 {
    let omega = 8.0;
    let dt = std::f64::consts::TAU / omega / 400.0;
    let opts = StepperOptions { memory, ..StepperOptions::new(dt, steps) };
    let mut s = Stepper::new(model, omega, &opts).expect("valid setup");
    for _ in 0..steps {
        s.step().expect("stable run");
    }
    s.displacements()[0]
}

fn benches(c: &mut Criterion) {
    let model = QuarterCar { k3: 5e6, ..Default::default() };
    let mut g = c.benchmark_group("quarter_car_1e5_steps");
    g.sample_size(10);
    g.bench_function("fast", |b| b.iter(|| black_box(run(&model, 100_000, Memory::Fast))));
    g.finish();

    let mut g = c.benchmark_group("quarter_car_naive");
    g.sample_size(10);
    for n in [10_000usize, 20_000] {
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter(|| black_box(run(&model, n, Memory::Naive)))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("crossover");
    g.sample_size(20);
    for n in [250usize, 500, 1000, 2000, 4000] {
        for (name, memory) in [("fast", Memory::Fast), ("naive", Memory::Naive)] {
            g.bench_with_input(BenchmarkId::new(name, n), &n, |b, &n| {
                b.iter(|| black_box(run(&model, n, memory)))
            });
        }
    }
    g.finish();
}

criterion_group!(timedomain, benches);
criterion_main!(timedomain);
