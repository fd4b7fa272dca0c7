//! The atlas's edges that no traced curve accounts for, checked one by one on a random
//! sample (beyond the paper): the orbit from rest of one cell is continued across the edge —
//! in ω along a row, in k along a column — to its neighbour, and the first bifurcation it
//! meets between the two cells is recorded, or why it meets none. A located fold, period
//! doubling, Neimark–Sacker point or grazing is a point of a boundary curve on that edge
//! (the curve itself not traced). The same continuation starts each traced curve
//! ([`super::curves::trace`]).

use super::cell::CellSearch;
use super::curves::{label, stable, BoundaryCurves};
use super::edges::{edges, left, Left};
use super::AtlasData;
use crate::analysis::continuation::{self, Branch, Family, Parameter, Settings as BranchSettings};
use crate::base::progress::Progress;
use crate::base::random::SplitMix64;
use crate::engine::sim::Simulator;
use crate::error::Error;
use crate::model::problems::Forced;
use nalgebra::DVector;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// A cell (row, column).
type At = (usize, usize);

/// The orbit from rest of one cell, continued towards a neighbour.
pub(super) struct Continued {
    /// The model at the cell.
    pub forced: Forced,
    /// The cell's value of it and the neighbour's.
    pub range: (f64, f64),
    /// The orbit's (m, n) at the cell.
    pub label: (u64, usize),
    /// The branch, from the cell towards the neighbour.
    pub branch: Branch,
}

/// A failure that ends one seed or one edge's check, not the atlas (an interruption or a
/// broken invariant ends it).
pub(super) fn seed_failure(e: Error) -> Result<String, Error> {
    match e {
        Error::Interrupted | Error::Invariant(_) => Err(e),
        other => Ok(other.to_string()),
    }
}

/// Cell `from`'s orbit from rest continued towards neighbour `to` (in ω along a row, in k
/// along a column), at most `max_points` points and, if `first_only`, only to its first
/// bifurcation; or why it cannot be.
///
/// At least four points lie between the two cells (steps at most a quarter of the cells'
/// distance in ln p, fewer where the orbit changes fast): two bifurcations close together
/// are then told apart, and the first is the first.
pub(super) fn continue_across(
    d: &AtlasData,
    (from, to): (At, At),
    max_points: usize,
    first_only: bool,
) -> Result<Result<Continued, String>, Error> {
    let p = &d.params;
    let modes = d.rows[from.0].modes;
    let k = d.rows[from.0].k_over_k1;
    let w = d.omega_over_w1[from.1];
    let (parameter, range) = if from.0 == to.0 {
        (Parameter::Frequency, (w, d.omega_over_w1[to.1]))
    } else {
        (Parameter::StopStiffness, (k, d.rows[to.0].k_over_k1))
    };
    let forced = p.model(modes, k, w)?;
    let sim = Simulator::new(forced.model()?)?;
    let orbit = match CellSearch::new(p, &sim, from).from_start(0) {
        Ok(Some(o)) => o,
        Ok(None) => return Ok(Err("rest reaches no stable orbit".into())),
        Err(e) => return seed_failure(e).map(Err),
    };
    let label = (orbit.period_m, orbit.impacts_n);
    let family = Family::forced(forced, parameter);
    let (lo, hi) = (range.0.min(range.1), range.0.max(range.1));
    let settings = BranchSettings {
        initial_step: (hi / lo).ln() / 8.0,
        max_step: (hi / lo).ln() / 4.0,
        max_points,
        stop_at_first: first_only,
        ..BranchSettings::new((lo, hi))
    };
    let direction = if range.1 > range.0 { 1.0 } else { -1.0 };
    let x = DVector::from_vec(orbit.state.clone());
    match continuation::continue_branch(&family, &x, range.0, orbit.period_m, direction, &settings)
    {
        Ok(branch) => Ok(Ok(Continued {
            forced,
            range,
            label,
            branch,
        })),
        Err(e) => {
            seed_failure(e).map(|w| Err(format!("continuation in {}: {w}", parameter.symbol())))
        }
    }
}

/// Points of a check's continuation at most: a grazing's branch turns sharply near it, so
/// the corrector may need tens of points across one grid step.
const CHECK_POINTS: usize = 120;

/// One sampled edge: what the orbit from rest on one side meets on the way to the other.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct EdgeCheck {
    /// The cell whose orbit from rest was continued, and its neighbour (row, column).
    pub cells: (At, At),
    /// Why no curve accounts for the edge ([`Left::key`]).
    pub left: String,
    /// The continued orbit's (m, n), when rest reaches one.
    pub orbit: Option<(u64, usize)>,
    /// The first bifurcation met between the two cells — fold, period doubling,
    /// Neimark–Sacker, grazing or branch point — and where (ω/(β₁⁻)² along a row, k/k₁
    /// along a column); None when none is met.
    pub meets: Option<(String, f64)>,
    /// When none is met, why: how the continuation ended.
    pub why: Option<String>,
}

/// The edges a check samples from: those no curve accounts for, other than basin edges and
/// edges between rows of different N (each explained without a bifurcation).
fn checkable(reason: Option<Left>) -> bool {
    matches!(
        reason,
        Some(Left::NotPeriodic | Left::SeedFailed | Left::NotSeeded)
    )
}

/// The check of one edge: continue the orbit from rest of the side whose orbit is not
/// stable on the other.
fn check_edge(d: &AtlasData, e: &super::curves::Edge, reason: Left) -> Result<EdgeCheck, Error> {
    let cell = |(i, j): At| &d.rows[i].cells[j];
    let (from, to) = if e.labels.0.is_some_and(|l| !stable(cell(e.b)).contains(&l)) {
        (e.a, e.b)
    } else {
        (e.b, e.a)
    };
    let mut out = EdgeCheck {
        cells: (from, to),
        left: reason.key().to_string(),
        orbit: label(cell(from)),
        meets: None,
        why: None,
    };
    let c = match continue_across(d, (from, to), CHECK_POINTS, true)? {
        Ok(c) => c,
        Err(why) => {
            out.why = Some(why);
            return Ok(out);
        }
    };
    out.orbit = Some(c.label);
    let b = &c.branch;
    // the branch's last point may lie beyond the neighbour (the step that left the range)
    // (1e-12: the round-off of p = exp(ln p) at the range's ends, which a point there carries)
    let (lo, hi) = (c.range.0.min(c.range.1), c.range.0.max(c.range.1));
    let between = |p: f64| (lo * (1.0 - 1e-12)..=hi * (1.0 + 1e-12)).contains(&p);
    let last = b.points.last();
    // a doubled orbit shrinking onto its half ends at the half's period doubling, met from
    // the doubled side
    let merges = b.end.starts_with("merges with");
    let first = match (b.bifurcations.first(), last) {
        (Some(bif), _) => Some((bif.kind.to_string(), bif.parameter)),
        (None, Some(q)) if merges => Some(("period doubling".to_string(), q.parameter)),
        _ => None,
    };
    match first {
        Some((kind, at)) if between(at) => out.meets = Some((kind, at)),
        Some((kind, at)) => {
            out.why = Some(format!(
                "its first bifurcation, a {kind} at {at:.6}, lies beyond the neighbour"
            ))
        }
        None => {
            let (u0, u1) = (c.range.0.ln(), c.range.1.ln());
            let reached = last.is_some_and(|q| (q.parameter.ln() - u0) / (u1 - u0) >= 1.0 - 1e-12);
            // no crossing detected up to a point at or beyond the neighbour: the orbit is
            // there what it is at that point
            out.why = Some(match (reached, last.map(|q| q.stable)) {
                (true, Some(true)) => "reaches the neighbour still stable: a stable orbit \
                                       the neighbour's search did not find"
                    .to_string(),
                (true, _) => {
                    "reaches the neighbour unstable, with no crossing detected".to_string()
                }
                (false, _) => b.end.clone(),
            });
        }
    }
    Ok(out)
}

/// Up to `n` of the edges no curve accounts for (other than basin edges and edges between
/// rows of different N, each explained without a bifurcation), drawn at random with
/// the atlas's seed, each checked by continuation across it; in the order of the edges.
///
/// # Errors
/// [`Error::Interrupted`] when cancelled; [`Error::Invariant`] from a run. An edge whose
/// check fails otherwise is recorded with the reason.
pub fn check_sample(
    d: &AtlasData,
    c: &BoundaryCurves,
    n: usize,
    progress: &dyn Progress,
) -> Result<Vec<EdgeCheck>, Error> {
    let pool: Vec<(super::curves::Edge, Left)> = edges(d, c)
        .into_iter()
        .filter_map(|e| {
            let why = left(d, c, &e);
            checkable(why).then_some((e, why?))
        })
        .collect();
    let take = n.min(pool.len());
    // a partial Fisher–Yates shuffle of the indices: the first `take` are the sample
    let mut index: Vec<usize> = (0..pool.len()).collect();
    let mut rng = SplitMix64::for_point(d.params.seed, u64::MAX, 0, 0);
    for i in 0..take {
        let j = i + (rng.next_u64() % (pool.len() - i) as u64) as usize;
        index.swap(i, j);
    }
    let mut chosen = index[..take].to_vec();
    chosen.sort_unstable();
    let task = progress.task("atlas: edges checked across", take as u64);
    chosen
        .par_iter()
        .map(|&i| {
            if progress.cancelled() {
                return Err(Error::Interrupted);
            }
            let r = check_edge(d, &pool[i].0, pool[i].1);
            task.advance(1);
            r
        })
        .collect()
}
