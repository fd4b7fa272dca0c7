//! A curve as one call from a model's specification, for every front end: the start orbit
//! found as [`find_orbit`](crate::analysis::find_orbit::find_orbit) finds it at the
//! specification's (p, q), the curve's point located from it at that q, and the curve traced
//! both ways within the rectangle asked for. The command line's `continue2` is this function.
//!
//! Supported: the compliant cantilever, as for one-parameter continuation
//! ([`crate::analysis::continuation::request`], which says why the rigid model and the
//! oscillator are refused).

use super::{trace_curve, Curve, CurveKind, CurveSettings, Family2};
use crate::analysis::continuation::request::{at, keyword};
use crate::analysis::continuation::Parameter;
use crate::analysis::find_orbit::{find_orbit_reporting, OrbitOptions};
use crate::base::progress::Progress;
use crate::engine::built::BuiltModel;
use crate::error::{self, Error, ParameterError};
use crate::model::ranges::{Count, Range};
use crate::model::spec::{ModelSpec, Start, Stop, Structure};
use serde::Serialize;

/// The largest arclength step (in the scaled state, ln p and ln q).
pub const MAX_STEP: Range = Range {
    name: "max_step",
    symbol: "in ln p, ln q and the scaled state",
    lo: 1e-4,
    hi: 0.2,
    why: "below 1e-4 a curve of a decade takes over 20 000 points; above 0.2 the predictor \
          leaves the corrector's basin",
};

/// Points each way from the start at most.
pub const MAX_POINTS: Count = Count {
    name: "max_points",
    symbol: "each way",
    min: 2,
    max: 20_000,
    why: "each point costs four monodromy matrices or more; 20 000 covers a curve over \
          several decades at the smallest step",
};

/// What to follow and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveOptions {
    /// What the curve follows.
    pub kind: CurveKind,
    /// p: solved for at the start (from its value in the specification).
    pub parameter: Parameter,
    /// q: held at its value in the specification while the first point is located.
    pub second: Parameter,
    /// The interval of p the curve is traced in (contains the start's p).
    pub range: (f64, f64),
    /// The interval of q (contains the start's q).
    pub second_range: (f64, f64),
    /// [`MAX_STEP`].
    pub max_step: f64,
    /// [`MAX_POINTS`].
    pub max_points: u64,
}

/// The traced curve and what it started from.
#[derive(Debug, Clone, Serialize)]
pub struct CurveReport {
    /// N.
    pub modes: usize,
    /// The start orbit's (p, q) as specified.
    pub start: (f64, f64),
    /// The curve.
    pub curve: Curve,
}

/// The value of `parameter` in `spec` (None when the specification has no such value).
fn value(spec: &ModelSpec, parameter: Parameter) -> Option<f64> {
    match (&spec.structure, &spec.stop, parameter) {
        (_, Stop::Compliant { stop_stiffness }, Parameter::StopStiffness) => Some(*stop_stiffness),
        (Structure::Cantilever(c), _, Parameter::Frequency) => Some(c.omega),
        (Structure::Cantilever(c), _, Parameter::Gap) => Some(c.gap),
        _ => None,
    }
}

/// Checks one range: finite, 0 < lo < hi, the start inside, both ends accepted by the model.
fn check_range(
    spec: &ModelSpec,
    parameter: Parameter,
    name: &str,
    start: f64,
    (lo, hi): (f64, f64),
) -> Result<(), Error> {
    let shown = format!("{}..{}", error::number(lo), error::number(hi));
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo && lo <= start && start <= hi) {
        return Err(ParameterError::new(
            name,
            shown,
            &format!(
                "0 < from < to, finite, containing the start value {} of {}",
                error::number(start),
                keyword(parameter)
            ),
        )
        .into());
    }
    for end in [lo, hi] {
        if let Err(e) = at(spec, parameter, end).galerkin() {
            return Err(
                ParameterError::new(name, shown, &format!("ends the model accepts ({e})")).into(),
            );
        }
    }
    Ok(())
}

/// Traces the curve of `options.kind` points through the orbit `spec` settles on from
/// `start`.
///
/// # Errors
/// [`Error::Parameter`] for options out of range, the same parameter twice, a start value
/// not > 0, or ranges the model does not accept; [`Error::Unsupported`] for the rigid model
/// or the oscillator; the start orbit's errors; [`Error::NotConverged`] when no point of the
/// curve is found near the start; [`Error::Interrupted`] when `progress` is cancelled.
pub fn curve_from(
    spec: &ModelSpec,
    start: &Start,
    orbit: &OrbitOptions,
    options: &CurveOptions,
    progress: &dyn Progress,
) -> Result<CurveReport, Error> {
    let modes = match (&spec.structure, &spec.stop) {
        (Structure::Cantilever(c), Stop::Compliant { .. }) => c.modes,
        _ => {
            return Err(Error::Unsupported(
                "curves are traced for the compliant cantilever, as branches are (see \
                 `continue`): not for the rigid-impact model or the oscillator"
                    .into(),
            ))
        }
    };
    if options.parameter == options.second {
        return Err(ParameterError::new(
            "second",
            keyword(options.second),
            "a parameter other than --parameter",
        )
        .into());
    }
    let (p0, q0) = (
        value(spec, options.parameter).unwrap_or(f64::NAN),
        value(spec, options.second).unwrap_or(f64::NAN),
    );
    for (parameter, v) in [(options.parameter, p0), (options.second, q0)] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(ParameterError::new(
                keyword(parameter),
                error::number(v),
                "a value > 0 to start from (curves are traced in the logarithms of the \
                 parameters)",
            )
            .into());
        }
    }
    check_range(spec, options.parameter, "range", p0, options.range)?;
    check_range(
        spec,
        options.second,
        "second_range",
        q0,
        options.second_range,
    )?;
    MAX_STEP.check(options.max_step)?;
    let max_points = MAX_POINTS.check(options.max_points as i128)? as usize;
    let model = BuiltModel::build(spec)?;
    let (x0, _) = model.start(start)?;
    let first = find_orbit_reporting(&model, &x0, orbit, progress)?;
    let task = progress.task("curve: orbits", 0);
    let (pp, qq) = (options.parameter, options.second);
    let family = Family2::new((pp, qq), |p, q| {
        task.advance(1);
        if progress.cancelled() {
            return Err(Error::Interrupted);
        }
        Ok(at(&at(spec, pp, p), qq, q).galerkin()?)
    });
    let settings = CurveSettings {
        max_step: options.max_step,
        initial_step: options.max_step.min(0.01),
        max_points,
        ..CurveSettings::new(options.range, options.second_range)
    };
    let curve = trace_curve(
        &family,
        options.kind,
        &first.state,
        (p0, q0),
        first.period_m,
        &settings,
        progress,
    )?;
    Ok(CurveReport {
        modes,
        start: (p0, q0),
        curve,
    })
}
