//! The whole quarter-car curve, Ω from 1 to 100 rad/s, N = 5: with Hill stability at
//! every point (the goal: about 1 ms on one core), and without it (and
//! without its resonance peaks); the quarter car with stops and lift-off at N = 15; one
//! stability analysis in full vs tracked from a neighbouring point; and a family of
//! curves, one after the other and in parallel.
use criterion::{criterion_group, criterion_main, Criterion};
use ihbm::balance::Balance;
use ihbm::continuation::{sweep, sweep_family, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::models::{QuarterCar, QuarterCarRide};
use ihbm::stability::{Hill, StabilityOptions};
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
    // What locating the five resonance peaks costs.
    let bare = SweepOptions { peaks: false, ..without.clone() };
    g.bench_function("quarter_car_1_100_N5_no_stability_no_peaks", |b| {
        b.iter(|| sweep(black_box(&car), 1.0, 100.0, &bare).expect("curve"))
    });
    // The quarter car with a bump stop, an asymmetric damper and tyre lift-off: kinks,
    // so 500 samples per period at N = 15 instead of an alias-free count.
    let ride = QuarterCarRide::default();
    let n15 = SweepOptions { harmonics: 15, ..Default::default() };
    let n15_bare = SweepOptions { stability: None, ..n15.clone() };
    let curve = sweep(&ride, 2.0, 100.0, &n15).expect("ride curve");
    eprintln!(
        "ride quarter car 2..100 rad/s, N = 15: {} points, {:?}",
        curve.points.len(),
        curve.stats
    );
    g.bench_function("quarter_car_ride_2_100_N15_with_stability", |b| {
        b.iter(|| sweep(black_box(&ride), 2.0, 100.0, &n15).expect("curve"))
    });
    g.bench_function("quarter_car_ride_2_100_N15_no_stability", |b| {
        b.iter(|| sweep(black_box(&ride), 2.0, 100.0, &n15_bare).expect("curve"))
    });
    g.finish();
}

/// One point of the quarter car at N = 5 (Ω = 60 and 60.5 rad/s, where every mode is
/// resolved): the full analysis, and tracking from the other point (two calls per
/// iteration, alternating, so that each starts from a genuine neighbour).
fn hill_point(c: &mut Criterion) {
    let car = QuarterCar::default();
    let so = SolveOptions { harmonics: 5, ..Default::default() };
    let pts: Vec<(f64, Vec<f64>)> = [60.0, 60.5]
        .iter()
        .map(|&w| (w, solve(&car, w, &so, None).expect("solution").coeffs))
        .collect();
    let opts = StabilityOptions::default();
    let mut bal = Balance::new(&car, 5).expect("balance");
    let mut hill = Hill::new(&car, 5).expect("hill");
    let mut g = c.benchmark_group("stability");
    g.bench_function("quarter_car_N5_analyse", |b| {
        b.iter(|| hill.analyse(&mut bal, black_box(&pts[0].1), pts[0].0, &opts).expect("hill"))
    });
    g.bench_function("quarter_car_N5_track_two_points", |b| {
        b.iter(|| {
            for (w, a) in &pts {
                hill.track(&mut bal, black_box(a), *w, &opts).expect("hill");
            }
        })
    });
    g.finish();
    eprintln!("hill counts in the track bench: {:?}", hill.counts());
}

/// A parameter family as the paper draws it (Fig. 9: k3 = 1e6 … 5e6, five curves
/// 1 → 100 rad/s with stability): one after the other, and [`sweep_family`] in
/// parallel across the cores.
fn k3_family(c: &mut Criterion) {
    let car = QuarterCar::default();
    let opts = SweepOptions::default();
    let values = [1e6, 2e6, 3e6, 4e6, 5e6];
    eprintln!("k3 family on {} threads", rayon::current_num_threads());
    let mut g = c.benchmark_group("family");
    g.sample_size(20);
    g.bench_function("quarter_car_k3_5_curves_sequential", |b| {
        b.iter(|| {
            for &k3 in &values {
                let m = QuarterCar { k3, ..car.clone() };
                black_box(sweep(&m, 1.0, 100.0, &opts).expect("curve"));
            }
        })
    });
    g.bench_function("quarter_car_k3_5_curves_parallel", |b| {
        b.iter(|| black_box(sweep_family(&car, "k3", &values, 1.0, 100.0, &opts)))
    });
    g.finish();
}

criterion_group!(benches, quarter_car_curve, hill_point, k3_family);
criterion_main!(benches);
