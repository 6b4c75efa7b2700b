//! A model behind the `BoxedModel` handle, or seen through `WithParams`, computes
//! exactly what the model itself computes: the same arithmetic in the same order,
//! reached through one more indirect call per residual, so every result is equal bit
//! for bit — values (`f64`), Jacobians and stability (`Dual64`), fold curves
//! (`HyperDual64`) and time integration.

use ihbm::bifurcation::{fold_curves, FoldCurveOptions};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::model::{BoxedModel, WithParams};
use ihbm::models::{Duffing, QuarterCar};
use ihbm::timedomain::{simulate, SimOptions};
use ihbm::Model;

#[test]
fn a_boxed_model_traces_the_same_curve_with_the_same_folds_and_stability() {
    let car = QuarterCar::default();
    let opts = SweepOptions::default();
    let typed = sweep(&car, 1.0, 100.0, &opts).unwrap();
    let erased = sweep(&BoxedModel::new(car), 1.0, 100.0, &opts).unwrap();
    assert!(typed.points.len() > 50 && typed.stability_checked);
    assert_eq!(typed, erased);
    // Through the folds and jumps of the hardening Duffing oscillator.
    let duffing = Duffing::default();
    let typed = sweep(&duffing, 0.5, 3.0, &opts).unwrap();
    let erased = sweep(&BoxedModel::new(duffing), 0.5, 3.0, &opts).unwrap();
    assert_eq!((typed.folds.len(), typed.jumps.len()), (2, 2), "{:?}", typed.folds);
    assert_eq!(typed, erased);
}

#[test]
fn a_boxed_duffing_has_the_same_fold_curves_and_cusp() {
    let model = Duffing::default();
    let mut opts = FoldCurveOptions::default();
    opts.sweep.harmonics = 1;
    opts.omega = (0.5, 3.0);
    let f = model.param_index("F").unwrap();
    let typed = fold_curves(&model, f, 0.01, 0.3, &opts).unwrap();
    let erased = fold_curves(&BoxedModel::new(model), f, 0.01, 0.3, &opts).unwrap();
    assert_eq!(typed.cusps.len(), 1);
    assert_eq!(typed, erased);
}

#[test]
fn a_boxed_model_integrates_to_the_same_state_and_keeps_its_parameters() {
    let mut boxed = BoxedModel::new(Duffing::default());
    boxed.set_param("F", 0.4).unwrap();
    let typed = Duffing { F: 0.4, ..Duffing::default() };
    let opts = SimOptions::default();
    assert_eq!(simulate(&typed, 1.3, &opts).unwrap(), simulate(&boxed, 1.3, &opts).unwrap());
    // What the type knew, the box tells: names, parameters, domains, checks.
    assert_eq!(boxed.name(), typed.name());
    assert_eq!(boxed.param_values(), typed.param_values());
    assert_eq!(boxed.params_info(), typed.params_info());
    let e = boxed.set_param("m", -1.0).unwrap_err().to_string();
    assert_eq!(e, typed.clone().set_param("m", -1.0).unwrap_err().to_string());
    assert_eq!(boxed.clone().param("F").unwrap(), 0.4);
}

#[test]
fn a_model_with_parameters_of_its_own_computes_what_a_changed_copy_computes() {
    let duffing = Duffing::default();
    let f = duffing.param_index("F").unwrap();
    let view = WithParams::with(&duffing, f, 0.2);
    let copy = Duffing { F: 0.2, ..Duffing::default() };
    let opts = SweepOptions::default();
    let seen = sweep(&view, 0.5, 3.0, &opts).unwrap();
    assert_eq!(seen, sweep(&copy, 0.5, 3.0, &opts).unwrap());
    // The view's parameters are its own: the model it looks at is untouched.
    assert_eq!(duffing.param("F").unwrap(), Duffing::default().F);
    assert_ne!(seen, sweep(&duffing, 0.5, 3.0, &opts).unwrap());
    // Its checks are the copy's, on the view's values.
    let mut bad = WithParams::new(&duffing);
    bad.set_param_value(duffing.param_index("m").unwrap(), -1.0);
    let mut bad_copy = Duffing::default();
    bad_copy.set_param_value(duffing.param_index("m").unwrap(), -1.0);
    assert_eq!(
        bad.validate().unwrap_err().to_string(),
        bad_copy.validate().unwrap_err().to_string()
    );
    // A boxed model handed over as itself (one indirect call) or through its handle
    // (two) traces the same curve.
    let boxed = BoxedModel::new(copy);
    assert_eq!(sweep(boxed.as_dyn(), 0.5, 3.0, &opts).unwrap(), seen);
    assert_eq!(sweep(&boxed, 0.5, 3.0, &opts).unwrap(), seen);
}
