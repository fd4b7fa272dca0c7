//! The experiment of §6 in the model's terms: Euler–Bernoulli beam theory for the steel
//! strip and for the pin's cantilever, the stop stiffness k/k₁, and the time and frequency
//! scales that put the model's numbers in seconds and hertz. Pure functions of the stated
//! dimensions and of a material (mild steel: E = 200–210 GPa, ρ = 7850 kg/m³).
//!
//! **The stop.** In the model's units (EI = ρA = L = 1) the stop's shear condition is
//! w_sss(1) = (k/4)(w − d₀) (eq 1, errata E1); in physical units EI w'''(L) = K(w − d₀), so
//! k = 4KL³/(EI), with K the stop's stiffness. A pin on a cantilever of the same steel
//! loaded at its tip has K = 3EI_pin/L_pin³ (Hertzian contact compliance in series would
//! lower it; the mounting is taken as rigid).

use crate::error::ParameterError;
use crate::model::continuum;
use serde::Serialize;

/// A rectangular steel strip clamped at one end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Strip {
    /// Free length L (m).
    pub length: f64,
    /// Width b (m).
    pub width: f64,
    /// Thickness h (m), in the direction of bending.
    pub thickness: f64,
}

/// A material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
}

/// The paper's strip: 300 × 25.5 × 1 mm.
pub const BEAM: Strip = Strip {
    length: 0.300,
    width: 0.0255,
    thickness: 0.001,
};

/// The pin's cantilever: 300 × 25.5 × 12 mm.
pub const PIN_BEAM: Strip = Strip {
    length: 0.300,
    width: 0.0255,
    thickness: 0.012,
};

/// The measured first natural frequency (Hz), from the ring-down test.
pub const MEASURED_F1: f64 = 5.92;

/// Mild steel at both ends of its usual modulus range.
pub const MILD_STEEL: [Material; 2] = [
    Material {
        youngs_modulus: 200e9,
        density: 7850.0,
    },
    Material {
        youngs_modulus: 210e9,
        density: 7850.0,
    },
];

impl Strip {
    /// I = bh³/12 (m⁴).
    pub fn second_moment(&self) -> f64 {
        self.width * self.thickness.powi(3) / 12.0
    }

    /// A = bh (m²).
    pub fn area(&self) -> f64 {
        self.width * self.thickness
    }

    /// EI/(ρA) (m⁴/s²).
    fn stiffness_over_mass(&self, m: &Material) -> f64 {
        m.youngs_modulus * self.second_moment() / (m.density * self.area())
    }

    /// The i-th natural frequency of the clamped-free strip (Hz):
    /// (β_i⁻)²/(2πL²)·√(EI/(ρA)).
    ///
    /// # Errors
    /// [`ParameterError`] for `i` out of 1…[`continuum::MAX_MODE_INDEX`].
    pub fn frequency(&self, i: usize, m: &Material) -> Result<f64, ParameterError> {
        let beta = continuum::free_root(i)?;
        Ok(
            beta * beta / (2.0 * std::f64::consts::PI * self.length.powi(2))
                * self.stiffness_over_mass(m).sqrt(),
        )
    }

    /// The free length that gives first frequency f (Hz), the rest unchanged.
    ///
    /// # Errors
    /// Never in practice: only the first free root is needed, which always exists (the
    /// [`ParameterError`] of [`Strip::frequency`] is passed on).
    pub fn length_for_frequency(&self, f: f64, m: &Material) -> Result<f64, ParameterError> {
        Ok(self.length * (self.frequency(1, m)? / f).sqrt())
    }

    /// The stiffness of the strip loaded at its tip (N/m): 3EI/L³.
    pub fn tip_stiffness(&self, m: &Material) -> f64 {
        3.0 * m.youngs_modulus * self.second_moment() / self.length.powi(3)
    }
}

/// k/k₁ for a stop of stiffness K (N/m) at the tip of `beam`: k = 4KL³/(EI), k₁ = (β₁⁻)⁴.
pub fn stop_ratio(beam: &Strip, stop: f64, m: &Material) -> f64 {
    let ei = m.youngs_modulus * beam.second_moment();
    4.0 * stop * beam.length.powi(3) / ei / crate::model::galerkin::first_modal_stiffness()
}

/// The tip mass, as a fraction μ of the strip's mass, that lowers its first frequency by
/// the factor `ratio` < 1: the exact frequency equation of a cantilever with a tip mass,
/// 1 + cos β cosh β + μβ(cos β sinh β − sin β cosh β) = 0, solved for μ at β = β₁⁻√ratio.
///
/// # Errors
/// [`ParameterError`] when `ratio` is not finite and > 0.
pub fn tip_mass_fraction(ratio: f64) -> Result<f64, ParameterError> {
    crate::error::finite_positive("frequency ratio", ratio)?;
    let beta = continuum::free_root(1)? * ratio.sqrt();
    let (c, s, ch, sh) = (beta.cos(), beta.sin(), beta.cosh(), beta.sinh());
    Ok(-(1.0 + c * ch) / (beta * (c * sh - s * ch)))
}

/// Seconds per unit of the model's time, given the measured first frequency: the model's
/// ω₁ = (β₁⁻)² is 2πf₁ rad/s.
pub fn time_unit(f1: f64) -> f64 {
    crate::model::galerkin::first_frequency() / (2.0 * std::f64::consts::PI * f1)
}

/// The rig as built: the strip, the pin's cantilever and the steel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Rig {
    /// The impacting strip.
    pub beam: Strip,
    /// The pin's cantilever.
    pub pin: Strip,
    /// The steel of both.
    pub material: Material,
}

/// The paper's rig, nominal: the stated dimensions and mild steel at E = 200 GPa.
pub const RIG: Rig = Rig {
    beam: BEAM,
    pin: PIN_BEAM,
    material: MILD_STEEL[0],
};

/// The ranges we assume for what the paper states as nominal values, each (low, high):
/// Young's modulus of mild steel 200–210 GPa; density 7800–7900 kg/m³; the strip's
/// thickness 1 mm ± 2.5 % (a cold-rolled strip's tolerance) and free length 300 ± 2 mm
/// (where the clamp grips); the pin bar's thickness 12 ± 0.1 mm and length 300 ± 2 mm. The
/// widths cancel from every quantity below but f₁'s, which does not depend on them.
pub const RANGES: [(&str, f64, f64); 6] = [
    ("E (Pa)", 200e9, 210e9),
    ("ρ (kg/m³)", 7800.0, 7900.0),
    ("h (m)", 0.975e-3, 1.025e-3),
    ("L (m)", 0.298, 0.302),
    ("h_pin (m)", 11.9e-3, 12.1e-3),
    ("L_pin (m)", 0.298, 0.302),
];

impl Rig {
    /// The rig at one corner of [`RANGES`]: bit i of `corner` picks the high end of range i.
    pub fn corner(corner: u32) -> Rig {
        let pick = |i: usize| {
            let (_, lo, hi) = RANGES[i];
            if corner >> i & 1 == 1 {
                hi
            } else {
                lo
            }
        };
        Rig {
            beam: Strip {
                thickness: pick(2),
                length: pick(3),
                ..BEAM
            },
            pin: Strip {
                thickness: pick(4),
                length: pick(5),
                ..PIN_BEAM
            },
            material: Material {
                youngs_modulus: pick(0),
                density: pick(1),
            },
        }
    }

    /// k/k₁ of the pin at the strip's tip.
    pub fn stop_ratio(&self) -> f64 {
        stop_ratio(
            &self.beam,
            self.pin.tip_stiffness(&self.material),
            &self.material,
        )
    }
}

/// The range (low, high) of `quantity` over the 64 corners of [`RANGES`]. Every quantity
/// computed here is a monotone function of each parameter (products of powers of them, or
/// monotone in such a product), so its extremes over the box are at corners.
///
/// # Errors
/// The first [`ParameterError`] `quantity` returns at a corner.
pub fn range_over(
    quantity: impl Fn(&Rig) -> Result<f64, ParameterError>,
) -> Result<(f64, f64), ParameterError> {
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for corner in 0..1u32 << RANGES.len() {
        let q = quantity(&Rig::corner(corner))?;
        range = (range.0.min(q), range.1.max(q));
    }
    Ok(range)
}

/// The pin's own first resonance (Hz): its cantilever's, by the same beam theory.
///
/// # Errors
/// Never in practice: the pin's first-mode frequency always exists (the [`ParameterError`]
/// of [`Strip::frequency`] is passed on).
pub fn pin_resonance(rig: &Rig) -> Result<f64, ParameterError> {
    rig.pin.frequency(1, &rig.material)
}

/// The pin's effective mass at its tip over the strip's modal mass at its tip, both in
/// their first modes: each is m/4 of its beam's mass m (a mode normalised with ∫φ² = 1 and
/// φ(1) = 2 has modal tip mass m/φ(1)² = m/4), so the ratio is the ratio of the beams'
/// masses, h_pin L_pin / (h L) for equal widths. (Rayleigh's static value for the pin,
/// 33/140 of its mass, gives 0.94 of this.)
pub fn pin_mass_ratio(rig: &Rig) -> f64 {
    (rig.pin.thickness * rig.pin.length) / (rig.beam.thickness * rig.beam.length)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tip_mass_of_zero_leaves_the_frequency_and_a_heavier_one_lowers_it() {
        assert!(tip_mass_fraction(1.0).unwrap().abs() < 1e-12);
        // a tip mass equal to the beam's lowers β₁ from 1.8751 to 1.2479 (Blevins, Table
        // 8-8: β₁ = 1.24792 for M/m = 1), i.e. f by (1.24792/1.87510)²
        let ratio = (1.24792f64 / 1.875_104_068_711_961).powi(2);
        assert!((tip_mass_fraction(ratio).unwrap() - 1.0).abs() < 1e-4);
    }

    #[test]
    fn the_stop_ratio_does_not_depend_on_the_modulus() {
        let [a, b] = MILD_STEEL;
        let ka = stop_ratio(&BEAM, PIN_BEAM.tip_stiffness(&a), &a);
        let kb = stop_ratio(&BEAM, PIN_BEAM.tip_stiffness(&b), &b);
        assert!((ka / kb - 1.0).abs() < 1e-14);
        // 4·3·(h_pin/h)³/(β₁⁻)⁴ for equal lengths and widths
        let expect = 12.0 * 12f64.powi(3) / crate::model::galerkin::first_modal_stiffness();
        assert!((ka / expect - 1.0).abs() < 1e-12);
    }
}
