//! Scene `fig3-abc`: Figure 3(a)–(c) and §4.1–4.3 — the compliant N-mode model through one
//! contact, against the impact laws of the rigid limit.
//!
//! F = 0, α = 0.1 (viscous damping), d₀ = 0, k = ε⁻², from η = 0 with η̇ = ε⁻¹e₁ (entering
//! contact), simulated exactly until the tip leaves the stop. The return velocities are
//! compared with:
//! - N = 1: (v⁻/v⁺)² against r_e² (eq 19, κ = 1) and the exact e^{−2απ/ω_d};
//! - N ≥ 2: −η̇⁻/(ε⁻¹) against the first column of \[R\]_N (eq 29) with r_e from κ = kNε² = N.
//!   For N = 2 the paper plots modes 1 and 2: R₁₁ = (1 − r_e)/2 → 0 ("mode 1's CoR tends to
//!   zero") and R₂₁ = (3r_e − 1)/2.

use crate::asymptotics;
use crate::flow::FlowError;
use crate::galerkin::{self, GalerkinModel, GalerkinParams};
use crate::restitution::stiffness_limit;
use crate::scenes::spectrum::fitted_slope;
use crate::simulator::{Observe, Simulator};
use nalgebra::DVector;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize)]
pub struct Fig3abcParams {
    /// Truncations N (the paper: 1 and 2; 3 and 10 extend it).
    pub modes: Vec<usize>,
    /// ε values (log-spaced from 1e-4 to 1).
    pub eps: Vec<f64>,
    /// α.
    pub alpha: f64,
    /// ε range used to fit the observed order of the gap.
    pub fit_range: (f64, f64),
}

impl Default for Fig3abcParams {
    fn default() -> Self {
        Self {
            modes: vec![1, 2, 3, 10],
            eps: (0..=16)
                .map(|i| 10f64.powf(-4.0 + 0.25 * i as f64))
                .collect(),
            alpha: 0.1,
            fit_range: (1e-4, 1e-2),
        }
    }
}

/// One truncation across ε.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// N.
    pub modes: usize,
    /// κ = kNε² = N.
    pub kappa: f64,
    /// Per ε: −η̇⁻/ε⁻¹ (the post-contact modal velocities, sign flipped, per unit v⁺).
    pub simulated: Vec<Vec<f64>>,
    /// Per ε: the first column of \[R\]_N(r_e(ε)).
    pub predicted: Vec<Vec<f64>>,
    /// Per ε: max_j |simulated_j − predicted_j|.
    pub gap: Vec<f64>,
    /// Per ε: the contact duration divided by the prediction πκ^{−1/2}ε (eq 18).
    pub passage_ratio: Vec<f64>,
    /// Least-squares slope of log gap against log ε over the fit range.
    pub observed_order: f64,
    /// N = 1 only: (v⁻/v⁺)² from the simulation, r_e², and the exact ratio squared.
    pub one_mode: Option<OneMode>,
}

/// The N = 1 comparison of Figure 3(a).
#[derive(Debug, Clone, Serialize)]
pub struct OneMode {
    /// (v⁻/v⁺)² simulated.
    pub simulated: Vec<f64>,
    /// r_e² (eq 19).
    pub asymptotic: Vec<f64>,
    /// e^{−2απ/ω_d}, exact.
    pub exact: Vec<f64>,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fig3abcData {
    /// The parameters used.
    pub params: Fig3abcParams,
    /// One series per N.
    pub series: Vec<Series>,
}

/// One contact: returns (post-contact modal velocities, contact duration).
fn one_contact(n: usize, eps: f64, alpha: f64) -> Result<(DVector<f64>, f64), FlowError> {
    let k = eps.powi(-2);
    let m = GalerkinModel::new(GalerkinParams::new(n, k).with_viscous_damping(alpha))
        .expect("valid parameters");
    let sim = Simulator::new(m)?;
    let mut x0 = DVector::zeros(2 * n);
    x0[n] = 1.0 / eps;
    // unforced: one bookkeeping "period" is one time unit, far longer than the contact
    let observe = Observe {
        events: true,
        event_states: true,
        ..Default::default()
    };
    let (_, trace) = sim.run(&x0, 1, observe);
    let exit = trace
        .events
        .first()
        .expect("the tip leaves the stop within one time unit");
    let state = exit.state.as_ref().expect("event states observed");
    Ok((
        DVector::from_iterator(n, state[n..].iter().cloned()),
        exit.time,
    ))
}

/// Runs the scene.
pub fn compute(p: &Fig3abcParams) -> Result<Fig3abcData, FlowError> {
    use rayon::prelude::*;
    let k1 = galerkin::first_modal_stiffness();
    let series = p
        .modes
        .par_iter()
        .map(|&n| {
            let kappa = n as f64;
            let mut s = Series {
                modes: n,
                kappa,
                simulated: vec![],
                predicted: vec![],
                gap: vec![],
                passage_ratio: vec![],
                observed_order: f64::NAN,
                one_mode: (n == 1).then(|| OneMode {
                    simulated: vec![],
                    asymptotic: vec![],
                    exact: vec![],
                }),
            };
            for &eps in &p.eps {
                let (post, duration) = one_contact(n, eps, p.alpha)?;
                let sim: Vec<f64> = post.iter().map(|v| -v * eps).collect();
                let r_e = asymptotics::effective_restitution(p.alpha, kappa, eps);
                let pred: Vec<f64> = stiffness_limit(n, r_e.clamp(0.0, 1.0))
                    .expect("r_e in [0, 1]")
                    .column(0)
                    .iter()
                    .cloned()
                    .collect();
                s.gap.push(
                    sim.iter()
                        .zip(&pred)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max),
                );
                s.passage_ratio
                    .push(duration / (asymptotics::passage_time_scaled(kappa) * eps));
                if let Some(one) = s.one_mode.as_mut() {
                    one.simulated.push(sim[0] * sim[0]);
                    one.asymptotic.push(r_e * r_e);
                    let exact = asymptotics::exact_one_mode_restitution(p.alpha, k1, eps.powi(-2));
                    one.exact.push(exact * exact);
                }
                s.simulated.push(sim);
                s.predicted.push(pred);
            }
            let (lo, hi) = p.fit_range;
            let (lx, ly): (Vec<f64>, Vec<f64>) = p
                .eps
                .iter()
                .zip(&s.gap)
                .filter(|(e, _)| **e >= lo * 0.999 && **e <= hi * 1.001)
                .map(|(e, g)| (e.ln(), g.ln()))
                .unzip();
            s.observed_order = fitted_slope(&lx, &ly);
            Ok(s)
        })
        .collect::<Result<Vec<_>, FlowError>>()?;
    Ok(Fig3abcData {
        params: p.clone(),
        series,
    })
}
