//! Scene `fig4`: Figure 4 and §5.3 — the periodic orbit of the N-mode bilinear model
//! (eq 34) for N = 1, 2, 3, 10 at k = 100k₁, α = 0, ζ₁ = 0.01 (material damping), d₀ = 0,
//! ω = 2(β₁⁻)², the forcing of eq (37), from rest, 1000 periods discarded. The paper
//! reports (1,1), (2,4), (1,3) and (1,1).
//!
//! Each orbit is also checked for robustness: a longer transient, a looser root
//! tolerance, the independent DP5 integrator, random initial conditions (coexisting
//! attractors), and the other reading of the damping ratio (errata E3).

use crate::galerkin::{self, Forcing, GalerkinModel, GalerkinParams};
use crate::orbit::{self, OrbitKind, SplitMix64};
use crate::reference::{self, Tolerances};
use crate::simulator::{Clock, Observe, Settings, Simulator};
use nalgebra::DVector;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize)]
pub struct Fig4Params {
    /// Truncations N with the paper's (m, n).
    pub cases: Vec<(usize, u64, u64)>,
    /// k/k₁.
    pub k_over_k1: f64,
    /// ζ₁.
    pub zeta1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// Periods discarded.
    pub transient: u64,
    /// Periods recorded.
    pub window: u64,
    /// Samples per period for the plots.
    pub dense_per_period: usize,
    /// A longer transient for the convergence check.
    pub long_transient: u64,
    /// A looser root tolerance for the convergence check.
    pub loose_root_tolerance: f64,
    /// rtol of the DP5 cross-check (None: skipped).
    pub reference_rtol: Option<f64>,
    /// Random initial conditions per N.
    pub random_starts: usize,
    /// Seed of the random initial conditions.
    pub seed: u64,
    /// ζ₁ of the other damping reading (Fig 4 caption taken literally: γ = 0.02(β₁⁻)²).
    pub literal_caption_zeta1: f64,
}

impl Fig4Params {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            cases: vec![(1, 1, 1), (2, 2, 4), (3, 1, 3), (10, 1, 1)],
            k_over_k1: 100.0,
            zeta1: 0.01,
            omega_over_w1: 2.0,
            transient: 1000,
            window: 40,
            dense_per_period: 400,
            long_transient: 4000,
            loose_root_tolerance: 1e-8,
            reference_rtol: Some(1e-11),
            random_starts: 16,
            seed: 2013,
            literal_caption_zeta1: 0.01 * galerkin::first_modal_stiffness(),
        }
    }

    /// A reduced version for the tests.
    pub fn test() -> Self {
        Self {
            long_transient: 1500,
            reference_rtol: Some(1e-10),
            random_starts: 3,
            ..Self::book()
        }
    }
}

/// The robustness checks of one orbit.
#[derive(Debug, Clone, Serialize)]
pub struct Evidence {
    /// The orbit after the long transient.
    pub long_transient: OrbitKind,
    /// The orbit with the loose root tolerance.
    pub loose_tolerance: OrbitKind,
    /// DP5: entries into contact in the last m periods of the same window, and the largest
    /// event-time difference to ours over the window (None: different event counts).
    pub reference: Option<(u64, Option<f64>)>,
    /// Orbits reached from random initial conditions, with counts.
    pub random_starts: Vec<(OrbitKind, usize)>,
    /// The orbit under the literal Fig 4 caption damping (ζ₁ ≈ 0.124).
    pub literal_caption: OrbitKind,
}

/// One panel.
#[derive(Debug, Clone, Serialize)]
pub struct Fig4Panel {
    /// N.
    pub modes: usize,
    /// Our orbit.
    pub kind: OrbitKind,
    /// The paper's.
    pub paper: OrbitKind,
    /// Relative periodicity residual.
    pub residual: f64,
    /// Contact intervals in the last orbit period, as (start, end) in units of T from the
    /// start of that period.
    pub contacts: Vec<(f64, f64)>,
    /// Tip velocities at the entries into contact in that period, divided by the
    /// unconstrained tip velocity amplitude at this ω.
    pub impact_velocities: Vec<f64>,
    /// Largest tip displacement over the period (certified, [`crate::simulator::TipMaximum`]),
    /// divided by the unconstrained tip amplitude.
    pub max_tip: f64,
    /// The shallowest interior local minimum of the penetration d − d₀ during contact (a
    /// "dwell" in which the tip nearly leaves the stop), normalised; None if there is none.
    /// A dwell that dipped below zero would split one contact into several.
    pub dwell_depth: Option<f64>,
    /// (t/T from the period start, tip displacement, tip velocity, in contact), normalised
    /// like the fields above, over the last orbit period (m periods; 1 if not periodic).
    pub series: Vec<(f64, f64, f64, bool)>,
    /// The robustness checks.
    pub evidence: Evidence,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fig4Data {
    /// The parameters used.
    pub params: Fig4Params,
    /// Unconstrained tip amplitude and velocity amplitude at ω (the plot units).
    pub free_amplitude: (f64, f64),
    /// One per N.
    pub panels: Vec<Fig4Panel>,
}

/// The model of Figs 4–5: material damping ζ₁, d₀ = 0, eq (37) forcing at ω.
pub fn model(modes: usize, k_over_k1: f64, zeta1: f64, omega_over_w1: f64) -> GalerkinModel {
    GalerkinModel::new(
        GalerkinParams::new(modes, k_over_k1 * galerkin::first_modal_stiffness())
            .with_zeta1(zeta1)
            .with_forcing(Forcing::paper(omega_over_w1 * galerkin::first_frequency())),
    )
    .expect("valid Figure 4/5 parameters")
}

/// Unconstrained tip amplitude and tip velocity amplitude of the forced response at ω.
pub fn free_amplitude(m: &GalerkinModel) -> (f64, f64) {
    let omega = m.params.forcing.as_ref().map_or(0.0, |f| f.omega);
    let amp: f64 = (0..m.modes())
        .map(|j| {
            let re = m.modal_stiffness[j] - omega * omega;
            let im = m.damping[j] * omega;
            m.tip[j] * m.forcing_amplitude[j] / (re * re + im * im).sqrt()
        })
        .sum::<f64>()
        .abs();
    (amp, amp * omega)
}

/// Orbits from random initial conditions, counted by kind.
pub fn random_orbits(
    sim: &Simulator,
    starts: usize,
    seed: u64,
    transient: u64,
    window: u64,
) -> Vec<(OrbitKind, usize)> {
    let n = sim.model.modes();
    let (amp, _) = free_amplitude(&sim.model);
    let omega = sim.free.omega;
    let mut counts: std::collections::BTreeMap<OrbitKind, usize> = Default::default();
    for i in 0..starts {
        let mut rng = SplitMix64::for_point(seed, n as u64, 0, i as u64);
        let x0 = orbit::random_state(&mut rng, n, 4.0 * amp, omega);
        let o = orbit::settle(sim, &x0, transient, window, 0);
        *counts.entry(o.kind).or_default() += 1;
    }
    counts.into_iter().collect()
}

fn panel(
    p: &Fig4Params,
    modes: usize,
    paper: OrbitKind,
) -> Result<Fig4Panel, crate::flow::FlowError> {
    let m = model(modes, p.k_over_k1, p.zeta1, p.omega_over_w1);
    let (amp, vamp) = free_amplitude(&m);
    let sim = Simulator::new(m.clone())?;
    let period = sim.period();
    let rest = DVector::zeros(2 * modes);
    let o = orbit::settle(&sim, &rest, p.transient, p.window, p.dense_per_period);
    let end = o.window_start + p.window as i64;
    let span = match o.kind {
        OrbitKind::Periodic { m, .. } => m as i64,
        OrbitKind::NotPeriodic => 1,
    };
    let t0 = (end - span) as f64 * period;
    let in_last = |t: f64| t >= t0 - 1e-12 * period;
    let series: Vec<(f64, f64, f64, bool)> = o
        .dense
        .iter()
        .filter(|s| in_last(s.0))
        .map(|&(t, d, v, c)| ((t - t0) / period, d / amp, v / vamp, c))
        .collect();
    let window_events: Vec<_> = o
        .events
        .iter()
        .filter(|e| in_last(e.time) && !e.grazing)
        .collect();
    let mut contacts = Vec::new();
    let mut open: Option<f64> = None;
    for e in &window_events {
        let t = (e.time - t0) / period;
        if e.entering {
            open = Some(t);
        } else {
            contacts.push((open.take().unwrap_or(0.0), t));
        }
    }
    if let Some(start) = open {
        contacts.push((start, span as f64));
    }
    let impact_velocities = window_events
        .iter()
        .filter(|e| e.entering)
        .map(|e| e.tip_velocity / vamp)
        .collect();
    // certified maximum over one more orbit period (the orbit repeats to 1e-9)
    let (_, again) = sim.run_from(
        &o.state,
        Clock {
            period,
            cycles: end,
            offset: 0.0,
        },
        span as u64,
        Observe {
            max_tip: true,
            ..Default::default()
        },
    );
    let max_tip = again
        .max_tip
        .expect("a run of at least one period has a maximum")
        .value
        / amp;
    let dwell_depth = series
        .windows(3)
        .filter(|w| w.iter().all(|s| s.3) && w[1].1 < w[0].1 && w[1].1 <= w[2].1)
        .map(|w| w[1].1)
        .reduce(f64::min);

    let long = orbit::settle(&sim, &rest, p.long_transient, p.window, 0).kind;
    let mut loose_sim = sim.clone();
    loose_sim.settings = Settings {
        root_tolerance: p.loose_root_tolerance,
    };
    let loose = orbit::settle(&loose_sim, &rest, p.transient, p.window, 0).kind;
    let reference = p.reference_rtol.map(|rtol| {
        let t_end = end as f64 * period;
        let r = reference::integrate(
            &m,
            &rest,
            t_end,
            Tolerances {
                rtol,
                atol: rtol * 1e-3,
            },
        );
        let entries = r
            .events
            .iter()
            .filter(|e| e.entering && e.time >= t0 - 1e-9 * period)
            .count() as u64;
        let ours: Vec<_> = o.events.iter().filter(|e| !e.grazing).collect();
        let theirs: Vec<_> = r
            .events
            .iter()
            .filter(|e| e.time >= o.window_start as f64 * period)
            .collect();
        let diff = (ours.len() == theirs.len()).then(|| {
            ours.iter()
                .zip(&theirs)
                .map(|(a, b)| (a.time - b.time).abs())
                .fold(0.0, f64::max)
        });
        (entries, diff)
    });
    let random_starts = random_orbits(&sim, p.random_starts, p.seed, p.transient, p.window);
    let literal = Simulator::new(model(
        modes,
        p.k_over_k1,
        p.literal_caption_zeta1,
        p.omega_over_w1,
    ))?;
    let literal_caption = orbit::settle(&literal, &rest, p.transient, p.window, 0).kind;
    Ok(Fig4Panel {
        modes,
        kind: o.kind,
        paper,
        residual: o.residual,
        contacts,
        impact_velocities,
        max_tip,
        dwell_depth,
        series,
        evidence: Evidence {
            long_transient: long,
            loose_tolerance: loose,
            reference,
            random_starts,
            literal_caption,
        },
    })
}

/// Runs the scene (one task per N, in parallel).
pub fn compute(p: &Fig4Params) -> Result<Fig4Data, crate::flow::FlowError> {
    use rayon::prelude::*;
    let panels = p
        .cases
        .par_iter()
        .map(|&(n, m, k)| panel(p, n, OrbitKind::Periodic { m, n: k }))
        .collect::<Result<Vec<_>, _>>()?;
    let first = model(1, p.k_over_k1, p.zeta1, p.omega_over_w1);
    Ok(Fig4Data {
        params: p.clone(),
        free_amplitude: free_amplitude(&first),
        panels,
    })
}
