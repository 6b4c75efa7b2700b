//! The whole reference study (`ihbm run`): every figure, time-domain points included.
//! Prints where the time goes (compute seconds per figure, summed over its jobs).

use criterion::{criterion_group, criterion_main, Criterion};
use ihbm::{study, Cli};
use std::time::Duration;

fn reference_study(c: &mut Criterion) {
    let cli = Cli::builtin();
    let spec = study::parse(study::REFERENCE_STUDY, "reference_study.toml")
        .expect("the reference study parses");
    spec.validate(cli.registry()).expect("the reference study is valid");
    let dir = std::env::temp_dir().join(format!("ihbm-bench-study-{}", std::process::id()));
    // One run outside the timer, to report the breakdown.
    let outcome = study::run(&spec, cli.registry(), &dir).expect("the study runs");
    eprintln!(
        "reference study: {:.2} s wall, {} files, {} failures",
        outcome.seconds,
        outcome.files.len(),
        outcome.failures.len()
    );
    for (id, s) in &outcome.figure_seconds {
        eprintln!("  {id:<24} {s:>7.2} s compute");
    }
    let mut g = c.benchmark_group("study");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(30))
        .warm_up_time(Duration::from_millis(1));
    g.bench_function("reference_study", |b| {
        b.iter(|| study::run(&spec, cli.registry(), &dir).expect("the study runs"))
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, reference_study);
criterion_main!(benches);
