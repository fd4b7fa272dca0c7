//! Continuation as one call from a model's specification, for every front end: the start
//! orbit found as [`find_orbit`](crate::analysis::find_orbit::find_orbit) finds it, then the branch through it in k/k₁, ω/(β₁⁻)² or
//! d₀, both ways unless asked for one. The command line's `continue` and the Python
//! package's `continue_branch` are this function with their names for its options.
//!
//! Supported: the compliant cantilever. The rigid-impact model is refused: its branches
//! would need the saltation matrices inside the corrector and a grazing that changes the
//! impact sequence (a discontinuity of the map, not a C¹ passage as for the compliant
//! stop), which this continuation does not handle. The oscillator is refused too: its
//! parameters are not in the units k/k₁, ω/(β₁⁻)².

use super::{continue_branch, trace, Branch, Family, Parameter, Settings};
use crate::analysis::find_orbit::{find_orbit_reporting, OrbitOptions};
use crate::base::progress::Progress;
use crate::engine::built::BuiltModel;
use crate::error::{self, Error, ParameterError};
use crate::model::ranges::{Count, Range};
use crate::model::spec::{ModelSpec, Start, Stop, Structure};
use serde::Serialize;

/// The largest step in ln p (also the spacing of the points).
pub const MAX_STEP: Range = Range {
    name: "max_step",
    symbol: "in ln p",
    lo: 1e-4,
    hi: 0.2,
    why: "below 1e-4 a branch of a decade takes over 20 000 points; above 0.2 the predictor \
          leaves the corrector's basin",
};

/// Period doublings are followed up to this period.
pub const DOUBLING_UP_TO: Count = Count {
    name: "doubling_up_to",
    symbol: "",
    min: 1,
    max: 64,
    why: "the orbit finder reads periods up to 64",
};

/// Where a branch goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinueOptions {
    /// The parameter continued; the branch starts at its value in the specification.
    pub parameter: Parameter,
    /// Where to continue to (> 0); unless `one_way`, the branch also goes back past the
    /// start to start²/to (the same factor the other way).
    pub to: f64,
    /// Only towards `to`, one branch (its period doublings are reported, not followed).
    pub one_way: bool,
    /// [`MAX_STEP`].
    pub max_step: f64,
    /// [`DOUBLING_UP_TO`] (1: no branch switching).
    pub doubling_up_to: u64,
}

/// The branches and what they started from.
#[derive(Debug, Clone, Serialize)]
pub struct Continuation {
    /// "k/k₁", "ω/(β₁⁻)²" or "d₀".
    pub parameter: &'static str,
    /// The start orbit's parameter value.
    pub start: f64,
    /// N.
    pub modes: usize,
    /// The branches (0: towards `to`; then the other way; then period-doubled ones).
    pub branches: Vec<Branch>,
}

/// The keyword of a continuation parameter (the command line's `--parameter` value with
/// `_` for `-`).
pub fn keyword(p: Parameter) -> &'static str {
    match p {
        Parameter::StopStiffness => "stop_stiffness",
        Parameter::Frequency => "omega",
        Parameter::Gap => "gap",
    }
}

/// The specification with the continued parameter at `p`.
pub(crate) fn at(spec: &ModelSpec, parameter: Parameter, p: f64) -> ModelSpec {
    let mut s = spec.clone();
    match (&mut s.structure, &mut s.stop, parameter) {
        (_, Stop::Compliant { stop_stiffness }, Parameter::StopStiffness) => *stop_stiffness = p,
        (Structure::Cantilever(c), _, Parameter::Frequency) => c.omega = p,
        (Structure::Cantilever(c), _, Parameter::Gap) => c.gap = p,
        _ => {}
    }
    s
}

/// Traces the branch through the orbit `spec` settles on from `start`.
///
/// # Errors
/// [`Error::Parameter`] for options out of range, a start value of the parameter that is
/// not > 0, or a `to` the model does not accept; [`Error::Unsupported`] for the rigid model
/// or the oscillator; the start orbit's errors ([`find_orbit`](crate::analysis::find_orbit::find_orbit)); [`Error::NotConverged`]
/// when the branch cannot be started; [`Error::Interrupted`] when `progress` is cancelled.
pub fn continue_from(
    spec: &ModelSpec,
    start: &Start,
    orbit: &OrbitOptions,
    options: &ContinueOptions,
    progress: &dyn Progress,
) -> Result<Continuation, Error> {
    let c =
        match (&spec.structure, &spec.stop) {
            (Structure::Cantilever(c), Stop::Compliant { .. }) => c,
            (_, Stop::Rigid { .. }) => {
                return Err(Error::Unsupported(
                    "continuation is built for the compliant model: the rigid-impact model's \
                 branches would need its saltation matrices in the corrector, and a grazing \
                 changes its impact sequence discontinuously (follow its orbits by find_orbit \
                 from the previous orbit instead)"
                        .into(),
                ))
            }
            (Structure::Oscillator(_), _) => return Err(Error::Unsupported(
                "continuation is built for the cantilever: the oscillator's parameters are not \
                 in the units k/k₁, ω/(β₁⁻)²"
                    .into(),
            )),
        };
    let p0 = match (options.parameter, spec.stop) {
        (Parameter::StopStiffness, Stop::Compliant { stop_stiffness }) => stop_stiffness,
        (Parameter::Frequency, _) => c.omega,
        _ => c.gap,
    };
    // the branch is traced in ln p
    if p0.is_nan() || p0 <= 0.0 {
        return Err(ParameterError::new(
            keyword(options.parameter),
            error::number(p0),
            "a value > 0 to continue from (the branch is traced in the logarithm of the \
             parameter)",
        )
        .into());
    }
    let to = options.to;
    if !(to.is_finite() && to > 0.0 && to != p0) {
        return Err(ParameterError::new(
            "to",
            error::number(to),
            "a finite value > 0 other than the start value",
        )
        .into());
    }
    MAX_STEP.check(options.max_step)?;
    DOUBLING_UP_TO.check(options.doubling_up_to as i128)?;
    // `to` must be a value the model accepts (k ≤ 1e12 k₁, say): refused here, not found
    // out as a corrector failure at the end of the branch
    if let Err(e) = at(spec, options.parameter, to).galerkin() {
        return Err(ParameterError::new(
            "to",
            error::number(to),
            &format!("a value the model accepts ({e})"),
        )
        .into());
    }
    let model = BuiltModel::build(spec)?;
    let (x0, _) = model.start(start)?;
    let first = find_orbit_reporting(&model, &x0, orbit, progress)?;
    let task = progress.task("continuation: orbits", 0);
    let family = Family::new(options.parameter, |p| {
        task.advance(1);
        if progress.cancelled() {
            return Err(Error::Interrupted);
        }
        Ok(at(spec, options.parameter, p).galerkin()?)
    });
    let other = if options.one_way { p0 } else { p0 * p0 / to };
    let settings = Settings {
        max_step: options.max_step,
        initial_step: options.max_step.min(0.01),
        max_period: options.doubling_up_to,
        ..Settings::new((to.min(other), to.max(other)))
    };
    let (x, m) = (&first.state, first.period_m);
    let mut branches = if options.one_way {
        let direction = (to - p0).signum();
        vec![continue_branch(&family, x, p0, m, direction, &settings)?]
    } else {
        trace(&family, x, p0, m, &settings)?
    };
    // branch 0 runs up; put the one towards `to` first
    if !options.one_way && to < p0 && branches.len() > 1 {
        branches.swap(0, 1);
    }
    Ok(Continuation {
        parameter: options.parameter.symbol(),
        start: p0,
        modes: c.modes,
        branches,
    })
}
