//! Where a figure's legend goes: a box, inside the plot, that no drawn line crosses.
//!
//! A fixed corner puts the legend on the data whenever a curve passes there (a resonance
//! peak near the top right, for instance). The candidates are the corners and points
//! along the edges of the plot, in a fixed order of preference; the first one whose box
//! (with a small clearance) no drawn segment meets is taken. When every one is crossed,
//! the legend goes outside the plot, to its right, where it covers nothing.

/// A point in pixels, y downwards.
pub type Point = (f64, f64);

/// An axis-aligned rectangle in pixels, `x0 ≤ x1`, `y0 ≤ y1` (y downwards).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Left edge.
    pub x0: f64,
    /// Top edge.
    pub y0: f64,
    /// Right edge.
    pub x1: f64,
    /// Bottom edge.
    pub y1: f64,
}

impl Rect {
    /// The rectangle grown by `d` on every side.
    pub fn grown(self, d: f64) -> Rect {
        Rect { x0: self.x0 - d, y0: self.y0 - d, x1: self.x1 + d, y1: self.y1 + d }
    }

    /// Whether the segment from `a` to `b` (a single point if `a == b`) meets the
    /// rectangle, edges included (Liang–Barsky clipping).
    pub fn meets(&self, a: Point, b: Point) -> bool {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        // Each pair: p·t ≤ q must hold for the part of the segment inside one slab side.
        for (p, q) in
            [(-dx, a.0 - self.x0), (dx, self.x1 - a.0), (-dy, a.1 - self.y0), (dy, self.y1 - a.1)]
        {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
                if t0 > t1 {
                    return false;
                }
            }
        }
        true
    }
}

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Placement {
    /// Inside the plot, in this box, which no drawn segment meets.
    Inside(Rect),
    /// Every candidate inside is crossed: outside the plot, to its right.
    Outside,
}

/// Gap between the legend box and the plot's edges, pixels.
pub const INSET: f64 = 6.0;
/// Clearance kept between the box and any drawn segment (half a line width and a
/// marker's radius), pixels.
pub const CLEARANCE: f64 = 6.0;

/// The candidate boxes of `size` (width, height) in `plot`, most preferred first: the
/// four corners (the upper right first, as it used to be fixed), then along the top and
/// bottom edges, then the middle of the right and left edges.
pub fn candidates(plot: Rect, size: (f64, f64)) -> Vec<Rect> {
    let (w, h) = size;
    let (left, right) = (plot.x0 + INSET, plot.x1 - INSET - w);
    let (top, bottom) = (plot.y0 + INSET, plot.y1 - INSET - h);
    let x_at = |f: f64| left + f * (right - left);
    let y_mid = 0.5 * (top + bottom);
    let mut spots = vec![(right, top), (left, top), (right, bottom), (left, bottom)];
    for f in [0.5, 0.75, 0.25] {
        spots.push((x_at(f), top));
        spots.push((x_at(f), bottom));
    }
    spots.extend([(right, y_mid), (left, y_mid)]);
    spots.into_iter().map(|(x, y)| Rect { x0: x, y0: y, x1: x + w, y1: y + h }).collect()
}

/// The first candidate box (see [`candidates`]) that no segment of `lines` (polylines
/// in pixels; a one-point line is a marker) comes within [`CLEARANCE`] of, or
/// [`Placement::Outside`] if there is none or the box does not fit in the plot.
pub fn place(plot: Rect, size: (f64, f64), lines: &[Vec<Point>]) -> Placement {
    let fits =
        size.0 + 2.0 * INSET <= plot.x1 - plot.x0 && size.1 + 2.0 * INSET <= plot.y1 - plot.y0;
    if !fits {
        return Placement::Outside;
    }
    let crossed = |r: &Rect| {
        let g = r.grown(CLEARANCE);
        lines.iter().any(|l| match l.as_slice() {
            [p] => g.meets(*p, *p),
            l => l.windows(2).any(|s| g.meets(s[0], s[1])),
        })
    };
    candidates(plot, size)
        .into_iter()
        .find(|r| !crossed(r))
        .map_or(Placement::Outside, Placement::Inside)
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: Rect = Rect { x0: 10.0, y0: 20.0, x1: 30.0, y1: 40.0 };

    #[test]
    fn segments_meet_a_rectangle_exactly_when_they_cross_or_touch_it() {
        // Through, into, along an edge, a corner touch, a point inside.
        assert!(R.meets((0.0, 30.0), (50.0, 30.0)));
        assert!(R.meets((20.0, 0.0), (20.0, 25.0)));
        assert!(R.meets((10.0, 0.0), (10.0, 100.0)));
        assert!(R.meets((0.0, 10.0), (10.0, 20.0)));
        assert!(R.meets((15.0, 35.0), (15.0, 35.0)));
        // Beside, short of it, passing a corner diagonally outside, a point outside.
        assert!(!R.meets((0.0, 0.0), (0.0, 100.0)));
        assert!(!R.meets((20.0, 0.0), (20.0, 19.9)));
        assert!(!R.meets((0.0, 15.0), (15.0, 0.0)));
        assert!(!R.meets((31.0, 35.0), (31.0, 35.0)));
        // Symmetric in the ends.
        assert!(R.meets((50.0, 30.0), (0.0, 30.0)) && !R.meets((15.0, 0.0), (0.0, 15.0)));
    }

    #[test]
    fn a_curve_through_the_upper_right_moves_the_legend() {
        let plot = Rect { x0: 0.0, y0: 0.0, x1: 800.0, y1: 400.0 };
        let size = (180.0, 60.0);
        // A resonance-like peak at the right: rises to the top near x = 700.
        let peak: Vec<Point> = (0..=80)
            .map(|i| {
                let x = 10.0 * i as f64;
                (x, 390.0 - 380.0 / (1.0 + ((x - 700.0) / 40.0).powi(2)))
            })
            .collect();
        let lines = vec![peak];
        let upper_right = candidates(plot, size)[0];
        let crossed = |r: Rect| lines[0].windows(2).any(|s| r.meets(s[0], s[1]));
        assert!(crossed(upper_right), "the old fixed place would cover the peak");
        let Placement::Inside(r) = place(plot, size, &lines) else {
            panic!("the upper left is free")
        };
        assert!(!crossed(r.grown(CLEARANCE)));
        assert_eq!(r, candidates(plot, size)[1]);
    }

    #[test]
    fn a_plot_crossed_everywhere_puts_the_legend_outside() {
        let plot = Rect { x0: 0.0, y0: 0.0, x1: 400.0, y1: 300.0 };
        // Horizontal lines every 40 px leave no 60-px-high gap anywhere.
        let lines: Vec<Vec<Point>> =
            (0..=8).map(|i| vec![(0.0, 40.0 * i as f64), (400.0, 40.0 * i as f64)]).collect();
        assert_eq!(place(plot, (100.0, 60.0), &lines), Placement::Outside);
        // A legend bigger than the plot does not fit either.
        assert_eq!(place(plot, (500.0, 60.0), &[]), Placement::Outside);
        // A single marker (one-point line) in the upper right counts.
        let p = place(plot, (100.0, 60.0), &[vec![(350.0, 30.0)]]);
        assert_eq!(p, Placement::Inside(candidates(plot, (100.0, 60.0))[1]));
    }
}
