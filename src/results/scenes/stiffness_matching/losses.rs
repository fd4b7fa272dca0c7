//! The two-basis truncation's cost per switch: the energy and the L² fraction of the state
//! lost when the state is projected onto the other basis (§2.2, [`crate::engine::two_basis`]).

use super::MatchingParams;
use crate::analysis::convergence::{self, Setup};
use crate::error::Error;
use crate::model::galerkin::{self, Forcing, GalerkinParams};
use crate::analysis::convergence::two_basis_runs;
use crate::engine::two_basis::{Switch, TwoBasisModel};
use crate::base::verification::fitted_slope_with_error;
use rayon::prelude::*;
use serde::Serialize;

/// Losses at one (k, N).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Losses {
    /// k/k₁.
    pub k_over_k1: f64,
    /// N, the number of modes.
    pub modes: usize,
    /// One contact: relative energy lost entering contact (the pre-impact profile φ₁/2
    /// projected onto the constrained modes) …
    pub entry_energy: f64,
    /// … and leaving it.
    pub exit_energy: f64,
    /// The L² fraction of the velocity field lost leaving contact.
    pub exit_velocity_l2: f64,
    /// The forced run (ω of Figure 4, from rest): switches made …
    pub forced_switches: usize,
    /// … the mean relative energy lost per switch …
    pub forced_mean_energy: f64,
    /// … the largest …
    pub forced_max_energy: f64,
    /// … and the largest |tip jump| at a switch, relative to the free tip amplitude.
    pub forced_max_tip_jump: f64,
}

/// The order of the losses in N: the least-squares slope of log(loss) against log N over
/// the finest points with losses above round-off, with its standard error.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LossOrder {
    /// k/k₁.
    pub k_over_k1: f64,
    /// Slope of the one-contact entry energy loss against N (negative: it falls) …
    pub entry_energy: (f64, f64),
    /// … and of the forced run's mean loss per switch.
    pub forced_mean_energy: (f64, f64),
}

/// Losses for every k of `p` and every N of `p.loss_modes`.
///
/// # Errors
/// A two-basis model out of range (`Error::Parameter`) or that cannot be built
/// (`Error::Flow`, `Error::Unsupported`), a tip that does not leave the stop, or a run the
/// model refuses (`Error::Invariant`).
pub fn compute(p: &MatchingParams) -> Result<(Vec<Losses>, Vec<LossOrder>), Error> {
    let jobs: Vec<(f64, usize)> = p
        .k_over_k1
        .iter()
        .flat_map(|&k| p.loss_modes.iter().map(move |&n| (k, n)))
        .collect();
    let rows: Vec<Losses> = jobs
        .par_iter()
        .map(|&(k, n)| at(k, n, p))
        .collect::<Result<_, Error>>()?;
    let slope = |k: f64, f: fn(&Losses) -> f64| {
        // losses below 1e-13 are round-off, not truncation; fit the finest four above it
        let (x, y): (Vec<f64>, Vec<f64>) = rows
            .iter()
            .filter(|r| r.k_over_k1 == k && f(r) > 1e-13 && r.modes >= 4)
            .map(|r| ((r.modes as f64).ln(), f(r).ln()))
            .unzip();
        let take = x.len().min(4);
        (take >= 3).then(|| fitted_slope_with_error(&x[x.len() - take..], &y[y.len() - take..]))
    };
    let orders = p
        .k_over_k1
        .iter()
        .filter_map(|&k| {
            Some(LossOrder {
                k_over_k1: k,
                entry_energy: slope(k, |r| r.entry_energy)?,
                forced_mean_energy: slope(k, |r| r.forced_mean_energy)?,
            })
        })
        .collect();
    Ok((rows, orders))
}

fn at(k_over_k1: f64, n: usize, p: &MatchingParams) -> Result<Losses, Error> {
    let k = k_over_k1 * galerkin::first_modal_stiffness();
    let omega = p.omegas[0] * galerkin::first_frequency();
    let unforced = GalerkinParams::new(n, k).with_zeta1(p.zeta1);
    let forced = unforced.clone().with_forcing(Forcing::paper(omega));
    let (_, _, _, one) = two_basis_runs::one_contact(&TwoBasisModel::new(unforced)?)?;
    let energy = |entering: bool| {
        one.iter()
            .find(|s| s.entering == entering)
            .map_or(0.0, Switch::relative_energy_lost)
    };
    let exit_velocity_l2 = one.iter().find(|s| !s.entering).map_or(0.0, |s| s.velocity_lost);
    let (_, _, sw) = two_basis_runs::forced_from_rest(&TwoBasisModel::new(forced)?, p.periods)?;
    // the switch at t = 0 from rest has no energy to lose
    let moving: Vec<&Switch> = sw.iter().filter(|s| s.energy_before > 0.0).collect();
    let lost: Vec<f64> = moving.iter().map(|s| s.relative_energy_lost()).collect();
    let setup = Setup {
        k_over_k1,
        zeta1: p.zeta1,
        omega_over_w1: p.omegas[0],
        periods: p.periods,
    };
    let (amplitude, _) = convergence::free_amplitude(&setup)?;
    Ok(Losses {
        k_over_k1,
        modes: n,
        entry_energy: energy(true),
        exit_energy: energy(false),
        exit_velocity_l2,
        forced_switches: sw.len(),
        forced_mean_energy: lost.iter().sum::<f64>() / lost.len().max(1) as f64,
        forced_max_energy: lost.iter().copied().fold(0.0, f64::max),
        forced_max_tip_jump: sw.iter().map(|s| s.tip_jump.abs()).fold(0.0, f64::max) / amplitude,
    })
}
