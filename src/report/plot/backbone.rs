//! A backbone: the output's amplitude against the mode's frequency (where forced
//! peaks lean), and the modal damping ratio against the amplitude, side by side.

use super::{plot_err, COLORS};
use crate::backbone::Backbone;
use crate::error::{Drawable, Error};
use plotters::coord::Shift;
use plotters::prelude::*;

const W: u32 = 1100;
const H: u32 = 500;

/// Draw `b` and return the SVG document.
pub fn backbone_svg(b: &Backbone, title: &str) -> Result<String, Error> {
    let out = b.output;
    let name = b.output_names.get(out).map_or("x", |s| s.as_str());
    let pts: Vec<(f64, f64, f64)> =
        b.points.iter().map(|p| (p.omega, p.outputs[out].max_abs, p.damping)).collect();
    if pts.is_empty() {
        return Err(Error::NothingToDraw { what: Drawable::BackbonePoints });
    }
    let range = |f: fn(&(f64, f64, f64)) -> f64| {
        let (lo, hi) = pts
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
        let pad = 0.05 * (hi - lo).abs().max(1e-12 * hi.abs().max(1e-300));
        (lo - pad, hi + pad)
    };
    let ((w0, w1), (a0, a1), (d0, d1)) = (range(|p| p.0), range(|p| p.1), range(|p| p.2));
    let a0 = a0.max(0.0);
    let color = COLORS[0];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(plot_err)?;
        let (left, right) = root.split_horizontally(W / 2);
        let mut c = ChartBuilder::on(&left)
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(w0..w1, a0..a1)
            .map_err(plot_err)?;
        c.configure_mesh()
            .x_desc("mode frequency ω (rad/s)")
            .y_desc(format!("max |{name}|"))
            .draw()
            .map_err(plot_err)?;
        c.draw_series(LineSeries::new(pts.iter().map(|p| (p.0, p.1)), color.stroke_width(2)))
            .map_err(plot_err)?;
        let mut c = ChartBuilder::on(&right)
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(a0..a1, d0..d1)
            .map_err(plot_err)?;
        c.configure_mesh()
            .x_desc(format!("max |{name}|"))
            .y_desc("modal damping ratio D")
            .draw()
            .map_err(plot_err)?;
        c.draw_series(LineSeries::new(pts.iter().map(|p| (p.1, p.2)), color.stroke_width(2)))
            .map_err(plot_err)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// One chart of the modes row: its area, y range, y label and y value of a point
/// `(amplitude, ω, D)`.
type Side<'a, 'b> =
    (&'a DrawingArea<SVGBackend<'b>, Shift>, (f64, f64), &'static str, fn(&(f64, f64, f64)) -> f64);

/// A padded range of `values` (the lower end at 0 when `from_zero`).
fn padded(values: impl Iterator<Item = f64>, from_zero: bool) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).abs().max(1e-12 * hi.abs().max(1e-300));
    (if from_zero { 0.0f64.min(lo) } else { lo - pad }, hi + pad)
}

/// The frequency (left) and the modal damping ratio (right) of every backbone
/// against its amplitude (`max |x|` of the output it was continued in), while its
/// frequency stays in `range` (rad/s, as the overlays on the panels), one colour and
/// legend entry per backbone: the row under a figure's panels
/// ([`super::figure_svg_modes`]).
pub(super) fn draw_modes(
    area: &DrawingArea<SVGBackend, Shift>,
    modes: &[(String, &Backbone)],
    range: (f64, f64),
    colors: &[RGBColor],
) -> Result<(), Error> {
    let (lo, hi) = (range.0.min(range.1), range.0.max(range.1));
    let pts: Vec<Vec<(f64, f64, f64)>> = modes
        .iter()
        .map(|(_, b)| {
            b.points
                .iter()
                .take_while(|p| p.omega >= lo && p.omega <= hi)
                .filter_map(|p| p.outputs.get(b.output).map(|o| (o.max_abs, p.omega, p.damping)))
                .collect()
        })
        .collect();
    let all = || pts.iter().flatten();
    let (a0, a1) = padded(all().map(|p| p.0), true);
    let (w0, w1) = padded(all().map(|p| p.1), false);
    let (d0, d1) = padded(all().map(|p| p.2), false);
    let (w, _) = area.dim_in_pixel();
    let (left, right) = area.split_horizontally(w / 2);
    let sides: [Side; 2] = [
        (&left, (w0, w1), "mode frequency ω (rad/s)", |p| p.1),
        (&right, (d0, d1), "modal damping ratio D", |p| p.2),
    ];
    for (side, (y0, y1), desc, y) in sides {
        let mut c = ChartBuilder::on(side)
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(a0..a1, y0..y1)
            .map_err(plot_err)?;
        c.configure_mesh()
            .x_desc("backbone amplitude: max |output| (the output in the legend)")
            .y_desc(desc)
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 15))
            .draw()
            .map_err(plot_err)?;
        // a mode's colour is its overlays' on the panels; its backbones in the
        // outputs after the first are dashed
        let mut seen: Vec<usize> = Vec::new();
        for ((label, b), p) in modes.iter().zip(&pts) {
            let first = !seen.contains(&b.mode);
            if first {
                seen.push(b.mode);
            }
            let at = seen.iter().position(|&m| m == b.mode).unwrap_or(0);
            let color = colors[at % colors.len()];
            let line = p.iter().map(|q| (q.0, y(q)));
            let style = color.stroke_width(2);
            let drawn = if first {
                c.draw_series(LineSeries::new(line, style)).map_err(plot_err)?
            } else {
                c.draw_series(DashedLineSeries::new(line, 8, 5, style)).map_err(plot_err)?
            };
            // the key: a line, or two dashes
            let gap = if first { 0 } else { 5 };
            drawn.label(label.clone()).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new([(0, 0), (8, 0)], color.stroke_width(2))
                    + PathElement::new([(8 + gap, 0), (20, 0)], color.stroke_width(2))
            });
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(plot_err)?;
    }
    Ok(())
}
