//! The curves' SVG, written by hand: polylines at sub-pixel precision, slotted into
//! the document plotters draws.

use super::plot_err;
use crate::error::Error;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Curves written as SVG polylines at sub-pixel precision. plotters hands its backends
/// whole-pixel coordinates, which turns a curve drawn through points a few pixels apart
/// into a staircase; so a panel draws a placeholder text where its curves belong in the
/// stacking order (over the grid, under markers and legend) and [`CurveSlots::fill`]
/// replaces it by the polylines once plotters is done.
#[derive(Debug, Default)]
pub(super) struct CurveSlots {
    svg: Vec<String>,
}

impl CurveSlots {
    fn token(k: usize) -> String {
        format!("ihbm-curve-slot-{k}-end")
    }

    /// Reserve a slot for `polylines` and draw its placeholder on `area`.
    pub(super) fn reserve(
        &mut self,
        area: &DrawingArea<SVGBackend, Shift>,
        polylines: String,
    ) -> Result<(), Error> {
        let token = Self::token(self.svg.len());
        self.svg.push(polylines);
        area.draw_text(&token, &("sans-serif", 1).into_font().color(&WHITE), (0, 0))
            .map_err(plot_err)
    }

    /// Replace every placeholder `<text ...>token</text>` by its polylines.
    pub(super) fn fill(self, mut svg: String) -> Result<String, Error> {
        for (k, lines) in self.svg.iter().enumerate() {
            let token = Self::token(k);
            let found = svg.find(&token).and_then(|at| {
                let start = svg[..at].rfind("<text")?;
                let end = at + svg[at..].find("</text>")? + "</text>".len();
                Some((start, end))
            });
            let Some((start, end)) = found else {
                return Err(Error::CurveSlotLost { slot: k });
            };
            svg.replace_range(start..end, lines);
        }
        Ok(svg)
    }
}

/// One SVG polyline in pixels (two decimals), dashed 6–4 when `dashed`.
pub(super) fn svg_polyline(
    pts: impl Iterator<Item = (f64, f64)>,
    color: RGBColor,
    dashed: bool,
) -> String {
    use std::fmt::Write;
    let RGBColor(r, g, b) = color;
    let dash = if dashed { r#" stroke-dasharray="6 4""# } else { "" };
    let mut s = format!(
        r##"<polyline fill="none" opacity="1" stroke="#{r:02X}{g:02X}{b:02X}" stroke-width="2" stroke-linejoin="round"{dash} points=""##
    );
    for (x, y) in pts {
        let _ = write!(s, "{x:.2},{y:.2} ");
    }
    s.push_str("\"/>\n");
    s
}

/// An overlay's SVG polyline in pixels (two decimals), dotted 2–3, with its tag as
/// the `data-overlay` attribute.
pub(super) fn overlay_polyline(
    pts: impl Iterator<Item = (f64, f64)>,
    color: RGBColor,
    tag: &str,
) -> String {
    use std::fmt::Write;
    let RGBColor(r, g, b) = color;
    let mut s = format!(
        r##"<polyline fill="none" opacity="1" stroke="#{r:02X}{g:02X}{b:02X}" stroke-width="2" stroke-dasharray="2 3" data-overlay="{tag}" points=""##
    );
    for (x, y) in pts {
        let _ = write!(s, "{x:.2},{y:.2} ");
    }
    s.push_str("\"/>\n");
    s
}
