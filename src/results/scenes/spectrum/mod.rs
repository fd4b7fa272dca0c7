//! Scene `spectrum`: the continuum eigenvalues of §2.1 (eqs 3–4).
//!
//! Computes β_i^- (free) and β_i^∞ (clamped-pinned) against the golden mpmath roots, the
//! ratio k₂/k₁ quoted in §5.3 (≈ 39.3), the frequency curves (β_i^+(k))² across k, and the
//! order and coefficient of the remainder of the small-k law (4).

pub mod render;

use crate::base::report::KeyNumbers;
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::model::continuum;
use crate::error::ParameterError;
use crate::base::golden::GoldenRoots;
use crate::base::report::Uncertainty;
use crate::base::verification::fitted_slope_with_error;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct SpectrumParams {
    /// Modes drawn in the frequency curves.
    pub curve_modes: usize,
    /// k/k₁ range of the curves (log-spaced), and points per decade.
    pub k_over_k1_range: (f64, f64),
    /// Points per decade.
    pub points_per_decade: usize,
    /// k/k₁ ladder over which the small-k remainder's order is fitted.
    pub small_k_ladder: Vec<f64>,
}

impl Default for SpectrumParams {
    fn default() -> Self {
        Self {
            curve_modes: 5,
            k_over_k1_range: (1e-3, 1e9),
            points_per_decade: 10,
            small_k_ladder: (0..7).map(|e| 10f64.powf(-4.0 + 0.5 * e as f64)).collect(),
        }
    }
}

/// One golden comparison.
#[derive(Debug, Clone, Serialize)]
pub struct RootCheck {
    /// Mode index i.
    pub i: usize,
    /// Our β.
    pub ours: f64,
    /// The golden β (mpmath, 25 digits).
    pub golden: f64,
    /// |ours − golden| / golden.
    pub rel_diff: f64,
}

/// The small-k law's remainder R(k) = (β_1^+)⁴ − (β_1^-)⁴ − k for mode `i`.
#[derive(Debug, Clone, Serialize)]
pub struct SmallKLaw {
    /// Mode index.
    pub i: usize,
    /// The k ladder (absolute k).
    pub k: Vec<f64>,
    /// R(k).
    pub remainder: Vec<f64>,
    /// Least-squares slope of log|R| against log k (eq 4 says 2).
    pub fitted_order: f64,
    /// Its standard error.
    pub fitted_order_error: f64,
    /// R/k² at the second-smallest k (the coefficient's first-order drift along the ladder).
    pub next_coefficient: f64,
    /// R/k² at the smallest k.
    pub fitted_coefficient: f64,
    /// Second-order perturbation theory: R/k² → −Σ_{j≠i} 1/(k_j − k_i) (j ≤ 1000).
    pub predicted_coefficient: f64,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct SpectrumData {
    /// The parameters used.
    pub params: SpectrumParams,
    /// Where the golden values come from.
    pub golden_source: String,
    /// β_i^- against golden.
    pub free: Vec<RootCheck>,
    /// β_i^∞ against golden.
    pub clamped_pinned: Vec<RootCheck>,
    /// β_i^+(k) against golden at the stored k/k₁ (keys "k/k1", i).
    pub finite_k: Vec<(f64, RootCheck)>,
    /// k₁ = (β₁⁻)⁴.
    pub k1: f64,
    /// k₂/k₁.
    pub k2_over_k1: f64,
    /// k/k₁ grid of the curves.
    pub k_over_k1: Vec<f64>,
    /// (β_i^+(k))² / (β_1^-)² for i = 1..curve_modes, per grid point.
    pub frequency: Vec<Vec<f64>>,
    /// The small-k law (4) prediction of the same, √((β_i^-)⁴ + k)/(β_1^-)².
    pub frequency_small_k: Vec<Vec<f64>>,
    /// (β_i^∞)²/(β_1^-)²: the clamped-pinned asymptotes.
    pub frequency_pinned: Vec<f64>,
    /// The small-k law remainder, mode 1.
    pub small_k: SmallKLaw,
}

fn check(i: usize, ours: f64, golden: f64) -> RootCheck {
    RootCheck {
        i,
        ours,
        golden,
        rel_diff: ((ours - golden) / golden).abs(),
    }
}

/// The remainder of eq (4) for mode i over a ladder of k/k₁.
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`continuum::MAX_MODE_INDEX`] or a ladder entry that
/// gives a negative or NaN stiffness.
pub fn small_k_law(i: usize, ladder: &[f64]) -> Result<SmallKLaw, ParameterError> {
    let k1 = continuum::modal_stiffness(1)?;
    let ki = continuum::modal_stiffness(i)?;
    let k: Vec<f64> = ladder.iter().map(|r| r * k1).collect();
    let remainder = k
        .iter()
        .map(|&k| Ok(continuum::root(i, k)?.powi(4) - ki - k))
        .collect::<Result<Vec<_>, ParameterError>>()?;
    let lx: Vec<f64> = k.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = remainder.iter().map(|v| v.abs().ln()).collect();
    let mut predicted = 0.0;
    for j in 1..=continuum::MAX_MODE_INDEX {
        if j != i {
            predicted -= 1.0 / (continuum::modal_stiffness(j)? - ki);
        }
    }
    let (fitted_order, fitted_order_error) = fitted_slope_with_error(&lx, &ly);
    Ok(SmallKLaw {
        i,
        fitted_order,
        fitted_order_error,
        next_coefficient: remainder[1] / (k[1] * k[1]),
        fitted_coefficient: remainder[0] / (k[0] * k[0]),
        predicted_coefficient: predicted,
        k,
        remainder,
    })
}

/// Runs the scene.
///
/// # Errors
/// [`ParameterError`] for `curve_modes` above [`continuum::MAX_MODE_INDEX`], a k/k₁ range or
/// small-k ladder that gives a negative or NaN stiffness.
///
/// # Panics
/// If the embedded golden file does not parse: never for the committed file, which the tests
/// load.
pub fn compute(params: &SpectrumParams) -> Result<SpectrumData, ParameterError> {
    let golden = GoldenRoots::load();
    let free = GoldenRoots::table(&golden.free)
        .into_iter()
        .map(|(i, g)| Ok(check(i, continuum::free_root(i)?, g)))
        .collect::<Result<Vec<_>, ParameterError>>()?;
    let clamped_pinned = GoldenRoots::table(&golden.clamped_pinned)
        .into_iter()
        .map(|(i, g)| Ok(check(i, continuum::clamped_pinned_root(i)?, g)))
        .collect::<Result<Vec<_>, ParameterError>>()?;
    let k1 = continuum::modal_stiffness(1)?;
    let mut finite_k = Vec::new();
    for (ratio, table) in &golden.finite_k {
        let r: f64 = ratio.parse().expect("k/k1 key");
        for (i, g) in GoldenRoots::table(table) {
            finite_k.push((r, check(i, continuum::root(i, r * k1)?, g)));
        }
    }
    finite_k.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.i.cmp(&b.1.i)));

    let (lo, hi) = params.k_over_k1_range;
    let decades = (hi / lo).log10();
    let points = (decades * params.points_per_decade as f64).round() as usize + 1;
    let k_over_k1: Vec<f64> = (0..points)
        .map(|p| lo * 10f64.powf(decades * p as f64 / (points - 1) as f64))
        .collect();
    let w1 = continuum::free_root(1)?.powi(2);
    let mut frequency = Vec::new();
    let mut frequency_small_k = Vec::new();
    let mut frequency_pinned = Vec::new();
    for i in 1..=params.curve_modes {
        let ki = continuum::modal_stiffness(i)?;
        frequency.push(
            k_over_k1
                .iter()
                .map(|r| Ok(continuum::root(i, r * k1)?.powi(2) / w1))
                .collect::<Result<Vec<_>, ParameterError>>()?,
        );
        frequency_small_k.push(
            k_over_k1
                .iter()
                .map(|r| (ki + r * k1).sqrt() / w1)
                .collect(),
        );
        frequency_pinned.push(continuum::clamped_pinned_root(i)?.powi(2) / w1);
    }
    Ok(SpectrumData {
        params: params.clone(),
        golden_source: golden.source,
        free,
        clamped_pinned,
        finite_k,
        k1,
        k2_over_k1: continuum::modal_stiffness(2)? / k1,
        k_over_k1,
        frequency,
        frequency_small_k,
        frequency_pinned,
        small_k: small_k_law(1, &params.small_k_ladder)?,
    })
}

/// The scene.
pub struct Spectrum;

impl Scene for Spectrum {
    const NAME: &'static str = "spectrum";
    const PAPER: &'static str = "§2.1, eqs (3)-(4)";
    const TITLE: &'static str = "Spectrum, stop held on";
    const GIST: &'static str = "cantilever → clamped–pinned; k₂ ≈ 39.3k₁";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str =
        "continuum roots beta_i (free, clamped-pinned, finite k) vs golden; k2/k1; small-k law";
    const CLAIM: &'static str = "The roots of eq (3) move from the cantilever to the clamped-pinned values; $(\\beta_i^+)^4 = (\\beta_i^-)^4 + k + O(k^2)$; $k_2 \\approx 39.3k_1$.";
    const CHAPTER: &'static str = "spectrum.md";
    const METHOD: &'static str = "roots of eq (3), scaled against overflow and bracketed between the free and clamped-pinned roots, by Brent's method to 1e-15 relative; checked against 50-digit mpmath values and Blevins' table; the remainder of eq (4) by a log–log fit and second-order perturbation theory";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[("k₂/k₁", "k2_over_k1"), ("order of the remainder of eq (4)", "small_k_fitted_order")];
    type Params = SpectrumParams;
    type Data = SpectrumData;

    fn params(_: Resolution) -> SpectrumParams {
        SpectrumParams::default()
    }

    fn compute(p: &SpectrumParams, _: &dyn Progress) -> Result<SpectrumData, crate::error::Error> {
        Ok(compute(p)?)
    }

    fn key_numbers(d: &SpectrumData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        // the root solver's tolerance (1e-15 relative plus its 4ε guard), which the
        // agreement with the 50-digit mpmath values confirms (the test asserts < 1e-13,
        // measured within 1e-15)
        let solver = |b: f64| {
            Uncertainty::round_off(b, 2e-15, "Brent's method to 1e-15; agrees with 50-digit mpmath")
        };
        for c in d.free.iter().filter(|c| c.i <= 5) {
            k.cited(format!("beta_free_{}", c.i), c.ours, 13, solver(c.ours), "");
        }
        for c in d.clamped_pinned.iter().filter(|c| c.i <= 5) {
            k.cited(format!("beta_pinned_{}", c.i), c.ours, 13, solver(c.ours), "");
        }
        let worst = d
            .free
            .iter()
            .chain(&d.clamped_pinned)
            .chain(d.finite_k.iter().map(|p| &p.1))
            .map(|c| c.rel_diff)
            .fold(0.0, f64::max);
        k.text(
            "roots against mpmath",
            if worst < 1e-15 {
                "within 1e-15 relative, every root".to_string()
            } else {
                format!("within {worst:.1e} relative")
            },
        );
        // k₁ = β⁴ and k₂/k₁: four and eight times the roots' relative uncertainty
        k.cited(
            "k1",
            d.k1,
            12,
            Uncertainty::round_off(d.k1, 8e-15, "four times the roots' 2e-15"),
            "",
        );
        k.cited(
            "k2_over_k1",
            d.k2_over_k1,
            10,
            Uncertainty::round_off(d.k2_over_k1, 1.6e-14, "eight times the roots' 2e-15"),
            "",
        );
        let law = &d.small_k;
        k.cited(
            "small_k_fitted_order",
            law.fitted_order,
            3,
            Uncertainty::new(
                law.fitted_order_error,
                "standard error of the 7-point least-squares slope",
            ),
            "",
        );
        k.cited(
            "small_k_coefficient",
            law.fitted_coefficient,
            4,
            Uncertainty::new(
                (law.fitted_coefficient - law.next_coefficient).abs(),
                "drift of R/k² between the two smallest k of the ladder (the O(k³) term)",
            ),
            "",
        );
        // Σ_{j>1000} 1/(k_j − k₁) ≤ Σ 1/((j−½)π)⁴ ≈ 1/(3π⁴·1000³)
        k.cited(
            "small_k_coefficient_theory",
            law.predicted_coefficient,
            4,
            Uncertainty::new(
                1.0 / (3.0 * std::f64::consts::PI.powi(4) * 1e9),
                "the tail of the perturbation sum beyond j = 1000",
            ),
            "",
        );
        k
    }

    fn verdict(d: &SpectrumData) -> Verdict {
        let worst = d
            .free
            .iter()
            .chain(&d.clamped_pinned)
            .chain(d.finite_k.iter().map(|p| &p.1))
            .map(|c| c.rel_diff)
            .fold(0.0, f64::max);
        // the paper prints 39.3: half a unit in its last place; the order of the remainder
        // of eq (4) is 2 (a 7-point fit resolves it to ~1e-2)
        let ratio_ok = (d.k2_over_k1 - 39.3).abs() <= 0.05;
        let order_ok = (d.small_k.fitted_order - 2.0).abs() < 0.05;
        Verdict {
            outcome: if worst < 1e-13 && ratio_ok && order_ok {
                Outcome::Reproduced
            } else {
                Outcome::Partly
            },
            evidence: format!(
                "roots match 50-digit mpmath to {:.1e}; $k_2/k_1$ = {:.4}; remainder of (4) of order {:.2}",
                worst, d.k2_over_k1, d.small_k.fitted_order
            ),
        }
    }

    fn render(d: &SpectrumData) -> Result<Rendered, crate::results::render::RenderError> {
        Rendered::drawn(|layout| render::plot(d, layout), render::table(d))
    }
}
