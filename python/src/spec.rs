//! The parameters of a model as given, checked against the ranges the `cantilever` command
//! line supports, with its messages (the command line keeps its ranges in its binary,
//! `src/bin/cantilever/simulate/mod.rs`, with each reason; they are restated here), and the
//! compliant cantilever built from them exactly as `cantilever simulate` builds it.

use impacting_cantilever::error::{self, ParameterError};
use impacting_cantilever::model::galerkin::{
    self, first_frequency, first_modal_stiffness, Forcing, GalerkinModel, GalerkinParams,
    SpatialProfile,
};
use impacting_cantilever::model::restitution;
use nalgebra::DMatrix;

/// Largest number of discarded periods.
pub const MAX_PERIODS: u64 = 100_000_000;
/// Largest number of recorded periods.
pub const MAX_RECORD: u64 = 100_000;
/// Supported |d₀|.
pub const MAX_GAP: f64 = 1e6;
/// Supported ζ₁.
pub const ZETA1_RANGE: (f64, f64) = (1e-8, 1e3);
/// Supported ω/(β₁⁻)².
pub const OMEGA_RANGE: (f64, f64) = (1e-3, 1e4);
/// Supported k/k₁.
pub const MAX_STIFFNESS: f64 = 1e12;
/// The smallest nonzero forcing amplitude or initial state accepted.
pub const MIN_SCALE: f64 = 1e-100;
/// The largest initial state entry accepted.
pub const MAX_STATE: f64 = 1e6;

/// A number in `[lo, hi]`, else the command line's message.
pub fn range(name: &str, value: f64, (lo, hi): (f64, f64)) -> Result<f64, ParameterError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(ParameterError::new(
            name,
            error::number(value),
            &format!(
                "a number from {} to {}",
                error::number(lo),
                error::number(hi)
            ),
        ))
    }
}

/// A count in `1..=max` (given as any integer, so a negative one is refused by name).
pub fn count(name: &str, value: i64, max: usize) -> Result<usize, ParameterError> {
    if value >= 1 && value as u64 <= max as u64 {
        Ok(value as usize)
    } else {
        Err(ParameterError::new(
            name,
            value,
            &format!("an integer from 1 to {max}"),
        ))
    }
}

/// A magnitude too small for the method, with the way out.
pub fn tiny(name: &str, value: f64) -> ParameterError {
    ParameterError::new(
        name,
        error::number(value),
        "0 or a magnitude of at least 1e-100 (the model is linear in each region: scale the \
         forcing, the state and the gap together instead)",
    )
}

/// The beam's forcing amplitude.
#[derive(Debug, Clone, PartialEq)]
pub enum ForcingSpec {
    /// eq (37) corrected: free tip amplitude 1 at resonance.
    Unit,
    /// eq (37) as printed.
    Printed,
    /// The profile φ₁(s): modal force f₁ cos ωt on mode 1.
    Modal(f64),
}

/// The rigid model's law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    StiffnessLimit,
    ImpulseResponse,
    Collocation,
    Newton,
}

impl Law {
    /// The law named as the command line names it.
    pub fn parse(text: &str) -> Result<Self, ParameterError> {
        Ok(match text {
            "stiffness-limit" => Law::StiffnessLimit,
            "impulse-response" => Law::ImpulseResponse,
            "collocation" => Law::Collocation,
            "newton" => Law::Newton,
            _ => {
                return Err(ParameterError::new(
                    "law",
                    text,
                    "stiffness-limit, impulse-response, collocation or newton",
                ))
            }
        })
    }

    /// Its name, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Law::StiffnessLimit => "stiffness-limit",
            Law::ImpulseResponse => "impulse-response",
            Law::Collocation => "collocation",
            Law::Newton => "newton",
        }
    }

    /// [R] for N modes and coefficient r.
    pub fn matrix(self, n: usize, r: f64) -> Result<DMatrix<f64>, ParameterError> {
        match self {
            Law::StiffnessLimit => restitution::stiffness_limit(n, r),
            Law::ImpulseResponse | Law::Newton => restitution::impulse_response(n, r),
            Law::Collocation => {
                restitution::collocation(n, r, &restitution::equally_spaced_points(n))
            }
        }
    }
}

/// The compliant cantilever's parameters, as given.
#[derive(Debug, Clone, PartialEq)]
pub struct Cantilever {
    pub modes: usize,
    pub stop_stiffness: f64,
    pub gap: f64,
    pub gap_over_free: bool,
    pub zeta1: f64,
    pub fig4_literal: bool,
    pub viscous: f64,
    pub omega: f64,
    pub forcing: ForcingSpec,
}

impl Cantilever {
    /// The validated model, as `cantilever simulate` builds it (`simulate::model`), in the
    /// command line's order of checks.
    pub fn model(&self) -> Result<GalerkinModel, ParameterError> {
        range(
            "stop_stiffness (k/k₁)",
            self.stop_stiffness,
            (0.0, MAX_STIFFNESS),
        )?;
        range("gap (d₀)", self.gap, (-MAX_GAP, MAX_GAP))?;
        range("zeta1 (ζ₁)", self.zeta1, ZETA1_RANGE)?;
        range("viscous (α)", self.viscous, (0.0, 1e6))?;
        range("omega (ω/(β₁⁻)²)", self.omega, OMEGA_RANGE)?;
        let profile = match self.forcing {
            ForcingSpec::Unit => SpatialProfile::UnitTipAtResonance,
            ForcingSpec::Printed => SpatialProfile::PaperEq37AsPrinted,
            ForcingSpec::Modal(f1) => {
                range("forcing (f₁)", f1, (-1e12, 1e12))?;
                if f1 != 0.0 && f1.abs() < MIN_SCALE {
                    return Err(tiny("forcing (f₁)", f1));
                }
                SpatialProfile::Modal(vec![f1])
            }
        };
        let forcing = Forcing {
            omega: self.omega * first_frequency(),
            profile,
        };
        let gap = if self.gap_over_free { 0.0 } else { self.gap };
        let mut params =
            GalerkinParams::new(self.modes, self.stop_stiffness * first_modal_stiffness())
                .with_gap(gap)
                .with_viscous_damping(self.viscous)
                .with_forcing(forcing);
        params.material_damping = if self.fig4_literal {
            2.0 * self.zeta1 * first_frequency()
        } else {
            galerkin::material_damping_from_zeta1(self.zeta1)
        };
        let model = GalerkinModel::new(params)?;
        if !self.gap_over_free {
            return Ok(model);
        }
        let model = model.with_gap_over_free(self.gap)?;
        range(
            "gap d₀ = gap × A_free(ω)",
            model.params().gap,
            (-MAX_GAP, MAX_GAP),
        )?;
        Ok(model)
    }
}
