//! The rigid-impact N-mode model (§3, eqs 10–11): exact free flight between impacts
//! ([`crate::sim::Simulator::free_flight`], certified contact detection), and at
//! φ(1)ᵀη = d₀ with approaching tip velocity the modal law η̇⁺ = −\[R\]η̇⁻ of any of the three
//! restitution laws ([`crate::restitution`]).
//!
//! **Chattering policy** (impacts accumulating in finite time; never an endless loop):
//! - an impact whose incoming tip velocity is below `v_stick` (relative to the velocity
//!   scale of the run), or a run of three impacts whose intervals shrink geometrically
//!   (ratio ρ < 1, consistent within 10%) with the last interval below 1e-6 T, is a chatter;
//! - its accumulation time is extrapolated geometrically, t_∞ = t_n + Δ_n ρ/(1 − ρ);
//! - N = 1: the model jumps to t_∞ and **sticks** (tip held at d₀, η̇ = 0) while the
//!   free-flight acceleration pushes into the stop; it is released, in closed form, when the
//!   forcing pulls the tip away;
//! - N > 1: sticking would need the constrained (N − 1)-mode dynamics, which this module does
//!   not implement: the run **stops** at t_∞ with [`Outcome::Chatter`].
//! - A hard cap of `max_impacts` impacts per run ends it with [`Outcome::ImpactLimit`].

use crate::error::ParameterError;
use crate::sim::{Clock, Simulator, Stats};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// One rigid-impact event.
#[derive(Debug, Clone, Serialize)]
pub enum RigidEvent {
    /// An impact: time, incoming and outgoing tip velocity φ(1)ᵀη̇, and the modal
    /// velocities η̇⁻ and η̇⁺ = −\[R\]η̇⁻.
    Impact {
        /// t.
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
    /// N = 1: the tip is held at the stop from `time`.
    StickStart {
        /// t.
        time: f64,
    },
    /// N = 1: the forcing releases the tip at `time`.
    StickEnd {
        /// t.
        time: f64,
    },
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Outcome {
    /// Reached the requested end.
    Completed,
    /// N > 1 chattering: stopped at the accumulation time.
    Chatter(f64),
    /// More than `max_impacts` impacts.
    ImpactLimit,
}

/// Settings of the chattering policy.
#[derive(Debug, Clone, Copy)]
pub struct RigidSettings {
    /// Incoming tip velocity below which an impact counts as chatter, relative to the
    /// largest tip velocity seen in the run.
    pub v_stick: f64,
    /// Hard cap on impacts per run.
    pub max_impacts: usize,
}

impl Default for RigidSettings {
    fn default() -> Self {
        Self {
            v_stick: 1e-9,
            max_impacts: 1_000_000,
        }
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

/// The rigid-impact model: the free flow of `sim` and the modal law `law` (\[R\]).
pub struct RigidImpact {
    /// The simulator whose free flow is used (its contact flow is not).
    pub sim: Simulator,
    /// \[R\].
    pub law: DMatrix<f64>,
    /// The chattering policy.
    pub settings: RigidSettings,
}

impl RigidImpact {
    /// Builds the model; `law` must be N × N with finite entries.
    pub fn new(sim: Simulator, law: DMatrix<f64>) -> Result<Self, ParameterError> {
        let n = sim.model().modes();
        if law.nrows() != n || law.ncols() != n {
            return Err(ParameterError::new(
                "restitution law [R]",
                format!("{} × {}", law.nrows(), law.ncols()),
                &format!("an N × N matrix, N = {n}"),
            ));
        }
        if law.iter().any(|r| !r.is_finite()) {
            return Err(ParameterError::new(
                "restitution law [R]",
                "a non-finite entry",
                "finite entries",
            ));
        }
        Ok(Self {
            sim,
            law,
            settings: RigidSettings::default(),
        })
    }

    fn tip_velocity(&self, x: &DVector<f64>) -> f64 {
        let n = self.sim.model().modes();
        self.sim.model().tip().dot(&x.rows(n, n))
    }

    /// Runs from x0 at t = 0 until t_end.
    pub fn run(&self, x0: &DVector<f64>, t_end: f64) -> RigidRun {
        let period = self.sim.period();
        self.run_until(
            x0,
            Clock::at_cycle(period, 0),
            Clock::at_time(period, t_end),
        )
    }

    /// Runs from x0 at `start` (any time and forcing phase) until the clock reads `end`.
    pub fn run_until(&self, x0: &DVector<f64>, start: Clock, end: Clock) -> RigidRun {
        let n = self.sim.model().modes();
        let period = self.sim.period();
        let t_end = end.time();
        let mut clock = start;
        let mut x = x0.clone();
        let mut stats = Stats::default();
        let mut events = Vec::new();
        let mut impacts: Vec<(f64, f64)> = Vec::new();
        let mut v_scale = self.tip_velocity(&x).abs();
        let mut outcome = Outcome::Completed;
        while clock.before(&end) {
            // to the end of this period, or to `end` within it
            let (horizon, last) = if clock.cycles < end.cycles {
                (period - clock.offset, false)
            } else {
                (end.offset - clock.offset, true)
            };
            let (crossing, state) = self.sim.free_flight(&x, &clock, horizon, &mut stats);
            x = state;
            let Some(s) = crossing else {
                if last {
                    clock = end;
                } else {
                    clock = Clock::at_cycle(period, clock.cycles + 1);
                }
                continue;
            };
            clock.advance(s);
            let t = clock.time();
            let incoming = self.tip_velocity(&x);
            v_scale = v_scale.max(incoming.abs());
            // the law acts on the modal velocities; the displacement is continuous
            let before: Vec<f64> = x.rows(n, n).iter().cloned().collect();
            let post = -(&self.law * x.rows(n, n));
            x.rows_mut(n, n).copy_from(&post);
            let outgoing = self.tip_velocity(&x);
            events.push(RigidEvent::Impact {
                time: t,
                incoming,
                outgoing,
                before,
                after: post.iter().cloned().collect(),
            });
            impacts.push((t, incoming));
            if impacts.len() > self.settings.max_impacts {
                outcome = Outcome::ImpactLimit;
                break;
            }
            if let Some(t_inf) = self.chatter(&impacts, incoming, v_scale, period) {
                events.push(RigidEvent::Chatter {
                    time: t,
                    accumulation: t_inf,
                });
                if n > 1 {
                    outcome = Outcome::Chatter(t_inf);
                    clock.advance((t_inf - t).max(0.0));
                    break;
                }
                // N = 1: stick at the stop from t_∞
                clock.advance((t_inf - t).max(0.0));
                let gap = self.sim.model().params().gap;
                x[0] = gap / self.sim.model().tip()[0];
                x[1] = 0.0;
                events.push(RigidEvent::StickStart { time: clock.time() });
                match self.release_time(&clock) {
                    Some(dt) if clock.time() + dt < t_end => {
                        clock.advance(dt);
                        events.push(RigidEvent::StickEnd { time: clock.time() });
                        impacts.clear();
                    }
                    _ => {
                        clock = end;
                        break;
                    }
                }
            }
        }
        RigidRun {
            events,
            time: clock.time(),
            clock,
            state: x,
            outcome,
            stats,
        }
    }

    /// The accumulation time if the recent impacts chatter.
    fn chatter(
        &self,
        impacts: &[(f64, f64)],
        incoming: f64,
        v_scale: f64,
        period: f64,
    ) -> Option<f64> {
        let (t_n, _) = *impacts.last()?;
        if incoming <= self.settings.v_stick * v_scale {
            return Some(t_n);
        }
        if impacts.len() < 4 {
            return None;
        }
        let k = impacts.len();
        let d: Vec<f64> = (k - 3..k)
            .map(|i| impacts[i].0 - impacts[i - 1].0)
            .collect();
        let (r1, r2) = (d[1] / d[0], d[2] / d[1]);
        let geometric = r1 > 0.0 && r2 > 0.0 && r2 < 1.0 && ((r2 - r1) / r2).abs() < 0.1;
        (geometric && d[2] < 1e-6 * period).then(|| t_n + d[2] * r2 / (1.0 - r2))
    }

    /// N = 1, stuck at the stop: the time until the free-flight tip acceleration,
    /// proportional to a(θ) = f₁ cos θ − k₁η with η = d₀/φ₁(1), turns away from the stop
    /// (None: never). Writing f₁ cos θ = |f₁| cos(θ − φ₀), φ₀ ∈ {0, π}, the release is the
    /// first downward zero θ = φ₀ + arccos(k₁η/|f₁|) + 2πm after the current phase.
    fn release_time(&self, clock: &Clock) -> Option<f64> {
        let m = &self.sim.model();
        let f1 = m.forcing_amplitude()[0];
        let hold = m.modal_stiffness()[0] * m.params().gap / m.tip()[0];
        let omega = self.sim.omega();
        let theta0 = omega * clock.offset;
        let now = f1 * theta0.cos() - hold;
        if now < 0.0 {
            return Some(0.0);
        }
        if omega == 0.0 || -f1.abs() - hold >= 0.0 {
            return None; // pushed into the stop for ever
        }
        let two_pi = 2.0 * std::f64::consts::PI;
        let phi0 = if f1 >= 0.0 { 0.0 } else { std::f64::consts::PI };
        let base = phi0 + (hold / f1.abs()).clamp(-1.0, 1.0).acos();
        let theta = base + two_pi * ((theta0 - base) / two_pi).ceil();
        Some((theta - theta0) / omega)
    }
}
