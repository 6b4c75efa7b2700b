//! The fold curves of a two-parameter analysis in the (Ω, parameter) plane: each
//! curve a line, each cusp a filled triangle (an isola point a ring), and the region where the amplitude–frequency
//! curve has three solutions (between the two folds of one hysteresis) shaded.

use super::plot_err;
use crate::bifurcation::{CurveEnd, FoldCurve, FoldCurves, TurnKind};
use crate::error::Error;
use plotters::prelude::*;

const W: u32 = 960;
const H: u32 = 600;

/// Draw the fold curves and return the SVG document. The parameter axis is
/// logarithmic when the range is positive and spans a decade or more.
pub fn folds_svg(f: &FoldCurves, title: &str) -> Result<String, Error> {
    let (lo, hi) = (f.range.0.min(f.range.1), f.range.0.max(f.range.1));
    let pts = f.curves.iter().flat_map(|c| c.points.iter());
    let (mut w0, mut w1) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in pts {
        w0 = w0.min(p.omega);
        w1 = w1.max(p.omega);
    }
    if !(w0.is_finite() && w1 > w0) {
        (w0, w1) = f.omega;
    }
    let pad = 0.05 * (w1 - w0);
    let (x0, x1) = ((w0 - pad).max(0.0), w1 + pad);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut cb = ChartBuilder::on(&root);
        cb.caption(title, ("sans-serif", 20))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(80);
        let log = lo > 0.0 && hi / lo >= 10.0;
        if log {
            let mut chart =
                cb.build_cartesian_2d(x0..x1, (lo..hi).log_scale()).map_err(plot_err)?;
            chart
                .configure_mesh()
                .x_desc("forcing frequency Ω (rad/s)")
                .y_desc(f.parameter.as_str())
                .draw()
                .map_err(plot_err)?;
            draw(&mut chart, f)?;
        } else {
            let mut chart = cb.build_cartesian_2d(x0..x1, lo..hi).map_err(plot_err)?;
            chart
                .configure_mesh()
                .x_desc("forcing frequency Ω (rad/s)")
                .y_desc(f.parameter.as_str())
                .draw()
                .map_err(plot_err)?;
            draw(&mut chart, f)?;
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
        |c: &FoldCurve| c.ended == CurveEnd::ReachedEnd && ends(c).is_some_and(|(a, b)| a != b);
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
) -> Result<(), Error>
where
    CT: plotters::coord::CoordTranslate<From = (f64, f64)>,
{
    let shade = RGBColor(70, 130, 180).mix(0.18);
    for poly in regions(f) {
        chart.draw_series(std::iter::once(Polygon::new(poly, shade.filled()))).map_err(plot_err)?;
    }
    let line = RGBColor(20, 60, 140);
    for c in &f.curves {
        let xy: Vec<(f64, f64)> = c.points.iter().map(|p| (p.omega, p.value)).collect();
        chart.draw_series(LineSeries::new(xy, line.stroke_width(2))).map_err(plot_err)?;
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
