//! Where slow up and down sweeps jump (the paper's "forward and reverse scanning").
//!
//! A slow sweep follows a stable branch while the parameter moves on. When the
//! branch folds back (a fold where the parameter would have to reverse), the response
//! drops to another stable branch at the same parameter value. We replay that on the
//! traced curve: start at the stable point with the smallest (up) or largest (down)
//! parameter, walk along the polyline while the parameter moves the sweep's way, and at
//! each turning point land on the stable piece of curve (any segment, away from the
//! fold itself) at the fold's parameter whose amplitudes are nearest (the polyline
//! locates the landing; [`Landing`] lets the caller solve there exactly). The walk stops
//! at the end of a segment, or where the branch loses stability without a fold (the
//! response then leaves for a branch this curve does not contain: period-2 or
//! quasi-periodic; no jump is invented).

use crate::results::{CurvePoint, Direction, Fold, Jump, Stability, Unknown};

struct Vertex {
    x: f64,
    amps: Vec<f64>,
    stable: bool,
    fold: bool,
    /// index into the points (None for a fold vertex)
    index: Option<usize>,
}

/// Where a jump lands on the traced curve: between `points[a]` and `points[b]`, at
/// weight `w` (0 at `a`, 1 at `b`) of the parameter. The amplitudes in the [`Jump`]s
/// are interpolated there; solving at the jump's parameter from the interpolated
/// coefficients gives them exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Landing {
    /// The first index of the jumps (one per output) that land here.
    pub jump: usize,
    /// The point before the landing.
    pub a: usize,
    /// The point after it.
    pub b: usize,
    /// Where between them, by parameter.
    pub w: f64,
}

/// Whether a slow sweep may follow (or land on) a point: a stable one, or any point
/// of a curve traced without stability (nothing tells it apart). A failed analysis is
/// no place to land.
fn followable(s: &Stability) -> bool {
    matches!(s, Stability::Stable | Stability::Unknown(Unknown::NotChecked))
}

/// The jumps of slow up and down sweeps over a traced curve, one per output each, and
/// where each group of jumps (one per output) lands.
///
/// Folds must carry their `after` index into `points`; fold vertices count as
/// unstable landing places.
pub(crate) fn find_landings(
    points: &[CurvePoint],
    folds: &[Fold],
    output_names: &[String],
) -> (Vec<Jump>, Vec<Landing>) {
    let nseg = points.iter().map(|p| p.segment + 1).max().unwrap_or(0);
    let mut lines: Vec<Vec<Vertex>> = (0..nseg).map(|_| Vec::new()).collect();
    for (i, p) in points.iter().enumerate() {
        lines[p.segment].push(Vertex {
            x: p.param,
            amps: p.outputs.iter().map(|o| o.max_abs).collect(),
            stable: followable(&p.stability),
            fold: false,
            index: Some(i),
        });
        for f in folds.iter().filter(|f| f.after == i) {
            lines[p.segment].push(Vertex {
                x: f.param,
                amps: f.outputs.iter().map(|o| o.max_abs).collect(),
                stable: false,
                fold: true,
                index: None,
            });
        }
    }
    let mut jumps = Vec::new();
    let mut landings = Vec::new();
    for (direction, sign) in [(Direction::Up, 1.0), (Direction::Down, -1.0)] {
        walk(&lines, direction, sign, folds.len(), output_names, &mut jumps, &mut landings);
    }
    (jumps, landings)
}

fn walk(
    lines: &[Vec<Vertex>],
    direction: Direction,
    sign: f64,
    nfolds: usize,
    names: &[String],
    jumps: &mut Vec<Jump>,
    landings: &mut Vec<Landing>,
) {
    let key = |v: &Vertex| sign * v.x;
    // Start: the stable point furthest back in the sweep direction.
    let mut start: Option<(usize, usize)> = None;
    for (l, line) in lines.iter().enumerate() {
        for (i, v) in line.iter().enumerate() {
            if v.stable && start.is_none_or(|(sl, si)| key(v) < key(&lines[sl][si])) {
                start = Some((l, i));
            }
        }
    }
    let Some((mut l, mut i)) = start else { return };
    let line = &lines[l];
    let mut d: isize = if i + 1 < line.len() && key(&line[i + 1]) >= key(&line[i]) {
        1
    } else if i > 0 && key(&line[i - 1]) >= key(&line[i]) {
        -1
    } else {
        return;
    };
    let mut budget = 2 * nfolds + 2;
    loop {
        let j = i as isize + d;
        if j < 0 || j as usize >= lines[l].len() {
            return;
        }
        let (vi, vj) = (&lines[l][i], &lines[l][j as usize]);
        if key(vj) >= key(vi) {
            if !vj.stable && !vj.fold {
                return; // stability lost without a fold: destination unknown
            }
            i = j as usize;
            continue;
        }
        // The branch turns back at vi: fall off.
        if budget == 0 {
            return;
        }
        budget -= 1;
        let xf = key(vi);
        let mut best: Option<(f64, usize, usize, Vec<f64>, f64)> = None;
        for (l2, line) in lines.iter().enumerate() {
            for k in 0..line.len().saturating_sub(1) {
                if l2 == l && k + 2 >= i && k <= i + 1 {
                    continue; // the fold's own neighbourhood
                }
                let (a, b) = (&line[k], &line[k + 1]);
                if !(a.stable && b.stable) {
                    continue;
                }
                let (ka, kb) = (key(a), key(b));
                if ka == kb || xf < ka.min(kb) || xf > ka.max(kb) {
                    continue;
                }
                let w = (xf - ka) / (kb - ka);
                let amps: Vec<f64> =
                    a.amps.iter().zip(&b.amps).map(|(p, q)| p + w * (q - p)).collect();
                let dist: f64 = amps
                    .iter()
                    .zip(&vi.amps)
                    .map(|(p, q)| (p - q).abs() / (p.abs() + q.abs()).max(f64::MIN_POSITIVE))
                    .sum();
                // The same branch traced again by the other segment is no place to
                // land: a jump goes to a different response.
                if dist < 1e-6 {
                    continue;
                }
                if best.as_ref().is_none_or(|b| dist < b.0) {
                    best = Some((dist, l2, k, amps, w));
                }
            }
        }
        let Some((_, l2, k, amps, w)) = best else { return };
        if let (Some(a), Some(b)) = (lines[l2][k].index, lines[l2][k + 1].index) {
            landings.push(Landing { jump: jumps.len(), a, b, w });
        }
        for (o, name) in names.iter().enumerate() {
            jumps.push(Jump {
                direction,
                at: vi.x,
                output: name.clone(),
                from: vi.amps[o],
                to: amps[o],
            });
        }
        l = l2;
        if key(&lines[l][k + 1]) > key(&lines[l][k]) {
            i = k + 1;
            d = 1;
        } else {
            i = k;
            d = -1;
        }
    }
}
