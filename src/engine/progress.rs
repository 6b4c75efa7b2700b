//! Progress on standard error, shown only when it is a terminal: a spinner for one
//! computation, a bar over a study's jobs, and [`shown`], the watcher that shows an
//! analysis's points as they are accepted.

use super::analysis::{Progress, Watch};
use crate::backbone::{Backbone, CycleFamily};
use crate::bifurcation::{FoldCurves, FoldEvent};
use crate::continuation::Control;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

fn target() -> ProgressDrawTarget {
    if std::io::stderr().is_terminal() && std::io::stdout().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    }
}

/// A spinner with a message for one long computation (finish it with `finish_and_clear`).
pub fn spinner(msg: &str) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(None, target());
    pb.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    pb.set_message(msg.to_string());
    pb.enable_steady_tick(Duration::from_millis(120));
    pb
}

/// A bar over `len` jobs.
pub fn bar(len: u64, msg: &str) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(Some(len), target());
    pb.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    pb.set_message(msg.to_string());
    pb
}

/// The progress line of an analysis under `label`: the points so far and where the
/// last one is.
pub fn message(label: &str, progress: &Progress<'_>) -> String {
    match *progress {
        Progress::Curve(_, t) => match t.points.last() {
            Some(p) => {
                format!("{label}: {} points, {} = {:.6}", t.points.len(), t.parameter, p.param)
            }
            None => label.to_string(),
        },
        Progress::Folds(e, f) => fold_message(label, e, f),
        Progress::Backbone(_, b) => backbone_message(label, b),
        Progress::Cycles(_, f) => family_message(label, f),
    }
}

/// A watcher that shows every event on `pb` (a [`spinner`], or a study's [`bar`]
/// shared by its jobs) under `label`. It never stops the run.
pub fn shown(pb: ProgressBar, label: &str) -> impl Watch + Send + 'static {
    let label = label.to_string();
    move |p: &Progress<'_>| {
        pb.set_message(message(&label, p));
        Control::Continue
    }
}

/// The progress line of a fold-curve analysis after `e`.
fn fold_message(label: &str, e: &FoldEvent, f: &FoldCurves) -> String {
    match *e {
        FoldEvent::Swept(end, n) => format!("{label}: {n} fold(s) at the {end:?} end"),
        FoldEvent::Point { curve, index } => {
            let p = &f.curves[curve].points[index];
            format!(
                "{label}: curve {} of {} folds, {} points, {} = {:.6e}, Ω = {:.6}",
                curve + 1,
                f.start_folds.0 + f.start_folds.1,
                f.curves[curve].points.len(),
                f.parameter,
                p.value,
                p.omega
            )
        }
        FoldEvent::Cusp(i) => {
            format!("{label}: cusp at {} = {:.6e}", f.parameter, f.cusps[i].value)
        }
        FoldEvent::CurveStart(i) | FoldEvent::CurveEnd(i) => format!("{label}: curve {}", i + 1),
        FoldEvent::Finished => format!("{label}: done"),
    }
}

/// A backbone's progress: points so far and the last one's frequency and amplitude.
fn backbone_message(label: &str, b: &Backbone) -> String {
    match b.points.last() {
        Some(p) => format!(
            "{label}: mode {} backbone, {} points, ω = {:.6}, max |{}| = {:.4e}",
            b.mode,
            b.points.len(),
            p.omega,
            b.output_names.get(b.output).map_or("x", String::as_str),
            p.outputs.get(b.output).map_or(f64::NAN, |o| o.max_abs),
        ),
        None => format!("{label}: mode {} backbone", b.mode),
    }
}

/// A family of limit cycles' progress: cycles so far and the last one's parameter.
fn family_message(label: &str, f: &CycleFamily) -> String {
    match f.points.last() {
        Some(p) => format!(
            "{label}: {} limit cycles, {} = {:.6e}, ω = {:.6}",
            f.points.len(),
            f.parameter,
            p.value,
            p.omega
        ),
        None => format!("{label}: limit cycles in {}", f.parameter),
    }
}
