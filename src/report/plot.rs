//! SVG figures: amplitude–frequency curves of a parameter family, one panel per output.
//!
//! Stable branches are solid, unstable ones dashed; folds are black triangles, jumps
//! dotted vertical arrows; time-integration points are open markers. Text is written
//! as SVG `<text>` elements (plotters' SVG backend without font features), so no
//! system font is read when drawing.

use super::FreqUnit;
use crate::error::Error;
use crate::results::Curve;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// One curve of a family, with its legend label (e.g. `"k3 = 3e6"`).
#[derive(Debug, Clone)]
pub struct Series<'a> {
    /// Legend label.
    pub label: String,
    /// The traced curve.
    pub curve: &'a Curve,
}

/// One panel: which output it shows and the y-axis label (with unit).
#[derive(Debug, Clone)]
pub struct Panel {
    /// Output name (must be one of the curves' `output_names`).
    pub output: String,
    /// Y-axis label, e.g. `"body displacement max|z1| (m)"`.
    pub label: String,
}

/// A time-integration result drawn over the curves (paper Fig. 6).
#[derive(Debug, Clone)]
pub struct TimeMarker {
    /// Legend label, e.g. `"time integration (GL)"`; markers with the same label share
    /// a shape.
    pub label: String,
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Output name the value belongs to.
    pub output: String,
    /// Steady `max_abs` of that output.
    pub value: f64,
}

/// A whole figure: title, axis unit, panels (stacked), curves and markers.
#[derive(Debug, Clone)]
pub struct Figure<'a> {
    /// Title drawn on top.
    pub title: String,
    /// Frequency-axis unit.
    pub unit: FreqUnit,
    /// Panels, drawn top to bottom.
    pub panels: Vec<Panel>,
    /// The curves (every panel shows every curve).
    pub series: Vec<Series<'a>>,
    /// Time-domain points.
    pub markers: Vec<TimeMarker>,
}

const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

const PANEL_W: u32 = 960;
const PANEL_H: u32 = 440;
const TITLE_H: u32 = 40;

fn plot_err<E: std::fmt::Debug>(e: E) -> Error {
    Error::Other(format!("drawing a figure failed: {e:?}"))
}

/// Draw a figure and return the SVG document.
pub fn figure_svg(fig: &Figure) -> Result<String, Error> {
    let mut svg = String::new();
    {
        let n = fig.panels.len().max(1) as u32;
        let root =
            SVGBackend::with_string(&mut svg, (PANEL_W, TITLE_H + n * PANEL_H)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (title, body) = root.split_vertically(TITLE_H);
        title
            .draw_text(&fig.title, &("sans-serif", 20).into_font().color(&BLACK), (20, 12))
            .map_err(plot_err)?;
        let areas = body.split_evenly((n as usize, 1));
        for (panel, area) in fig.panels.iter().zip(areas) {
            draw_panel(fig, panel, &area)?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// The x axis: Ω in the figure's unit, or the parameter of a parameter sweep (the
/// first series whose curve's `parameter` is not `"omega"` decides).
#[derive(Debug, Clone, Copy)]
enum XAxis<'a> {
    Freq(FreqUnit),
    Param(&'a str),
}

impl<'a> XAxis<'a> {
    fn of(fig: &'a Figure) -> Self {
        match fig.series.iter().find(|s| !s.curve.parameter.is_omega()) {
            Some(s) => XAxis::Param(s.curve.parameter.name()),
            None => XAxis::Freq(fig.unit),
        }
    }

    /// Where a point at frequency `omega` and parameter value `param` goes.
    fn x(self, omega: f64, param: f64) -> f64 {
        match self {
            XAxis::Freq(u) => u.from_rad(omega),
            XAxis::Param(_) => param,
        }
    }

    fn label(self) -> String {
        match self {
            XAxis::Freq(u) => format!("forcing frequency Ω ({})", u.label()),
            XAxis::Param(p) => format!("parameter {p}"),
        }
    }
}

/// Runs of consecutive points with one stability and one segment; a run that starts
/// at a stability change repeats the previous point so the line stays continuous.
fn runs(curve: &Curve, idx: usize, axis: XAxis) -> Vec<(bool, Vec<(f64, f64)>)> {
    let mut out: Vec<(bool, Vec<(f64, f64)>)> = Vec::new();
    let mut prev: Option<(usize, bool, (f64, f64))> = None;
    for p in &curve.points {
        let Some(o) = p.outputs.get(idx) else { continue };
        let xy = (axis.x(p.omega, p.param), o.max_abs);
        if !xy.0.is_finite() || !xy.1.is_finite() {
            continue;
        }
        match prev {
            Some((seg, st, _)) if seg == p.segment && st == drawn_stable(p) => {
                if let Some(last) = out.last_mut() {
                    last.1.push(xy);
                }
            }
            Some((seg, _, pxy)) if seg == p.segment => out.push((drawn_stable(p), vec![pxy, xy])),
            _ => out.push((drawn_stable(p), vec![xy])),
        }
        prev = Some((p.segment, drawn_stable(p), xy));
    }
    out
}

fn draw_panel(
    fig: &Figure,
    panel: &Panel,
    area: &DrawingArea<SVGBackend, Shift>,
) -> Result<(), Error> {
    let axis = XAxis::of(fig);
    let (mut x0, mut x1, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for s in &fig.series {
        if let Some(i) = s.curve.output_names.iter().position(|n| *n == panel.output) {
            for p in &s.curve.points {
                let x = axis.x(p.omega, p.param);
                if let Some(o) = p.outputs.get(i) {
                    if x.is_finite() && o.max_abs.is_finite() {
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                        y1 = y1.max(o.max_abs);
                    }
                }
            }
        }
    }
    for m in fig.markers.iter().filter(|m| m.output == panel.output) {
        if m.value.is_finite() {
            y1 = y1.max(m.value);
        }
    }
    if x0.partial_cmp(&x1) != Some(std::cmp::Ordering::Less) {
        (x0, x1) = (0.0, 1.0);
    }
    if y1 <= 0.0 {
        y1 = 1.0;
    }
    // A little room left and right so end points and markers are not clipped.
    let pad = 0.01 * (x1 - x0);
    let (x0, x1) = (x0 - pad, x1 + pad);
    // Enough decimals for three significant digits at the top of the axis.
    let decimals = (2.0 - y1.log10().floor()).clamp(0.0, 12.0) as usize;
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, 0.0..y1 * 1.08)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(axis.label())
        .y_desc(panel.label.clone())
        .y_label_formatter(&|v| format!("{v:.decimals$}"))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(plot_err)?;

    let mut fold_legend = false;
    let mut jump_legend = false;
    let mut unstable_legend = false;
    for (k, s) in fig.series.iter().enumerate() {
        let color = COLORS[k % COLORS.len()];
        let Some(idx) = s.curve.output_names.iter().position(|n| *n == panel.output) else {
            continue;
        };
        let mut labelled = false;
        for (stable, pts) in runs(s.curve, idx, axis) {
            let style = color.stroke_width(2);
            if stable {
                let series = chart.draw_series(LineSeries::new(pts, style)).map_err(plot_err)?;
                if !labelled {
                    series.label(s.label.clone()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                    labelled = true;
                }
            } else {
                let series =
                    chart.draw_series(DashedLineSeries::new(pts, 6, 4, style)).map_err(plot_err)?;
                if !labelled {
                    series.label(s.label.clone()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                    labelled = true;
                }
                if !unstable_legend {
                    unstable_legend = true;
                    chart
                        .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                        .map_err(plot_err)?
                        .label("unstable (dashed)")
                        .legend(|(x, y)| {
                            DashedPathElement::new(
                                vec![(x, y), (x + 20, y)],
                                5,
                                3,
                                BLACK.stroke_width(2),
                            )
                        });
                }
            }
        }
        let folds: Vec<(f64, f64)> = s
            .curve
            .folds
            .iter()
            .filter_map(|f| f.outputs.get(idx).map(|o| (axis.x(f.omega, f.param), o.max_abs)))
            .collect();
        if !folds.is_empty() {
            let series = chart
                .draw_series(folds.into_iter().map(|xy| TriangleMarker::new(xy, 7, BLACK.filled())))
                .map_err(plot_err)?;
            if !fold_legend {
                fold_legend = true;
                series
                    .label("fold")
                    .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLACK.filled()));
            }
        }
        for j in s.curve.jumps.iter().filter(|j| j.output == panel.output) {
            // A jump's `omega` is the continuation parameter's value.
            let x = axis.x(j.at, j.at);
            chart
                .draw_series(std::iter::once(TriangleMarker::new((x, j.to), 5, color.filled())))
                .map_err(plot_err)?;
            let series = chart
                .draw_series(DashedLineSeries::new(
                    vec![(x, j.from), (x, j.to)],
                    3,
                    3,
                    color.stroke_width(1),
                ))
                .map_err(plot_err)?;
            if !jump_legend {
                jump_legend = true;
                series.label("jump (slow sweep)").legend(|(x, y)| {
                    DashedPathElement::new(
                        vec![(x + 10, y - 6), (x + 10, y + 6)],
                        3,
                        3,
                        BLACK.stroke_width(1),
                    )
                });
            }
        }
    }
    let mut labels: Vec<&str> = Vec::new();
    for m in &fig.markers {
        if !labels.contains(&m.label.as_str()) {
            labels.push(&m.label);
        }
    }
    for (k, label) in labels.iter().enumerate() {
        let pts: Vec<(f64, f64)> = fig
            .markers
            .iter()
            .filter(|m| m.label == *label && m.output == panel.output && m.value.is_finite())
            .map(|m| (axis.x(m.omega, m.omega), m.value))
            .collect();
        let style = BLACK.stroke_width(2);
        let series = if k % 2 == 0 {
            chart
                .draw_series(pts.into_iter().map(|xy| Circle::new(xy, 5, style)))
                .map_err(plot_err)?
        } else {
            chart
                .draw_series(pts.into_iter().map(|xy| Cross::new(xy, 5, style)))
                .map_err(plot_err)?
        };
        if k % 2 == 0 {
            series
                .label(label.to_string())
                .legend(|(x, y)| Circle::new((x + 10, y), 5, BLACK.stroke_width(2)));
        } else {
            series
                .label(label.to_string())
                .legend(|(x, y)| Cross::new((x + 10, y), 5, BLACK.stroke_width(2)));
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// Drawn as a stable (solid) line unless known unstable: a curve traced without
/// stability is drawn solid.
fn drawn_stable(p: &crate::results::CurvePoint) -> bool {
    !p.stability.is_unstable()
}
