//! Work that a signal cuts short within a fraction of a second.
//!
//! A continuation stops at its next point when its observer says so, but one point
//! can take minutes (a thousand harmonics: one dense factorisation, one Hill
//! eigenproblem). So the application runs long work on a thread of its own and
//! waits: when the stop flag is set and the work has not returned within
//! [`GRACE`], the caller goes on without it — writing what the work published so
//! far — and the process exits with the thread abandoned mid-step.

use crate::continuation::{Event, Observer, Trace};
use crate::results::Curve;
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

/// A running continuation's trace as far as it has come, for the thread that may have
/// to go on without it: updated at every event by [`TraceCopy::watching`], at the
/// cost of what the event added ([`Trace::update`]).
#[derive(Clone, Default)]
pub struct TraceCopy(Arc<Mutex<Option<Trace>>>);

impl TraceCopy {
    /// Bring the copy up to date with `trace`.
    pub fn publish(&self, trace: &Trace) {
        let Ok(mut copy) = self.0.lock() else { return };
        match &mut *copy {
            Some(c) => trace.update(c),
            None => *copy = Some(trace.clone()),
        }
    }

    /// The curve as far as the copy goes (`None` before the first event), its open
    /// segment ended "stopped" ([`Trace::into_stopped_curve`]).
    pub fn stopped_curve(&self, model: &str, stability_checked: bool) -> Option<Curve> {
        let trace = self.0.lock().ok()?.take()?;
        Some(trace.into_stopped_curve(model, stability_checked))
    }

    /// An observer that publishes every event's trace here, then asks `inner`.
    pub fn watching<'a, O: Observer + 'a>(&'a self, mut inner: O) -> impl Observer + 'a {
        move |event: &Event, trace: &Trace| {
            self.publish(trace);
            inner.observe(event, trace)
        }
    }
}

/// What an analysis published last (fold curves, a backbone, a family of cycles),
/// for the thread that may have to go on without it: the whole of it, cloned at
/// every event by [`Latest::watching`] (these analyses take milliseconds or more per
/// point, and a clone of their points takes microseconds).
pub struct Latest<T>(Arc<Mutex<Option<T>>>);

impl<T> Clone for Latest<T> {
    fn clone(&self) -> Self {
        Latest(Arc::clone(&self.0))
    }
}

impl<T> Default for Latest<T> {
    fn default() -> Self {
        Latest(Arc::default())
    }
}

impl<T: Clone> Latest<T> {
    /// Keep a copy of `value`.
    pub fn publish(&self, value: &T) {
        if let Ok(mut copy) = self.0.lock() {
            *copy = Some(value.clone());
        }
    }

    /// The last copy (`None` before the first event).
    pub fn take(&self) -> Option<T> {
        self.0.lock().ok()?.take()
    }

    /// An observer that publishes what is traced at every event, then asks `inner`.
    pub fn watching<'a, E, O: Observer<E, T> + 'a>(
        &'a self,
        mut inner: O,
    ) -> impl Observer<E, T> + 'a {
        move |event: &E, traced: &T| {
            self.publish(traced);
            inner.observe(event, traced)
        }
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
