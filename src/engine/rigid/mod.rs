//! The rigid-impact N-mode model (§3, eqs 10–11): exact free flight between impacts
//! ([`crate::engine::sim::Simulator::free_flight`], certified contact detection), and at
//! φ(1)ᵀη = d₀ with approaching tip velocity the modal law η̇⁺ = −\[R\]η̇⁻ of any of the three
//! restitution laws ([`crate::model::restitution`]).
//!
//! **Chattering policy** (impacts accumulating in finite time; never an endless loop):
//! - an impact whose incoming tip velocity is below `v_stick` (relative to the velocity
//!   scale of the run, and at least to ωA_free, the forcing's, so that a restarted run
//!   judges it alike), or a run of three impacts whose intervals shrink geometrically
//!   (ratio ρ < 1, consistent within 10%) with the last interval and the time left to the
//!   accumulation both below 1e-6 T, is a chatter;
//! - its accumulation time is extrapolated geometrically, t_∞ = t_n + Δ_n ρ/(1 − ρ);
//! - the model moves to t_∞, puts the tip on the stop with zero tip velocity, and
//!   **sticks** there while the contact force pushes (the exact constrained flow of the
//!   other N − 1 directions, [`sticking`]); it is released at the certified time the force
//!   would turn to pulling, and flies on;
//! - that limit of infinitely many impacts exists only for a law that leaves the velocity
//!   orthogonal to φ(1) unchanged (Newton's law at the tip, \[R\]_IR; any law for N = 1).
//!   Under another law (\[R\]_N, \[R\]_C with N > 1) the run **stops** at t_∞ with
//!   [`Outcome::Chatter`];
//! - a hard cap of `max_impacts` impacts between sticking phases, and of 10 000 in one
//!   forcing period, ends it with [`Outcome::ImpactLimit`].

mod jacobian;
mod run;
pub mod sticking;

use crate::engine::sim::monodromy::flow_jacobian;
use crate::engine::sim::{check_state, Clock, Simulator, Stats};
use crate::error::ParameterError;
use crate::model::galerkin::{GalerkinModel, Region};
use nalgebra::{DMatrix, DVector};
pub use run::{Outcome, RigidEvent, RigidObserver, RigidRun, RigidSettings};
use std::sync::OnceLock;
pub use sticking::Sticking;

/// The rigid-impact model: the free flow of `sim` and the modal law `law` (\[R\]).
#[derive(Clone)]
pub struct RigidImpact {
    /// The simulator whose free flow is used (its contact flow is not).
    pub sim: Simulator,
    /// \[R\].
    pub law: DMatrix<f64>,
    /// The chattering policy.
    pub settings: RigidSettings,
    /// The constrained flow of a sticking phase, built on first use.
    sticking: OnceLock<Sticking>,
    /// ωA_free, the forcing's tip velocity scale (0 unforced): the least velocity scale a
    /// chatter is judged on.
    velocity_floor: f64,
}

impl RigidImpact {
    /// Builds the model; `law` must be N × N with finite entries.
    ///
    /// # Errors
    /// [`ParameterError`] for a `law` that is not N × N or has an entry that is not finite.
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
        let velocity_floor = sim.model().free_tip_amplitude().1;
        Ok(Self {
            sim,
            law,
            settings: RigidSettings::default(),
            sticking: OnceLock::new(),
            velocity_floor,
        })
    }

    /// The generic impact oscillator ẍ + cẋ + kx = F cos ωt, stop at gx = d₀, with
    /// Newton's law of restitution r ([`crate::model::galerkin::GalerkinModel::oscillator`]).
    ///
    /// # Errors
    /// [`crate::error::Error::Parameter`] for a bad oscillator or r outside [0, 1];
    /// [`crate::error::Error::Flow`] when a region's flow cannot be built.
    pub fn oscillator(
        o: &crate::model::galerkin::Oscillator,
        r: f64,
    ) -> Result<Self, crate::error::Error> {
        let sim = Simulator::new(crate::model::galerkin::GalerkinModel::oscillator(o)?)?;
        Ok(Self::new(
            sim,
            crate::model::restitution::impulse_response(1, r)?,
        )?)
    }

    /// The sticking phase's constrained flow.
    pub fn sticking(&self) -> &Sticking {
        self.sticking
            .get_or_init(|| Sticking::new(self.sim.model()))
    }

    /// Whether the law leaves every velocity orthogonal to φ(1) unchanged (−\[R\]v = v for
    /// φ(1)ᵀv = 0, to round-off): then a chatter's limit is the constrained state, and the
    /// model can stick.
    pub fn can_stick(&self) -> bool {
        let n = self.sim.model().modes();
        let phi = self.sim.model().tip();
        let projector = DMatrix::identity(n, n) - phi * phi.transpose() / phi.norm_squared();
        let defect = (-&self.law - DMatrix::identity(n, n)) * projector;
        defect.amax() <= 1e-12 * (1.0 + self.law.amax())
    }

    /// The free-flight state s after x at `clock`, ignoring the stop (exact).
    pub fn coast(&self, x: &DVector<f64>, clock: &Clock, s: f64) -> DVector<f64> {
        let flow = self.sim.flow(Region::Free);
        let phase = self.sim.omega() * clock.offset;
        flow.state(&flow.modal(x, phase), phase, s)
    }

    /// The sticking phase's state s after x (on the stop) at `clock` (exact, while the stop
    /// pushes).
    pub fn held(&self, x: &DVector<f64>, clock: &Clock, s: f64) -> DVector<f64> {
        self.sticking().state(x, self.sim.omega() * clock.offset, s)
    }

    fn tip_velocity(&self, x: &DVector<f64>) -> f64 {
        let n = self.sim.model().modes();
        self.sim.model().tip().dot(&x.rows(n, n))
    }

    /// Runs from x0 at t = 0 until t_end.
    ///
    /// # Errors
    /// [`crate::error::Error::Parameter`] for a t_end that is not a finite number ≥ 0, or a
    /// state of the wrong length, not finite or beyond the stop;
    /// [`crate::error::Error::Invariant`] when a free flight passes through the stop.
    pub fn run(&self, x0: &DVector<f64>, t_end: f64) -> Result<RigidRun, crate::error::Error> {
        crate::error::finite_non_negative("end time t_end", t_end)?;
        let period = self.sim.period();
        self.run_until(
            x0,
            Clock::at_cycle(period, 0),
            Clock::at_time(period, t_end),
        )
    }

    /// Runs from x0 at `start` (any time and forcing phase) until the clock reads `end`
    /// (nothing happens if `end` is not after `start`).
    ///
    /// # Errors
    /// [`crate::error::Error::Parameter`] for a state of the wrong length, not finite or
    /// beyond the stop, or a clock that does not read a finite time;
    /// [`crate::error::Error::Invariant`] when a free flight passes through the stop.
    pub fn run_until(
        &self,
        x0: &DVector<f64>,
        start: Clock,
        end: Clock,
    ) -> Result<RigidRun, crate::error::Error> {
        self.run_observed(x0, start, end, &mut ())
    }

    /// [`Self::run_until`], reporting the pieces of the motion to `observer` (which changes
    /// nothing of the run).
    ///
    /// # Errors
    /// As [`Self::run_until`]; [`crate::error::Error::Interrupted`] when the observer asks
    /// the run to stop.
    pub fn run_observed(
        &self,
        x0: &DVector<f64>,
        start: Clock,
        end: Clock,
        observer: &mut dyn RigidObserver,
    ) -> Result<RigidRun, crate::error::Error> {
        check_state(x0, 2 * self.sim.model().modes(), "the rigid-impact model")?;
        check_clock("start clock", &start)?;
        check_clock("end clock", &end)?;
        self.check_not_beyond(x0)?;
        self.run_core(x0, start, end, None, observer)
    }

    /// The run, accumulating the Jacobian of the state at the end with respect to x0 in
    /// `jacobian` when given (valid while no chatter or sticking occurs).
    fn run_core(
        &self,
        x0: &DVector<f64>,
        start: Clock,
        end: Clock,
        mut jacobian: Option<&mut DMatrix<f64>>,
        observer: &mut dyn RigidObserver,
    ) -> Result<RigidRun, crate::error::Error> {
        let n = self.sim.model().modes();
        let period = self.sim.period();
        let mut clock = start;
        let mut x = x0.clone();
        let mut stats = Stats::default();
        let mut events = Vec::new();
        let mut impacts: Vec<(f64, f64)> = Vec::new();
        let mut v_scale = self.tip_velocity(&x).abs();
        // impacts since the start of the current forcing period
        let (mut counted_cycle, mut in_cycle) = (clock.cycles, 0u64);
        let mut outcome = Outcome::Completed;
        // a start resting on the stop while the stop pushes (a run that ended stuck,
        // restarted at a period boundary, a chunk or from a saved state) is still stuck:
        // sticking survives any restart
        let mut stuck = false;
        if self.at_rest_on_stop(&x) {
            let on = self.sticking().project(&x);
            if self.sticking().push(&on, self.sim.omega() * clock.offset) > 0.0 {
                if !self.can_stick() {
                    // the limit of this law's chatter is not a sticking phase: stop, as a
                    // chatter found in flight does
                    events.push(RigidEvent::Chatter {
                        time: clock.time(),
                        accumulation: clock.time(),
                    });
                    return Ok(RigidRun {
                        events,
                        time: clock.time(),
                        clock,
                        state: x,
                        outcome: Outcome::Chatter(clock.time()),
                        stats,
                    });
                }
                x = on;
                stuck = true;
            }
        }
        while clock.before(&end) {
            if observer.interrupted() {
                return Err(crate::error::Error::Interrupted);
            }
            if std::mem::take(&mut stuck) {
                if self.hold_from(&mut x, &mut clock, &end, &mut events, &mut stats, observer) {
                    impacts.clear();
                    v_scale = 0.0;
                    continue;
                }
                break;
            }
            // to the end of this period, or to `end` within it
            let (horizon, last) = if clock.cycles < end.cycles {
                (period - clock.offset, false)
            } else {
                (end.offset - clock.offset, true)
            };
            let (crossing, state) = self.sim.free_flight(&x, &clock, horizon, &mut stats);
            observer.flight(self, &clock, &x, crossing.unwrap_or(horizon));
            if let Some(j) = jacobian.as_deref_mut() {
                let flown = crossing.unwrap_or(horizon);
                let phase = self.sim.omega() * clock.offset;
                *j = flow_jacobian(self.sim.flow(Region::Free), phase, flown) * &*j;
            }
            x = state;
            let Some(s) = crossing else {
                // a flight that ends beyond the stop passed through it: no result
                if let Some(beyond) = self.sim.model().beyond_the_stop(&x) {
                    return Err(crate::error::Error::Invariant(format!(
                        "the tip passed the rigid stop by {beyond:e} in a free flight ending at \
                         t = {:.17e}",
                        clock.time() + horizon
                    )));
                }
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
            let x_before = x.clone();
            x.rows_mut(n, n).copy_from(&post);
            if let Some(j) = jacobian.as_deref_mut() {
                *j = self.saltation(&x_before, &x, t) * &*j;
            }
            let outgoing = self.tip_velocity(&x);
            events.push(RigidEvent::Impact {
                time: t,
                incoming,
                outgoing,
                before,
                after: post.iter().cloned().collect(),
            });
            impacts.push((t, incoming));
            if clock.cycles != counted_cycle {
                (counted_cycle, in_cycle) = (clock.cycles, 0);
            }
            in_cycle += 1;
            if impacts.len() > self.settings.max_impacts
                || in_cycle > self.settings.max_impacts_per_period
            {
                outcome = Outcome::ImpactLimit;
                break;
            }
            // the run's own speeds, but never below the forcing's (ωA_free): a run restarted
            // in the middle of a chatter judges its impacts as the whole run would
            let scale = v_scale.max(self.velocity_floor);
            if let Some(t_inf) = self.chatter(&impacts, incoming, scale, period) {
                events.push(RigidEvent::Chatter {
                    time: t,
                    accumulation: t_inf,
                });
                if !self.can_stick() {
                    outcome = Outcome::Chatter(t_inf);
                    clock.advance((t_inf - t).max(0.0));
                    break;
                }
                // to the accumulation point (the remaining impacts only remove the tip
                // velocity), onto the stop, and held while the stop has to push
                let dt = (t_inf - t).max(0.0).min(end.time() - t);
                observer.flight(self, &clock, &x, dt);
                x = self.sticking().project(&self.coast(&x, &clock, dt));
                clock.advance(dt);
                if !clock.before(&end) {
                    break;
                }
                let phase = self.sim.omega() * clock.offset;
                if self.sticking().push(&x, phase) <= 0.0 {
                    // the free motion already pulls away: it flies off at once
                    impacts.clear();
                    continue;
                }
                if self.hold_from(&mut x, &mut clock, &end, &mut events, &mut stats, observer) {
                    impacts.clear();
                    // the next flight's speeds are measured afresh
                    v_scale = 0.0;
                } else {
                    break;
                }
            } else if self.cannot_leave(&x, &clock) {
                // A (nearly) plastic impact at the tip: the tip leaves the stop by less than
                // 1e-14 of its length scale before the push brings it back — below what the
                // search can tell from the surface, where it finds no certain crossing (the
                // next "impact" was found deeper each time, the penetration doubling). It
                // rests on the stop: it sticks while the stop pushes, as after a chatter,
                // or, under a law with no sticking limit, the run stops there.
                if !self.can_stick() {
                    events.push(RigidEvent::Chatter {
                        time: t,
                        accumulation: t,
                    });
                    outcome = Outcome::Chatter(t);
                    break;
                }
                x = self.sticking().project(&x);
                if self.hold_from(&mut x, &mut clock, &end, &mut events, &mut stats, observer) {
                    impacts.clear();
                    v_scale = 0.0;
                } else {
                    break;
                }
            }
        }
        Ok(RigidRun {
            events,
            time: clock.time(),
            clock,
            state: x,
            outcome,
            stats,
        })
    }

    /// Holds x (on the stop) in the sticking phase from `clock` until the stop would pull
    /// or `end`; true if it was released before `end` (x and the clock are then at the
    /// release), false if it is still stuck at `end`.
    fn hold_from(
        &self,
        x: &mut DVector<f64>,
        clock: &mut Clock,
        end: &Clock,
        events: &mut Vec<RigidEvent>,
        stats: &mut Stats,
        observer: &mut dyn RigidObserver,
    ) -> bool {
        events.push(RigidEvent::StickStart { time: clock.time() });
        let span = end.time() - clock.time();
        let (release, state) = self.sticking().hold(
            x,
            clock,
            span,
            self.sim.h_min(),
            self.sim.settings().root_tolerance,
            stats,
        );
        // to `end` in the form the dense grid measures offsets in, so that a grid point at
        // `end` is excluded exactly (end.time() − clock.time() rounds otherwise)
        let to_end = (end.cycles - clock.cycles) as f64 * clock.period + end.offset - clock.offset;
        observer.held(self, clock, x, release.unwrap_or(to_end));
        *x = state;
        match release {
            Some(s) => {
                clock.advance(s);
                events.push(RigidEvent::StickEnd { time: clock.time() });
                true
            }
            None => {
                *clock = *end;
                false
            }
        }
    }

    /// How far beyond the stop the tip is (φ(1)ᵀη − d₀), and the scales a distance and a
    /// speed of this state are judged on: the length scale
    /// ([`GalerkinModel::length_scale`]: |d₀| + |φ(1)|·‖η‖∞, at least A_free) and
    /// |φ(1)|·‖η̇‖∞ + ω times the first.
    fn stop_measures(&self, x: &DVector<f64>) -> (f64, f64, f64, f64) {
        let model = self.sim.model();
        let n = model.modes();
        let phi = model.tip();
        let g = model.gap_of(x.rows(0, n));
        let v = phi.dot(&x.rows(n, n));
        let length = model.length_scale(x.rows(0, n));
        let speed = phi.amax() * x.rows(n, n).amax() + self.sim.omega() * length;
        (g, v, length, speed)
    }

    /// A rigid stop cannot be penetrated: a state with the tip beyond it (by more than
    /// 1e-9 of its scale) is not a state of the model.
    fn check_not_beyond(&self, x: &DVector<f64>) -> Result<(), ParameterError> {
        if let Some(g) = beyond_the_stop(self.sim.model(), x) {
            return Err(ParameterError::new(
                "initial state",
                format!("a tip {} beyond the rigid stop", crate::error::number(g)),
                "a tip at or before the stop d₀ (a rigid stop cannot be penetrated; a \
                 preloaded stop, d₀ < 0 from rest, is the compliant model's)",
            ));
        }
        Ok(())
    }

    /// Whether the tip rests on the stop: on it and still, to 1e-9 of the state's own
    /// scales (closer than that, a free state would reach the stop at once and chatter to
    /// the same sticking phase).
    pub fn at_rest_on_stop(&self, x: &DVector<f64>) -> bool {
        let (g, v, length, speed) = self.stop_measures(x);
        g.abs() <= 1e-9 * length && v.abs() <= 1e-9 * speed
    }

    /// Whether a tip just off an impact cannot leave the stop: on it, pressed into it (the
    /// stop would have to push, |φ|²λ = a > 0) and moving out at a speed v so small that
    /// its excursion v²/2a stays within 1e-14 of the length scale — inside the band of
    /// round-off where the search cannot tell the tip from the surface — or at rest. (A
    /// chatter whose flights can be resolved is found first by its geometric sequence, at
    /// excursions of ~1e-12 of the scale: this catches the laws that remove nearly all the
    /// tip's speed at once, r ≲ 1e-2, before they give the four impacts it needs.)
    fn cannot_leave(&self, x: &DVector<f64>, clock: &Clock) -> bool {
        let (g, v, length, _) = self.stop_measures(x);
        if g.abs() > 1e-9 * length {
            return false;
        }
        let on = self.sticking().project(x);
        let push = self.sticking().push(&on, self.sim.omega() * clock.offset);
        push > 0.0 && (self.at_rest_on_stop(x) || (v <= 0.0 && v * v <= 2e-14 * length * push))
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
        // The rest of the sequence is crossed in free flight ignoring the stop, which the
        // tip passes by about a·τ²/2 over the time τ left: τ is held to 1e-6 T too, so that
        // overshoot stays ~2e-11 of the motion. (An elastic bounce on a stop the forcing
        // presses against repeats at a nearly constant interval, ρ → 1: that is no
        // accumulation, and its extrapolation, 5e4 intervals, left the tip 2e-4 beyond the
        // stop before it was put back.)
        let rest = d[2] * r2 / (1.0 - r2);
        (geometric && d[2] < 1e-6 * period && rest < 1e-6 * period).then_some(t_n + rest)
    }
}

/// A clock must read a finite time: a NaN or infinite end would run "to" nowhere.
fn check_clock(what: &str, c: &Clock) -> Result<(), ParameterError> {
    if c.time().is_finite() && c.offset.is_finite() && c.period.is_finite() && c.period > 0.0 {
        Ok(())
    } else {
        Err(ParameterError::new(
            what,
            crate::error::number(c.time()),
            "a clock at a finite time with a finite, positive period",
        ))
    }
}

/// How far beyond a rigid stop state x = [η; η̇] puts the tip
/// ([`GalerkinModel::beyond_the_stop`]).
pub fn beyond_the_stop(model: &GalerkinModel, x: &DVector<f64>) -> Option<f64> {
    model.beyond_the_stop(x)
}
