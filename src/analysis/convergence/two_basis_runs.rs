//! The two-basis model's experiments: the one contact and the forced run of the refinement
//! studies ([`super`]), and the settling to a periodic orbit.

use super::PeriodicObservables;
use crate::analysis::orbit::{self, OrbitKind};
use crate::engine::map::PeriodMap;
use crate::engine::sim::Clock;
use crate::engine::two_basis::{Switch, TwoBasisModel};
use crate::error::Error;
use crate::model::galerkin::Region;
use nalgebra::DVector;

/// The one-contact experiment of [`crate::analysis::convergence`] on the two-basis model: the beam
/// at rest, undeflected, with the velocity profile ½φ₁ (tip velocity 1 into the stop at
/// d₀ = 0), until the tip first leaves the stop. Returns the contact duration, the exit tip
/// velocity (in the constrained basis, before the switch), the state after the switch (free
/// basis) and the switches (entry at t = 0 and the exit).
///
/// # Errors
/// [`Error::Unsupported`] when the tip has not left the stop within four time units; the
/// errors of [`TwoBasisModel::run_switches`] ([`Error::Invariant`]).
pub fn one_contact(model: &TwoBasisModel) -> Result<(f64, f64, DVector<f64>, Vec<Switch>), Error> {
    let n = model.modes();
    let mut x = DVector::zeros(2 * n);
    x[n] = 0.5;
    let (state, entry) = model.start(&x, 0.0);
    let mut switches: Vec<Switch> = entry.into_iter().collect();
    // unforced: one bookkeeping "period" is one time unit, far longer than the contact
    let period = model.period();
    let exits_before = usize::from(state.region == Region::Free);
    let run = model.run_switches(
        state,
        Clock::at_cycle(period, 0),
        Clock::at_cycle(period, 4),
        1 + exits_before,
    )?;
    switches.extend(run.switches);
    match switches.iter().find(|s| !s.entering) {
        Some(exit) if run.state.region == Region::Free => {
            Ok((exit.time, exit.tip_velocity, run.state.x, switches))
        }
        _ => Err(Error::Unsupported(
            "the tip did not leave the stop within four time units".into(),
        )),
    }
}

/// Tip displacement and velocity after `periods` forcing periods from rest (x⁺(0) = 0 in
/// the region the start rule gives), and the switches on the way.
///
/// # Errors
/// The errors of [`TwoBasisModel::run_until`] ([`Error::Invariant`] when a projection leaves
/// the state beyond the surface in both bases).
pub fn forced_from_rest(
    model: &TwoBasisModel,
    periods: u64,
) -> Result<(f64, f64, Vec<Switch>), Error> {
    let n = model.modes();
    let (state, first) = model.start(&DVector::zeros(2 * n), 0.0);
    let period = model.period();
    let run = model.run_until(
        state,
        Clock::at_cycle(period, 0),
        Clock::at_cycle(period, periods as i64),
    )?;
    let (d, v) = model.tip(&run.state);
    let mut switches: Vec<Switch> = first.into_iter().collect();
    switches.extend(run.switches);
    Ok((d, v, switches))
}

/// The forced run from rest continued until its stroboscopic samples repeat (§5.2's test,
/// relative to the state; samples in different bases never match): the one settle of
/// every model ([`orbit::settle_until_periodic`]), `chunk` periods at a time, a `window`
/// of samples, at most `max` periods in all.
///
/// # Errors
/// The errors of [`orbit::settle_until_periodic`] ([`Error::Invariant`]); an orbit that does
/// not settle within `max` is not an error.
pub fn settle(
    model: &TwoBasisModel,
    chunk: u64,
    window: u64,
    max: u64,
) -> Result<PeriodicObservables, Error> {
    let (o, discarded) = orbit::settle_until_periodic(model, &model.rest(), chunk, window, max)?;
    let periodic = o.kind != OrbitKind::NotPeriodic;
    Ok(PeriodicObservables {
        kind: o.kind,
        impact_velocity: if periodic {
            o.orbit_entry_velocities()
                .iter()
                .fold(f64::NAN, |a, &b| a.max(b))
        } else {
            f64::NAN
        },
        max_tip: None,
        transient: discarded + if periodic { 0 } else { window },
    })
}
