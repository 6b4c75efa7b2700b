//! Smooth lines through drawn points: a cubic Hermite spline in chord length.
//!
//! A continuation takes long steps where the curve is straight in its own (state-space)
//! metric, which can still be strongly curved on a figure; joining the points by straight
//! lines then shows corners. This spline passes exactly through every point and only adds
//! points *for drawing* (data files keep the computed points).
//!
//! - The parameter is the chord length in a metric the caller gives (pixels per unit on
//!   each axis), i.e. the arc length *as drawn*. It is never the abscissa, so a fold (Ω
//!   turning back) stays a fold.
//! - The tangent at a point is the derivative of the parabola through it and its two
//!   neighbours (Bessel's tangent; at an end, of the parabola through the first or last
//!   three points). In chord length an interior tangent is a convex combination of the two
//!   adjacent unit chords, so its length is at most 1; an end tangent is capped at 1 too.
//!   Each piece is then inside the convex hull of its Bézier polygon, whose inner points
//!   lie within a third of the chord from the chord's ends: no loops, bounded overshoot.
//! - Exact for straight lines (in any spacing) and, with exact tangents, for cubics.

/// A point in the plane.
pub type Point = (f64, f64);

/// The cubic Hermite piece with ends `p0`, `p1`, end derivatives `m0`, `m1` with respect
/// to a parameter running over an interval of length `h`, evaluated at the fraction `s`
/// of that interval (`s` = 0 gives `p0`, `s` = 1 gives `p1`).
pub fn hermite(p0: Point, m0: Point, p1: Point, m1: Point, h: f64, s: f64) -> Point {
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    (
        h00 * p0.0 + h10 * h * m0.0 + h01 * p1.0 + h11 * h * m1.0,
        h00 * p0.1 + h10 * h * m0.1 + h01 * p1.1 + h11 * h * m1.1,
    )
}

/// Derivatives at the knots `t` of the parabolas through consecutive triples of
/// `points` (exact when the points lie on a quadratic in `t`). An interval of zero
/// length has no slope: a point next to one takes the slope of its other side.
/// Fewer than three points: the chord's slope (zero for a single point).
///
/// `t` must be non-decreasing and as long as `points`.
pub fn parabola_tangents(t: &[f64], points: &[Point]) -> Vec<Point> {
    let n = points.len().min(t.len());
    let h: Vec<f64> = (1..n).map(|i| t[i] - t[i - 1]).collect();
    let slope: Vec<Option<Point>> = (1..n)
        .map(|i| {
            let hi = h[i - 1];
            (hi > 0.0).then(|| {
                ((points[i].0 - points[i - 1].0) / hi, (points[i].1 - points[i - 1].1) / hi)
            })
        })
        .collect();
    let zero = (0.0, 0.0);
    let mix = |a: Point, wa: f64, b: Point, wb: f64| (wa * a.0 + wb * b.0, wa * a.1 + wb * b.1);
    (0..n)
        .map(|i| {
            if n < 3 {
                return slope.first().copied().flatten().unwrap_or(zero);
            }
            // The triple whose parabola gives the tangent at point i, and i's place in it.
            let (j, at) = match i {
                0 => (1, 0),
                _ if i == n - 1 => (n - 2, 2),
                _ => (i, 1),
            };
            let (ha, hb) = (h[j - 1], h[j]);
            match (slope[j - 1], slope[j]) {
                (Some(da), Some(db)) => match at {
                    // p'(t_{j-1}) = ((2ha + hb) da - ha db) / (ha + hb)
                    0 => mix(da, (2.0 * ha + hb) / (ha + hb), db, -ha / (ha + hb)),
                    // p'(t_j) = (hb da + ha db) / (ha + hb)
                    1 => mix(da, hb / (ha + hb), db, ha / (ha + hb)),
                    // p'(t_{j+1}) = ((2hb + ha) db - hb da) / (ha + hb)
                    _ => mix(da, -hb / (ha + hb), db, (2.0 * hb + ha) / (ha + hb)),
                },
                (Some(d), None) | (None, Some(d)) => d,
                (None, None) => zero,
            }
        })
        .collect()
}

/// A spline through points, parametrised by chord length in the caller's metric.
#[derive(Debug, Clone)]
pub struct Spline {
    /// The points as given.
    nodes: Vec<Point>,
    /// Pixels per unit on each axis.
    scale: Point,
    /// Chord lengths of the intervals, in pixels.
    h: Vec<f64>,
    /// Tangents in scaled coordinates, per unit chord length (length ≤ 1).
    m: Vec<Point>,
}

impl Spline {
    /// The spline through `nodes`, lengths measured as `hypot(dx·sx, dy·sy)` with
    /// `scale = (sx, sy)` (pixels per unit; a scale that is not positive and finite
    /// counts as 1). Points must be finite.
    pub fn through(nodes: &[Point], scale: Point) -> Self {
        let ok = |v: f64| if v.is_finite() && v > 0.0 { v } else { 1.0 };
        let scale = (ok(scale.0), ok(scale.1));
        let q: Vec<Point> = nodes.iter().map(|p| (p.0 * scale.0, p.1 * scale.1)).collect();
        let h: Vec<f64> = q.windows(2).map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1)).collect();
        let mut t = Vec::with_capacity(q.len());
        let mut acc = 0.0;
        t.push(acc);
        for hi in &h {
            acc += hi;
            t.push(acc);
        }
        let m = parabola_tangents(&t, &q)
            .into_iter()
            .map(|m| {
                // Only an end tangent can exceed 1; a drawn curve's unit tangent cannot.
                let len = m.0.hypot(m.1);
                if len > 1.0 {
                    (m.0 / len, m.1 / len)
                } else {
                    m
                }
            })
            .collect();
        Spline { nodes: nodes.to_vec(), scale, h, m }
    }

    /// Number of intervals (points − 1, or 0).
    pub fn intervals(&self) -> usize {
        self.h.len()
    }

    /// The point at fraction `s` ∈ [0, 1] of interval `i` (panics if `i` is out of range).
    pub fn at(&self, i: usize, s: f64) -> Point {
        let (sx, sy) = self.scale;
        let q0 = (self.nodes[i].0 * sx, self.nodes[i].1 * sy);
        let q1 = (self.nodes[i + 1].0 * sx, self.nodes[i + 1].1 * sy);
        let q = hermite(q0, self.m[i], q1, self.m[i + 1], self.h[i], s);
        (q.0 / sx, q.1 / sy)
    }

    /// Interval `i` as a polyline: its two nodes exactly as given, with points in between
    /// about `spacing` pixels apart (none if the chord is shorter; at most 64). Panics if
    /// `i` is out of range, as indexing does.
    pub fn interval(&self, i: usize, spacing: f64) -> Vec<Point> {
        let pieces =
            if spacing > 0.0 { (self.h[i] / spacing).ceil().clamp(1.0, 64.0) } else { 1.0 };
        let k = pieces as usize;
        let mut out = Vec::with_capacity(k + 1);
        out.push(self.nodes[i]);
        out.extend((1..k).map(|j| self.at(i, j as f64 / k as f64)));
        out.push(self.nodes[i + 1]);
        out
    }

    /// The whole spline as one polyline (see [`Spline::interval`]).
    pub fn polyline(&self, spacing: f64) -> Vec<Point> {
        let mut out = self.nodes.first().copied().into_iter().collect::<Vec<_>>();
        for i in 0..self.intervals() {
            out.extend(self.interval(i, spacing).into_iter().skip(1));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn close(a: Point, b: Point, tol: f64) -> bool {
        (a.0 - b.0).abs() <= tol && (a.1 - b.1).abs() <= tol
    }

    #[test]
    fn every_node_is_drawn_exactly_including_folds_and_repeats() {
        // Ω goes forward, turns back (a fold), forward again; one point is repeated.
        let nodes = [
            (1.0, 0.1),
            (2.0, 0.2),
            (3.0, 0.5),
            (2.5, 0.9),
            (2.5, 0.9),
            (2.0, 1.3),
            (4.0, 1.4),
            (7.0, 0.3),
        ];
        let s = Spline::through(&nodes, (100.0, 300.0));
        assert_eq!(s.intervals(), nodes.len() - 1);
        for i in 0..s.intervals() {
            let line = s.interval(i, 2.0);
            assert_eq!(line[0], nodes[i]);
            assert_eq!(*line.last().unwrap(), nodes[i + 1]);
            assert!(
                close(s.at(i, 0.0), nodes[i], 1e-14) && close(s.at(i, 1.0), nodes[i + 1], 1e-14)
            );
            assert!(line.iter().all(|p| p.0.is_finite() && p.1.is_finite()));
        }
        let all = s.polyline(2.0);
        assert!(nodes.iter().all(|n| all.contains(n)));
    }

    #[test]
    fn a_straight_line_is_drawn_straight_at_its_own_arc_length() {
        // Collinear points, unevenly spaced, in a metric that is not isotropic: chord length
        // is arc length, so the spline is the linear interpolation itself.
        let (a, d) = ((0.3, -1.0), (3.0, -2.0));
        let ts = [0.0, 0.1, 0.15, 0.9, 1.0, 2.5];
        let nodes: Vec<Point> = ts.iter().map(|t| (a.0 + t * d.0, a.1 + t * d.1)).collect();
        let s = Spline::through(&nodes, (2.0, 0.5));
        for i in 0..s.intervals() {
            for j in 0..=10 {
                let f = j as f64 / 10.0;
                let t = ts[i] + f * (ts[i + 1] - ts[i]);
                assert!(close(s.at(i, f), (a.0 + t * d.0, a.1 + t * d.1), 1e-12), "{i} {f}");
            }
        }
    }

    #[test]
    fn hermite_with_exact_tangents_reproduces_a_cubic() {
        let p = |t: f64| (t.powi(3) - 2.0 * t + 1.0, 0.5 * t.powi(3) + t * t - 4.0);
        let dp = |t: f64| (3.0 * t * t - 2.0, 1.5 * t * t + 2.0 * t);
        let (t0, t1) = (-0.7, 1.9);
        for j in 0..=20 {
            let s = j as f64 / 20.0;
            let got = hermite(p(t0), dp(t0), p(t1), dp(t1), t1 - t0, s);
            assert!(close(got, p(t0 + s * (t1 - t0)), 1e-12), "s = {s}");
        }
    }

    #[test]
    fn parabola_tangents_are_exact_for_a_quadratic_at_uneven_knots() {
        let p = |t: f64| (2.0 * t * t - t + 3.0, -0.5 * t * t + 4.0 * t);
        let dp = |t: f64| (4.0 * t - 1.0, -t + 4.0);
        let t = [0.0, 0.3, 1.0, 1.1, 2.6];
        let pts: Vec<Point> = t.iter().map(|&t| p(t)).collect();
        let m = parabola_tangents(&t, &pts);
        for (ti, mi) in t.iter().zip(&m) {
            assert!(close(*mi, dp(*ti), 1e-12), "t = {ti}: {mi:?}");
        }
        // Hence the Hermite pieces are the quadratic itself.
        for i in 0..t.len() - 1 {
            let s = 0.37;
            let got = hermite(pts[i], m[i], pts[i + 1], m[i + 1], t[i + 1] - t[i], s);
            assert!(close(got, p(t[i] + s * (t[i + 1] - t[i])), 1e-12));
        }
    }

    /// Largest `err` on the spline through `nodes` and on their chords, each interval
    /// sampled at 401 points.
    fn worst(nodes: &[Point], scale: Point, err: impl Fn(Point) -> f64) -> (f64, f64) {
        let s = Spline::through(nodes, scale);
        let (mut smooth, mut straight) = (0.0f64, 0.0f64);
        for i in 0..s.intervals() {
            let (a, b) = (nodes[i], nodes[i + 1]);
            for j in 0..=400 {
                let f = j as f64 / 400.0;
                smooth = smooth.max(err(s.at(i, f)));
                straight = straight.max(err((a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1))));
            }
        }
        (smooth, straight)
    }

    /// Largest |r − 1| on the spline and on the chords through `n + 1` points spread
    /// evenly over an arc of `arc` radians of the unit circle.
    fn circle_errors(n: usize, arc: f64) -> (f64, f64) {
        let nodes: Vec<Point> = (0..=n)
            .map(|i| {
                let a = arc * i as f64 / n as f64;
                (a.cos(), a.sin())
            })
            .collect();
        worst(&nodes, (1.0, 1.0), |p| (p.0.hypot(p.1) - 1.0).abs())
    }

    #[test]
    fn a_coarse_circle_is_drawn_far_closer_than_by_chords() {
        // Three quarters of the unit circle in 9 steps of 30°: the chords miss it by
        // 1 − cos 15° ≈ 0.034 (at their midpoints).
        let (smooth, straight) = circle_errors(9, 1.5 * PI);
        assert!((straight - (1.0 - (PI / 12.0).cos())).abs() < 1e-5, "{straight}");
        assert!(straight >= 5.0 * smooth, "spline {smooth:.2e} vs chords {straight:.2e}");
        // Halving the step: the chords' error falls 4× (second order), the spline's at
        // least 8× (third order or better).
        let (smooth2, straight2) = circle_errors(18, 1.5 * PI);
        assert!((straight / straight2 - 4.0).abs() < 0.1, "{straight} -> {straight2}");
        assert!(smooth / smooth2 >= 8.0, "{smooth:.2e} -> {smooth2:.2e}");
    }

    /// Largest vertical distance in pixels from the spline and from the chords through
    /// `n + 1` evenly spaced Ω in [0, 2] to the resonance curve |X(Ω)| of a 1-DOF
    /// oscillator m x'' + c x' + k x = F cos Ωt, |X| = F / sqrt((k − mΩ²)² + (cΩ)²),
    /// drawn on 800 × 400 pixels (with m = k = F = 1, c = 0.5, the peak is near 2.07).
    fn resonance_errors(n: usize) -> (f64, f64) {
        let (m, c, k, f) = (1.0, 0.5, 1.0, 1.0);
        let amp = |w: f64| f / ((k - m * w * w).powi(2) + (c * w).powi(2)).sqrt();
        let scale = (800.0 / 2.0, 400.0 / 2.3);
        let nodes: Vec<Point> =
            (0..=n).map(|i| 2.0 * i as f64 / n as f64).map(|w| (w, amp(w))).collect();
        worst(&nodes, scale, |p| (p.1 - amp(p.0)).abs() * scale.1)
    }

    #[test]
    fn a_coarse_linear_resonance_curve_is_drawn_far_closer_than_by_chords() {
        // 60 points: steps of 13 px across, up to ~60 px along the flanks of the peak.
        let (smooth, straight) = resonance_errors(60);
        assert!(straight >= 5.0 * smooth, "spline {smooth:.3} px vs chords {straight:.3} px");
        // Orders as for the circle: chords second, the spline third or better.
        let (s40, c40) = resonance_errors(40);
        let (s80, c80) = resonance_errors(80);
        assert!(c40 / c80 > 3.5 && c40 / c80 < 4.5, "chords {c40:.3} -> {c80:.3}");
        assert!(s40 / s80 >= 8.0, "spline {s40:.3} -> {s80:.3}");
    }

    #[test]
    fn pieces_stay_within_a_third_of_their_chord() {
        // A zig-zag with long and short steps. A piece lies in the convex hull of its
        // Bézier polygon p0, p0 + h m0 / 3, p1 − h m1 / 3, p1 with |m| ≤ 1, hence within
        // h / 3 of its chord.
        let nodes = [(0.0, 0.0), (10.0, 0.0), (10.5, 3.0), (0.0, 3.2), (0.2, 0.1), (9.0, 0.0)];
        let s = Spline::through(&nodes, (1.0, 1.0));
        for i in 0..s.intervals() {
            let (a, b) = (nodes[i], nodes[i + 1]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let h = dx.hypot(dy);
            for p in s.interval(i, 0.05) {
                let u = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (h * h)).clamp(0.0, 1.0);
                let d = (p.0 - a.0 - u * dx).hypot(p.1 - a.1 - u * dy);
                assert!(d <= h / 3.0 + 1e-12, "{i}: {p:?} is {d} from a chord of {h}");
            }
        }
    }
}
