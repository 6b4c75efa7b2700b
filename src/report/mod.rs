//! Turning results into files a user reads: CSV, JSON, SVG figures and `summary.md`.
//!
//! Data flows one way: solvers fill [`crate::results`] types (or the records below),
//! this module only formats them. Every writer takes data and returns text or writes
//! one file; nothing here solves anything.

pub mod csv;
pub mod json;
pub mod legend;
pub mod plot;
pub mod smooth;
pub mod summary;

use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::path::Path;

pub use csv::{backbone_csv, curve_csv, cycles_csv, folds_csv, Num, STATS};
pub use json::{
    backbone_json, cycle_json, cycles_json, folds_json, simulate_json, solve_json, sweep_json,
};
pub use plot::{
    backbone_svg, cycles_svg, figure_svg, figure_svg_modes, figure_svg_with, folds_svg,
    folds_svg_family, trend_svg, Figure, Overlay, Panel, Series, TimeMarker,
};
pub use summary::{convergence_line, curve_facts, CurveFacts};

/// The unit of the frequency axis of figures (data files are always in rad/s).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FreqUnit {
    /// Radians per second (the solvers' unit).
    #[default]
    #[serde(rename = "rad/s")]
    RadPerSec,
    /// Hertz: Ω / 2π.
    #[serde(rename = "Hz")]
    Hz,
}

impl FreqUnit {
    /// Convert a frequency in rad/s to this unit.
    pub fn from_rad(self, omega: f64) -> f64 {
        match self {
            FreqUnit::RadPerSec => omega,
            FreqUnit::Hz => omega / std::f64::consts::TAU,
        }
    }

    /// The unit as printed on axes.
    pub fn label(self) -> &'static str {
        match self {
            FreqUnit::RadPerSec => "rad/s",
            FreqUnit::Hz => "Hz",
        }
    }
}

/// The suffix of the temporary file [`write_file`] writes before renaming it into
/// place: `NAME.PID.ihbm-tmp`, `PID` the writing process's.
const TMP_SUFFIX: &str = ".ihbm-tmp";

/// Remove the temporary files that runs killed outright (SIGKILL, a power cut: no
/// chance to clean up) left in `dir`, and say how many. Only files of
/// [`write_file`]'s pattern whose process no longer runs (on Linux, no `/proc/PID`);
/// elsewhere, where that cannot be told, only this process's own. A directory that
/// cannot be read has nothing to remove.
///
/// ```
/// let dir = std::env::temp_dir().join(format!("ihbm-doc-stale-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// // A process id no process has (beyond Linux's pid_max).
/// std::fs::write(dir.join("fig.csv.4194305.ihbm-tmp"), "half").unwrap();
/// std::fs::write(dir.join("fig.csv"), "whole").unwrap();
/// // Process 1 runs (init): its file may still be renamed into place.
/// std::fs::write(dir.join("fig.svg.1.ihbm-tmp"), "being written").unwrap();
/// # #[cfg(target_os = "linux")]
/// assert_eq!(ihbm::report::remove_stale_temporaries(&dir), 1);
/// assert!(dir.join("fig.csv").exists() && dir.join("fig.svg.1.ihbm-tmp").exists());
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn remove_stale_temporaries(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else { return 0 };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_suffix(TMP_SUFFIX)
            .and_then(|rest| rest.rsplit('.').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let gone = if pid == std::process::id() {
            true
        } else {
            cfg!(target_os = "linux") && !Path::new("/proc").join(pid.to_string()).exists()
        };
        if gone && std::fs::remove_file(e.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Write `text` to `path`, creating parent directories; errors name the path.
///
/// The file is written whole or not at all: the text goes to a temporary file beside
/// `path` (same directory, so the rename cannot cross file systems), which is then
/// renamed over `path`. An interrupt, a full disk or a file-size limit leaves the old
/// file (or none) and at worst a `.ihbm-tmp` file, never a truncated `path`; a
/// study removes such files left by killed runs ([`remove_stale_temporaries`]).
///
/// A `path` that exists and is not a regular file (a device such as `/dev/stdout`, a
/// named pipe) is written in place: renaming over it would replace the device by a
/// file and report success while nothing reached it. Every write error then fails the
/// call too (`/dev/full` gives "No space left on device").
///
/// ```
/// let dir = std::env::temp_dir().join(format!("ihbm-doc-write-{}", std::process::id()));
/// let path = dir.join("a/b.txt");
/// ihbm::report::write_file(&path, "one")?;
/// ihbm::report::write_file(&path, "two")?;
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "two");
/// let left: Vec<_> = std::fs::read_dir(dir.join("a")).unwrap().collect();
/// assert_eq!(left.len(), 1, "no temporary file is left behind");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), ihbm::Error>(())
/// ```
pub fn write_file(path: &Path, text: &str) -> Result<(), Error> {
    fn io(p: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
        move |source| Error::Io { path: p.display().to_string(), source }
    }
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
        }
    }
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        use std::io::Write as _;
        return std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut f| f.write_all(text.as_bytes()).and_then(|()| f.flush()))
            .map_err(io(path));
    }
    let mut tmp_name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    tmp_name.push(format!(".{}{TMP_SUFFIX}", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let written = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        // Nothing half-written stays behind; the original error is the one to report.
        let _ = std::fs::remove_file(&tmp);
    }
    written.map_err(io(path))
}
