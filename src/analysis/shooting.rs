//! Periodic orbits of the compliant model by Newton shooting on the stroboscopic map, with
//! their Floquet multipliers (§5.2–5.3).
//!
//! **The exact Jacobian.** Within a region the flow is affine in the state,
//! x(s) = Φ(s)(x₀ − x_p(0)) + x_p(s) with Φ(s) = e^{A^± s} ([`crate::engine::flow`]), so a segment's
//! Jacobian is Φ(s) itself, evaluated in closed form (the columns Φ(s)e_i, no difference
//! quotient). At a switch the Jacobian picks up the saltation matrix
//!
//! ```text
//! S = I + (f⁺ − f⁻) ∇gᵀ / (∇gᵀ f⁻),   f⁺ − f⁻ = [0; −(k/4)φ(1)(φ(1)ᵀη − d₀)],
//! ```
//!
//! and f⁺ − f⁻ vanishes on the switching surface φ(1)ᵀη = d₀: the stop force is continuous
//! (the model is bilinear, not impacting), so S = I and the monodromy matrix of m periods is
//! the plain product of the segments' exponentials. (The rigid-impact model's saltation is
//! not the identity; it is not handled here.) The Jacobian is checked against central
//! differences in the tests.
//!
//! **Newton.** G(x) = P^m(x) − x, DG = M − I with M the monodromy; a step is halved (up to
//! 20 times) until ‖G‖ decreases. Converged when ‖G‖∞ ≤ 1e-12·‖x‖∞ (relative, §5.2's test
//! on the orbit's own scale).
//!
//! **Floquet multipliers** are the eigenvalues of M. M is a product of segment maps; its
//! entries can span many orders of magnitude when high modes are heavily damped, so the
//! eigenvalues are computed from M balanced (Parlett–Reinsch, [`crate::engine::flow::eigen_balanced`]).
//! Their accuracy is measured, not assumed: the leading multiplier is compared against the
//! decay rate of a transient started near the orbit (tests).

use crate::base::newton::{self, Evaluation};
use crate::engine::flow::eigenvalues_balanced;
use crate::engine::map::{relative_residual, PeriodMap};
pub use crate::engine::sim::Monodromy;
use crate::error::{Error, ParameterError};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use serde::Serialize;

/// Relative residual ‖P^m(x) − x‖∞/‖x‖∞ at which Newton stops.
pub const TOLERANCE: f64 = 1e-12;

/// Newton iterations allowed.
pub const MAX_ITERATIONS: usize = 40;

/// P^m(x) from the start of cycle 0, with its monodromy and the entries into contact
/// ([`PeriodMap::map_with_jacobian`]).
///
/// # Errors
/// Those of the model's [`PeriodMap::map_with_jacobian`]: [`Error::Unsupported`] for a model
/// without a Jacobian, [`Error::Parameter`] for a bad state, or a run that fails.
pub fn map_with_jacobian<M: PeriodMap + ?Sized>(
    model: &M,
    x: &DVector<f64>,
    m: u64,
) -> Result<(DVector<f64>, DMatrix<f64>, usize), Error> {
    let (px, mono, entries) = model.map_with_jacobian(x, m)?;
    Ok((px, mono, entries as usize))
}

/// Where an orbit's state is taken.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Section {
    /// At the start of a forcing period (ωt = 0 mod 2π): the stroboscopic map.
    Stroboscopic,
    /// At an entry into contact, d = d₀ with ḋ > 0 ([`crate::analysis::impact_section`]).
    Impact {
        /// The entry's time after the start of its forcing period, in [0, T).
        phase_time: f64,
    },
}

/// A periodic orbit found by shooting, of any model with a Jacobian.
#[derive(Debug, Clone, Serialize)]
pub struct PeriodicOrbit {
    /// The state [η; η̇] on the orbit, taken on `section`.
    pub state: Vec<f64>,
    /// Where the state is taken.
    pub section: Section,
    /// m: forcing periods per orbit period (the least: an orbit of period d | m found
    /// while asking for m is reported at d).
    pub period_m: u64,
    /// n: entries into contact (impacts, for the rigid model) per orbit period.
    pub impacts_n: usize,
    /// Floquet multipliers (eigenvalues of the monodromy) as [re, im], largest modulus
    /// first.
    pub multipliers: Vec<[f64; 2]>,
    /// All multipliers inside the unit circle.
    pub stable: bool,
    /// The final relative residual ‖P^m(x) − x‖∞/‖x‖∞.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

impl PeriodicOrbit {
    /// The largest multiplier modulus.
    pub fn spectral_radius(&self) -> f64 {
        self.multipliers.first().map_or(0.0, |z| z[0].hypot(z[1]))
    }

    /// The state as a vector.
    pub fn state_vector(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.state)
    }

    /// The multipliers as complex numbers, largest modulus first.
    pub fn multipliers_complex(&self) -> Vec<Complex64> {
        self.multipliers
            .iter()
            .map(|z| Complex64::new(z[0], z[1]))
            .collect()
    }
}

/// A period d < m is the orbit's least period when P^d(x) returns to x to this relative
/// distance (Newton on P^m converges to a period-d orbit too when d divides m). An orbit
/// converged to [`TOLERANCE`] returns to ~1e-12; the distinct strobe points of a genuine
/// period-m orbit are O(1) of its size apart (≥ 1.3e-2 over the whole atlas), so 1e-6
/// separates the two with six decades on either side.
pub const LEAST_PERIOD: f64 = 1e-6;

/// Newton shooting for a period-m orbit from the guess `x0` (a state at the start of a
/// forcing period), reported at its least period.
///
/// # Errors
/// [`Error::NotConverged`] when Newton does not reach [`TOLERANCE`] in [`MAX_ITERATIONS`]
/// (a guess outside the orbit's basin of convergence, or a period m that does not exist
/// there), saying how close it came; [`Error::Parameter`] for a guess of the wrong length
/// or not finite, or m outside 1 to 64; [`Error::Unsupported`] for a model without a
/// Jacobian; [`Error::Chatter`] for a run the model cannot continue.
pub fn shoot<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    m: u64,
) -> Result<PeriodicOrbit, Error> {
    shoot_within(model, x0, m, MAX_ITERATIONS)
}

/// [`shoot`] with at most `max_iterations` Newton steps (a sweep that tries many guesses
/// gives up early on those that do not converge fast: from a guess near the orbit, Newton
/// converges quadratically in a few steps).
///
/// # Errors
/// As [`shoot`], with `max_iterations` in place of [`MAX_ITERATIONS`].
pub fn shoot_within<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    m: u64,
    max_iterations: usize,
) -> Result<PeriodicOrbit, Error> {
    if !(1..=64).contains(&m) {
        return Err(ParameterError::new("orbit period m", m, "an integer from 1 to 64").into());
    }
    model.check_state("shooting guess", x0)?;
    let orbit = newton(model, x0, m, max_iterations)?;
    // reduce to the least period: the smallest divisor d of m with P^d(x) = x
    let x = orbit.state_vector();
    for d in (1..m).filter(|&d| m.is_multiple_of(d)) {
        let pd = model.advance(&x, 0, d, false)?.state;
        if relative_residual(&pd, &x) < LEAST_PERIOD {
            return newton(model, &x, d, max_iterations);
        }
    }
    Ok(orbit)
}

/// [`shoot_within`] at exactly period m, without the reduction to the least period: for
/// continuation along a period-m branch, whose points near a period doubling come close to
/// the period-m/2 orbit they branch from and must still be computed at m.
///
/// # Errors
/// As [`shoot_within`].
pub fn shoot_at_period<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    m: u64,
    max_iterations: usize,
) -> Result<PeriodicOrbit, Error> {
    if !(1..=64).contains(&m) {
        return Err(ParameterError::new("orbit period m", m, "an integer from 1 to 64").into());
    }
    model.check_state("shooting guess", x0)?;
    newton(model, x0, m, max_iterations)
}

/// Newton on G(x) = P^m(x) − x with DG = M − I (M the monodromy), and the multipliers.
fn newton<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    m: u64,
    max_iterations: usize,
) -> Result<PeriodicOrbit, Error> {
    let dim = x0.len();
    let evaluate = |x: &DVector<f64>| -> Result<Evaluation<(DMatrix<f64>, u64)>, Error> {
        let (px, mono, n) = model.map_with_jacobian(x, m)?;
        let g = &px - x;
        Ok(Evaluation {
            merit: g.amax(),
            residual: relative_residual(&px, x),
            jacobian: &mono - DMatrix::identity(dim, dim),
            g,
            extra: (mono, n),
        })
    };
    let what = format!("shooting for a period-{m} orbit of {}", model.name());
    let done = newton::solve(
        x0.clone(),
        evaluate,
        |x| x,
        TOLERANCE,
        max_iterations,
        &what,
    )?;
    let (mono, n) = done.at.extra;
    let mut multipliers = floquet(&mono)?;
    multipliers.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    Ok(PeriodicOrbit {
        state: done.x.as_slice().to_vec(),
        section: Section::Stroboscopic,
        period_m: m,
        impacts_n: n as usize,
        stable: multipliers.iter().all(|z| z.norm() < 1.0),
        multipliers: multipliers.iter().map(|z| [z.re, z.im]).collect(),
        residual: done.at.residual,
        iterations: done.iterations,
    })
}

/// The eigenvalues of a monodromy matrix.
///
/// # Errors
/// [`Error::Parameter`] for a matrix that is not square or has an entry that is not
/// finite; [`Error::Flow`] when the eigensolver does not converge.
pub fn floquet(m: &DMatrix<f64>) -> Result<Vec<Complex64>, Error> {
    if m.nrows() != m.ncols() {
        return Err(ParameterError::new(
            "monodromy matrix",
            format!("{} × {}", m.nrows(), m.ncols()),
            "a square matrix",
        )
        .into());
    }
    if m.iter().any(|v| !v.is_finite()) {
        return Err(ParameterError::new(
            "monodromy matrix",
            "an entry that is not finite",
            "finite entries",
        )
        .into());
    }
    Ok(eigenvalues_balanced(m)?)
}
