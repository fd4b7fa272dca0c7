//! Exact piecewise-linear simulation of the N-mode bilinear model (§5.1–5.2, eqs 34–36)
//! with certified switching times.
//!
//! Within a region the solution is exact ([`crate::engine::flow`]); the tip gap of each segment is
//! an exponential sum with derivative bounds (`signal`), so the first switch is found by
//! a certified search (`crossing`) and polished to round-off. What a run records is up
//! to its [`Observer`]s ([`observe`]): events, stroboscopic samples, dense output, the exact
//! energy budget ([`energy`]), the certified maximum of the tip ([`maximum`]).
//!
//! The modules, one concept each:
//! - [`clock`]: t = cycles·T + offset, so the forcing phase stays exact over long runs;
//! - `signal`: the segment's tip signal and its derivative bounds;
//! - `crossing`: the certified crossing search;
//! - `segment`: one region's segment of exact flow, and the flight to its first crossing;
//! - [`maximum`]: the certified maximum;
//! - [`energy`]: the exact energy integrals;
//! - [`observe`]: the observer trait and the standard observers;
//! - this module: the driver.
//!
//! A touch with zero normal velocity is recorded as a grazing event and does not switch
//! the region.

pub mod clock;
pub(crate) mod crossing;
pub mod energy;
pub mod maximum;
pub mod monodromy;
pub mod observe;
mod segment;
pub(crate) mod signal;

pub use clock::Clock;
pub use energy::EnergyBudget;
pub use monodromy::Monodromy;
pub use observe::{
    Dense, DenseStates, Energy, Event, EventView, Events, Observer, Sample, SegmentView,
    StateSample, Strobe, TipMax, TipMaximum,
};

use crate::engine::flow::{FlowError, RegionFlow};
use crate::error::Error;
use crate::model::galerkin::{GalerkinModel, Region};
use energy::EnergyTables;
use nalgebra::DVector;
pub use segment::Flight;
use segment::Segment;
use signal::Signal;
use std::sync::OnceLock;

/// A state x = [η; η̇] must have 2N finite entries: a wrong length would fail deep inside
/// the linear algebra, and a NaN would run to a NaN "result".
///
/// # Errors
/// [`Error::Parameter`] for a length other than `dim`, or an entry that is not finite or
/// exceeds 1e100 in magnitude.
pub fn check_state(x: &DVector<f64>, dim: usize, model: &str) -> Result<(), Error> {
    if x.len() != dim {
        return Err(crate::error::ParameterError::new(
            "state [η; η̇]",
            format!("a vector of length {}", x.len()),
            &format!("length {dim} for {model}"),
        )
        .into());
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite() || v.abs() > 1e100) {
        return Err(crate::error::ParameterError::new(
            "state [η; η̇]",
            format!("entry {i} = {}", x[i]),
            "finite entries of magnitude at most 1e100 (the energies, their squares, must not overflow)",
        )
        .into());
    }
    Ok(())
}

/// Shortest certified step, as a fraction of the forcing period.
const H_MIN_FRACTION: f64 = 1e-13;

/// Longest segment without a restart, in forcing periods.
const MAX_SEGMENT_PERIODS: i64 = 16;

/// Most entries into contact in one forcing period. A tip that comes to rest on a very
/// stiff stop goes on bouncing at the contact frequency (√k above the beam's): the
/// compliant model really does make ~10⁵ micro-impacts per period at k = 10¹²k₁ with
/// N = 10, each a segment to locate, which would take minutes per period. Beyond this
/// many (about a second of work) the run stops with the reason and the ways out, instead
/// of running on for hours.
pub const MAX_CONTACTS_PER_PERIOD: u64 = 10_000;

/// Work counters.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Stats {
    /// Region segments propagated.
    pub segments: u64,
    /// Evaluations of the switching function.
    pub evaluations: u64,
    /// Certified advancement steps.
    pub steps: u64,
    /// Of those, steps taken in contact.
    pub contact_steps: u64,
    /// Evaluations spent polishing switching times.
    pub polish_evaluations: u64,
}

/// Simulation settings.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Relative tolerance of the (Halley) polish of a switching time (default 1e-15).
    pub root_tolerance: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            root_tolerance: 1e-15,
        }
    }
}

/// Where a run ended.
#[derive(Debug, Clone)]
pub struct RunEnd {
    /// The state [η; η̇].
    pub state: DVector<f64>,
    /// The time.
    pub clock: Clock,
    /// Work counters.
    pub stats: Stats,
}

/// The simulator: the model and its two exact region flows.
#[derive(Debug, Clone)]
pub struct Simulator {
    model: GalerkinModel,
    free: RegionFlow,
    contact: RegionFlow,
    settings: Settings,
    /// Tables for the exact energy integrals of the − and + regions, built on first use.
    energy_tables: OnceLock<[EnergyTables; 2]>,
    /// The modal maps at a switch into the − and + regions ([`monodromy`]), on first use.
    switch_maps: OnceLock<[nalgebra::DMatrix<f64>; 2]>,
}

impl Simulator {
    /// Builds both region flows.
    ///
    /// # Errors
    /// The [`FlowError`] of either region's [`RegionFlow::new`] (an eigensolver failure, an
    /// unstable or ill-conditioned basis).
    pub fn new(model: GalerkinModel) -> Result<Self, FlowError> {
        let free = RegionFlow::new(&model, Region::Free)?;
        let contact = RegionFlow::new(&model, Region::Contact)?;
        Ok(Self {
            free,
            contact,
            model,
            settings: Settings::default(),
            energy_tables: OnceLock::new(),
            switch_maps: OnceLock::new(),
        })
    }

    /// The same simulator with other settings.
    pub fn with_settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self
    }

    /// The model.
    pub fn model(&self) -> &GalerkinModel {
        &self.model
    }

    /// The settings.
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// The exact flow of a region.
    pub fn flow(&self, region: Region) -> &RegionFlow {
        match region {
            Region::Free => &self.free,
            Region::Contact => &self.contact,
        }
    }

    /// The larger eigenvector condition ‖V‖₁‖V⁻¹‖₁ of the two region flows: the flow is
    /// accurate to about this times ε.
    pub fn condition(&self) -> f64 {
        self.free.condition().max(self.contact.condition())
    }

    /// The forcing frequency ω (0 without forcing).
    pub fn omega(&self) -> f64 {
        self.free.omega()
    }

    /// The forcing period T (1 without forcing).
    pub fn period(&self) -> f64 {
        let omega = self.omega();
        if omega > 0.0 {
            2.0 * std::f64::consts::PI / omega
        } else {
            1.0
        }
    }

    /// The shortest certified step (1e-13 T): the search's resolution.
    pub fn h_min(&self) -> f64 {
        H_MIN_FRACTION * self.period()
    }

    /// The start of cycle `cycles` of this simulator's forcing.
    pub fn clock_at_cycle(&self, cycles: i64) -> Clock {
        Clock::at_cycle(self.period(), cycles)
    }

    pub(crate) fn energy_tables(&self, region: Region) -> &EnergyTables {
        let tables = self.energy_tables.get_or_init(|| {
            [
                EnergyTables::new(&self.free, &self.model),
                EnergyTables::new(&self.contact, &self.model),
            ]
        });
        &tables[usize::from(region == Region::Contact)]
    }

    /// Stored energy: ½|η̇|² + ½ηᵀK⁻η + (k/8)(φ(1)ᵀη − d₀)₊².
    ///
    /// # Errors
    /// [`Error::Parameter`] for a state of the wrong length or not finite.
    pub fn stored_energy(&self, x: &DVector<f64>) -> Result<f64, Error> {
        check_state(x, 2 * self.model.modes(), "the compliant model")?;
        Ok(energy::stored_energy(&self.model, x))
    }

    /// Runs `periods` forcing periods from state x at the start of cycle 0 (t = 0).
    ///
    /// # Errors
    /// As [`Self::run_until`].
    pub fn run(
        &self,
        x0: &DVector<f64>,
        periods: u64,
        observer: &mut dyn Observer,
    ) -> Result<RunEnd, Error> {
        self.run_from(x0, self.clock_at_cycle(0), periods, observer)
    }

    /// Runs from `start` until `periods` whole periods later (ending at a period boundary).
    ///
    /// # Errors
    /// As [`Self::run_until`].
    pub fn run_from(
        &self,
        x0: &DVector<f64>,
        start: Clock,
        periods: u64,
        observer: &mut dyn Observer,
    ) -> Result<RunEnd, Error> {
        let end = Clock::at_cycle(start.period, start.cycles.saturating_add_unsigned(periods));
        self.run_until(x0, start, end, observer)
    }

    /// Runs from `start` until the clock reads `end` (any time, not only a period
    /// boundary); nothing happens if `end` is not after `start`.
    ///
    /// Invariant, checked at every switch: an entry into contact moves into the stop
    /// (ḋ ≥ 0) and an exit away from it (ḋ ≤ 0), beyond the grazing band. A run that breaks
    /// it stops with [`Error::Invariant`] rather than return a wrong trajectory.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a bad `x0`; [`Error::Chatter`] beyond
    /// [`MAX_CONTACTS_PER_PERIOD`] entries in a period; [`Error::Invariant`] as above;
    /// [`Error::Interrupted`] when the observer asks the run to stop.
    pub fn run_until(
        &self,
        x0: &DVector<f64>,
        start: Clock,
        end: Clock,
        observer: &mut dyn Observer,
    ) -> Result<RunEnd, Error> {
        check_state(x0, 2 * self.model.modes(), "the compliant model")?;
        let period = self.period();
        let omega = self.omega();
        let gap = self.model.params().gap;
        let h_min = self.h_min();
        let boundaries = observer.wants_period_boundaries();
        let mut stats = Stats::default();
        let mut clock = start;
        let mut x = x0.clone();
        let mut region = self.model.start_region(&x, clock.offset);
        // entries into contact since the start of the current forcing period
        let (mut counted_cycle, mut contacts) = (clock.cycles, 0u64);
        observer.begin(self, &clock, &x);
        while clock.before(&end) {
            let flow = self.flow(region);
            let seg = Segment::new(flow, &x, omega * clock.offset, gap, self.model.tip());
            stats.segments += 1;
            // Segments end at switches, at the run's end, and after at most
            // MAX_SEGMENT_PERIODS periods, so the forcing phase argument ω·(offset + s)
            // stays below 2π·16 and keeps ~14 digits over any run length. Never where an
            // observer would like them to: observing must not change the run.
            let remaining = end.cycles - clock.cycles;
            let (horizon, to_boundary) = if remaining == 0 {
                (end.offset - clock.offset, false)
            } else {
                let ahead = remaining.min(MAX_SEGMENT_PERIODS);
                (ahead as f64 * period - clock.offset, true)
            };
            let found = seg.next_switch(horizon, h_min, self.settings.root_tolerance, &mut stats);
            let (crossing, touch) = match found {
                Some(crossing::Found::Crossing(s)) => (Some(s), false),
                Some(crossing::Found::Touch(s)) => (Some(s), true),
                None => (None, false),
            };
            let s_end = crossing.unwrap_or(horizon);
            observer.segment(&SegmentView {
                sim: self,
                flow,
                y: &seg.y,
                phase0: seg.phase0,
                signal: &seg.signal,
                start: clock,
                end: s_end,
                region,
            });
            if boundaries {
                // the period boundaries this segment passes (one it ends on without a switch
                // is reported below, with the state it ends in; one a switch falls on is
                // reported here, before the switch)
                let mut b = 1;
                loop {
                    let s_b = b as f64 * period - clock.offset;
                    if s_b >= horizon || s_b > s_end || (s_b == s_end && crossing.is_none()) {
                        break;
                    }
                    observer.period_boundary(
                        &Clock::at_cycle(period, clock.cycles + b),
                        &seg.state(s_b),
                    );
                    b += 1;
                }
            }
            x = seg.state(s_end);
            if observer.interrupted() {
                return Err(Error::Interrupted);
            }
            match crossing {
                Some(s) => {
                    clock.advance(s);
                    let (_, v) = seg.signal.tip(s);
                    // A touch whose normal velocity vanishes to round-off (relative to the
                    // tip velocity scale, plus the representation's error) does not enter
                    // the other region. The relative round-off is the flow's own: its modal
                    // coefficients are good to about κε (κ the eigenvectors' condition), and
                    // so is a velocity summed from them (κ reaches 1e7–1e8 for a stop of
                    // 1e11–1e12k₁, where 1e-13 alone mislabelled tangencies as entries
                    // with the wrong sign).
                    let relative = 1e-13_f64.max(64.0 * f64::EPSILON * flow.condition());
                    let velocity_bound = seg.signal.velocity_bound(s);
                    let vscale = relative * velocity_bound + seg.velocity_floor;
                    let entering = region == Region::Free;
                    // A velocity of the wrong sign is judged against either flow's round-off:
                    // after a release the state carries the contact flow's error (κ ~ 1e8
                    // against ~1e3 in free flight), and a tip hovering in the band of the
                    // surface after a tangential release may be "found" entering it while
                    // moving away by that much (N = 20 at 1e11k₁, d₀ = 0.006, ω = 0.3:
                    // −1.7e-12 against a free-flight scale of 5.7e-13): a touch.
                    let wrong_sign = entering != (v > 0.0);
                    let either = 1e-13_f64.max(64.0 * f64::EPSILON * self.condition());
                    let wrong_sign_touch =
                        wrong_sign && v.abs() <= either * velocity_bound + seg.velocity_floor;
                    // A crossing out of contact with the right sign is a release however slow:
                    // kept in contact, the stop would pull the tip back as a spring in tension
                    // (N = 10 at 1e12k₁, d₀ = 0: "touches" at ḋ ~ −1e-11 held the tip on the
                    // stop for the rest of the run, where the Dormand–Prince reference leaves
                    // it at t = 0.2635).
                    let slow_release = !entering && v < 0.0;
                    let grazing = touch || (v.abs() <= vscale && !slow_release) || wrong_sign_touch;
                    if !grazing && (entering != (v > 0.0)) {
                        return Err(Error::Invariant(format!(
                            "at t = {:.17e} the tip {} contact with velocity {v:e} (its round-off \
                             scale {vscale:.1e}, eigenvector condition {:.1e})",
                            clock.time(),
                            if entering { "entered" } else { "left" },
                            flow.condition()
                        )));
                    }
                    observer.event(&EventView {
                        clock,
                        entering: region == Region::Free,
                        grazing,
                        tip_velocity: v,
                        state: &x,
                    });
                    if clock.cycles != counted_cycle {
                        (counted_cycle, contacts) = (clock.cycles, 0);
                    }
                    if entering && !grazing {
                        contacts += 1;
                        if contacts > MAX_CONTACTS_PER_PERIOD {
                            return Err(self.chatter_refusal(&clock));
                        }
                    }
                    // A crossing at zero velocity (within round-off) that the current
                    // region's acceleration carries on through the surface is a slow switch,
                    // not a touch — the rule that starts a run at rest on the surface
                    // (`start_region`). Kept in this region, the next segment finds the same
                    // crossing again a few ulps on: a tip at rest 1e-30 from the stop
                    // stalled at 2.8e-24 per segment (found by the package's property tests).
                    let carried_through = grazing
                        && !touch
                        && seg
                            .signal
                            .local(
                                s,
                                signal::Target {
                                    sign: seg.sign,
                                    level: seg.gap,
                                },
                            )
                            .gdd
                            > 0.0;
                    if !grazing || carried_through {
                        region = match region {
                            Region::Free => Region::Contact,
                            Region::Contact => Region::Free,
                        };
                    }
                }
                None if to_boundary => {
                    clock.cycles += ((clock.offset + s_end) / period).round() as i64;
                    clock.offset = 0.0;
                    observer.period_boundary(&clock, &x);
                }
                None => clock = end,
            }
        }
        observer.end(self, &clock, &x, &stats);
        Ok(RunEnd {
            state: x,
            clock,
            stats,
        })
    }

    /// Why a run that chatters beyond [`MAX_CONTACTS_PER_PERIOD`] stops, with the contact
    /// frequency that sets the count and what to change.
    fn chatter_refusal(&self, clock: &Clock) -> Error {
        let contact = self.flow(Region::Contact);
        let fastest = contact
            .eigenvalues()
            .iter()
            .map(|l| l.im.abs())
            .fold(0.0, f64::max);
        Error::Chatter(format!(
            "more than {MAX_CONTACTS_PER_PERIOD} entries into contact in the forcing period \
             ending near t = {:.6e}: the tip chatters on the stop at its contact frequency \
             ({:.1e} oscillations per forcing period), and each bounce is an event to locate. \
             Ways out: more modes (their material damping quiets the contact vibration), a \
             softer stop, or the rigid-impact model (--model rigid)",
            clock.time(),
            fastest * self.period() / (2.0 * std::f64::consts::PI),
        ))
    }

    /// The region a state starts in ([`GalerkinModel::starting_region`]).
    ///
    /// # Errors
    /// [`crate::error::ParameterError`] for a state whose length is not 2N.
    pub fn initial_region(
        &self,
        x: &DVector<f64>,
        clock: &Clock,
    ) -> Result<Region, crate::error::ParameterError> {
        self.model.starting_region(x, clock.offset)
    }
}
