//! Progress of a run in whole forcing periods, and the caller's cancellation passed to it:
//! an observer of the compliant run ([`Observer`]) and of the rigid-impact run
//! ([`RigidObserver`]) that asks for nothing else, so it changes nothing of the run (the
//! state it ends in is the unobserved run's, bit for bit).

use crate::base::progress::{Progress, Task};
use crate::engine::rigid::{RigidImpact, RigidObserver};
use crate::engine::sim::{Clock, Observer, SegmentView, Simulator, Stats};
use nalgebra::DVector;

/// Reports whole periods as the run passes them to `task`, and stops the run (with
/// [`crate::error::Error::Interrupted`]) when `progress` is cancelled.
pub struct Ticker<'a> {
    task: &'a dyn Task,
    progress: &'a dyn Progress,
    /// The last whole period reported, as the clock counts cycles.
    done: i64,
}

impl<'a> Ticker<'a> {
    /// A ticker for a run that starts at cycle `start`.
    pub fn new(task: &'a dyn Task, progress: &'a dyn Progress, start: i64) -> Self {
        Ticker {
            task,
            progress,
            done: start,
        }
    }

    /// The run has reached cycle `now`: the periods completed since the last report.
    pub fn tick(&mut self, now: i64) {
        if now > self.done {
            self.task.advance((now - self.done) as u64);
            self.done = now;
        }
    }

    fn tick_after(&mut self, start: &Clock, duration: f64) {
        let mut at = *start;
        at.advance(duration);
        self.tick(at.cycles);
    }
}

impl Observer for Ticker<'_> {
    fn begin(&mut self, _: &Simulator, clock: &Clock, _: &DVector<f64>) {
        self.done = clock.cycles;
    }
    fn segment(&mut self, seg: &SegmentView) {
        self.tick_after(&seg.start, seg.end);
    }
    fn end(&mut self, _: &Simulator, clock: &Clock, _: &DVector<f64>, _: &Stats) {
        // where the run ends, exactly (a segment's end may round to just before it)
        self.tick(clock.cycles);
    }
    fn interrupted(&self) -> bool {
        self.progress.cancelled()
    }
}

impl RigidObserver for Ticker<'_> {
    fn flight(&mut self, _: &RigidImpact, start: &Clock, _: &DVector<f64>, duration: f64) {
        self.tick_after(start, duration);
    }
    fn held(&mut self, _: &RigidImpact, start: &Clock, _: &DVector<f64>, duration: f64) {
        self.tick_after(start, duration);
    }
    fn interrupted(&self) -> bool {
        self.progress.cancelled()
    }
}
