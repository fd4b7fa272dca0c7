//! The continuum beam with a compliant end stop: §2.1, eqs (1)–(4).
//!
//! Eigenfrequencies are (β_i^±)², with β_i^± the i-th positive root of eq (3),
//!
//! ```text
//! cos β cosh β + 1 + k/(4β³) (sin β cosh β − cos β sinh β) = 0,
//! ```
//!
//! for stop stiffness k^- = 0 (the free cantilever) or k^+ = k; k = ∞ gives the
//! clamped-pinned beam. Mode shapes are eq (2),
//! ψ_i(s) = cos βs − cosh βs − σ(sin βs − sinh βs), σ = (cos β + cosh β)/(sin β + sinh β).
//!
//! Numerics (the paper is silent on them):
//! - eq (3) is evaluated divided by cosh β and by (4β³ + k), so it neither overflows for
//!   large β nor loses scale for large k, and k = ∞ is the same formula;
//! - the i-th root for k > 0 is bracketed by the free and the clamped-pinned roots
//!   (eigenvalues increase monotonically with k, and interlacing bounds them by the k = ∞
//!   limit), so the solver can never jump to a neighbouring branch;
//! - mode shapes use cosh x − σ sinh x = e^{−x} + (1 − σ) sinh x with 1 − σ formed without
//!   cancellation, so ψ_i is accurate to round-off for i in the hundreds.
//!
//! Deviation from the paper: eq (1) prints the stop's shear condition as
//! w_sss = (k/4)(d₀ − w); eq (3), eq (5)–(6) and the energy all require
//! w_sss = (k/4)(w − d₀). We implement the latter (see the book's errata chapter).

use crate::base::numerics::brent;
use crate::error::{finite_non_negative, ParameterError};
use std::f64::consts::PI;

/// Largest mode index served (β ≈ 3140; well inside the overflow-free range).
pub const MAX_MODE_INDEX: usize = 1000;

/// Relative tolerance the root solver is asked for (the accuracy target is 1e-13).
const ROOT_REL_TOL: f64 = 1e-15;

/// eq (3) divided by cosh β · (4β³ + k)/(4β³): a weighted mean of the cantilever
/// (cos β + sech β) and the clamped-pinned (sin β − cos β tanh β) equations.
/// `stop_stiffness` may be `f64::INFINITY`.
pub fn characteristic(beta: f64, stop_stiffness: f64) -> f64 {
    let free = beta.cos() + 1.0 / beta.cosh();
    let pinned = beta.sin() - beta.cos() * beta.tanh();
    if stop_stiffness.is_infinite() {
        return pinned;
    }
    if stop_stiffness == 0.0 {
        return free;
    }
    let b3 = 4.0 * beta.powi(3);
    (b3 * free + stop_stiffness * pinned) / (b3 + stop_stiffness)
}

fn check_index(i: usize) -> Result<usize, ParameterError> {
    crate::error::count_in_range("mode index i", i, MAX_MODE_INDEX)
}

/// β_i^-: the i-th root of cos β + sech β = 0 (free cantilever, k = 0).
/// It lies in ((i−1)π, iπ), where cos is monotone and sech < 0.09 (for i ≥ 2) keeps the
/// root unique.
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`MAX_MODE_INDEX`].
///
/// # Panics
/// Never: the root is bracketed by a sign change of eq (3) for every index served.
pub fn free_root(i: usize) -> Result<f64, ParameterError> {
    check_index(i)?;
    let lo = (i as f64 - 1.0) * PI;
    let hi = i as f64 * PI;
    Ok(brent(|b| characteristic(b, 0.0), lo, hi, ROOT_REL_TOL).expect("sign change by theory"))
}

/// β_i^∞: the i-th root of tan β = tanh β (clamped-pinned beam, k = ∞).
/// It lies in (iπ, iπ + π/2), where tan rises from 0 to ∞ and tanh ∈ (0, 1).
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`MAX_MODE_INDEX`].
///
/// # Panics
/// Never: the root is bracketed by a sign change for every index served.
pub fn clamped_pinned_root(i: usize) -> Result<f64, ParameterError> {
    check_index(i)?;
    let lo = i as f64 * PI;
    let hi = lo + 0.5 * PI;
    Ok(
        brent(|b| characteristic(b, f64::INFINITY), lo, hi, ROOT_REL_TOL)
            .expect("sign change by theory"),
    )
}

/// β_i^+(k): the i-th root of eq (3) for stop stiffness k ∈ [0, ∞] (`f64::INFINITY`
/// allowed), to relative accuracy ≈ 1e-15.
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`MAX_MODE_INDEX`] or a NaN or negative stiffness.
pub fn root(i: usize, stop_stiffness: f64) -> Result<f64, ParameterError> {
    if stop_stiffness.is_nan() || stop_stiffness < 0.0 {
        return Err(ParameterError::new(
            "stop stiffness k",
            stop_stiffness,
            "a number ≥ 0, or ∞ for the clamped-pinned limit",
        ));
    }
    let lo = free_root(i)?;
    if stop_stiffness == 0.0 {
        return Ok(lo);
    }
    let hi = clamped_pinned_root(i)?;
    if stop_stiffness.is_infinite() {
        return Ok(hi);
    }
    let f = |b| characteristic(b, stop_stiffness);
    // If k is so small (or so large) that the root sits within round-off of an end of the
    // bracket, the end values may share a sign: the nearer end is then the root.
    Ok(brent(f, lo, hi, ROOT_REL_TOL).unwrap_or_else(|| {
        if f(lo).abs() <= f(hi).abs() {
            lo
        } else {
            hi
        }
    }))
}

/// β_1^+ … β_n^+ for stop stiffness k.
///
/// # Errors
/// [`ParameterError`] for `n` above [`MAX_MODE_INDEX`] or a NaN or negative stiffness.
pub fn roots(n: usize, stop_stiffness: f64) -> Result<Vec<f64>, ParameterError> {
    (1..=n).map(|i| root(i, stop_stiffness)).collect()
}

/// k_j = (β_j^-)⁴: the modal stiffness of free cantilever mode j (eq 8).
///
/// # Errors
/// [`ParameterError`] for `j` out of 1…[`MAX_MODE_INDEX`].
pub fn modal_stiffness(j: usize) -> Result<f64, ParameterError> {
    Ok(free_root(j)?.powi(4))
}

/// The small-k law, eq (4): (β_i^+)⁴ ≈ (β_i^-)⁴ + k.
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`MAX_MODE_INDEX`] or a stiffness that is not finite
/// and ≥ 0.
pub fn small_k_eigenvalue(i: usize, stop_stiffness: f64) -> Result<f64, ParameterError> {
    let k = finite_non_negative("stop stiffness k", stop_stiffness)?;
    Ok(modal_stiffness(i)? + k)
}

/// A mode shape of eq (2), scaled: `scale · ψ(s)` for the ψ printed in eq (2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeShape {
    /// β: the mode's wavenumber; its frequency is β².
    pub beta: f64,
    /// σ of eq (2).
    pub sigma: f64,
    /// 1 − σ, formed without cancellation (σ → 1 exponentially fast in β).
    pub one_minus_sigma: f64,
    /// Factor applied to the printed ψ (normalisation and sign).
    pub scale: f64,
}

impl ModeShape {
    /// ψ exactly as printed in eq (2) (scale 1), for any β > 0.
    pub fn printed(beta: f64) -> Self {
        // With E = e^{−β}: cosh β = (1 + E²)/(2E), sinh β = (1 − E²)/(2E), so
        // σ = (1 + E² + 2E cos β)/(1 − E² + 2E sin β) and
        // 1 − σ = 2E (sin β − cos β − E)/(1 − E² + 2E sin β): no cancellation, no overflow.
        let e = (-beta).exp();
        let den = 1.0 - e * e + 2.0 * e * beta.sin();
        let sigma = (1.0 + e * e + 2.0 * e * beta.cos()) / den;
        let one_minus_sigma = 2.0 * e * (beta.sin() - beta.cos() - e) / den;
        Self {
            beta,
            sigma,
            one_minus_sigma,
            scale: 1.0,
        }
    }

    /// [ψ, ψ', ψ'', ψ'''] at s ∈ [0, 1] (times `scale`).
    pub fn derivatives(&self, s: f64) -> [f64; 4] {
        let b = self.beta;
        let x = b * s;
        let (sx, cx) = x.sin_cos();
        // (1 − σ)·sinh x and (1 − σ)·cosh x, written with e^{x−β} so they stay bounded:
        // (1 − σ) = 2E(·)/den, and 2E·sinh x = e^{x−β} − e^{−x−β}.
        let e = (-b).exp();
        let den = 1.0 - e * e + 2.0 * e * b.sin();
        let lead = (b.sin() - b.cos() - e) / den;
        let (up, down) = ((x - b).exp(), (-x - b).exp());
        let oms_sinh = lead * (up - down);
        let oms_cosh = lead * (up + down);
        let emx = (-x).exp();
        // H0 = cosh x − σ sinh x, H1 = sinh x − σ cosh x, C0 = cos x − σ sin x,
        // C1 = −sin x − σ cos x; then ψ = C0 − H0, ψ' = β(C1 − H1), ψ'' = β²(−C0 − H0),
        // ψ''' = β³(−C1 − H1).
        let h0 = emx + oms_sinh;
        let h1 = -emx + oms_cosh;
        let c0 = cx - self.sigma * sx;
        let c1 = -sx - self.sigma * cx;
        let k = self.scale;
        [
            k * (c0 - h0),
            k * b * (c1 - h1),
            k * b * b * (-c0 - h0),
            k * b * b * b * (-c1 - h1),
        ]
    }

    /// ψ(s) (times `scale`).
    pub fn value(&self, s: f64) -> f64 {
        self.derivatives(s)[0]
    }

    /// ∫₀¹ (scale·ψ)² ds in closed form. For w'''' = β⁴w with w(0) = w'(0) = 0,
    /// integrating by parts gives
    /// 4β⁴∫w² = [β⁴w² + w''² − 2w'w''' − w'w'' + 3ww''']_{s=1}.
    pub fn squared_norm(&self) -> f64 {
        let [w, w1, w2, w3] = self.derivatives(1.0);
        let lambda = self.beta.powi(4);
        (lambda * w * w + w2 * w2 - 2.0 * w1 * w3 - w1 * w2 + 3.0 * w * w3) / (4.0 * lambda)
    }
}

/// φ_i = (−1)^i ψ_i^-: the free cantilever mode scaled so that φ_i(1) = 2 and
/// ∫φ_i² = 1 (§2.2; the text's (−1)^{i+1} is a sign slip, see the errata).
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`MAX_MODE_INDEX`].
pub fn free_mode(i: usize) -> Result<ModeShape, ParameterError> {
    let mut m = ModeShape::printed(free_root(i)?);
    m.scale = if i.is_multiple_of(2) { 1.0 } else { -1.0 };
    Ok(m)
}

/// ψ_i^+ for stop stiffness k ∈ [0, ∞], normalised to ∫ψ² = 1 with the sign of eq (2).
///
/// # Errors
/// [`ParameterError`] for `i` out of 1…[`MAX_MODE_INDEX`] or a NaN or negative stiffness.
pub fn constrained_mode(i: usize, stop_stiffness: f64) -> Result<ModeShape, ParameterError> {
    let mut m = ModeShape::printed(root(i, stop_stiffness)?);
    m.scale = 1.0 / m.squared_norm().sqrt();
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bracket_endpoints_interlace() {
        for i in 1..=50 {
            let (f, p) = (free_root(i).unwrap(), clamped_pinned_root(i).unwrap());
            assert!(f < p && p < free_root(i + 1).unwrap());
        }
    }

    #[test]
    fn bad_stiffness_is_an_error() {
        assert!(root(1, -1.0).is_err());
        assert!(root(1, f64::NAN).is_err());
        assert!(root(0, 1.0).is_err());
    }

    #[test]
    fn printed_mode_satisfies_the_clamped_and_moment_free_conditions() {
        for i in [1, 7, 60] {
            let m = ModeShape::printed(free_root(i).unwrap());
            let [w0, w1, _, _] = m.derivatives(0.0);
            let [_, _, w2, w3] = m.derivatives(1.0);
            let b = m.beta;
            // each term is O(β^n) and cancels to round-off: bound 1e-13 · β^n
            assert!(w0.abs() < 1e-13 && w1.abs() < 1e-13 * b);
            assert!(w2.abs() < 1e-13 * b * b && w3.abs() < 1e-13 * b.powi(3));
        }
    }
}
