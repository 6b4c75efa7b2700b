//! The fold curves of a two-parameter analysis in the (Ω, parameter) plane: each
//! curve a line, each cusp a filled triangle (an isola point a ring), and the region where the amplitude–frequency
//! curve has three solutions (between the two folds of one hysteresis) shaded.

use super::{plot_err, COLORS};
use crate::bifurcation::{End, FoldCurve, FoldCurves, TurnKind};
use crate::error::{Drawable, Error};
use plotters::prelude::*;

const W: u32 = 960;
const H: u32 = 600;

/// Draw the fold curves and return the SVG document. The parameter axis is
/// logarithmic when the range is positive and spans a decade or more.
pub fn folds_svg(f: &FoldCurves, title: &str) -> Result<String, Error> {
    folds_svg_family(&[(f.model.as_str(), f)], title)
}

/// [`folds_svg`] for several analyses of one parameter (a study figure varying a
/// second parameter): each in its own colour, with a legend when there are several.
pub fn folds_svg_family(family: &[(&str, &FoldCurves)], title: &str) -> Result<String, Error> {
    let Some((_, first)) = family.first() else {
        return Err(Error::NothingToDraw { what: Drawable::FoldCurves });
    };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut w0, mut w1) = (f64::INFINITY, f64::NEG_INFINITY);
    for (_, f) in family {
        lo = lo.min(f.range.0.min(f.range.1));
        hi = hi.max(f.range.0.max(f.range.1));
        for p in f.curves.iter().flat_map(|c| c.points.iter()) {
            w0 = w0.min(p.omega);
            w1 = w1.max(p.omega);
        }
    }
    if !(w0.is_finite() && w1 > w0) {
        (w0, w1) = first.omega;
    }
    let pad = 0.05 * (w1 - w0);
    let (x0, x1) = ((w0 - pad).max(0.0), w1 + pad);
    let ylabel = first.parameter.as_str();
    let legend = family.len() > 1;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut cb = ChartBuilder::on(&root);
        frame(&mut cb, title);
        macro_rules! body {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc("forcing frequency Ω (rad/s)")
                    .y_desc(ylabel)
                    .y_label_formatter(&|v| tick(*v))
                    .draw()
                    .map_err(plot_err)?;
                for (k, (label, f)) in family.iter().enumerate() {
                    draw(&mut chart, f, k, legend.then_some(*label))?;
                }
                if legend {
                    chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.85))
                        .border_style(BLACK)
                        .draw()
                        .map_err(plot_err)?;
                }
            }};
        }
        if lo > 0.0 && hi / lo >= 10.0 {
            body!(cb.build_cartesian_2d(x0..x1, (lo..hi).log_scale()).map_err(plot_err)?);
        } else {
            body!(cb.build_cartesian_2d(x0..x1, lo..hi).map_err(plot_err)?);
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// The title and margins of the figures here.
fn frame<DB: DrawingBackend>(cb: &mut ChartBuilder<'_, '_, DB>, title: &str) {
    cb.caption(title, ("sans-serif", 20)).margin(16).x_label_area_size(44).y_label_area_size(80);
}

/// A tick label: plain for moderate magnitudes, `2e6` style beyond.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-3..1e5).contains(&a) {
        format!("{}", (v * 1e6).round() / 1e6)
    } else {
        format!("{v:e}")
    }
}

/// Points `(x, y)` as markers joined by a line, log-log when all are positive: a
/// quantity of each member of a family against the varied value (the least cusp of
/// each fold analysis, for example).
pub fn trend_svg(
    points: &[(f64, f64)],
    xlabel: &str,
    ylabel: &str,
    title: &str,
) -> Result<String, Error> {
    if points.is_empty() {
        return Err(Error::NothingToDraw { what: Drawable::Points });
    }
    let fold = |f: fn(f64, f64) -> f64, init: f64, sel: fn(&(f64, f64)) -> f64| {
        points.iter().map(sel).fold(init, f)
    };
    let (xl, xh) =
        (fold(f64::min, f64::INFINITY, |p| p.0), fold(f64::max, f64::NEG_INFINITY, |p| p.0));
    let (yl, yh) =
        (fold(f64::min, f64::INFINITY, |p| p.1), fold(f64::max, f64::NEG_INFINITY, |p| p.1));
    let pos = xl > 0.0 && yl > 0.0;
    let widen = |lo: f64, hi: f64| {
        if pos {
            (lo / 1.5, hi * 1.5)
        } else {
            let pad = 0.1 * (hi - lo).abs().max(lo.abs().max(1e-300));
            (lo - pad, hi + pad)
        }
    };
    let ((x0, x1), (y0, y1)) = (widen(xl, xh), widen(yl, yh));
    let mut pts = points.to_vec();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let color = COLORS[0];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut cb = ChartBuilder::on(&root);
        frame(&mut cb, title);
        macro_rules! body {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(xlabel)
                    .y_desc(ylabel)
                    .x_labels(8)
                    .x_label_formatter(&|v| tick(*v))
                    .y_label_formatter(&|v| tick(*v))
                    .draw()
                    .map_err(plot_err)?;
                chart
                    .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                    .map_err(plot_err)?;
                chart
                    .draw_series(
                        pts.iter()
                            .map(|&p| TriangleMarker::new(p, 7, RGBColor(200, 30, 30).filled())),
                    )
                    .map_err(plot_err)?;
            }};
        }
        if pos {
            body!(cb
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(plot_err)?);
        } else {
            body!(cb.build_cartesian_2d(x0..x1, y0..y1).map_err(plot_err)?);
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// The regions with three solutions near each cusp: between the two branches that
/// leave it, as far as both go on away from the cusp's value (up to the first turn
/// of either, or the end); and between two curves from the folds of one hysteresis
/// that both crossed the whole range.
fn regions(f: &FoldCurves) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    for k in f.cusps.iter().filter(|k| k.kind == TurnKind::Cusp) {
        let pts = &f.curves[k.curve].points;
        let tip = (k.omega, k.value);
        let back: Vec<(f64, f64)> =
            pts[..=k.after].iter().rev().map(|p| (p.omega, p.value)).collect();
        let ahead: Vec<(f64, f64)> =
            pts[k.after + 1..].iter().map(|p| (p.omega, p.value)).collect();
        let (a, b) = (monotone(tip, &back), monotone(tip, &ahead));
        let reach = |v: &[(f64, f64)]| v.last().map_or(tip.1, |p| p.1);
        // both branches go the same way from the cusp; clip to the nearer reach
        let limit = if (reach(&a) - tip.1).abs() < (reach(&b) - tip.1).abs() {
            reach(&a)
        } else {
            reach(&b)
        };
        let mut poly = clip(tip, &a, limit);
        poly.extend(clip(tip, &b, limit).into_iter().rev());
        if poly.len() > 3 {
            out.push(poly);
        }
    }
    let ends =
        |c: &FoldCurve| c.points.first().zip(c.points.last()).map(|(p, q)| (p.value, q.value));
    let crossed =
        |c: &FoldCurve| c.ended == End::ReachedEnd && ends(c).is_some_and(|(a, b)| a != b);
    for (i, c) in f.curves.iter().enumerate() {
        if c.start_fold % 2 != 0 || !crossed(c) {
            continue;
        }
        let partner = f.curves[i + 1..]
            .iter()
            .find(|b| b.start == c.start && b.start_fold == c.start_fold + 1);
        if let Some(b) = partner.filter(|b| crossed(b)) {
            let mut poly: Vec<(f64, f64)> = c.points.iter().map(|p| (p.omega, p.value)).collect();
            poly.extend(b.points.iter().rev().map(|p| (p.omega, p.value)));
            out.push(poly);
        }
    }
    out
}

/// The start of `branch` (from `tip`) while its value moves away from the tip's.
fn monotone(tip: (f64, f64), branch: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = vec![tip];
    let mut dir = 0.0;
    for &p in branch {
        let last = out[out.len() - 1];
        let d = (p.1 - last.1).signum();
        if dir == 0.0 {
            dir = d;
        } else if d != dir && d != 0.0 {
            break;
        }
        out.push(p);
    }
    out
}

/// `branch` up to the value `limit` (the last segment cut there).
fn clip(tip: (f64, f64), branch: &[(f64, f64)], limit: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (i, &p) in branch.iter().enumerate() {
        let beyond = (p.1 - tip.1).abs() > (limit - tip.1).abs();
        if beyond && i > 0 {
            let q = branch[i - 1];
            let s = (limit - q.1) / (p.1 - q.1);
            out.push((q.0 + s * (p.0 - q.0), limit));
            break;
        }
        out.push(p);
    }
    out
}

fn draw<DB: DrawingBackend, CT>(
    chart: &mut ChartContext<'_, DB, CT>,
    f: &FoldCurves,
    k: usize,
    label: Option<&str>,
) -> Result<(), Error>
where
    CT: plotters::coord::CoordTranslate<From = (f64, f64)>,
{
    let line = COLORS[k % COLORS.len()];
    for poly in regions(f) {
        chart
            .draw_series(std::iter::once(Polygon::new(poly, line.mix(0.18).filled())))
            .map_err(plot_err)?;
    }
    for (i, c) in f.curves.iter().enumerate() {
        let xy: Vec<(f64, f64)> = c.points.iter().map(|p| (p.omega, p.value)).collect();
        let series =
            chart.draw_series(LineSeries::new(xy, line.stroke_width(2))).map_err(plot_err)?;
        if let (Some(l), 0) = (label, i) {
            series.label(l.to_string()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], line.stroke_width(2))
            });
        }
    }
    let red = RGBColor(200, 30, 30);
    let cusps = f.cusps.iter().filter(|k| k.kind == TurnKind::Cusp);
    chart
        .draw_series(cusps.map(|k| TriangleMarker::new((k.omega, k.value), 7, red.filled())))
        .map_err(plot_err)?;
    let isolas = f.cusps.iter().filter(|k| k.kind == TurnKind::Isola);
    chart
        .draw_series(isolas.map(|k| Circle::new((k.omega, k.value), 5, red.stroke_width(2))))
        .map_err(plot_err)?;
    Ok(())
}
