//! (in progress: continuation issue)
