//! Canonical problems: the paper's parameter sets as named constructors, in one place.
//! Scenes, tests, benchmarks, examples and the command line build their models here and
//! nowhere else, so "the Figure 4 model" means one thing.
//!
//! Units (as in the paper's §5): lengths and time are those of the non-dimensional beam
//! (EI = ρA = L = 1); stop stiffness is given as k/k₁ with k₁ = (β₁⁻)⁴ ≈ 12.36 and
//! frequencies as ω/(β₁⁻)². With the corrected eq (37) forcing (errata E2) the free tip
//! amplitude at resonance is 1, so d₀ is in units of it.

use crate::error::ParameterError;
use crate::model::galerkin::{
    first_frequency, first_modal_stiffness, Forcing, GalerkinModel, GalerkinParams, SpatialProfile,
};
use nalgebra::DVector;
use serde::Serialize;

/// The paper's forced bilinear model (eq 34 with the forcing of eq 37, material damping):
/// N modes, k = `k_over_k1`·k₁, ζ₁ (γ = 2ζ₁/(β₁⁻)², errata E3), ω = `omega_over_w1`·(β₁⁻)²,
/// gap d₀, α = 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct Forced {
    /// N, the number of modes.
    pub modes: usize,
    /// k/k₁.
    pub k_over_k1: f64,
    /// ζ₁, the first mode's damping ratio.
    pub zeta1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// d₀ (in units of the free tip amplitude at resonance).
    pub gap: f64,
    /// The forcing amplitude as printed in eq (37) (`true`; 1/(4ζ₁²) times larger) or as
    /// the text intends, unit free tip amplitude at resonance (`false`, the default).
    pub printed_eq37_amplitude: bool,
}

impl Forced {
    /// The model (errors name the parameter that is out of range).
    ///
    /// # Errors
    /// The [`ParameterError`] of [`GalerkinModel::new`]: N out of 1…400, k/k₁ or ω/(β₁⁻)² out of
    /// its range, a gap that is not finite, or ζ₁ not > 0 (the forcing profile scales with it).
    pub fn model(&self) -> Result<GalerkinModel, ParameterError> {
        let profile = if self.printed_eq37_amplitude {
            SpatialProfile::PaperEq37AsPrinted
        } else {
            SpatialProfile::UnitTipAtResonance
        };
        GalerkinModel::new(
            GalerkinParams::new(self.modes, self.k_over_k1 * first_modal_stiffness())
                .with_gap(self.gap)
                .with_zeta1(self.zeta1)
                .with_forcing(Forcing {
                    omega: self.omega_over_w1 * first_frequency(),
                    profile,
                }),
        )
    }
}

impl Forced {
    /// The same problem with its gap d₀ given in units of the free tip amplitude A_free at
    /// the forcing frequency (the linear steady response without the stop), rather than at
    /// resonance: a gap chosen as a fraction of the motion actually forced is reached at
    /// any ω (`gap_over_free` < 1 means contact).
    ///
    /// # Errors
    /// [`ParameterError`] for a ratio that is not finite, or the errors of [`Forced::model`].
    pub fn with_gap_over_free(self, gap_over_free: f64) -> Result<Self, ParameterError> {
        crate::error::finite("gap d₀/A_free", gap_over_free)?;
        let a_free = Forced { gap: 0.0, ..self }.model()?.free_tip_amplitude().0;
        Ok(Forced {
            gap: gap_over_free * a_free,
            ..self
        })
    }
}

/// Figure 4 and §5.3: k = 100k₁, α = 0, ζ₁ = 0.01, d₀ = 0, ω = 2(β₁⁻)², from rest (the
/// paper's N = 1, 2, 3, 10). Figure 5 sweeps its k.
pub fn figure4(modes: usize) -> Forced {
    Forced {
        modes,
        k_over_k1: 100.0,
        zeta1: 0.01,
        omega_over_w1: 2.0,
        gap: 0.0,
        printed_eq37_amplitude: false,
    }
}

/// Figure 6(a), §5.4: N = 20 in the paper, k = 1000k₁, d₀ = 0.8, ω = 1.15(β₁⁻)², ζ₁ = 0.1
/// ("a (1,1) orbit near grazing", r_E = 0.036).
pub fn figure6a(modes: usize) -> Forced {
    Forced {
        modes,
        k_over_k1: 1000.0,
        zeta1: 0.1,
        omega_over_w1: 1.15,
        gap: 0.8,
        printed_eq37_amplitude: false,
    }
}

/// Figure 6(b), §5.4: N = 20 in the paper, k = 1000k₁, d₀ = 0, ω = 2(β₁⁻)², ζ₁ = 0.01
/// (multiple taps, r_E = 0.74).
pub fn figure6b(modes: usize) -> Forced {
    Forced {
        modes,
        k_over_k1: 1000.0,
        zeta1: 0.01,
        omega_over_w1: 2.0,
        gap: 0.0,
        printed_eq37_amplitude: false,
    }
}

/// Figure 9, §6 (the experiment's parameters): N = 20 in the paper, ζ₁ = 7.7e-4 (the
/// caption's ζ₁ = γ(β₁⁻)²/2), α = 0, ω = 1.7(β₁⁻)², k = 1000k₁. The gap is not stated in
/// the paper: pass it.
pub fn figure9(modes: usize, gap: f64) -> Forced {
    Forced {
        modes,
        k_over_k1: 1000.0,
        zeta1: 7.7e-4,
        omega_over_w1: 1.7,
        gap,
        printed_eq37_amplitude: false,
    }
}

/// One contact at k = ε⁻² (Figure 3(a)–(c), §4.1–4.3): N modes, viscous damping α, no
/// forcing, d₀ = 0, from η = 0 with η̇ = ε⁻¹e₁ (the tip entering the stop). Returns the
/// model and the initial state.
///
/// # Errors
/// [`ParameterError`] for ε not finite and > 0, N out of 1…400, ε⁻² above the stiffness range,
/// or α negative or not finite.
pub fn one_contact(
    modes: usize,
    eps: f64,
    alpha: f64,
) -> Result<(GalerkinModel, DVector<f64>), ParameterError> {
    crate::error::finite_positive("scale ε", eps)?;
    let model =
        GalerkinModel::new(GalerkinParams::new(modes, eps.powi(-2)).with_viscous_damping(alpha))?;
    let mut x0 = DVector::zeros(2 * modes);
    x0[modes] = 1.0 / eps;
    Ok((model, x0))
}

/// The linear model with the stop out of reach (d₀ = 10⁶, k = 100k₁): N modes, material
/// damping ζ₁, the eq (37) forcing at ω/(β₁⁻)²; the flow never switches, so every
/// closed-form result of a forced linear system applies (see [`linear_response`]).
pub fn out_of_reach(modes: usize, zeta1: f64, omega_over_w1: f64) -> Forced {
    Forced {
        modes,
        k_over_k1: 100.0,
        zeta1,
        omega_over_w1,
        gap: 1e6,
        printed_eq37_amplitude: false,
    }
}

/// The exact solution of one damped forced mode, ẍ + cẋ + kx = F cos ωt from (x₀, v₀),
/// underdamped (c² < 4k): (x(t), ẋ(t)). Mode j of [`out_of_reach`] obeys it with k = k_j,
/// c = C_jj, F = f_j.
#[allow(clippy::too_many_arguments)]
pub fn linear_response(k: f64, c: f64, f: f64, omega: f64, x0: f64, v0: f64, t: f64) -> (f64, f64) {
    let den = (k - omega * omega).powi(2) + (c * omega).powi(2);
    let (pr, pi) = (f * (k - omega * omega) / den, f * c * omega / den);
    // x_p = pr cos ωt + pi sin ωt
    let xp = |t: f64| pr * (omega * t).cos() + pi * (omega * t).sin();
    let vp = |t: f64| omega * (-pr * (omega * t).sin() + pi * (omega * t).cos());
    let wd = (k - c * c / 4.0).sqrt();
    let a = x0 - xp(0.0);
    let b = (v0 - vp(0.0) + c / 2.0 * a) / wd;
    let e = (-c * t / 2.0).exp();
    let (s, co) = (wd * t).sin_cos();
    let xh = e * (a * co + b * s);
    let vh = e * (-c / 2.0 * (a * co + b * s) + wd * (-a * s + b * co));
    (xp(t) + xh, vp(t) + vh)
}
