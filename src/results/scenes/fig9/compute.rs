//! Figure 9's computation: the primary orbit with its exact spectrum, the convergence in N,
//! and the scans of the contact count.

use super::{Count, Fig9Data, Fig9Params, Peak, ScanPoint};
use crate::error::Error;
use crate::analysis::harmonics::TipHarmonics;
use crate::base::numerics::polar;
use crate::analysis::orbit::{self, OrbitKind, Settled};
use crate::model::problems::{self, Forced};
use crate::results::scene::Progress;
use crate::engine::sim::{Dense, Simulator};
use nalgebra::DVector;
use num_complex::Complex64;
use rayon::prelude::*;

/// The model at N modes, stop stiffness k/k₁, ω/(β₁⁻)², with d₀ = `gap_over_free` times the
/// free tip amplitude at ω (d₀ itself for the primary reading d₀ = 0).
fn forced(p: &Fig9Params, modes: usize, k: f64, omega: f64, gap_over_free: f64) -> Result<Forced, Error> {
    Ok(Forced {
        k_over_k1: k,
        zeta1: p.zeta1,
        omega_over_w1: omega,
        ..problems::figure9(modes, 0.0)
    }
    .with_gap_over_free(gap_over_free)?)
}

/// The orbit after its transient, with the periods discarded.
fn settle(sim: &Simulator, p: &Fig9Params, max: u64) -> Result<(Settled, u64), Error> {
    let n = sim.model().modes();
    orbit::settle_until_periodic(sim, &DVector::zeros(2 * n), p.chunk, p.window, max)
}

/// Counts contact intervals and sampled penetration maxima per forcing period on the
/// settled orbit.
fn count_contacts(sim: &Simulator, p: &Fig9Params, max: u64) -> Result<(Count, Settled, u64), Error> {
    let (o, discarded) = settle(sim, p, max)?;
    let (intervals, maxima) = match o.kind {
        OrbitKind::Periodic { m, n } => {
            let cycle = (discarded + p.window) as i64;
            let mut dense = Dense::new(p.samples_per_period);
            sim.run_from(&o.state, sim.clock_at_cycle(cycle), m, &mut dense)?;
            let maxima = dense
                .samples
                .windows(3)
                .filter(|w| w.iter().all(|s| s.3) && w[1].1 > w[0].1 && w[1].1 >= w[2].1)
                .count();
            (Some(n as f64 / m as f64), Some(maxima as f64 / m as f64))
        }
        OrbitKind::NotPeriodic => (None, None),
    };
    Ok((
        Count {
            kind: o.kind,
            intervals,
            maxima,
            transient: discarded,
        },
        o,
        discarded,
    ))
}

/// The primary reading's simulator, its settled orbit and the periods discarded (the
/// experiment's scene computes the same orbit through the same library function).
fn primary_orbit(p: &Fig9Params) -> Result<(Simulator, Settled, u64), Error> {
    let settling = orbit::Settling {
        chunk: p.chunk,
        window: p.window,
        max: p.max_transient,
    };
    let problem = forced(p, p.modes, p.k_over_k1, p.omega_over_w1, p.gap)?;
    orbit::settle_from_rest(&problem, &settling)
}

/// c_n by a DFT of `per_period` samples over one period from x at `cycle`.
fn dft(sim: &Simulator, x: &DVector<f64>, cycle: i64, per_period: usize, harmonics: usize) -> Result<Vec<Complex64>, Error> {
    let mut dense = Dense::new(per_period);
    sim.run_from(x, sim.clock_at_cycle(cycle), 1, &mut dense)?;
    let omega = sim.omega();
    Ok((1..=harmonics)
        .map(|n| {
            dense
                .samples
                .iter()
                .map(|&(t, _, v, _)| v * polar(1.0, -(n as f64) * omega * t))
                .sum::<Complex64>()
                * (2.0 / per_period as f64)
        })
        .collect())
}

fn scan<F>(values: &[f64], p: &Fig9Params, build: F) -> Result<Vec<ScanPoint>, Error>
where
    F: Fn(f64) -> Result<Forced, Error> + Sync,
{
    values
        .par_iter()
        .map(|&v| {
            let sim = Simulator::new(build(v)?.model()?)?;
            let (c, _, _) = count_contacts(&sim, p, p.scan_max_transient)?;
            Ok(ScanPoint { value: v, count: c })
        })
        .collect()
}

/// Runs the scene.
///
/// # Errors
/// A model out of range (`Error::Parameter`), a flow that cannot be built, or a run the
/// simulator refuses (chatter, a broken invariant).
pub fn compute(p: &Fig9Params, progress: &dyn Progress) -> Result<Fig9Data, Error> {
    let (sim, o, discarded) = primary_orbit(p)?;
    let scale = sim.model().free_tip_amplitude();
    let period = sim.period();
    let (count, _, _) = count_contacts(&sim, p, p.max_transient)?;
    let cycle = (discarded + p.window) as i64;
    let m = match o.kind {
        OrbitKind::Periodic { m, .. } => m,
        OrbitKind::NotPeriodic => 1,
    };
    let mut harmonics = TipHarmonics::new(p.harmonics);
    let mut dense = Dense::new(p.samples_per_period);
    let mut events = crate::engine::sim::Events::default();
    sim.run_from(
        &o.state,
        sim.clock_at_cycle(cycle),
        m,
        &mut (&mut harmonics, &mut dense, &mut events),
    )?;
    let t0 = cycle as f64 * period;
    let phase = |t: f64| (t - t0) / period;
    let mut contacts = Vec::new();
    let mut entry = None;
    let mut entry_velocities = Vec::new();
    for e in events.events.iter().filter(|e| !e.grazing) {
        if e.entering {
            entry = Some(phase(e.time));
            entry_velocities.push(e.tip_velocity / scale.1);
        } else {
            contacts.push((entry.take().unwrap_or(0.0), phase(e.time)));
        }
    }
    if let Some(a) = entry {
        contacts.push((a, m as f64));
    }
    let exact = harmonics.coefficients();
    let amplitudes: Vec<f64> = exact.iter().map(|c| c.norm() / scale.1).collect();
    let (coarse, fine) = (
        dft(&sim, &o.state, cycle, p.dft_samples.0, p.harmonics)?,
        dft(&sim, &o.state, cycle, p.dft_samples.1, p.harmonics)?,
    );
    let worst = |f: &dyn Fn(usize) -> f64| (0..p.harmonics).map(f).fold(0.0, f64::max);
    let dft_check = (
        worst(&|k| (fine[k] - exact[k]).norm()) / scale.1,
        // the finer DFT's own error by Richardson, assuming at least second order
        worst(&|k| (coarse[k] - fine[k]).norm() / 3.0) / scale.1,
    );
    let energy: f64 = amplitudes.iter().map(|v| v * v).sum();
    let higher_harmonic_share = if energy > 0.0 {
        1.0 - amplitudes[0] * amplitudes[0] / energy
    } else {
        0.0
    };
    let w = sim.omega();
    let mode_harmonics: Vec<f64> = (1..=40)
        .map(|i| crate::model::continuum::free_root(i).map(|b| b * b / w))
        .take_while(|h| h.as_ref().is_ok_and(|h| *h <= p.harmonics as f64 + 0.5))
        .collect::<Result<_, _>>()?;
    // the spectrum's interior local maxima (n = 2 … harmonics − 1: the last harmonic has no
    // right neighbour to be a maximum against) above a hundredth of the largest beyond n = 1
    let top = amplitudes.iter().skip(1).cloned().fold(0.0, f64::max);
    let peaks = (1..p.harmonics.saturating_sub(1))
        .filter(|&k| {
            amplitudes[k] > amplitudes[k - 1]
                && amplitudes[k] >= amplitudes[k + 1]
                && amplitudes[k] >= 0.01 * top
        })
        .map(|k| {
            let n = k + 1;
            let (mode, h) = mode_harmonics
                .iter()
                .enumerate()
                .min_by(|a, b| (a.1 - n as f64).abs().total_cmp(&(b.1 - n as f64).abs()))
                .map_or((0, f64::NAN), |(i, h)| (i + 1, *h));
            Peak {
                harmonic: n,
                amplitude: amplitudes[k],
                mode,
                mode_harmonic: h,
            }
        })
        .collect();
    let samples = dense
        .samples
        .iter()
        .map(|&(t, _, v, c)| (phase(t), v / scale.1, c))
        .collect();
    let task = progress.task("fig9 truncations and scans", 5);
    let by_modes = p
        .convergence_modes
        .par_iter()
        .map(|&n| {
            let sim = Simulator::new(forced(p, n, p.k_over_k1, p.omega_over_w1, p.gap)?.model()?)?;
            Ok((n, count_contacts(&sim, p, p.max_transient)?.0))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    task.advance(1);
    let (n, k, om) = (p.scan_n, p.k_over_k1, p.omega_over_w1);
    let scan_gap = scan(&p.scan_gap, p, |g| forced(p, n, k, om, g))?;
    task.advance(1);
    let scan_k = scan(&p.scan_k, p, |kk| forced(p, n, kk, om, p.gap))?;
    task.advance(1);
    let scan_omega = scan(&p.scan_omega, p, |w| forced(p, n, k, w, p.gap))?;
    task.advance(1);
    let modes: Vec<f64> = p.scan_modes.iter().map(|&m| m as f64).collect();
    let scan_modes = scan(&modes, p, |m| forced(p, m as usize, k, om, p.gap))?;
    task.advance(1);
    Ok(Fig9Data {
        params: p.clone(),
        count,
        residual: o.residual,
        contacts,
        entry_velocities,
        harmonic_amplitudes: amplitudes,
        dft_check,
        higher_harmonic_share,
        peaks,
        mode_harmonics,
        samples,
        free_amplitude: scale,
        by_modes,
        scan_gap,
        scan_k,
        scan_omega,
        scan_modes,
    })
}
