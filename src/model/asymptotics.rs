//! Impact asymptotics of the compliant model as k = κε⁻² → ∞: §4.1–4.4, eqs (15)–(30).
//!
//! With t = ετ the contact phase of the N-mode model is a single fast mode (the stop mode,
//! eigenvector 𝟙/√N, scaled stiffness κ = kNε²) plus N − 1 slow modes (eq 27):
//!
//! - passage time through the + region Δ⁺ = πκ^{−1/2} in τ, i.e. πκ^{−1/2}ε in t (eq 18;
//!   §4 says O(ε⁻¹) for the latter: errata E6);
//! - effective restitution of the fast mode r_e = 1 − απκ^{−1/2}ε (eq 19);
//! - slow modes' velocity factor 1 − 2απκ^{−1/2}ε (eq 23).
//!
//! The exact 1-DOF return ratio, e^{−απ/ω_d} with ω_d = √(k₁ + k − α²), is also given so
//! the error of eq (19) can be measured.

/// κ = kNε² for stop stiffness k, N modes and scale ε (§4.3).
pub fn kappa(stop_stiffness: f64, modes: usize, eps: f64) -> f64 {
    stop_stiffness * modes as f64 * eps * eps
}

/// Δ⁺ = πκ^{−1/2}: the scaled passage time (eq 18); multiply by ε for time t.
pub fn passage_time_scaled(kappa: f64) -> f64 {
    std::f64::consts::PI / kappa.sqrt()
}

/// r_e = 1 − απκ^{−1/2}ε (eq 19).
pub fn effective_restitution(alpha: f64, kappa: f64, eps: f64) -> f64 {
    1.0 - alpha * std::f64::consts::PI / kappa.sqrt() * eps
}

/// The slow modes' velocity factor 1 − 2απκ^{−1/2}ε (eq 23).
pub fn slow_mode_factor(alpha: f64, kappa: f64, eps: f64) -> f64 {
    1.0 - 2.0 * alpha * std::f64::consts::PI / kappa.sqrt() * eps
}

/// The exact return-velocity ratio of η̈ + 2αη̇ + (k₁ + k)η = 0 from η = 0, η̇ > 0:
/// e^{−απ/ω_d}, ω_d = √(k₁ + k − α²) (underdamped).
pub fn exact_one_mode_restitution(alpha: f64, k1: f64, stop_stiffness: f64) -> f64 {
    let wd = (k1 + stop_stiffness - alpha * alpha).sqrt();
    (-alpha * std::f64::consts::PI / wd).exp()
}
