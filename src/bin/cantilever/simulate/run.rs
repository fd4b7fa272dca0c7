//! The runs behind `simulate`: the compliant model through the exact simulator (one run for
//! the transient, one for the window, with a progress ticker that only watches), the rigid
//! model through its impacts in chunks of periods.

use super::{output, ModelKind, Setup, SimulateArgs};
use crate::progress::Bars;
use impacting_cantilever::analysis::orbit::detect_period;
use impacting_cantilever::engine::rigid::{Outcome, RigidEvent, RigidImpact};
use impacting_cantilever::engine::sim::{
    Clock, Energy, EnergyBudget, EventView, Observer, SegmentView, Simulator, Strobe, TipMax,
    TipMaximum,
};
use impacting_cantilever::error::{Error, ParameterError};
use impacting_cantilever::model::galerkin::Region;
use impacting_cantilever::results::scene::Progress;
use nalgebra::DVector;
use std::time::Instant;

/// Periods per chunk of a long rigid run (one progress step).
const CHUNK: u64 = 1000;

/// Reports whole periods as segments pass them: progress without touching the numerics
/// (it asks for no period boundaries).
struct Ticker<'a> {
    task: &'a dyn impacting_cantilever::results::scene::Task,
    done: i64,
}

impl Observer for Ticker<'_> {
    fn begin(&mut self, _: &Simulator, clock: &Clock, _: &DVector<f64>) {
        self.done = clock.cycles;
    }
    fn segment(&mut self, seg: &SegmentView) {
        let now = ((seg.start.time() + seg.end) / seg.start.period).floor() as i64;
        if now > self.done {
            self.task.advance((now - self.done) as u64);
            self.done = now;
        }
    }
}

/// One event of the recorded window (serialized as is into the JSON report's `events`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct EventOut {
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
    #[serde(rename = "outgoing_tip_velocity")]
    pub outgoing: Option<f64>,
    /// Modal velocities η̇ at the event (rigid: before the impact).
    pub modal_velocities: Vec<f64>,
    /// Rigid: modal velocities after the impact.
    #[serde(rename = "modal_velocities_after")]
    pub modal_after: Option<Vec<f64>>,
}

/// One dense sample: t, in contact, tip, tip velocity, the state [η; η̇].
pub type DenseRow = (f64, bool, f64, f64, Vec<f64>);

/// What the command reports.
pub struct Report {
    /// The inputs.
    pub args: SimulateArgs,
    /// The model, its law and its start.
    pub setup: Setup,
    /// Events of the recorded window.
    pub events: Vec<EventOut>,
    /// The smallest period m ≤ `max_period_searched` with a relative strobe residual below
    /// the tolerance; None if none (or fewer than 2 recorded periods).
    pub period_m: Option<u64>,
    /// The smallest residual over m ≤ `max_period_searched` (None: < 2 recorded periods).
    pub periodicity_residual: Option<f64>,
    /// min(--max-period, record/2): the largest period tested.
    pub max_period_searched: usize,
    /// Entries into contact (impacts) per period, when periodic.
    pub impacts_per_period: Option<u64>,
    /// Entries into contact (impacts) in the whole recorded window.
    pub contacts_in_window: u64,
    /// The certified maximum of the tip in the window (compliant, with a window).
    pub max_tip: Option<TipMaximum>,
    /// Relative energy imbalance of the whole run (compliant).
    pub energy_imbalance: Option<f64>,
    /// What round-off explains of it ([`EnergyBudget::round_off_bound`]).
    pub energy_imbalance_bound: Option<f64>,
    /// The larger condition of the two region flows (the flow is good to about this × ε).
    pub condition: f64,
    /// How the run ended (rigid: completed, chatter, impact limit).
    pub outcome: String,
    /// Where it ended.
    pub final_clock: Clock,
    /// The final state.
    pub final_state: DVector<f64>,
    /// Dense output of the window (if asked for).
    pub dense: Vec<DenseRow>,
    /// Wall time.
    pub wall_seconds: f64,
}

/// Dense samples of the whole state on the grid t = cycles·T + j·T/per_period.
struct ModalDense {
    per_period: usize,
    rows: Vec<DenseRow>,
}

impl Observer for ModalDense {
    fn needs_period_boundaries(&self) -> bool {
        true
    }
    fn segment(&mut self, seg: &SegmentView) {
        let dt = seg.start.period / self.per_period as f64;
        let mut j = (seg.start.offset / dt).ceil() as i64;
        // j < per_period: j = per_period is the next cycle's j = 0
        while j < self.per_period as i64 {
            let s = j as f64 * dt - seg.start.offset;
            if s >= seg.end {
                break;
            }
            let (d, v) = seg.tip(s);
            let x = seg.state(s);
            self.rows.push((
                seg.start.time() + s,
                seg.region == Region::Contact,
                d,
                v,
                x.iter().cloned().collect(),
            ));
            j += 1;
        }
    }
}

/// The most numbers the recorded events may hold (each event: its N modal velocities and
/// six more), as for `--dense`: ~250 MB of JSON. A window with more is refused when it
/// ends (how many events a window has is not known before it is run), without the memory.
const MAX_EVENT_NUMBERS: usize = 10_000_000;

/// Events with the modal velocities.
#[derive(Default)]
struct EventLog(Vec<EventOut>, usize, bool);

impl EventLog {
    /// The refusal when the window's events did not fit.
    fn check(&self, args: &SimulateArgs) -> Result<(), Error> {
        if !self.2 {
            return Ok(());
        }
        Err(Error::Parameter(ParameterError::new(
            "--record",
            args.record,
            &format!(
                "a window whose events fit in {MAX_EVENT_NUMBERS} numbers (~250 MB as JSON); \
                 this one had more than {} events at N = {}: fewer recorded periods, or the \
                 window in pieces (--final-state, then --initial-state)",
                self.0.len(),
                args.modes
            ),
        )))
    }
}

impl Observer for EventLog {
    fn event(&mut self, e: &EventView) {
        let n = e.state.len() / 2;
        self.1 += n + 6;
        if self.1 > MAX_EVENT_NUMBERS {
            self.2 = true;
            return;
        }
        self.0.push(EventOut {
            time: e.clock.time(),
            cycle: e.clock.cycles,
            phase: e.clock.offset / e.clock.period,
            entering: e.entering,
            grazing: e.grazing,
            tip_velocity: e.tip_velocity,
            outgoing: None,
            modal_velocities: e.state.rows(n, n).iter().cloned().collect(),
            modal_after: None,
        });
    }
}

/// Runs the command.
pub fn run(args: &SimulateArgs) -> Result<Report, Error> {
    let setup = super::setup(args)?;
    output::check_writable(args)?;
    let started = Instant::now();
    let bars = Bars::default();
    let report = match args.model {
        ModelKind::Compliant => compliant(args, setup, &bars)?,
        ModelKind::Rigid => rigid(args, setup, &bars)?,
    };
    let mut report = report;
    report.wall_seconds = started.elapsed().as_secs_f64();
    output::write_files(&report)?;
    Ok(report)
}

fn period_search(
    args: &SimulateArgs,
    strobe: &[DVector<f64>],
) -> (Option<u64>, Option<f64>, usize) {
    let max_m = super::period_search_depth(args);
    if strobe.len() < 2 || max_m == 0 {
        return (None, None, max_m);
    }
    let (m, r) = detect_period(strobe, args.periodicity_tolerance, max_m);
    (m, r.is_finite().then_some(r), max_m)
}

fn compliant(args: &SimulateArgs, setup: Setup, bars: &Bars) -> Result<Report, Error> {
    let sim = Simulator::new(setup.model.clone())?;
    let period = sim.period();
    let task = bars.task("simulate: periods", args.periods + args.record);
    let mut x = setup.x0.clone();
    let mut clock = sim.clock_at_cycle(0);
    let mut budget: Option<EnergyBudget> = None;
    let mut add = |b: &EnergyBudget| {
        budget = Some(budget.map_or(*b, |a| a.then(b)));
    };
    let mut ticker = Ticker {
        task: task.as_ref(),
        done: 0,
    };
    // the transient, with the energy budget unless --no-energy
    let budgeted = || (!args.no_energy).then(Energy::default);
    let mut energy = budgeted();
    let end = sim.run_from(&x, clock, args.periods, &mut (&mut energy, &mut ticker))?;
    if let Some(e) = &energy {
        add(&e.budget);
    }
    let mut segments = end.stats.segments;
    (x, clock) = (end.state, end.clock);
    // the recorded window
    let (mut log, mut max_tip) = (EventLog::default(), TipMax::default());
    let mut dense = ModalDense {
        per_period: args.dense_per_period,
        rows: Vec::new(),
    };
    // the period search looks back at most max_m periods from the last
    let keep = super::period_search_depth(args) + 1;
    let mut strobe = Strobe::keeping_last(keep);
    // in chunks, so that a window whose events pass the cap is refused then, not after
    // all its periods (each restart is at a period boundary, where segments end anyway)
    let mut remaining = args.record;
    while remaining > 0 {
        let step = remaining.min(CHUNK);
        let mut energy = budgeted();
        let end = if args.dense.is_some() {
            sim.run_from(
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
            )?
        } else {
            sim.run_from(
                &x,
                clock,
                step,
                &mut (
                    &mut log,
                    &mut max_tip,
                    &mut energy,
                    &mut strobe,
                    &mut ticker,
                ),
            )?
        };
        if let Some(e) = &energy {
            add(&e.budget);
        }
        segments += end.stats.segments;
        log.check(args)?;
        (x, clock) = (end.state, end.clock);
        remaining -= step;
    }
    let strobe_states = strobe.states();
    drop(task);
    let (period_m, periodicity_residual, max_period_searched) = period_search(args, &strobe_states);
    let last_cycle = clock.cycles;
    let contacts = |from: i64| {
        log.0
            .iter()
            .filter(|e| e.entering && !e.grazing && e.cycle >= from)
            .count() as u64
    };
    let window_start = last_cycle - args.record as i64;
    Ok(Report {
        impacts_per_period: period_m.map(|m| contacts(last_cycle - m as i64)),
        contacts_in_window: contacts(window_start),
        events: log.0,
        period_m,
        periodicity_residual,
        max_period_searched,
        max_tip: max_tip.maximum,
        energy_imbalance: budget.map(|b| b.relative_imbalance()),
        energy_imbalance_bound: budget
            .map(|_| EnergyBudget::round_off_bound(sim.condition(), segments)),
        condition: sim.condition(),
        outcome: "completed".into(),
        final_clock: Clock::at_cycle(period, last_cycle),
        final_state: x,
        dense: dense.rows,
        wall_seconds: 0.0,
        args: args.clone(),
        setup,
    })
}

/// One dense row of the rigid model: in contact when the tip rests on the stop.
fn rigid_sample(model: &RigidImpact, t: f64, x: &DVector<f64>) -> DenseRow {
    let m = model.sim.model();
    let n = m.modes();
    let tip = m.tip().dot(&x.rows(0, n));
    let velocity = m.tip().dot(&x.rows(n, n));
    (
        t,
        model.at_rest_on_stop(x),
        tip,
        velocity,
        x.iter().copied().collect(),
    )
}

fn rigid(args: &SimulateArgs, setup: Setup, bars: &Bars) -> Result<Report, Error> {
    let sim = Simulator::new(setup.model.clone())?;
    let period = sim.period();
    let condition = sim.flow(Region::Free).condition();
    let law = setup.law.clone().unwrap_or_default();
    let model = RigidImpact::new(sim, law)?;
    let task = bars.task("simulate: periods", args.periods + args.record);
    let (mut x, mut cycle) = (setup.x0.clone(), 0i64);
    let mut outcome = Outcome::Completed;
    let mut final_clock = Clock::at_cycle(period, 0);
    let mut events = Vec::new();
    let mut strobe_states = Vec::new();
    let mut dense = Vec::new();
    let total = args.periods + args.record;
    let mut done = 0u64;
    while done < total && outcome == Outcome::Completed {
        // the transient in chunks, the window period by period (its strobe)
        let step = if done < args.periods {
            (args.periods - done).min(CHUNK)
        } else {
            1
        };
        let recording = done >= args.periods;
        if recording && strobe_states.is_empty() {
            strobe_states.push(x.clone());
        }
        let r = if recording && args.dense.is_some() {
            // the window's dense output: the period in equal pieces, chained (a sticking
            // phase survives the restarts)
            if dense.is_empty() {
                dense.push(rigid_sample(&model, cycle as f64 * period, &x));
            }
            let pieces = args.dense_per_period.max(1);
            let mut clock = Clock::at_cycle(period, cycle);
            let mut state = x.clone();
            let mut joined: Option<impacting_cantilever::engine::rigid::RigidRun> = None;
            for j in 1..=pieces {
                let next = if j == pieces {
                    Clock::at_cycle(period, cycle + 1)
                } else {
                    let mut c = Clock::at_cycle(period, cycle);
                    c.advance(period * j as f64 / pieces as f64);
                    c
                };
                let piece = model.run_until(&state, clock, next)?;
                state = piece.state.clone();
                clock = piece.clock;
                dense.push(rigid_sample(&model, clock.time(), &state));
                let stop = piece.outcome != Outcome::Completed;
                joined = Some(match joined.take() {
                    None => piece,
                    Some(mut all) => {
                        all.events.extend(piece.events);
                        all.state = piece.state;
                        all.clock = piece.clock;
                        all.time = piece.time;
                        all.outcome = piece.outcome;
                        all
                    }
                });
                if stop {
                    break;
                }
            }
            joined.expect("at least one piece")
        } else {
            model.run_until(
                &x,
                Clock::at_cycle(period, cycle),
                Clock::at_cycle(period, cycle + step as i64),
            )?
        };
        if recording {
            events.extend(r.events.iter().filter_map(|e| match e {
                RigidEvent::Impact {
                    time,
                    incoming,
                    outgoing,
                    before,
                    after,
                } => {
                    let c = Clock::at_time(period, *time);
                    Some(EventOut {
                        time: *time,
                        cycle: c.cycles,
                        phase: c.offset / period,
                        entering: true,
                        grazing: false,
                        tip_velocity: *incoming,
                        outgoing: Some(*outgoing),
                        modal_velocities: before.clone(),
                        modal_after: Some(after.clone()),
                    })
                }
                _ => None,
            }));
            // each impact holds 2N modal velocities and six more numbers
            let numbers = events.len() * (2 * args.modes + 6);
            if numbers > MAX_EVENT_NUMBERS {
                let full = EventLog(std::mem::take(&mut events), numbers, true);
                full.check(args)?;
            }
        }
        outcome = r.outcome;
        x = r.state;
        final_clock = r.clock;
        if outcome == Outcome::Completed {
            cycle += step as i64;
            done += step;
            if recording {
                strobe_states.push(x.clone());
                // the period search needs only the last max_m + 1
                let keep = super::period_search_depth(args) + 1;
                if strobe_states.len() > keep {
                    strobe_states.remove(0);
                }
            }
        }
        task.advance(step);
    }
    drop(task);
    // as the compliant model's: the window's end is the final state, not a sample
    if outcome == Outcome::Completed && !dense.is_empty() {
        dense.pop();
    }
    let (period_m, periodicity_residual, max_period_searched) = period_search(args, &strobe_states);
    let impacts = |from: i64| events.iter().filter(|e| e.cycle >= from).count() as u64;
    let chatter = "impacts accumulate (chatter), and this law changes the velocity orthogonal to the tip at every impact, so the chatter has no sticking limit (use --law impulse-response)";
    let outcome_text = match outcome {
        Outcome::Completed => "completed".to_string(),
        Outcome::Chatter(t) => format!("stopped at t = {t}: {chatter}"),
        Outcome::ImpactLimit => "stopped: more impacts than the policy's limit".to_string(),
    };
    // a run that stopped before its window began recorded nothing: that is no result
    let window_start = args.periods as f64 * period;
    if outcome != Outcome::Completed && (done < args.periods || final_clock.time() <= window_start)
    {
        return Err(Error::Unsupported(match outcome {
            Outcome::Chatter(t) if t < window_start => format!(
                "nothing recorded: the run stopped at t = {t}, before its window (from t = {window_start}): {chatter}"
            ),
            Outcome::Chatter(t) => format!(
                "nothing recorded: the run stopped at t = {t}, as its window began: {chatter}"
            ),
            _ => format!(
                "nothing recorded: the run stopped before its window (from t = {window_start}): more impacts than the policy's limit"
            ),
        }));
    }
    Ok(Report {
        impacts_per_period: period_m.map(|m| impacts(cycle - m as i64)),
        contacts_in_window: impacts(cycle - args.record as i64),
        events,
        period_m,
        periodicity_residual,
        max_period_searched,
        max_tip: None,
        energy_imbalance: None,
        energy_imbalance_bound: None,
        condition,
        outcome: outcome_text,
        final_clock,
        final_state: x,
        dense,
        wall_seconds: 0.0,
        args: args.clone(),
        setup,
    })
}
