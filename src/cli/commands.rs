//! What each subcommand does, given parsed arguments and the registered models.

use super::args::{Command, CurveArgs};
use super::Failure;
use crate::backbone::{Backbone, CycleFamily, End, FamilyOptions};
use crate::bifurcation::FoldCurves;
use crate::engine::analysis::{Analysis, Outcome};
use crate::engine::detach::{self, Ran};
use crate::engine::progress;
use crate::engine::registry::{NamedModel, Registry};
use crate::engine::{ArgNames, BackboneSettings, SimSettings, SolveSettings};
use crate::error::Error;
use crate::report::{self, Figure, FreqUnit, Panel, Series};
use crate::results::Curve;
use crate::study;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::Ordering;
use std::sync::Arc;

pub(super) fn execute(reg: &Registry, cmd: Command, out: &mut dyn Write) -> Result<(), Failure> {
    match cmd {
        Command::Models { name } => models(reg, name.as_deref(), out),
        Command::Solve { name, omega, harmonics, aft_samples, sensitivity, set, json } => {
            let model = configured(reg, &name, &set, aft_samples, harmonics)?;
            let settings = SolveSettings { harmonics, sensitivity };
            let analysis = Analysis::Solve { omega, settings };
            let what = format!("solving {name} at Ω = {omega} rad/s");
            let Outcome::Solved(rec) = computed(&model, &analysis, &what)?.0 else {
                return Err(mismatch(&analysis));
            };
            match json.as_deref() {
                Some(target) => {
                    let mut v = report::solve_json(&rec);
                    v["aft_samples"] = model.samples(harmonics).into();
                    emit_json(&v, target, out)?
                }
                None => {
                    w(out, format_args!(
                        "{} at Ω = {} rad/s, N = {}: {} after {} iterations (residual {:.3e}), stable: {}\n",
                        rec.model,
                        rec.omega,
                        rec.harmonics,
                        if rec.converged { "converged" } else { "NOT converged" },
                        rec.iterations,
                        rec.residual_norm,
                        rec.stability
                    ))?;
                    let rows = rec.outputs.iter().map(|o| {
                        (o.name.as_str(), [o.max_abs, o.mean, o.amp1, o.rms, o.min, o.max])
                    });
                    stats_table(out, rows)?;
                    for (p, rates) in &rec.sensitivities {
                        w(out, format_args!("rates of change per unit of {p} (NaN: none):\n"))?;
                        let rows = rec.outputs.iter().zip(rates).map(|(o, r)| {
                            let v = [r.max_abs, r.mean, r.amp1, r.rms, r.min, r.max];
                            (o.name.as_str(), v.map(|x| x.unwrap_or(f64::NAN)))
                        });
                        stats_table(out, rows)?;
                    }
                }
            }
            if rec.converged {
                Ok(())
            } else if let Some(why) = &rec.failure {
                Err(Failure::failed(format!("{why}; result written with \"converged\": false")))
            } else {
                Err(Failure::failed(format!(
                    "Newton did not converge at omega = {} after {} iterations (residual norm {:.3e}); result written with \"converged\": false",
                    rec.omega, rec.iterations, rec.residual_norm
                )))
            }
        }
        Command::Sweep { name, from, to, period, break_symmetry, backbone, curve: args } => {
            distinct_outputs(&args)?;
            if !(1..=2).contains(&period) {
                return Err(Failure::usage(format!(
                    "invalid --period: {period} (expected 1, or 2 for the period-doubled branch)"
                )));
            }
            let model = configured(reg, &name, &args.set, args.aft_samples, args.harmonics)?;
            let what = format!("sweeping {name} from {from} to {to} rad/s");
            let settings = args.cont.settings(args.harmonics);
            if period == 2 {
                let analysis = Analysis::PeriodTwo { from, to, settings };
                let Outcome::PeriodTwo(both) = computed(&model, &analysis, &what)?.0 else {
                    return Err(mismatch(&analysis));
                };
                let title = format!(
                    "{name}: period-1 curve (N = {}) and period-2 branch (N = {} harmonics of Ω/2)",
                    both.period_one.harmonics, both.period_two.harmonics
                );
                let (l1, l2) = (format!("{name} (period 1)"), format!("{name} (period 2)"));
                let parent = Some((l1.as_str(), &both.period_one, Branch::PeriodTwo));
                let samples = model.samples(both.period_two.harmonics);
                let files = CurveFiles { args: &args, samples };
                return write_curve(&both.period_two, &l2, &title, &files, parent, &[], out);
            }
            if break_symmetry {
                let analysis = Analysis::BreakSymmetry { from, to, settings };
                let Outcome::BrokenSymmetry(both) = computed(&model, &analysis, &what)?.0 else {
                    return Err(mismatch(&analysis));
                };
                let title = format!(
                    "{name}: symmetric curve and the branch that breaks its symmetry, N = {}",
                    both.broken.harmonics
                );
                let (l1, l2) = (format!("{name} (symmetric)"), format!("{name} (asymmetric)"));
                let parent = Some((l1.as_str(), &both.symmetric, Branch::Asymmetric));
                let files = CurveFiles { args: &args, samples: model.samples(args.harmonics) };
                return write_curve(&both.broken, &l2, &title, &files, parent, &[], out);
            }
            let analysis = Analysis::Sweep { from, to, settings };
            let (Outcome::Curve(curve), stopped) = computed(&model, &analysis, &what)? else {
                return Err(mismatch(&analysis));
            };
            let title = format!("{name}: amplitude–frequency curve, N = {}", curve.harmonics);
            let (overlays, warnings) = if backbone {
                backbone_overlays(&model, &curve, (from, to))
            } else {
                (Vec::new(), Vec::new())
            };
            let files = CurveFiles { args: &args, samples: model.samples(args.harmonics) };
            write_curve(&curve, &name, &title, &files, None, &overlays, out)?;
            if args.json.as_deref() != Some("-") {
                for warning in warnings {
                    w(out, format_args!("warning: {warning}\n"))?;
                }
            }
            interrupted(stopped, &curve)
        }
        Command::SweepParam { name, param, from, to, omega, curve: args } => {
            distinct_outputs(&args)?;
            let model = configured(reg, &name, &args.set, args.aft_samples, args.harmonics)?;
            let what =
                format!("sweeping {param} of {name} from {from} to {to} at Ω = {omega} rad/s");
            let settings = args.cont.settings(args.harmonics);
            let analysis = Analysis::SweepParam { param: param.clone(), from, to, omega, settings };
            let (Outcome::Curve(curve), stopped) = computed(&model, &analysis, &what)? else {
                return Err(mismatch(&analysis));
            };
            let title = format!(
                "{name}: amplitude against {param} at Ω = {omega} rad/s, N = {}",
                curve.harmonics
            );
            let files = CurveFiles { args: &args, samples: model.samples(args.harmonics) };
            write_curve(&curve, &name, &title, &files, None, &[], out)?;
            interrupted(stopped, &curve)
        }
        Command::Folds { name, param, from, to, omega_from, omega_to, boundary, curve: args } => {
            distinct_outputs(&args)?;
            let model = configured(reg, &name, &args.set, args.aft_samples, args.harmonics)?;
            let what = format!("fold curves of {name} for {param} from {from} to {to}");
            let settings = args.cont.settings(args.harmonics);
            let omega = (omega_from, omega_to);
            let analysis = Analysis::Folds { param, from, to, omega, boundary, settings };
            let (Outcome::Folds(res), stopped) = computed(&model, &analysis, &what)? else {
                return Err(mismatch(&analysis));
            };
            write_folds(&res, &args, out)?;
            if stopped {
                let message = match res.curves.len() {
                    0 => "interrupted before the first fold curve: what the sweeps at the ends \
                          of the range found is written"
                        .to_string(),
                    n => format!(
                        "interrupted: the {n} fold curve(s) traced so far are written (the one \
                         being traced ended 'stopped')"
                    ),
                };
                return Err(Failure { code: super::EXIT_INTERRUPTED, message });
            }
            Ok(())
        }
        Command::Backbone {
            name,
            to,
            mode,
            output,
            harmonics,
            aft_samples,
            set,
            csv,
            json,
            plot,
        } => {
            distinct_files(csv.as_deref(), json.as_deref(), plot.as_deref())?;
            let model = configured(reg, &name, &set, aft_samples, harmonics)?;
            let what = format!("backbone of {name}, mode {mode}, to {to}");
            let analysis = Analysis::Backbone(BackboneSettings { mode, output, to, harmonics });
            let Outcome::Backbone(b) = computed(&model, &analysis, &what)?.0 else {
                return Err(mismatch(&analysis));
            };
            let files = BackboneFiles {
                csv: csv.as_deref(),
                json: json.as_deref(),
                plot: plot.as_deref(),
                samples: model.samples(harmonics),
            };
            write_backbone(&b, &files, out)
        }
        Command::Cycle { name, omega, harmonics, set, param, from, to, json, csv, plot } => {
            let model = configured(reg, &name, &set, None, 1)?;
            if let (Some(param), Some(from), Some(to)) = (param, from, to) {
                distinct_files(csv.as_deref(), json.as_deref(), plot.as_deref())?;
                let what = format!(
                    "limit cycles of {name} near ω = {omega} for {param} from {from} to {to}"
                );
                let opts =
                    FamilyOptions { param, from, to, omega, harmonics, ..Default::default() };
                let analysis = Analysis::Cycles(opts);
                let Outcome::Cycles(f) = computed(&model, &analysis, &what)?.0 else {
                    return Err(mismatch(&analysis));
                };
                return write_cycles(&f, csv.as_deref(), json.as_deref(), plot.as_deref(), out);
            }
            let what = format!("limit cycle of {name} near ω = {omega}");
            let analysis = Analysis::Cycle { omega, harmonics };
            let Outcome::Cycle(c) = computed(&model, &analysis, &what)?.0 else {
                return Err(mismatch(&analysis));
            };
            match json.as_deref() {
                Some(target) => emit_json(&report::cycle_json(&c), target, out),
                None => w(out, format_args!(
                    "{}: limit cycle (mode {}), N = {}: ω = {:.9} rad/s, period {:.9} s, max |{}| = {:.9}, stable: {}\n",
                    c.model, c.mode, c.harmonics, c.omega, c.period,
                    c.outputs.first().map_or("x", |o| o.name.as_str()),
                    c.outputs.first().map_or(f64::NAN, |o| o.max_abs),
                    c.stability.verdict().map_or("unknown".to_string(), |b| b.to_string()),
                )),
            }
        }
        Command::Simulate { name, omega, dt, periods, scheme, set, json } => {
            let model = configured(reg, &name, &set, None, 1)?;
            let settings = SimSettings { dt, periods, scheme };
            let what = format!("integrating {name} at Ω = {omega} rad/s ({periods} periods)");
            let analysis = Analysis::Simulate { omega, settings };
            let Outcome::Simulated(rec) = computed(&model, &analysis, &what)?.0 else {
                return Err(mismatch(&analysis));
            };
            match json.as_deref() {
                Some(target) => emit_json(&report::simulate_json(&rec), target, out)?,
                None => {
                    w(out, format_args!(
                        "{} at Ω = {} rad/s, dt = {:.4e} s, {} periods, scheme {} (last 10 periods):\n",
                        rec.model, rec.omega, rec.dt, rec.periods, rec.scheme
                    ))?;
                    let rows = rec.outputs.iter().map(|o| {
                        (o.name.as_str(), [o.max_abs, o.mean, o.amp1, o.rms, o.min, o.max])
                    });
                    stats_table(out, rows)?;
                    if let Some(why) = rec.transient_warning() {
                        w(out, format_args!("warning: {why}\n"))?;
                    }
                    for o in rec.outputs.iter().filter(|o| !o.steady()) {
                        w(out, format_args!(
                            "warning: {} is not steady: its max_abs changed by {:.1} % between the last two blocks of 10 periods (integrate more --periods)\n",
                            o.name, 100.0 * o.drift
                        ))?;
                    }
                }
            }
            Ok(())
        }
        Command::Run { study: file, out: dir } => run(reg, file.as_deref(), &dir, out),
    }
}

/// `--csv`, `--json FILE` and `--plot` name three different files (two of them on
/// one path would leave only the last one written), refused before any work.
fn distinct_outputs(files: &CurveArgs) -> Result<(), Failure> {
    distinct_files(files.csv.as_deref(), files.json.as_deref(), files.plot.as_deref())
}

/// [`distinct_outputs`] for the three paths.
fn distinct_files(
    csv: Option<&Path>,
    json: Option<&str>,
    plot: Option<&Path>,
) -> Result<(), Failure> {
    let json = json.filter(|t| *t != "-").map(Path::new);
    let named = [("--csv", csv), ("--json", json), ("--plot", plot)];
    let given: Vec<(&str, std::path::PathBuf)> = named
        .iter()
        .filter_map(|&(flag, p)| {
            p.map(|p| (flag, std::path::absolute(p).unwrap_or(p.to_path_buf())))
        })
        .collect();
    for (i, (a, pa)) in given.iter().enumerate() {
        if let Some((b, _)) = given[i + 1..].iter().find(|(_, pb)| pb == pa) {
            return Err(Failure::usage(format!(
                "{a} and {b} name the same file {}: give each output its own path",
                pa.display()
            )));
        }
    }
    Ok(())
}

/// Which branch a curve switched onto from a parent curve is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Branch {
    /// The period-2 branch of a period doubling.
    PeriodTwo,
    /// The branch that breaks the parent's symmetry.
    Asymmetric,
}

/// Write a backbone: CSV, SVG, and the JSON or a human summary; a backbone that did
/// not reach its amplitude is written, then reported as a failure.
/// Where a backbone goes, and the transform's samples per period it was computed with.
struct BackboneFiles<'a> {
    csv: Option<&'a Path>,
    json: Option<&'a str>,
    plot: Option<&'a Path>,
    samples: usize,
}

fn write_backbone(b: &Backbone, files: &BackboneFiles, out: &mut dyn Write) -> Result<(), Failure> {
    let (csv, json, plot) = (files.csv, files.json, files.plot);
    if let Some(path) = csv {
        report::write_file(path, &report::backbone_csv(b)).map_err(Failure::failed)?;
    }
    let name = b.output_names.get(b.output).map_or("x", |s| s.as_str());
    if let Some(path) = plot {
        let title = format!("{}: backbone of mode {}, N = {}", b.model, b.mode, b.harmonics);
        let svg = report::backbone_svg(b, &title).map_err(Failure::failed)?;
        report::write_file(path, &svg).map_err(Failure::failed)?;
    }
    if let Some(target) = json {
        let mut v = report::backbone_json(b);
        v["aft_samples"] = files.samples.into();
        emit_json(&v, target, out)?;
    } else if let (Some(first), Some(last)) = (b.points.first(), b.points.last()) {
        w(out, format_args!(
            "{}: mode {} backbone, N = {}: {} points, {}\n  linear: ω = {:.6} rad/s, D = {:.6e}\n  last:   ω = {:.6} rad/s, D = {:.6e} at max |{name}| = {:.6e}\n",
            b.model, b.mode, b.harmonics, b.points.len(), b.ended, first.omega, first.damping,
            last.omega, last.damping, last.outputs[b.output].max_abs,
        ))?;
        for e in &b.events {
            let what = match e.kind {
                crate::backbone::EventKind::Turn => "turn in amplitude".to_string(),
                crate::backbone::EventKind::InternalResonance { mode, ratio } => {
                    format!("{ratio}:1 internal resonance with mode {mode}")
                }
            };
            w(
                out,
                format_args!(
                    "  {what} at ω = {:.6} rad/s, max |{name}| = {:.6e}\n",
                    e.omega, e.amplitude
                ),
            )?;
        }
    }
    match &b.ended {
        End::ReachedAmplitude => Ok(()),
        End::Stopped => Err(stopped(b.points.len())),
        end => Err(Failure::failed(format!(
            "the backbone did not reach max |{name}| = {} ({end}); the {} points traced are written",
            b.to,
            b.points.len()
        ))),
    }
}

/// Write a family of limit cycles: CSV, SVG, and the JSON or a human summary; a
/// family that stalled is written, then reported as a failure (one that collapsed to
/// the equilibrium ended where cycles end: at the Hopf point).
fn write_cycles(
    f: &CycleFamily,
    csv: Option<&Path>,
    json: Option<&str>,
    plot: Option<&Path>,
    out: &mut dyn Write,
) -> Result<(), Failure> {
    if let Some(path) = csv {
        report::write_file(path, &report::cycles_csv(f)).map_err(Failure::failed)?;
    }
    if let Some(path) = plot {
        let title = format!(
            "{}: limit cycles against {} (mode {}), N = {}",
            f.model, f.parameter, f.mode, f.harmonics
        );
        let svg = report::cycles_svg(f, &title).map_err(Failure::failed)?;
        report::write_file(path, &svg).map_err(Failure::failed)?;
    }
    if let Some(target) = json {
        emit_json(&report::cycles_json(f), target, out)?;
    } else if let (Some(first), Some(last)) = (f.points.first(), f.points.last()) {
        let x = f.output_names.first().map_or("x", |s| s.as_str());
        w(out, format_args!(
            "{}: limit cycles in {} (mode {}), N = {}: {} points, {}\n  first: {} = {:.6}, ω = {:.6} rad/s, max |{x}| = {:.6e}\n  last:  {} = {:.6}, ω = {:.6} rad/s, max |{x}| = {:.6e}\n",
            f.model, f.parameter, f.mode, f.harmonics, f.points.len(), f.ended,
            f.parameter, first.value, first.omega, first.outputs.first().map_or(f64::NAN, |o| o.max_abs),
            f.parameter, last.value, last.omega, last.outputs.first().map_or(f64::NAN, |o| o.max_abs),
        ))?;
        match f.hopf {
            Some(h) => w(
                out,
                format_args!(
                    "  Hopf point: {} = {:.10}, ω = {:.10} rad/s\n",
                    f.parameter, h.value, h.omega
                ),
            )?,
            None => w(out, format_args!("  no Hopf point in the range covered\n"))?,
        }
    }
    match &f.ended {
        End::Stopped => Err(stopped(f.points.len())),
        End::Stalled(why) => Err(Failure::failed(format!(
            "the limit cycles did not reach {} = {} ({why}); the {} points traced are written",
            f.parameter,
            f.range.1,
            f.points.len()
        ))),
        _ => Ok(()),
    }
}

/// Write fold curves: CSV, SVG, and the JSON or a human summary.
fn write_folds(f: &FoldCurves, files: &CurveArgs, out: &mut dyn Write) -> Result<(), Failure> {
    if let Some(path) = &files.csv {
        report::write_file(path, &report::folds_csv(f)).map_err(Failure::failed)?;
    }
    if let Some(path) = &files.plot {
        let title = format!(
            "{}: {} curves in the (Ω, {}) plane, N = {}",
            f.model, f.boundary, f.parameter, f.harmonics
        );
        let svg = report::folds_svg(f, &title).map_err(Failure::failed)?;
        report::write_file(path, &svg).map_err(Failure::failed)?;
    }
    if let Some(target) = files.json.as_deref() {
        emit_json(&report::folds_json(f), target, out)?;
    } else {
        w(out, format_args!(
            "{}: {} {} curve(s) for {} in [{}, {}], Ω in [{}, {}] rad/s, N = {} ({} and {} at the two ends)\n",
            f.model, f.curves.len(), f.boundary, f.parameter, f.range.0, f.range.1, f.omega.0, f.omega.1,
            f.harmonics, f.start_folds.0, f.start_folds.1
        ))?;
        for (i, c) in f.curves.iter().enumerate() {
            let (first, last) = (c.points.first(), c.points.last());
            let span = |p: Option<&crate::bifurcation::FoldPoint>| {
                p.map_or("-".to_string(), |p| {
                    format!("(Ω {:.6}, {} {:.6e})", p.omega, f.parameter, p.value)
                })
            };
            w(
                out,
                format_args!(
                    "curve {i}: {} points from {} to {}, {}\n",
                    c.points.len(),
                    span(first),
                    span(last),
                    c.ended
                ),
            )?;
        }
        for c in &f.cusps {
            w(
                out,
                format_args!(
                    "{} on curve {}: {} = {:.9e} at Ω = {:.9} rad/s{}\n",
                    c.kind,
                    c.curve,
                    f.parameter,
                    c.value,
                    c.omega,
                    if c.located { "" } else { " (not located to 1e-8)" }
                ),
            )?;
        }
    }
    // As for sweeps: a curve that stalled is reported, and what it traced is kept.
    for (i, c) in f.curves.iter().enumerate() {
        if matches!(c.ended, crate::bifurcation::End::Stalled(_)) && files.json.is_none() {
            w(out, format_args!("warning: curve {i} {} (its points so far are kept)\n", c.ended))?;
        }
    }
    Ok(())
}

/// The backbones of the modes in the sweep's range as overlays of its figure: on
/// each output's panel, the backbone continued in that output to the sweep's largest
/// amplitude of it. A backbone that could not start, or stopped short, is drawn as
/// far as it went (if at all), and said so in the warnings returned.
fn backbone_overlays(
    model: &NamedModel,
    curve: &Curve,
    range: (f64, f64),
) -> (Vec<report::Overlay>, Vec<String>) {
    let tops = crate::engine::largest_amplitudes([curve], curve.output_names.len());
    let analysis = Analysis::Backbones { range, tops, harmonics: curve.harmonics };
    let found = match model.run(&analysis, &ArgNames::CLI, &mut ()) {
        Ok(Outcome::Backbones(found)) => found,
        _ => Vec::new(),
    };
    let (overlays, mut warnings) = crate::engine::backbone_overlays(&found, &curve.output_names);
    if found.is_empty() {
        warnings.insert(
            0,
            "no mode's linear natural frequency lies in the range: no backbone drawn".into(),
        );
    }
    (overlays, warnings)
}

/// Write a traced curve: CSV, SVG, and the JSON or a human summary.
/// Where a curve goes, and the transform's samples per period it was computed with.
struct CurveFiles<'a> {
    args: &'a CurveArgs,
    samples: usize,
}

fn write_curve(
    curve: &Curve,
    name: &str,
    title: &str,
    files: &CurveFiles,
    parent: Option<(&str, &Curve, Branch)>,
    overlays: &[report::Overlay],
    out: &mut dyn Write,
) -> Result<(), Failure> {
    let (samples, files) = (files.samples, files.args);
    let json = || {
        let mut v = report::sweep_json(curve);
        v["aft_samples"] = samples.into();
        match parent.map(|p| p.2) {
            Some(Branch::PeriodTwo) => v["period"] = 2.into(),
            Some(Branch::Asymmetric) => v["branch"] = "symmetry-breaking".into(),
            None => {}
        }
        v
    };
    if let Some(path) = &files.csv {
        report::write_file(path, &report::curve_csv(curve)).map_err(Failure::failed)?;
    }
    if curve.points.is_empty() {
        // Nothing to draw; the JSON still says why each segment ended.
        if let Some(target) = files.json.as_deref() {
            emit_json(&json(), target, out)?;
        }
        let why: Vec<String> = curve.segments.iter().map(|s| s.ended.to_string()).collect();
        return Err(Failure::failed(format!("the sweep produced no point ({})", why.join("; "))));
    }
    if let Some(path) = &files.plot {
        let panels = curve
            .output_names
            .iter()
            .map(|o| Panel { output: o.clone(), label: format!("max |{o}|") })
            .collect();
        let fig = Figure {
            title: title.to_string(),
            unit: FreqUnit::RadPerSec,
            panels,
            series: parent
                .map(|(label, c, _)| Series { label: label.to_string(), curve: c })
                .into_iter()
                .chain(std::iter::once(Series { label: name.to_string(), curve }))
                .collect(),
            markers: vec![],
        };
        let svg = report::figure_svg_with(&fig, overlays).map_err(Failure::failed)?;
        report::write_file(path, &svg).map_err(Failure::failed)?;
    }
    if let Some(target) = files.json.as_deref() {
        return emit_json(&json(), target, out);
    }
    // The continuation parameter as people write it, with its unit.
    let (p, unit) = if curve.parameter.is_omega() {
        ("Ω".to_string(), " rad/s")
    } else {
        (curve.parameter.name().to_string(), "")
    };
    w(
        out,
        format_args!(
            "{name}: {} points, {} folds, {} jumps, {} segments\n",
            curve.points.len(),
            curve.folds.len(),
            curve.jumps.len(),
            curve.segments.len()
        ),
    )?;
    for f in &curve.folds {
        let how = if f.located { "" } else { " (not located: the corrector failed on the way)" };
        w(out, format_args!("  fold at {p} = {:.8}{unit}{how}\n", f.param))?;
    }
    for j in &curve.jumps {
        w(
            out,
            format_args!(
                "  jump ({:?}) at {p} = {:.6}{unit}: {} {:.6e} -> {:.6e}\n",
                j.direction, j.at, j.output, j.from, j.to
            ),
        )?;
    }
    for k in &curve.peaks {
        let output = curve.output_names.get(k.output).map_or("?", String::as_str);
        let how = if k.located { "" } else { " (not located: the corrector failed on the way)" };
        w(
            out,
            format_args!(
                "  peak of {output} at {p} = {:.8}{unit}: max_abs {:.6e}{how}\n",
                k.param, k.value
            ),
        )?;
    }
    for s in &curve.segments {
        w(out, format_args!("  segment {p} = {} -> {}{unit}: {}\n", s.from, s.to, s.ended))?;
    }
    if let Some(c) = &curve.convergence {
        w(out, format_args!("  {}\n", report::convergence_line(c)))?;
    }
    let unrefined = curve.stats.stability_unrefined;
    if unrefined > 0 {
        w(
            out,
            format_args!(
                "  warning: at {unrefined} of {} points a fractional exponent did not refine \
                 (its frozen-order value is listed); the verdict there counts the unstable \
                 roots of det T instead, or is unknown where that failed\n",
                curve.points.len(),
            ),
        )?;
    }
    Ok(())
}

fn w(out: &mut dyn Write, args: std::fmt::Arguments) -> Result<(), Failure> {
    out.write_fmt(args).map_err(|e| Failure::failed(format!("writing to standard output: {e}")))
}

/// A fresh model with `--set P=V` overrides applied, and `--aft-samples M` (checked at
/// `harmonics` harmonics).
fn configured(
    reg: &Registry,
    name: &str,
    sets: &[String],
    samples: Option<usize>,
    harmonics: usize,
) -> Result<NamedModel, Failure> {
    let mut model = reg.get(name).map_err(Failure::from_error)?;
    for s in sets {
        let (p, v) = parse_set(s)?;
        model.set_param(p, v).map_err(Failure::from_error)?;
    }
    if let Some(m) = samples {
        model.set_aft_samples(m, harmonics, "--aft-samples").map_err(Failure::from_error)?;
    }
    Ok(model)
}

/// Parse `P=V` with V a finite number.
pub(crate) fn parse_set(s: &str) -> Result<(&str, f64), Failure> {
    let Some((p, v)) = s.split_once('=') else {
        return Err(Failure::usage(format!("invalid --set '{s}': expected P=V, e.g. k3=3e6")));
    };
    let (p, v) = (p.trim(), v.trim());
    if p.is_empty() {
        return Err(Failure::usage(format!(
            "invalid --set '{s}': missing parameter name before '='"
        )));
    }
    match v.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok((p, x)),
        _ => Err(Failure::usage(format!(
            "invalid value '{v}' for parameter {p}: expected a finite number"
        ))),
    }
}

fn emit_json(v: &serde_json::Value, target: &str, out: &mut dyn Write) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(v).map_err(Failure::failed)? + "\n";
    if target == "-" {
        out.write_all(text.as_bytes())
            .map_err(|e| Failure::failed(format!("writing to standard output: {e}")))
    } else {
        report::write_file(Path::new(target), &text).map_err(Failure::failed)
    }
}

fn models(reg: &Registry, name: Option<&str>, out: &mut dyn Write) -> Result<(), Failure> {
    let Some(name) = name else {
        if reg.entries().is_empty() {
            w(out, format_args!("no models registered\n"))?;
        }
        for m in reg.entries() {
            let desc = m.description().split_whitespace().collect::<Vec<_>>().join(" ");
            w(out, format_args!("{:<22} {}\n", m.name(), desc))?;
        }
        return Ok(());
    };
    let m = reg.get(name).map_err(Failure::from_error)?;
    w(out, format_args!("model {}\n", m.name()))?;
    if !m.description().is_empty() {
        w(out, format_args!("  {}\n", m.description()))?;
    }
    w(out, format_args!("parameters (name = default in domain: meaning):\n"))?;
    for (i, p) in m.params_info().iter().enumerate() {
        let domain = format!("in {}", p.domain);
        let v = m.param_value(i);
        w(out, format_args!("  {:<6} = {:<12} {domain:<17} {}\n", p.name, v, p.doc))?;
    }
    w(out, format_args!("dofs: {}\n", m.dofs().join(", ")))?;
    w(
        out,
        format_args!(
            "outputs: {}\n",
            m.outputs().iter().map(|o| &*o.name).collect::<Vec<_>>().join(", ")
        ),
    )?;
    if !m.equations().is_empty() {
        w(out, format_args!("equations:\n"))?;
        for e in m.equations() {
            w(out, format_args!("  {e}\n"))?;
        }
    }
    Ok(())
}

fn run(
    reg: &Registry,
    file: Option<&Path>,
    dir: &Path,
    out: &mut dyn Write,
) -> Result<(), Failure> {
    let (text, label) = match file {
        Some(p) => (
            std::fs::read_to_string(p).map_err(|source| {
                Failure::usage(Error::Io { path: p.display().to_string(), source })
            })?,
            p.display().to_string(),
        ),
        None => (
            study::REFERENCE_STUDY.to_string(),
            "models/reference_study.toml (built in)".to_string(),
        ),
    };
    let spec = study::parse(&text, &label).map_err(Failure::from_error)?;
    spec.validate(reg).map_err(Failure::from_error)?;
    let files = study::output_files(&spec, reg).map_err(Failure::from_error)?;
    if let Some(input) = file.and_then(|p| std::path::absolute(p).ok()) {
        let hit =
            files.iter().find(|n| std::path::absolute(dir.join(n)).ok().as_ref() == Some(&input));
        if let Some(name) = hit {
            return Err(Failure::usage(format!(
                "the study would write {name} over its own file {}: choose another --out",
                input.display()
            )));
        }
    }
    let stop = interrupt_flag();
    let outcome = study::run_until(&spec, reg, dir, &stop).map_err(Failure::failed)?;
    w(
        out,
        format_args!(
            "{}: {} files written to {} in {:.1} s\n",
            spec.title.as_deref().unwrap_or(&label),
            outcome.files.len(),
            dir.display(),
            outcome.seconds
        ),
    )?;
    for f in &outcome.files {
        w(out, format_args!("  {}\n", f.display()))?;
    }
    for f in &outcome.failures {
        w(out, format_args!("FAILED: {f}\n"))?;
    }
    if outcome.interrupted {
        return Err(Failure {
            code: super::EXIT_INTERRUPTED,
            message: format!(
                "interrupted: {} part(s) did not finish; everything finished was written to {} \
                 (summary.md names what is missing)",
                outcome.unfinished.len(),
                dir.display()
            ),
        });
    }
    if outcome.failures.is_empty() {
        Ok(())
    } else {
        Err(Failure::failed(format!(
            "{} part(s) of the study failed (first: {}); everything finished was written to {}",
            outcome.failures.len(),
            outcome.failures[0],
            dir.display()
        )))
    }
}

/// After a sweep whose files are written: exit [`super::EXIT_INTERRUPTED`] if a
/// signal stopped it (its points so far are what was written).
fn interrupted(stopped: bool, curve: &Curve) -> Result<(), Failure> {
    if !stopped {
        return Ok(());
    }
    Err(Failure {
        code: super::EXIT_INTERRUPTED,
        message: format!(
            "interrupted: the {} point(s) traced so far are written (the last segment ended \
             'stopped')",
            curve.points.len()
        ),
    })
}

/// The six statistics of every output as a table (one row per output).
fn stats_table<'a>(
    out: &mut dyn Write,
    rows: impl Iterator<Item = (&'a str, [f64; 6])>,
) -> Result<(), Failure> {
    w(out, format_args!("{:<10}", "output"))?;
    for stat in report::STATS {
        w(out, format_args!(" {stat:>14}"))?;
    }
    w(out, format_args!("\n"))?;
    for (name, values) in rows {
        w(out, format_args!("{name:<10}"))?;
        for v in values {
            w(out, format_args!(" {v:>14.6e}"))?;
        }
        w(out, format_args!("\n"))?;
    }
    Ok(())
}

/// A backbone or family that a signal stopped, its `points` written.
fn stopped(points: usize) -> Failure {
    Failure {
        code: super::EXIT_INTERRUPTED,
        message: format!("interrupted: the {points} point(s) traced so far are written"),
    }
}

/// Run `analysis` on `model` on a thread of its own ([`detach::run_analysis`]), a
/// spinner showing `what` and then its progress, stopped by SIGINT or SIGTERM: its
/// outcome and whether a signal stopped it. When the stop is not answered within
/// [`detach::GRACE`] (one point of a large problem can take minutes), the outcome is
/// what it had traced at its last event.
fn computed(
    model: &NamedModel,
    analysis: &Analysis,
    what: &str,
) -> Result<(Outcome, bool), Failure> {
    let pb = progress::spinner(what);
    let stop = interrupt_flag();
    let flag = Arc::clone(&stop);
    let shown = progress::shown(pb.clone(), model.name());
    let ran = detach::run_analysis(
        model,
        analysis,
        ArgNames::CLI,
        move || flag.load(Ordering::Relaxed),
        shown,
    );
    pb.finish_and_clear();
    let stopped = stop.load(Ordering::Relaxed);
    match ran {
        Ran::Returned(r, _) => Ok((r.map_err(Failure::from_error)?, stopped)),
        Ran::Abandoned(Some(outcome)) => Ok((outcome, true)),
        Ran::Abandoned(None) => Err(Failure {
            code: super::EXIT_INTERRUPTED,
            message: format!("interrupted before {}: nothing written", analysis.first()),
        }),
        Ran::Panicked(why) => Err(Failure::failed(why)),
    }
}

/// An outcome of another kind than the analysis gives (a bug).
fn mismatch(analysis: &Analysis) -> Failure {
    Failure::failed(format!(
        "internal error: the {} gave a result of another kind",
        analysis.noun()
    ))
}

/// A flag the first SIGINT or SIGTERM sets (the study or sweep then stops and writes
/// what finished); a second one ends the process at once with
/// [`super::EXIT_INTERRUPTED`]. The handlers are installed once per process and the
/// flag cleared for each command; where they cannot be installed the flag is never
/// set and signals keep their default effect.
fn interrupt_flag() -> std::sync::Arc<std::sync::atomic::AtomicBool> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use std::sync::{atomic::AtomicBool, Arc, OnceLock};
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    let flag = FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        for sig in [SIGINT, SIGTERM] {
            // The conditional shutdown first: it acts only once the flag is set.
            let _ = signal_hook::flag::register_conditional_shutdown(
                sig,
                i32::from(super::EXIT_INTERRUPTED),
                Arc::clone(&flag),
            );
            let _ = signal_hook::flag::register(sig, Arc::clone(&flag));
        }
        flag
    });
    flag.store(false, std::sync::atomic::Ordering::Relaxed);
    Arc::clone(flag)
}
