//! Periodic orbits by Newton shooting on the impact section Σ = {d = d₀, ḋ > 0} (§5.3's
//! section of Figure 5), the alternative to the stroboscopic formulation of
//! [`crate::analysis::shooting`].
//!
//! **The return map.** From a state x on Σ at time t₀, the flow runs to the n-th entry
//! into contact after t₀, at time tₙ in state xₙ ∈ Σ. A period-m orbit with n contacts
//! solves G(x, t₀) = (xₙ − x, tₙ − t₀ − mT) = 0: 2N + 1 equations in 2N + 1 unknowns (the
//! impact's phase is an unknown; x is kept on Σ by projecting each Newton iterate onto it).
//!
//! **The exact Jacobian.** With Φ the product of the segments' exponentials from t₀ to tₙ
//! (the saltation at intermediate switches is I, [`crate::analysis::shooting`]), f the vector field
//! (continuous across Σ), ∇g = [φ(1); 0] and c = ∇gᵀf(xₙ, tₙ) > 0 the tip velocity at
//! the impact, the time-of-flight correction at the final crossing gives
//!
//! ```text
//! ∂xₙ/∂x = PΦ,   ∂xₙ/∂t₀ = −PΦf₀,   ∂tₙ/∂x = −∇gᵀΦ/c,   ∂tₙ/∂t₀ = ∇gᵀΦf₀/c,
//! P = I − f(xₙ, tₙ)∇gᵀ/c,   f₀ = f(x, t₀)
//! ```
//!
//! (a later start with the same state is, to first order, the same state shifted back
//! along the flow: ∂x(t)/∂t₀ = −Φ(t, t₀)f₀).
//!
//! **Multipliers.** On the orbit the flow direction (f₀, 1) is mapped to zero, so the
//! (2N + 1)-square Jacobian J has one eigenvalue 0; the other 2N are the orbit's Floquet
//! multipliers — the same as the stroboscopic map's, which the tests check (two
//! independent formulations of one orbit).

use crate::analysis::shooting::Monodromy;
use crate::engine::flow::eigen_balanced;
use crate::engine::sim::{Clock, Events, Simulator};
use crate::error::Error;
use crate::model::galerkin::Region;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Relative residual at which Newton stops (as for the stroboscopic map).
pub const TOLERANCE: f64 = crate::analysis::shooting::TOLERANCE;

/// An orbit found on the impact section.
#[derive(Debug, Clone, Serialize)]
pub struct SectionOrbit {
    /// The state at an entry into contact (on Σ).
    pub state: Vec<f64>,
    /// The entry's phase: its time after the start of a forcing period, in [0, T).
    pub phase_time: f64,
    /// m: forcing periods per orbit period.
    pub period_m: u64,
    /// n: entries into contact per period.
    pub impacts_n: usize,
    /// Floquet multipliers as [re, im], largest modulus first (the trivial 0 of the flow
    /// direction removed).
    pub multipliers: Vec<[f64; 2]>,
    /// All multipliers inside the unit circle.
    pub stable: bool,
    /// max(‖xₙ − x‖∞/‖x‖∞, |tₙ − t₀ − mT|/T).
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// The vector field in free flight, [η̇; −Kη − Cη̇ + F(t)] (continuous across Σ).
fn field(sim: &Simulator, x: &DVector<f64>, t: f64) -> DVector<f64> {
    let model = sim.model();
    let n = model.modes();
    let mut f = model.state_matrix(Region::Free) * x;
    let force = model.force(t, Region::Free);
    for j in 0..n {
        f[n + j] += force[j];
    }
    f
}

/// x with its displacement moved along φ(1) onto Σ.
fn onto_section(sim: &Simulator, x: &DVector<f64>) -> DVector<f64> {
    let model = sim.model();
    let n = model.modes();
    let tip = model.tip();
    let g = model.switching_function(&x.rows(0, n).into_owned());
    let mut y = x.clone();
    let shift = tip * (g / tip.norm_squared());
    for j in 0..n {
        y[j] -= shift[j];
    }
    y
}

/// One return: the state and clock of the n-th entry after (x, start), and the Jacobian
/// of (xₙ, tₙ) with respect to (x, t₀).
fn return_map(
    sim: &Simulator,
    x: &DVector<f64>,
    start: Clock,
    n: usize,
    horizon: i64,
) -> Result<(DVector<f64>, Clock, DMatrix<f64>), Error> {
    let period = sim.period();
    let end = Clock {
        cycles: start.cycles + horizon,
        ..start
    };
    let mut events = Events::default();
    sim.run_until(x, start, end, &mut events)?;
    // entries strictly after the start: a start a round-off outside Σ enters within
    // ~1e-16 T; a genuine next entry comes after a whole contact and a free flight, far
    // longer than 1e-9 T unless the orbit grazes (where the section is not transversal
    // and this formulation does not apply)
    let after = |c: &Clock| {
        (c.cycles - start.cycles) as f64 * period + (c.offset - start.offset) > 1e-9 * period
    };
    let entry = events
        .events
        .iter()
        .filter(|e| e.entering && !e.grazing && after(&e.clock))
        .nth(n - 1)
        .map(|e| e.clock)
        .ok_or_else(|| {
            Error::Unsupported(format!(
                "no {n}-th entry into contact within {horizon} periods of the start on the impact section"
            ))
        })?;
    let mut mono = Monodromy::default();
    let xn = sim.run_until(x, start, entry, &mut mono)?.state;
    let dim = x.len();
    let phi = mono.matrix.unwrap_or_else(|| DMatrix::identity(dim, dim));
    let modes = dim / 2;
    let mut grad = DVector::zeros(dim);
    grad.rows_mut(0, modes).copy_from(sim.model().tip());
    let (f0, fn_) = (field(sim, x, start.time()), field(sim, &xn, entry.time()));
    let c = grad.dot(&fn_);
    let p = DMatrix::identity(dim, dim) - &fn_ * grad.transpose() / c;
    let pphi = &p * &phi;
    let gphi = grad.transpose() * &phi / c; // 1 × dim
    let mut j = DMatrix::zeros(dim + 1, dim + 1);
    j.view_mut((0, 0), (dim, dim)).copy_from(&pphi);
    j.view_mut((0, dim), (dim, 1)).copy_from(&(-&pphi * &f0));
    j.view_mut((dim, 0), (1, dim)).copy_from(&(-&gphi));
    j[(dim, dim)] = (&gphi * &f0)[0];
    Ok((xn, entry, j))
}

/// Newton shooting on the impact section for an orbit with n entries per period, from a
/// state `x0` at an entry into contact at clock `start` (from a transient's events, say).
/// The period m is read from the first return. Fails with [`Error::Unsupported`] when
/// Newton does not reach [`TOLERANCE`] in `max_iterations` steps.
pub fn shoot(
    sim: &Simulator,
    x0: &DVector<f64>,
    start: Clock,
    n: usize,
    max_iterations: usize,
) -> Result<SectionOrbit, Error> {
    if n == 0 {
        return Err(Error::Unsupported(
            "an orbit on the impact section has at least one entry into contact".into(),
        ));
    }
    let period = sim.period();
    let dim = x0.len();
    // the n-th entry of an orbit of period m ≤ 32 (the longest [`crate::analysis::orbit`] labels)
    // comes within m periods; twice that leaves room for a guess off the orbit
    let horizon = 64;
    let mut x = onto_section(sim, x0);
    let mut t0 = Clock::at_time(period, start.offset);
    let (mut xn, mut tn, mut jac) = return_map(sim, &x, t0, n, horizon)?;
    let elapsed =
        |a: &Clock, b: &Clock| (b.cycles - a.cycles) as f64 * period + (b.offset - a.offset);
    let m = (elapsed(&t0, &tn) / period).round().max(1.0);
    let residual = |x: &DVector<f64>, xn: &DVector<f64>, t0: &Clock, tn: &Clock| {
        let dx = (xn - x).amax() / x.amax().max(xn.amax());
        let dt = (elapsed(t0, tn) - m * period).abs() / period;
        dx.max(dt)
    };
    let mut r = residual(&x, &xn, &t0, &tn);
    let mut iterations = 0;
    while r > TOLERANCE {
        if iterations == max_iterations {
            return Err(Error::Unsupported(format!(
                "shooting on the impact section did not converge in {max_iterations} Newton steps (residual {r:.1e})"
            )));
        }
        iterations += 1;
        let mut g = DVector::zeros(dim + 1);
        g.rows_mut(0, dim).copy_from(&(&xn - &x));
        g[dim] = elapsed(&t0, &tn) - m * period;
        let dg = &jac - DMatrix::identity(dim + 1, dim + 1);
        let step = dg.lu().solve(&(-&g)).ok_or_else(|| {
            Error::Unsupported(
                "the impact-section Jacobian J − I is singular (a multiplier equals 1)".into(),
            )
        })?;
        let mut lambda = 1.0;
        loop {
            let trial_x = onto_section(sim, &(&x + step.rows(0, dim) * lambda));
            let trial_t = Clock::at_time(period, t0.offset + step[dim] * lambda);
            match return_map(sim, &trial_x, trial_t, n, horizon) {
                Ok((x2, t2, j2)) => {
                    let r2 = residual(&trial_x, &x2, &trial_t, &t2);
                    if r2 < r || lambda < 1e-6 {
                        (x, t0, xn, tn, jac, r) = (trial_x, trial_t, x2, t2, j2, r2);
                        break;
                    }
                }
                // a step too long can lose an entry (a grazing passed): shorten it
                Err(e) if lambda < 1e-6 => return Err(e),
                Err(_) => {}
            }
            lambda *= 0.5;
        }
    }
    let (values, _) = eigen_balanced(&jac)?;
    let mut values: Vec<_> = values.into_iter().collect();
    values.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    // the flow direction's eigenvalue 0 (to round-off) is not a multiplier: the smallest
    // is dropped (multipliers of heavily damped modes can be as small, and are then as
    // good as 0 themselves)
    values.pop();
    Ok(SectionOrbit {
        state: x.as_slice().to_vec(),
        phase_time: t0.offset,
        period_m: m as u64,
        impacts_n: n,
        stable: values.iter().all(|z| z.norm() < 1.0),
        multipliers: values.iter().map(|z| [z.re, z.im]).collect(),
        residual: r,
        iterations,
    })
}
