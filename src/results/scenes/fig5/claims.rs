//! Figure 5's claims, measured on the diagrams: where the truncations agree and where they
//! first differ, and where the paper's Figure 4 orbits appear.

use super::Diagram;
use crate::analysis::orbit::OrbitKind;
use crate::base::report::{Cited, KeyValue, Uncertainty};
use serde::Serialize;

/// A change found on the k grid lies between two adjacent grid values: cited as their
/// midpoint ± half the interval, the one form every table, verdict and key number prints.
/// `first` marks the first grid value where something holds (the change is below it),
/// otherwise the last one (the change is above it). `None` at either end of the grid.
pub fn grid_threshold(grid: &[f64], x: f64, first: bool, scale: f64, unit: &str) -> Option<Cited> {
    let i = grid.iter().position(|g| *g == x)?;
    let (lo, hi) = if first {
        (grid[i.checked_sub(1)?], x)
    } else {
        (x, *grid.get(i + 1)?)
    };
    Some(Cited::new(
        0.5 * (lo + hi) / scale,
        4,
        Uncertainty::new(
            0.5 * (hi - lo) / scale,
            format!("between adjacent grid values {lo:.4} and {hi:.4} k₁ (log-spaced k grid)"),
        ),
        unit,
    ))
}

/// [`grid_threshold`] for prose and tables: "2.69 ± 0.05", or what the grid says instead.
pub fn threshold_text(grid: &[f64], x: Option<f64>, first: bool) -> String {
    match x {
        None => "never on the grid".into(),
        Some(x) => grid_threshold(grid, x, first, 1.0, "").map_or_else(
            || format!("at the end of the grid, {x:.3}"),
            |c| KeyValue::Float(c).prose(true),
        ),
    }
}

/// The paper's three claims, measured.
#[derive(Debug, Clone, Serialize)]
pub struct Claims {
    /// At the smallest k: every N and start gives (1,1).
    pub all_one_one_at_smallest_k: bool,
    /// At the smallest k: the largest relative spread of the impact velocity across N.
    pub velocity_spread_at_smallest_k: f64,
    /// The smallest k/k₁ at which N = 10 and N = 1 reach different orbit sets.
    pub first_orbit_difference: Option<f64>,
    /// The smallest k/k₁ at which the rest-start impact velocities of N = 10 and N = 1
    /// differ by more than 5%.
    pub first_velocity_difference: Option<f64>,
    /// The fraction of k values at which N = 3 and N = 10 reach the same orbit sets.
    pub n3_n10_agreement: f64,
    /// The same for N = 2 and N = 10.
    pub n2_n10_agreement: f64,
    /// The k/k₁ at which the orbits from rest match the paper's Figure 4 set
    /// (N = 1: (1,1), 2: (2,4), 3: (1,3), 10: (1,1)) all at once.
    pub paper_figure4_set_at: Vec<f64>,
    /// The k/k₁ at which, for every N, some start reaches the paper's Figure 4 orbit (the
    /// four orbits coexist as attractors, though not necessarily reached from rest).
    pub paper_figure4_set_reachable_at: Vec<f64>,
    /// The smallest k/k₁ at which N = 3 from rest reaches the paper's (1,3).
    pub n3_one_three_from: Option<f64>,
    /// The smallest k/k₁ at which N = 3 from rest is not on the (1,1) orbit.
    pub n3_leaves_one_one_at: Option<f64>,
}

/// Measures the claims on the diagrams over the k/k₁ grid.
pub fn claims(grid: &[f64], diagrams: &[Diagram]) -> Claims {
    let by_n = |n: usize| diagrams.iter().find(|d| d.modes == n);
    let first_velocity = |d: &Diagram, i: usize| d.columns[i][0].impact_velocities.first().copied();
    let all_one_one_at_smallest_k = diagrams.iter().all(|d| {
        d.columns[0]
            .iter()
            .all(|s| s.kind == OrbitKind::Periodic { m: 1, n: 1 })
    });
    let v0: Vec<f64> = diagrams
        .iter()
        .filter_map(|d| first_velocity(d, 0))
        .collect();
    let (lo, hi) = v0
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    let velocity_spread_at_smallest_k = if v0.is_empty() {
        f64::NAN
    } else {
        (hi - lo) / hi.abs()
    };
    let agreement = |a: usize, b: usize| match (by_n(a), by_n(b)) {
        (Some(x), Some(y)) => {
            (0..grid.len())
                .filter(|&i| x.kinds(i) == y.kinds(i))
                .count() as f64
                / grid.len() as f64
        }
        _ => f64::NAN,
    };
    let (first_orbit_difference, first_velocity_difference) = match (by_n(1), by_n(10)) {
        (Some(one), Some(ten)) => (
            (0..grid.len())
                .find(|&i| one.kinds(i) != ten.kinds(i))
                .map(|i| grid[i]),
            (0..grid.len())
                .find(
                    |&i| match (first_velocity(one, i), first_velocity(ten, i)) {
                        (Some(a), Some(b)) => ((a - b) / a).abs() > 0.05,
                        _ => true,
                    },
                )
                .map(|i| grid[i]),
        ),
        _ => (None, None),
    };
    let rest_kind = |n: usize, i: usize| by_n(n).map(|d| d.columns[i][0].kind);
    let periodic = |m, n| Some(OrbitKind::Periodic { m, n });
    let paper_figure4_set_at = (0..grid.len())
        .filter(|&i| {
            rest_kind(1, i) == periodic(1, 1)
                && rest_kind(2, i) == periodic(2, 4)
                && rest_kind(3, i) == periodic(1, 3)
                && rest_kind(10, i) == periodic(1, 1)
        })
        .map(|i| grid[i])
        .collect();
    let reachable =
        |n: usize, i: usize, kind: OrbitKind| by_n(n).is_some_and(|d| d.kinds(i).contains(&kind));
    let paper_figure4_set_reachable_at = (0..grid.len())
        .filter(|&i| {
            reachable(1, i, OrbitKind::Periodic { m: 1, n: 1 })
                && reachable(2, i, OrbitKind::Periodic { m: 2, n: 4 })
                && reachable(3, i, OrbitKind::Periodic { m: 1, n: 3 })
                && reachable(10, i, OrbitKind::Periodic { m: 1, n: 1 })
        })
        .map(|i| grid[i])
        .collect();
    let n3_one_three_from = (0..grid.len())
        .find(|&i| rest_kind(3, i) == periodic(1, 3))
        .map(|i| grid[i]);
    let n3_leaves_one_one_at = (0..grid.len())
        .find(|&i| rest_kind(3, i).is_some_and(|k| k != OrbitKind::Periodic { m: 1, n: 1 }))
        .map(|i| grid[i]);
    Claims {
        paper_figure4_set_at,
        paper_figure4_set_reachable_at,
        n3_one_three_from,
        n3_leaves_one_one_at,
        all_one_one_at_smallest_k,
        velocity_spread_at_smallest_k,
        first_orbit_difference,
        first_velocity_difference,
        n3_n10_agreement: agreement(3, 10),
        n2_n10_agreement: agreement(2, 10),
    }
}
