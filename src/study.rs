//! (in progress: CLI issue)
