//! `simulate`: a transient discarded, then a recorded window — contact events, the period m
//! and contacts per period n, the certified maximum of the tip, the exact energy budget,
//! dense output — exactly as `cantilever simulate` runs it (`src/bin/cantilever/simulate/
//! run.rs`: the same runs with the same observers, so the same segments and the same bits).

use crate::convert::{matrix, Reporter};
use crate::model::{count, Model, MAX_PERIODS, MAX_RECORD};
use crate::{bad, Res};
use impacting_cantilever::analysis::orbit::detect_period;
use impacting_cantilever::engine::rigid::{Outcome, RigidEvent, RigidImpact, RigidRun};
use impacting_cantilever::engine::sim::{
    Clock, Energy, EnergyBudget, EventView, Observer, SegmentView, Simulator, Strobe, TipMax,
    TipMaximum,
};
use impacting_cantilever::error::Error;
use impacting_cantilever::model::galerkin::Region;
use nalgebra::DVector;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::time::Instant;

/// Periods per chunk of a long rigid run (one progress step).
const CHUNK: u64 = 1000;

/// The most numbers of dense output a run may hold (2 GB of doubles).
const MAX_DENSE_VALUES: f64 = 2.5e8;

/// What a run asks for.
struct Args {
    periods: u64,
    record: u64,
    dense: Option<usize>,
    tolerance: f64,
    max_period: usize,
}

/// One event of the recorded window.
struct EventOut {
    time: f64,
    cycle: i64,
    phase: f64,
    entering: bool,
    grazing: bool,
    tip_velocity: f64,
    outgoing: Option<f64>,
    modal_velocities: Vec<f64>,
    modal_after: Option<Vec<f64>>,
}

/// Dense samples, column by column (so that they become numpy arrays without a copy): t, in
/// contact, tip, tip velocity, and the states [η; η̇] one after another.
#[derive(Default)]
struct DenseOut {
    t: Vec<f64>,
    contact: Vec<bool>,
    tip: Vec<f64>,
    velocity: Vec<f64>,
    states: Vec<f64>,
}

impl DenseOut {
    fn push(&mut self, t: f64, contact: bool, tip: f64, velocity: f64, x: &DVector<f64>) {
        self.t.push(t);
        self.contact.push(contact);
        self.tip.push(tip);
        self.velocity.push(velocity);
        self.states.extend_from_slice(x.as_slice());
    }

    /// Drops the last sample (the window's end, which is the final state).
    fn pop(&mut self) {
        if self.t.pop().is_some() {
            let n = self.states.len() / (self.t.len() + 1);
            self.contact.pop();
            self.tip.pop();
            self.velocity.pop();
            self.states.truncate(self.states.len() - n);
        }
    }
}

/// What a run reports.
struct Report {
    events: Vec<EventOut>,
    period_m: Option<u64>,
    residual: Option<f64>,
    max_period_searched: usize,
    impacts_n: Option<u64>,
    contacts_in_window: u64,
    max_tip: Option<TipMaximum>,
    energy_imbalance: Option<f64>,
    condition: f64,
    outcome: String,
    final_clock: Clock,
    final_state: DVector<f64>,
    dense: Option<DenseOut>,
}

/// Reports whole periods as segments pass them (asks for no period boundaries, so it
/// changes nothing of the run).
struct Ticker<'a> {
    reporter: &'a Reporter,
    done: i64,
    total: u64,
}

impl Observer for Ticker<'_> {
    fn segment(&mut self, seg: &SegmentView) {
        let now = ((seg.start.time() + seg.end) / seg.start.period).floor() as i64;
        if now > self.done {
            self.done = now;
            let done = (now.max(0) as u64).min(self.total);
            self.reporter.report("simulate: periods", done, self.total);
        }
    }
}

/// Dense samples of the whole state on the grid t = cycles·T + j·T/per_period.
struct ModalDense {
    per_period: usize,
    out: DenseOut,
}

impl Observer for ModalDense {
    fn needs_period_boundaries(&self) -> bool {
        true
    }
    fn segment(&mut self, seg: &SegmentView) {
        let dt = seg.start.period / self.per_period as f64;
        let mut j = (seg.start.offset / dt).ceil() as i64;
        while j < self.per_period as i64 {
            let s = j as f64 * dt - seg.start.offset;
            if s >= seg.end {
                break;
            }
            let (d, v) = seg.tip(s);
            let x = seg.state(s);
            let contact = seg.region == Region::Contact;
            self.out.push(seg.start.time() + s, contact, d, v, &x);
            j += 1;
        }
    }
}

/// Events with the modal velocities.
#[derive(Default)]
struct EventLog(Vec<EventOut>);

impl Observer for EventLog {
    fn event(&mut self, e: &EventView) {
        let n = e.state.len() / 2;
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

fn period_search(args: &Args, strobe: &[DVector<f64>]) -> (Option<u64>, Option<f64>, usize) {
    let max_m = args.max_period.min(args.record as usize / 2);
    if strobe.len() < 2 || max_m == 0 {
        return (None, None, max_m);
    }
    let (m, r) = detect_period(strobe, args.tolerance, max_m);
    (m, r.is_finite().then_some(r), max_m)
}

fn compliant(
    sim: &Simulator,
    x0: &DVector<f64>,
    args: &Args,
    reporter: &Reporter,
) -> Result<Report, Error> {
    let period = sim.period();
    let mut budget: Option<EnergyBudget> = None;
    let mut add = |b: &EnergyBudget| {
        budget = Some(budget.map_or(*b, |a| a.then(b)));
    };
    let mut ticker = Ticker {
        reporter,
        done: 0,
        total: args.periods + args.record,
    };
    // the transient
    let mut energy = Energy::default();
    let clock = sim.clock_at_cycle(0);
    let end = sim.run_from(x0, clock, args.periods, &mut (&mut energy, &mut ticker))?;
    add(&energy.budget);
    let (x, clock) = (end.state, end.clock);
    // the recorded window
    let (mut log, mut max_tip) = (EventLog::default(), TipMax::default());
    let mut dense = ModalDense {
        per_period: args.dense.unwrap_or(1),
        out: DenseOut::default(),
    };
    let (mut energy, mut strobe) = (Energy::default(), Strobe::default());
    let end = if args.dense.is_some() {
        sim.run_from(
            &x,
            clock,
            args.record,
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
            args.record,
            &mut (
                &mut log,
                &mut max_tip,
                &mut energy,
                &mut strobe,
                &mut ticker,
            ),
        )?
    };
    add(&energy.budget);
    let strobe_states = strobe.states();
    let (x, clock) = (end.state, end.clock);
    let (period_m, residual, max_period_searched) = period_search(args, &strobe_states);
    let last_cycle = clock.cycles;
    let contacts = |from: i64| {
        log.0
            .iter()
            .filter(|e| e.entering && !e.grazing && e.cycle >= from)
            .count() as u64
    };
    let window_start = last_cycle - args.record as i64;
    Ok(Report {
        impacts_n: period_m.map(|m| contacts(last_cycle - m as i64)),
        contacts_in_window: contacts(window_start),
        events: log.0,
        period_m,
        residual,
        max_period_searched,
        max_tip: max_tip.maximum,
        energy_imbalance: budget.map(|b| b.relative_imbalance()),
        condition: sim.condition(),
        outcome: "completed".into(),
        final_clock: Clock::at_cycle(period, last_cycle),
        final_state: x,
        dense: args.dense.map(|_| dense.out),
    })
}

/// One dense sample of the rigid model: in contact when the tip rests on the stop.
fn rigid_sample(model: &RigidImpact, t: f64, x: &DVector<f64>, dense: &mut DenseOut) {
    let m = model.sim.model();
    let n = m.modes();
    let tip = m.tip().dot(&x.rows(0, n));
    let velocity = m.tip().dot(&x.rows(n, n));
    dense.push(t, model.at_rest_on_stop(x), tip, velocity, x);
}

/// One period of the window in `pieces` equal pieces, chained (the dense output).
fn rigid_dense_period(
    model: &RigidImpact,
    x: &DVector<f64>,
    cycle: i64,
    pieces: usize,
    dense: &mut DenseOut,
) -> Result<RigidRun, Error> {
    let period = model.sim.period();
    if dense.t.is_empty() {
        rigid_sample(model, cycle as f64 * period, x, dense);
    }
    let mut clock = Clock::at_cycle(period, cycle);
    let mut state = x.clone();
    let mut joined: Option<RigidRun> = None;
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
        rigid_sample(model, clock.time(), &state, dense);
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
    joined.ok_or_else(|| Error::Unsupported("a period in no pieces".into()))
}

fn rigid(
    model: &RigidImpact,
    x0: &DVector<f64>,
    args: &Args,
    reporter: &Reporter,
) -> Result<Report, Error> {
    let period = model.sim.period();
    let condition = model.sim.flow(Region::Free).condition();
    let (mut x, mut cycle) = (x0.clone(), 0i64);
    let mut outcome = Outcome::Completed;
    let mut final_clock = Clock::at_cycle(period, 0);
    let (mut events, mut strobe_states) = (Vec::new(), Vec::new());
    let mut dense = DenseOut::default();
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
        let r = match args.dense {
            Some(pieces) if recording => {
                rigid_dense_period(model, &x, cycle, pieces.max(1), &mut dense)?
            }
            _ => model.run_until(
                &x,
                Clock::at_cycle(period, cycle),
                Clock::at_cycle(period, cycle + step as i64),
            )?,
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
        }
        outcome = r.outcome;
        x = r.state;
        final_clock = r.clock;
        if outcome == Outcome::Completed {
            cycle += step as i64;
            done += step;
            if recording {
                strobe_states.push(x.clone());
            }
        }
        reporter.report("simulate: periods", done, total);
        if reporter.stopped() {
            return Err(Error::Unsupported("interrupted".into()));
        }
    }
    // as the compliant model's: the window's end is the final state, not a sample
    if outcome == Outcome::Completed {
        dense.pop();
    }
    let (period_m, residual, max_period_searched) = period_search(args, &strobe_states);
    let impacts = |from: i64| events.iter().filter(|e| e.cycle >= from).count() as u64;
    let chatter = "impacts accumulate (chatter), and this law changes the velocity orthogonal to the tip at every impact, so the chatter has no sticking limit (use law impulse-response)";
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
        impacts_n: period_m.map(|m| impacts(cycle - m as i64)),
        contacts_in_window: impacts(cycle - args.record as i64),
        events,
        period_m,
        residual,
        max_period_searched,
        max_tip: None,
        energy_imbalance: None,
        condition,
        outcome: outcome_text,
        final_clock,
        final_state: x,
        dense: args.dense.map(|_| dense),
    })
}

fn events_dict<'py>(py: Python<'py>, events: &[EventOut], n: usize) -> Res<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let col = |f: &dyn Fn(&EventOut) -> f64| -> Vec<f64> { events.iter().map(f).collect() };
    d.set_item("time", PyArray1::from_vec(py, col(&|e| e.time)))?;
    let cycles: Vec<i64> = events.iter().map(|e| e.cycle).collect();
    d.set_item("cycle", PyArray1::from_vec(py, cycles))?;
    d.set_item("phase", PyArray1::from_vec(py, col(&|e| e.phase)))?;
    let flags = |f: &dyn Fn(&EventOut) -> bool| -> Vec<bool> { events.iter().map(f).collect() };
    d.set_item("entering", PyArray1::from_vec(py, flags(&|e| e.entering)))?;
    d.set_item("grazing", PyArray1::from_vec(py, flags(&|e| e.grazing)))?;
    d.set_item(
        "tip_velocity",
        PyArray1::from_vec(py, col(&|e| e.tip_velocity)),
    )?;
    let rows = events.iter().map(|e| e.modal_velocities.as_slice());
    d.set_item("modal_velocities", matrix(py, rows, n)?)?;
    let rigid = events.first().is_some_and(|e| e.outgoing.is_some());
    if rigid {
        let out = col(&|e| e.outgoing.unwrap_or(f64::NAN));
        d.set_item("outgoing_tip_velocity", PyArray1::from_vec(py, out))?;
        let nan = vec![f64::NAN; n];
        let after = events
            .iter()
            .map(|e| e.modal_after.as_deref().unwrap_or(&nan));
        d.set_item("modal_velocities_after", matrix(py, after, n)?)?;
    } else {
        d.set_item("outgoing_tip_velocity", py.None())?;
        d.set_item("modal_velocities_after", py.None())?;
    }
    Ok(d)
}

fn dense_dict<'py>(py: Python<'py>, dense: DenseOut, n: usize) -> Res<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rows = dense.t.len();
    d.set_item("t", PyArray1::from_vec(py, dense.t))?;
    d.set_item("in_contact", PyArray1::from_vec(py, dense.contact))?;
    d.set_item("tip", PyArray1::from_vec(py, dense.tip))?;
    d.set_item("tip_velocity", PyArray1::from_vec(py, dense.velocity))?;
    let states = Array2::from_shape_vec((rows, 2 * n), dense.states)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("state", states.into_pyarray(py))?;
    Ok(d)
}

/// Simulates `model` from `start` (or `seed`, or rest): `periods` discarded, `record`
/// recorded. Returns a dict (see the Python layer's `Simulation`).
#[pyfunction]
#[pyo3(signature = (model, periods, record, start, seed, dense_per_period, periodicity_tolerance, max_period, progress))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    model: &Model,
    periods: i64,
    record: i64,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    dense_per_period: Option<i64>,
    periodicity_tolerance: f64,
    max_period: i64,
    progress: Option<Py<PyAny>>,
) -> Res<Bound<'py, PyDict>> {
    if !(0..=MAX_PERIODS as i64).contains(&periods) {
        return Err(bad(
            "periods",
            periods,
            &format!("an integer from 0 to {MAX_PERIODS}"),
        ));
    }
    if !(0..=MAX_RECORD as i64).contains(&record) {
        return Err(bad(
            "record",
            record,
            &format!("an integer from 0 to {MAX_RECORD}"),
        ));
    }
    if periods == 0 && record == 0 {
        return Err(bad("periods/record", 0, "at least one period in all"));
    }
    let max_period = count("max_period", max_period, 1000).map_err(crate::value_error)?;
    let dense = dense_per_period
        .map(|d| count("dense_per_period", d, 10_000))
        .transpose()
        .map_err(crate::value_error)?;
    if !(periodicity_tolerance > 0.0 && periodicity_tolerance < 1.0) {
        return Err(bad(
            "periodicity_tolerance",
            periodicity_tolerance,
            "a number in (0, 1)",
        ));
    }
    if let Some(per) = dense {
        // the dense output is held in memory (as the command line holds it before writing
        // its file): refuse one that would not fit rather than abort the interpreter
        let values = record as f64 * per as f64 * (2 * model.n() + 4) as f64;
        if values > MAX_DENSE_VALUES {
            return Err(bad(
                "dense_per_period",
                format!("{per} with record = {record} and N = {}", model.n()),
                "at most 2.5e8 numbers of dense output in all, record × dense_per_period × \
                 (2N + 4) (2 GB): record fewer periods or sample fewer per period",
            ));
        }
    }
    let (x0, from) = model.start(start, seed)?;
    let args = Args {
        periods: periods as u64,
        record: record as u64,
        dense,
        tolerance: periodicity_tolerance,
        max_period,
    };
    let reporter = Reporter::new(progress);
    let started = Instant::now();
    let result = py.detach(|| match &model.rigid {
        Some(r) => rigid(r, &x0, &args, &reporter),
        None => compliant(&model.sim, &x0, &args, &reporter),
    });
    let wall = started.elapsed().as_secs_f64();
    let report = reporter.finish(result)?;
    let n = model.n();
    let d = PyDict::new(py);
    d.set_item("events", events_dict(py, &report.events, n)?)?;
    d.set_item("period_m", report.period_m)?;
    d.set_item("periodicity_residual", report.residual)?;
    d.set_item("periodicity_tolerance", periodicity_tolerance)?;
    d.set_item("max_period_searched", report.max_period_searched)?;
    d.set_item("impacts_n", report.impacts_n)?;
    d.set_item("contacts_in_window", report.contacts_in_window)?;
    d.set_item("max_tip", report.max_tip.map(|m| m.value))?;
    d.set_item("max_tip_time", report.max_tip.map(|m| m.time))?;
    d.set_item("max_tip_tolerance", report.max_tip.map(|m| m.tolerance))?;
    d.set_item("energy_imbalance", report.energy_imbalance)?;
    d.set_item("eigenvector_condition", report.condition)?;
    d.set_item("outcome", report.outcome)?;
    let c = report.final_clock;
    d.set_item("final_time", c.time())?;
    d.set_item("final_cycle", c.cycles)?;
    d.set_item("final_phase", c.offset / c.period)?;
    d.set_item("final_state", crate::model::state(py, &report.final_state))?;
    match report.dense {
        Some(dense) => d.set_item("dense", dense_dict(py, dense, n)?)?,
        None => d.set_item("dense", py.None())?,
    }
    d.set_item("start", from)?;
    d.set_item("periods", periods)?;
    d.set_item("record", record)?;
    d.set_item("wall_seconds", wall)?;
    Ok(d)
}

/// The runs behind `simulate` with no interpreter in the loop (for timing the pure-Rust
/// call): the same work, the results dropped.
pub fn run_silently(
    model: &Model,
    x0: &DVector<f64>,
    periods: u64,
    record: u64,
    dense: Option<usize>,
) -> Result<(), Error> {
    let args = Args {
        periods,
        record,
        dense,
        tolerance: 1e-9,
        max_period: 32,
    };
    let reporter = Reporter::silent();
    match &model.rigid {
        Some(r) => rigid(r, x0, &args, &reporter).map(|_| ()),
        None => compliant(&model.sim, x0, &args, &reporter).map(|_| ()),
    }
}
