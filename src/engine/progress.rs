//! Progress on standard error, shown only when it is a terminal: a spinner for one
//! computation, a bar over a study's jobs, and [`CurveProgress`], the continuation
//! observer that shows a sweep's points as they are accepted.

use crate::backbone::{Backbone, CycleFamily};
use crate::bifurcation::{FoldCurves, FoldEvent};
use crate::continuation::{Control, Event, Observer, Trace};
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

/// Shows a running continuation on a spinner or bar: the label, the points accepted
/// so far and where the curve is. It never stops the run.
pub struct CurveProgress {
    pb: ProgressBar,
    label: String,
}

impl CurveProgress {
    /// Report on `pb` (a [`spinner`], or a study's [`bar`] shared by its jobs) under `label`.
    pub fn new(pb: ProgressBar, label: &str) -> Self {
        CurveProgress { pb, label: label.to_string() }
    }
}

impl Observer for CurveProgress {
    fn observe(&mut self, event: &Event, trace: &Trace) -> Control {
        if let Event::Point(i) = *event {
            if let Some(p) = trace.points.get(i) {
                self.pb.set_message(format!(
                    "{}: {} points, {} = {:.6}",
                    self.label,
                    trace.points.len(),
                    trace.parameter,
                    p.param
                ));
            }
        }
        Control::Continue
    }
}

/// An observer that asks the continuation to stop once `stop` is set (by a signal
/// handler, say), and otherwise defers to `inner`.
pub struct Stoppable<'a, O> {
    /// The observer seeing every event until then.
    pub inner: O,
    /// The flag.
    pub stop: &'a std::sync::atomic::AtomicBool,
}

impl<O: Observer> Observer for Stoppable<'_, O> {
    fn observe(&mut self, event: &Event, trace: &Trace) -> Control {
        if self.stop.load(std::sync::atomic::Ordering::Relaxed) {
            Control::Stop
        } else {
            self.inner.observe(event, trace)
        }
    }
}

/// The progress line of a fold-curve analysis after `e`.
pub fn fold_message(label: &str, e: &FoldEvent, f: &FoldCurves) -> String {
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
pub fn backbone_message(label: &str, b: &Backbone) -> String {
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
pub fn family_message(label: &str, f: &CycleFamily) -> String {
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
