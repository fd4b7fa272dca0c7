//! Newton's method with step halving, for G(x) = 0 with an exact Jacobian: the one Newton
//! loop of the crate (shooting on the stroboscopic map and on the impact section use it).
//!
//! Each iteration solves DG·Δ = −G and tries x + λΔ for λ = 1, ½, ¼, …: a trial is taken
//! when its merit (‖G‖ or a residual of the caller's choosing) is below the current one, or
//! once λ < 1e-6 (a last small step rather than a stall). A trial whose evaluation fails (a
//! long step that loses an event, say) counts as a worse one and is halved. Converged when
//! the caller's residual is at most `tolerance`.

use crate::error::Error;
use nalgebra::{DMatrix, DVector};

/// One evaluation at x: G(x), its Jacobian DG(x), how good x is (`merit`, compared between
/// trials, and `residual`, compared with the tolerance), and what else the caller keeps
/// (the map's image, a count of events…).
#[derive(Debug, Clone)]
pub struct Evaluation<E> {
    /// G(x).
    pub g: DVector<f64>,
    /// DG(x).
    pub jacobian: DMatrix<f64>,
    /// What a step must decrease.
    pub merit: f64,
    /// What must fall to the tolerance.
    pub residual: f64,
    /// The caller's own data at x.
    pub extra: E,
}

/// The outcome of [`solve`].
#[derive(Debug, Clone)]
pub struct Converged<E> {
    /// The root.
    pub x: DVector<f64>,
    /// The evaluation at the root.
    pub at: Evaluation<E>,
    /// Newton steps taken.
    pub iterations: usize,
}

/// The smallest step fraction tried before a step is taken anyway.
const SMALLEST_STEP: f64 = 1e-6;

/// Solves G(x) = 0 from x0. `evaluate` gives G and DG at x; `project` maps a trial point
/// onto the set the unknowns live on (the identity for most problems). `what` names the
/// problem in the errors: no convergence within `max_iterations` steps (saying how close
/// it came), or a singular DG.
///
/// # Errors
/// `Error::NotConverged` (with the residual) when the residual is still above `tolerance`
/// after `max_iterations` steps or DG is singular; an error of `evaluate` at `x0`, or at a
/// trial step once it is below 1e-6 of a full step, is passed on.
pub fn solve<E>(
    x0: DVector<f64>,
    mut evaluate: impl FnMut(&DVector<f64>) -> Result<Evaluation<E>, Error>,
    project: impl Fn(DVector<f64>) -> DVector<f64>,
    tolerance: f64,
    max_iterations: usize,
    what: &str,
) -> Result<Converged<E>, Error> {
    let mut x = x0;
    let mut at = evaluate(&x)?;
    let mut iterations = 0;
    while at.residual > tolerance {
        if iterations == max_iterations {
            return Err(Error::NotConverged {
                message: format!(
                    "{what} did not converge in {max_iterations} Newton steps (residual \
                     {:.1e}); start closer to the orbit (more transient periods) or try \
                     another period",
                    at.residual
                ),
                residual: Some(at.residual),
            });
        }
        iterations += 1;
        let step =
            at.jacobian
                .clone()
                .lu()
                .solve(&(-&at.g))
                .ok_or_else(|| Error::NotConverged {
                    message: format!(
                        "{what}: the Jacobian is singular at Newton step {iterations} (a Floquet \
                     multiplier equals 1: a fold or a resonance)"
                    ),
                    residual: Some(at.residual),
                })?;
        let mut lambda = 1.0;
        loop {
            let trial = project(&x + &step * lambda);
            match evaluate(&trial) {
                Ok(e) if e.merit < at.merit || lambda < SMALLEST_STEP => {
                    (x, at) = (trial, e);
                    break;
                }
                Ok(_) => {}
                Err(e) if lambda < SMALLEST_STEP => return Err(e),
                Err(_) => {}
            }
            lambda *= 0.5;
        }
    }
    Ok(Converged { x, at, iterations })
}
