//! `summary.md`: per figure the paper's claim next to what we found, per curve the
//! peaks and folds, and every failed part.

use super::claims::{evaluate, Member, TdRow};
use super::outcome::StudyOutcome;
use super::spec::{FigureSpec, Study};
use crate::backbone::{Backbone, EventKind};
use crate::bifurcation::{Boundary, Cusp, FoldCurves, TurnKind};
use crate::engine::SweepBackbone;
use crate::report::{convergence_line, curve_facts};
use std::fmt::Write;

/// What one figure produced (input of [`markdown`]).
pub struct FigureResult<'a> {
    /// Its specification (claims and checks).
    pub spec: &'a FigureSpec,
    /// Title.
    pub title: String,
    /// Panel outputs.
    pub outputs: Vec<String>,
    /// Harmonics of the time-domain solves.
    pub harmonics: usize,
    /// Frequency range, rad/s.
    pub range: (f64, f64),
    /// The curves that finished.
    pub members: Vec<Member<'a>>,
    /// Labels of curves that failed.
    pub missing: Vec<String>,
    /// Time-domain comparisons.
    pub td_rows: Vec<TdRow>,
    /// The analyses of a fold figure that finished.
    pub folds: Vec<FoldMember<'a>>,
    /// The backbones drawn over the curves (with `backbone`).
    pub backbones: Vec<&'a SweepBackbone>,
    /// Compute time, s.
    pub seconds: f64,
}

/// One finished analysis of a fold figure.
pub struct FoldMember<'a> {
    /// Its label (`k3 = 5e6`, or the model's name).
    pub label: String,
    /// The varied value (NaN without `vary`).
    pub value: f64,
    /// The fold curves.
    pub folds: &'a FoldCurves,
}

impl FoldMember<'_> {
    /// The located turning point with the least parameter value: for fold curves
    /// the least cusp (where jumps begin as the parameter grows), for period-doubling
    /// and torus curves the least turn (where the unstable interval they bound
    /// appears).
    pub fn onset(&self) -> Option<&Cusp> {
        let kind = match self.folds.boundary {
            Boundary::Fold => TurnKind::Cusp,
            Boundary::PeriodDoubling | Boundary::Torus => TurnKind::Turn,
        };
        self.folds
            .cusps
            .iter()
            .filter(|c| c.kind == kind && c.located)
            .min_by(|a, b| a.value.total_cmp(&b.value))
    }
}

/// The fold figure's table: per analysis its turning points and how its curves ended.
fn fold_table(s: &mut String, fig: &FigureResult) {
    let _ = writeln!(
        s,
        "| analysis | parameter | turning points (kind: value at Ω rad/s) | curves ended |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    for m in &fig.folds {
        let f = m.folds;
        let turns = if f.cusps.is_empty() {
            "none".to_string()
        } else {
            f.cusps
                .iter()
                .map(|c| format!("{}: {:.6e} at {:.4}", c.kind, c.value, c.omega))
                .collect::<Vec<_>>()
                .join("; ")
        };
        let ends = f.curves.iter().map(|c| c.ended.to_string()).collect::<Vec<_>>().join(", ");
        let _ = writeln!(s, "| {} | {} | {turns} | {ends} |", m.label, f.parameter);
    }
    for l in &fig.missing {
        let _ = writeln!(s, "| {l} | — | failed | |");
    }
    s.push('\n');
    for m in &fig.folds {
        let (what, turn) = match m.folds.boundary {
            Boundary::Fold => ("jumps begin", "cusp"),
            Boundary::PeriodDoubling => ("period doubling begins", "turning point"),
            Boundary::Torus => ("the quasi-periodic (torus) response begins", "turning point"),
        };
        if let Some(c) = m.onset() {
            let _ = writeln!(
                s,
                "- **We find** ({}): {what} at {} = {:.6e} ({turn} at Ω = {:.4} rad/s, N = {}).",
                m.label, m.folds.parameter, c.value, c.omega, m.folds.harmonics
            );
        } else {
            let _ = writeln!(s, "- **We find** ({}): no {turn} in the range.", m.label);
        }
    }
    s.push('\n');
}

/// The backbones' table: per backbone its mode, the output it was continued in, the
/// linearised mode's frequency and damping ratio, both at the largest amplitude
/// reached, the turns and internal resonances met, and how it ended.
fn backbone_table(s: &mut String, fig: &FigureResult) {
    let _ = writeln!(
        s,
        "| backbone | output | linear ω (rad/s) | linear D | largest max\\|x\\| | ω there (rad/s) | D there | events | ended |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for sb in &fig.backbones {
        let b: &Backbone = match &sb.backbone {
            Ok(b) => b,
            Err(e) => {
                let _ = writeln!(s, "| mode {} | — | failed: {e} | | | | | | |", sb.mode);
                continue;
            }
        };
        let out = b.output_names.get(b.output).map_or("", String::as_str);
        let top = b
            .points
            .iter()
            .filter_map(|p| p.outputs.get(b.output).map(|o| (o.max_abs, p)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let events = if b.events.is_empty() {
            "none".to_string()
        } else {
            b.events
                .iter()
                .map(|e| match e.kind {
                    EventKind::Turn => format!("turn at ω = {:.4}", e.omega),
                    EventKind::InternalResonance { mode, ratio } => {
                        format!("{ratio}:1 with mode {mode} at ω = {:.4}", e.omega)
                    }
                })
                .collect::<Vec<_>>()
                .join("; ")
        };
        let (a, w, d) =
            top.map_or((f64::NAN, f64::NAN, f64::NAN), |(a, p)| (a, p.omega, p.damping));
        let _ = writeln!(
            s,
            "| mode {} | {out} | {:.4} | {:.4e} | {a:.4e} | {w:.4} | {d:.4e} | {events} | {} |",
            b.mode, b.linear.0, b.linear.1, b.ended
        );
    }
    s.push('\n');
}

/// The Markdown text of `summary.md`.
pub fn markdown(study: &Study, figs: &[FigureResult], out: &StudyOutcome) -> String {
    let mut s = String::new();
    let title = study.title.as_deref().unwrap_or("Study");
    let _ = writeln!(s, "# {title}\n");
    let _ = writeln!(
        s,
        "Model `{}`, N = {} unless stated, Ω from {} to {} rad/s. Wall time {:.1} s. Amplitudes are \
         max |x(t)| over one period (m). \"Stable\" means no growing mode was found (Hill's method); \
         folds are turning points of the traced curve.\n",
        study.model.get_ref(),
        study.harmonics,
        study.frequency.from,
        study.frequency.to,
        out.seconds
    );
    if out.interrupted {
        let _ = writeln!(
            s,
            "**The run was interrupted**: {} part(s) did not finish (what they had computed \
             is written, and the figures are drawn from what finished):\n",
            out.unfinished.len()
        );
        for u in &out.unfinished {
            let _ = writeln!(s, "- {u}");
        }
        s.push('\n');
    }
    if out.failures.is_empty() {
        if !out.interrupted {
            let _ = writeln!(s, "Every part of the study finished.\n");
        }
    } else {
        let _ = writeln!(
            s,
            "**{} part(s) failed** (everything else was written):\n",
            out.failures.len()
        );
        for f in &out.failures {
            let _ = writeln!(s, "- {f}");
        }
        s.push('\n');
    }
    let (mut agree, mut disagree, mut inconclusive) = (0, 0, 0);
    for fig in figs {
        let _ = writeln!(s, "## {} (`{}`)\n", fig.title, fig.spec.id.get_ref());
        if let Some(m) = &fig.spec.model {
            let _ = writeln!(
                s,
                "Model `{}` (its defaults, then the figure's parameters).\n",
                m.get_ref()
            );
        }
        if let Some(claim) = &fig.spec.claim {
            let _ = writeln!(s, "**Paper:** {claim}\n");
        }
        if fig.spec.folds.is_some() {
            fold_table(&mut s, fig);
            let _ = writeln!(s, "Compute time {:.2} s (summed over jobs).\n", fig.seconds);
            continue;
        }
        let _ = writeln!(s, "| curve | output | peak max\\|x\\| | at Ω (rad/s) | folds at Ω (rad/s) | unstable points | ends |");
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for m in &fig.members {
            let ends =
                m.curve.segments.iter().map(|e| e.ended.to_string()).collect::<Vec<_>>().join(", ");
            for o in &fig.outputs {
                if let Some(f) = curve_facts(m.curve, o, None) {
                    let folds = if f.folds.is_empty() {
                        "none".to_string()
                    } else {
                        f.folds.iter().map(|w| format!("{w:.4}")).collect::<Vec<_>>().join(", ")
                    };
                    let _ = writeln!(
                        s,
                        "| {} | {o} | {:.4e} | {:.3} | {folds} | {} | {ends} |",
                        m.label, f.peak, f.peak_omega, f.unstable_points
                    );
                }
            }
        }
        for l in &fig.missing {
            let _ = writeln!(s, "| {l} | — | failed | | | | |");
        }
        s.push('\n');
        if fig.spec.backbone.is_some() {
            let _ = writeln!(
                s,
                "Backbones (nonlinear modes by EPMC, forcing left out, N = {}): D is the modal damping ratio.\n",
                fig.harmonics
            );
            backbone_table(&mut s, fig);
        }
        for m in &fig.members {
            if let Some(c) = &m.curve.convergence {
                let _ = writeln!(s, "- {}: {}", m.label, convergence_line(c));
            }
        }
        if fig.members.iter().any(|m| m.curve.convergence.is_some()) {
            s.push('\n');
        }
        if !fig.td_rows.is_empty() {
            let _ = writeln!(s, "Time integration vs IHBM (N = {}):\n", fig.harmonics);
            let _ = writeln!(
                s,
                "| Ω (rad/s) | scheme | output | IHBM | time integration | rel. diff |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|");
            for r in &fig.td_rows {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {:.5e} | {:.5e} | {:.2e} |",
                    r.omega,
                    r.scheme,
                    r.output,
                    r.ihbm,
                    r.sim,
                    r.rel_diff()
                );
            }
            s.push('\n');
        }
        let first = fig.outputs.first().map(String::as_str).unwrap_or("");
        for c in &fig.spec.checks {
            let (v, found) = evaluate(c, &fig.members, &fig.td_rows, first);
            match v {
                super::claims::Verdict::Agree => agree += 1,
                super::claims::Verdict::Disagree => disagree += 1,
                super::claims::Verdict::Inconclusive => inconclusive += 1,
            }
            let _ = writeln!(s, "- claim ({:?}, expect {:?}): **{v}** — {found}", c.kind, c.expect);
        }
        let _ = writeln!(s, "\nCompute time {:.2} s (summed over jobs).\n", fig.seconds);
    }
    let _ = writeln!(
        s,
        "## Verdicts\n\n{agree} agree, {disagree} disagree, {inconclusive} inconclusive."
    );
    s
}
