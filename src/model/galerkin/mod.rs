//! The N-mode Galerkin compliant (bilinear) model: §2.2 eqs (5)–(9) and §5.1 eqs (31)–(35).
//!
//! The beam deflection is expanded in the free cantilever modes, w = Σ φ_i(s) η_i(t), with
//! ∫φ_iφ_j = δ_ij and φ_i(1) = 2 ([`crate::model::continuum::free_mode`]). Then
//!
//! ```text
//! η̈ + \[C\] η̇ + \[K^±\] η = F^±(t),                                   (34)
//! K⁻ = diag(k_j),  K⁺ = K⁻ + (k/4) φ(1)φ(1)ᵀ = K⁻ + k·11ᵀ,           (9)
//! C = diag(2α + γ k_j),                                            (34)
//! F⁺ = F⁻ + (k d₀/4) φ(1),   F⁻_j(t) = ∫ φ_j f(s) ds · cos ωt,      (8)–(9)
//! ```
//!
//! with k_j = (β_j^-)⁴, switching surface φ(1)ᵀη = d₀, and state-space form (35),
//! x = [η; η̇], A^± = [[0, I], [−K^±, −C]].
//!
//! Deviations from the printed paper (each in the book's errata):
//! - Damping ratio: C₁₁ = γk₁ = 2ζ₁(β₁⁻)², so γ = 2ζ₁/(β₁⁻)² (the Fig 9 caption's reading;
//!   §5.2 prints ζ₁ = γ(β₁⁻)⁻²/2).
//! - Forcing amplitude, eq (37): the printed k₁ψ₁(s)/(2ζ₁ψ₁(1)) gives an unconstrained tip
//!   amplitude 1/(4ζ₁²), not the unit amplitude the text asks for.
//!   [`SpatialProfile::UnitTipAtResonance`] is the profile a·φ₁(s) with a = C₁₁(β₁⁻)²/2,
//!   which gives exactly 1 (a = ζ₁k₁ for α = 0); [`SpatialProfile::PaperEq37AsPrinted`]
//!   keeps the printed amplitude for comparison.

use crate::base::numerics::brent;
use crate::error::{self, ParameterError};
use crate::model::continuum;
use crate::model::forcing::project;
pub use crate::model::forcing::{Forcing, SpatialProfile};
use crate::model::ranges;

mod equations;
use nalgebra::DVector;

/// Largest number of modes N accepted ([`crate::model::ranges::MODES`]).
pub const MAX_MODES: usize = ranges::MODES.max as usize;

/// Which side of the switching surface φ(1)ᵀη = d₀ the beam is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Region {
    /// The − region, φ(1)ᵀη < d₀: free flight.
    Free,
    /// The + region, φ(1)ᵀη ≥ d₀: in contact with the stop.
    Contact,
}

/// A generic impact oscillator ẍ + cẋ + kx = F cos ωt, stop at gx = d₀
/// ([`GalerkinModel::oscillator`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    /// k, the stiffness (force per unit displacement).
    pub stiffness: f64,
    /// c, the viscous damping coefficient (force per unit velocity).
    pub damping: f64,
    /// F.
    pub forcing: f64,
    /// ω.
    pub omega: f64,
    /// g: the tip displacement per unit x.
    pub tip_gain: f64,
    /// d₀.
    pub gap: f64,
    /// The stop stiffness k_s of the compliant contact (0 for the rigid model alone).
    pub stop_stiffness: f64,
}

/// The free modes of a discretised beam, mass-normalised ([`GalerkinModel::from_modes`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FreeModes {
    /// k_j, the modal stiffnesses (squared free frequencies).
    pub stiffness: Vec<f64>,
    /// t_j, each mode's tip displacement.
    pub tip: Vec<f64>,
    /// c_j, the modal damping.
    pub damping: Vec<f64>,
    /// f_j, the modal forcing amplitudes.
    pub forcing: Vec<f64>,
}

/// Parameters of the Galerkin model, validated by [`GalerkinModel::new`].
#[derive(Debug, Clone)]
pub struct GalerkinParams {
    /// N, the number of free cantilever modes.
    pub modes: usize,
    /// k, the stop stiffness (the stop itself has stiffness k/4, eq 1).
    pub stop_stiffness: f64,
    /// d₀, the gap between the tip at rest and the stop.
    pub gap: f64,
    /// α: mass-proportional viscous damping, entering as 2α (eq 1).
    pub viscous_damping: f64,
    /// γ: stiffness-proportional material damping (eq 31).
    pub material_damping: f64,
    /// The harmonic forcing; `None` for free vibration.
    pub forcing: Option<Forcing>,
}

impl GalerkinParams {
    /// N modes, stop stiffness k; no gap, damping or forcing.
    pub fn new(modes: usize, stop_stiffness: f64) -> Self {
        Self {
            modes,
            stop_stiffness,
            gap: 0.0,
            viscous_damping: 0.0,
            material_damping: 0.0,
            forcing: None,
        }
    }

    /// Sets the gap d₀.
    pub fn with_gap(mut self, gap: f64) -> Self {
        self.gap = gap;
        self
    }

    /// Sets the viscous damping α.
    pub fn with_viscous_damping(mut self, alpha: f64) -> Self {
        self.viscous_damping = alpha;
        self
    }

    /// Sets the material damping from ζ₁, the first mode's damping ratio:
    /// γ = 2ζ₁/(β₁⁻)² (so that C₁₁ = γk₁ = 2ζ₁(β₁⁻)²). A bad ζ₁ surfaces as a bad γ.
    pub fn with_zeta1(mut self, zeta1: f64) -> Self {
        self.material_damping = material_damping_from_zeta1(zeta1);
        self
    }

    /// Sets the forcing.
    pub fn with_forcing(mut self, forcing: Forcing) -> Self {
        self.forcing = Some(forcing);
        self
    }
}

/// γ = 2ζ₁/(β₁⁻)²: the material damping that gives mode 1 the damping ratio ζ₁.
pub fn material_damping_from_zeta1(zeta1: f64) -> f64 {
    2.0 * zeta1 / first_frequency()
}

/// (β₁⁻)², the first free frequency; the time and frequency unit of the CLI.
///
/// # Panics
/// Never: the first free root always exists.
pub fn first_frequency() -> f64 {
    continuum::free_root(1).expect("mode 1 exists").powi(2)
}

/// k₁ = (β₁⁻)⁴, the first modal stiffness; the unit of stop stiffness in the CLI.
pub fn first_modal_stiffness() -> f64 {
    first_frequency().powi(2)
}

/// The assembled N-mode model.
#[derive(Debug, Clone)]
pub struct GalerkinModel {
    params: GalerkinParams,
    beta: Vec<f64>,
    modal_stiffness: DVector<f64>,
    tip: DVector<f64>,
    damping: DVector<f64>,
    forcing_amplitude: DVector<f64>,
}

impl GalerkinModel {
    /// Validates the parameters and assembles the model.
    ///
    /// # Errors
    /// [`ParameterError`] for N out of 1…[`MAX_MODES`]; k negative, not finite or above 1e12 k₁;
    /// ω/(β₁⁻)² outside 1e-3…1e4; a gap that is not finite; α or γ negative or not finite; or a
    /// forcing profile that needs damping it lacks or projects to an amplitude that is not finite.
    pub fn new(params: GalerkinParams) -> Result<Self, ParameterError> {
        let n = error::count_in_range("modes N", params.modes, MAX_MODES)?;
        error::finite_non_negative("stop stiffness k", params.stop_stiffness)?;
        // the supported ranges (in the units users give them), with a hair of slack for the
        // rounding of k/k₁·k₁ and ω/(β₁⁻)²·(β₁⁻)² back to the user's value
        let slack = 1.0 + 1e-12;
        if params.stop_stiffness > ranges::STOP_STIFFNESS.hi * first_modal_stiffness() * slack {
            ranges::STOP_STIFFNESS.check(params.stop_stiffness / first_modal_stiffness())?;
        }
        if let Some(f) = &params.forcing {
            let w = f.omega / first_frequency();
            if !(w * slack >= ranges::OMEGA.lo && w <= ranges::OMEGA.hi * slack) {
                ranges::OMEGA.check(w)?;
            }
        }
        error::finite("gap d₀", params.gap)?;
        error::finite_non_negative("viscous damping α", params.viscous_damping)?;
        error::finite_non_negative("material damping γ", params.material_damping)?;
        let beta = continuum::roots(n, 0.0)?;
        let modal_stiffness = DVector::from_iterator(n, beta.iter().map(|b| b.powi(4)));
        let damping =
            modal_stiffness.map(|kj| 2.0 * params.viscous_damping + params.material_damping * kj);
        let forcing_amplitude = match &params.forcing {
            None => DVector::zeros(n),
            Some(f) => {
                error::finite_positive("forcing frequency ω", f.omega)?;
                project(&f.profile, n, damping[0], beta[0])?
            }
        };
        Ok(Self {
            tip: DVector::from_element(n, 2.0),
            params,
            beta,
            modal_stiffness,
            damping,
            forcing_amplitude,
        })
    }

    /// The generic one-degree-of-freedom impact oscillator in this model's form:
    /// ẍ + cẋ + kx = F cos ωt with the stop at gx = d₀ — any stiffness, damping, forcing
    /// and tip gain g, not only the cantilever's mode 1. The compliant contact adds
    /// (k_s/4)g²(x − d₀/g) beyond the stop; the rigid-impact model ([`crate::engine::rigid`]) uses
    /// only its position. It has no beam profile, so [`Self::modal_state`] refuses it.
    ///
    /// # Errors
    /// [`ParameterError`] when k, ω or g is not finite and > 0, c or the stop stiffness is not
    /// finite and ≥ 0, or F or d₀ is not finite.
    pub fn oscillator(o: &Oscillator) -> Result<Self, ParameterError> {
        error::finite_positive("oscillator stiffness k", o.stiffness)?;
        error::finite_non_negative("oscillator damping c", o.damping)?;
        error::finite("oscillator forcing amplitude F", o.forcing)?;
        error::finite_positive("oscillator forcing frequency ω", o.omega)?;
        error::finite_positive("oscillator tip gain g", o.tip_gain)?;
        error::finite("oscillator gap d₀", o.gap)?;
        error::finite_non_negative("oscillator stop stiffness", o.stop_stiffness)?;
        if o.damping == 0.0 && o.forcing != 0.0 {
            not_at_resonance(o)?;
        }
        let params = GalerkinParams::new(1, o.stop_stiffness)
            .with_gap(o.gap)
            .with_forcing(Forcing {
                omega: o.omega,
                profile: SpatialProfile::Modal(vec![o.forcing]),
            });
        Ok(Self {
            params,
            beta: Vec::new(),
            modal_stiffness: DVector::from_element(1, o.stiffness),
            tip: DVector::from_element(1, o.tip_gain),
            damping: DVector::from_element(1, o.damping),
            forcing_amplitude: DVector::from_element(1, o.forcing),
        })
    }

    /// A beam model given by the free modes of another discretisation (the finite-element
    /// beam, [`crate::model::fe`]): K⁻ = diag(k_j), tip values t_j, damping diag(c_j), forcing
    /// amplitudes f_j, so that K⁺ = K⁻ + (k/4)ttᵀ and F⁺ = F⁻ + (kd₀/4)t as in eq (9). It has
    /// no continuum profile, so [`Self::modal_state`] refuses it.
    ///
    /// # Errors
    /// [`ParameterError`] for no modes or more than 2·[`MAX_MODES`], lists of unequal length, a
    /// modal stiffness not finite and > 0, a negative or non-finite damping, a tip value, forcing
    /// amplitude, gap or stop stiffness that is not finite (or k < 0), or a forcing ω ≤ 0.
    pub fn from_modes(modes: &FreeModes, params: GalerkinParams) -> Result<Self, ParameterError> {
        let n = error::count_in_range("modes N", modes.stiffness.len(), 2 * MAX_MODES)?;
        error::finite_non_negative("stop stiffness k", params.stop_stiffness)?;
        error::finite("gap d₀", params.gap)?;
        let same = [&modes.tip, &modes.damping, &modes.forcing]
            .iter()
            .all(|v| v.len() == n);
        if !same {
            return Err(ParameterError::new(
                "free-mode lists",
                "of unequal length",
                "one entry per mode in each",
            ));
        }
        for j in 0..n {
            error::finite_positive("modal stiffness", modes.stiffness[j])?;
            error::finite("modal tip value", modes.tip[j])?;
            error::finite_non_negative("modal damping", modes.damping[j])?;
            error::finite("modal forcing amplitude", modes.forcing[j])?;
        }
        if let Some(f) = &params.forcing {
            error::finite_positive("forcing frequency ω", f.omega)?;
        }
        Ok(Self {
            params,
            beta: Vec::new(),
            modal_stiffness: DVector::from_column_slice(&modes.stiffness),
            tip: DVector::from_column_slice(&modes.tip),
            damping: DVector::from_column_slice(&modes.damping),
            forcing_amplitude: DVector::from_column_slice(&modes.forcing),
        })
    }

    /// N, the number of modes.
    pub fn modes(&self) -> usize {
        self.modal_stiffness.len()
    }

    /// The validated parameters.
    pub fn params(&self) -> &GalerkinParams {
        &self.params
    }

    /// β_j^-, j = 1..N.
    /// (empty for a [`Self::oscillator`]).
    pub fn beta(&self) -> &[f64] {
        &self.beta
    }

    /// k_j = (β_j^-)⁴, the diagonal of K⁻.
    pub fn modal_stiffness(&self) -> &DVector<f64> {
        &self.modal_stiffness
    }

    /// φ(1): every entry is 2.
    pub fn tip(&self) -> &DVector<f64> {
        &self.tip
    }

    /// Diagonal of \[C\]: 2α + γk_j.
    pub fn damping(&self) -> &DVector<f64> {
        &self.damping
    }

    /// Modal forcing amplitudes f_j = ∫φ_j f ds (zero without forcing).
    pub fn forcing_amplitude(&self) -> &DVector<f64> {
        &self.forcing_amplitude
    }

    /// The forcing frequency ω (0 without forcing).
    pub fn omega(&self) -> f64 {
        self.params.forcing.as_ref().map_or(0.0, |f| f.omega)
    }

    /// A_free(ω) and ωA_free(ω): the steady-state tip amplitude and tip velocity amplitude of
    /// the forced response with the stop removed, |Σ_j φ_j(1) f_j/(k_j − ω² + iC_jjω)|. The
    /// paper's unit of displacement (1 at ω = (β₁⁻)² with the corrected eq (37)).
    pub fn free_tip_amplitude(&self) -> (f64, f64) {
        let omega = self.omega();
        // the modes' responses add as phasors: a mode forced above its resonance moves
        // against one forced below it
        let amp = (0..self.modes())
            .map(|j| {
                let denominator = num_complex::Complex64::new(
                    self.modal_stiffness[j] - omega * omega,
                    self.damping[j] * omega,
                );
                self.tip[j] * self.forcing_amplitude[j] / denominator
            })
            .sum::<num_complex::Complex64>()
            .norm();
        (amp, amp * omega)
    }

    /// The same model forced at frequency ω instead (the modal forcing amplitudes do not
    /// depend on ω, so nothing is recomputed); an error without forcing or for a bad ω.
    ///
    /// # Errors
    /// [`ParameterError`] for ω not finite and > 0, or a model without forcing.
    pub fn with_omega(&self, omega: f64) -> Result<Self, ParameterError> {
        error::finite_positive("forcing frequency ω", omega)?;
        let mut m = self.clone();
        match m.params.forcing.as_mut() {
            Some(f) => f.omega = omega,
            None => {
                return Err(ParameterError::new(
                    "forcing frequency ω",
                    omega,
                    "a model with forcing",
                ))
            }
        }
        Ok(m)
    }

    /// The same model with its gap d₀ set to `gap_over_free` times A_free(ω), the free tip
    /// amplitude at the forcing frequency ([`Self::free_tip_amplitude`]): a gap chosen as a
    /// fraction of the motion actually forced is reached at any ω (< 1 means contact).
    ///
    /// # Errors
    /// [`ParameterError`] for a ratio that is not finite, a model without forcing (A_free = 0), or
    /// a resulting gap that is not finite.
    pub fn with_gap_over_free(&self, gap_over_free: f64) -> Result<Self, ParameterError> {
        error::finite("gap d₀/A_free", gap_over_free)?;
        let a_free = self.free_tip_amplitude().0;
        if a_free == 0.0 {
            return Err(ParameterError::new(
                "gap d₀/A_free",
                gap_over_free,
                "a model with forcing (A_free is 0 without it)",
            ));
        }
        let mut m = self.clone();
        m.params.gap = gap_over_free * a_free;
        error::finite("gap d₀", m.params.gap)?;
        Ok(m)
    }
}

/// Eigenvalues λ_1 < … < λ_N of K⁺ = diag(d) + k·11ᵀ (Fig 2), from the secular equation
/// 1 + k Σ_j 1/(d_j − λ) = 0. Each root is bracketed (interlacing: d_i < λ_i < d_{i+1},
/// d_N < λ_N ≤ d_N + kN) and solved in the shifted variable μ = λ − d_i, so even
/// λ_i − d_i ≈ k ≪ d_i keeps full relative accuracy. `d` must be strictly increasing.
pub fn contact_eigenvalues(d: &[f64], stop_stiffness: f64) -> Vec<f64> {
    let n = d.len();
    let k = stop_stiffness;
    // every shift λ_i − d_i lies in [0, kN] (they sum to the trace kN); below half an ulp
    // of d_1 each λ_i rounds to d_i. (Then 1/k may overflow, for subnormal k: the bracket
    // below would fail.)
    if k * n as f64 <= 0.25 * f64::EPSILON * d.first().map_or(0.0, |x| x.abs()) || k == 0.0 {
        return d.to_vec();
    }
    (0..n)
        .map(|i| {
            let width = if i + 1 < n {
                d[i + 1] - d[i]
            } else {
                k * n as f64
            };
            // The secular function divided by k, g(μ) = 1/k + Σ_j 1/(d_j − d_i − μ): the same
            // roots, and no overflow for k up to f64::MAX. g → −∞ as μ → 0⁺ and is ≥ 0 at the
            // upper end (for i = N: each term is ≥ −1/(kN), N of them).
            let g = |mu: f64| 1.0 / k + (0..n).map(|j| 1.0 / ((d[j] - d[i]) - mu)).sum::<f64>();
            let hi = if i + 1 < n {
                width * (1.0 - 4.0 * f64::EPSILON)
            } else {
                width
            };
            // a lower end with g < 0: the root is ≈ min(k, width) for any k, so start
            // below that and halve (g(μ) ≈ −1/μ dominates as μ shrinks)
            let mut lo = 0.5 * k.min(width);
            while g(lo) >= 0.0 && lo > f64::MIN_POSITIVE * 4.0 {
                lo *= 0.5;
            }
            let mu =
                brent(g, lo, hi, 1e-15).unwrap_or(if g(lo).abs() < g(hi).abs() { lo } else { hi });
            d[i] + mu
        })
        .collect()
}

/// How near an undamped oscillator's forcing frequency may come to a natural frequency,
/// relative in ω²: the exact flow is the periodic particular solution plus the free
/// motion, and near resonance both grow like 1/|ω² − ω_n²| while their difference stays of
/// the order of the motion, so within 1e-6 of resonance more than six of the result's
/// sixteen digits would cancel.
pub const RESONANCE_SEPARATION: f64 = 1e-6;

/// Refuses an undamped oscillator forced (F ≠ 0) at (or within [`RESONANCE_SEPARATION`] of) a
/// natural frequency of its free or its contact region: there the forced response grows
/// like t and has no periodic part, which the exact flow does not represent.
fn not_at_resonance(o: &Oscillator) -> Result<(), ParameterError> {
    let contact = o.stiffness + o.stop_stiffness * o.tip_gain * o.tip_gain / 4.0;
    let regions = [("free", o.stiffness), ("in contact", contact)];
    for (region, stiffness) in regions
        .into_iter()
        .take(if o.stop_stiffness > 0.0 { 2 } else { 1 })
    {
        let square = o.omega * o.omega;
        if (square - stiffness).abs() <= RESONANCE_SEPARATION * stiffness {
            return Err(ParameterError::new(
                "oscillator forcing frequency ω",
                error::number(o.omega),
                &format!(
                    "with no damping (c = 0), ω² not within {RESONANCE_SEPARATION:e} (relative) of \
                     the natural frequency² {} ({region}): the forced response there grows \
                     like t without a periodic part; give c > 0 or another ω",
                    error::number(stiffness)
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_undamped_oscillator_at_resonance_is_refused_by_name() {
        let at = |omega: f64, damping: f64, stop_stiffness: f64| {
            GalerkinModel::oscillator(&Oscillator {
                stiffness: 4.0,
                damping,
                forcing: 1.0,
                omega,
                tip_gain: 1.0,
                gap: 0.5,
                stop_stiffness,
            })
        };
        let e = at(2.0, 0.0, 0.0).unwrap_err().to_string();
        assert!(
            e.starts_with(
                "invalid oscillator forcing frequency ω: got 2; allowed: with no damping"
            ),
            "{e}"
        );
        assert!(e.contains("natural frequency² 4 (free)"), "{e}");
        // in contact: k + k_s g²/4 = 4 + 12/4 = 7
        let e = at(7f64.sqrt(), 0.0, 12.0).unwrap_err().to_string();
        assert!(e.contains("natural frequency² 7 (in contact)"), "{e}");
        // damped, or away from resonance: built
        assert!(at(2.0, 0.01, 0.0).is_ok() && at(2.0 * (1.0 + 1e-6), 0.0, 0.0).is_ok());
        assert!(at(7f64.sqrt(), 0.0, 0.0).is_ok());
        // unforced, there is no forced response to grow
        let free = Oscillator {
            forcing: 0.0,
            damping: 0.0,
            omega: 2.0,
            stiffness: 4.0,
            tip_gain: 1.0,
            gap: 0.5,
            stop_stiffness: 0.0,
        };
        assert!(GalerkinModel::oscillator(&free).is_ok());
    }

    #[test]
    fn contact_stiffness_is_diagonal_plus_k_times_ones() {
        let m = GalerkinModel::new(GalerkinParams::new(3, 7.0)).unwrap();
        let kp = m.stiffness(Region::Contact);
        let km = m.stiffness(Region::Free);
        for i in 0..3 {
            for j in 0..3 {
                // entries are sums of two doubles: exact to one rounding of k_j
                let expected = km[(i, j)] + 7.0;
                assert!((kp[(i, j)] - expected).abs() <= 4.0 * f64::EPSILON * expected);
            }
        }
    }

    #[test]
    fn a_vanishing_stop_leaves_the_free_eigenvalues() {
        // subnormal and tiny k: each λ_i is d_i to the last bit (the shift kN is below half
        // an ulp), not a root lost to 1/k = ∞
        let d = [12.36, 485.5, 3806.5];
        for k in [5e-324, 1e-310, 1e-300, 1e-20] {
            assert_eq!(contact_eigenvalues(&d, k), d.to_vec(), "k = {k:e}");
        }
        // just above: the shift shows in the last bits, and nothing is lost or reordered
        let l = contact_eigenvalues(&d, 1e-14);
        assert!(l
            .iter()
            .zip(&d)
            .all(|(a, b)| a >= b && a - b <= 3e-14 + 4.0 * f64::EPSILON * b));
    }

    #[test]
    fn bad_parameters_are_typed_errors() {
        let err = |p: GalerkinParams| GalerkinModel::new(p).unwrap_err().to_string();
        assert!(err(GalerkinParams::new(0, 1.0)).starts_with("invalid modes N: got 0"));
        assert!(err(GalerkinParams::new(2, -1.0)).starts_with("invalid stop stiffness k"));
        assert!(err(GalerkinParams::new(2, f64::INFINITY)).contains("finite"));
        assert!(err(GalerkinParams::new(2, 1.0).with_gap(f64::NAN)).contains("gap d₀"));
        assert!(err(GalerkinParams::new(2, 1.0).with_zeta1(-0.1)).contains("material damping"));
        let bad_omega = GalerkinParams::new(2, 1.0).with_forcing(Forcing::paper(0.0));
        assert!(err(bad_omega).contains("omega (ω/(β₁⁻)²)"));
        // the supported ranges hold here too, not only in the front ends: ω = 1e-300 and a
        // stop beyond 1e12k₁ are refused, and the paper's unit forcing of an undamped beam
        // (amplitude C₁₁(β₁⁻)²/2 = 0: silently no forcing) is refused
        let tiny_omega = GalerkinParams::new(2, 1.0)
            .with_zeta1(0.01)
            .with_forcing(Forcing::paper(1e-300));
        assert!(err(tiny_omega).starts_with("invalid omega (ω/(β₁⁻)²): got 2.84"));
        let stiff = GalerkinParams::new(2, 2e12 * first_modal_stiffness());
        assert!(err(stiff).starts_with("invalid stop_stiffness (k/k₁): got 2e12"));
        let at_limit = GalerkinParams::new(2, 1e12 * first_modal_stiffness());
        assert!(GalerkinModel::new(at_limit).is_ok());
        let undamped = GalerkinParams::new(2, 1.0).with_forcing(Forcing::paper(first_frequency()));
        assert!(err(undamped).contains("first-mode damping C₁₁"));
    }
}
