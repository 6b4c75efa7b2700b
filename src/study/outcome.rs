//! What a study run produced: the files, the failures, the timings, what an
//! interruption left unfinished.

use std::path::PathBuf;

/// What a study run produced.
#[derive(Debug, Clone, Default)]
pub struct StudyOutcome {
    /// Files written, in order.
    pub files: Vec<PathBuf>,
    /// One line per failed part (curve, time-domain point, file).
    pub failures: Vec<String>,
    /// Wall time, s.
    pub seconds: f64,
    /// Compute time per figure id, s (summed over its jobs, so more than wall time
    /// when jobs ran in parallel).
    pub figure_seconds: Vec<(String, f64)>,
    /// Whether the run was cut short ([`run_until`](super::run_until)'s flag was set).
    pub interrupted: bool,
    /// The parts an interruption left unfinished: not started, or stopped part way
    /// (what they had computed is written).
    pub unfinished: Vec<String>,
}

impl StudyOutcome {
    /// Record the files and failures of `other` after ours.
    pub(super) fn append(&mut self, other: StudyOutcome) {
        self.files.extend(other.files);
        self.failures.extend(other.failures);
        self.unfinished.extend(other.unfinished);
    }
}
