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

pub mod render;

use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::model::asymptotics;
use crate::error::Error;
use crate::model::galerkin;
use crate::model::restitution::stiffness_limit;
use crate::model::problems;
use crate::engine::sim::{Events, Simulator};
use crate::base::verification::fitted_slope_with_error;
use nalgebra::DVector;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
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
            // a log grid, refined where k = ε⁻² crosses k₂ (ε ≈ 0.045): there the stop stops
            // being the fastest mode of the two-mode contact and the gap jumps
            eps: {
                let k2 = crate::model::continuum::modal_stiffness(2).unwrap_or(485.0);
                let mut e: Vec<f64> = (0..=16)
                    .map(|i| 10f64.powf(-4.0 + 0.25 * i as f64))
                    .chain([0.035, 0.04, k2.powf(-0.5), 0.05, 0.06])
                    .collect();
                e.sort_by(f64::total_cmp);
                e
            },
            alpha: 0.1,
            // the asymptotic range of §4.3: for ε ≤ 1e-3 the stop (k = ε⁻² ≥ 1e6) is
            // stiffer than every retained mode (k₁₀ ≈ 7.9e5) and the ε³ term of the N = 1
            // expansion is below 4% of the ε² remainder (απk₁ε/2 vs α²π²/2)
            fit_range: (1e-4, 1e-3),
        }
    }
}

/// One truncation across ε.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// N, the number of modes.
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
    /// Its standard error.
    pub observed_order_error: f64,
    /// The slope over the wider range ε ∈ [1e-4, 1e-2] (pre-asymptotic for large N).
    pub observed_order_wide: f64,
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
fn one_contact(n: usize, eps: f64, alpha: f64) -> Result<(DVector<f64>, f64), Error> {
    let (model, x0) = problems::one_contact(n, eps, alpha)?;
    let sim = Simulator::new(model)?;
    // unforced: one bookkeeping "period" is one time unit, far longer than the contact
    let mut events = Events::with_states();
    sim.run(&x0, 1, &mut events)?;
    let exit = events.events.first().ok_or_else(|| {
        Error::Unsupported(format!(
            "N = {n}, ε = {eps:e}: the tip did not leave the stop within one time unit"
        ))
    })?;
    let state = exit.state.clone().unwrap_or_default();
    Ok((
        DVector::from_iterator(n, state[n..].iter().cloned()),
        exit.time,
    ))
}

/// Runs the scene.
///
/// # Errors
/// A one-contact problem out of range (ε, N or α: `Error::Parameter`), a flow that cannot be
/// built, a run the simulator refuses, or `Error::Unsupported` when the tip does not leave
/// the stop within one time unit.
pub fn compute(p: &Fig3abcParams) -> Result<Fig3abcData, Error> {
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
                observed_order_error: f64::NAN,
                observed_order_wide: f64::NAN,
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
                let pred: Vec<f64> = stiffness_limit(n, r_e.clamp(0.0, 1.0))?
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
            (s.observed_order, s.observed_order_error) = fitted_slope_with_error(&lx, &ly);
            let (wx, wy): (Vec<f64>, Vec<f64>) = p
                .eps
                .iter()
                .zip(&s.gap)
                .filter(|(e, _)| **e >= 1e-4 * 0.999 && **e <= 1e-2 * 1.001)
                .map(|(e, g)| (e.ln(), g.ln()))
                .unzip();
            s.observed_order_wide = fitted_slope_with_error(&wx, &wy).0;
            Ok(s)
        })
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(Fig3abcData {
        params: p.clone(),
        series,
    })
}

/// The scene.
pub struct Fig3abc;

impl Scene for Fig3abc {
    const NAME: &'static str = "fig3-abc";
    const PAPER: &'static str = "Fig 3(a)-(c), §4.1-4.3";
    const TITLE: &'static str = "Fig 3(a)–(c): k → ∞";
    const GIST: &'static str = "return velocities → r_e and [R]₂";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str = "one contact of the compliant model, k = eps^-2, vs r_e (eq 19) and [R]_N (eq 29), N = 1, 2, 3, 10";
    const CLAIM: &'static str = "Simulated return velocities approach $r_e$ ($N = 1$) and $[R]_2$ ($N = 2$) as $k \\to \\infty$; mode 1's coefficient of restitution tends to zero.";
    const CHAPTER: &'static str = "fig3abc.md";
    const METHOD: &'static str = "one contact of the N-mode compliant model at k = ε⁻², α = 0.1, from η = 0, η̇ = ε⁻¹e₁, simulated exactly (piecewise-linear flow, certified exit time); compared with r_e of eq (19) and the first column of [R]_N of eq (29)";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[("order of the gap to $[R]_N$, N = 1", "N=1 observed_order"), ("N = 2", "N=2 observed_order"), ("mode 1 return coefficient at ε = 10⁻⁴, N = 2", "N=2 eps=1.000e-4 mode1 ratio")];
    type Params = Fig3abcParams;
    type Data = Fig3abcData;

    fn params(_: Resolution) -> Fig3abcParams {
        Fig3abcParams::default()
    }

    fn compute(p: &Fig3abcParams, _: &dyn Progress) -> Result<Fig3abcData, Error> {
        compute(p)
    }

    fn key_numbers(d: &Fig3abcData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        // one contact simulated exactly: for N = 1 the ratio equals the closed form to
        // 1e-12 (tested), the bound used for every simulated ratio and for the gaps
        let exact = || Uncertainty::new(1e-12, "exact simulation of one contact (N = 1 equals its closed form to 1e-12)");
        for s in &d.series {
            let key = format!("N={}", s.modes);
            k.integer(format!("{key} kappa"), s.kappa as i64);
            k.cited(
                format!("{key} observed_order"),
                s.observed_order,
                3,
                Uncertainty::new(
                    s.observed_order_error,
                    "standard error of the least-squares slope over ε ∈ [1e-4, 1e-3]",
                ),
                "",
            );
            for (i, e) in d.params.eps.iter().enumerate() {
                for (j, v) in s.simulated[i].iter().take(2).enumerate() {
                    k.cited(format!("{key} eps={e:.3e} mode{} ratio", j + 1), *v, 8, exact(), "");
                }
                k.cited(format!("{key} eps={e:.3e} gap"), s.gap[i], 3, exact(), "");
            }
            k.cited(
                format!("{key} observed_order over [1e-4, 1e-2]"),
                s.observed_order_wide,
                3,
                Uncertainty::new(0.01, "a pre-asymptotic slope: stated to two figures"),
                "",
            );
            k.cited(
                format!("{key} passage time relative error at eps=1e-4"),
                (s.passage_ratio[0] - 1.0).abs(),
                2,
                exact(),
                "",
            );
            if let Some(one) = &s.one_mode {
                let worst = one
                    .simulated
                    .iter()
                    .zip(&one.exact)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                k.text(
                    format!("{key} deviation from the exact one-mode ratio"),
                    if worst < 1e-12 { "below 1e-12".to_string() } else { format!("{worst:.1e}") },
                );
            }
            if s.modes == 2 {
                k.cited(
                    format!("{key} eps=1.000e-4 mode1 predicted"),
                    s.predicted[0][0],
                    3,
                    Uncertainty::round_off(s.predicted[0][0], 1e-12, "closed form"),
                    "",
                );
            }
        }
        let k2 = crate::model::continuum::modal_stiffness(2).unwrap_or(f64::NAN);
        k.cited(
            "eps where k = k2",
            k2.powf(-0.5),
            4,
            Uncertainty::round_off(k2.powf(-0.5), 1e-15, "k₂ from the root of eq (3)"),
            "",
        );
        k
    }

    fn verdict(d: &Fig3abcData) -> Verdict {
        let orders: Vec<String> = d
            .series
            .iter()
            .map(|s| format!("{:.2}", s.observed_order))
            .collect();
        // the gap must close (a positive order) and mode 1's CoR for N = 2 must vanish
        // with ε: below 1e-4 at the smallest ε = 1e-4 (first-order theory: (1 − r_e)/2 ~ ε)
        let closes = d.series.iter().all(|s| s.observed_order > 1.0);
        let mode1 = d
            .series
            .iter()
            .find(|s| s.modes == 2)
            .map(|s| s.simulated[0][0].abs());
        Verdict {
            outcome: if closes && mode1.is_some_and(|v| v < 1e-4) {
                Outcome::Reproduced
            } else {
                Outcome::Partly
            },
            evidence: format!(
                "the gap to $[R]_N$ closes like $\\varepsilon^p$, p = {} for N = {}; for N = 2 the first mode's return coefficient is {} at ε = 1e-4",
                orders.join(", "),
                d.series
                    .iter()
                    .map(|s| s.modes.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                mode1.map_or("—".into(), |v| format!("{v:.1e}"))
            ),
        }
    }

    fn render(d: &Fig3abcData) -> Result<Rendered, crate::results::render::RenderError> {
        let mut r = Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?;
        r.extra_tables.push(("ratios", render::ratios_table(d)));
        Ok(r)
    }
}
