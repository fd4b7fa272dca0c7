//! The atlas's boundaries by two-parameter continuation (beyond the paper): the curves of
//! folds, period doublings, Neimark–Sacker points and grazings ([`crate::analysis::curves`])
//! that bound the regions of the brute-force atlas, traced in (ω, k) in each band of rows
//! that share one N (each curve at its band's N, within its band's k), and how well they
//! account for its region boundaries.
//!
//! **Boundaries.** Two neighbouring cells (along ω or along k) whose orbits from rest have
//! different labels (m, n) — or where one has none — meet at a boundary *edge*. An edge is a
//! *basin* edge when the orbit from rest on one side is, by its label, among the stable
//! orbits found on the other: rest changed basin between coexisting orbits, which no local
//! bifurcation of either accounts for. Every other edge is a *bifurcation* edge: the orbit
//! from rest on one side is not stable on the other, so between them it loses stability,
//! ends at a fold or gains or loses a contact (or the atlas's search missed it there).
//!
//! **Seeds and curves.** Curves are seeded from bifurcation edges along ω, the most
//! frequent pairs of labels first: the orbit from rest of one cell is continued in ω
//! ([`crate::analysis::continuation`]) towards its neighbour, and the first fold, period
//! doubling, Neimark–Sacker point or grazing met between the two cells is followed in
//! (ω, k). Edges within one grid step of a traced curve are then accounted for, and the
//! next seed is the most frequent pair still unaccounted for. Seeds are taken in rounds of
//! a fixed size, traced in parallel and accepted in order, so the curves do not depend on
//! the number of threads.
//!
//! **Agreement.** Distances are measured on the grid: one step is one column in ω or one
//! row in ln k. An edge is within one step of a curve when the curve passes within one step
//! of the edge's midpoint. Conversely, every grid edge a curve crosses is checked: do its
//! two cells differ in the orbit from rest, or at least in the set of stable (m, n) found?

use super::across::{check_sample, continue_across, seed_failure, Continued, EdgeCheck};
use super::{AtlasData, Cell};
use crate::analysis::continuation::{BifurcationKind, Parameter};
use crate::analysis::curves::{self, CodimTwo, CurveKind, CurveSettings, Family2, Meets};
use crate::base::progress::Progress;
use crate::error::Error;
use nalgebra::DVector;
use rayon::prelude::*;

pub use super::edges::{crossings, edges, left, Crossing, Left};
use super::edges::{curve_distance, grid};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// An orbit's label (m, n), None for no stable orbit of period ≤ max_m.
pub type Label = Option<(u64, usize)>;

/// A cell (row, column).
type At = (usize, usize);

/// A curve's orbit is unstable at a point when a multiplier lies outside the unit circle by
/// more than this: the curve's own critical multipliers lie on it to their test residuals
/// (at most ~1e-5, on fold curves).
pub const UNSTABLE: f64 = 1e-3;

/// A point is near a fold of its orbit when a Floquet multiplier lies within this of 1
/// (see [`BoundaryCurve::test_residual_off_folds`]).
pub const NEAR_FOLD: f64 = 1e-4;

/// A band (its rows) and an unordered pair of labels.
type BandPair = (Option<(usize, usize)>, (Label, Label));

/// How the boundary curves are searched.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CurveSearch {
    /// Curves traced at most (0: none).
    pub max_curves: usize,
    /// Seeds tried at most (a seed may fail: no bifurcation between its cells, or a curve
    /// that cannot be started).
    pub max_seeds: usize,
    /// Points each way along a curve at most.
    pub max_points: usize,
    /// Seeds per round (traced in parallel, accepted in order).
    pub round: usize,
    /// Edges no curve accounts for checked one by one at most, drawn at random
    /// ([`super::across`]; 0: none).
    #[serde(default)]
    pub edge_sample: usize,
}

/// What separates two neighbouring cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EdgeClass {
    /// The orbit from rest on one side is stable on the other too: a basin boundary.
    Basin,
    /// Neither side's orbit from rest is stable on the other.
    Bifurcation,
}

/// A boundary edge between cells `a` and `b` (row, column), neighbours along ω or k.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Edge {
    /// The first cell (row, column).
    pub a: (usize, usize),
    /// The second: (row, column + 1) or (row + 1, column).
    pub b: (usize, usize),
    /// The labels of their orbits from rest.
    pub labels: (Label, Label),
    /// The two rows use different N (an edge along k between two bands): its labels may
    /// differ because N does.
    pub modes_change: bool,
    /// Basin or bifurcation.
    pub class: EdgeClass,
    /// The nearest curve within one grid step of the edge's midpoint, and its distance in
    /// grid steps.
    pub curve: Option<(usize, f64)>,
}

/// A codimension-two point of a curve, between two of its points.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CurveMeeting {
    /// What the curve meets (a fold, period-doubling or Neimark–Sacker curve, a grazing, a
    /// cusp).
    pub meets: String,
    /// ω/(β₁⁻)², interpolated, and half the distance between the two points.
    pub omega: (f64, f64),
    /// k/k₁, interpolated, and half the distance between the two points.
    pub k_over_k1: (f64, f64),
}

/// One traced curve.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BoundaryCurve {
    /// Fold, period doubling, Neimark–Sacker or grazing.
    pub kind: String,
    /// N: the modes of its band's rows.
    pub modes: usize,
    /// The continued orbit's label (m, n) at its seed.
    pub orbit: (u64, usize),
    /// The cell whose orbit from rest was continued, and the neighbour it was continued
    /// towards (row, column).
    pub seed: ((usize, usize), (usize, usize)),
    /// The points (ω/(β₁⁻)², k/k₁) in arclength order.
    pub points: Vec<(f64, f64)>,
    /// The largest orbit and test residuals over the points (relative; see
    /// [`crate::analysis::curves::CurvePoint`]).
    pub residuals: (f64, f64),
    /// The largest test residual over its points with no Floquet multiplier within
    /// [`NEAR_FOLD`] of 1. Near a fold of the orbit shooting at a fixed (ω, k) determines the
    /// orbit only to its residual over |1 − μ|, and polishing a point moves it that far
    /// along the fold's direction, so the condition there holds less well.
    #[serde(default)]
    pub test_residual_off_folds: f64,
    /// At each point, whether its orbit is unstable apart from the curve's own critical
    /// multiplier (one lies outside the unit circle by more than [`UNSTABLE`]): a curve
    /// of an unstable orbit changes no stable orbit the atlas can find.
    #[serde(default)]
    pub unstable: Vec<bool>,
    /// Its codimension-two points.
    pub meetings: Vec<CurveMeeting>,
    /// Why each end ends.
    pub ends: (String, String),
}

/// A seed that gave no curve, and why.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct FailedSeed {
    /// The cell and its neighbour.
    pub seed: ((usize, usize), (usize, usize)),
    /// Why.
    pub why: String,
}

/// A band of consecutive rows that use one N.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Band {
    /// Its rows: `rows.0` to `rows.1` − 1.
    pub rows: (usize, usize),
    /// N.
    pub modes: usize,
}

/// The curves of an atlas.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BoundaryCurves {
    /// The search's settings.
    pub search: CurveSearch,
    /// The bands of rows of one N, from the lowest k; each curve is traced within one.
    pub bands: Vec<Band>,
    /// The curves, in the order they were accepted.
    pub curves: Vec<BoundaryCurve>,
    /// Seeds that gave none.
    pub failed: Vec<FailedSeed>,
    /// Seeds whose curve was one already traced (another seed of the same round on it).
    pub duplicates: usize,
    /// A random sample of the edges the curves leave, each checked by continuation across
    /// it ([`super::across`]).
    #[serde(default)]
    pub checked: Vec<EdgeCheck>,
}

/// The cell (row, column).
fn cell(d: &AtlasData, (i, j): (usize, usize)) -> &Cell {
    &d.rows[i].cells[j]
}

/// A cell's label.
pub fn label(c: &Cell) -> Label {
    c.rest().map(|a| (a.period_m, a.impacts_n))
}

/// The labels of a cell's stable orbits.
pub(super) fn stable(c: &Cell) -> BTreeSet<(u64, usize)> {
    c.attractors
        .iter()
        .map(|a| (a.period_m, a.impacts_n))
        .collect()
}

/// The bands of consecutive rows that use one N, from row 0.
pub fn bands(d: &AtlasData) -> Vec<Band> {
    let mut out: Vec<Band> = Vec::new();
    for (i, r) in d.rows.iter().enumerate() {
        match out.last_mut() {
            Some(b) if b.modes == r.modes => b.rows.1 = i + 1,
            _ => out.push(Band {
                rows: (i, i + 1),
                modes: r.modes,
            }),
        }
    }
    out
}

/// The band of row `i`.
fn band_of(bands: &[Band], i: usize) -> Option<&Band> {
    bands.iter().find(|b| (b.rows.0..b.rows.1).contains(&i))
}

/// Whether a curve's end is a stall (its corrector failed, or the model's orbit left the
/// curve's condition), not the map's edge, a closed loop or the cap on points.
fn stalled(end: &str) -> bool {
    end.starts_with("corrector") || end.starts_with("the model's orbit")
}

/// The curve kind a one-parameter bifurcation is followed as (none for a branch point).
fn curve_kind(kind: BifurcationKind) -> Option<CurveKind> {
    match kind {
        BifurcationKind::Fold => Some(CurveKind::Fold),
        BifurcationKind::PeriodDoubling => Some(CurveKind::PeriodDoubling),
        BifurcationKind::NeimarkSacker => Some(CurveKind::NeimarkSacker),
        BifurcationKind::Grazing => Some(CurveKind::Grazing),
        BifurcationKind::BranchPoint => None,
    }
}

/// The curve through the first bifurcation of cell `from`'s orbit from rest met on the way
/// (in ω) to cell `to`, or why there is none.
fn trace_seed(
    d: &AtlasData,
    c: &CurveSearch,
    band: Band,
    (from, to): ((usize, usize), (usize, usize)),
    progress: &dyn Progress,
) -> Result<Result<BoundaryCurve, String>, Error> {
    let p = &d.params;
    let k = d.rows[from.0].k_over_k1;
    let Continued {
        forced,
        label,
        branch,
        ..
    } = match continue_across(d, (from, to), 200, false)? {
        Ok(c) => c,
        Err(why) => return Ok(Err(why)),
    };
    let Some((bif, kind)) = branch
        .bifurcations
        .iter()
        .find_map(|b| curve_kind(b.kind).map(|k| (b, k)))
    else {
        return Ok(Err(format!(
            "the ({},{}) orbit meets no bifurcation between the two cells",
            label.0, label.1
        )));
    };
    let start = &branch.points[bif.index];
    let family2 = Family2::forced(forced, Parameter::Frequency, Parameter::StopStiffness)?;
    // within the band: beyond it the rows use another N
    let k_range = (
        d.rows[band.rows.0].k_over_k1,
        d.rows[band.rows.1 - 1].k_over_k1,
    );
    let settings2 = CurveSettings {
        max_points: c.max_points,
        max_step: 0.2,
        ..CurveSettings::new(p.omega_range, k_range)
    };
    let state = DVector::from_vec(start.state.clone());
    let curve = match curves::trace_curve(
        &family2,
        kind,
        &state,
        (bif.parameter, k),
        branch.period_m,
        &settings2,
        progress,
    ) {
        Ok(cv) => cv,
        Err(e) => return seed_failure(e).map(|w| Err(format!("{kind} curve: {w}"))),
    };
    let residuals = curve.points.iter().fold((0.0f64, 0.0f64), |r, q| {
        (r.0.max(q.orbit_residual), r.1.max(q.test_residual))
    });
    let test_residual_off_folds = curve
        .points
        .iter()
        .filter(|q| {
            q.multipliers
                .iter()
                .all(|z| (z[0] - 1.0).hypot(z[1]) > NEAR_FOLD)
        })
        .map(|q| q.test_residual)
        .fold(0.0, f64::max);
    let unstable = curve
        .points
        .iter()
        .map(|q| {
            q.multipliers
                .iter()
                .any(|z| z[0].hypot(z[1]) > 1.0 + UNSTABLE)
        })
        .collect();
    let meetings = curve
        .codim_two
        .iter()
        .map(|m: &CodimTwo| {
            let (a, b) = (&curve.points[m.index], &curve.points[m.index + 1]);
            CurveMeeting {
                meets: match m.meets {
                    Meets::Fold => "a fold curve",
                    Meets::PeriodDoubling => "a period-doubling curve",
                    Meets::NeimarkSacker => "a Neimark–Sacker curve",
                    Meets::Grazing => "a grazing (the contacts change)",
                    Meets::Cusp => "a cusp",
                }
                .to_string(),
                omega: (m.p, (b.p - a.p).abs() / 2.0),
                k_over_k1: (m.q, (b.q - a.q).abs() / 2.0),
            }
        })
        .collect();
    Ok(Ok(BoundaryCurve {
        kind: kind.to_string(),
        modes: band.modes,
        orbit: label,
        seed: (from, to),
        points: curve.points.iter().map(|q| (q.p, q.q)).collect(),
        residuals,
        test_residual_off_folds,
        unstable,
        meetings,
        ends: curve.ends,
    }))
}

/// The seeds still open: bifurcation edges along ω not within one step of a curve nor within
/// two steps of a failed seed of the same labels, in bands of at least two rows; the pair of
/// labels with the most edges left in its band first, then by row and column; each as (cell
/// continued, neighbour).
fn open_seeds(d: &AtlasData, found: &BoundaryCurves) -> Vec<((usize, usize), (usize, usize))> {
    let all = edges(d, found);
    let pair = |e: &Edge| {
        let (a, b) = e.labels;
        if a <= b {
            (a, b)
        } else {
            (b, a)
        }
    };
    // the edges still to account for, per pair of labels in one band: a curve is traced
    // within its band, so it can account only for its band's edges
    let band = |i: usize| band_of(&found.bands, i).map(|b| b.rows);
    let mut frequency: BTreeMap<BandPair, usize> = BTreeMap::new();
    for e in all.iter().filter(|e| e.curve.is_none() && !e.modes_change) {
        *frequency.entry((band(e.a.0), pair(e))).or_default() += 1;
    }
    let cell = |(i, j): (usize, usize)| &d.rows[i].cells[j];
    let mut open: Vec<(usize, At, At)> = all
        .iter()
        .filter(|e| e.class == EdgeClass::Bifurcation && e.curve.is_none() && e.a.0 == e.b.0)
        // a curve is continued in k within its band: a band of one row has no k to follow
        .filter(|e| band_of(&found.bands, e.a.0).is_some_and(|b| b.rows.1 - b.rows.0 >= 2))
        .filter_map(|e| {
            let (la, lb) = e.labels;
            // continue an orbit that is not stable on the other side
            let seed = if la.is_some_and(|l| !stable(cell(e.b)).contains(&l)) {
                (e.a, e.b)
            } else if lb.is_some_and(|l| !stable(cell(e.a)).contains(&l)) {
                (e.b, e.a)
            } else {
                return None;
            };
            let near_failure = found.failed.iter().any(|f| {
                let (fa, fb) = f.seed;
                (label(cell(fa)), label(cell(fb))) == (label(cell(seed.0)), label(cell(seed.1)))
                    && (fa.0 as f64 - seed.0 .0 as f64).hypot(fa.1 as f64 - seed.0 .1 as f64) <= 2.0
            });
            (!near_failure).then(|| (frequency[&(band(e.a.0), pair(e))], seed.0, seed.1))
        })
        .collect();
    open.sort_by(|x, y| y.0.cmp(&x.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    open.into_iter().map(|(_, a, b)| (a, b)).collect()
}

/// Traces the boundary curves of an atlas (see the module's doc), each at the N of its
/// seed's band of rows, within that band.
///
/// # Errors
/// [`Error::Interrupted`] when cancelled; [`Error::Invariant`] from a run; a parameter error
/// for a model out of range. A seed that fails otherwise is recorded with its reason.
pub fn trace(
    d: &AtlasData,
    search: &CurveSearch,
    progress: &dyn Progress,
) -> Result<BoundaryCurves, Error> {
    let mut found = BoundaryCurves {
        search: *search,
        bands: bands(d),
        curves: Vec::new(),
        failed: Vec::new(),
        duplicates: 0,
        checked: Vec::new(),
    };
    if search.max_curves == 0 {
        return Ok(found);
    }
    let task = progress.task("atlas: boundary curves", search.max_seeds as u64);
    let mut tried = 0;
    while found.curves.len() < search.max_curves && tried < search.max_seeds {
        let open = open_seeds(d, &found);
        if open.is_empty() {
            break;
        }
        // a round: the next seeds, one per pair of labels and band (a curve explains many
        // edges of its pair; the next round sees which are left)
        let mut round: Vec<((usize, usize), (usize, usize))> = Vec::new();
        let labels = |x: &((usize, usize), (usize, usize))| {
            let (a, b) = (label(cell(d, x.0)), label(cell(d, x.1)));
            let band = band_of(&found.bands, x.0 .0).map(|b| b.rows);
            if a <= b {
                (band, a, b)
            } else {
                (band, b, a)
            }
        };
        for s in open {
            if round.len() >= search.round.min(search.max_seeds - tried) {
                break;
            }
            if !round.iter().any(|r| labels(r) == labels(&s)) {
                round.push(s);
            }
        }
        let results: Vec<Result<Result<BoundaryCurve, String>, Error>> = round
            .par_iter()
            .map(|&s| match band_of(&found.bands, s.0 .0) {
                Some(&band) => trace_seed(d, search, band, s, progress),
                None => Err(Error::Invariant(format!("seed row {} in no band", s.0 .0))),
            })
            .collect();
        for (s, r) in round.iter().zip(results) {
            tried += 1;
            task.advance(1);
            match r? {
                Ok(curve) => {
                    // the located curve must pass between the seed's cells (Newton at the
                    // seed's k may converge to another point of the test function), and not
                    // be one already traced (another seed of the round on it: its edge is
                    // then accounted for). A curve that overlaps one traced but also passes
                    // by its own seed's edge, which that one does not, is kept: it goes
                    // further (a seed whose edge stays open is otherwise tried again).
                    let mid = ((s.0 .1 + s.1 .1) as f64 / 2.0, s.0 .0 as f64);
                    let duplicate = found
                        .curves
                        .iter()
                        .any(|cv| curve_distance(&d.params, cv, mid) <= 1.0);
                    // a curve that stalls both ways within its first grid step
                    // accounts for no more than its seed: no curve, and no use of the
                    // curve budget
                    let first = curve.points.first().map(|&q| grid(&d.params, q));
                    let extent = curve
                        .points
                        .iter()
                        .map(|&q| {
                            let (g, f) = (grid(&d.params, q), first.unwrap_or((0.0, 0.0)));
                            (g.0 - f.0).hypot(g.1 - f.1)
                        })
                        .fold(0.0, f64::max);
                    if curve_distance(&d.params, &curve, mid) > 1.0 {
                        found.failed.push(FailedSeed {
                            seed: *s,
                            why: format!(
                                "the {} curve located from it does not pass between its cells",
                                curve.kind
                            ),
                        });
                    } else if extent < 1.0 && stalled(&curve.ends.0) && stalled(&curve.ends.1) {
                        found.failed.push(FailedSeed {
                            seed: *s,
                            why: format!(
                                "the {} curve stalls within one grid step of its start ({})",
                                curve.kind, curve.ends.0
                            ),
                        });
                    } else if duplicate || found.curves.len() >= search.max_curves {
                        found.duplicates += 1;
                    } else {
                        found.curves.push(curve);
                    }
                }
                Err(why) => found.failed.push(FailedSeed { seed: *s, why }),
            }
        }
    }
    drop(task);
    found.checked = check_sample(d, &found, search.edge_sample, progress)?;
    Ok(found)
}
