//! Shared by the curve tests: the multipliers of an orbit by shooting, not by the curve's
//! own system.

use impacting_cantilever::analysis::continuation::{Family, Parameter};
use impacting_cantilever::analysis::shooting;
use impacting_cantilever::model::problems::{self, Forced};
use nalgebra::DVector;

/// The Floquet multipliers [re, im] of the period-1 orbit near `x` of Figure 4's N-mode model
/// at (k/k₁, ω/(β₁⁻)²), by shooting.
pub fn multipliers_at(n: usize, k: f64, omega: f64, x: &[f64]) -> Vec<[f64; 2]> {
    let base = Forced {
        k_over_k1: k,
        ..problems::figure4(n)
    };
    let sim = Family::forced(base, Parameter::Frequency)
        .simulator(omega)
        .unwrap();
    shooting::shoot(&sim, &DVector::from_row_slice(x), 1)
        .unwrap()
        .multipliers
}
