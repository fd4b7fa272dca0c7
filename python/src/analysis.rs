//! What is computed from runs: periodic orbits (`find_orbit`), branches (`continue_branch`),
//! curves of bifurcations in two parameters (`continue_curve`),
//! the energetic coefficient of restitution r_E (eq 39) and the modes a stop needs — each
//! one call of the library (the same call the command line makes), run with the
//! interpreter released.

use crate::convert::{json_to_py, Reporter};
use crate::model::{start_of, state, Model};
use crate::{bad, py_error, Res};
use impacting_cantilever::analysis::continuation::{continue_from, ContinueOptions, Parameter};
use impacting_cantilever::analysis::convergence;
use impacting_cantilever::analysis::curves::request::{curve_from, CurveOptions};
use impacting_cantilever::analysis::curves::CurveKind;
use impacting_cantilever::analysis::energetic;
use impacting_cantilever::analysis::find_orbit::{self as library, FoundOrbit, OrbitOptions};
use impacting_cantilever::analysis::orbit::{TRANSIENT, WINDOW};
use impacting_cantilever::error::Error;
use nalgebra::DVector;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::time::Instant;

/// The library's orbit options from the Python arguments (integers checked by the
/// library's ranges, so a negative one is refused by name).
fn options(
    transient: i64,
    window: i64,
    period: Option<i64>,
    period_tolerance: f64,
    max_iterations: i64,
    restitution: bool,
) -> Res<OrbitOptions> {
    Ok(OrbitOptions {
        transient: TRANSIENT.check(transient.into()).map_err(py_error)?,
        window: WINDOW.check(window.into()).map_err(py_error)?,
        period: period
            .map(|m| u64::try_from(m).map_err(|_| bad("period m", m, "1 to 64")))
            .transpose()?,
        period_tolerance,
        max_iterations: usize::try_from(max_iterations)
            .map_err(|_| bad("max_iterations", max_iterations, "1 to 1000"))?,
        restitution,
    })
}

/// The start orbit's options of a branch or a curve: the given transient, window and
/// period, the library's defaults for the rest.
fn start_orbit_options(transient: i64, window: i64, period: Option<i64>) -> Res<OrbitOptions> {
    options(
        transient,
        window,
        period,
        OrbitOptions::DEFAULTS.period_tolerance,
        OrbitOptions::DEFAULTS.max_iterations as i64,
        false,
    )
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
    // the transient reports to the reporter and stops on Ctrl-C
    let f: FoundOrbit = Reporter::new(None).run(py, |r| {
        library::find_orbit_reporting(&model.built, &x0, &o, r)
    })?;
    orbit_dict(py, &f, from)
}

/// A found orbit's fields, as the Python layer's `Orbit` takes them.
fn orbit_dict<'py>(py: Python<'py>, f: &FoundOrbit, from: String) -> Res<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("state", state(py, &f.state))?;
    d.set_item("period_m", f.period_m)?;
    d.set_item("impacts_n", f.impacts_n)?;
    d.set_item("impacts_n_range", f.impacts_n_range)?;
    d.set_item("multipliers", PyArray1::from_vec(py, f.multipliers.clone()))?;
    d.set_item("stable", f.stable)?;
    d.set_item("residual", f.residual)?;
    d.set_item("iterations", f.iterations)?;
    d.set_item("energetic_restitution", f.energetic_restitution)?;
    d.set_item("spectral_radius", f.spectral_radius())?;
    d.set_item("start", from)?;
    Ok(d)
}

/// The periodic orbit of each model from its start, in parallel (the Python layer's
/// `sweep`): each entry the orbit's fields, or the failure's (class, message, residual).
#[pyfunction]
#[pyo3(signature = (models, start, seed, transient, window, period, period_tolerance, max_iterations, restitution, progress, threads))]
#[allow(clippy::too_many_arguments)]
pub fn find_orbits<'py>(
    py: Python<'py>,
    models: Vec<PyRef<'py, Model>>,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    transient: i64,
    window: i64,
    period: Option<i64>,
    period_tolerance: f64,
    max_iterations: i64,
    restitution: bool,
    progress: Option<Py<PyAny>>,
    threads: Option<i64>,
) -> Res<Vec<Bound<'py, PyAny>>> {
    let o = options(
        transient,
        window,
        period,
        period_tolerance,
        max_iterations,
        restitution,
    )?;
    let start = start_of(start, seed)?;
    let mut starts = Vec::with_capacity(models.len());
    for m in &models {
        starts.push(m.built.start(&start).map_err(py_error)?);
    }
    let built: Vec<_> = models.iter().map(|m| m.built.clone()).collect();
    let xs: Vec<_> = starts.iter().map(|(x, _)| x.clone()).collect();
    let found = Reporter::new(progress)
        .threads(threads)?
        .run(py, |r| library::find_orbits(&built, &xs, &o, r))?;
    found
        .into_iter()
        .zip(starts)
        .map(|(f, (_, from))| match f {
            Ok(f) => Ok(orbit_dict(py, &f, from)?.into_any()),
            Err(e) => {
                let residual = match &e {
                    Error::NotConverged { residual, .. } => *residual,
                    _ => None,
                };
                let failure = (crate::class_of(&e), e.to_string(), residual);
                Ok(failure.into_pyobject(py)?.into_any())
            }
        })
        .collect()
}

/// A branch of periodic orbits continued in k/k₁, ω/(β₁⁻)² or d₀, as `cantilever continue`
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
    let which = parameter_named(parameter, "parameter")?;
    let orbit = start_orbit_options(transient, window, period)?;
    let start = start_of(start, seed)?;
    let o = ContinueOptions {
        parameter: which,
        to,
        one_way,
        max_step,
        doubling_up_to: u64::try_from(doubling_up_to)
            .map_err(|_| bad("doubling_up_to", doubling_up_to, "1 to 64"))?,
    };
    let spec = model.built.spec();
    let doc = Reporter::new(progress).run(py, |r| {
        let c = continue_from(spec, &start, &orbit, &o, r)?;
        serde_json::to_value(&c).map_err(|e| Error::Unsupported(e.to_string()))
    })?;
    json_to_py(py, &doc)
}

/// A parameter by its keyword.
fn parameter_named(name: &str, what: &str) -> Res<Parameter> {
    match name {
        "stop_stiffness" => Ok(Parameter::StopStiffness),
        "omega" => Ok(Parameter::Frequency),
        "gap" => Ok(Parameter::Gap),
        other => Err(bad(what, other, "stop_stiffness, omega or gap")),
    }
}

/// The curve of folds, period doublings, Neimark–Sacker points or grazings in two parameters through the model's
/// orbit (see the Python layer's `continue_curve`).
#[pyfunction]
#[pyo3(signature = (model, kind, parameter, second, range, second_range, max_step, max_points, start, seed, transient, window, period, progress, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn continue_curve<'py>(
    py: Python<'py>,
    model: &Model,
    kind: &str,
    parameter: &str,
    second: &str,
    range: (f64, f64),
    second_range: (f64, f64),
    max_step: f64,
    max_points: i64,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    transient: i64,
    window: i64,
    period: Option<i64>,
    progress: Option<Py<PyAny>>,
    threads: Option<i64>,
) -> Res<Bound<'py, PyAny>> {
    let kind = match kind {
        "fold" => CurveKind::Fold,
        "period_doubling" => CurveKind::PeriodDoubling,
        "grazing" => CurveKind::Grazing,
        "neimark_sacker" => CurveKind::NeimarkSacker,
        other => {
            return Err(bad(
                "kind",
                other,
                "fold, period_doubling, grazing or neimark_sacker",
            ))
        }
    };
    let orbit = start_orbit_options(transient, window, period)?;
    let start = start_of(start, seed)?;
    let o = CurveOptions {
        kind,
        parameter: parameter_named(parameter, "parameter")?,
        second: parameter_named(second, "second")?,
        range,
        second_range,
        max_step,
        max_points: u64::try_from(max_points)
            .map_err(|_| bad("max_points", max_points, "2 to 20000"))?,
    };
    let spec = model.built.spec();
    let doc = Reporter::new(progress).threads(threads)?.run(py, |r| {
        let c = curve_from(spec, &start, &orbit, &o, r)?;
        serde_json::to_value(&c).map_err(|e| Error::Unsupported(e.to_string()))
    })?;
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
    let transient = TRANSIENT.check(transient.into()).map_err(py_error)?;
    let window = WINDOW.check(window.into()).map_err(py_error)?;
    let (x0, _) = model.start(start, seed)?;
    let doc = Reporter::new(None).run(py, |r| {
        let o =
            energetic::energetic_restitution_reporting(&model.built, &x0, transient, window, r)?;
        serde_json::to_value(&o).map_err(|e| Error::Unsupported(e.to_string()))
    })?;
    json_to_py(py, &doc)
}

/// What the motion from the start is — chaotic, quasi-periodic, periodic or undecided —
/// with its two largest Lyapunov exponents, its period and rotation number, by the book's
/// rule (`cantilever motion --json`: the motion's fields and the options used).
#[pyfunction]
#[pyo3(signature = (model, start, seed, transient, segments, segment_periods, iterates, longest_period, resolution, progress))]
#[allow(clippy::too_many_arguments)]
pub fn motion<'py>(
    py: Python<'py>,
    model: &Model,
    start: Option<PyReadonlyArray1<'py, f64>>,
    seed: Option<u64>,
    transient: i64,
    segments: Option<i64>,
    segment_periods: Option<i64>,
    iterates: Option<i64>,
    longest_period: Option<i64>,
    resolution: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> Res<Bound<'py, PyAny>> {
    use impacting_cantilever::analysis::motion::{classify, MotionOptions, MotionOverrides};
    let whole =
        |name: &str, v: i64| u64::try_from(v).map_err(|_| bad(name, v, "a whole number ≥ 0"));
    let opt = |name: &str, v: Option<i64>| v.map(|v| whole(name, v)).transpose();
    let changed = MotionOverrides {
        segments: opt("segments", segments)?.map(|v| v as usize),
        periods: opt("segment_periods", segment_periods)?,
        iterates: opt("iterates", iterates)?.map(|v| v as usize),
        longest_period: opt("longest_period", longest_period)?,
        resolution,
    };
    let transient = whole("transient", transient)?;
    let (x0, from) = model.start(start, seed)?;
    let options = MotionOptions::for_model_with(model.built.galerkin(), transient, &changed);
    let doc = Reporter::new(progress).run(py, |r| {
        // the library's "periods" (per segment) is this function's segment_periods
        let m = classify(&model.built, &x0, &options, r).map_err(|e| match e {
            Error::Parameter(mut p) if p.name == "periods" => {
                p.name = "segment_periods".into();
                Error::Parameter(p)
            }
            e => e,
        })?;
        let mut v = serde_json::to_value(&m).map_err(|e| Error::Unsupported(e.to_string()))?;
        v["options"] =
            serde_json::to_value(options).map_err(|e| Error::Unsupported(e.to_string()))?;
        Ok(v)
    })?;
    let d = json_to_py(py, &doc)?;
    d.set_item("start", from)?;
    Ok(d)
}

/// How many modes resolve a stop of stiffness k/k₁ to a relative accuracy, as
/// `cantilever modes-needed --json` gives it.
#[pyfunction]
#[pyo3(signature = (stop_stiffness, tolerance, zeta1, threads=None))]
pub fn modes_needed(
    py: Python<'_>,
    stop_stiffness: f64,
    tolerance: f64,
    zeta1: f64,
    threads: Option<i64>,
) -> Res<Bound<'_, PyAny>> {
    let doc = Reporter::new(None).threads(threads)?.run(py, |_| {
        let m = convergence::modes_needed(stop_stiffness, tolerance, zeta1)?;
        serde_json::to_value(&m).map_err(|e| Error::Unsupported(e.to_string()))
    })?;
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
            "find_orbit" => library::find_orbit(&model.built, &x0, &o).map(|_| ()),
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
    result.map_err(py_error)
}
