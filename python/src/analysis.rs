//! What is computed from runs: periodic orbits (`find_orbit`), branches (`continue_branch`),
//! the energetic coefficient of restitution r_E (eq 39) and the modes a stop needs — each
//! one call of the library, run with the interpreter released.

use crate::convert::{json_to_py, Reporter};
use crate::model::{state, Beam, Model};
use crate::{bad, value_error, Res};
use impacting_cantilever::analysis::continuation::{self, Family, Parameter, Settings};
use impacting_cantilever::analysis::convergence;
use impacting_cantilever::analysis::energetic::orbit_coefficient;
use impacting_cantilever::analysis::find_orbit::{self as library, FoundOrbit, OrbitOptions};
use impacting_cantilever::analysis::shooting;
use impacting_cantilever::error::Error;
use nalgebra::DVector;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A count given as any integer: negative ones are refused with the library's range.
fn non_negative(name: &str, value: i64, allowed: &str) -> Res<u64> {
    u64::try_from(value).map_err(|_| bad(name, value, allowed))
}

/// The library's orbit options from the Python arguments.
fn options(
    transient: i64,
    window: i64,
    period: Option<i64>,
    period_tolerance: f64,
    max_iterations: i64,
    restitution: bool,
) -> Res<OrbitOptions> {
    Ok(OrbitOptions {
        transient: non_negative("transient", transient, "0 to 1e8 periods")?,
        window: non_negative("window", window, "2 to 10 000 periods")?,
        period: period
            .map(|m| non_negative("period m", m, "1 to 64"))
            .transpose()?,
        period_tolerance,
        max_iterations: non_negative("max_iterations", max_iterations, "1 to 1000")? as usize,
        restitution,
    })
}

fn orbit_of(model: &Model, x0: &DVector<f64>, o: &OrbitOptions) -> Result<FoundOrbit, Error> {
    match &model.rigid {
        Some(r) => library::find_orbit(r, x0, o),
        None => library::find_orbit(&model.sim, x0, o),
    }
}

/// The periodic orbit `model` settles on from the start (see the Python layer's
/// `find_orbit`).
#[pyfunction]
#[pyo3(signature = (model, start, seed, transient, window, period, period_tolerance, max_iterations, restitution))]
#[allow(clippy::too_many_arguments)]
pub fn find_orbit<'py>(
    py: Python<'py>,
    model: &Model,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    transient: i64,
    window: i64,
    period: Option<i64>,
    period_tolerance: f64,
    max_iterations: i64,
    restitution: bool,
) -> Res<Bound<'py, PyDict>> {
    let o = options(
        transient,
        window,
        period,
        period_tolerance,
        max_iterations,
        restitution,
    )?;
    let (x0, from) = model.start(start, seed)?;
    let reporter = Reporter::new(None);
    let result = py.detach(|| orbit_of(model, &x0, &o));
    let f = reporter.finish(result)?;
    let d = PyDict::new(py);
    d.set_item("state", state(py, &f.state))?;
    d.set_item("period_m", f.period_m)?;
    d.set_item("impacts_n", f.impacts_n)?;
    d.set_item("multipliers", PyArray1::from_vec(py, f.multipliers.clone()))?;
    d.set_item("stable", f.stable)?;
    d.set_item("residual", f.residual)?;
    d.set_item("iterations", f.iterations)?;
    d.set_item("energetic_restitution", f.energetic_restitution)?;
    d.set_item("spectral_radius", f.spectral_radius())?;
    d.set_item("start", from)?;
    Ok(d)
}

/// A branch of periodic orbits continued in k/k₁ or ω/(β₁⁻)², as `cantilever continue`
/// traces it; returns its JSON document's fields as Python objects.
#[pyfunction]
#[pyo3(signature = (model, parameter, to, one_way, max_step, doubling_up_to, start, seed, transient, window, period, progress))]
#[allow(clippy::too_many_arguments)]
pub fn continue_branch<'py>(
    py: Python<'py>,
    model: &Model,
    parameter: &str,
    to: f64,
    one_way: bool,
    max_step: f64,
    doubling_up_to: i64,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    transient: i64,
    window: i64,
    period: Option<i64>,
    progress: Option<Py<PyAny>>,
) -> Res<Bound<'py, PyAny>> {
    let base = match (&model.beam, &model.rigid) {
        (Beam::Cantilever(c), None) => c.clone(),
        _ => {
            return Err(value_error(Error::Unsupported(
                "continuation is built for the compliant cantilever model (the rigid model's \
                 orbits can be followed by find_orbit from the previous orbit; the oscillator's \
                 parameters are not in the units k/k₁, ω/(β₁⁻)²)"
                    .into(),
            )))
        }
    };
    let (which, p0) = match parameter {
        "stop_stiffness" => (Parameter::StopStiffness, base.stop_stiffness),
        "omega" => (Parameter::Frequency, base.omega),
        other => return Err(bad("parameter", other, "stop_stiffness or omega")),
    };
    if !(to.is_finite() && to > 0.0 && to != p0) {
        return Err(bad(
            "to",
            to,
            "a finite value > 0 other than the start value",
        ));
    }
    if !(1e-4..=0.2).contains(&max_step) {
        return Err(bad("max_step", max_step, "1e-4 to 0.2"));
    }
    if !(1..=64).contains(&doubling_up_to) {
        return Err(bad("doubling_up_to", doubling_up_to, "1 to 64"));
    }
    let o = options(
        transient,
        window,
        period,
        1e-3,
        shooting::MAX_ITERATIONS as i64,
        false,
    )?;
    let (x0, _) = model.start(start, seed)?;
    let reporter = Reporter::new(progress);
    let built = AtomicU64::new(0);
    let result = py.detach(|| {
        // the start orbit, found as `cantilever orbit` finds it
        let start = library::find_orbit(&model.sim, &x0, &o)?;
        let family = Family::new(which, |p| {
            let done = built.fetch_add(1, Ordering::Relaxed) + 1;
            reporter.report("continuation: orbits", done, 0);
            if reporter.stopped() {
                return Err(Error::Unsupported("interrupted".into()));
            }
            let mut c = base.clone();
            match which {
                Parameter::StopStiffness => c.stop_stiffness = p,
                Parameter::Frequency => c.omega = p,
                // not offered here (`parameter` is stop_stiffness or omega); the model's gap
                Parameter::Gap => c.gap = p,
            }
            Ok(c.model()?)
        });
        let other = if one_way { p0 } else { p0 * p0 / to };
        let settings = Settings {
            max_step,
            initial_step: max_step.min(0.01),
            max_period: doubling_up_to as u64,
            ..Settings::new((to.min(other), to.max(other)))
        };
        let x = start.state.clone();
        let m = start.period_m;
        let mut branches = if one_way {
            let dir = (to - p0).signum();
            vec![continuation::continue_branch(
                &family, &x, p0, m, dir, &settings,
            )?]
        } else {
            continuation::trace(&family, &x, p0, m, &settings)?
        };
        // branch 0 runs up; put the one towards `to` first
        if !one_way && to < p0 && branches.len() > 1 {
            branches.swap(0, 1);
        }
        Ok(serde_json::json!({
            "parameter": which.symbol(),
            "start": p0,
            "modes": base.modes,
            "branches": branches,
        }))
    });
    let doc = reporter.finish(result)?;
    json_to_py(py, &doc)
}

/// r_E (eq 39) of the orbit the compliant model settles on, with each contact's r̃_E (eq 38).
#[pyfunction]
#[pyo3(signature = (model, start, seed, transient, window))]
pub fn energetic_restitution<'py>(
    py: Python<'py>,
    model: &Model,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    transient: i64,
    window: i64,
) -> Res<Bound<'py, PyAny>> {
    if model.rigid.is_some() {
        return Err(value_error(Error::Unsupported(
            "r_E (eqs 38–39) weighs the work of the compliant contact force on mode 1; the \
             rigid-impact model has no contact force — its restitution is its law"
                .into(),
        )));
    }
    if !(0..=100_000_000).contains(&transient) {
        return Err(bad("transient", transient, "0 to 1e8 periods"));
    }
    if !(2..=10_000).contains(&window) {
        return Err(bad("window", window, "2 to 10 000 periods"));
    }
    let (x0, _) = model.start(start, seed)?;
    let reporter = Reporter::new(None);
    let result = py.detach(|| {
        let o = orbit_coefficient(&model.sim, &x0, transient as u64, window as u64)?;
        serde_json::to_value(&o).map_err(|e| Error::Unsupported(e.to_string()))
    });
    let doc = reporter.finish(result)?;
    json_to_py(py, &doc)
}

/// How many modes resolve a stop of stiffness k/k₁ to a relative accuracy, as
/// `cantilever modes-needed --json` gives it.
#[pyfunction]
pub fn modes_needed(
    py: Python<'_>,
    stop_stiffness: f64,
    tolerance: f64,
    zeta1: f64,
) -> Res<Bound<'_, PyAny>> {
    let reporter = Reporter::new(None);
    let result = py.detach(|| {
        let m = convergence::modes_needed(stop_stiffness, tolerance, zeta1)?;
        serde_json::to_value(&m).map_err(|e| Error::Unsupported(e.to_string()))
    });
    let doc = reporter.finish(result)?;
    json_to_py(py, &doc)
}

/// The processor time of the calling thread, in seconds.
fn thread_time() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    if ok {
        t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
    } else {
        f64::NAN
    }
}

/// (wall time, processor time of the thread) of `repeats` pure-Rust calls — `find_orbit`
/// from rest with the default options, or the library runs behind `simulate` — measured
/// inside the extension with no Python in the loop: the reference for the binding's
/// overhead.
#[pyfunction]
#[pyo3(signature = (model, what, repeats, periods=0, record=1, dense_per_period=None))]
pub fn time_rust(
    py: Python<'_>,
    model: &Model,
    what: &str,
    repeats: usize,
    periods: u64,
    record: u64,
    dense_per_period: Option<usize>,
) -> Res<Vec<(f64, f64)>> {
    let x0 = DVector::zeros(2 * model.n());
    let o = OrbitOptions::default();
    let one = || -> Result<(), Error> {
        match what {
            "find_orbit" => orbit_of(model, &x0, &o).map(|_| ()),
            "simulate" => {
                crate::simulate::run_silently(model, &x0, periods, record, dense_per_period)
            }
            other => Err(Error::Unsupported(format!("no timing of {other}"))),
        }
    };
    let result = py.detach(|| {
        (0..repeats)
            .map(|_| {
                let (wall, cpu) = (Instant::now(), thread_time());
                one().map(|()| (wall.elapsed().as_secs_f64(), thread_time() - cpu))
            })
            .collect::<Result<Vec<_>, _>>()
    });
    result.map_err(value_error)
}
