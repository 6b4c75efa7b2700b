//! (in progress: time-domain issue)
