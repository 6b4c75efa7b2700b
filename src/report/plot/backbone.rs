//! A backbone: the output's amplitude against the mode's frequency (where forced
//! peaks lean), and the modal damping ratio against the amplitude, side by side.

use super::{plot_err, COLORS};
use crate::backbone::Backbone;
use crate::error::Error;
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
        return Err(Error::Other("no backbone points to draw".into()));
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
