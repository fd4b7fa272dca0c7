//! Scene `energetic-map`: beyond the paper, §5.4 and §7 made quantitative — the energetic
//! coefficient of restitution r_E (eq 39, [`crate::analysis::energetic`]) over the forcing frequency
//! ω and the stop stiffness k at d₀ = 0, ζ₁ = 0.01 (Figure 4's damping and forcing). The
//! paper concludes that such coefficients are "dependent on the dynamics observed"; this
//! chart says by how much.
//!
//! **The truncation at each k** follows stiffness matching (§2.3), by the book's one rule
//! ([`crate::analysis::convergence::matched_modes`]): at least 10 modes, and as many as
//! one contact needs for its observables to 1 %; every point is recomputed with N + 10
//! modes: a point whose orbit or
//! r_E (beyond 0.01) changes is marked unconverged rather than coloured. A random start
//! marks coexisting attractors.

pub mod render;

use crate::analysis::energetic::{orbit_coefficient, Coefficient};
use crate::error::Error;
use crate::analysis::orbit::{random_state, OrbitKind, SplitMix64};
use crate::model::problems::Forced;
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::engine::sim::Simulator;
use nalgebra::DVector;
use rayon::prelude::*;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct MapParams {
    /// ω/(β₁⁻)² values.
    pub omega_over_w1: Vec<f64>,
    /// k/k₁ values.
    pub k_over_k1: Vec<f64>,
    /// ζ₁.
    pub zeta1: f64,
    /// Periods discarded.
    pub transient: u64,
    /// Periods over which the orbit is labelled.
    pub window: u64,
    /// Modes added for the convergence check.
    pub extra_modes: usize,
    /// r_E changes above this mark a point unconverged.
    pub convergence_tolerance: f64,
    /// Seed of the random start.
    pub seed: u64,
}

impl MapParams {
    /// The book's resolution: 23 × 13 points.
    pub fn book() -> Self {
        Self {
            omega_over_w1: (0..=22).map(|i| 0.8 + 0.1 * i as f64).collect(),
            k_over_k1: (0..=12).map(|i| 10f64.powf(1.0 + 0.25 * i as f64)).collect(),
            zeta1: 0.01,
            transient: 1000,
            window: 40,
            extra_modes: 10,
            convergence_tolerance: 0.01,
            seed: 2013,
        }
    }

    /// A reduced version for the tests.
    pub fn test() -> Self {
        Self {
            omega_over_w1: vec![0.8, 2.0, 3.0],
            k_over_k1: vec![10.0, 100.0, 1000.0],
            ..Self::book()
        }
    }
}

/// The truncation for stop stiffness k/k₁: the book's one rule
/// ([`crate::analysis::convergence::matched_modes`]: at least 10 modes, and as many as one
/// contact needs for its observables to 1 %).
///
/// # Errors
/// The errors of [`crate::analysis::convergence::matched_modes`]: `Error::Unsupported` when N*
/// is unresolved or above the model's largest N, `Error::Parameter` for k/k₁ or ζ₁ out of range.
pub fn matched_modes(k_over_k1: f64, zeta1: f64) -> Result<usize, Error> {
    crate::analysis::convergence::matched_modes(k_over_k1, 1e-2, zeta1, 10)
}

/// What a point shows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Cell {
    /// A converged, unique periodic orbit with a real r_E.
    Value(f64),
    /// The orbit or r_E changes with N + 10 modes.
    Unconverged,
    /// Not periodic within the window (eq 39's limit not established).
    NotPeriodic,
    /// Rest and a random start reach different orbits.
    Coexisting,
    /// Mode 1 loses more than its entry kinetic energy: no real r_E.
    NoRealValue,
    /// The tip never reaches the stop.
    NoContact,
}

/// One point of the map.
#[derive(Debug, Clone, Serialize)]
pub struct MapPoint {
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// k/k₁.
    pub k_over_k1: f64,
    /// N used.
    pub modes: usize,
    /// The orbit from rest.
    pub kind: OrbitKind,
    /// Its eq (39) value.
    pub coefficient: Option<Coefficient>,
    /// With N + extra modes.
    pub refined: (OrbitKind, Option<Coefficient>),
    /// From a random start.
    pub random: OrbitKind,
    /// The verdict on the point.
    pub cell: Cell,
    /// With N + 2 × extra modes: the third rung of the truncation ladder, computed only for
    /// the points the key numbers cite ([`cited_points`]).
    pub third: Option<(OrbitKind, Option<Coefficient>)>,
}

impl MapPoint {
    /// The truncation ± of a converged value by the book's one rule (Richardson over N,
    /// N + extra, N + 2·extra: [`crate::analysis::convergence::truncation`]); None without the
    /// third rung or when it leaves the orbit.
    pub fn truncation(&self, extra: usize) -> Option<crate::analysis::convergence::TruncationError> {
        let Cell::Value(r) = self.cell else {
            return None;
        };
        let (kind, third) = self.third?;
        let value = |c: Option<Coefficient>| c.and_then(|c| c.value());
        if kind != self.kind {
            return None;
        }
        let ladder = [
            (self.modes, r),
            (self.modes + extra, value(self.refined.1)?),
            (self.modes + 2 * extra, value(third)?),
        ];
        crate::analysis::convergence::truncation_error(self.modes, &ladder)
    }
}

/// The points whose r_E the key numbers cite: the smallest and largest converged values and
/// the converged values along ω = 2(β₁⁻)² at k = 10² and 10³k₁ (Figure 6(b)'s frequency).
pub fn cited_points(points: &[MapPoint]) -> Vec<usize> {
    let values: Vec<(usize, f64)> = points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| match p.cell {
            Cell::Value(r) => Some((i, r)),
            _ => None,
        })
        .collect();
    let mut cited: Vec<usize> = [
        values.iter().min_by(|a, b| a.1.total_cmp(&b.1)),
        values.iter().max_by(|a, b| a.1.total_cmp(&b.1)),
    ]
    .into_iter()
    .flatten()
    .map(|v| v.0)
    .collect();
    cited.extend(values.iter().map(|v| v.0).filter(|&i| on_omega_2_at_cited_k(&points[i])));
    cited.sort_unstable();
    cited.dedup();
    cited
}

/// ω = 2(β₁⁻)² and k = 10² or 10³k₁: the line of Figure 6(b) whose r_E is cited.
fn on_omega_2_at_cited_k(p: &MapPoint) -> bool {
    (p.omega_over_w1 - 2.0).abs() < 1e-9
        && [100.0, 1000.0]
            .iter()
            .any(|k| (p.k_over_k1 / k - 1.0).abs() < 1e-9)
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct MapData {
    /// The parameters used.
    pub params: MapParams,
    /// Points, ω fastest.
    pub points: Vec<MapPoint>,
}

fn point(p: &MapParams, omega: f64, k: f64, modes: usize, index: u64) -> Result<MapPoint, Error> {
    let forced = |n| Forced {
        modes: n,
        k_over_k1: k,
        zeta1: p.zeta1,
        omega_over_w1: omega,
        gap: 0.0,
        printed_eq37_amplitude: false,
    };
    let sim = Simulator::new(forced(modes).model()?)?;
    let base = orbit_coefficient(&sim, &DVector::zeros(2 * modes), p.transient, p.window)?;
    let n2 = modes + p.extra_modes;
    let fine = Simulator::new(forced(n2).model()?)?;
    let refined = orbit_coefficient(&fine, &DVector::zeros(2 * n2), p.transient, p.window)?;
    let (amp, _) = sim.model().free_tip_amplitude();
    let mut rng = SplitMix64::for_point(p.seed, index, 0, 0);
    let x0 = random_state(&mut rng, modes, 4.0 * amp, sim.omega());
    let random = orbit_coefficient(&sim, &x0, p.transient, p.window)?.kind;
    let value = |c: Option<Coefficient>| c.and_then(|c| c.value());
    let cell = match (base.kind, base.coefficient) {
        (OrbitKind::NotPeriodic, _) => Cell::NotPeriodic,
        _ if random != base.kind => Cell::Coexisting,
        _ if refined.kind != base.kind => Cell::Unconverged,
        (_, Some(Coefficient::NoContact)) => Cell::NoContact,
        (_, Some(Coefficient::NoRealValue(_))) => Cell::NoRealValue,
        (_, c) => match (value(c), value(refined.coefficient)) {
            (Some(a), Some(b)) if (a - b).abs() <= p.convergence_tolerance => Cell::Value(a),
            (Some(_), _) => Cell::Unconverged,
            (None, _) => Cell::NotPeriodic,
        },
    };
    Ok(MapPoint {
        omega_over_w1: omega,
        k_over_k1: k,
        modes,
        kind: base.kind,
        coefficient: base.coefficient,
        refined: (refined.kind, refined.coefficient),
        random,
        cell,
        third: None,
    })
}

/// The third rung (N + 2·extra modes, from rest) of a cited point.
fn third_rung(p: &MapParams, point: &MapPoint) -> Result<(OrbitKind, Option<Coefficient>), Error> {
    let n3 = point.modes + 2 * p.extra_modes;
    let model = Forced {
        modes: n3,
        k_over_k1: point.k_over_k1,
        zeta1: p.zeta1,
        omega_over_w1: point.omega_over_w1,
        gap: 0.0,
        printed_eq37_amplitude: false,
    }
    .model()?;
    let sim = Simulator::new(model)?;
    let o = orbit_coefficient(&sim, &DVector::zeros(2 * n3), p.transient, p.window)?;
    Ok((o.kind, o.coefficient))
}

/// Computes every point (in parallel, deterministic for the seed whatever the thread
/// count: each point has its own random stream).
///
/// # Errors
/// A k the stiffness matching cannot serve ([`matched_modes`]), a model out of range
/// (`Error::Parameter`), a flow that cannot be built, or a run the simulator refuses.
pub fn compute(p: &MapParams, progress: &dyn Progress) -> Result<MapData, Error> {
    let grid: Vec<(f64, f64)> = p
        .k_over_k1
        .iter()
        .flat_map(|&k| p.omega_over_w1.iter().map(move |&w| (w, k)))
        .collect();
    // N per k, once per k (each is a scan of one contact over N = 1 … 200)
    let modes: Vec<usize> = p
        .k_over_k1
        .par_iter()
        .map(|&k| matched_modes(k, p.zeta1))
        .collect::<Result<_, Error>>()?;
    let task = progress.task("r_E map", grid.len() as u64);
    let points = grid
        .par_iter()
        .enumerate()
        .map(|(i, &(w, k))| {
            let n = modes[i / p.omega_over_w1.len()];
            let r = point(p, w, k, n, i as u64);
            task.advance(1);
            r
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let mut points = points;
    let cited = cited_points(&points);
    let thirds = cited
        .par_iter()
        .map(|&i| third_rung(p, &points[i]))
        .collect::<Result<Vec<_>, Error>>()?;
    for (i, t) in cited.into_iter().zip(thirds) {
        points[i].third = Some(t);
    }
    Ok(MapData {
        params: p.clone(),
        points,
    })
}

/// The scene.
pub struct EnergeticMap;

impl Scene for EnergeticMap {
    const NAME: &'static str = "energetic-map";
    const PAPER: &'static str = "§5.4 and §7 (beyond the paper)";
    const TITLE: &'static str = "§7: r_E and the dynamics";
    const GIST: &'static str = "r_E depends on the dynamics";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str = "r_E (eq 39) over the forcing frequency and the stop stiffness, d0 = 0, zeta1 = 0.01, N by stiffness matching";
    const CLAIM: &'static str = "Energetic coefficients of restitution are \"dependent on the dynamics observed\" (§7).";
    const CHAPTER: &'static str = "fig6.md";
    const METHOD: &'static str = "at each (ω, k) the compliant model with N from stiffness matching (at least 10 modes, and as many as one contact needs for its observables to 1 %) from rest, 1000 periods discarded, eq (39) over one period of the orbit; recomputed with N + 10 modes (orbit and r_E within 0.01, else unconverged) and from a random start (else coexisting); each cited r_E also with N + 20 modes, its ± by Richardson extrapolation over the three N";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("smallest converged r_E", "smallest r_E"),
        ("largest", "largest r_E"),
        ("points with a converged, unique r_E", "points with a value"),
    ];
    const SETTABLE: &'static [crate::results::settings::Setting] = &[crate::results::settings::ZETA1, crate::results::settings::SEED];
    type Params = MapParams;
    type Data = MapData;

    fn params(resolution: Resolution) -> MapParams {
        match resolution {
            Resolution::Book => MapParams::book(),
            Resolution::Test => MapParams::test(),
        }
    }

    fn compute(p: &MapParams, progress: &dyn Progress) -> Result<MapData, Error> {
        compute(p, progress)
    }

    fn key_numbers(d: &MapData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        let count = |f: &dyn Fn(&Cell) -> bool| d.points.iter().filter(|p| f(&p.cell)).count() as i64;
        k.integer("points", d.points.len() as i64);
        // N at each k, as runs "N from k"
        let mut runs: Vec<String> = Vec::new();
        let mut last = None;
        for (i, &kk) in d.params.k_over_k1.iter().enumerate() {
            let n = d.points[i * d.params.omega_over_w1.len()].modes;
            if last != Some(n) {
                // as the atlas writes it: 10k₁, 1000k₁, 5623k₁
                let k = crate::base::report::pretty(kk, 3);
                let k = if k.contains('.') { k.trim_end_matches('0').trim_end_matches('.').to_string() } else { k };
                runs.push(format!("{n} from {k}k₁"));
                last = Some(n);
            }
        }
        k.text("modes along k", runs.join(", "));
        k.integer("points with a value", count(&|c| matches!(c, Cell::Value(_))));
        k.integer("unconverged points", count(&|c| *c == Cell::Unconverged));
        k.integer("not periodic points", count(&|c| *c == Cell::NotPeriodic));
        k.integer("coexisting points (lower bound)", count(&|c| *c == Cell::Coexisting));
        k.integer("no real value points", count(&|c| *c == Cell::NoRealValue));
        k.integer("no contact points", count(&|c| *c == Cell::NoContact));
        let values: Vec<(f64, &MapPoint)> = d
            .points
            .iter()
            .filter_map(|p| match p.cell {
                Cell::Value(r) => Some((r, p)),
                _ => None,
            })
            .collect();
        let extra = d.params.extra_modes;
        let at = |p: &MapPoint| format!("ω = {:.1}(β₁⁻)², k = {:.3e}k₁", p.omega_over_w1, p.k_over_k1);
        // a converged value with its truncation ± (the book's one rule), or as text when
        // the third rung left the orbit
        let cite = |k: &mut KeyNumbers, key: &str, r: f64, p: &MapPoint, digits: usize| match p
            .truncation(extra)
        {
            Some(t) => k.cited(key, r, digits, Uncertainty::new(t.plus_minus.max(1e-12), t.basis()), ""),
            None => k.text(
                key,
                format!("{r:.3} (N + {} modes leaves the orbit: no convergence estimate)", 2 * extra),
            ),
        };
        if let Some((r, p)) = values.iter().min_by(|a, b| a.0.total_cmp(&b.0)) {
            cite(&mut k, "smallest r_E", *r, p, 3);
            k.text("smallest r_E at", at(p));
        }
        if let Some((r, p)) = values.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
            cite(&mut k, "largest r_E", *r, p, 3);
            k.text("largest r_E at", at(p));
        }
        // along ω = 2(β₁⁻)², Figure 6(b)'s frequency: where r_E first reaches the paper's 0.74
        let line: Vec<(f64, f64)> = d
            .points
            .iter()
            .filter(|p| (p.omega_over_w1 - 2.0).abs() < 1e-9)
            .filter_map(|p| match p.cell {
                Cell::Value(r) => Some((p.k_over_k1, r)),
                _ => None,
            })
            .collect();
        match line.iter().position(|&(_, r)| r >= 0.74) {
            None | Some(0) => k.text("omega=2 r_E reaches 0.74 at k", "not between two grid values"),
            Some(i) => {
                let (lo, hi) = (line[i - 1].0, line[i].0);
                k.cited(
                    "omega=2 r_E reaches 0.74 at k",
                    0.5 * (lo + hi),
                    3,
                    Uncertainty::new(
                        0.5 * (hi - lo),
                        format!("between adjacent grid values {lo:.4} and {hi:.4} k₁"),
                    ),
                    "k₁",
                );
            }
        }
        for p in d.points.iter().filter(|p| on_omega_2_at_cited_k(p)) {
            let key = format!("omega=2 k={:e} r_E", p.k_over_k1);
            match p.cell {
                Cell::Value(r) => cite(&mut k, &key, r, p, 4),
                c => k.text(key, format!("{c:?}")),
            }
        }
        k
    }

    fn verdict(d: &MapData) -> Verdict {
        let values: Vec<f64> = d
            .points
            .iter()
            .filter_map(|p| match p.cell {
                Cell::Value(r) => Some(r),
                _ => None,
            })
            .collect();
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| (a.min(r), b.max(r)));
        Verdict {
            outcome: if values.len() >= 2 && hi - lo > 0.1 {
                Outcome::Reproduced
            } else {
                Outcome::NotReproduced
            },
            evidence: format!(
                "r_E ranges from {lo:.2} to {hi:.2} over {} of {} points; the others have no unique periodic orbit, no real value or no converged truncation",
                values.len(),
                d.points.len()
            ),
        }
    }

    fn render(d: &MapData) -> Result<Rendered, crate::results::render::RenderError> {
        Rendered::drawn(|layout| render::plot(d, layout), render::table(d))
    }
}
