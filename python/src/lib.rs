//! `impacting_cantilever._core`: the Python face of the `impacting-cantilever` library.
//!
//! A thin layer over the library's public API: models are built and validated here, every
//! computation is the library's own (the same code the `cantilever` command line runs), and
//! results leave as numpy arrays or as the JSON-shaped data the command line prints, which
//! the Python package (`impacting_cantilever/`) shapes into typed result objects.
//!
//! Errors: every failure of the library becomes a Python `ValueError` whose message is the
//! library's one-line message (the text the command line prints after `error: `). Long work
//! runs with the interpreter released (`Python::detach`), so other Python threads go on, and
//! reports to an optional progress callback `progress(what, done, total)`.

mod analysis;
mod convert;
mod model;
mod results;
mod simulate;
mod spec;

use impacting_cantilever::error::{Error, ParameterError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A library error as the Python `ValueError` carrying its one-line message.
pub(crate) fn value_error(e: impl Into<Error>) -> PyErr {
    PyValueError::new_err(e.into().to_string())
}

/// A parameter error of this layer, in the library's format.
pub(crate) fn bad(name: &str, value: impl std::fmt::Display, allowed: &str) -> PyErr {
    value_error(ParameterError::new(name, value, allowed))
}

/// Extension-module result.
pub(crate) type Res<T> = PyResult<T>;

/// The Python face of the `impacting-cantilever` library (Melcher, Champneys & Wagg 2013).
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
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
    m.add_function(wrap_pyfunction!(analysis::energetic_restitution, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::modes_needed, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::time_rust, m)?)?;
    m.add_function(wrap_pyfunction!(results::scene_list, m)?)?;
    m.add_function(wrap_pyfunction!(results::scene_run, m)?)?;
    m.add_function(wrap_pyfunction!(results::citations, m)?)?;
    m.add_function(wrap_pyfunction!(results::cite, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_params, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_shard, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_merge, m)?)?;
    m.add_function(wrap_pyfunction!(results::atlas_build, m)?)?;
    Ok(())
}
