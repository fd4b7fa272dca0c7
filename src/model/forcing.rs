//! The forcing f(s) cos ωt of eq (8) and its profiles, eq (37) among them, and their
//! projection onto the free modes, F⁻_j = ∫₀¹ φ_j f ds (re-exported by
//! [`crate::model::galerkin`], which assembles them into the model).
//!
//! Deviation from the printed paper (in the book's errata): eq (37)'s printed amplitude
//! k₁ψ₁(s)/(2ζ₁ψ₁(1)) gives an unconstrained tip amplitude 1/(4ζ₁²), not the unit amplitude
//! the text asks for; [`SpatialProfile::UnitTipAtResonance`] gives exactly 1 and
//! [`SpatialProfile::PaperEq37AsPrinted`] keeps the printed one for comparison.

use crate::base::numerics::Quadrature;
use crate::error::{self, ParameterError};
use crate::model::continuum;
use nalgebra::DVector;
use std::fmt;
use std::sync::Arc;

/// The spatial profile f(s) of harmonic forcing f(s) cos ωt.
#[derive(Clone)]
pub enum SpatialProfile {
    /// eq (37) with the amplitude the text intends: f(s) = a φ₁(s), a = C₁₁(β₁⁻)²/2, so
    /// that the unconstrained tip amplitude is 1 at ω = (β₁⁻)².
    UnitTipAtResonance,
    /// eq (37) as printed: f(s) = k₁ψ₁(s)/(2ζ₁ψ₁(1)) = k₁φ₁(s)/(4ζ₁), with ζ₁ = C₁₁/(2(β₁⁻)²).
    PaperEq37AsPrinted,
    /// Modal amplitudes f_j given directly (missing entries are zero).
    Modal(Vec<f64>),
    /// Any profile f(s) on [0, 1], projected onto φ_j by quadrature.
    Function(Arc<dyn Fn(f64) -> f64 + Send + Sync>),
}

impl fmt::Debug for SpatialProfile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnitTipAtResonance => write!(f, "UnitTipAtResonance"),
            Self::PaperEq37AsPrinted => write!(f, "PaperEq37AsPrinted"),
            Self::Modal(v) => write!(f, "Modal({v:?})"),
            Self::Function(_) => write!(f, "Function(..)"),
        }
    }
}

/// Harmonic forcing f(s) cos ωt.
#[derive(Debug, Clone)]
pub struct Forcing {
    /// ω, the forcing frequency.
    pub omega: f64,
    /// f(s).
    pub profile: SpatialProfile,
}

impl Forcing {
    /// Forcing f(s) cos ωt with a profile f of your choosing (projected onto the modes by
    /// quadrature).
    pub fn from_fn(omega: f64, profile: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        Self {
            omega,
            profile: SpatialProfile::Function(Arc::new(profile)),
        }
    }

    /// The paper's forcing, eq (37), with the corrected amplitude, at frequency ω.
    pub fn paper(omega: f64) -> Self {
        Self {
            omega,
            profile: SpatialProfile::UnitTipAtResonance,
        }
    }
}

/// f_j = ∫₀¹ φ_j f ds for j = 1..n.
pub(crate) fn project(
    profile: &SpatialProfile,
    n: usize,
    c11: f64,
    beta1: f64,
) -> Result<DVector<f64>, ParameterError> {
    let k1 = beta1.powi(4);
    let phi1 = continuum::free_mode(1)?;
    let amplitudes = match profile {
        SpatialProfile::Modal(v) => {
            let mut f = DVector::zeros(n);
            for (j, &a) in v.iter().take(n).enumerate() {
                f[j] = error::finite("modal forcing amplitude", a)?;
            }
            f
        }
        SpatialProfile::UnitTipAtResonance => {
            // the unit tip amplitude at resonance is set by the damping: undamped, the
            // amplitude would be 0 (and the resonant response unbounded)
            error::finite_positive(
                "first-mode damping C₁₁ (the unit amplitude at resonance scales with it)",
                c11,
            )?;
            let a = c11 * beta1 * beta1 / 2.0;
            project_function(&|s| a * phi1.value(s), n)?
        }
        SpatialProfile::PaperEq37AsPrinted => {
            let zeta1 = c11 / (2.0 * beta1 * beta1);
            error::finite_positive("first-mode damping ratio ζ₁ (eq 37 divides by it)", zeta1)?;
            project_function(&|s| k1 * phi1.value(s) / (4.0 * zeta1), n)?
        }
        SpatialProfile::Function(f) => project_function(f.as_ref(), n)?,
    };
    for a in amplitudes.iter() {
        error::finite("projected forcing amplitude", *a)?;
    }
    Ok(amplitudes)
}

/// ∫₀¹ φ_j f ds for j = 1..n, by quadrature fine enough for φ_n (also the modal state of a
/// deflection profile).
pub(crate) fn project_function(
    f: &dyn Fn(f64) -> f64,
    n: usize,
) -> Result<DVector<f64>, ParameterError> {
    let rule = weighted_modes(n)?;
    let fs: Vec<f64> = rule.nodes.iter().map(|&s| f(s)).collect();
    Ok(DVector::from_iterator(
        n,
        rule.weighted
            .iter()
            .map(|row| row.iter().zip(&fs).map(|(&wm, &fv)| wm * fv).sum::<f64>()),
    ))
}

/// The quadrature of the first n modes: its nodes s_i and, per mode, w_i·φ_j(s_i).
struct WeightedModes {
    nodes: Vec<f64>,
    weighted: Vec<Vec<f64>>,
}

/// The quadrature of the first n modes, built once per n: a model is built at every point of
/// a continuation or a curve (three per Newton step of a curve), and evaluating the mode
/// shapes at the nodes was a sixth of an atlas's curve tracing. The values are those a
/// fresh build gives, bit for bit. The last few n up to 64 are kept (at most 64 × 1280
/// values each); a larger N is built afresh (a 400-mode table holds 3.2 × 10⁶ values, and a
/// sweep over N meets each N once).
fn weighted_modes(n: usize) -> Result<Arc<WeightedModes>, ParameterError> {
    use std::sync::Mutex;
    static KEPT: Mutex<Vec<(usize, Arc<WeightedModes>)>> = Mutex::new(Vec::new());
    const KEEP: usize = 4;
    const LARGEST_KEPT: usize = 64;
    if let Some(hit) = KEPT
        .lock()
        .ok()
        .and_then(|kept| kept.iter().find(|(m, _)| *m == n).map(|(_, t)| t.clone()))
    {
        return Ok(hit);
    }
    let modes: Vec<_> = (1..=n)
        .map(continuum::free_mode)
        .collect::<Result<_, _>>()?;
    let quad = Quadrature::for_wavenumber(modes[n - 1].beta);
    let weighted = modes
        .iter()
        .map(|m| {
            quad.nodes
                .iter()
                .zip(&quad.weights)
                .map(|(&s, &w)| w * m.value(s))
                .collect()
        })
        .collect();
    let table = Arc::new(WeightedModes {
        nodes: quad.nodes,
        weighted,
    });
    if n > LARGEST_KEPT {
        return Ok(table);
    }
    if let Ok(mut kept) = KEPT.lock() {
        // (another thread may have built the same n meanwhile: kept once)
        if !kept.iter().any(|(m, _)| *m == n) {
            if kept.len() >= KEEP {
                kept.remove(0);
            }
            kept.push((n, table.clone()));
        }
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::{continuum, project_function, Quadrature};

    /// The kept quadrature gives the projection a fresh one gives, bit for bit: on the first
    /// call for an N, on a later one, and for an N too large to be kept.
    #[test]
    fn a_kept_quadrature_projects_as_a_fresh_one() {
        let f = |s: f64| (3.0 * s).sin() + s * s;
        for n in [1, 7, 20, 65] {
            let modes: Vec<_> = (1..=n).map(|j| continuum::free_mode(j).unwrap()).collect();
            let quad = Quadrature::for_wavenumber(modes[n - 1].beta);
            let fresh: Vec<f64> = modes
                .iter()
                .map(|m| {
                    quad.nodes
                        .iter()
                        .zip(&quad.weights)
                        .map(|(&s, &w)| w * m.value(s) * f(s))
                        .sum::<f64>()
                })
                .collect();
            for _ in 0..2 {
                let projected = project_function(&f, n).unwrap();
                assert!(
                    projected
                        .iter()
                        .zip(&fresh)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "N = {n}"
                );
            }
        }
    }
}
