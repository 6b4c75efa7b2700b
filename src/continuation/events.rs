//! What a running continuation tells the outside: the [`Event`]s of
//! [`Continuation::step`](super::Continuation::step), the [`Trace`] traced so far, and
//! the [`Observer`]s that watch a run and may stop it.

use crate::results::{
    Bifurcation, Curve, CurvePoint, CurveStats, End, Fold, Jump, Parameter, Peak, Segment,
};

/// What one [`Continuation::step`](super::Continuation::step) produced. Indices point into the [`Trace`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A point was accepted: `trace.points[i]`, with its stability.
    Point(usize),
    /// A fold was located: `trace.folds[i]` (reported before the point after it).
    Fold(usize),
    /// A change of stability that is not a fold: `trace.bifurcations[i]`.
    Bifurcation(usize),
    /// A local maximum of an output's `max_abs` was located: `trace.peaks[i]`
    /// (reported before the point after it).
    Peak(usize),
    /// A segment ended: `trace.segments[i]` says why.
    SegmentEnd(usize),
    /// Nothing more to trace; [`Continuation::finish`](super::Continuation::finish) gives the curve. Every later
    /// `step` returns `Finished` again.
    Finished,
}

/// An observer's answer: go on, or stop the run here (what is traced is kept).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Take the next step.
    Continue,
    /// Stop: [`Continuation::run`](super::Continuation::run) finishes the curve with what is traced.
    Stop,
}

/// Watches a run: called with every event and what is traced so far, and may stop it.
///
/// One trait for every path: a frequency or parameter sweep (the defaults, [`Event`]
/// and [`Trace`]), fold curves ([`FoldEvent`](crate::bifurcation::FoldEvent),
/// [`FoldCurves`](crate::bifurcation::FoldCurves)), a backbone
/// ([`BackboneEvent`](crate::backbone::BackboneEvent),
/// [`Backbone`](crate::backbone::Backbone)) and a family of limit cycles
/// ([`FamilyEvent`](crate::backbone::FamilyEvent),
/// [`CycleFamily`](crate::backbone::CycleFamily)). Closures
/// `FnMut(&E, &T) -> Control` are observers, and so is `()` (it never stops).
pub trait Observer<E = Event, T: ?Sized = Trace> {
    /// See one event; `traced` holds everything traced so far.
    fn observe(&mut self, event: &E, traced: &T) -> Control;
}

impl<E, T: ?Sized, F: FnMut(&E, &T) -> Control> Observer<E, T> for F {
    fn observe(&mut self, event: &E, traced: &T) -> Control {
        self(event, traced)
    }
}

impl<E, T: ?Sized> Observer<E, T> for () {
    fn observe(&mut self, _: &E, _: &T) -> Control {
        Control::Continue
    }
}

/// Everything traced so far, in arc-length order (the [`Curve`](crate::results::Curve) without its jumps,
/// which need the whole curve).
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// Number of harmonics N.
    pub harmonics: usize,
    /// The continuation parameter.
    pub parameter: Parameter,
    /// Output names, in model order.
    pub output_names: Vec<String>,
    /// Accepted points.
    pub points: Vec<CurvePoint>,
    /// Located folds.
    pub folds: Vec<Fold>,
    /// Changes of stability that are not folds.
    pub bifurcations: Vec<Bifurcation>,
    /// Located local maxima of the outputs' `max_abs`.
    pub peaks: Vec<Peak>,
    /// Ended segments.
    pub segments: Vec<Segment>,
    /// Counters so far.
    pub stats: CurveStats,
}

impl Trace {
    /// Bring `copy`, an earlier clone of this trace, up to date by copying only what
    /// was added since: a continuation only appends to a trace, so an observer keeps a
    /// current copy (for a run it may have to abandon) at the cost of the new entries.
    pub fn update(&self, copy: &mut Trace) {
        fn tail<T: Clone>(from: &[T], to: &mut Vec<T>) {
            if to.len() > from.len() {
                to.clear(); // not an earlier copy of this trace after all
            }
            to.extend_from_slice(&from[to.len()..]);
        }
        copy.harmonics = self.harmonics;
        if copy.parameter != self.parameter {
            copy.parameter = self.parameter.clone();
        }
        if copy.output_names != self.output_names {
            copy.output_names = self.output_names.clone();
        }
        tail(&self.points, &mut copy.points);
        tail(&self.folds, &mut copy.folds);
        tail(&self.bifurcations, &mut copy.bifurcations);
        tail(&self.peaks, &mut copy.peaks);
        tail(&self.segments, &mut copy.segments);
        copy.stats = self.stats;
    }

    /// The curve as far as this trace goes, for a run abandoned between two events
    /// (an interrupted study keeps the copy an observer took at the last event): a
    /// segment still being traced ends [`End::Stopped`], and the jumps are
    /// those the points show, their landings not refined (what
    /// [`Continuation::finish`](super::Continuation::finish) adds).
    pub fn into_stopped_curve(mut self, model: &str, stability_checked: bool) -> Curve {
        let open = self.segments.len();
        let lambda = |p: &CurvePoint| match self.parameter {
            Parameter::Omega => p.omega,
            Parameter::Model { .. } => p.param,
        };
        let mut on = self.points.iter().filter(|p| p.segment == open);
        if let Some(first) = on.next() {
            let from = lambda(first);
            let to = on.next_back().map_or(from, lambda);
            self.segments.push(Segment { from, to, ended: End::Stopped });
        }
        self.stats.folds = self.folds.len();
        self.stats.folds_unlocated = self.folds.iter().filter(|f| !f.located).count();
        let (jumps, _) = super::jumps::find_landings(&self.points, &self.folds, &self.output_names);
        self.into_curve(model, stability_checked, jumps)
    }

    /// The curve with these jumps.
    pub(super) fn into_curve(
        self,
        model: &str,
        stability_checked: bool,
        jumps: Vec<Jump>,
    ) -> Curve {
        Curve {
            model: model.to_string(),
            harmonics: self.harmonics,
            parameter: self.parameter,
            output_names: self.output_names,
            points: self.points,
            stability_checked,
            folds: self.folds,
            jumps,
            peaks: self.peaks,
            segments: self.segments,
            stats: self.stats,
            bifurcations: self.bifurcations,
            convergence: None,
        }
    }
}
