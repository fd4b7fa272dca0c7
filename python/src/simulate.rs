//! `simulate`: keyword arguments → the library's [`simulate`] (the same call `cantilever
//! simulate` makes, so the same runs and the same bits) → a dict of numpy arrays and
//! numbers, which the Python layer shapes into `Simulation`.

use crate::convert::{matrix, Reporter};
use crate::model::Model;
use crate::{py_error, Res};
use impacting_cantilever::analysis::simulate::{
    simulate as run, DenseOutput, SimEvent, SimulateOptions, DENSE_PER_PERIOD, MAX_PERIOD, PERIODS,
    RECORD,
};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::error::Error;
use nalgebra::DVector;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The library's options from the keyword arguments (integers checked by the library's
/// ranges, so a negative one is refused by name).
fn options(
    periods: i64,
    record: i64,
    dense_per_period: Option<i64>,
    periodicity_tolerance: f64,
    max_period: i64,
    energy: bool,
) -> Result<SimulateOptions, Error> {
    Ok(SimulateOptions {
        periods: PERIODS.check(periods.into())?,
        record: RECORD.check(record.into())?,
        dense_per_period: dense_per_period
            .map(|d| DENSE_PER_PERIOD.check(d.into()).map(|d| d as usize))
            .transpose()?,
        periodicity_tolerance,
        max_period: MAX_PERIOD.check(max_period.into())? as usize,
        energy,
    })
}

fn events_dict<'py>(py: Python<'py>, events: &[SimEvent], n: usize) -> Res<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let col = |f: &dyn Fn(&SimEvent) -> f64| -> Vec<f64> { events.iter().map(f).collect() };
    d.set_item("time", PyArray1::from_vec(py, col(&|e| e.time)))?;
    let cycles: Vec<i64> = events.iter().map(|e| e.cycle).collect();
    d.set_item("cycle", PyArray1::from_vec(py, cycles))?;
    d.set_item("phase", PyArray1::from_vec(py, col(&|e| e.phase)))?;
    let flags = |f: &dyn Fn(&SimEvent) -> bool| -> Vec<bool> { events.iter().map(f).collect() };
    d.set_item("entering", PyArray1::from_vec(py, flags(&|e| e.entering)))?;
    d.set_item("grazing", PyArray1::from_vec(py, flags(&|e| e.grazing)))?;
    d.set_item(
        "tip_velocity",
        PyArray1::from_vec(py, col(&|e| e.tip_velocity)),
    )?;
    let rows = events.iter().map(|e| e.modal_velocities.as_slice());
    d.set_item("modal_velocities", matrix(py, rows, n)?)?;
    let rigid = events
        .first()
        .is_some_and(|e| e.outgoing_tip_velocity.is_some());
    if rigid {
        let out = col(&|e| e.outgoing_tip_velocity.unwrap_or(f64::NAN));
        d.set_item("outgoing_tip_velocity", PyArray1::from_vec(py, out))?;
        let nan = vec![f64::NAN; n];
        let after = events
            .iter()
            .map(|e| e.modal_velocities_after.as_deref().unwrap_or(&nan));
        d.set_item("modal_velocities_after", matrix(py, after, n)?)?;
    } else {
        d.set_item("outgoing_tip_velocity", py.None())?;
        d.set_item("modal_velocities_after", py.None())?;
    }
    Ok(d)
}

fn dense_dict<'py>(py: Python<'py>, dense: DenseOutput, n: usize) -> Res<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rows = dense.len();
    d.set_item("t", PyArray1::from_vec(py, dense.t))?;
    d.set_item("in_contact", PyArray1::from_vec(py, dense.in_contact))?;
    d.set_item("tip", PyArray1::from_vec(py, dense.tip))?;
    d.set_item("tip_velocity", PyArray1::from_vec(py, dense.tip_velocity))?;
    let states = Array2::from_shape_vec((rows, 2 * n), dense.states)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("state", states.into_pyarray(py))?;
    Ok(d)
}

/// Simulates `model` from `start` (or `seed`, or rest): `periods` discarded, `record`
/// recorded. Returns a dict (see the Python layer's `Simulation`).
#[pyfunction]
#[pyo3(signature = (model, periods, record, start, seed, dense_per_period, periodicity_tolerance, max_period, progress, energy=true))]
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
    energy: bool,
) -> Res<Bound<'py, PyDict>> {
    let o = options(
        periods,
        record,
        dense_per_period,
        periodicity_tolerance,
        max_period,
        energy,
    )
    .map_err(py_error)?;
    o.check(model.n()).map_err(py_error)?;
    let (x0, from) = model.start(start, seed)?;
    let s = Reporter::new(progress).run(py, |r| run(&model.built, &x0, &o, r))?;
    let n = model.n();
    let d = PyDict::new(py);
    d.set_item("events", events_dict(py, &s.events, n)?)?;
    d.set_item("period_m", s.period_m)?;
    d.set_item("periodicity_residual", s.periodicity_residual)?;
    d.set_item("periodicity_tolerance", periodicity_tolerance)?;
    d.set_item("max_period_searched", s.max_period_searched)?;
    d.set_item("impacts_n", s.impacts_n)?;
    d.set_item("impacts_n_range", s.impacts_n_range)?;
    d.set_item("contacts_in_window", s.contacts_in_window)?;
    d.set_item("shallow_flights", s.shallow_flights)?;
    d.set_item("flight_resolution", s.flight_resolution)?;
    d.set_item("max_tip", s.max_tip.map(|m| m.value))?;
    d.set_item("max_tip_time", s.max_tip.map(|m| m.time))?;
    d.set_item("max_tip_tolerance", s.max_tip.map(|m| m.tolerance))?;
    d.set_item("energy_imbalance", s.energy_imbalance)?;
    d.set_item("energy_imbalance_bound", s.energy_imbalance_bound)?;
    d.set_item("eigenvector_condition", s.condition)?;
    d.set_item("outcome", s.ending.to_string())?;
    let c = s.final_clock;
    d.set_item("final_time", c.time())?;
    d.set_item("final_cycle", c.cycles)?;
    d.set_item("final_phase", c.offset / c.period)?;
    d.set_item("final_state", crate::model::state(py, &s.final_state))?;
    match s.dense {
        Some(dense) => d.set_item("dense", dense_dict(py, dense, n)?)?,
        None => d.set_item("dense", py.None())?,
    }
    d.set_item("start", from)?;
    d.set_item("periods", periods)?;
    d.set_item("record", record)?;
    d.set_item("wall_seconds", s.wall_seconds)?;
    Ok(d)
}

/// The library's `simulate` with no interpreter in the loop (for timing the pure-Rust
/// call): the same work, the results dropped.
pub fn run_silently(
    model: &Model,
    x0: &DVector<f64>,
    periods: u64,
    record: u64,
    dense_per_period: Option<usize>,
) -> Result<(), Error> {
    let o = SimulateOptions {
        periods,
        record,
        dense_per_period,
        ..SimulateOptions::default()
    };
    run(&model.built, x0, &o, &Silent).map(|_| ())
}
