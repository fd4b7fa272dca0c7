//! Scene `restitution`: §3–4 — the modal restitution laws against each other and the
//! compliant model's approach to the rigid-impact limit.
//!
//! - r_e of eq (19) against the exact one-mode return ratio e^{−απ/ω_d}: the error's
//!   observed order in ε (the first-order theory's remainder is O(ε²));
//! - the kinetic energy an impact law can create: max |−\[R\]v|²/|v|² over deterministic test
//!   velocities, for \[R\]_IR, \[R\]_N and \[R\]_C at r = 1 (N = 5);
//! - Nordmark: the compliant N = 1 model's (1,1) impact velocity against the rigid model's
//!   (Newton's law, r = 1) as k → ∞, at the Figure 4 damping and forcing, at
//!   ω = 1.5(β₁⁻)² (fast approach) and at the paper's ω = 2(β₁⁻)² (slow).

pub mod render;

use crate::model::asymptotics;
use crate::error::Error;
use crate::model::galerkin::first_modal_stiffness;
use crate::analysis::orbit::{self, OrbitKind};
use crate::model::problems::{self, Forced};
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::model::restitution::{collocation, equally_spaced_points, impulse_response, stiffness_limit};
use crate::engine::rigid::RigidImpact;
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::engine::sim::Simulator;
use crate::base::verification::fitted_slope_with_error;
use nalgebra::DVector;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct RestitutionParams {
    /// α of the one-mode return ratio.
    pub alpha: f64,
    /// ε ladder of the r_e error.
    pub eps: Vec<f64>,
    /// k/k₁ ladder of the Nordmark study.
    pub nordmark_k: Vec<f64>,
    /// The forcing frequencies ω/(β₁⁻)² of the Nordmark study.
    pub nordmark_omega: Vec<f64>,
    /// Periods discarded before reading an orbit.
    pub transient: u64,
    /// Periods recorded.
    pub window: u64,
}

impl RestitutionParams {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            alpha: 0.1,
            eps: (0..9).map(|i| 10f64.powf(-5.0 + 0.25 * i as f64)).collect(),
            nordmark_k: vec![1e4, 3e4, 1e5, 3e5, 1e6],
            nordmark_omega: vec![1.5, 2.0],
            transient: 1000,
            window: 40,
        }
    }
}

/// One forcing frequency of the Nordmark study.
#[derive(Debug, Clone, Serialize)]
pub struct Nordmark {
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// The rigid model's orbit and its impact velocity / (ωA_free).
    pub rigid_kind: OrbitKind,
    /// The rigid orbit's stroboscopic residual.
    pub rigid_residual: f64,
    /// Rigid impact velocity / (ωA_free).
    pub rigid_velocity: f64,
    /// Per k: the compliant orbit and impact velocity / (ωA_free).
    pub compliant: Vec<(OrbitKind, f64)>,
    /// Per k: the compliant orbit's stroboscopic residual.
    pub compliant_residual: Vec<f64>,
    /// Per k: |compliant − rigid| / (ωA_free).
    pub gap: Vec<f64>,
    /// The slope of log gap against log k, with its standard error.
    pub rate: (f64, f64),
    /// The velocity unit: A_free and ωA_free at this ω.
    pub free_amplitude: (f64, f64),
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct RestitutionData {
    /// The parameters used.
    pub params: RestitutionParams,
    /// |r_e − e^{−απ/ω_d}| per ε.
    pub re_error: Vec<f64>,
    /// Its observed order and standard error over ε ≤ 1e-3.
    pub re_order: (f64, f64),
    /// max |−\[R\]v|²/|v|² over the test velocities at r = 1, N = 5: IR, N, C.
    pub energy_ratio: [f64; 3],
    /// The Nordmark study per ω.
    pub nordmark: Vec<Nordmark>,
}

/// Deterministic test velocities (no RNG): smooth but non-special.
fn vectors(n: usize) -> Vec<DVector<f64>> {
    (0..12)
        .map(|k| {
            DVector::from_fn(n, |i, _| {
                ((i * 7 + k * 13) as f64 * 0.61).sin() + 0.3 * (k as f64 - 5.0) / (1.0 + i as f64)
            })
        })
        .collect()
}

fn nordmark(p: &RestitutionParams, omega: f64) -> Result<Nordmark, Error> {
    let case = |k_over_k1: f64| Forced {
        k_over_k1,
        omega_over_w1: omega,
        ..problems::figure4(1)
    };
    let model = case(1.0).model()?;
    let free_amplitude = model.free_tip_amplitude();
    let vamp = free_amplitude.1;
    let rigid = RigidImpact::new(Simulator::new(model)?, impulse_response(1, 1.0)?)?;
    let settled = orbit::settle_rigid(&rigid, &DVector::zeros(2), p.transient, p.window)?;
    let rigid_velocity = settled.impact_velocity / vamp;
    let mut compliant = Vec::new();
    let mut compliant_residual = Vec::new();
    for &k in &p.nordmark_k {
        let sim = Simulator::new(case(k).model()?)?;
        let o = orbit::settle(&sim, &DVector::zeros(2), p.transient, p.window, 0)?;
        let v = o
            .events
            .iter()
            .rev()
            .find(|e| e.entering)
            .map_or(f64::NAN, |e| e.tip_velocity)
            / vamp;
        compliant.push((o.kind, v));
        compliant_residual.push(o.residual);
    }
    let gap: Vec<f64> = compliant.iter().map(|(_, v)| (v - rigid_velocity).abs()).collect();
    let lx: Vec<f64> = p.nordmark_k.iter().map(|k| k.ln()).collect();
    let ly: Vec<f64> = gap.iter().map(|g| g.ln()).collect();
    Ok(Nordmark {
        omega_over_w1: omega,
        compliant_residual,
        rigid_kind: settled.kind,
        rigid_residual: settled.residual,
        rigid_velocity,
        compliant,
        gap,
        rate: fitted_slope_with_error(&lx, &ly),
        free_amplitude,
    })
}

/// Runs the scene.
///
/// # Errors
/// A law or model out of range (`Error::Parameter`), a flow that cannot be built, or a run
/// the compliant or the rigid-impact simulator refuses (`Error::Chatter`, ...).
pub fn compute(p: &RestitutionParams) -> Result<RestitutionData, Error> {
    use rayon::prelude::*;
    let k1 = first_modal_stiffness();
    let re_error: Vec<f64> = p
        .eps
        .iter()
        .map(|&e| {
            let k = e.powi(-2);
            (asymptotics::effective_restitution(p.alpha, asymptotics::kappa(k, 1, e), e)
                - asymptotics::exact_one_mode_restitution(p.alpha, k1, k))
            .abs()
        })
        .collect();
    let (lx, ly): (Vec<f64>, Vec<f64>) = p
        .eps
        .iter()
        .zip(&re_error)
        .filter(|(e, _)| **e <= 1e-3 * 1.001)
        .map(|(e, r)| (e.ln(), r.ln()))
        .unzip();
    let re_order = fitted_slope_with_error(&lx, &ly);
    let n = 5;
    let laws = [
        impulse_response(n, 1.0)?,
        stiffness_limit(n, 1.0)?,
        collocation(n, 1.0, &equally_spaced_points(n))?,
    ];
    let energy_ratio = laws.map(|law| {
        vectors(n)
            .iter()
            .map(|v| (-(&law * v)).norm_squared() / v.norm_squared())
            .fold(0.0, f64::max)
    });
    let nordmark = p
        .nordmark_omega
        .par_iter()
        .map(|&w| nordmark(p, w))
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(RestitutionData {
        params: p.clone(),
        re_error,
        re_order,
        energy_ratio,
        nordmark,
    })
}

/// The scene.
pub struct RestitutionLaws;

impl Scene for RestitutionLaws {
    const NAME: &'static str = "restitution";
    const PAPER: &'static str = "§3–4, eqs (11)-(29)";
    const TITLE: &'static str = "Restitution laws (§3–4)";
    const GIST: &'static str = "compliant → stiffness-limit law, k → ∞";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str =
        "modal restitution laws: r_e against the exact 1-DOF ratio, energy, the rigid limit (Nordmark)";
    const CLAIM: &'static str = "Several modal laws satisfy Newton's law at the tip yet differ; the compliant model tends to the stiffness-limit law $[R]_N$ as $k \\to \\infty$ with $r_e = 1 - \\alpha\\pi\\kappa^{-1/2}\\varepsilon$ (eq 19).";
    const CHAPTER: &'static str = "restitution.md";
    const METHOD: &'static str = "the laws of eqs (12), (14), (29) in closed form; r_e of eq (19) against the exact one-mode ratio; the compliant N = 1 model (exact simulation, 1000 periods from rest) against the rigid-impact model with Newton's law r = 1 at k = 1e4 … 1e6 k₁";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[("order of the error of $r_e$", "r_e error observed order"), ("rate of approach to the rigid limit, ω = 1.5(β₁⁻)²", "omega=1.5 convergence rate"), ("rigid-limit impact velocity, ω = 2(β₁⁻)²", "omega=2 rigid impact velocity")];
    type Params = RestitutionParams;
    type Data = RestitutionData;

    fn params(_: Resolution) -> RestitutionParams {
        RestitutionParams::book()
    }

    fn compute(p: &RestitutionParams, _: &dyn Progress) -> Result<RestitutionData, Error> {
        compute(p)
    }

    fn key_numbers(d: &RestitutionData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        let (o, e) = d.re_order;
        k.cited(
            "r_e error observed order",
            o,
            3,
            Uncertainty::new(e, "standard error of the slope over ε ∈ [1e-5, 1e-3]"),
            "",
        );
        let fit = |x: f64| Uncertainty::round_off(x, 1e-13, "products of a 5 × 5 law with O(1) vectors");
        for (name, r) in ["impulse-response", "stiffness-limit", "collocation"]
            .iter()
            .zip(d.energy_ratio)
        {
            k.cited(format!("{name} max energy ratio at r=1"), r, 6, fit(r), "");
        }
        for n in &d.nordmark {
            let key = format!("omega={}", n.omega_over_w1);
            k.free_amplitude(&format!("{key} "), n.free_amplitude);
            k.text(format!("{key} rigid orbit"), n.rigid_kind.to_string());
            // a velocity on an orbit is as good as the orbit is settled (its stroboscopic
            // residual), and no better than round-off
            let on_orbit = |v: f64, residual: f64| {
                Uncertainty::new(
                    v.abs() * residual.max(1e-12),
                    "distance to the periodic orbit (stroboscopic residual) and round-off",
                )
            };
            let rigid_u = on_orbit(n.rigid_velocity, n.rigid_residual);
            k.cited(format!("{key} rigid impact velocity"), n.rigid_velocity, 6, rigid_u.clone(), "ωA_free");
            for ((kk, (kind, v)), r) in d.params.nordmark_k.iter().zip(&n.compliant).zip(&n.compliant_residual) {
                k.text(format!("{key} k={kk:e} orbit"), kind.to_string());
                k.cited(format!("{key} k={kk:e} impact velocity"), *v, 6, on_orbit(*v, *r), "ωA_free");
            }
            for ((kk, g), ((_, v), r)) in d.params.nordmark_k.iter().zip(&n.gap).zip(n.compliant.iter().zip(&n.compliant_residual)) {
                let u = Uncertainty::new(on_orbit(*v, *r).value + rigid_u.value, "the two velocities' uncertainties, added");
                k.cited(format!("{key} k={kk:e} gap to rigid"), *g, 2, u, "ωA_free");
            }
            k.cited(
                format!("{key} convergence rate"),
                n.rate.0,
                2,
                Uncertainty::new(n.rate.1, "standard error of the slope of log gap against log k"),
                "",
            );
        }
        k
    }

    fn verdict(d: &RestitutionData) -> Verdict {
        let (order, _) = d.re_order;
        let collocation_creates = d.energy_ratio[2] > 1.0;
        let conserve = d.energy_ratio[0] <= 1.0 + 1e-12 && d.energy_ratio[1] <= 1.0 + 1e-12;
        let fast = d.nordmark.first();
        let converges = fast.is_some_and(|n| n.rate.0 < -0.3);
        Verdict {
            outcome: if (order - 2.0).abs() < 0.05 && conserve && converges {
                Outcome::Reproduced
            } else {
                Outcome::Partly
            },
            evidence: format!(
                "$r_e$ error of order {order:.2} in ε; $[R]_C$ {} kinetic energy (×{:.3} at r = 1), $[R]_{{IR}}$ and $[R]_N$ conserve it; the compliant N = 1 orbit approaches the rigid one like $k^{{{:.2}}}$ at ω = {}(β₁⁻)²",
                if collocation_creates { "can create" } else { "does not create" },
                d.energy_ratio[2],
                fast.map_or(f64::NAN, |n| n.rate.0),
                fast.map_or(f64::NAN, |n| n.omega_over_w1),
            ),
        }
    }

    fn render(d: &RestitutionData) -> Result<Rendered, crate::results::render::RenderError> {
        Rendered::drawn(|layout| render::plot(d, layout), render::table(d))
    }
}
