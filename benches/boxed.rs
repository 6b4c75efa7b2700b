//! The price of a model behind the [`BoxedModel`] handle (what the command line,
//! studies and Python hold): the same quarter-car computations with the model passed
//! as itself ("typed": `&QuarterCar`, which the solvers take as `&dyn DynModel`, one
//! indirect call per residual evaluation) and through the handle ("boxed": `&boxed`,
//! a second indirect call; `boxed.as_dyn()` avoids it, as the application does).
use criterion::{criterion_group, criterion_main, Criterion};
use ihbm::balance::{linearized_guess, Balance};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::model::{BoxedModel, Model};
use ihbm::models::QuarterCar;
use ihbm::runtime::RuntimeModel;
use std::hint::black_box;

#[path = "../tests/shared/model_text.rs"]
mod model_text;

fn jacobian<M: Model>(c: &mut Criterion, label: &str, model: &M) {
    let a = linearized_guess(model, 9.0, 5).expect("linear guess");
    let mut hb = Balance::new(model, 5).expect("balance");
    let len = hb.len();
    let mut r = vec![0.0; len];
    let mut jac = faer::Mat::<f64>::zeros(len, len);
    c.bench_function(label, |b| {
        b.iter(|| hb.jacobian(black_box(&a), black_box(9.0), &mut r, jac.as_mut()))
    });
}

fn newton<M: Model>(c: &mut Criterion, label: &str, model: &M) {
    let opts = SolveOptions::default();
    c.bench_function(label, |b| {
        b.iter(|| solve(black_box(model), black_box(9.0), &opts, None).expect("converges"))
    });
}

fn curve<M: Model>(c: &mut Criterion, label: &str, model: &M, opts: &SweepOptions) {
    let mut g = c.benchmark_group("boxed_curve");
    g.sample_size(20);
    g.bench_function(label, |b| {
        b.iter(|| sweep(black_box(model), 1.0, 100.0, opts).expect("curve").points.len())
    });
    g.finish();
}

fn boxed(c: &mut Criterion) {
    let car = QuarterCar { k3: 8e6, ..QuarterCar::default() };
    let boxed_car = BoxedModel::new(car.clone());
    jacobian(c, "quarter_car_jacobian_n5 typed", &car);
    jacobian(c, "quarter_car_jacobian_n5 boxed", &boxed_car);
    newton(c, "quarter_car_newton_solve_n5 typed", &car);
    newton(c, "quarter_car_newton_solve_n5 boxed", &boxed_car);

    let car = QuarterCar::default();
    let boxed_car = BoxedModel::new(car.clone());
    let with = SweepOptions::default();
    let without = SweepOptions { stability: None, ..Default::default() };
    curve(c, "quarter_car_1_100_N5_no_stability typed", &car, &without);
    curve(c, "quarter_car_1_100_N5_no_stability boxed", &boxed_car, &without);
    curve(c, "quarter_car_1_100_N5_with_stability typed", &car, &with);
    curve(c, "quarter_car_1_100_N5_with_stability boxed", &boxed_car, &with);

    let src = include_str!("../models/quarter_car.rs");
    let rt =
        RuntimeModel::from_text(&model_text::bodies(src)[0], "quarter_car.rs").expect("valid text");
    let boxed_rt = BoxedModel::new(rt.clone());
    curve(c, "runtime_quarter_car_1_100_N5_with_stability typed", &rt, &with);
    curve(c, "runtime_quarter_car_1_100_N5_with_stability boxed", &boxed_rt, &with);
}

criterion_group!(benches, boxed);
criterion_main!(benches);
