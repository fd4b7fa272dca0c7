//! `impacting_cantilever._core`: the Python face of the `impacting-cantilever` library.
//!
//! A thin layer over the library's public API: keyword arguments are mapped onto the
//! library's model specification and options, each call is one call of the library (the
//! same the `cantilever` command line makes), and results leave as numpy arrays or as the
//! JSON-shaped data the command line prints, which the Python package
//! (`impacting_cantilever/`) shapes into typed result objects.
//!
//! Errors: every failure of the library becomes the exception class of its kind
//! (`impacting_cantilever.errors`: `ParameterError` — also a `ValueError` —, `NoPeriodError`,
//! `NotConvergedError`, `ChatterError`, `UnsupportedError`, `CancelledError`, ...), whose
//! message is the library's one-line message (the text the command line prints after
//! `error: `). Long work runs with the interpreter released (`Python::detach`), so other
//! Python threads go on, and reports to an optional progress callback
//! `progress(what, done, total)`.

mod analysis;
mod convert;
mod model;
mod results;
mod simulate;

use impacting_cantilever::error::Error;
use pyo3::prelude::*;

/// The exception class of each kind of library error (in `impacting_cantilever.errors`).
pub(crate) fn class_of(e: &Error) -> &'static str {
    match e.kind() {
        "parameter" => "ParameterError",
        "no-period" => "NoPeriodError",
        "not-converged" => "NotConvergedError",
        "chatter" => "ChatterError",
        "unsupported" => "UnsupportedError",
        "interrupted" => "CancelledError",
        "io" => "OutputError",
        "invariant" => "InvariantError",
        _ => "NumericalError",
    }
}

/// A library error as the Python exception of its kind, carrying its one-line message (and,
/// for `NotConvergedError`, the residual it stopped at).
pub(crate) fn py_error(e: impl Into<Error>) -> PyErr {
    let e = e.into();
    let message = e.to_string();
    Python::attach(|py| {
        let raised = (|| -> PyResult<PyErr> {
            let class = py
                .import("impacting_cantilever.errors")?
                .getattr(class_of(&e))?;
            let residual = match &e {
                Error::NotConverged { residual, .. } => *residual,
                _ => None,
            };
            let exc = class.call1((message.clone(),))?;
            if let Some(r) = residual {
                exc.setattr("residual", r)?;
            }
            Ok(PyErr::from_value(exc))
        })();
        // the package's module is always there; a broken install still raises, plainly
        raised.unwrap_or_else(|_| pyo3::exceptions::PyValueError::new_err(message))
    })
}

/// A parameter error of this layer (a keyword the library does not see), in the library's
/// format.
pub(crate) fn bad(name: &str, value: impl std::fmt::Display, allowed: &str) -> PyErr {
    py_error(impacting_cantilever::error::ParameterError::new(
        name, value, allowed,
    ))
}

/// Extension-module result.
pub(crate) type Res<T> = PyResult<T>;

/// The Python face of the `impacting-cantilever` library (Melcher, Champneys & Wagg 2013).
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use impacting_cantilever::model::spec::defaults;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DEFAULT_STOP_STIFFNESS", defaults::STOP_STIFFNESS)?;
    m.add("DEFAULT_RESTITUTION", defaults::RESTITUTION)?;
    m.add_class::<model::Model>()?;
    m.add_class::<results::SceneRun>()?;
    m.add_function(wrap_pyfunction!(model::compliant, m)?)?;
    m.add_function(wrap_pyfunction!(model::rigid, m)?)?;
    m.add_function(wrap_pyfunction!(model::oscillator, m)?)?;
    m.add_function(wrap_pyfunction!(model::problem, m)?)?;
    m.add_function(wrap_pyfunction!(model::units, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::find_orbit, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::continue_branch, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::continue_curve, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::energetic_restitution, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::find_orbits, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::motion, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::modes_needed, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::time_rust, m)?)?;
    m.add_function(wrap_pyfunction!(results::scene_list, m)?)?;
    m.add_function(wrap_pyfunction!(results::scene_run, m)?)?;
    m.add_function(wrap_pyfunction!(results::scene_restore, m)?)?;
    m.add_function(wrap_pyfunction!(results::citations, m)?)?;
    m.add_function(wrap_pyfunction!(results::cite, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_params, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_shard, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_merge, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_build, m)?)?;
    Ok(())
}
