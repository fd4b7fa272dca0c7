//! Modal restitution laws of the rigid-impact limit: §3–4, eqs (10)–(14) and (24)–(29).
//!
//! An N-mode impact law maps pre-impact to post-impact modal velocities,
//! η̇⁺ = −\[R\] η̇⁻ (eq 11), applied when φ(1)ᵀη = d₀ with φ(1)ᵀη̇ > 0. Three laws:
//!
//! - **collocation** \[R\]_C (eq 12, Wagg & Bishop): Newton's law at the tip and unchanged
//!   velocity at N − 1 collocation points s_j; non-unique (it depends on the s_j);
//! - **impulse-response** \[R\]_IR (eq 14, Vyasarayani et al.): the tip velocity is reversed
//!   by an impulsive tip force, η̇⁺ = η̇⁻ − ((r+1)/N) 𝟙 𝟙ᵀη̇⁻; eq (14) is labelled "2DOF" but
//!   holds for any N (errata E6);
//! - **stiffness-limit** \[R\]_N (eqs 28–29): the k → ∞ limit of the compliant model, with the
//!   effective coefficient r_e of eq (19).
//!
//! Deviation: eq (25) as printed is the negative of eq (24) (errata E4);
//! [`two_mode_eq25_as_printed`] keeps it for the test that shows it.

use crate::error::{self, ParameterError};
use crate::model::continuum;
use nalgebra::DMatrix;

/// Largest N accepted by the laws.
pub const MAX_MODES: usize = crate::model::ranges::MODES.max as usize;

fn check(n: usize, r: f64) -> Result<(), ParameterError> {
    error::count_in_range("modes N", n, MAX_MODES)?;
    if !(r.is_finite() && (0.0..=1.0).contains(&r)) {
        return Err(ParameterError::new(
            "coefficient of restitution r",
            r,
            "a number in [0, 1]",
        ));
    }
    Ok(())
}

/// \[R\]_IR of eq (14): (1/N)[(r + 1)𝟙𝟙ᵀ − N I].
///
/// # Errors
/// [`ParameterError`] for N out of 1…[`MAX_MODES`] or r outside [0, 1].
pub fn impulse_response(n: usize, r: f64) -> Result<DMatrix<f64>, ParameterError> {
    check(n, r)?;
    let nf = n as f64;
    Ok(DMatrix::from_fn(n, n, |i, j| {
        (r + 1.0) / nf - if i == j { 1.0 } else { 0.0 }
    }))
}

/// \[R\]_N of eq (29): (1 − 2r_e) I + ((3r_e − 1)/N) 𝟙𝟙ᵀ.
///
/// # Errors
/// [`ParameterError`] for N out of 1…[`MAX_MODES`] or r_e outside [0, 1].
pub fn stiffness_limit(n: usize, r_e: f64) -> Result<DMatrix<f64>, ParameterError> {
    check(n, r_e)?;
    let nf = n as f64;
    Ok(DMatrix::from_fn(n, n, |i, j| {
        (3.0 * r_e - 1.0) / nf + if i == j { 1.0 - 2.0 * r_e } else { 0.0 }
    }))
}

/// \[R\]_N from eq (28): V diag(1 − 2r_e, …, 1 − 2r_e, r_e) Vᵀ for an orthogonal V whose last
/// column is the fast (stop) mode. With V from the eigenvectors of K⁺ as k → ∞ this is
/// eq (29); for finite k it is the law the compliant model's own eigenvectors imply.
///
/// # Errors
/// [`ParameterError`] for a V that is not square, has an entry that is not finite or is
/// empty, or an r_e outside [0, 1].
pub fn from_eigenvectors(v: &DMatrix<f64>, r_e: f64) -> Result<DMatrix<f64>, ParameterError> {
    let n = v.ncols();
    if v.nrows() != n || n == 0 {
        return Err(ParameterError::new(
            "eigenvector matrix [V]",
            format!("{} × {}", v.nrows(), n),
            "a square N × N matrix, N ≥ 1",
        ));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(ParameterError::new(
            "eigenvector matrix [V]",
            "an entry that is not finite",
            "finite entries",
        ));
    }
    check(n, r_e)?;
    let mut d = DMatrix::from_element(n, n, 0.0);
    for i in 0..n {
        d[(i, i)] = if i + 1 == n { r_e } else { 1.0 - 2.0 * r_e };
    }
    Ok(v * d * v.transpose())
}

/// \[V\] of eq (21): the k → ∞ eigenvectors of K⁺ for N = 2, slow mode first.
pub fn two_mode_eigenvectors() -> DMatrix<f64> {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    DMatrix::from_row_slice(2, 2, &[s, s, -s, s])
}

/// Eq (25) exactly as printed: ½[[r_e − 1, 1 − 3r_e], [1 − 3r_e, r_e − 1]].
pub fn two_mode_eq25_as_printed(r_e: f64) -> DMatrix<f64> {
    DMatrix::from_row_slice(
        2,
        2,
        &[r_e - 1.0, 1.0 - 3.0 * r_e, 1.0 - 3.0 * r_e, r_e - 1.0],
    ) * 0.5
}

/// Equally spaced collocation points s_j = j/N, j = 1 … N − 1 (the default of §3.1).
pub fn equally_spaced_points(n: usize) -> Vec<f64> {
    (1..n).map(|j| j as f64 / n as f64).collect()
}

/// \[R\]_C of eq (12) with collocation points `points` (N − 1 distinct values in (0, 1)) and
/// the impact at s_I = 1: Φ⁻¹ diag(−1, …, −1, r) Φ, Φ's rows φ(s_j)ᵀ and φ(1)ᵀ.
///
/// # Errors
/// [`ParameterError`] for N out of 1…[`MAX_MODES`], r outside [0, 1], not N − 1 points, a
/// point outside (0, 1), repeated points, or points whose modal matrix is singular or has
/// condition above 1e12.
pub fn collocation(n: usize, r: f64, points: &[f64]) -> Result<DMatrix<f64>, ParameterError> {
    check(n, r)?;
    if points.len() != n - 1 {
        return Err(ParameterError::new(
            "collocation points",
            points.len(),
            &format!("exactly N − 1 = {} points", n - 1),
        ));
    }
    if let Some(s) = points
        .iter()
        .find(|s| !(s.is_finite() && **s > 0.0 && **s < 1.0))
    {
        return Err(ParameterError::new(
            "collocation point",
            s,
            "a number in (0, 1)",
        ));
    }
    let mut sorted = points.to_vec();
    sorted.sort_by(f64::total_cmp);
    if sorted.windows(2).any(|w| w[0] == w[1]) {
        return Err(ParameterError::new(
            "collocation points",
            format!("{points:?}"),
            "distinct points",
        ));
    }
    let modes: Vec<_> = (1..=n)
        .map(continuum::free_mode)
        .collect::<Result<_, _>>()?;
    let phi = DMatrix::from_fn(n, n, |row, j| {
        let s = if row + 1 == n { 1.0 } else { points[row] };
        modes[j].value(s)
    });
    let singular = || {
        ParameterError::new(
            "collocation points",
            format!("{points:?}"),
            "points giving a well-conditioned modal matrix (condition below 1e12)",
        )
    };
    let inv = phi.clone().try_inverse().ok_or_else(singular)?;
    if phi.amax() * inv.amax() * (n * n) as f64 > 1e12 {
        return Err(singular());
    }
    let mut d = DMatrix::from_element(n, n, 0.0);
    for i in 0..n {
        d[(i, i)] = if i + 1 == n { r } else { -1.0 };
    }
    Ok(inv * d * phi)
}

/// Post-impact modal velocities η̇⁺ = −\[R\]η̇⁻ (eq 11).
///
/// # Errors
/// [`ParameterError`] when \[R\] is not N × N for the N velocities given.
pub fn apply(
    r: &DMatrix<f64>,
    pre: &nalgebra::DVector<f64>,
) -> Result<nalgebra::DVector<f64>, ParameterError> {
    let n = pre.len();
    if r.nrows() != n || r.ncols() != n {
        return Err(ParameterError::new(
            "restitution law [R]",
            format!("{} × {} for {n} velocities", r.nrows(), r.ncols()),
            "an N × N matrix for N modal velocities",
        ));
    }
    Ok(-(r * pre))
}
