//! Continued branches for Figure 5: every periodic orbit the brute-force diagram finds,
//! traced in k by [`crate::analysis::continuation`] with its stability and bifurcations.
//!
//! Seeds, in a fixed order (so the result does not depend on the thread count): the
//! Figure 4 orbit (k = 100k₁ from rest, the paper's parameters), then each periodic
//! attractor of the brute-force diagram (period m ≤ 8) that no traced branch passes
//! through yet — same m and n, stable, the same largest impact velocity to 1% within
//! 1.5 grid intervals — up to `branch_seeds` attempts, in order of k and start. A seed
//! whose shooting does not converge (a slowly settling orbit, or one that converges to an
//! orbit of a divisor of m) is not retried for the same (m, n) at the next k.

use super::{point_state, Fig5Data, Fig5Params};
use crate::analysis::continuation::{self, Bifurcation, Branch, Family, Parameter, Settings};
use crate::error::Error;
use crate::analysis::orbit::{self, OrbitKind};
use crate::base::report::{KeyNumbers, Uncertainty};
use nalgebra::DVector;
use serde::Serialize;

/// One point of a branch, as drawn.
#[derive(Debug, Clone, Serialize)]
pub struct OverlayPoint {
    /// k/k₁.
    pub k_over_k1: f64,
    /// n.
    pub impacts_n: usize,
    /// Stable.
    pub stable: bool,
    /// The largest multiplier modulus.
    pub spectral_radius: f64,
    /// Impact velocities / ωA_free, largest first.
    pub impact_velocities: Vec<f64>,
}

/// A traced branch.
#[derive(Debug, Clone, Serialize)]
pub struct OverlayBranch {
    /// m.
    pub period_m: u64,
    /// The points.
    pub points: Vec<OverlayPoint>,
    /// Its bifurcations.
    pub bifurcations: Vec<Bifurcation>,
    /// Why it ends.
    pub end: String,
    /// At each Neimark–Sacker point: k/k₁ and the critical pair's |arg μ|/2π (the mean of
    /// the two points it lies between), the rotation number of the torus it gives birth to.
    pub neimark_sacker_rotation: Vec<(f64, f64)>,
}

/// All branches of one truncation.
#[derive(Debug, Clone, Serialize)]
pub struct BranchSet {
    /// N, the number of modes.
    pub modes: usize,
    /// The branches.
    pub branches: Vec<OverlayBranch>,
    /// Seeds traced (the Fig 4 orbit first).
    pub seeds: Vec<(f64, OrbitKind)>,
}

fn family(p: &Fig5Params, modes: usize) -> Family<'static> {
    // the base value of k is replaced by the family's parameter
    Family::forced(super::forced(p, modes, 1.0), Parameter::StopStiffness)
}

fn settings(p: &Fig5Params) -> Settings {
    Settings {
        max_step: p.branch_step,
        initial_step: p.branch_step.min(0.01),
        ..Settings::new(p.k_over_k1_range)
    }
}

fn overlay(b: &Branch, vamp: f64) -> OverlayBranch {
    OverlayBranch {
        period_m: b.period_m,
        points: b
            .points
            .iter()
            .map(|q| {
                let mut v: Vec<f64> = q.shape.impact_velocities.iter().map(|v| v / vamp).collect();
                v.sort_by(|a, b| b.total_cmp(a));
                OverlayPoint {
                    k_over_k1: q.parameter,
                    impacts_n: q.impacts_n,
                    stable: q.stable,
                    spectral_radius: q.spectral_radius(),
                    impact_velocities: v,
                }
            })
            .collect(),
        bifurcations: b.bifurcations.clone(),
        end: b.end.clone(),
        neimark_sacker_rotation: b
            .bifurcations
            .iter()
            .filter(|f| f.kind == continuation::BifurcationKind::NeimarkSacker)
            .filter_map(|f| {
                let at = |i: usize| super::rotation::pair_rotation(&b.points.get(i)?.multipliers);
                Some((f.parameter, 0.5 * (at(f.index)? + at(f.index + 1)?)))
            })
            .collect(),
    }
}

/// Whether a stable (m, n) orbit with largest impact velocity `v` at k is on a branch.
fn covered(set: &[OverlayBranch], k: f64, kind: (u64, usize), v: f64, spacing: f64) -> bool {
    set.iter().filter(|b| b.period_m == kind.0).any(|b| {
        b.points.iter().any(|q| {
            (q.k_over_k1 / k).ln().abs() <= 1.5 * spacing
                && q.stable
                && q.impacts_n == kind.1
                && q.impact_velocities
                    .first()
                    .is_some_and(|w| (w - v).abs() <= 0.01 * v.abs().max(1e-12))
        })
    })
}

/// The branch set of truncation `modes`, seeded from the brute-force diagram `d`.
///
/// # Errors
/// A model out of range (`Error::Parameter`), a flow that cannot be built, a run the
/// simulator refuses, or a failed continuation of the Figure 4 orbit (a seed from the
/// diagram that does not continue is skipped).
pub fn branch_set(p: &Fig5Params, d: &Fig5Data, modes: usize) -> Result<BranchSet, Error> {
    let fam = family(p, modes);
    let s = settings(p);
    let vamp = d.free_amplitude.1;
    let mut set = Vec::new();
    let mut seeds = Vec::new();
    // the Figure 4 orbit: k = 100k₁ from rest, its period read from the window
    let k0 = 100f64.clamp(p.k_over_k1_range.0, p.k_over_k1_range.1);
    let sim = fam.simulator(k0)?;
    let o = orbit::settle(&sim, &DVector::zeros(2 * modes), p.transient, p.recorded, 0)?;
    if let OrbitKind::Periodic { m, .. } = o.kind {
        for b in continuation::trace(&fam, &o.state, k0, m, &s)? {
            set.push(overlay(&b, vamp));
        }
        seeds.push((k0, o.kind));
    }
    let Some(g) = d.diagrams.iter().find(|g| g.modes == modes) else {
        return Ok(BranchSet {
            modes,
            branches: set,
            seeds,
        });
    };
    let spacing = (d.k_over_k1[1] / d.k_over_k1[0]).ln();
    let mut attempts = 0;
    // (grid index, m, n) of seeds that did not converge: not retried at the next k
    let mut failed: Vec<(usize, u64, u64)> = Vec::new();
    'grid: for (i, col) in g.columns.iter().enumerate() {
        for (start, r) in col.iter().enumerate() {
            let OrbitKind::Periodic { m, n } = r.kind else {
                continue;
            };
            let v = r.impact_velocities.iter().fold(0.0f64, |a, &b| a.max(b));
            if m > 8
                || failed.iter().any(|&f| f.1 == m && f.2 == n && f.0 + 1 >= i)
                || covered(&set, d.k_over_k1[i], (m, n as usize), v, spacing)
            {
                continue;
            }
            if attempts == p.branch_seeds {
                break 'grid;
            }
            attempts += 1;
            let k = d.k_over_k1[i];
            let x = point_state(p, modes, i, k, start)?;
            // a seed that does not converge (a slowly settling orbit) is skipped
            match continuation::trace(&fam, &x, k, m, &s) {
                Ok(bs) => {
                    set.extend(bs.iter().map(|b| overlay(b, vamp)));
                    seeds.push((k, r.kind));
                }
                Err(_) => failed.push((i, m, n)),
            }
        }
    }
    Ok(BranchSet {
        modes,
        branches: set,
        seeds,
    })
}

/// The continued branches' key numbers: per N the bifurcations of its period-1 branches
/// (text, 3 digits: each lies between two points at most one step apart), and the N = 3
/// grazings that turn the Figure 4 (1,1) orbit into (1,3), cited with their brackets.
pub(super) fn key_numbers(k: &mut KeyNumbers, d: &Fig5Data) {
    use crate::analysis::continuation::BifurcationKind;
    for set in &d.branches {
        let mut found: Vec<(f64, String)> = set
            .branches
            .iter()
            .filter(|b| b.period_m == 1)
            .flat_map(|b| &b.bifurcations)
            .map(|f| {
                (
                    f.parameter,
                    format!("{} {}", f.kind, crate::base::report::round_sig(f.parameter, 3)),
                )
            })
            .collect();
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        found.dedup_by(|a, b| a.1 == b.1);
        let list: Vec<String> = found.into_iter().map(|f| f.1).collect();
        k.text(
            format!("N={} period-1 bifurcations", set.modes),
            if list.is_empty() { "none".into() } else { list.join("; ") },
        );
        k.integer(format!("N={} continued branches", set.modes), set.branches.len() as i64);
    }
    isolas(k, d);
    neimark_sacker_pairs(k, d);
    // The Figure 4 branch (the first one traced, upwards from k = 100k₁): where its
    // contact splits (N = 3: twice, on the way to the paper's (1,3); N = 10: once).
    let graze = |modes: usize, impacts: (usize, usize)| {
        let up = d.branches.iter().find(|s| s.modes == modes)?.branches.first()?;
        up.bifurcations
            .iter()
            .find(|f| f.kind == BifurcationKind::Grazing && f.impacts == impacts)
            .cloned()
    };
    for (modes, impacts, name) in [
        (3, (1, 2), "N=3 grazing to 2 contacts at"),
        (3, (2, 3), "N=3 grazing to 3 contacts at"),
        (10, (1, 2), "N=10 grazing to 2 contacts at"),
    ] {
        if !d.branches.iter().any(|s| s.modes == modes) {
            continue;
        }
        match graze(modes, impacts) {
            Some(f) => {
                let (lo, hi) = (f.between.0.min(f.between.1), f.between.0.max(f.between.1));
                k.cited(
                    name,
                    f.parameter,
                    8,
                    Uncertainty::new(
                        (f.parameter - lo).max(hi - f.parameter),
                        format!("between orbits at {lo:.7} and {hi:.7} k₁ with the two contact counts (the continuation's bracket bisected; grazing distance interpolated to 0)"),
                    ),
                    "k₁",
                );
            }
            None => k.text(name, "not found"),
        }
    }
    // N = 2's Figure 4 orbit, (2,4), loses stability by period doubling: where the sweep's
    // (2,4) must give way to (4,8)
    let doubling = d
        .branches
        .iter()
        .find(|s| s.modes == 2)
        .and_then(|s| s.branches.first())
        .and_then(|b| b.bifurcations.iter().find(|f| f.kind == BifurcationKind::PeriodDoubling));
    if let Some(f) = doubling {
        let (lo, hi) = (f.between.0.min(f.between.1), f.between.0.max(f.between.1));
        k.cited(
            "N=2 period doubling on the Fig 4 branch",
            f.parameter,
            4,
            Uncertainty::new(
                (f.parameter - lo).max(hi - f.parameter),
                format!("between adjacent continuation points {lo:.4} and {hi:.4} k₁ (the multiplier's crossing of −1 interpolated)"),
            ),
            "k₁",
        );
    }
    let Some(up) = d.branches.iter().find(|s| s.modes == 3).and_then(|s| s.branches.first()) else {
        return;
    };
    k.text(
        "N=3 bifurcations on the Fig 4 branch up to 1000k1",
        up.bifurcations
            .iter()
            .map(|f| f.kind.to_string())
            .collect::<Vec<_>>()
            .join(", "),
    );
}

/// N = 1's windows of period m ≥ 3: closed branches (isolas) bounded by folds. Their
/// periods, and the largest k any of them reaches: a fold, beyond the largest traced k by
/// no more than that point's larger k-difference to its two neighbours (near a fold k is
/// quadratic in arclength, k_f − c(s − s_f)²; the nearest point lies within h/2 of s_f, so
/// k_f − k_max ≤ ch²/4, while the neighbour a step further from s_f differs from it by
/// at least ch²).
fn isolas(k: &mut KeyNumbers, d: &Fig5Data) {
    let Some(one) = d.branches.iter().find(|s| s.modes == 1) else {
        return;
    };
    let windows: Vec<&OverlayBranch> = one
        .branches
        .iter()
        .filter(|b| b.period_m >= 3 && b.end.starts_with("closed loop"))
        .collect();
    let (Some(lo), Some(hi)) = (
        windows.iter().map(|b| b.period_m).min(),
        windows.iter().map(|b| b.period_m).max(),
    ) else {
        return k.text("N=1 isolas, periods", "none");
    };
    k.text("N=1 isolas, periods", format!("{lo} to {hi}"));
    // the largest traced k, and the larger step to its neighbours on the loop
    let mut top = (0.0f64, 0.0f64);
    for b in &windows {
        let ks: Vec<f64> = b.points.iter().map(|p| p.k_over_k1).collect();
        for (i, &x) in ks.iter().enumerate() {
            if x > top.0 {
                let prev = ks[(i + ks.len() - 1) % ks.len()];
                let next = ks[(i + 1) % ks.len()];
                top = (x, (x - prev).abs().max((x - next).abs()));
            }
        }
    }
    k.cited(
        "N=1 isolas reach up to",
        top.0,
        3,
        Uncertainty::new(
            top.1,
            "the largest k traced on the loops; the fold lies within one continuation step",
        ),
        "k₁",
    );
}

/// The Neimark–Sacker pair that bounds the torus interval on the (1,1) branch of every
/// N ≥ 2: the lowest and the highest of the pair over the truncations.
fn neimark_sacker_pairs(k: &mut KeyNumbers, d: &Fig5Data) {
    use crate::analysis::continuation::BifurcationKind;
    let mut first = Vec::new();
    let mut second = Vec::new();
    for set in d.branches.iter().filter(|s| s.modes >= 2) {
        let mut ns: Vec<f64> = set
            .branches
            .iter()
            .filter(|b| b.period_m == 1)
            .flat_map(|b| &b.bifurcations)
            .filter(|f| f.kind == BifurcationKind::NeimarkSacker)
            .map(|f| f.parameter)
            .collect();
        ns.sort_by(f64::total_cmp);
        ns.dedup_by(|a, b| (*a - *b).abs() < 1e-6 * b.abs());
        if let [a, b] = ns[..] {
            first.push(a);
            second.push(b);
        }
    }
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let r = |x| crate::base::report::round_sig(x, 3);
        if r(lo) == r(hi) {
            format!("{}", r(lo))
        } else {
            format!("{}–{}", r(lo), r(hi))
        }
    };
    if first.is_empty() {
        return k.text("N>=2 (1,1) Neimark-Sacker pair", "none");
    }
    k.text("N>=2 (1,1) first Neimark-Sacker", range(&first));
    k.text("N>=2 (1,1) second Neimark-Sacker", range(&second));
}
