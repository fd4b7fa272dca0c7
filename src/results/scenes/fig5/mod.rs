//! Scene `fig5`: Figure 5 and §5.3 — brute-force bifurcation diagrams in the stop
//! stiffness k on the impact section (d = d₀, ḋ > 0), for N = 1, 2, 3, 10, with the other
//! parameters of Figure 4 and several initial conditions per k (the first one at rest).
//!
//! The paper's claims tested here: agreement between the truncations for k ≲ k₁;
//! N-dependence from about k₂ = 39.3k₁; "N = 3 is sufficient to capture the qualitative
//! features of the bifurcation".
//!
//! Sweep points run in parallel (rayon); each point's random initial conditions come from
//! its own seeded stream, so the diagram does not depend on the thread count.

pub mod branches;
mod claims;
pub mod render;
pub mod rotation;

pub use claims::Claims;
use claims::claims;

use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::error::{self, Error, ParameterError};
use crate::analysis::orbit::{self, OrbitKind, SplitMix64};
use crate::model::problems::{self, Forced};
use crate::engine::sim::Simulator;
use nalgebra::DVector;
use rayon::prelude::*;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct Fig5Params {
    /// Truncations N.
    pub modes: Vec<usize>,
    /// k/k₁ range (log-spaced, inclusive).
    pub k_over_k1_range: (f64, f64),
    /// Number of k values.
    pub points: usize,
    /// Initial conditions per k (the first at rest).
    pub starts: usize,
    /// Periods discarded.
    pub transient: u64,
    /// Periods recorded.
    pub recorded: u64,
    /// ζ₁.
    pub zeta1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// Seed of the initial conditions.
    pub seed: u64,
    /// Largest continuation step of the overlaid branches (in ln k, with the orbit scaled
    /// by its size).
    pub branch_step: f64,
    /// Brute-force attractors not yet on a branch that seed one, at most.
    pub branch_seeds: usize,
}

impl Fig5Params {
    /// The book's resolution (the issue asks for at least 200 × 8 × 1000 + 50).
    pub fn book() -> Self {
        Self {
            modes: vec![1, 2, 3, 10],
            k_over_k1_range: (1.0, 1000.0),
            points: 200,
            starts: 8,
            transient: 1000,
            recorded: 50,
            zeta1: 0.01,
            omega_over_w1: 2.0,
            seed: 2013,
            branch_step: 0.02,
            branch_seeds: 16,
        }
    }

    /// A reduced version for the tests: fewer k values and starts, but the paper's
    /// 1000-period transient (with ζ₁ = 0.01 free motion decays only like e^{-0.031 t/T},
    /// so a shorter transient leaves orbits unsettled at the 1e-9 test).
    pub fn test() -> Self {
        Self {
            points: 10,
            starts: 2,
            recorded: 40,
            branch_step: 0.05,
            branch_seeds: 2,
            ..Self::book()
        }
    }

    /// Every count at least what the diagram needs, the k range positive and increasing.
    ///
    /// # Errors
    /// [`ParameterError`] for no truncations, an N out of 1…400, starts out of 1…1000, points out
    /// of 1…100 000, fewer than 2 recorded periods, or a k range that is not 0 < lower < upper.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if self.modes.is_empty() {
            return Err(ParameterError::new("truncations N", "none", "at least one"));
        }
        for &n in &self.modes {
            error::count_in_range("modes N", n, crate::model::galerkin::MAX_MODES)?;
        }
        error::count_in_range("initial conditions per k", self.starts, 1000)?;
        error::count_in_range("k values", self.points, 100_000)?;
        if self.recorded < 2 {
            return Err(ParameterError::new(
                "recorded periods",
                self.recorded,
                "at least 2 (periodicity is tested between strobe samples)",
            ));
        }
        let (lo, hi) = self.k_over_k1_range;
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
            return Err(ParameterError::new(
                "k/k₁ range",
                format!("{lo}..{hi}"),
                "0 < lower < upper, finite",
            ));
        }
        Ok(())
    }

    /// The k/k₁ grid.
    pub fn grid(&self) -> Vec<f64> {
        let (lo, hi) = self.k_over_k1_range;
        let n = self.points.max(2);
        (0..n)
            .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
            .collect()
    }
}

/// One initial condition at one k.
#[derive(Debug, Clone, Serialize)]
pub struct StartResult {
    /// The orbit reached.
    pub kind: OrbitKind,
    /// Tip velocities at every entry into contact in the recorded window, divided by the
    /// unconstrained tip velocity amplitude ωA_free.
    pub impact_velocities: Vec<f64>,
}

/// One diagram (one N).
#[derive(Debug, Clone, Serialize)]
pub struct Diagram {
    /// N, the number of modes.
    pub modes: usize,
    /// Per k: one result per start.
    pub columns: Vec<Vec<StartResult>>,
}

impl Diagram {
    /// The distinct orbit kinds reached at grid point i.
    pub fn kinds(&self, i: usize) -> Vec<OrbitKind> {
        let mut k: Vec<OrbitKind> = self.columns[i].iter().map(|s| s.kind).collect();
        k.sort();
        k.dedup();
        k
    }
}

/// A change of the set of orbits between consecutive k.
#[derive(Debug, Clone, Serialize)]
pub struct Transition {
    /// k/k₁ before and after.
    pub between: (f64, f64),
    /// Orbit sets before and after.
    pub from: Vec<OrbitKind>,
    /// Orbit sets before and after.
    pub to: Vec<OrbitKind>,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fig5Data {
    /// The parameters used.
    pub params: Fig5Params,
    /// The k/k₁ grid.
    pub k_over_k1: Vec<f64>,
    /// One diagram per N.
    pub diagrams: Vec<Diagram>,
    /// Orbit-set changes along k, per N.
    pub transitions: Vec<(usize, Vec<Transition>)>,
    /// The claims.
    pub claims: Claims,
    /// The rigid limit of the N = 1 diagram (when N = 1 is swept).
    pub rigid_limit: Option<RigidLimit>,
    /// The velocity unit: the free tip amplitude A_free and ωA_free at this ω (the same for
    /// every N and k: the forcing has mode 1's shape, and mode 1 does not feel k in free
    /// flight).
    pub free_amplitude: (f64, f64),
    /// The continued branches, one set per N.
    pub branches: Vec<branches::BranchSet>,
    /// The "not periodic" bands between each N's Neimark–Sacker pair, with their rotation
    /// numbers.
    pub bands: Vec<rotation::Band>,
}

/// The N = 1 model's k → ∞ limit: the impact oscillator with Newton's law, r = 1 (the
/// compliant contact's restitution tends to 1), from rest.
#[derive(Debug, Clone, Serialize)]
pub struct RigidLimit {
    /// Its orbit.
    pub kind: OrbitKind,
    /// The stroboscopic residual of the last window.
    pub residual: f64,
    /// The impact velocity on that orbit, divided by ωA_free.
    pub impact_velocity: f64,
    /// The compliant N = 1 impact velocity (from rest) at the largest k of the sweep.
    pub compliant_at_largest_k: f64,
    /// The rigid limit's (1,1) orbit by shooting (with the saltation matrix at the
    /// impact): its Floquet multipliers as [re, im], largest first.
    pub multipliers: Vec<[f64; 2]>,
    /// The compliant N = 1 (1,1) orbit's multipliers at the largest k of the sweep.
    pub compliant_multipliers_at_largest_k: Vec<[f64; 2]>,
    /// e^{−c₁T/2}, c₁ = 2ζ₁(β₁⁻)²: what each of two multipliers would be if the pair's
    /// product, e^{−c₁T} by Liouville's formula (the stop adds stiffness, no damping, and
    /// r = 1 keeps the tip speed), were shared equally.
    pub damping_bound: f64,
}

/// The N = 1 rigid limit at the sweep's ζ₁ and ω (see [`RigidLimit`]), and the
/// multipliers of both models' (1,1) orbits.
fn rigid_limit(
    p: &Fig5Params,
    compliant_at_largest_k: f64,
    largest_k: f64,
) -> Result<RigidLimit, Error> {
    use crate::analysis::shooting;
    use crate::engine::rigid::RigidImpact;
    let m = forced(p, 1, 1.0).model()?;
    let (_, vamp) = m.free_tip_amplitude();
    let rigid = RigidImpact::new(
        Simulator::new(m)?,
        crate::model::restitution::impulse_response(1, 1.0)?,
    )?;
    let o = orbit::settle_rigid(&rigid, &DVector::zeros(2), p.transient, p.recorded)?;
    let start = DVector::from_column_slice(&o.state);
    let rigid_orbit = shooting::shoot(&rigid, &start, 1)?;
    let compliant = Simulator::new(forced(p, 1, largest_k).model()?)?;
    let settled = orbit::settle_map(&compliant, &DVector::zeros(2), p.transient, p.recorded)?;
    let compliant_orbit = shooting::shoot(&compliant, &settled.state, 1)?;
    let c1 = 2.0 * p.zeta1 * crate::model::galerkin::first_frequency();
    let period = 2.0 * std::f64::consts::PI / (p.omega_over_w1 * crate::model::galerkin::first_frequency());
    Ok(RigidLimit {
        kind: o.kind,
        residual: o.residual,
        impact_velocity: o.impact_velocity / vamp,
        compliant_at_largest_k,
        multipliers: rigid_orbit.multipliers,
        compliant_multipliers_at_largest_k: compliant_orbit.multipliers,
        damping_bound: (-c1 * period / 2.0).exp(),
    })
}

/// The diagram's model: Figure 4's parameters at N modes and stop stiffness k/k₁.
pub fn forced(p: &Fig5Params, modes: usize, k_over_k1: f64) -> Forced {
    Forced {
        k_over_k1,
        zeta1: p.zeta1,
        omega_over_w1: p.omega_over_w1,
        ..problems::figure4(modes)
    }
}

/// The state a start of the diagram ends in after the transient (the seed of a branch).
///
/// # Errors
/// A model out of range (`Error::Parameter`), a flow that cannot be built, or a transient the
/// simulator refuses (`Error::Chatter`, `Error::Invariant`).
pub fn point_state(
    p: &Fig5Params,
    modes: usize,
    k_index: usize,
    k_over_k1: f64,
    start: usize,
) -> Result<DVector<f64>, Error> {
    let m = forced(p, modes, k_over_k1).model()?;
    let (amp, _) = m.free_tip_amplitude();
    let omega = m.omega();
    let sim = Simulator::new(m)?;
    let x0 = start_state(p, modes, k_index, start, amp, omega);
    Ok(sim.run(&x0, p.transient, &mut ())?.state)
}

/// Start `s` at grid point `k_index`: rest, or a seeded random state.
fn start_state(
    p: &Fig5Params,
    modes: usize,
    k_index: usize,
    s: usize,
    amp: f64,
    omega: f64,
) -> DVector<f64> {
    if s == 0 {
        DVector::zeros(2 * modes)
    } else {
        let mut rng = SplitMix64::for_point(p.seed, modes as u64, k_index as u64, s as u64);
        orbit::random_state(&mut rng, modes, 4.0 * amp, omega)
    }
}

fn point(
    p: &Fig5Params,
    modes: usize,
    k_index: usize,
    k_over_k1: f64,
) -> Result<Vec<StartResult>, Error> {
    let m = forced(p, modes, k_over_k1).model()?;
    let (amp, vamp) = m.free_tip_amplitude();
    let omega = m.omega();
    let sim = Simulator::new(m)?;
    (0..p.starts)
        .map(|s| {
            let x0 = start_state(p, modes, k_index, s, amp, omega);
            let o = orbit::settle(&sim, &x0, p.transient, p.recorded, 0)?;
            let end = o.window_start + p.recorded as i64;
            Ok(StartResult {
                kind: o.kind,
                impact_velocities: o
                    .entries(o.window_start, end)
                    .map(|e| e.tip_velocity / vamp)
                    .collect(),
            })
        })
        .collect()
}

/// Runs the scene; `progress` is called once per finished (N, k) point.
///
/// # Errors
/// Parameters that fail [`Fig5Params::validate`] or a model out of range (`Error::Parameter`);
/// a flow that cannot be built; a run the simulator refuses; shooting for the rigid limit's
/// orbits that does not converge; or the errors of [`branches::branch_set`].
pub fn compute(p: &Fig5Params, progress: &(dyn Fn() + Sync)) -> Result<Fig5Data, Error> {
    p.validate()?;
    let grid = p.grid();
    let tasks: Vec<(usize, usize)> = p
        .modes
        .iter()
        .flat_map(|&n| (0..grid.len()).map(move |i| (n, i)))
        .collect();
    let results = tasks
        .par_iter()
        .map(|&(n, i)| {
            let r = point(p, n, i, grid[i]);
            progress();
            r
        })
        .collect::<Result<Vec<_>, _>>()?;
    let diagrams: Vec<Diagram> = p
        .modes
        .iter()
        .enumerate()
        .map(|(d, &n)| Diagram {
            modes: n,
            columns: results[d * grid.len()..(d + 1) * grid.len()].to_vec(),
        })
        .collect();
    let transitions = diagrams
        .iter()
        .map(|d| {
            let t = (1..grid.len())
                .filter(|&i| d.kinds(i) != d.kinds(i - 1))
                .map(|i| Transition {
                    between: (grid[i - 1], grid[i]),
                    from: d.kinds(i - 1),
                    to: d.kinds(i),
                })
                .collect();
            (d.modes, t)
        })
        .collect();
    let claims = claims(&grid, &diagrams);
    let rigid_limit = match diagrams.iter().find(|d| d.modes == 1) {
        Some(one) => {
            let last = &one.columns[grid.len() - 1][0];
            let v = last.impact_velocities.first().copied().unwrap_or(f64::NAN);
            Some(rigid_limit(p, v, grid[grid.len() - 1])?)
        }
        None => None,
    };
    // k does not matter: mode 1 does not feel the stop in free flight
    let unit = forced(p, 1, 100.0).model()?.free_tip_amplitude();
    let mut data = Fig5Data {
        params: p.clone(),
        k_over_k1: grid,
        diagrams,
        transitions,
        claims,
        rigid_limit,
        free_amplitude: unit,
        branches: Vec::new(),
        bands: Vec::new(),
    };
    // one truncation per task: each set is traced in a fixed order
    data.branches = p
        .modes
        .par_iter()
        .map(|&n| branches::branch_set(p, &data, n))
        .collect::<Result<_, _>>()?;
    data.bands = rotation::bands(p, &data)?;
    Ok(data)
}


/// The scene.
pub struct Fig5;

impl Scene for Fig5 {
    const NAME: &'static str = "fig5";
    const PAPER: &'static str = "Fig 5, §5.3";
    const TITLE: &'static str = "Fig 5: bifurcations in k";
    const GIST: &'static str = "N-dependence from about k₂ ≈ 39.3k₁";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str =
        "bifurcation diagrams in k (impact section), N = 1, 2, 3, 10, random starts";
    const CLAIM: &'static str = "All truncations agree for $k \\lesssim k_1$; they depend on $N$ from about $k_2 \\approx 39.3k_1$; $N = 3$ captures the qualitative features.";
    const CHAPTER: &'static str = "fig5.md";
    const METHOD: &'static str = "brute-force bifurcation diagrams: at each of 200 log-spaced k and for 8 starts (rest and 7 seeded random states) the N-mode compliant model is simulated exactly for 1000 periods, then 50 are recorded; the impact velocities of settled orbits (stroboscopic residual < 1e-9) on the impact section d = d₀, ḋ > 0; the rigid limit of N = 1 (Newton's law, r = 1) by the rigid-impact model";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[("spread of the impact velocities at k = k₁", "velocity spread at smallest k"), ("first k where N = 10 and N = 1 differ", "first orbit difference N=10 vs N=1"), ("share of k where N = 3 and N = 10 agree", "N=3 vs N=10 orbit agreement"), ("N = 1 rigid-limit impact velocity", "N=1 rigid-limit impact velocity")];
    const SETTABLE: &'static [crate::results::settings::Setting] = &[crate::results::settings::ZETA1, crate::results::settings::OMEGA, crate::results::settings::SEED];
    type Params = Fig5Params;
    type Data = Fig5Data;

    fn params(resolution: Resolution) -> Fig5Params {
        match resolution {
            Resolution::Book => Fig5Params::book(),
            Resolution::Test => Fig5Params::test(),
        }
    }

    fn compute(p: &Fig5Params, progress: &dyn Progress) -> Result<Fig5Data, Error> {
        let task = progress.task("fig5 (N, k) points", (p.points * p.modes.len()) as u64);
        compute(p, &|| task.advance(1))
    }

    fn key_numbers(d: &Fig5Data) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        k.free_amplitude("", d.free_amplitude);
        for g in &d.diagrams {
            // the orbit sets along k, exactly (integers): the diagram's skeleton
            let sets: Vec<String> = (0..d.k_over_k1.len())
                .map(|i| {
                    g.kinds(i)
                        .iter()
                        .map(|k| k.to_string())
                        .collect::<Vec<_>>()
                        .join("+")
                })
                .collect();
            k.text(format!("N={} orbits along k", g.modes), sets.join(" "));
        }
        let c = &d.claims;
        let grid = &d.k_over_k1;
        k.text(
            "all (1,1) at smallest k",
            c.all_one_one_at_smallest_k.to_string(),
        );
        // the velocities come from orbits settled to 1e-9; their spread is known to that
        k.cited(
            "velocity spread at smallest k",
            c.velocity_spread_at_smallest_k,
            2,
            Uncertainty::new(1e-9, "velocities on orbits settled to a residual of 1e-9"),
            "",
        );
        // a change between two adjacent grid values (see `claims::grid_threshold`)
        let mut threshold = |name: &str, v: Option<f64>, first: bool, scale: f64, unit: &str| {
            let Some(x) = v else {
                return k.text(name, "never on the grid");
            };
            match claims::grid_threshold(grid, x, first, scale, unit) {
                Some(c) => k.push(name, c),
                None => k.text(name, format!("at the end of the grid, {}", x / scale)),
            }
        };
        threshold("first orbit difference N=10 vs N=1", c.first_orbit_difference, true, 1.0, "k₁");
        threshold("first velocity difference N=10 vs N=1", c.first_velocity_difference, true, 1.0, "k₁");
        threshold("N=3 from rest leaves (1,1) at", c.n3_leaves_one_one_at, true, 1.0, "k₁");
        threshold("N=3 from rest reaches (1,3) at", c.n3_one_three_from, true, 1.0, "k₁");
        let reachable = &c.paper_figure4_set_reachable_at;
        threshold("all four Fig 4 orbits are attractors from", reachable.first().copied(), true, 1.0, "k₁");
        threshold("all four Fig 4 orbits are attractors up to", reachable.last().copied(), false, 1.0, "k₁");
        // from where on N = 3 and N = 10 never reach the same orbit set again
        let by = |n: usize| d.diagrams.iter().find(|g| g.modes == n);
        if let (Some(three), Some(ten)) = (by(3), by(10)) {
            let last_agree = (0..grid.len()).rev().find(|&i| three.kinds(i) == ten.kinds(i));
            let from = last_agree.map_or(Some(grid[0]), |i| grid.get(i + 1).copied());
            threshold("N=3 and N=10 differ at every k from", from, true, 1.0, "k₁");
        }
        threshold("N=3 (1,3) onset over the paper's k = 100k1", c.n3_one_three_from, true, 100.0, "");
        let points = grid.len() as f64;
        let fraction = || {
            Uncertainty::new(1.0 / points, format!("resolution of a {points}-point k grid"))
        };
        k.cited("N=3 vs N=10 orbit agreement", c.n3_n10_agreement, 4, fraction(), "");
        k.cited("N=2 vs N=10 orbit agreement", c.n2_n10_agreement, 4, fraction(), "");
        k.integer(
            "k values matching all four Fig 4 orbits",
            c.paper_figure4_set_at.len() as i64,
        );
        k.integer(
            "k values where all four Fig 4 orbits are attractors",
            c.paper_figure4_set_reachable_at.len() as i64,
        );
        branches::key_numbers(&mut k, d);
        rotation::key_numbers(&mut k, d);
        if let Some(r) = &d.rigid_limit {
            k.cited(
                "N=1 rigid-limit impact velocity",
                r.impact_velocity,
                6,
                Uncertainty::new(
                    r.impact_velocity.abs() * r.residual.max(1e-12),
                    "distance to the rigid model's periodic orbit (its stroboscopic residual)",
                ),
                "ωA_free",
            );
            k.cited(
                "N=1 impact velocity at the largest k",
                r.compliant_at_largest_k,
                4,
                Uncertainty::new(1e-9 * r.compliant_at_largest_k.abs(), "velocity on an orbit settled to 1e-9"),
                "ωA_free",
            );
            // multipliers of an orbit converged to 1e-12 by shooting: the rigid ones agree
            // with the impact oscillator's closed form to 1e-9 (tests/rigid_orbits.rs)
            let basis = "eigenvalues of the exact monodromy of an orbit converged to 1e-12 (closed-form check 1e-9)";
            let radius = |m: &[[f64; 2]]| m.first().map_or(f64::NAN, |z| z[0].hypot(z[1]));
            for (key, mult) in [
                ("N=1 rigid-limit multipliers", &r.multipliers),
                ("N=1 multipliers at the largest k", &r.compliant_multipliers_at_largest_k),
            ] {
                let moduli: Vec<(f64, f64)> = mult.iter().map(|z| {
                    let m = z[0].hypot(z[1]);
                    (m, 1e-9 * m)
                }).collect();
                k.series(key, &moduli, 9, basis, "");
            }
            k.cited(
                "N=1 rigid-limit spectral radius",
                radius(&r.multipliers),
                9,
                Uncertainty::new(1e-9 * radius(&r.multipliers), basis),
                "",
            );
            k.cited(
                "N=1 spectral radius at the largest k",
                radius(&r.compliant_multipliers_at_largest_k),
                9,
                Uncertainty::new(1e-9 * radius(&r.compliant_multipliers_at_largest_k), basis),
                "",
            );
            k.cited(
                "N=1 damping bound e^(-c1 T/2)",
                r.damping_bound,
                9,
                Uncertainty::round_off(r.damping_bound, 1e-15, "closed form"),
                "",
            );
        }
        k
    }

    fn verdict(d: &Fig5Data) -> Verdict {
        let c = &d.claims;
        // claim 1 holds if every truncation is on the same (1,1) orbit at the smallest k,
        // with impact velocities within 2% (the diagram's visual resolution)
        let small_k = c.all_one_one_at_smallest_k && c.velocity_spread_at_smallest_k < 0.02;
        // claim 2: N-dependence sets in near k₂ ≈ 39.3 k₁, not an order of magnitude earlier
        let onset = c
            .first_orbit_difference
            .into_iter()
            .chain(c.first_velocity_difference)
            .fold(f64::INFINITY, f64::min);
        let from_k2 = onset > 39.3 / 3.0;
        // claim 3: N = 3 reaches the same orbit sets as N = 10 everywhere
        let n3 = c.n3_n10_agreement >= 1.0;
        let holds = [small_k, from_k2, n3];
        Verdict {
            outcome: match holds.iter().filter(|h| **h).count() {
                3 => Outcome::Reproduced,
                0 => Outcome::NotReproduced,
                _ => Outcome::Partly,
            },
            evidence: format!(
                "all (1,1) within {:.1}% at the smallest k; N-dependence from k = {} $k_1$; N = 3 and N = 10 reach the same orbits at {:.0}% of the k values",
                100.0 * c.velocity_spread_at_smallest_k,
                claims::threshold_text(&d.k_over_k1, onset.is_finite().then_some(onset), true),
                100.0 * c.n3_n10_agreement
            ),
        }
    }

    fn render(d: &Fig5Data) -> Result<Rendered, crate::results::render::RenderError> {
        let mut r = Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?;
        r.extra_tables
            .push(("transitions", render::transitions_table(d)));
        r.extra_tables.push(("bands", render::bands_table(d)));
        Ok(r)
    }
}
