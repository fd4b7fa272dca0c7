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

use crate::analysis::orbit::relative_residual;
use crate::engine::flow::eigen_balanced;
pub use crate::engine::sim::Monodromy;
use crate::engine::sim::{Events, Simulator};
use crate::error::Error;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use serde::Serialize;

/// Relative residual ‖P^m(x) − x‖∞/‖x‖∞ at which Newton stops.
pub const TOLERANCE: f64 = 1e-12;

/// Newton iterations allowed.
pub const MAX_ITERATIONS: usize = 40;

/// P^m(x) from the start of cycle 0, with its monodromy and the entries into contact.
pub fn map_with_jacobian(
    sim: &Simulator,
    x: &DVector<f64>,
    m: u64,
) -> Result<(DVector<f64>, DMatrix<f64>, usize), Error> {
    let (mut mono, mut events) = (Monodromy::default(), Events::default());
    let end = sim.run(x, m, &mut (&mut mono, &mut events))?;
    let entries = events
        .events
        .iter()
        .filter(|e| e.entering && !e.grazing)
        .count();
    let dim = x.len();
    Ok((
        end.state,
        mono.matrix.unwrap_or_else(|| DMatrix::identity(dim, dim)),
        entries,
    ))
}

/// A periodic orbit found by shooting.
#[derive(Debug, Clone, Serialize)]
pub struct PeriodicOrbit {
    /// The state [η; η̇] at the start of a forcing period on the orbit.
    pub state: Vec<f64>,
    /// m: forcing periods per orbit period.
    pub period_m: u64,
    /// n: entries into contact per orbit period.
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
}

/// Newton shooting for a period-m orbit from the guess `x0` (a state at the start of a
/// forcing period). Fails with [`Error::Unsupported`] when Newton does not reach
/// [`TOLERANCE`] in [`MAX_ITERATIONS`] (a guess outside the orbit's basin of convergence,
/// or a period m that does not exist there), saying how close it came.
pub fn shoot(sim: &Simulator, x0: &DVector<f64>, m: u64) -> Result<PeriodicOrbit, Error> {
    shoot_within(sim, x0, m, MAX_ITERATIONS)
}

/// [`shoot`] with at most `max_iterations` Newton steps (a sweep that tries many guesses
/// gives up early on those that do not converge fast: from a guess near the orbit, Newton
/// converges quadratically in a few steps).
pub fn shoot_within(
    sim: &Simulator,
    x0: &DVector<f64>,
    m: u64,
    max_iterations: usize,
) -> Result<PeriodicOrbit, Error> {
    if m == 0 {
        return Err(Error::Unsupported(
            "the orbit period m must be at least 1".into(),
        ));
    }
    let dim = x0.len();
    let mut x = x0.clone();
    let (mut px, mut mono, mut n) = map_with_jacobian(sim, &x, m)?;
    let mut r = relative_residual(&px, &x);
    let mut iterations = 0;
    while r > TOLERANCE {
        if iterations == max_iterations {
            return Err(Error::Unsupported(format!(
                "shooting for a period-{m} orbit did not converge in {max_iterations} Newton steps (residual {r:.1e}); start closer to the orbit (more transient periods) or try another m"
            )));
        }
        iterations += 1;
        let g = &px - &x;
        let dg = &mono - DMatrix::identity(dim, dim);
        let step = dg.lu().solve(&(-&g)).ok_or_else(|| {
            Error::Unsupported(format!(
                "the shooting Jacobian M − I is singular at iteration {iterations}: a multiplier equals 1 (a fold or a period-m resonance)"
            ))
        })?;
        let norm = g.amax();
        let mut lambda = 1.0;
        loop {
            let trial = &x + &step * lambda;
            let (p2, m2, n2) = map_with_jacobian(sim, &trial, m)?;
            if (&p2 - &trial).amax() < norm || lambda < 1e-6 {
                x = trial;
                (px, mono, n) = (p2, m2, n2);
                break;
            }
            lambda *= 0.5;
        }
        r = relative_residual(&px, &x);
    }
    let mut multipliers = floquet(&mono)?;
    multipliers.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    let stable = multipliers.iter().all(|z| z.norm() < 1.0);
    Ok(PeriodicOrbit {
        state: x.as_slice().to_vec(),
        period_m: m,
        impacts_n: n,
        multipliers: multipliers.iter().map(|z| [z.re, z.im]).collect(),
        stable,
        residual: r,
        iterations,
    })
}

/// The eigenvalues of a monodromy matrix.
pub fn floquet(m: &DMatrix<f64>) -> Result<Vec<Complex64>, Error> {
    Ok(eigen_balanced(m)?.0)
}
