use ihbm::continuation::{sweep, SweepOptions};
use ihbm::models::{Duffing, QuarterCar};
use ihbm::Model;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model = Duffing { m: 1.0, c: 0.05, k: 1.0, k3: 1.0, F: 0.2 };
    let c = sweep(&model, 0.5, 2.5, &SweepOptions { harmonics: 1, ..Default::default() }).unwrap();
    println!(
        "duffing: {} points stats {:?} folds {:?}",
        c.points.len(),
        c.stats,
        c.folds.iter().map(|f| f.omega).collect::<Vec<_>>()
    );
    println!("jumps {:?}", c.jumps);
    let mut car = QuarterCar::default();
    for kv in args.iter().skip(1) {
        let (k, v) = kv.split_once('=').unwrap();
        car.set_param(k, v.parse().unwrap()).unwrap();
    }
    let t = std::time::Instant::now();
    let c = sweep(&car, 1.0, 100.0, &SweepOptions::default()).unwrap();
    println!("car: {:?} points {} stats {:?}", t.elapsed(), c.points.len(), c.stats);
    println!("segments {:?}", c.segments);
    println!(
        "folds {:?}",
        c.folds.iter().map(|f| (f.omega, f.outputs[0].max_abs)).collect::<Vec<_>>()
    );
    println!("bif {:?}", c.bifurcations.iter().map(|b| (b.kind, b.omega)).collect::<Vec<_>>());
    println!("jumps {:?}", c.jumps);
    let unstable: Vec<_> =
        c.points.iter().enumerate().filter(|(_, p)| !p.stable).map(|(i, p)| (i, p.omega)).collect();
    println!("unstable {:?}", unstable);
    if std::env::var("PTS").is_ok() {
        for p in &c.points {
            println!("{:.4} {:.5} {} {}", p.omega, p.outputs[0].max_abs, p.stable, p.segment);
        }
    }
}
