//! Work that a signal cuts short within a fraction of a second.
//!
//! A continuation stops at its next point when its observer says so, but one point
//! can take minutes (a thousand harmonics: one dense factorisation, one Hill
//! eigenproblem). So the application runs long work on a thread of its own and
//! waits: when the stop flag is set and the work has not returned within
//! [`GRACE`], the caller goes on without it — writing what the work published so
//! far — and the process exits with the thread abandoned mid-step.

use super::analysis::{Analysis, Outcome, Progress, Watch};
use super::registry::NamedModel;
use super::ArgNames;
use crate::backbone::{Backbone, CycleFamily};
use crate::bifurcation::FoldCurves;
use crate::continuation::{Control, Trace};
use crate::error::Result;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long stopped work gets to return by itself (a curve ends at its next point,
/// which for ordinary sizes takes milliseconds) before it is abandoned.
pub const GRACE: Duration = Duration::from_millis(300);

/// How often the stop flag is looked at while the work runs.
const POLL: Duration = Duration::from_millis(25);

/// How detached work ended.
#[derive(Debug)]
pub enum Detached<T> {
    /// It returned.
    Returned(T),
    /// The flag was set and it did not return within [`GRACE`]: it still runs, and
    /// whatever it publishes after this is not looked at.
    Abandoned,
    /// It panicked (a bug: the message is the panic's).
    Panicked(String),
}

/// Run `work` on a thread of its own and wait for it, or, once `stop` is set, for at
/// most [`GRACE`] more. Where no thread can be started the work runs here (and then
/// stops only as promptly as it checks the flag itself).
pub fn run<T, F>(stop: &AtomicBool, work: F) -> Detached<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    run_polled(|| stop.load(Ordering::Relaxed), work)
}

/// [`run`], asking `stopped` every few milliseconds instead of reading a flag (a
/// front end that must look for signals itself, as Python's main thread does).
pub fn run_polled<T, F>(mut stopped: impl FnMut() -> bool, work: F) -> Detached<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    let (tx, rx) = mpsc::channel();
    let spawned = std::thread::Builder::new().name("ihbm-work".into()).spawn(move || {
        // A send fails only once the waiter has gone: the result is not wanted.
        let _ = tx.send(work());
    });
    let handle = match spawned {
        Ok(h) => h,
        Err(e) => {
            // The closure went into the failed spawn; nothing is left to run here.
            return Detached::Panicked(format!("could not start a worker thread: {e}"));
        }
    };
    let mut deadline: Option<Instant> = None;
    loop {
        let wait = match deadline {
            Some(d) => d.saturating_duration_since(Instant::now()).min(POLL),
            None => POLL,
        };
        match rx.recv_timeout(wait) {
            Ok(value) => return Detached::Returned(value),
            Err(RecvTimeoutError::Disconnected) => {
                return Detached::Panicked(match handle.join() {
                    Err(p) => panic_message(p.as_ref()),
                    Ok(()) => "the worker ended without a result".into(),
                });
            }
            Err(RecvTimeoutError::Timeout) => {}
        }
        match deadline {
            Some(d) if Instant::now() >= d => return Detached::Abandoned,
            None if stopped() => deadline = Some(Instant::now() + GRACE),
            _ => {}
        }
    }
}

/// What a running analysis has traced, kept at every event for the thread that may
/// have to go on without it ([`Partial::watching`]). A curve's trace is brought up to
/// date at the cost of what the event added ([`Trace::update`]); fold curves, a
/// backbone or a family of cycles are cloned whole (they take milliseconds or more
/// per point, and a clone of their points takes microseconds).
#[derive(Clone, Default)]
pub struct Partial(Arc<Mutex<Option<Kept>>>);

enum Kept {
    Trace(Box<Trace>),
    Folds(Box<FoldCurves>),
    Backbone(Box<Backbone>),
    Cycles(Box<CycleFamily>),
}

impl Partial {
    /// Keep what `progress` shows.
    pub fn publish(&self, progress: &Progress<'_>) {
        let Ok(mut kept) = self.0.lock() else { return };
        match (progress, &mut *kept) {
            (Progress::Curve(_, t), Some(Kept::Trace(c))) => t.update(c),
            (Progress::Curve(_, t), k) => *k = Some(Kept::Trace(Box::new((*t).clone()))),
            (Progress::Folds(_, f), k) => *k = Some(Kept::Folds(Box::new((*f).clone()))),
            (Progress::Backbone(_, b), k) => *k = Some(Kept::Backbone(Box::new((*b).clone()))),
            (Progress::Cycles(_, f), k) => *k = Some(Kept::Cycles(Box::new((*f).clone()))),
        }
    }

    /// What was kept (`None` before the first event), as the outcome of `analysis` on
    /// the model called `model`: a curve's open segment ended "stopped"
    /// ([`Trace::into_stopped_curve`]).
    pub fn outcome(&self, model: &str, analysis: &Analysis) -> Option<Outcome> {
        let kept = self.0.lock().ok()?.take()?;
        let mut outcome = match kept {
            Kept::Trace(t) => {
                Outcome::Curve(t.into_stopped_curve(model, analysis.checks_stability()))
            }
            Kept::Folds(f) => Outcome::Folds(*f),
            Kept::Backbone(b) => Outcome::Backbone(*b),
            Kept::Cycles(f) => Outcome::Cycles(*f),
        };
        outcome.set_model(model);
        Some(outcome)
    }

    /// A watcher that keeps every event's progress here, then asks `inner`.
    pub fn watching<'a>(&'a self, inner: &'a mut dyn Watch) -> impl Watch + 'a {
        move |progress: &Progress<'_>| {
            self.publish(progress);
            inner.watch(progress)
        }
    }
}

/// How an analysis run by [`run_analysis`] ended.
pub enum Ran<W> {
    /// It returned: its result, and the watcher (with whatever it noted).
    Returned(Result<Outcome>, W),
    /// It was stopped and did not return within [`GRACE`]: what it had traced at its
    /// last event (`None`: it was stopped before its first).
    Abandoned(Option<Outcome>),
    /// It panicked (a bug: the message is the panic's).
    Panicked(String),
}

/// Run `analysis` on `model` on a thread of its own ([`run_polled`]), its events shown
/// to `watch`; once `stopped` says so, the analysis is asked to stop at its next
/// event and, if it does not return within [`GRACE`], abandoned with what it had
/// traced. The command line, a study and Python all stop an analysis this way.
pub fn run_analysis<W: Watch + Send + 'static>(
    model: &NamedModel,
    analysis: &Analysis,
    names: ArgNames,
    mut stopped: impl FnMut() -> bool,
    mut watch: W,
) -> Ran<W> {
    let partial = Partial::default();
    let stop = Arc::new(AtomicBool::new(false));
    let work = {
        let (model, analysis) = (model.clone(), analysis.clone());
        let (partial, stop) = (partial.clone(), Arc::clone(&stop));
        move || {
            let mut stoppable = |p: &Progress<'_>| {
                if stop.load(Ordering::Relaxed) {
                    Control::Stop
                } else {
                    watch.watch(p)
                }
            };
            let r = model.run(&analysis, &names, &mut partial.watching(&mut stoppable));
            (r, watch)
        }
    };
    let ran = run_polled(
        || {
            let s = stopped();
            if s {
                stop.store(true, Ordering::Relaxed);
            }
            s
        },
        work,
    );
    match ran {
        Detached::Returned((r, watch)) => Ran::Returned(r, watch),
        Detached::Abandoned => Ran::Abandoned(partial.outcome(model.name(), analysis)),
        Detached::Panicked(why) => Ran::Panicked(why),
    }
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_that_returns_is_waited_for() {
        let stop = AtomicBool::new(false);
        assert!(matches!(run(&stop, || 6 * 7), Detached::Returned(42)));
    }

    #[test]
    fn work_that_ignores_the_flag_is_abandoned_within_the_grace_period() {
        let stop = AtomicBool::new(true);
        let t = Instant::now();
        let r = run(&stop, || std::thread::sleep(Duration::from_secs(30)));
        assert!(matches!(r, Detached::Abandoned));
        let waited = t.elapsed();
        assert!(waited >= GRACE && waited < GRACE + Duration::from_secs(2), "{waited:?}");
    }

    #[test]
    fn a_panic_is_reported_not_propagated() {
        let stop = AtomicBool::new(false);
        let r = run(&stop, || -> u8 { panic!("boom") });
        assert!(matches!(r, Detached::Panicked(m) if m == "boom"));
    }
}
