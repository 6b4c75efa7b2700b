//! Running a validated study: every curve and time-domain point as an independent
//! job (in parallel), then the files of every figure from whatever finished.

use super::claims::{fmt_num, Member, TdRow};
use super::outcome::StudyOutcome;
use super::spec::{BackboneSpec, Study, Vary};
use super::summary::{self, FigureResult, FoldMember};
use crate::bifurcation::FoldCurves;
use crate::continuation::Control;
use crate::engine::analysis::{Analysis, Outcome, Progress};
use crate::engine::detach::{self, Detached, Partial};
use crate::engine::progress;
use crate::engine::registry::{NamedModel, Registry};
use crate::engine::{ArgNames, SimSettings, SweepBackbone, SweepSettings};
use crate::error::{Error, Result};
use crate::report::{self, Figure, FreqUnit, Panel, Series, TimeMarker};
use crate::results::Curve;
use crate::timedomain::CompareRow;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

struct CurvePlan {
    label: String,
    value: f64,
    model: NamedModel,
    sweep: SweepSettings,
    stem: String,
}

struct TdPlan {
    omega: f64,
    sim: SimSettings,
}

/// What a figure computes: one kind or the other, never a mix (the study file's
/// checks refuse `timedomain`, `check` and `backbone` in a fold figure).
enum FigureKind {
    /// Amplitude–frequency curves, one per value of `vary`, with comparisons against
    /// time integration and backbones drawn over them.
    Curves {
        td: Vec<TdPlan>,
        /// The backbones drawn over the curves (of `td_model`: the figure's model).
        backbone: Option<BackboneSpec>,
    },
    /// Fold, period-doubling or torus curves in the plane of Ω and a parameter, one
    /// analysis per value of `vary`.
    Folds(FoldPlan),
}

/// The parameter and range of a fold figure.
struct FoldPlan {
    param: String,
    from: f64,
    to: f64,
    boundary: crate::bifurcation::Boundary,
}

struct FigurePlan {
    id: String,
    kind: FigureKind,
    title: String,
    unit: FreqUnit,
    outputs: Vec<String>,
    range: (f64, f64),
    harmonics: usize,
    curves: Vec<CurvePlan>,
    td_model: NamedModel,
}

impl FigurePlan {
    /// The time-domain comparison points (none in a fold figure).
    fn td(&self) -> &[TdPlan] {
        match &self.kind {
            FigureKind::Curves { td, .. } => td,
            FigureKind::Folds(_) => &[],
        }
    }

    /// The backbones asked for (never in a fold figure).
    fn backbone(&self) -> Option<&BackboneSpec> {
        match &self.kind {
            FigureKind::Curves { backbone, .. } => backbone.as_ref(),
            FigureKind::Folds(_) => None,
        }
    }

    fn is_folds(&self) -> bool {
        matches!(self.kind, FigureKind::Folds(_))
    }

    /// The stem of the files of the backbone of `mode` continued in `output`.
    fn backbone_stem(&self, mode: usize, output: &str) -> String {
        format!("{}_backbone{mode}_{output}", self.id)
    }

    /// The modes whose backbones may be drawn: those listed, or (for `true`) every
    /// mode of the model, of which those in the frequency range are.
    fn backbone_modes(&self) -> Vec<usize> {
        match self.backbone().map(BackboneSpec::modes) {
            None => Vec::new(),
            Some(Some(m)) => m.to_vec(),
            Some(None) => (1..=self.td_model.dofs().len()).collect(),
        }
    }
}

/// One parallel job of figure `.0`: the analysis at its value `.1` (a curve, or fold
/// curves, by the figure's kind), or its harmonic-balance/time-integration comparison
/// at point `.1`.
#[derive(Clone, Copy)]
enum Job {
    Value(usize, usize),
    Compare(usize, usize),
}

impl Job {
    fn figure(self) -> usize {
        match self {
            Job::Value(f, _) | Job::Compare(f, _) => f,
        }
    }

    fn index(self) -> usize {
        match self {
            Job::Value(_, k) | Job::Compare(_, k) => k,
        }
    }
}

/// How the analyses of a study name what they check: by the study file's keys (the
/// study's own checks, with line and column, have run before any job starts).
const STUDY_NAMES: ArgNames = ArgNames {
    from: "frequency",
    to: "frequency",
    omega: "timedomain.omegas",
    omega_from: "frequency",
    omega_to: "frequency",
    setting: sweep_key,
};

fn sweep_key(key: &str) -> String {
    format!("sweep.{key}")
}

/// What the jobs of one figure produced.
struct Finished {
    curves: Vec<Option<Curve>>,
    folds: Vec<Option<FoldCurves>>,
    rows: Vec<Option<CompareRow>>,
    /// The backbones over the curves (empty without `backbone`).
    backbones: Vec<SweepBackbone>,
    seconds: f64,
}

fn plan(study: &Study, reg: &Registry) -> Result<Vec<FigurePlan>> {
    let mut plans = Vec::new();
    for fig in &study.figures {
        let id = fig.id.get_ref().clone();
        let model = study.figure_model(fig, reg)?;
        let harmonics = fig.harmonics.unwrap_or(study.harmonics);
        let range = fig.frequency.unwrap_or(study.frequency);
        let sweep = study.sweep.merged(fig.sweep.as_ref());
        let mut curves = Vec::new();
        match &fig.vary {
            None => curves.push(CurvePlan {
                label: model.name().to_string(),
                value: f64::NAN,
                model: model.clone(),
                sweep: SweepSettings { harmonics, ..sweep.clone() },
                stem: id.clone(),
            }),
            Some(v) => {
                for &x in &fig.values {
                    let mut m = model.clone();
                    let mut n = harmonics;
                    let name = v.get_ref().as_str();
                    let label = match v.get_ref() {
                        Vary::Harmonics => {
                            n = x as usize;
                            format!("N = {n}")
                        }
                        Vary::Param(name) => {
                            m.set_param(name, x)?;
                            format!("{name} = {}", fmt_num(x))
                        }
                    };
                    curves.push(CurvePlan {
                        label,
                        value: x,
                        model: m,
                        sweep: SweepSettings { harmonics: n, ..sweep.clone() },
                        stem: format!("{id}_{name}_{}", fmt_num(x)),
                    });
                }
            }
        }
        let mut td = Vec::new();
        if let Some(t) = &fig.timedomain {
            for &w in &t.omegas {
                for &scheme in &t.schemes {
                    let periods = t.periods.unwrap_or(SimSettings::default().periods);
                    let dt = t.steps_per_period.map(|s| std::f64::consts::TAU / (w * s));
                    td.push(TdPlan { omega: w, sim: SimSettings { dt, periods, scheme } });
                }
            }
        }
        let kind = match &fig.folds {
            Some(f) => FigureKind::Folds(FoldPlan {
                param: f.param.get_ref().clone(),
                from: f.from,
                to: f.to,
                boundary: f.boundary,
            }),
            None => FigureKind::Curves {
                td,
                backbone: fig.backbone.as_ref().map(|b| b.get_ref().clone()),
            },
        };
        plans.push(FigurePlan {
            title: fig.title.clone().unwrap_or_else(|| id.clone()),
            kind,
            id,
            unit: fig.unit.unwrap_or(study.unit),
            outputs: study.figure_outputs(fig, &model),
            range: (range.from, range.to),
            harmonics,
            curves,
            td_model: model,
        });
    }
    Ok(plans)
}

/// The file names a run of `study` may write (in its output directory; a figure
/// with `backbone = true` writes those of the modes in its range), each with the
/// part it belongs to. Two parts on one name would overwrite each other: that is an
/// error naming both (for example `values = [0.1, 0.1000001]`, equal in file names,
/// or a figure `f1_F_1` beside figure `f1` varying `F` over 1).
pub fn output_files(study: &Study, reg: &Registry) -> Result<Vec<String>> {
    let plans = plan(study, reg)?;
    let mut files: Vec<(String, String)> = Vec::new();
    for p in &plans {
        for c in &p.curves {
            let part = format!("figure '{}', {}", p.id, c.label);
            files.push((format!("{}.csv", c.stem), part.clone()));
            files.push((format!("{}.json", c.stem), part));
        }
        if !p.td().is_empty() {
            files.push((format!("{}_timedomain.csv", p.id), format!("figure '{}'", p.id)));
        }
        for k in p.backbone_modes() {
            for o in &p.outputs {
                let part = format!("figure '{}', the backbone of mode {k} on {o}", p.id);
                files.push((format!("{}.csv", p.backbone_stem(k, o)), part.clone()));
                files.push((format!("{}.json", p.backbone_stem(k, o)), part));
            }
        }
        if p.is_folds() && p.curves.len() > 1 {
            files.push((format!("{}_cusps.svg", p.id), format!("figure '{}'", p.id)));
        }
        files.push((format!("{}.svg", p.id), format!("figure '{}'", p.id)));
    }
    files.push(("summary.md".into(), "the summary".into()));
    let mut seen: std::collections::HashMap<&str, &str> = std::collections::HashMap::new();
    for (name, part) in &files {
        if let Some(first) = seen.insert(name, part) {
            return Err(Error::Study(format!(
                "{first} and {part} would both write {name}: give them distinct ids or values"
            )));
        }
    }
    Ok(files.into_iter().map(|(n, _)| n).collect())
}

/// Run `study` (already validated) and write its files into `dir`: per curve a CSV
/// and a sweep JSON, per figure an SVG (and a time-domain CSV), and `summary.md`.
/// Failed parts are listed in the outcome and in `summary.md`; the rest is written.
pub fn run(study: &Study, reg: &Registry, dir: &Path) -> Result<StudyOutcome> {
    run_until(study, reg, dir, &Arc::new(AtomicBool::new(false)))
}

/// [`run`], cut short when `stop` is set (by a signal handler, say): no part starts
/// after that, and within a fraction of a second ([`detach::GRACE`]) the figures and
/// `summary.md` are written from whatever finished, each curve or fold analysis
/// still running kept as far as it had come (ended "stopped"), the summary naming
/// the parts left unfinished. The computation runs on threads of its own, so a
/// point that takes minutes does not hold the stop up; it is abandoned, and the
/// process is expected to exit. Each curve's CSV and JSON are written as soon as
/// it finishes, and until the run ends `summary.md` says that it has not finished
/// and which parts have, so a run killed outright leaves no summary of an earlier
/// run behind.
pub fn run_until(
    study: &Study,
    reg: &Registry,
    dir: &Path,
    stop: &Arc<AtomicBool>,
) -> Result<StudyOutcome> {
    let start = Instant::now();
    output_files(study, reg)?;
    let plans = Arc::new(plan(study, reg)?);
    std::fs::create_dir_all(dir)
        .map_err(|source| Error::Io { path: dir.display().to_string(), source })?;
    // A run killed outright here before may have left a file half-written under its
    // temporary name.
    crate::report::remove_stale_temporaries(dir);
    let mut out = StudyOutcome::default();
    let log = RunLog::start(study, dir, &mut out);
    let jobs = Arc::new(Jobs::new(&plans, dir.to_path_buf(), log));
    let running = {
        let (jobs, plans, flag) = (Arc::clone(&jobs), Arc::clone(&plans), Arc::clone(stop));
        detach::run(stop.as_ref(), move || jobs.run(&plans, &flag))
    };
    if let Detached::Panicked(why) = &running {
        out.failures.push(format!("the run ended abnormally: {why}"));
    }
    let mut finished = jobs.collect(&plans, &mut out);
    if !stop.load(Ordering::Relaxed) && !matches!(running, Detached::Panicked(_)) {
        let (plans, tops) = (Arc::clone(&plans), backbone_tops(&plans, &finished));
        match detach::run(stop.as_ref(), move || backbones(&plans, &tops)) {
            Detached::Returned(found) => {
                for (done, (b, t)) in finished.iter_mut().zip(found) {
                    done.backbones = b;
                    done.seconds += t;
                }
            }
            Detached::Abandoned => {}
            Detached::Panicked(why) => out.failures.push(format!("backbones: {why}")),
        }
    }
    out.interrupted = stop.load(Ordering::Relaxed);
    let mut results = Vec::new();
    for (f, (p, done)) in plans.iter().zip(&finished).enumerate() {
        results.push(write_figure(study, f, p, done, dir, &mut out));
    }
    out.seconds = start.elapsed().as_secs_f64();
    let md = summary::markdown(study, &results, &out);
    write(dir, "summary.md".into(), &md, &mut out);
    Ok(out)
}

/// `summary.md` while a run is under way: that it has not finished, and the parts
/// that have (rewritten as each finishes).
struct RunLog {
    dir: PathBuf,
    title: String,
    done: Mutex<Vec<String>>,
}

impl RunLog {
    fn start(study: &Study, dir: &Path, out: &mut StudyOutcome) -> Self {
        let log = RunLog {
            dir: dir.to_path_buf(),
            title: study.title.clone().unwrap_or_else(|| "Study".into()),
            done: Mutex::new(Vec::new()),
        };
        if let Err(e) = report::write_file(&dir.join("summary.md"), &log.text(&[])) {
            out.failures.push(e.to_string());
        }
        log
    }

    fn text(&self, done: &[String]) -> String {
        let mut s = format!(
            "# {} (not finished)\n\nThis run has not finished: it is still running, or it was \
             cut short before it could write its summary. The files of the parts listed here \
             are from this run; any other file in this directory is from an earlier one.\n\n\
             Done so far ({}):\n\n",
            self.title,
            done.len()
        );
        for d in done {
            s.push_str(&format!("- {d}\n"));
        }
        s
    }

    /// Record `part` as finished (a failure to rewrite the file only costs the note).
    fn finished(&self, part: String) {
        let Ok(mut done) = self.done.lock() else { return };
        done.push(part);
        let _ = report::write_file(&self.dir.join("summary.md"), &self.text(&done));
    }
}

/// Where one job stands, readable by the waiting thread whether or not the job ever
/// returns.
enum Slot {
    /// Not started.
    Pending,
    /// Started (what it has traced so far is in its [`Partial`]).
    Running,
    /// Finished, its files written: the result, seconds taken, files and notes.
    Done(Box<Result<Outcome>>, f64, Box<StudyOutcome>),
}

/// The model a job runs on, what it runs, and how its progress is labelled.
fn job_analysis(plans: &[FigurePlan], job: Job) -> (&NamedModel, Analysis, String) {
    let p = &plans[job.figure()];
    match (job, &p.kind) {
        (Job::Value(_, k), FigureKind::Curves { .. }) => {
            let c = &p.curves[k];
            let (from, to) = p.range;
            let analysis = Analysis::Sweep { from, to, settings: c.sweep.clone() };
            (&c.model, analysis, c.model.name().to_string())
        }
        (Job::Value(_, k), FigureKind::Folds(fp)) => {
            let c = &p.curves[k];
            let analysis = Analysis::Folds {
                param: fp.param.clone(),
                from: fp.from,
                to: fp.to,
                omega: p.range,
                boundary: fp.boundary,
                settings: c.sweep.clone(),
            };
            (&c.model, analysis, format!("{}: {} curves, {}", p.id, fp.boundary, c.label))
        }
        (Job::Compare(_, k), _) => {
            let td = &p.td()[k];
            let analysis =
                Analysis::Compare { omega: td.omega, sim: td.sim.clone(), harmonics: p.harmonics };
            (&p.td_model, analysis, part_name(plans, job))
        }
    }
}

/// Every job of a run and where each stands. Workers write files only while the run
/// is open; the waiting thread closes it before it writes from the slots, so no file
/// is written twice at once and none after the run's own summary.
struct Jobs {
    list: Vec<Job>,
    slots: Vec<Mutex<Slot>>,
    partials: Vec<Partial>,
    open: Mutex<bool>,
    dir: PathBuf,
    log: RunLog,
    pb: indicatif::ProgressBar,
}

impl Jobs {
    fn new(plans: &[FigurePlan], dir: PathBuf, log: RunLog) -> Self {
        let mut list = Vec::new();
        for (f, p) in plans.iter().enumerate() {
            list.extend((0..p.curves.len()).map(|k| Job::Value(f, k)));
            list.extend((0..p.td().len()).map(|k| Job::Compare(f, k)));
        }
        let slots = list.iter().map(|_| Mutex::new(Slot::Pending)).collect();
        let partials = list.iter().map(|_| Partial::default()).collect();
        let pb = progress::bar(list.len() as u64, "curves and time-domain points");
        Jobs { list, slots, partials, open: Mutex::new(true), dir, log, pb }
    }

    fn set(&self, i: usize, slot: Slot) {
        if let Ok(mut s) = self.slots[i].lock() {
            *s = slot;
        }
    }

    /// Every curve and comparison of every figure, in parallel, each result left in
    /// its slot (files written as each finishes).
    fn run(&self, plans: &[FigurePlan], stop: &AtomicBool) {
        let stopped = || stop.load(Ordering::Relaxed);
        (0..self.list.len()).into_par_iter().for_each(|i| {
            if stopped() {
                return;
            }
            let job = self.list[i];
            self.set(i, Slot::Running);
            let t = Instant::now();
            let (model, analysis, label) = job_analysis(plans, job);
            let mut show = |p: &Progress<'_>| {
                if stopped() {
                    return Control::Stop;
                }
                self.pb.set_message(progress::message(&label, p));
                Control::Continue
            };
            let r = model.run(&analysis, &STUDY_NAMES, &mut self.partials[i].watching(&mut show));
            let t = t.elapsed().as_secs_f64();
            let Ok(open) = self.open.lock() else { return };
            if !*open {
                return; // the waiting thread has taken over: it writes from the copy
            }
            let mut written = StudyOutcome::default();
            if let Ok(o) = &r {
                write_outcome(&self.dir, plans, job, o, &mut written);
            }
            // A part the interruption cut short is unfinished, though what it
            // computed is kept.
            let part = part_name(plans, job);
            if stopped() && !matches!(r, Ok(Outcome::Compared(_))) {
                written.unfinished.push(format!("{part}: stopped part way (interrupted)"));
            } else {
                let failed = match &r {
                    Ok(Outcome::Compared(row)) => row.failure.is_some(),
                    r => r.is_err(),
                };
                self.log.finished(if failed { format!("{part} (failed: no files)") } else { part });
            }
            self.pb.inc(1);
            self.set(i, Slot::Done(Box::new(r), t, Box::new(written)));
        });
    }

    /// Close the run and gather every slot by figure: finished parts as they are,
    /// parts still running as far as they came (their files written here), parts not
    /// started noted as such.
    fn collect(&self, plans: &[FigurePlan], out: &mut StudyOutcome) -> Vec<Finished> {
        if let Ok(mut open) = self.open.lock() {
            *open = false;
        }
        self.pb.finish_and_clear();
        let mut finished: Vec<Finished> = plans
            .iter()
            .map(|p| Finished {
                curves: p.curves.iter().map(|_| None).collect(),
                folds: p.curves.iter().map(|_| None).collect(),
                rows: p.td().iter().map(|_| None).collect(),
                backbones: Vec::new(),
                seconds: 0.0,
            })
            .collect();
        for (i, (&job, slot)) in self.list.iter().zip(&self.slots).enumerate() {
            let slot = match slot.lock() {
                Ok(mut s) => std::mem::replace(&mut *s, Slot::Pending),
                Err(_) => Slot::Pending,
            };
            let part = || part_name(plans, job);
            let (f, k) = (job.figure(), job.index());
            match slot {
                Slot::Pending => {
                    out.unfinished.push(format!("{}: not started (interrupted)", part()))
                }
                Slot::Running => {
                    out.unfinished.push(format!("{}: stopped part way (interrupted)", part()));
                    let (model, analysis, _) = job_analysis(plans, job);
                    if let Some(o) = self.partials[i].outcome(model.name(), &analysis) {
                        write_outcome(&self.dir, plans, job, &o, out);
                        finished[f].keep(k, o);
                    }
                }
                Slot::Done(r, t, written) => {
                    out.append(*written);
                    finished[f].seconds += t;
                    match *r {
                        Ok(o) => {
                            if let Outcome::Compared(row) = &o {
                                if let Some(why) = &row.failure {
                                    out.failures.push(format!("{}: {why}", part()));
                                }
                            }
                            finished[f].keep(k, o);
                        }
                        Err(e) => out.failures.push(format!("{}: {e}", part())),
                    }
                }
            }
        }
        finished
    }
}

impl Finished {
    /// Keep the outcome of job `k` of its kind.
    fn keep(&mut self, k: usize, o: Outcome) {
        match o {
            Outcome::Curve(c) => self.curves[k] = Some(c),
            Outcome::Folds(f) => self.folds[k] = Some(f),
            Outcome::Compared(row) => self.rows[k] = Some(row),
            _ => {}
        }
    }
}

/// A finished (or stopped) job's files: a curve's or fold analysis's CSV and JSON.
fn write_outcome(dir: &Path, plans: &[FigurePlan], job: Job, o: &Outcome, out: &mut StudyOutcome) {
    let Job::Value(f, k) = job else { return };
    let stem = &plans[f].curves[k].stem;
    match o {
        Outcome::Curve(c) => write_curve(dir, stem, c, out),
        Outcome::Folds(folds) => write_folds(dir, stem, folds, out),
        _ => {}
    }
}

/// How a job is named in failures and in the summary.
fn part_name(plans: &[FigurePlan], job: Job) -> String {
    match job {
        Job::Value(f, k) => format!("{}, {}", plans[f].id, plans[f].curves[k].label),
        Job::Compare(f, k) => {
            let td = &plans[f].td()[k];
            format!(
                "{}, time-domain check ({}) at Ω = {}",
                plans[f].id,
                td.sim.scheme.name(),
                td.omega
            )
        }
    }
}

/// A finished curve's CSV and sweep JSON.
fn write_curve(dir: &Path, stem: &str, c: &Curve, out: &mut StudyOutcome) {
    write(dir, format!("{stem}.csv"), &report::curve_csv(c), out);
    let json = serde_json::to_string_pretty(&report::sweep_json(c)).unwrap_or_default();
    write(dir, format!("{stem}.json"), &json, out);
}

/// A finished fold analysis's CSV and JSON.
fn write_folds(dir: &Path, stem: &str, folds: &FoldCurves, out: &mut StudyOutcome) {
    write(dir, format!("{stem}.csv"), &report::folds_csv(folds), out);
    let json = serde_json::to_string_pretty(&report::folds_json(folds)).unwrap_or_default();
    write(dir, format!("{stem}.json"), &json, out);
}

/// The backbones of every figure that asks for them, in parallel over figures: of
/// the figure's model, each mode continued in each panel's output to the largest
/// amplitude of it on the finished curves ([`Analysis::Backbones`]).
fn backbones(plans: &[FigurePlan], tops: &[Vec<f64>]) -> Vec<(Vec<SweepBackbone>, f64)> {
    plans
        .par_iter()
        .zip(tops.par_iter())
        .map(|(p, tops)| {
            let Some(spec) = p.backbone() else { return (Vec::new(), 0.0) };
            let t = Instant::now();
            let (range, keep) = match spec.modes() {
                None => (p.range, None),
                Some(modes) => ((0.0, f64::INFINITY), Some(modes)),
            };
            let mut found = match keep {
                Some([]) => Vec::new(),
                _ => {
                    let analysis =
                        Analysis::Backbones { range, tops: tops.clone(), harmonics: p.harmonics };
                    match p.td_model.run(&analysis, &STUDY_NAMES, &mut ()) {
                        Ok(Outcome::Backbones(found)) => found,
                        _ => Vec::new(),
                    }
                }
            };
            if let Some(keep) = keep {
                found.retain(|b| keep.contains(&b.mode));
                found.sort_by_key(|b| keep.iter().position(|&k| k == b.mode));
            }
            (found, t.elapsed().as_secs_f64())
        })
        .collect()
}

/// For each figure, the amplitude each output's backbone is continued to: the
/// largest on its finished curves, 0 (not continued) for an output on no panel.
fn backbone_tops(plans: &[FigurePlan], finished: &[Finished]) -> Vec<Vec<f64>> {
    plans
        .iter()
        .zip(finished)
        .map(|(p, done)| {
            let names: Vec<&str> = p.td_model.outputs().iter().map(|o| &*o.name).collect();
            let mut tops =
                crate::engine::largest_amplitudes(done.curves.iter().flatten(), names.len());
            for (t, n) in tops.iter_mut().zip(&names) {
                if !p.outputs.iter().any(|o| o == n) {
                    *t = 0.0; // not on a panel: not continued
                }
            }
            tops
        })
        .collect()
}

/// Write `text` to `dir/name`, recording the file or the failure.
fn write(dir: &Path, name: String, text: &str, out: &mut StudyOutcome) {
    let path = dir.join(name);
    match report::write_file(&path, text) {
        Ok(()) => out.files.push(path),
        Err(e) => out.failures.push(e.to_string()),
    }
}

/// The comparisons of one figure as rows per output (only where both methods gave a
/// value).
fn td_rows(p: &FigurePlan, done: &Finished) -> Vec<TdRow> {
    let mut rows = Vec::new();
    for (row, tp) in done.rows.iter().zip(p.td()) {
        let Some(row) = row else { continue };
        for o in row.outputs.iter().filter(|o| o.hb_max_abs.is_finite() && o.td_max_abs.is_finite())
        {
            rows.push(TdRow {
                omega: tp.omega,
                scheme: tp.sim.scheme.name().to_string(),
                output: o.name.clone(),
                ihbm: o.hb_max_abs,
                sim: o.td_max_abs,
            });
        }
    }
    rows
}

/// The files of figure `f` (curves' CSV and JSON, the time-domain CSV, the SVG) and
/// its result for the summary.
fn write_figure<'a>(
    study: &'a Study,
    f: usize,
    p: &FigurePlan,
    done: &'a Finished,
    dir: &Path,
    out: &mut StudyOutcome,
) -> FigureResult<'a> {
    if let FigureKind::Folds(fp) = &p.kind {
        return write_fold_figure(study, f, p, fp, done, dir, out);
    }
    let mut members = Vec::new();
    for (c, plan) in done.curves.iter().zip(&p.curves) {
        if let Some(c) = c {
            members.push(Member { label: plan.label.clone(), value: plan.value, curve: c });
        }
    }
    let td_rows = td_rows(p, done);
    if !p.td().is_empty() {
        let mut csv = String::from("omega,scheme,output,ihbm_max_abs,sim_max_abs,rel_diff\n");
        for r in &td_rows {
            csv.push_str(&format!(
                "{},{},{},{},{},{}\n",
                report::Num(r.omega),
                r.scheme,
                r.output,
                report::Num(r.ihbm),
                report::Num(r.sim),
                report::Num(r.rel_diff())
            ));
        }
        write(dir, format!("{}_timedomain.csv", p.id), &csv, out);
    }
    let markers: Vec<TimeMarker> = td_rows
        .iter()
        .map(|r| TimeMarker {
            label: format!("time integration ({})", r.scheme.to_uppercase()),
            omega: r.omega,
            output: r.output.clone(),
            value: r.sim,
        })
        .collect();
    let fig = Figure {
        title: p.title.clone(),
        unit: p.unit,
        panels: p
            .outputs
            .iter()
            .map(|o| Panel {
                output: o.clone(),
                label: study.labels.get(o).cloned().unwrap_or_else(|| format!("max |{o}|")),
            })
            .collect(),
        series: members.iter().map(|m| Series { label: m.label.clone(), curve: m.curve }).collect(),
        markers,
    };
    let overlays = write_backbones(p, done, dir, out);
    let names = p.td_model.outputs();
    let modes: Vec<(String, &crate::backbone::Backbone)> = done
        .backbones
        .iter()
        .filter_map(|sb| {
            let b = sb.backbone.as_ref().ok()?;
            Some((format!("mode {}, max |{}|", sb.mode, names.get(sb.output)?.name), b))
        })
        .collect();
    if members.is_empty() && td_rows.is_empty() {
        nothing_drawn(p, out);
    } else {
        let svg = report::figure_svg_modes(&fig, &overlays, &modes, p.range);
        write_svg(dir, format!("{}.svg", p.id), svg, &p.id, out);
    }
    out.figure_seconds.push((p.id.clone(), done.seconds));
    FigureResult {
        members,
        td_rows,
        backbones: done.backbones.iter().collect(),
        ..result(study, f, p, &done.curves, done.seconds)
    }
}

/// The CSV and JSON of every backbone of a figure, and the overlays that draw them;
/// a backbone that could not start or stopped short is a failed part (drawn as far
/// as it went).
fn write_backbones(
    p: &FigurePlan,
    done: &Finished,
    dir: &Path,
    out: &mut StudyOutcome,
) -> Vec<report::Overlay> {
    if p.backbone().is_none() {
        return Vec::new();
    }
    let names: Vec<String> = p.td_model.outputs().iter().map(|o| o.name.to_string()).collect();
    for sb in &done.backbones {
        if let (Ok(b), Some(o)) = (&sb.backbone, names.get(sb.output)) {
            let stem = p.backbone_stem(sb.mode, o);
            write(dir, format!("{stem}.csv"), &report::backbone_csv(b), out);
            let json = serde_json::to_string_pretty(&report::backbone_json(b)).unwrap_or_default();
            write(dir, format!("{stem}.json"), &json, out);
        }
    }
    let (overlays, warnings) = crate::engine::backbone_overlays(&done.backbones, &names);
    out.failures.extend(warnings.into_iter().map(|w| format!("{}: {w}", p.id)));
    if done.backbones.is_empty() && !p.backbone_modes().is_empty() {
        if out.interrupted {
            out.unfinished.push(format!("{}: backbones not computed (interrupted)", p.id));
            return overlays;
        }
        let why = if done.curves.iter().all(Option::is_none) {
            "no curve finished to take the amplitudes from"
        } else if p.backbone().and_then(BackboneSpec::modes).is_some() {
            "the modes asked for have no oscillatory linear mode to start from"
        } else {
            "no mode's linear natural frequency lies in the range"
        };
        out.failures.push(format!("{}: {why}: no backbone drawn", p.id));
    }
    overlays
}

/// The result of figure `f` for the summary, with nothing finished in it yet but the
/// labels of the parts that are missing from `done`.
fn result<'a, T>(
    study: &'a Study,
    f: usize,
    p: &FigurePlan,
    done: &[Option<T>],
    seconds: f64,
) -> FigureResult<'a> {
    FigureResult {
        spec: &study.figures[f],
        title: p.title.clone(),
        outputs: p.outputs.clone(),
        harmonics: p.harmonics,
        range: p.range,
        members: Vec::new(),
        missing: p
            .curves
            .iter()
            .zip(done)
            .filter(|(_, c)| c.is_none())
            .map(|(pl, _)| pl.label.clone())
            .collect(),
        td_rows: Vec::new(),
        folds: Vec::new(),
        backbones: Vec::new(),
        seconds,
    }
}

/// Record a figure none of whose parts finished: a failure, unless an interruption
/// is the reason.
fn nothing_drawn(p: &FigurePlan, out: &mut StudyOutcome) {
    if out.interrupted {
        out.unfinished
            .push(format!("{}: no figure drawn (nothing finished before the interruption)", p.id));
    } else {
        out.failures.push(format!("{}: nothing finished, no figure drawn", p.id));
    }
}

/// Write a drawn figure, or record why it could not be drawn.
fn write_svg(dir: &Path, name: String, svg: Result<String>, id: &str, out: &mut StudyOutcome) {
    match svg {
        Ok(svg) => write(dir, name, &svg, out),
        Err(e) => out.failures.push(format!("{id}: {e}")),
    }
}

/// The files of a fold figure: per analysis its JSON and CSV, the fold curves of all
/// of them in one figure, and with several analyses the least cusp of each against
/// the varied value.
fn write_fold_figure<'a>(
    study: &'a Study,
    f: usize,
    p: &FigurePlan,
    fp: &FoldPlan,
    done: &'a Finished,
    dir: &Path,
    out: &mut StudyOutcome,
) -> FigureResult<'a> {
    let mut folds = Vec::new();
    for (r, plan) in done.folds.iter().zip(&p.curves) {
        if let Some(r) = r {
            folds.push(FoldMember { label: plan.label.clone(), value: plan.value, folds: r });
        }
    }
    if folds.is_empty() {
        nothing_drawn(p, out);
    } else {
        let series: Vec<(&str, &FoldCurves)> =
            folds.iter().map(|m| (m.label.as_str(), m.folds)).collect();
        let svg = report::folds_svg_family(&series, &p.title);
        write_svg(dir, format!("{}.svg", p.id), svg, &p.id, out);
        let vary = study.figures[f].vary.as_ref().map(|v| v.get_ref().to_string());
        if let (Some(vary), true) = (vary, p.curves.len() > 1) {
            let param = &fp.param;
            let title = format!("{}: the onset in {param} against {vary}", p.title);
            let points: Vec<(f64, f64)> =
                folds.iter().filter_map(|m| m.onset().map(|c| (m.value, c.value))).collect();
            let svg = report::trend_svg(&points, &vary, &format!("{param} at the onset"), &title);
            write_svg(dir, format!("{}_cusps.svg", p.id), svg, &p.id, out);
        }
    }
    out.figure_seconds.push((p.id.clone(), done.seconds));
    FigureResult { folds, ..result(study, f, p, &done.folds, done.seconds) }
}
