//! What a running continuation tells the outside: the [`Event`]s of
//! [`Continuation::step`](super::Continuation::step), the [`Trace`] traced so far, and
//! the [`Observer`]s that watch a run and may stop it.

use crate::results::{Bifurcation, CurvePoint, CurveStats, Fold, Parameter, Segment};

/// What one [`Continuation::step`](super::Continuation::step) produced. Indices point into the [`Trace`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A point was accepted: `trace.points[i]`, with its stability.
    Point(usize),
    /// A fold was located: `trace.folds[i]` (reported before the point after it).
    Fold(usize),
    /// A change of stability that is not a fold: `trace.bifurcations[i]`.
    Bifurcation(usize),
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

/// Watches a run: called with every event and the trace so far.
///
/// Closures `FnMut(&Event, &Trace) -> Control` are observers, and so is `()` (it
/// never stops).
pub trait Observer {
    /// See one event; `trace` holds everything traced so far.
    fn observe(&mut self, event: &Event, trace: &Trace) -> Control;
}

impl<F: FnMut(&Event, &Trace) -> Control> Observer for F {
    fn observe(&mut self, event: &Event, trace: &Trace) -> Control {
        self(event, trace)
    }
}

impl Observer for () {
    fn observe(&mut self, _: &Event, _: &Trace) -> Control {
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
    /// Ended segments.
    pub segments: Vec<Segment>,
    /// Counters so far.
    pub stats: CurveStats,
}
