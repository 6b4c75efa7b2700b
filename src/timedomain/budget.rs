//! One memory budget for every time integration of the process: an integration holds
//! its estimated memory ([`super::estimate_bytes`]) while it runs, and one that would
//! take the total beyond [`MEMORY_LIMIT`] waits for others to finish instead of
//! failing an allocation (which aborts the whole process and loses every result, as
//! two 20M-step integrations of a study in parallel once did).

use crate::balance::MEMORY_LIMIT;
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};

static USED: Mutex<f64> = Mutex::new(0.0);
static FREED: Condvar = Condvar::new();

fn used() -> MutexGuard<'static, f64> {
    // The guarded value is a plain sum, valid whatever a panicking holder did.
    USED.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A share of the budget, given back when dropped.
#[derive(Debug)]
pub struct Reservation {
    bytes: f64,
}

/// Hold `bytes` of the budget, first waiting while other integrations hold so much
/// that both would not fit. An integration alone always starts: that `bytes` fits
/// the limit at all is the caller's check ([`super::simulate`] refuses more).
pub fn reserve(bytes: f64) -> Reservation {
    let mut held = used();
    while *held > 0.0 && *held + bytes > MEMORY_LIMIT {
        held = FREED.wait(held).unwrap_or_else(PoisonError::into_inner);
    }
    *held += bytes;
    Reservation { bytes }
}

impl Drop for Reservation {
    fn drop(&mut self) {
        let mut held = used();
        *held = (*held - self.bytes).max(0.0);
        FREED.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    #[test]
    fn integrations_that_do_not_fit_together_run_one_after_the_other() {
        let running = Arc::new(AtomicUsize::new(0));
        let most = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..4)
            .map(|_| {
                let (running, most) = (Arc::clone(&running), Arc::clone(&most));
                std::thread::spawn(move || {
                    let _r = reserve(0.6 * MEMORY_LIMIT);
                    let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                    most.fetch_max(now, Ordering::SeqCst);
                    std::thread::sleep(std::time::Duration::from_millis(20));
                    running.fetch_sub(1, Ordering::SeqCst);
                })
            })
            .collect();
        for t in threads {
            t.join().unwrap();
        }
        assert_eq!(most.load(Ordering::SeqCst), 1);
    }
}
