//! One row of the atlas: a k, swept up in ω, each cell searched from the previous cell's
//! orbits and the seeded starts, and checked with more modes on the checked cells.

use super::cell::{CellSearch, Found};
use super::{AtlasParams, Check, Row};
use crate::base::progress::{Progress, Task};
use crate::engine::sim::Simulator;
use crate::error::Error;

/// Computes row i with `modes` modes; each finished cell advances `task` by one, and the row
/// stops before its next cell when `progress` is cancelled.
///
/// # Errors
/// [`Error::Parameter`] for a cell's model out of range; [`Error::Flow`] when its flow cannot
/// be built; the errors of [`CellSearch::run`] and of the check's searches;
/// [`Error::Interrupted`] when cancelled.
pub fn row(
    p: &AtlasParams,
    i: usize,
    modes: usize,
    task: &dyn Task,
    progress: &dyn Progress,
) -> Result<Row, Error> {
    let k = p.k_over_k1(i);
    let checked_row = i.is_multiple_of(p.check_stride);
    let mut cells = Vec::with_capacity(p.omega_points);
    let mut previous: Vec<Found> = Vec::new();
    for j in 0..p.omega_points {
        if progress.cancelled() {
            return Err(Error::Interrupted);
        }
        let w = p.omega_over_w1(j);
        let sim = Simulator::new(p.model(modes, k, w)?.model()?)?;
        let search = CellSearch::new(p, &sim, (i, j));
        let (mut cell, found) = search.run(&previous)?;
        if checked_row && j.is_multiple_of(p.check_stride) {
            let check_modes = (modes + p.check_extra_modes).min(crate::model::galerkin::MAX_MODES);
            let sim = Simulator::new(p.model(check_modes, k, w)?.model()?)?;
            let check = CellSearch {
                sim: &sim,
                ..search
            };
            let orbit = check.from_start(0)?;
            let change = match (&orbit, cell.rest()) {
                (Some(o), Some(a)) if (o.period_m, o.impacts_n) == (a.period_m, a.impacts_n) => {
                    let theirs = check.impact_velocities(o)?;
                    Some(velocity_change(&a.impact_velocities, &theirs))
                }
                _ => None,
            };
            let extra = p.starts..p.starts + p.check_starts;
            cell.check = Some(Check {
                modes: check_modes,
                from_rest: orbit.map(|o| (o.period_m, o.impacts_n)),
                impact_velocity_change: change,
                missed: search.missed(&found, extra)?,
            });
        }
        cells.push(cell);
        previous = found;
        task.advance(1);
    }
    Ok(Row {
        index: i,
        k_over_k1: k,
        modes,
        cells,
    })
}

/// The largest difference between two lists of entry velocities, each sorted, relative to
/// the largest velocity (1 when their lengths differ).
fn velocity_change(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() || a.is_empty() {
        return 1.0;
    }
    let sorted = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v
    };
    let (a, b) = (sorted(a), sorted(b));
    let scale = a.iter().chain(&b).fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale.max(f64::MIN_POSITIVE)
}
