//! The geometry of the atlas's boundary curves on its grid (see [`super::curves`]): where a
//! curve lies in grid steps, the boundary edges between cells with the nearest curve to
//! each, the grid edges each curve crosses, and why an edge no curve accounts for is left.

use super::curves::{label, stable, BoundaryCurve, BoundaryCurves, Edge, EdgeClass, Label};
use super::{AtlasData, AtlasParams};
use serde::Serialize;
use std::collections::BTreeMap;

/// A cell (row, column).
type Cell = (usize, usize);

/// Grid coordinates (column, row) of (ω, k): one unit is one grid step.
pub(super) fn grid(p: &AtlasParams, (omega, k): (f64, f64)) -> (f64, f64) {
    let (w0, w1) = p.omega_range;
    let (k0, k1) = p.k_over_k1_range;
    let col = if p.omega_points > 1 {
        (omega - w0) / (w1 - w0) * (p.omega_points - 1) as f64
    } else {
        0.0
    };
    let row = if p.k_points > 1 {
        (k / k0).ln() / (k1 / k0).ln() * (p.k_points - 1) as f64
    } else {
        0.0
    };
    (col, row)
}

/// The distance of point c from segment ab.
fn segment_distance(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((c.0 - a.0) * dx + (c.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a.0 + t * dx - c.0).hypot(a.1 + t * dy - c.1)
}

/// The distance of point c (grid coordinates) from a curve's polyline.
pub(super) fn curve_distance(p: &AtlasParams, curve: &BoundaryCurve, c: (f64, f64)) -> f64 {
    let pts: Vec<(f64, f64)> = curve.points.iter().map(|&q| grid(p, q)).collect();
    match pts.len() {
        0 => f64::INFINITY,
        1 => (pts[0].0 - c.0).hypot(pts[0].1 - c.1),
        _ => pts
            .windows(2)
            .map(|w| segment_distance(w[0], w[1], c))
            .fold(f64::INFINITY, f64::min),
    }
}

/// Every boundary edge of the atlas, with the nearest curve within one step.
pub fn edges(d: &AtlasData, c: &BoundaryCurves) -> Vec<Edge> {
    let rows = d.rows.len();
    let mut out = Vec::new();
    let cell = |(i, j): (usize, usize)| &d.rows[i].cells[j];
    for i in 0..rows {
        let width = d.rows[i].cells.len();
        for j in 0..width {
            let mut pairs = Vec::new();
            if j + 1 < width {
                pairs.push(((i, j), (i, j + 1)));
            }
            if i + 1 < rows {
                pairs.push(((i, j), (i + 1, j)));
            }
            for (a, b) in pairs {
                let (la, lb) = (label(cell(a)), label(cell(b)));
                if la == lb {
                    continue;
                }
                let basin = la.is_some_and(|l| stable(cell(b)).contains(&l))
                    || lb.is_some_and(|l| stable(cell(a)).contains(&l));
                let mid = ((a.1 + b.1) as f64 / 2.0, (a.0 + b.0) as f64 / 2.0);
                let curve = c
                    .curves
                    .iter()
                    .enumerate()
                    .map(|(n, cv)| (n, curve_distance(&d.params, cv, mid)))
                    .filter(|&(_, dist)| dist <= 1.0)
                    .min_by(|x, y| x.1.total_cmp(&y.1));
                out.push(Edge {
                    a,
                    b,
                    labels: (la, lb),
                    modes_change: d.rows[a.0].modes != d.rows[b.0].modes,
                    class: if basin {
                        EdgeClass::Basin
                    } else {
                        EdgeClass::Bifurcation
                    },
                    curve,
                });
            }
        }
    }
    out
}

/// A grid edge a curve crosses, and whether its two cells differ in the orbit from rest and
/// in the set of stable (m, n).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Crossing {
    /// The curve.
    pub curve: usize,
    /// The two cells.
    pub cells: ((usize, usize), (usize, usize)),
    /// Their orbits from rest differ.
    pub rest_differs: bool,
    /// Their sets of stable (m, n) differ.
    pub stable_differs: bool,
    /// The curve's orbit is unstable at both ends of the curve's segment that crosses the
    /// edge (None when the curve carries no stability).
    pub orbit_unstable: Option<bool>,
}

/// Every grid edge (between two cells of the atlas) each curve crosses, once per curve.
pub fn crossings(d: &AtlasData, c: &BoundaryCurves) -> Vec<Crossing> {
    let rows = d.rows.len();
    let mut out = Vec::new();
    for (n, curve) in c.curves.iter().enumerate() {
        // each crossed edge with the index of the first segment that crosses it
        let mut seen: BTreeMap<(Cell, Cell), usize> = BTreeMap::new();
        let pts: Vec<(f64, f64)> = curve.points.iter().map(|&q| grid(&d.params, q)).collect();
        for (segment, w) in pts.windows(2).enumerate() {
            let ((u0, v0), (u1, v1)) = (w[0], w[1]);
            // lines through cell centres: column j (u = j) and row i (v = i); crossing the
            // row line v = i between columns j and j + 1 crosses the edge along ω there
            for (lo, hi, along_omega) in [
                (v0.min(v1), v0.max(v1), true),
                (u0.min(u1), u0.max(u1), false),
            ] {
                let mut line = lo.ceil();
                while line <= hi {
                    let (s0, s1, t0, t1) = if along_omega {
                        (v0, v1, u0, u1)
                    } else {
                        (u0, u1, v0, v1)
                    };
                    if s1 != s0 {
                        let t = t0 + (t1 - t0) * (line - s0) / (s1 - s0);
                        let (f, l) = (t.floor(), line as usize);
                        if f >= 0.0 {
                            let f = f as usize;
                            let pair = if along_omega {
                                ((l, f), (l, f + 1))
                            } else {
                                ((f, l), (f + 1, l))
                            };
                            let inside =
                                |(i, j): (usize, usize)| i < rows && j < d.rows[i].cells.len();
                            if inside(pair.0) && inside(pair.1) {
                                seen.entry(pair).or_insert(segment);
                            }
                        }
                    }
                    line += 1.0;
                }
            }
        }
        for ((a, b), segment) in seen {
            let (ca, cb) = (&d.rows[a.0].cells[a.1], &d.rows[b.0].cells[b.1]);
            let unstable = |i: usize| curve.unstable.get(i).copied();
            out.push(Crossing {
                curve: n,
                cells: (a, b),
                rest_differs: label(ca) != label(cb),
                stable_differs: stable(ca) != stable(cb) || label(ca) != label(cb),
                orbit_unstable: unstable(segment)
                    .zip(unstable(segment + 1))
                    .map(|(x, y)| x && y),
            });
        }
    }
    out
}

/// Why an edge no curve accounts for is left, in the order the reasons are tried (each edge
/// is counted once, for the first that applies).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Left {
    /// Its two rows use different N: the labels may differ because N does.
    ModesChange,
    /// Rest changes basin between coexisting orbits: no local bifurcation of either.
    Basin,
    /// One side has no stable orbit of period ≤ max_m: the edge of a quasi-periodic or
    /// chaotic region, or of a window of longer periods.
    NotPeriodic,
    /// A seed of its pair of labels in its band was tried and gave no curve.
    SeedFailed,
    /// Its pair of labels in its band was not reached within the seeds tried.
    NotSeeded,
}

impl Left {
    /// Every reason, in order.
    pub const ALL: [Left; 5] = [
        Left::ModesChange,
        Left::Basin,
        Left::NotPeriodic,
        Left::SeedFailed,
        Left::NotSeeded,
    ];

    /// Its key's name.
    pub fn key(self) -> &'static str {
        match self {
            Left::ModesChange => "between rows of different N",
            Left::Basin => "basin edges",
            Left::NotPeriodic => "next to a cell without a stable orbit",
            Left::SeedFailed => "a seed of their pair gave no curve",
            Left::NotSeeded => "their pair not seeded",
        }
    }
}

/// The reason an edge no curve accounts for is left (None for an accounted edge).
pub fn left(d: &AtlasData, c: &BoundaryCurves, e: &Edge) -> Option<Left> {
    if e.curve.is_some() {
        return None;
    }
    let band = |i: usize| {
        c.bands
            .iter()
            .position(|b| (b.rows.0..b.rows.1).contains(&i))
    };
    let unordered = |(a, b): (Label, Label)| if a <= b { (a, b) } else { (b, a) };
    let failed_here = || {
        c.failed.iter().any(|f| {
            let l = |(i, j): (usize, usize)| label(&d.rows[i].cells[j]);
            band(f.seed.0 .0) == band(e.a.0)
                && unordered((l(f.seed.0), l(f.seed.1))) == unordered(e.labels)
        })
    };
    Some(if e.modes_change {
        Left::ModesChange
    } else if e.class == EdgeClass::Basin {
        Left::Basin
    } else if e.labels.0.is_none() || e.labels.1.is_none() {
        Left::NotPeriodic
    } else if failed_here() {
        Left::SeedFailed
    } else {
        Left::NotSeeded
    })
}
