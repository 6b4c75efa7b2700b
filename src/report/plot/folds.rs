//! The fold curves of a two-parameter analysis in the (Ω, parameter) plane: each
//! curve a line, each cusp a marker, and the region where the amplitude–frequency
//! curve has three solutions (between the two folds of one hysteresis) shaded.

use super::plot_err;
use crate::bifurcation::{CurveEnd, FoldCurve, FoldCurves};
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

/// The regions with three solutions: a curve that turned at a cusp and came back to
/// the end it started from encloses one; two curves from the folds of one hysteresis
/// that both reached the other end enclose one between them.
fn regions(f: &FoldCurves) -> Vec<Vec<(f64, f64)>> {
    let xy = |c: &FoldCurve| c.points.iter().map(|p| (p.omega, p.value)).collect::<Vec<_>>();
    let ends =
        |c: &FoldCurve| c.points.first().zip(c.points.last()).map(|(p, q)| (p.value, q.value));
    let came_back =
        |c: &FoldCurve| c.ended == CurveEnd::ReachedEnd && ends(c).is_some_and(|(a, b)| a == b);
    let crossed =
        |c: &FoldCurve| c.ended == CurveEnd::ReachedEnd && ends(c).is_some_and(|(a, b)| a != b);
    let mut out = Vec::new();
    for (i, c) in f.curves.iter().enumerate() {
        if came_back(c) && f.cusps.iter().any(|k| k.curve == i) {
            out.push(xy(c));
        }
        if c.start_fold % 2 != 0 || !crossed(c) {
            continue;
        }
        let partner = f.curves[i + 1..]
            .iter()
            .find(|b| b.start == c.start && b.start_fold == c.start_fold + 1);
        if let Some(b) = partner.filter(|b| crossed(b)) {
            let mut poly = xy(c);
            poly.extend(xy(b).into_iter().rev());
            out.push(poly);
        }
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
    chart
        .draw_series(
            f.cusps.iter().map(|k| TriangleMarker::new((k.omega, k.value), 7, red.filled())),
        )
        .map_err(plot_err)?;
    Ok(())
}
