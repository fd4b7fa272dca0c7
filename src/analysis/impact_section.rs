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

use crate::analysis::shooting::{Monodromy, PeriodicOrbit, Section};
use crate::base::newton::{self, Evaluation};
use crate::engine::flow::eigenvalues_balanced;
use crate::engine::map::PeriodMap;
use crate::engine::sim::{Clock, Events, Simulator};
use crate::error::Error;
use crate::model::galerkin::Region;
use nalgebra::{DMatrix, DVector};

/// Relative residual at which Newton stops (as for the stroboscopic map).
pub const TOLERANCE: f64 = crate::analysis::shooting::TOLERANCE;

/// The vector field in free flight, [η̇; −Kη − Cη̇ + F(t)] (continuous across Σ).
fn field(sim: &Simulator, x: &DVector<f64>, t: f64) -> DVector<f64> {
    sim.model().field(x, t, Region::Free)
}

/// x with its displacement moved along φ(1) onto Σ.
fn onto_section(sim: &Simulator, x: &DVector<f64>) -> DVector<f64> {
    let model = sim.model();
    let n = model.modes();
    let tip = model.tip();
    let g = model.gap_of(x.rows(0, n));
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
            Error::NoPeriod(format!(
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
/// The period m is read from the first return. Fails with [`Error::NotConverged`] when
/// Newton does not reach [`TOLERANCE`] in `max_iterations` steps.
///
/// # Errors
/// [`Error::Parameter`] for n = 0 or a bad `x0`; [`Error::NoPeriod`] when the n-th entry does
/// not come within 64 periods; [`Error::NotConverged`]; [`Error::Flow`] when the multipliers'
/// eigensolver fails; a run's [`Error::Chatter`] or [`Error::Invariant`].
pub fn shoot(
    sim: &Simulator,
    x0: &DVector<f64>,
    start: Clock,
    n: usize,
    max_iterations: usize,
) -> Result<PeriodicOrbit, Error> {
    if n == 0 {
        return Err(crate::error::ParameterError::new(
            "entries per period n",
            n,
            "at least one (an orbit on the impact section has an entry into contact)",
        )
        .into());
    }
    sim.check_state("shooting guess", x0)?;
    let period = sim.period();
    let dim = x0.len();
    // the n-th entry of an orbit of period m ≤ 32 (the longest [`crate::analysis::orbit`]
    // labels) comes within m periods; twice that leaves room for a guess off the orbit
    let horizon = 64;
    let elapsed =
        |a: &Clock, b: &Clock| (b.cycles - a.cycles) as f64 * period + (b.offset - a.offset);
    // the unknowns: the state on Σ and the entry's time in the period, z = (x, t₀)
    let x = onto_section(sim, x0);
    let t0 = Clock::at_time(period, start.offset);
    let (_, tn, _) = return_map(sim, &x, t0, n, horizon)?;
    let m = (elapsed(&t0, &tn) / period).round().max(1.0);
    let evaluate = |z: &DVector<f64>| -> Result<Evaluation<DMatrix<f64>>, Error> {
        let x = z.rows(0, dim).into_owned();
        let t0 = Clock::at_time(period, z[dim]);
        let (xn, tn, jac) = return_map(sim, &x, t0, n, horizon)?;
        let mut g = DVector::zeros(dim + 1);
        g.rows_mut(0, dim).copy_from(&(&xn - &x));
        g[dim] = elapsed(&t0, &tn) - m * period;
        let dx = (&xn - &x).amax() / x.amax().max(xn.amax());
        let residual = dx.max(g[dim].abs() / period);
        Ok(Evaluation {
            g,
            jacobian: &jac - DMatrix::identity(dim + 1, dim + 1),
            merit: residual,
            residual,
            extra: jac,
        })
    };
    // keep x on Σ and t₀ in [0, T)
    let project = |z: DVector<f64>| {
        let mut y = z.clone();
        y.rows_mut(0, dim)
            .copy_from(&onto_section(sim, &z.rows(0, dim).into_owned()));
        y[dim] = Clock::at_time(period, z[dim]).offset;
        y
    };
    let mut z0 = DVector::zeros(dim + 1);
    z0.rows_mut(0, dim).copy_from(&x);
    z0[dim] = t0.offset;
    let done = newton::solve(
        z0,
        evaluate,
        project,
        TOLERANCE,
        max_iterations,
        "shooting on the impact section",
    )?;
    let values = eigenvalues_balanced(&done.at.extra)?;
    let mut values: Vec<_> = values.into_iter().collect();
    values.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    // the flow direction's eigenvalue 0 (to round-off) is not a multiplier: the smallest
    // is dropped (multipliers of heavily damped modes can be as small, and are then as
    // good as 0 themselves)
    values.pop();
    Ok(PeriodicOrbit {
        state: done.x.rows(0, dim).iter().copied().collect(),
        section: Section::Impact {
            phase_time: done.x[dim],
        },
        period_m: m as u64,
        impacts_n: n,
        stable: values.iter().all(|z| z.norm() < 1.0),
        multipliers: values.iter().map(|z| [z.re, z.im]).collect(),
        residual: done.at.residual,
        iterations: done.iterations,
    })
}
