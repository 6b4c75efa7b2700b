//! Running a validated study: every curve and time-domain point as an independent
//! job (in parallel), then the files of every figure from whatever finished.

use super::claims::{fmt_num, Member, TdRow};
use super::spec::{apply, Study};
use super::summary::{self, FigureResult};
use crate::engine::progress;
use crate::engine::registry::{AnyModel, Registry};
use crate::engine::{SimSettings, SolveSettings, SweepSettings};
use crate::error::{Error, Result};
use crate::report::{self, Figure, FreqUnit, Panel, Series, SimRecord, SolveRecord, TimeMarker};
use crate::results::Curve;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
}

struct CurvePlan {
    label: String,
    value: f64,
    model: Box<dyn AnyModel>,
    sweep: SweepSettings,
    stem: String,
}

struct TdPlan {
    omega: f64,
    sim: SimSettings,
}

struct FigurePlan {
    id: String,
    title: String,
    unit: FreqUnit,
    outputs: Vec<String>,
    range: (f64, f64),
    harmonics: usize,
    curves: Vec<CurvePlan>,
    td_model: Box<dyn AnyModel>,
    td: Vec<TdPlan>,
    td_omegas: Vec<f64>,
}

enum Job {
    Curve(usize, usize),
    Sim(usize, usize),
    Solve(usize, usize),
}

enum Done {
    // Boxed: a curve's header outweighs the other results several times.
    Curve(Result<Box<Curve>>),
    Sim(Result<SimRecord>),
    Solve(Result<SolveRecord>),
}

fn plan(study: &Study, reg: &Registry) -> Result<Vec<FigurePlan>> {
    let base = study.base_model(reg)?;
    let default_outputs: Vec<String> = if study.outputs.is_empty() {
        base.outputs().iter().map(|o| o.name.to_string()).collect()
    } else {
        study.outputs.iter().map(|o| o.get_ref().clone()).collect()
    };
    let mut plans = Vec::new();
    for fig in &study.figures {
        let id = fig.id.get_ref().clone();
        let mut model = base.clone_box();
        apply(study, model.as_mut(), &fig.params)?;
        let harmonics = fig.harmonics.unwrap_or(study.harmonics);
        let range = fig.frequency.unwrap_or(study.frequency);
        let sweep = study.sweep.merged(fig.sweep.as_ref());
        let mut curves = Vec::new();
        match &fig.vary {
            None => curves.push(CurvePlan {
                label: model.name().to_string(),
                value: f64::NAN,
                model: model.clone_box(),
                sweep: SweepSettings { harmonics, ..sweep.clone() },
                stem: id.clone(),
            }),
            Some(v) => {
                for &x in &fig.values {
                    let mut m = model.clone_box();
                    let mut n = harmonics;
                    let name = v.get_ref().as_str();
                    if name == "harmonics" {
                        n = x as usize;
                    } else {
                        m.set_param(name, x)?;
                    }
                    let label = if name == "harmonics" {
                        format!("N = {n}")
                    } else {
                        format!("{name} = {}", fmt_num(x))
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
        let mut td_omegas = Vec::new();
        if let Some(t) = &fig.timedomain {
            for &w in &t.omegas {
                td_omegas.push(w);
                for &scheme in &t.schemes {
                    let periods = t.periods.unwrap_or(100);
                    let dt = t.steps_per_period.map(|s| std::f64::consts::TAU / (w * s));
                    td.push(TdPlan { omega: w, sim: SimSettings { dt, periods, scheme } });
                }
            }
        }
        plans.push(FigurePlan {
            title: fig.title.clone().unwrap_or_else(|| id.clone()),
            id,
            unit: fig.unit.unwrap_or(study.unit),
            outputs: fig
                .outputs
                .as_ref()
                .map(|o| o.iter().map(|s| s.get_ref().clone()).collect())
                .unwrap_or_else(|| default_outputs.clone()),
            range: (range.from, range.to),
            harmonics,
            curves,
            td_model: model,
            td,
            td_omegas,
        });
    }
    Ok(plans)
}

/// Run `study` (already validated) and write its files into `dir`: per curve a CSV
/// and a sweep JSON, per figure an SVG (and a time-domain CSV), and `summary.md`.
/// Failed parts are listed in the outcome and in `summary.md`; the rest is written.
pub fn run(study: &Study, reg: &Registry, dir: &Path) -> Result<StudyOutcome> {
    let start = Instant::now();
    let plans = plan(study, reg)?;
    std::fs::create_dir_all(dir)
        .map_err(|source| Error::Io { path: dir.display().to_string(), source })?;
    let mut jobs = Vec::new();
    for (f, p) in plans.iter().enumerate() {
        jobs.extend((0..p.curves.len()).map(|k| Job::Curve(f, k)));
        jobs.extend((0..p.td.len()).map(|k| Job::Sim(f, k)));
        jobs.extend((0..p.td_omegas.len()).map(|k| Job::Solve(f, k)));
    }
    let pb = progress::bar(jobs.len() as u64, "curves and time-domain points");
    let done: Vec<(Done, f64)> = jobs
        .par_iter()
        .map(|job| {
            let t = Instant::now();
            let r = match *job {
                Job::Curve(f, k) => {
                    let (p, c) = (&plans[f], &plans[f].curves[k]);
                    Done::Curve(c.model.sweep(p.range.0, p.range.1, &c.sweep).map(Box::new))
                }
                Job::Sim(f, k) => {
                    let p = &plans[f];
                    Done::Sim(p.td_model.simulate(p.td[k].omega, &p.td[k].sim))
                }
                Job::Solve(f, k) => {
                    let p = &plans[f];
                    Done::Solve(
                        p.td_model.solve(p.td_omegas[k], &SolveSettings { harmonics: p.harmonics }),
                    )
                }
            };
            pb.inc(1);
            (r, t.elapsed().as_secs_f64())
        })
        .collect();
    pb.finish_and_clear();

    let mut out = StudyOutcome::default();
    let mut curves: Vec<Vec<Option<Curve>>> =
        plans.iter().map(|p| p.curves.iter().map(|_| None).collect()).collect();
    let mut sims: Vec<Vec<Option<SimRecord>>> =
        plans.iter().map(|p| p.td.iter().map(|_| None).collect()).collect();
    let mut solves: Vec<Vec<Option<SolveRecord>>> =
        plans.iter().map(|p| p.td_omegas.iter().map(|_| None).collect()).collect();
    let mut secs = vec![0.0; plans.len()];
    for (job, (r, t)) in jobs.iter().zip(done) {
        match (job, r) {
            (&Job::Curve(f, k), Done::Curve(r)) => {
                secs[f] += t;
                match r {
                    Ok(c) => curves[f][k] = Some(*c),
                    Err(e) => out
                        .failures
                        .push(format!("{}, {}: {e}", plans[f].id, plans[f].curves[k].label)),
                }
            }
            (&Job::Sim(f, k), Done::Sim(r)) => {
                secs[f] += t;
                let p = &plans[f].td[k];
                match r {
                    Ok(s) => sims[f][k] = Some(s),
                    Err(e) => out.failures.push(format!(
                        "{}, time integration ({}) at Ω = {}: {e}",
                        plans[f].id,
                        p.sim.scheme.as_str(),
                        p.omega
                    )),
                }
            }
            (&Job::Solve(f, k), Done::Solve(r)) => {
                secs[f] += t;
                match r {
                    Ok(s) if s.converged => solves[f][k] = Some(s),
                    Ok(s) => out.failures.push(format!(
                        "{}, IHBM solve at Ω = {}: Newton did not converge (residual {:.3e})",
                        plans[f].id, s.omega, s.residual_norm
                    )),
                    Err(e) => out.failures.push(format!(
                        "{}, IHBM solve at Ω = {}: {e}",
                        plans[f].id, plans[f].td_omegas[k]
                    )),
                }
            }
            _ => {}
        }
    }

    let mut results = Vec::new();
    for (f, p) in plans.iter().enumerate() {
        let write = |name: String, text: &str, out: &mut StudyOutcome| {
            let path = dir.join(name);
            match report::write_file(&path, text) {
                Ok(()) => out.files.push(path),
                Err(e) => out.failures.push(e.to_string()),
            }
        };
        let mut members = Vec::new();
        for (c, plan) in curves[f].iter().zip(&p.curves) {
            if let Some(c) = c {
                write(format!("{}.csv", plan.stem), &report::curve_csv(c), &mut out);
                let json = serde_json::to_string_pretty(&report::sweep_json(c)).unwrap_or_default();
                write(format!("{}.json", plan.stem), &json, &mut out);
                members.push(Member { label: plan.label.clone(), value: plan.value, curve: c });
            }
        }
        // Time-domain rows: each simulation next to the IHBM solve at its frequency.
        let mut td_rows = Vec::new();
        for (s, tp) in sims[f].iter().zip(&p.td) {
            let (Some(s), Some(sol)) = (
                s,
                p.td_omegas.iter().position(|&w| w == tp.omega).and_then(|i| solves[f][i].as_ref()),
            ) else {
                continue;
            };
            for o in &s.outputs {
                if let Some(h) = sol.outputs.iter().find(|x| x.name == o.name) {
                    td_rows.push(TdRow {
                        omega: tp.omega,
                        scheme: s.scheme.clone(),
                        output: o.name.clone(),
                        ihbm: h.max_abs,
                        sim: o.max_abs,
                    });
                }
            }
        }
        if !p.td.is_empty() {
            let mut csv = String::from("omega,scheme,output,ihbm_max_abs,sim_max_abs,rel_diff\n");
            for r in &td_rows {
                csv.push_str(&format!(
                    "{},{},{},{},{},{}\n",
                    r.omega,
                    r.scheme,
                    r.output,
                    r.ihbm,
                    r.sim,
                    r.rel_diff()
                ));
            }
            write(format!("{}_timedomain.csv", p.id), &csv, &mut out);
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
            series: members
                .iter()
                .map(|m| Series { label: m.label.clone(), curve: m.curve })
                .collect(),
            markers,
        };
        if members.is_empty() && td_rows.is_empty() {
            out.failures.push(format!("{}: nothing finished, no figure drawn", p.id));
        } else {
            match report::figure_svg(&fig) {
                Ok(svg) => write(format!("{}.svg", p.id), &svg, &mut out),
                Err(e) => out.failures.push(format!("{}: {e}", p.id)),
            }
        }
        out.figure_seconds.push((p.id.clone(), secs[f]));
        let spec = &study.figures[f];
        results.push(FigureResult {
            spec,
            title: p.title.clone(),
            outputs: p.outputs.clone(),
            harmonics: p.harmonics,
            range: p.range,
            members: members
                .iter()
                .map(|m| Member { label: m.label.clone(), value: m.value, curve: m.curve })
                .collect(),
            missing: p
                .curves
                .iter()
                .zip(&curves[f])
                .filter(|(_, c)| c.is_none())
                .map(|(pl, _)| pl.label.clone())
                .collect(),
            td_rows,
            seconds: secs[f],
        });
    }
    out.seconds = start.elapsed().as_secs_f64();
    let md = summary::markdown(study, &results, &out);
    let path = dir.join("summary.md");
    match report::write_file(&path, &md) {
        Ok(()) => out.files.push(path),
        Err(e) => out.failures.push(e.to_string()),
    }
    Ok(out)
}
