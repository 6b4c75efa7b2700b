//! A study cut short: by SIGINT (what finished is written, the summary names what did
//! not, exit 130) and by SIGKILL (no file half-written, and the summary of an earlier
//! run in the same directory does not survive to claim that everything finished).

use crate::common::tmp;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn start_study(dir: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_ihbm"))
        .args(["run", "--out"])
        .arg(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the ihbm binary starts")
}

/// Wait until the run has written the CSV of at least one finished part.
fn wait_for_a_part(dir: &Path, child: &mut Child) {
    wait_until(child, || {
        std::fs::read_dir(dir).into_iter().flatten().flatten().any(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.ends_with(".csv") && !name.contains(".ihbm-tmp")
        })
    });
}

fn wait_until(child: &mut Child, done: impl Fn() -> bool) {
    let t = Instant::now();
    loop {
        if done() {
            return;
        }
        assert!(child.try_wait().unwrap().is_none(), "the study ended before any part finished");
        assert!(t.elapsed() < Duration::from_secs(60), "no part finished within 60 s");
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill").args([sig, &child.id().to_string()]).status().unwrap();
    assert!(ok.success());
}

/// Every output file is whole: JSON parses, a CSV's rows have its header's width, an
/// SVG ends its root element; and no temporary file is left but, after a SIGKILL,
/// one of the killed process (`killed`): a kill that lands while a file is being
/// written leaves it under its temporary name, never a truncated output.
fn assert_whole(dir: &Path, killed: Option<u32>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let path = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if let Some(pid) = killed {
            if name.ends_with(&format!(".{pid}.ihbm-tmp")) {
                continue;
            }
        }
        assert!(!name.contains(".ihbm-tmp"), "temporary file left behind: {name}");
        let text = std::fs::read_to_string(&path).unwrap();
        match path.extension().and_then(|x| x.to_str()) {
            Some("json") => {
                serde_json::from_str::<serde_json::Value>(&text)
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
            }
            Some("csv") => {
                let mut lines = text.lines();
                let width = lines.next().map_or(0, |h| h.split(',').count());
                assert!(width > 0 && text.ends_with('\n'), "{name}: no header or cut short");
                for l in lines {
                    assert_eq!(l.split(',').count(), width, "{name}: row '{l}'");
                }
            }
            Some("svg") => assert!(text.trim_end().ends_with("</svg>"), "{name}: cut short"),
            _ => {}
        }
    }
}

#[test]
fn an_interrupted_study_writes_what_finished_and_says_what_did_not() {
    let dir = tmp("interrupted-study");
    let _ = std::fs::remove_dir_all(&dir);
    let mut child = start_study(&dir);
    wait_for_a_part(&dir, &mut child);
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    // The reference study has ~40 parts over several seconds; the signal follows the
    // first one within milliseconds.
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: interrupted: "), "{err}");
    assert_whole(&dir, None);
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("**The run was interrupted**"), "{summary}");
    assert!(!summary.contains("Every part of the study finished"), "{summary}");
    assert!(summary.contains("not started (interrupted)"), "{summary}");
}

#[test]
fn a_killed_study_leaves_no_earlier_summary_and_no_half_written_file() {
    let dir = tmp("killed-study");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // An earlier, complete run's summary.
    std::fs::write(dir.join("summary.md"), "# Study\n\nEvery part of the study finished.\n")
        .unwrap();
    let mut child = start_study(&dir);
    // Until the running summary lists a finished part (its files are written before
    // it is listed).
    let summary = dir.join("summary.md");
    wait_until(&mut child, || {
        std::fs::read_to_string(&summary)
            .is_ok_and(|s| s.contains("(not finished)") && s.contains("\n- "))
    });
    let pid = child.id();
    signal(&child, "-KILL");
    let _ = child.wait();
    assert_whole(&dir, Some(pid));
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    assert!(summary.contains("(not finished)"), "{summary}");
    assert!(!summary.contains("Every part of the study finished"), "{summary}");
    // It lists the parts that had finished.
    let listed: Vec<&str> = summary.lines().filter_map(|l| l.strip_prefix("- ")).collect();
    assert!(!listed.is_empty(), "{summary}");
    // The next run removes what the killed one may have left under a temporary name
    // (as a study does first thing), and only that: the outputs stay.
    let outputs = std::fs::read_dir(&dir).unwrap().count();
    let left = ihbm::report::remove_stale_temporaries(&dir);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), outputs - left);
    assert_whole(&dir, None);
}

/// A sweep stopped by SIGINT writes the points it has traced (its segment ended
/// "stopped") and exits 130. The half car at N = 60 takes tens of seconds, its first
/// point about one (measured: 17 points after 2 s, 106 after 4 s); the signal comes
/// after five, so that there are points to keep however loaded the machine.
#[test]
fn an_interrupted_sweep_writes_its_points_so_far() {
    let json = tmp("interrupted-sweep.json");
    let _ = std::fs::remove_file(&json);
    let child = Command::new(env!("CARGO_BIN_EXE_ihbm"))
        .args(["sweep", "half-car", "--from", "1", "--to", "100", "--harmonics", "60", "--json"])
        .arg(&json)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(5));
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        err.starts_with("error: interrupted: ") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let segs = v["segments"].as_array().unwrap();
    assert_eq!(segs.last().unwrap()["ended"], "stopped", "{segs:?}");
    assert!(v["points"].as_array().unwrap().iter().all(|p| p["omega"].as_f64().is_some()));
}

/// Stopping is prompt even in the middle of one long point: at N = 800 one point of
/// the quarter car takes minutes (a dense factorisation of order 6 400 and its
/// stability), yet SIGTERM ends a study within the grace period of a fraction of a
/// second (allowed here: 5 s), with 130 and a summary naming the curve stopped part
/// way; and a sweep and a fold analysis likewise, saying that nothing was traced.
#[test]
fn a_signal_inside_one_long_point_stops_within_seconds() {
    let dir = tmp("stopped-inside-a-point");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("large.toml");
    std::fs::write(
        &study,
        "title = \"Large N\"\nmodel = \"quarter-car\"\nharmonics = 800\noutputs = [\"z1\"]\n\
         frequency = { from = 1.0, to = 100.0 }\n\n[[figure]]\nid = \"large\"\ntitle = \"N = 800\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_ihbm"))
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let summary = out.join("summary.md");
    wait_until(&mut child, || summary.exists());
    std::thread::sleep(Duration::from_millis(500));
    let (code, err, waited) = stop_and_wait(child, "-TERM");
    assert!(waited < Duration::from_secs(5), "exited {waited:?} after the signal");
    assert_eq!(code, Some(130), "{err}");
    let summary = std::fs::read_to_string(&summary).unwrap();
    assert!(summary.contains("large, quarter-car: stopped part way (interrupted)"), "{summary}");
    assert_whole(&out, None);

    let json = dir.join("sweep.json");
    let sweep = ["sweep", "quarter-car", "--from", "1", "--to", "100", "--harmonics", "800"];
    let err = terminated(&sweep, &json, Duration::from_secs(1));
    assert_eq!(err.trim_end(), "error: interrupted before the first point: nothing written");
    assert!(!json.exists());

    // A fold analysis: its end sweeps at N = 600 take minutes too.
    let json = dir.join("folds.json");
    let folds = ["folds", "duffing", "--param", "F", "--from", "0.01", "--to", "0.3"];
    let window = ["--omega-from", "0.5", "--omega-to", "3", "--harmonics", "600"];
    let err = terminated(&[&folds[..], &window].concat(), &json, Duration::from_secs(1));
    assert!(err.starts_with("error: interrupted before the first fold"), "{err}");
}

/// A backbone and a family of limit cycles stop at a signal too, within the grace
/// period: their points so far are written, ended "stopped", with exit code 130 and a
/// message that counts them.
#[test]
fn an_interrupted_backbone_or_family_writes_its_points_so_far() {
    let dir = tmp("stopped-backbone");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let cycles = ["cycle", "van-der-pol", "--omega", "1", "--param", "mu", "--from", "1"];
    let cycles = [&cycles[..], &["--to", "-0.5", "--harmonics", "200"]].concat();
    let runs: [(&str, &[&str]); 2] = [
        ("backbone", &["backbone", "quarter-car", "--to", "300", "--harmonics", "300"]),
        ("cycles", &cycles),
    ];
    // Both at once (each waits seconds for its points).
    std::thread::scope(|scope| {
        for (what, args) in runs {
            let dir = &dir;
            scope.spawn(move || {
                let json = dir.join(format!("{what}.json"));
                // The first point takes a second or so, longer while other tests load the
                // machine: a signal before it writes nothing, so a later one is tried then.
                let mut stopped = None;
                for wait in [2, 5, 10] {
                    let err = terminated(args, &json, Duration::from_secs(wait));
                    if json.exists() {
                        stopped = Some(err);
                        break;
                    }
                    assert!(err.contains("interrupted before the first"), "{what}: {err}");
                }
                let err = stopped.unwrap_or_else(|| panic!("{what}: no point in 10 s"));
                let v: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
                assert_eq!(v["ended"], "stopped", "{what}");
                let n = v["points"].as_array().unwrap().len();
                assert!(n >= 1, "{what}");
                assert_eq!(
                    err.trim_end(),
                    format!("error: interrupted: the {n} point(s) traced so far are written"),
                    "{what}"
                );
            });
        }
    });
}

/// Send `sig` and wait for the exit: its code, its standard error, and how long it
/// took after the signal.
/// Run `ihbm ARGS --json JSON`, send SIGTERM after `wait`, and check that it exits
/// within the grace period (allowed: 5 s) with code 130; its standard error.
fn terminated(args: &[&str], json: &Path, wait: Duration) -> String {
    let child = Command::new(env!("CARGO_BIN_EXE_ihbm"))
        .args(args)
        .arg("--json")
        .arg(json)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(wait);
    let (code, err, waited) = stop_and_wait(child, "-TERM");
    assert!(waited < Duration::from_secs(5), "{args:?}: exited {waited:?} after the signal");
    assert_eq!(code, Some(130), "{args:?}: {err}");
    err
}

fn stop_and_wait(child: Child, sig: &str) -> (Option<i32>, String, Duration) {
    signal(&child, sig);
    let t = Instant::now();
    let out = child.wait_with_output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned(), t.elapsed())
}
