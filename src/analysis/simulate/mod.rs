//! The forced simulation of §5.2 as one call, for every front end: a transient discarded,
//! then a recorded window — the contact events (impacts, for the rigid model), the period m
//! and the entries per period n from the stroboscopic map, the certified maximum of the
//! tip, the exact energy budget and dense output. The command line's `simulate` and the
//! Python package's `simulate` are this function with their names for its options.
//!
//! **Recording never changes what is recorded.** How a run is cut into pieces (the
//! transient in one run, the window in chunks of [`CHUNK`] periods; the rigid model's window
//! period by period, for its strobe) depends only on the options that say what is run,
//! never on what is recorded: dense output is sampled inside the exact pieces of the motion
//! (the compliant model's segments, the rigid model's flights and sticking phases), and the
//! energy budget and the final state only watch. So events, strobe and final state are the
//! same bits with and without them (tested over models, laws and observers).

use crate::analysis::orbit::detect_period;
use crate::base::progress::{Progress, Task};
use crate::engine::built::{BuiltModel, Variant};
use crate::engine::rigid::{Outcome, RigidEvent, RigidImpact, RigidObserver};
use crate::engine::sim::{
    Clock, DenseStates, Energy, EnergyBudget, EventView, Observer, Simulator, Strobe, TipMax,
    TipMaximum,
};
use crate::engine::ticker::Ticker;
use crate::error::{Error, ParameterError};
use crate::model::ranges::Count;
use nalgebra::DVector;
use serde::Serialize;
use std::time::Instant;

mod rigid;

/// Periods simulated and discarded (at ~10 µs a period for N = 10, 1e8 is about 20 minutes).
pub const PERIODS: Count = Count {
    name: "periods",
    symbol: "",
    min: 0,
    max: 100_000_000,
    why: "at ~10 µs a period for N = 10, 1e8 periods take about 20 minutes",
};

/// Periods recorded after the transient.
pub const RECORD: Count = Count {
    name: "record",
    symbol: "",
    min: 0,
    max: 100_000,
    why: "the window's events and strobe are kept in memory",
};

/// Dense samples per forcing period.
pub const DENSE_PER_PERIOD: Count = Count {
    name: "dense_per_period",
    symbol: "",
    min: 1,
    max: 10_000,
    why: "ten thousand samples resolve a contact of 1e-4 T",
};

/// The longest period m searched.
pub const MAX_PERIOD: Count = Count {
    name: "max_period",
    symbol: "",
    min: 1,
    max: 1000,
    why: "a period must be seen twice in the window, and the strobe keeps m + 1 samples",
};

/// Most numbers a dense output may hold (~250 MB as CSV, 80 MB in memory): refused upfront
/// with the projected size rather than run out of memory.
pub const MAX_DENSE_NUMBERS: u64 = 10_000_000;

/// Most numbers the recorded events may hold (each event: its N modal velocities, N more
/// after a rigid impact, and six more): ~250 MB of JSON. How many events a window has is not
/// known before it is run, so a window with more is refused within a chunk of passing it.
pub const MAX_EVENT_NUMBERS: usize = 10_000_000;

/// Periods per chunk of the window (and of a rigid transient): one progress step, and the
/// granularity of the event cap.
pub const CHUNK: u64 = 1000;

/// What a simulation runs and records.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulateOptions {
    /// Periods simulated and discarded ([`PERIODS`]).
    pub periods: u64,
    /// Periods recorded after them ([`RECORD`]); at least one period in all.
    pub record: u64,
    /// Dense samples of the window per period ([`DENSE_PER_PERIOD`]), if wanted.
    pub dense_per_period: Option<usize>,
    /// The relative periodicity tolerance on the strobe (§5.2's 1e-9), in (0, 1).
    pub periodicity_tolerance: f64,
    /// The longest period m searched ([`MAX_PERIOD`]; also at most record/2).
    pub max_period: usize,
    /// The exact energy budget of the compliant model (about 20% of a run).
    pub energy: bool,
}

/// The options every front end starts from: no transient, 32 periods recorded, no dense
/// output, §5.2's tolerance 1e-9, periods up to 32 searched, the energy budget on.
pub const DEFAULTS: SimulateOptions = SimulateOptions {
    periods: 0,
    record: 32,
    dense_per_period: None,
    periodicity_tolerance: 1e-9,
    max_period: 32,
    energy: true,
};

/// Dense samples per period when dense output is asked for without a count.
pub const DEFAULT_DENSE_PER_PERIOD: usize = 200;

impl Default for SimulateOptions {
    fn default() -> Self {
        DEFAULTS
    }
}

impl SimulateOptions {
    /// The longest period searched: `max_period`, and at most half the recorded periods
    /// (a period must be seen twice).
    pub fn period_search_depth(&self) -> usize {
        self.max_period.min(self.record as usize / 2)
    }

    /// Checks every option against its range, for a model of N modes.
    ///
    /// # Errors
    /// [`ParameterError`] naming the first option out of its range.
    pub fn check(&self, modes: usize) -> Result<(), ParameterError> {
        PERIODS.check(self.periods as i128)?;
        RECORD.check(self.record as i128)?;
        if self.periods == 0 && self.record == 0 {
            return Err(ParameterError::new(
                "periods/record",
                0,
                "at least one period in all",
            ));
        }
        MAX_PERIOD.check(self.max_period as i128)?;
        if let Some(per) = self.dense_per_period {
            DENSE_PER_PERIOD.check(per as i128)?;
            // rows of t, region, tip, tip velocity and the 2N state
            let rows = (self.record * per as u64).max(1);
            let numbers = rows.saturating_mul(4 + 2 * modes as u64);
            if numbers > MAX_DENSE_NUMBERS {
                return Err(ParameterError::new(
                    "dense_per_period",
                    format!(
                        "{rows} rows of {} numbers (~{} MB of CSV) for record {} × \
                         dense_per_period {per}",
                        4 + 2 * modes,
                        numbers * 25 / 1_000_000,
                        self.record
                    ),
                    &format!(
                        "at most {MAX_DENSE_NUMBERS} numbers (~250 MB as CSV): fewer recorded \
                         periods or samples per period, or the window in pieces (its final \
                         state, then a run from it)"
                    ),
                ));
            }
        }
        if !(self.periodicity_tolerance > 0.0 && self.periodicity_tolerance < 1.0) {
            return Err(ParameterError::new(
                "periodicity_tolerance",
                self.periodicity_tolerance,
                "a number in (0, 1)",
            ));
        }
        Ok(())
    }
}

/// One event of the recorded window: an entry into or exit from contact (compliant), or an
/// impact (rigid).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimEvent {
    /// t, the time of the event (non-dimensional beam time).
    pub time: f64,
    /// The forcing cycle it falls in.
    pub cycle: i64,
    /// Its forcing phase, as a fraction of the period in [0, 1).
    pub phase: f64,
    /// Entering contact (compliant) or an impact (rigid).
    pub entering: bool,
    /// A touch with zero normal velocity (compliant): recorded, no switch.
    pub grazing: bool,
    /// Tip velocity at the event (rigid: before the impact).
    pub tip_velocity: f64,
    /// Rigid: tip velocity after the impact.
    pub outgoing_tip_velocity: Option<f64>,
    /// Modal velocities η̇ at the event (rigid: before the impact).
    pub modal_velocities: Vec<f64>,
    /// Rigid: modal velocities after the impact.
    pub modal_velocities_after: Option<Vec<f64>>,
}

/// Dense output of the window, column by column: record × dense_per_period samples on the
/// grid t = c·T + j·T/per_period from the window's start, its end excluded (the end is the
/// final state); a rigid run that stops inside its window ends with a sample at the stop.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DenseOutput {
    /// t.
    pub t: Vec<f64>,
    /// In contact (compliant), or resting on the stop (rigid).
    pub in_contact: Vec<bool>,
    /// The tip displacement d = φ(1)ᵀη.
    pub tip: Vec<f64>,
    /// The tip velocity φ(1)ᵀη̇.
    pub tip_velocity: Vec<f64>,
    /// The states [η; η̇], one after another (2N numbers a sample).
    pub states: Vec<f64>,
}

impl DenseOutput {
    fn push(&mut self, t: f64, contact: bool, tip: f64, velocity: f64, x: &DVector<f64>) {
        self.t.push(t);
        self.in_contact.push(contact);
        self.tip.push(tip);
        self.tip_velocity.push(velocity);
        self.states.extend_from_slice(x.as_slice());
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ending {
    /// It ran all its periods.
    Completed,
    /// A rigid run chattered under a law with no sticking limit, at t.
    Chatter(f64),
    /// A rigid run made more impacts than its policy's limit.
    ImpactLimit,
}

impl std::fmt::Display for Ending {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Ending::Completed => write!(f, "completed"),
            Ending::Chatter(t) => write!(f, "stopped at t = {t}: {CHATTER}"),
            Ending::ImpactLimit => write!(
                f,
                "stopped: more impacts than the policy's limit (10 000 in a forcing period: \
                 the tip bounces on the stop without accumulating, as an elastic law does \
                 with the stop pressed)"
            ),
        }
    }
}

/// The fewest and most counted events (cycle, counted) in each whole block of `m` periods
/// of a window of `record` periods ending at cycle `last`, blocks counted back from the end.
/// A periodic orbit has the same count in every block unless round-off decides an event
/// (measured at 1e12k₁: 4244 and 4245 entries in alternate periods of an orbit settled to
/// 1e-14).
pub fn impacts_range(events: &[(i64, bool)], last: i64, m: u64, record: u64) -> (u64, u64) {
    let blocks = (record / m.max(1)).max(1) as i64;
    let m = m as i64;
    (1..=blocks)
        .map(|b| {
            let (from, to) = (last - b * m, last - (b - 1) * m);
            events
                .iter()
                .filter(|(c, counted)| *counted && *c >= from && *c < to)
                .count() as u64
        })
        .fold((u64::MAX, 0), |(lo, hi), n| (lo.min(n), hi.max(n)))
}

const CHATTER: &str = "impacts accumulate (chatter), and this law changes the velocity \
                       orthogonal to the tip at every impact, so the chatter has no sticking \
                       limit (use the impulse-response law)";

/// What a simulation found.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The events of the recorded window.
    pub events: Vec<SimEvent>,
    /// The smallest m ≤ `max_period_searched` with ‖x(t₀+mT) − x(t₀)‖∞ below the tolerance
    /// times ‖x(t₀)‖∞ at the end of the window; None if none (or < 2 recorded periods).
    pub period_m: Option<u64>,
    /// The smallest such residual (None with fewer than 2 recorded periods).
    pub periodicity_residual: Option<f64>,
    /// The longest period tested.
    pub max_period_searched: usize,
    /// Entries into contact (impacts) per period m, when periodic (the window's last m
    /// periods).
    pub impacts_n: Option<u64>,
    /// The fewest and most entries in each block of m periods of the window, counted back
    /// from its end, when periodic: apart where round-off decides an event of the orbit
    /// ([`impacts_range`]).
    pub impacts_n_range: Option<(u64, u64)>,
    /// Entries into contact (impacts) in the whole window, grazes excluded.
    pub contacts_in_window: u64,
    /// Flights of the window between two contacts that rise less than `flight_resolution`
    /// from the stop ([`shallow_flights`]): where there are any, round-off decides the
    /// counts (a 50-digit run at 10¹¹k₁ has 2416 entries in a period this engine counts
    /// 2506), so they are not exact.
    pub shallow_flights: u64,
    /// The tip displacement the flow resolves: its accuracy κε times the larger of the
    /// window's largest tip displacement and the free tip amplitude A_free(ω) (0 without a
    /// window or for the rigid model).
    pub flight_resolution: f64,
    /// The certified maximum of the tip in the window (compliant, with a window).
    pub max_tip: Option<TipMaximum>,
    /// Relative energy imbalance of the whole run (compliant, with the budget).
    pub energy_imbalance: Option<f64>,
    /// What round-off explains of it ([`EnergyBudget::round_off_bound`]).
    pub energy_imbalance_bound: Option<f64>,
    /// The eigenvector condition of the flows used (results good to about this × ε).
    pub condition: f64,
    /// How the run ended.
    pub ending: Ending,
    /// Where it ended.
    pub final_clock: Clock,
    /// The final state.
    pub final_state: DVector<f64>,
    /// Dense output of the window, if asked for.
    pub dense: Option<DenseOutput>,
    /// Wall time of the runs (the model's set-up excluded).
    pub wall_seconds: f64,
}

/// Simulates `model` from `x0` at the start of cycle 0: `options.periods` discarded, then
/// `options.record` recorded, reporting whole periods to `progress` and stopping when it
/// is cancelled.
///
/// # Errors
/// [`Error::Parameter`] for options out of range, a start of the wrong length, or a window
/// whose events pass [`MAX_EVENT_NUMBERS`]; [`Error::Chatter`] for a compliant stop beyond
/// its contact cap, or a rigid run that stops before its window records anything;
/// [`Error::Interrupted`] when `progress` is cancelled; [`Error::Invariant`] for a run
/// that breaks an invariant of the exact solution.
pub fn simulate(
    model: &BuiltModel,
    x0: &DVector<f64>,
    options: &SimulateOptions,
    progress: &dyn Progress,
) -> Result<Simulation, Error> {
    options.check(model.modes())?;
    let started = Instant::now();
    let task = progress.task("simulate: periods", options.periods + options.record);
    let mut out = match model.variant() {
        Variant::Compliant(sim) => compliant(sim, x0, options, task.as_ref(), progress)?,
        Variant::Rigid(model) => rigid::rigid(model, x0, options, task.as_ref(), progress)?,
    };
    out.condition = model.condition();
    if let (Some(top), Variant::Compliant(sim)) = (out.max_tip, model.variant()) {
        // the flow's error is relative to the whole motion, not to the tip's excursion
        // towards the stop (6.8e-9 at d₀ = 0 and 10¹²k₁, where the beam swings by 6.7e-3)
        let free = sim.model().free_tip_amplitude().0;
        let scale = top
            .value
            .abs()
            .max(if free.is_finite() { free } else { 0.0 });
        out.flight_resolution = out.condition * f64::EPSILON * scale;
        out.shallow_flights = shallow_flights(&out.events, out.flight_resolution);
    }
    out.wall_seconds = started.elapsed().as_secs_f64();
    Ok(out)
}

/// The flights between a contact's end and the next entry that rise less than `resolution`
/// from the stop. A flight's rise is estimated from its ends as a parabola's,
/// Δt·(|v_leave| + |v_enter|)/8 (the tip's acceleration is nearly constant over a
/// micro-bounce's flight): cheap, and well inside the factor of the flow's accuracy that
/// decides whether the flight is resolved.
pub fn shallow_flights(events: &[SimEvent], resolution: f64) -> u64 {
    let real: Vec<&SimEvent> = events.iter().filter(|e| !e.grazing).collect();
    real.windows(2)
        .filter(|w| !w[0].entering && w[1].entering)
        .filter(|w| {
            let rise =
                (w[1].time - w[0].time) * (w[0].tip_velocity.abs() + w[1].tip_velocity.abs()) / 8.0;
            rise < resolution
        })
        .count() as u64
}

/// The period search on the strobe's last samples: (m, residual, depth).
fn period_search(
    options: &SimulateOptions,
    strobe: &[DVector<f64>],
) -> (Option<u64>, Option<f64>, usize) {
    let max_m = options.period_search_depth();
    if strobe.len() < 2 || max_m == 0 {
        return (None, None, max_m);
    }
    let (m, r) = detect_period(strobe, options.periodicity_tolerance, max_m);
    (m, r.is_finite().then_some(r), max_m)
}

/// The refusal of a window whose events do not fit.
fn too_many_events(options: &SimulateOptions, events: usize, modes: usize) -> Error {
    ParameterError::new(
        "record",
        options.record,
        &format!(
            "a window whose events fit in {MAX_EVENT_NUMBERS} numbers (~250 MB as JSON); this \
             one had more than {events} events at N = {modes}: fewer recorded periods, or the \
             window in pieces (its final state, then a run from it)"
        ),
    )
    .into()
}

/// The window's events with their modal velocities, up to the cap.
#[derive(Default)]
struct EventLog {
    events: Vec<SimEvent>,
    numbers: usize,
    full: bool,
}

impl Observer for EventLog {
    fn event(&mut self, e: &EventView) {
        let n = e.state.len() / 2;
        self.numbers += n + 6;
        if self.numbers > MAX_EVENT_NUMBERS {
            self.full = true;
            return;
        }
        self.events.push(SimEvent {
            time: e.clock.time(),
            cycle: e.clock.cycles,
            phase: e.clock.offset / e.clock.period,
            entering: e.entering,
            grazing: e.grazing,
            tip_velocity: e.tip_velocity,
            outgoing_tip_velocity: None,
            modal_velocities: e.state.rows(n, n).iter().copied().collect(),
            modal_velocities_after: None,
        });
    }
}

fn compliant(
    sim: &Simulator,
    x0: &DVector<f64>,
    options: &SimulateOptions,
    task: &dyn Task,
    progress: &dyn Progress,
) -> Result<Simulation, Error> {
    let period = sim.period();
    let mut budget: Option<EnergyBudget> = None;
    let mut add = |b: &EnergyBudget| {
        budget = Some(budget.map_or(*b, |a| a.then(b)));
    };
    let mut ticker = Ticker::new(task, progress, 0);
    let budgeted = || options.energy.then(Energy::default);
    // the transient, in one run
    let mut energy = budgeted();
    let end = sim.run_from(
        x0,
        sim.clock_at_cycle(0),
        options.periods,
        &mut (&mut energy, &mut ticker),
    )?;
    if let Some(e) = &energy {
        add(&e.budget);
    }
    let mut segments = end.stats.segments;
    let (mut x, mut clock) = (end.state, end.clock);
    // the window, in chunks (restarts at period boundaries, fixed by `record` alone), so a
    // window whose events pass the cap is refused within a chunk of passing it
    let (mut log, mut max_tip) = (EventLog::default(), TipMax::default());
    let mut dense = options.dense_per_period.map(DenseStates::new);
    let mut strobe = Strobe::keeping_last(options.period_search_depth() + 1);
    let mut remaining = options.record;
    while remaining > 0 {
        let step = remaining.min(CHUNK);
        let mut energy = budgeted();
        let end = sim.run_from(
            &x,
            clock,
            step,
            &mut (
                &mut log,
                &mut max_tip,
                &mut energy,
                &mut strobe,
                (&mut dense, &mut ticker),
            ),
        )?;
        if let Some(e) = &energy {
            add(&e.budget);
        }
        segments += end.stats.segments;
        if log.full {
            return Err(too_many_events(
                options,
                log.events.len(),
                sim.model().modes(),
            ));
        }
        (x, clock) = (end.state, end.clock);
        remaining -= step;
    }
    let (period_m, periodicity_residual, max_period_searched) =
        period_search(options, &strobe.states());
    let last = clock.cycles;
    let contacts = |from: i64| {
        log.events
            .iter()
            .filter(|e| e.entering && !e.grazing && e.cycle >= from)
            .count() as u64
    };
    let dense = dense.map(|d| {
        let mut out = DenseOutput::default();
        for (t, contact, tip, v, x) in &d.samples {
            out.push(*t, *contact, *tip, *v, x);
        }
        out
    });
    let counted: Vec<(i64, bool)> = log
        .events
        .iter()
        .map(|e| (e.cycle, e.entering && !e.grazing))
        .collect();
    Ok(Simulation {
        impacts_n_range: period_m.map(|m| impacts_range(&counted, last, m, options.record)),
        impacts_n: period_m.map(|m| contacts(last - m as i64)),
        contacts_in_window: contacts(last - options.record as i64),
        shallow_flights: 0,
        flight_resolution: 0.0,
        events: log.events,
        period_m,
        periodicity_residual,
        max_period_searched,
        max_tip: max_tip.maximum,
        energy_imbalance: budget.map(|b| b.relative_imbalance()),
        energy_imbalance_bound: budget.map(|b| b.round_off_bound(sim.condition(), segments)),
        condition: 0.0,
        ending: Ending::Completed,
        final_clock: Clock::at_cycle(period, last),
        final_state: x,
        dense,
        wall_seconds: 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::impacts_range;

    #[test]
    fn the_count_range_is_over_whole_blocks_back_from_the_end() {
        // (cycle, counted): a window of cycles 10..16, m = 2: blocks 14-15, 12-13, 10-11
        let mut events = vec![(10, true), (11, true), (12, true), (12, false), (13, true)];
        events.extend([(14, true), (15, true), (15, true)]);
        assert_eq!(impacts_range(&events, 16, 2, 6), (2, 3));
        // a block cut off by the window's start is not counted: m = 4 fits once in 6
        assert_eq!(impacts_range(&events, 16, 4, 6), (5, 5));
        assert_eq!(impacts_range(&[], 16, 1, 3), (0, 0));
    }

    #[test]
    fn a_flight_is_shallow_when_its_parabola_stays_below_the_resolution() {
        let event = |time: f64, entering: bool, v: f64| super::SimEvent {
            time,
            cycle: 0,
            phase: 0.0,
            entering,
            grazing: false,
            tip_velocity: v,
            outgoing_tip_velocity: None,
            modal_velocities: vec![],
            modal_velocities_after: None,
        };
        // leave at 1 m/s for 4e-3: rise 4e-3·2/8 = 1e-3; then leave at 1e-6 for 1e-6: 2.5e-13
        let events = [
            event(0.0, true, 1.0),
            event(1.0, false, -1.0),
            event(1.004, true, 1.0),
            event(1.1, false, -1e-6),
            event(1.100001, true, 1e-6),
        ];
        assert_eq!(super::shallow_flights(&events, 1e-10), 1);
        assert_eq!(super::shallow_flights(&events, 2e-3), 2);
        assert_eq!(super::shallow_flights(&events, 0.0), 0);
    }
}
