//! (in progress: core issue)
