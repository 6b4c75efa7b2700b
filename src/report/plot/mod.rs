//! SVG figures: amplitude–frequency curves of a parameter family, one panel per output.
//!
//! Stable branches are solid, unstable ones dashed; folds are black triangles, jumps
//! dotted vertical arrows; time-integration points are open markers. Text is written
//! as SVG `<text>` elements (plotters' SVG backend without font features), so no
//! system font is read when drawing.
//!
//! Curves are drawn smoothly through the computed points ([`super::smooth`], in the
//! plot's pixel metric, so folds stay folds); the extra points exist only in the
//! figure, never in the CSV/JSON. The legend goes where it covers no curve
//! ([`super::legend`]).

mod backbone;
mod cycles;
mod folds;
mod key;
mod svg;

pub use backbone::backbone_svg;

pub use cycles::cycles_svg;
pub use folds::{folds_svg, folds_svg_family, trend_svg};

use super::legend::{self, Placement, Rect};
use super::smooth::Spline;
use super::FreqUnit;
use crate::error::Error;
use crate::results::{Curve, CurvePoint};
use key::{draw_legend, legend_size, marker_key, Key};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use svg::{svg_polyline, CurveSlots};

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

/// A curve computed elsewhere drawn over a figure's panel, straight through its
/// points (no smoothing: the vertices are the data): a backbone over a sweep.
#[derive(Debug, Clone)]
pub struct Overlay {
    /// Legend label, e.g. `"backbone, mode 1"`.
    pub label: String,
    /// The panel (output name) it is drawn on.
    pub output: String,
    /// Its points: frequency (rad/s) and the output's value.
    pub points: Vec<(f64, f64)>,
    /// Written as the polyline's `data-overlay` attribute (to find it in the SVG).
    pub tag: String,
}

/// The colours of overlays with different labels, in order (drawn dotted: a dark
/// grey first, which no family member has).
const OVERLAY_COLORS: [RGBColor; 4] =
    [RGBColor(40, 40, 40), RGBColor(214, 39, 40), RGBColor(148, 103, 189), RGBColor(44, 160, 44)];

/// The colours of a family's members, in order (also the fold-curve figures').
pub(super) const COLORS: [RGBColor; 10] = [
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
    Error::Plot { reason: format!("{e:?}") }
}

/// Draw a figure and return the SVG document.
pub fn figure_svg(fig: &Figure) -> Result<String, Error> {
    figure_svg_with(fig, &[])
}

/// [`figure_svg`] with `overlays` drawn over the panels they name, dotted, each with
/// its legend entry.
pub fn figure_svg_with(fig: &Figure, overlays: &[Overlay]) -> Result<String, Error> {
    figure_svg_modes(fig, overlays, &[], (0.0, f64::INFINITY))
}

/// [`figure_svg_with`] and, under the panels, a row with the frequency and the modal
/// damping ratio of every backbone in `modes` (label, backbone) against its
/// amplitude, while its frequency stays in `range` (rad/s): where the forced peaks
/// lean, and how damped the mode is there.
pub fn figure_svg_modes(
    fig: &Figure,
    overlays: &[Overlay],
    modes: &[(String, &crate::backbone::Backbone)],
    range: (f64, f64),
) -> Result<String, Error> {
    let mut svg = String::new();
    let mut slots = CurveSlots::default();
    {
        let n = fig.panels.len().max(1) as u32;
        let extra = if modes.is_empty() { 0 } else { PANEL_H };
        let root = SVGBackend::with_string(&mut svg, (PANEL_W, TITLE_H + n * PANEL_H + extra))
            .into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (title, body) = root.split_vertically(TITLE_H);
        title
            .draw_text(&fig.title, &("sans-serif", 20).into_font().color(&BLACK), (20, 12))
            .map_err(plot_err)?;
        let (body, row) = body.split_vertically(n * PANEL_H);
        let areas = body.split_evenly((n as usize, 1));
        for (panel, area) in fig.panels.iter().zip(areas) {
            draw_panel(fig, overlays, panel, &area, &mut slots)?;
        }
        if !modes.is_empty() {
            backbone::draw_modes(&row, modes, range, &OVERLAY_COLORS)?;
        }
        root.present().map_err(plot_err)?;
    }
    slots.fill(svg)
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

/// Whether a point is drawn as stable (solid line). The one place that reads the
/// verdict, so a change of its type changes one line.
fn drawn_stable(p: &CurvePoint) -> bool {
    !p.stability.is_unstable()
}

/// An overlay as a panel draws it: colour, tag and points in data coordinates.
type DrawnOverlay = (RGBColor, String, Vec<(f64, f64)>);

/// A stretch of curve drawn in one style: whether stable, and its points.
type Run = (bool, Vec<(f64, f64)>);

/// A segment's nodes and, for each, the style of the interval ending there.
type Nodes = (Vec<(f64, f64)>, Vec<bool>);

/// Spacing of the extra points drawn between computed ones, pixels.
const SMOOTH_SPACING: f64 = 4.0;

/// Runs of one stability, drawn smoothly through the points of each segment (see
/// [`super::smooth`]) in the plot's pixel metric `scale` (pixels per unit). The interval
/// ending at a point is drawn in that point's style, so a run that starts at a stability
/// change begins at the previous point and the line stays continuous. A located fold
/// between two points of a segment is drawn through as well.
fn runs(curve: &Curve, idx: usize, axis: XAxis, scale: (f64, f64)) -> Vec<Run> {
    let finite = |xy: (f64, f64)| xy.0.is_finite() && xy.1.is_finite();
    // Per segment: the nodes and, for each, the style of the interval ending there.
    let mut segments: Vec<Nodes> = Vec::new();
    let mut prev: Option<(usize, usize)> = None; // (point index, segment) of the last node
    for (k, p) in curve.points.iter().enumerate() {
        let Some(o) = p.outputs.get(idx) else { continue };
        let xy = (axis.x(p.omega, p.param), o.max_abs);
        if !finite(xy) {
            continue;
        }
        let (st, seg) = (drawn_stable(p), p.segment);
        match (prev, segments.last_mut()) {
            (Some((_, s)), Some((nodes, styles))) if s == seg => {
                let fold = curve.folds.iter().find(|f| f.located && f.after + 1 == k);
                let fold_xy = fold.filter(|_| prev.map(|(j, _)| j + 1) == Some(k)).and_then(|f| {
                    f.outputs.get(idx).map(|o| (axis.x(f.omega, f.param), o.max_abs))
                });
                if let Some(fxy) = fold_xy.filter(|&xy| finite(xy)) {
                    nodes.push(fxy);
                    styles.push(st);
                }
                nodes.push(xy);
                styles.push(st);
            }
            _ => segments.push((vec![xy], vec![st])),
        }
        prev = Some((k, seg));
    }
    let mut out: Vec<Run> = Vec::new();
    for (nodes, styles) in segments {
        let spline = Spline::through(&nodes, scale);
        out.push((styles[0], vec![nodes[0]]));
        for i in 0..spline.intervals() {
            let line = spline.interval(i, SMOOTH_SPACING);
            match out.last_mut() {
                Some((st, pts)) if *st == styles[i + 1] => pts.extend(line.into_iter().skip(1)),
                _ => out.push((styles[i + 1], line)),
            }
        }
    }
    out
}

/// The x range and the top of the y range of a panel's data and markers.
fn bounds(fig: &Figure, panel: &Panel, axis: XAxis) -> (f64, f64, f64) {
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
    (x0 - pad, x1 + pad, y1)
}

/// Everything a panel draws, in data coordinates, and its legend entries (in the order
/// they used to appear: each series, then the first unstable/fold/jump after the series
/// that first has one, then the marker kinds).
struct Content {
    /// Per series: colour and stability runs.
    curves: Vec<(RGBColor, Vec<Run>)>,
    /// Fold points.
    folds: Vec<(f64, f64)>,
    /// Jumps: colour, x, from, to.
    jumps: Vec<(RGBColor, f64, f64, f64)>,
    /// Time-domain markers: kind index and point.
    markers: Vec<(usize, (f64, f64))>,
    /// Overlays: their colour, tag and points.
    overlays: Vec<DrawnOverlay>,
    /// Legend rows.
    entries: Vec<(String, Key)>,
}

impl Content {
    fn of(
        fig: &Figure,
        overlays: &[Overlay],
        panel: &Panel,
        axis: XAxis,
        (scale, x_range): ((f64, f64), (f64, f64)),
    ) -> Self {
        let mut c = Content {
            curves: Vec::new(),
            folds: Vec::new(),
            jumps: Vec::new(),
            markers: Vec::new(),
            overlays: Vec::new(),
            entries: Vec::new(),
        };
        let (mut unstable_legend, mut fold_legend, mut jump_legend) = (false, false, false);
        for (k, s) in fig.series.iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            let Some(idx) = s.curve.output_names.iter().position(|n| *n == panel.output) else {
                continue;
            };
            let runs = runs(s.curve, idx, axis, scale);
            if !runs.is_empty() {
                c.entries.push((s.label.clone(), Key::Line(color)));
            }
            if !unstable_legend && runs.iter().any(|(st, _)| !st) {
                unstable_legend = true;
                c.entries.push(("unstable (dashed)".into(), Key::Dashed));
            }
            c.curves.push((color, runs));
            let n_folds = c.folds.len();
            c.folds.extend(
                s.curve.folds.iter().filter_map(|f| {
                    f.outputs.get(idx).map(|o| (axis.x(f.omega, f.param), o.max_abs))
                }),
            );
            if !fold_legend && c.folds.len() > n_folds {
                fold_legend = true;
                c.entries.push(("fold".into(), Key::Fold));
            }
            for j in s.curve.jumps.iter().filter(|j| j.output == panel.output) {
                // A jump's `omega` is the continuation parameter's value.
                c.jumps.push((color, axis.x(j.at, j.at), j.from, j.to));
                if !jump_legend {
                    jump_legend = true;
                    c.entries.push(("jump (slow sweep)".into(), Key::Jump));
                }
            }
        }
        // an overlay is drawn from its start while it stays in the curves' x range
        let mut labels: Vec<&str> = Vec::new();
        for o in overlays.iter().filter(|o| o.output == panel.output) {
            let pts: Vec<(f64, f64)> = o
                .points
                .iter()
                .map(|&(w, v)| (axis.x(w, w), v))
                .take_while(|p| p.0 >= x_range.0 && p.0 <= x_range.1)
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            if pts.is_empty() {
                continue;
            }
            let k = labels.iter().position(|l| *l == o.label).unwrap_or(labels.len());
            let color = OVERLAY_COLORS[k % OVERLAY_COLORS.len()];
            if k == labels.len() {
                labels.push(&o.label);
                c.entries.push((o.label.clone(), Key::Dotted(color)));
            }
            c.overlays.push((color, o.tag.clone(), pts));
        }
        let mut labels: Vec<&str> = Vec::new();
        for m in &fig.markers {
            if !labels.contains(&m.label.as_str()) {
                labels.push(&m.label);
            }
        }
        for (k, label) in labels.iter().enumerate() {
            c.entries.push((label.to_string(), marker_key(k)));
            c.markers.extend(
                fig.markers
                    .iter()
                    .filter(|m| {
                        m.label == *label && m.output == panel.output && m.value.is_finite()
                    })
                    .map(|m| (k, (axis.x(m.omega, m.omega), m.value))),
            );
        }
        c
    }

    /// Every stability run of every curve: colour, points, whether stable.
    fn runs(&self) -> impl Iterator<Item = (RGBColor, &[(f64, f64)], bool)> {
        self.curves
            .iter()
            .flat_map(|(c, runs)| runs.iter().map(|(st, pts)| (*c, pts.as_slice(), *st)))
    }

    /// What is drawn, as polylines in backend pixels (a marker is a one-point line):
    /// the curves' runs first, in the order of [`Content::runs`].
    fn pixel_lines(&self, map: PixelMap) -> Vec<Vec<(f64, f64)>> {
        let to_px = |p| map.px(p);
        let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
        for (_, runs) in &self.curves {
            out.extend(runs.iter().map(|(_, pts)| pts.iter().map(|&p| to_px(p)).collect()));
        }
        out.extend(self.overlays.iter().map(|(_, _, pts)| pts.iter().map(|&p| to_px(p)).collect()));
        out.extend(self.folds.iter().map(|&p| vec![to_px(p)]));
        out.extend(self.jumps.iter().map(|&(_, x, a, b)| vec![to_px((x, a)), to_px((x, b))]));
        out.extend(self.markers.iter().map(|&(_, p)| vec![to_px(p)]));
        out
    }
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The y axis runs to this multiple of the largest value drawn.
const HEADROOM: f64 = 1.08;

/// Margin around a panel's chart, pixels.
const MARGIN: u32 = 12;

fn build_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    (x0, x1, y1): (f64, f64, f64),
    right: u32,
) -> Result<Chart<'a, 'b>, Error> {
    ChartBuilder::on(area)
        .margin(MARGIN)
        .margin_right(right)
        .x_label_area_size(44)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, 0.0..y1 * HEADROOM)
        .map_err(plot_err)
}

/// Data to backend pixels without rounding (plotters' own map floors to whole pixels).
#[derive(Debug, Clone, Copy)]
struct PixelMap {
    /// Data and pixel values of two corners: (x, y) at the lower left and upper right.
    data: [(f64, f64); 2],
    px: [(f64, f64); 2],
}

impl PixelMap {
    fn of(chart: &Chart, (x0, x1, y1): (f64, f64, f64)) -> Self {
        let data = [(x0, 0.0), (x1, y1 * HEADROOM)];
        let px = data.map(|d| {
            let (x, y) = chart.backend_coord(&d);
            (f64::from(x), f64::from(y))
        });
        PixelMap { data, px }
    }

    fn px(&self, (x, y): (f64, f64)) -> (f64, f64) {
        let [(dx0, dy0), (dx1, dy1)] = self.data;
        let [(px0, py0), (px1, py1)] = self.px;
        (px0 + (x - dx0) / (dx1 - dx0) * (px1 - px0), py0 + (y - dy0) / (dy1 - dy0) * (py1 - py0))
    }
}

/// The plotting area of a chart in backend pixels, and pixels per data unit.
fn plot_rect(chart: &Chart, (x0, x1, y1): (f64, f64, f64)) -> (Rect, (f64, f64)) {
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let r = Rect { x0: xs.start as f64, y0: ys.start as f64, x1: xs.end as f64, y1: ys.end as f64 };
    (r, ((r.x1 - r.x0) / (x1 - x0), (r.y1 - r.y0) / (y1 * HEADROOM)))
}

fn draw_panel(
    fig: &Figure,
    overlays: &[Overlay],
    panel: &Panel,
    area: &DrawingArea<SVGBackend, Shift>,
    slots: &mut CurveSlots,
) -> Result<(), Error> {
    let axis = XAxis::of(fig);
    let b = bounds(fig, panel, axis);
    let mut chart = build_chart(area, b, MARGIN)?;
    let (mut rect, scale) = plot_rect(&chart, b);
    let mut content = Content::of(fig, overlays, panel, axis, (scale, (b.0, b.1)));
    let size = legend_size(&content.entries);
    let mut lines = content.pixel_lines(PixelMap::of(&chart, b));
    let mut legend_at = match legend::place(rect, size, &lines) {
        Placement::Inside(r) => (r.x0, r.y0),
        Placement::Outside => {
            // Narrow the plot to make room on the right; the smoothing's metric changes
            // with it.
            chart = build_chart(area, b, MARGIN + (size.0 + 2.0 * legend::INSET).ceil() as u32)?;
            let (r, scale) = plot_rect(&chart, b);
            rect = r;
            content = Content::of(fig, overlays, panel, axis, (scale, (b.0, b.1)));
            lines = content.pixel_lines(PixelMap::of(&chart, b));
            (rect.x1 + legend::INSET, rect.y0)
        }
    };
    // Legend coordinates are drawn relative to the panel.
    let base = area.get_base_pixel();
    legend_at = (legend_at.0 - f64::from(base.0), legend_at.1 - f64::from(base.1));

    // Enough decimals for three significant digits at the top of the axis.
    let decimals = (2.0 - b.2.log10().floor()).clamp(0.0, 12.0) as usize;
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
    // The curves' pixel lines come first in `lines`, run by run.
    let mut polylines = String::new();
    for ((color, _, stable), px) in content.runs().zip(&lines) {
        polylines.push_str(&svg_polyline(px.iter().copied(), color, !stable));
    }
    let map = PixelMap::of(&chart, b);
    for (color, tag, pts) in &content.overlays {
        polylines.push_str(&svg::overlay_polyline(pts.iter().map(|&p| map.px(p)), *color, tag));
    }
    slots.reserve(area, polylines)?;
    chart
        .draw_series(content.folds.iter().map(|&xy| TriangleMarker::new(xy, 7, BLACK.filled())))
        .map_err(plot_err)?;
    for &(color, x, from, to) in &content.jumps {
        chart
            .draw_series(std::iter::once(TriangleMarker::new((x, to), 5, color.filled())))
            .map_err(plot_err)?;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x, from), (x, to)],
                3,
                3,
                color.stroke_width(1),
            ))
            .map_err(plot_err)?;
    }
    let style = BLACK.stroke_width(2);
    for &(k, xy) in &content.markers {
        match marker_key(k) {
            Key::Circle => chart.draw_series(std::iter::once(Circle::new(xy, 5, style))),
            _ => chart.draw_series(std::iter::once(Cross::new(xy, 5, style))),
        }
        .map_err(plot_err)?;
    }
    let at = (legend_at.0.round() as i32, legend_at.1.round() as i32);
    draw_legend(area, at, size, &content.entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{CurveStats, Fold, PointOutput};

    fn out(v: f64) -> Vec<PointOutput> {
        vec![PointOutput::harmonic(0.0, v)]
    }

    /// A frequency-sweep curve of one output `x` through `(Ω, |x|, stable, segment)`.
    fn curve(points: &[(f64, f64, bool, usize)], folds: Vec<Fold>) -> Curve {
        Curve {
            model: "synthetic".into(),
            harmonics: 1,
            parameter: crate::results::Parameter::Omega,
            output_names: vec!["x".into()],
            points: points
                .iter()
                .map(|&(w, a, stable, segment)| CurvePoint {
                    omega: w,
                    param: w,
                    coeffs: vec![],
                    stability: crate::results::Stability::from_verdict(stable),
                    outputs: out(a),
                    segment,
                })
                .collect(),
            stability_checked: true,
            folds,
            jumps: vec![],
            peaks: vec![],
            segments: vec![],
            stats: CurveStats::default(),
            bifurcations: vec![],
            convergence: None,
        }
    }

    #[test]
    fn runs_pass_through_every_point_and_switch_style_where_the_points_do() {
        // Stable up to a fold between points 3 and 4, unstable back to point 5, stable
        // again; a second segment with a point that is not finite.
        let pts = [
            (1.0, 0.1, true, 0),
            (2.0, 0.3, true, 0),
            (3.0, 0.6, true, 0),
            (4.0, 1.0, true, 0),
            (3.6, 1.4, false, 0),
            (3.0, 1.6, false, 0),
            (3.2, 2.0, true, 0),
            (5.0, 2.2, true, 0),
            (6.0, 1.0, true, 1),
            (6.5, f64::NAN, true, 1),
            (7.0, 0.5, true, 1),
        ];
        let fold = Fold {
            omega: 4.1,
            param: 4.1,
            coeffs: vec![],
            outputs: out(1.2),
            after: 3,
            located: true,
        };
        let c = curve(&pts, vec![fold]);
        let runs = runs(&c, 0, XAxis::Freq(FreqUnit::RadPerSec), (100.0, 100.0));
        let p = |i: usize| (pts[i].0, pts[i].1);
        let nodes: Vec<(f64, f64)> =
            (0..pts.len()).filter(|&i| i != 9).map(p).chain([(4.1, 1.2)]).collect();
        // The old rule, on the computed points (and the located fold, drawn through): a
        // run that starts at a stability change begins at the previous point.
        let expected = vec![
            (true, vec![p(0), p(1), p(2), p(3)]),
            (false, vec![p(3), (4.1, 1.2), p(4), p(5)]),
            (true, vec![p(5), p(6), p(7)]),
            (true, vec![p(8), p(10)]),
        ];
        let got: Vec<Run> = runs
            .iter()
            .map(|(st, line)| (*st, line.iter().copied().filter(|q| nodes.contains(q)).collect()))
            .collect();
        assert_eq!(got, expected);
        // Each run starts and ends on a computed point, and long steps gained points.
        for (_, line) in &runs {
            assert!(nodes.contains(&line[0]) && nodes.contains(line.last().unwrap()));
        }
        let drawn: usize = runs.iter().map(|(_, l)| l.len()).sum();
        assert!(drawn > 3 * nodes.len(), "{drawn} drawn points for {} nodes", nodes.len());
    }

    /// `(x, y)` pairs of a `points` attribute.
    fn coords(points: &str) -> Vec<(f64, f64)> {
        points
            .split_whitespace()
            .map(|xy| {
                let (x, y) = xy.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect()
    }

    #[test]
    fn the_legend_leaves_a_curve_through_the_upper_right_uncovered() {
        // A peak at the right reaching the top of the plot, a plateau across the top right
        // and a rise at the left: the old fixed place (upper right) sits on the data.
        let pts: Vec<(f64, f64, bool, usize)> = (0..=90)
            .map(|i| {
                let w = 1.0 + 0.1 * i as f64;
                (w, 0.2 + 0.8 / (1.0 + ((w - 9.0) / 0.6).powi(2)), !(8.0..=9.5).contains(&w), 0)
            })
            .collect();
        let c = curve(&pts, vec![]);
        let fig = Figure {
            title: "legend placement".into(),
            unit: FreqUnit::RadPerSec,
            panels: vec![Panel { output: "x".into(), label: "|x| (m)".into() }],
            series: vec![Series { label: "a peak in the upper right".into(), curve: &c }],
            markers: vec![],
        };
        let svg = figure_svg(&fig).unwrap();
        assert!(!svg.contains("ihbm-curve-slot"), "a placeholder was left");
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let border: Vec<Rect> = doc
            .descendants()
            .filter(|n| n.has_tag_name("rect") && n.attribute("stroke") == Some("#000000"))
            .map(|n| {
                let v = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
                Rect { x0: v("x"), y0: v("y"), x1: v("x") + v("width"), y1: v("y") + v("height") }
            })
            .collect();
        let [legend] = border.as_slice() else { panic!("one legend box: {border:?}") };
        let lines: Vec<Vec<(f64, f64)>> = doc
            .descendants()
            .filter(|n| {
                n.has_tag_name("polyline") && n.attribute("stroke-linejoin") == Some("round")
            })
            .map(|n| coords(n.attribute("points").unwrap()))
            .collect();
        assert_eq!(lines.len(), 3, "stable, unstable, stable");
        assert!(lines.iter().flatten().any(|p| p.0.fract() != 0.0), "sub-pixel coordinates");
        for line in &lines {
            for s in line.windows(2) {
                assert!(!legend.meets(s[0], s[1]), "{s:?} crosses the legend {legend:?}");
            }
        }
        // The curve's top is at the right; the legend went left of it.
        let top = lines.iter().flatten().copied().fold((0.0, f64::INFINITY), |a, p| {
            if p.1 < a.1 {
                p
            } else {
                a
            }
        });
        assert!(legend.x1 < top.0, "legend {legend:?}, top of the curve at {top:?}");
    }

    #[test]
    fn a_legend_with_no_free_place_inside_goes_to_the_right_of_the_plot() {
        // Eleven level curves 0.1 apart in |x| cross every candidate box.
        let curves: Vec<Curve> = (0..=10)
            .map(|k| {
                let pts: Vec<(f64, f64, bool, usize)> = (0..=20)
                    .map(|i| (1.0 + i as f64, 0.1 * k as f64 + 0.001 * i as f64, true, 0))
                    .collect();
                curve(&pts, vec![])
            })
            .collect();
        let fig = Figure {
            title: "crowded".into(),
            unit: FreqUnit::RadPerSec,
            panels: vec![Panel { output: "x".into(), label: "|x| (m)".into() }],
            series: curves
                .iter()
                .enumerate()
                .map(|(k, c)| Series { label: format!("level {k}"), curve: c })
                .collect(),
            markers: vec![],
        };
        let svg = figure_svg(&fig).unwrap();
        if let Ok(dir) = std::env::var("IHBM_REPORT_SVG_DIR") {
            std::fs::write(format!("{dir}/crowded.svg"), &svg).unwrap();
        }
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let legend = doc
            .descendants()
            .find(|n| n.has_tag_name("rect") && n.attribute("stroke") == Some("#000000"))
            .unwrap();
        let v = |a: &str| legend.attribute(a).unwrap().parse::<f64>().unwrap();
        let right_of_curves = doc
            .descendants()
            .filter(|n| {
                n.has_tag_name("polyline") && n.attribute("stroke-linejoin") == Some("round")
            })
            .flat_map(|n| coords(n.attribute("points").unwrap()))
            .fold(f64::NEG_INFINITY, |a, p| a.max(p.0));
        assert!(
            v("x") > right_of_curves,
            "legend at {} left of a curve at {right_of_curves}",
            v("x")
        );
        assert!(v("x") + v("width") <= f64::from(PANEL_W), "the legend leaves the figure");
    }
}
