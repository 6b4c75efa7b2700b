//! The legend box as drawn: its entries' keys (line styles and markers), its size
//! without font metrics, and its drawing (where it goes is `report::legend`'s).

use super::plot_err;
use crate::error::Error;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// How a legend entry's key is drawn.
#[derive(Debug, Clone, Copy)]
pub(super) enum Key {
    /// A series' colour, solid.
    Line(RGBColor),
    /// Black, dashed: unstable branches.
    Dashed,
    /// A colour, dotted: an overlay (a backbone).
    Dotted(RGBColor),
    /// A filled triangle: folds.
    Fold,
    /// A short vertical dotted line: jumps.
    Jump,
    /// An open circle: the first kind of time-domain marker.
    Circle,
    /// A cross: the second kind.
    Cross,
}

/// The shape of the `k`-th kind of time-domain marker.
pub(super) fn marker_key(k: usize) -> Key {
    if k % 2 == 0 {
        Key::Circle
    } else {
        Key::Cross
    }
}

const LEGEND_FONT: u32 = 13;
const LEGEND_ROW: f64 = 17.0;
const LEGEND_PAD: f64 = 6.0;
const LEGEND_KEY_W: f64 = 30.0;

/// Width and height of the legend box, pixels. The SVG has no font metrics; plotters
/// writes text at size/1.24, and sans-serif glyphs average under 0.6 em, so 0.6 em per
/// character is a safe width.
pub(super) fn legend_size(entries: &[(String, Key)]) -> (f64, f64) {
    let em = f64::from(LEGEND_FONT) / 1.24;
    let chars = entries.iter().map(|(l, _)| l.chars().count()).max().unwrap_or(0);
    (
        2.0 * LEGEND_PAD + LEGEND_KEY_W + 0.6 * em * chars as f64,
        2.0 * LEGEND_PAD + LEGEND_ROW * entries.len() as f64,
    )
}

/// Draw the legend box with its top-left corner at `at` (pixels in `area`).
pub(super) fn draw_legend(
    area: &DrawingArea<SVGBackend, Shift>,
    at: (i32, i32),
    size: (f64, f64),
    entries: &[(String, Key)],
) -> Result<(), Error> {
    let (x, y) = at;
    let corner = (x + size.0.round() as i32, y + size.1.round() as i32);
    area.draw(&Rectangle::new([at, corner], WHITE.mix(0.85).filled())).map_err(plot_err)?;
    area.draw(&Rectangle::new([at, corner], BLACK)).map_err(plot_err)?;
    let font = ("sans-serif", LEGEND_FONT).into_font().color(&BLACK);
    for (row, (label, key)) in entries.iter().enumerate() {
        let top = y + (LEGEND_PAD + LEGEND_ROW * row as f64).round() as i32;
        let mid = top + (LEGEND_ROW / 2.0).round() as i32;
        let kx = x + LEGEND_PAD as i32;
        let line = vec![(kx, mid), (kx + 20, mid)];
        match *key {
            Key::Line(c) => area.draw(&PathElement::new(line, c.stroke_width(2))),
            Key::Dashed => area.draw(&DashedPathElement::new(line, 5, 3, BLACK.stroke_width(2))),
            Key::Dotted(c) => area.draw(&DashedPathElement::new(line, 2, 3, c.stroke_width(2))),
            Key::Fold => area.draw(&TriangleMarker::new((kx + 10, mid), 6, BLACK.filled())),
            Key::Jump => area.draw(&DashedPathElement::new(
                vec![(kx + 10, mid - 6), (kx + 10, mid + 6)],
                3,
                3,
                BLACK.stroke_width(1),
            )),
            Key::Circle => area.draw(&Circle::new((kx + 10, mid), 5, BLACK.stroke_width(2))),
            Key::Cross => area.draw(&Cross::new((kx + 10, mid), 5, BLACK.stroke_width(2))),
        }
        .map_err(plot_err)?;
        let tx = x + (LEGEND_PAD + LEGEND_KEY_W) as i32;
        area.draw_text(label, &font, (tx, top + 2)).map_err(plot_err)?;
    }
    Ok(())
}
