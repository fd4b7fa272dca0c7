//! What a rigid-impact run reports: its events ([`RigidEvent`]), how it ended ([`Outcome`]),
//! the chattering policy's settings, the observer of its flights and sticking phases, and
//! the run itself ([`RigidRun`]).

use super::RigidImpact;
use crate::engine::sim::{Clock, Stats};
use nalgebra::DVector;
use serde::Serialize;

/// One rigid-impact event.
#[derive(Debug, Clone, Serialize)]
pub enum RigidEvent {
    /// An impact: time, incoming and outgoing tip velocity φ(1)ᵀη̇, and the modal
    /// velocities η̇⁻ and η̇⁺ = −\[R\]η̇⁻.
    Impact {
        /// t, the time of the event (non-dimensional beam time).
        time: f64,
        /// Tip velocity before (> 0, approaching).
        incoming: f64,
        /// Tip velocity after.
        outgoing: f64,
        /// Modal velocities before.
        before: Vec<f64>,
        /// Modal velocities after.
        after: Vec<f64>,
    },
    /// Chattering detected: impacts accumulate at `accumulation`.
    Chatter {
        /// t of the last resolved impact.
        time: f64,
        /// The extrapolated accumulation time.
        accumulation: f64,
    },
    /// The tip is held at the stop from `time` (after a chatter).
    StickStart {
        /// t, the time of the event (non-dimensional beam time).
        time: f64,
    },
    /// The contact force reaches zero at `time` and the tip flies off.
    StickEnd {
        /// t, the time of the event (non-dimensional beam time).
        time: f64,
    },
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Outcome {
    /// Reached the requested end.
    Completed,
    /// Chattering under a law whose limit does not leave the tangential velocity alone
    /// (N > 1 with \[R\]_N or \[R\]_C): stopped at the accumulation time.
    Chatter(f64),
    /// More than `max_impacts` impacts since the last sticking phase, or more than
    /// `max_impacts_per_period` in one forcing period.
    ImpactLimit,
}

/// Settings of the chattering policy.
#[derive(Debug, Clone, Copy)]
pub struct RigidSettings {
    /// Incoming tip velocity below which an impact counts as chatter, relative to the
    /// largest tip velocity seen in the run.
    pub v_stick: f64,
    /// Hard cap on impacts between two sticking phases.
    pub max_impacts: usize,
    /// Hard cap on impacts in one forcing period: a tip that bounces on the stop without
    /// accumulating (an elastic law with the forcing pressing the tip on the stop repeats
    /// bounces of 1e-6 T for the rest of the press, ~1e6 a period) is stopped with the
    /// reason instead of run for minutes, as the compliant model's contact cap does.
    pub max_impacts_per_period: u64,
}

impl Default for RigidSettings {
    fn default() -> Self {
        Self {
            v_stick: 1e-9,
            max_impacts: 1_000_000,
            max_impacts_per_period: 10_000,
        }
    }
}

/// What a rigid-impact run reports to, besides its events: the exact pieces of the motion,
/// so that samples are taken inside them (observing never restarts the run, and so never
/// changes it). Every method has an empty default.
pub trait RigidObserver {
    /// Free flight from state x at `start` for `duration` (the state at s ∈ [0, duration)
    /// is [`RigidImpact::coast`]`(x, start, s)`; an impact, if any, ends it).
    fn flight(&mut self, _model: &RigidImpact, _start: &Clock, _x: &DVector<f64>, _duration: f64) {}
    /// A sticking phase from x (on the stop) at `start` for `duration` (the state at s is
    /// [`RigidImpact::held`]`(x, start, s)`).
    fn held(&mut self, _model: &RigidImpact, _start: &Clock, _x: &DVector<f64>, _duration: f64) {}
    /// Whether the run should stop now (polled before each flight): the run then ends with
    /// [`crate::error::Error::Interrupted`].
    fn interrupted(&self) -> bool {
        false
    }
}

impl RigidObserver for () {}

impl<O: RigidObserver + ?Sized> RigidObserver for &mut O {
    fn flight(&mut self, model: &RigidImpact, start: &Clock, x: &DVector<f64>, duration: f64) {
        (**self).flight(model, start, x, duration)
    }
    fn held(&mut self, model: &RigidImpact, start: &Clock, x: &DVector<f64>, duration: f64) {
        (**self).held(model, start, x, duration)
    }
    fn interrupted(&self) -> bool {
        (**self).interrupted()
    }
}

/// A rigid-impact run.
#[derive(Debug, Clone)]
pub struct RigidRun {
    /// Events in order.
    pub events: Vec<RigidEvent>,
    /// The state at the end.
    pub state: DVector<f64>,
    /// The time at the end.
    pub time: f64,
    /// The clock at the end (for chaining runs).
    pub clock: Clock,
    /// How it ended.
    pub outcome: Outcome,
    /// Work counters of the free flights.
    pub stats: Stats,
}

impl RigidRun {
    /// The impacts in order, as (t, incoming tip velocity, outgoing tip velocity).
    pub fn impacts(&self) -> Vec<(f64, f64, f64)> {
        self.events
            .iter()
            .filter_map(|e| match e {
                RigidEvent::Impact {
                    time,
                    incoming,
                    outgoing,
                    ..
                } => Some((*time, *incoming, *outgoing)),
                _ => None,
            })
            .collect()
    }
}
