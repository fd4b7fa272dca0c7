//! Figure 6's computation: each case's orbit and r_E with its diagnostics, the one-mode
//! comparison, and the scan of panel (a).

use super::{Case, Diagnostics, Fig6Data, Fig6Params, OneMode, Probe, Reading, ScanPoint};
use crate::analysis::convergence::{truncation_error, TruncationError};
use crate::analysis::energetic::{orbit_coefficient, OrbitCoefficient};
use crate::error::Error;
use crate::analysis::orbit::{self, random_state, OrbitKind, SplitMix64};
use crate::model::problems::{self, Forced};
use crate::model::restitution::impulse_response;
use crate::engine::rigid::RigidImpact;
use crate::results::scene::Progress;
use crate::engine::sim::{Clock, Observer, SegmentView, Settings, Simulator};
use nalgebra::DVector;
use rayon::prelude::*;

/// The paper's panel (a) gap.
const PANEL_A_GAP: f64 = 0.8;

/// The model of a case at N modes.
fn forced(panel: &str, reading: Reading, modes: usize) -> Result<Forced, Error> {
    Ok(match (panel, reading) {
        ("b", _) => problems::figure6b(modes),
        (_, Reading::PrintedEq37) => Forced {
            printed_eq37_amplitude: true,
            ..problems::figure6a(modes)
        },
        (_, Reading::UnitAtForcingFrequency) => {
            // unit amplitude at ω with d₀ = 0.8 is, with every length scaled by A_free(ω)
            // of the text's amplitude, that amplitude with d₀ = 0.8·A_free(ω)
            let a = problems::figure6a(1).model()?.free_tip_amplitude().0;
            Forced {
                gap: PANEL_A_GAP * a,
                ..problems::figure6a(modes)
            }
        }
        _ => problems::figure6a(modes),
    })
}

/// Panel (a)'s model with d₀ = ρ·A_free(ω) (the text's amplitude).
pub(super) fn scanned(rho: f64, modes: usize) -> Result<Forced, Error> {
    let a = problems::figure6a(1).model()?.free_tip_amplitude().0;
    Ok(Forced {
        gap: rho * a,
        ..problems::figure6a(modes)
    })
}

fn probe(sim: &Simulator, x0: &DVector<f64>, p: &Fig6Params, transient: u64) -> Result<(Probe, OrbitCoefficient), Error> {
    let o = orbit_coefficient(sim, x0, transient, p.window)?;
    Ok((
        Probe {
            kind: o.kind,
            coefficient: o.coefficient,
        },
        o,
    ))
}

fn random_start(sim: &Simulator, p: &Fig6Params, a: u64, b: u64) -> DVector<f64> {
    let n = sim.model().modes();
    let (amp, _) = sim.model().free_tip_amplitude();
    let mut rng = SplitMix64::for_point(p.seed, n as u64, a, b);
    random_state(&mut rng, n, 4.0 * amp, sim.omega())
}

/// Samples of the tip d and of its mode-1 part φ₁(1)η₁ on the grid of `per_period` points
/// per period.
struct ModeOneSamples {
    per_period: usize,
    samples: Vec<(f64, f64, f64, bool)>,
}

impl Observer for ModeOneSamples {
    fn segment(&mut self, seg: &SegmentView) {
        let tip = seg.simulator().model().tip();
        let n = tip.len();
        for (s, t) in seg.start.grid(seg.end, self.per_period) {
            let x = seg.state(s);
            let d = tip.dot(&x.rows(0, n));
            self.samples.push((
                t,
                d,
                tip[0] * x[0],
                seg.region == crate::model::galerkin::Region::Contact,
            ));
        }
    }
}

fn diagnostics(
    panel: &str,
    reading: Reading,
    p: &Fig6Params,
    base: &Probe,
) -> Result<Diagnostics, Error> {
    let by_modes = p
        .convergence_modes
        .iter()
        .map(|&n| {
            if n == p.modes {
                return Ok((n, base.clone()));
            }
            let sim = Simulator::new(forced(panel, reading, n)?.model()?)?;
            Ok((n, probe(&sim, &DVector::zeros(2 * n), p, p.transient)?.0))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let model = forced(panel, reading, p.modes)?.model()?;
    let sim = Simulator::new(model.clone())?;
    let rest = DVector::zeros(2 * p.modes);
    let long_transient = probe(&sim, &rest, p, p.long_transient)?.0;
    let loose = Simulator::new(model)?.with_settings(Settings {
        root_tolerance: p.loose_root_tolerance,
    });
    let loose_tolerance = probe(&loose, &rest, p, p.transient)?.0;
    let random_starts = (0..p.random_starts)
        .map(|i| {
            let x0 = random_start(&sim, p, 1, i as u64);
            Ok(probe(&sim, &x0, p, p.transient)?.0)
        })
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(Diagnostics {
        by_modes,
        long_transient,
        loose_tolerance,
        random_starts,
    })
}

/// The uncertainty of r_E: its truncation ± by the book's one rule
/// ([`truncation_error`]: Richardson over the three finest N of the diagnostic's ladder)
/// plus the largest change under the longer transient, the looser root tolerance and the
/// random starts (settling and solver, not truncation). None when a refinement (an N above
/// the published one, or one of those runs) changes the orbit or has no real r_E, or fewer
/// than three N are on the published orbit.
fn uncertainty(base: &Probe, d: &Diagnostics, modes: usize) -> Option<(f64, TruncationError)> {
    let r = base.value()?;
    let mut ladder = Vec::new();
    for (n, probe) in &d.by_modes {
        match (probe.kind == base.kind, probe.value()) {
            (true, Some(v)) => ladder.push((*n, v)),
            // a coarser N on another orbit leaves the ladder; a finer one leaves no estimate
            _ if *n > modes => return None,
            _ => {}
        }
    }
    let truncation = truncation_error(modes, &ladder)?;
    let mut worst = 0.0_f64;
    for probe in [&d.long_transient, &d.loose_tolerance]
        .into_iter()
        .chain(&d.random_starts)
    {
        if probe.kind != base.kind {
            return None;
        }
        worst = worst.max((probe.value()? - r).abs());
    }
    Some((truncation.plus_minus + worst, truncation))
}

fn one_mode(
    panel: &str,
    reading: Reading,
    r: f64,
    p: &Fig6Params,
    scale: (f64, f64),
) -> Result<OneMode, Error> {
    let model = forced(panel, reading, 1)?.model()?;
    let sim = Simulator::new(model)?;
    let period = sim.period();
    let rigid = RigidImpact::new(sim, impulse_response(1, r)?)?;
    let settled = orbit::settle_rigid(&rigid, &DVector::zeros(2), p.transient, p.window)?;
    let m = match settled.kind {
        OrbitKind::Periodic { m, .. } => m,
        OrbitKind::NotPeriodic => 1,
    };
    let start = Clock::at_cycle(period, settled.cycle);
    let mut x = DVector::from_vec(settled.state.clone());
    let mut clock = start;
    let per = p.samples_per_period as u64 * m;
    let tip = rigid.sim.model().tip()[0];
    let (mut samples, mut phases, mut velocities) = (Vec::new(), Vec::new(), Vec::new());
    samples.push((0.0, tip * x[0] / scale.0));
    for j in 1..=per {
        let mut next = start;
        next.advance(j as f64 * period / p.samples_per_period as f64);
        let run = rigid.run_until(&x, clock, next)?;
        for (t, v, _) in run.impacts() {
            phases.push((t - start.time()) / period);
            velocities.push(v / scale.1);
            // the impact itself, a corner the grid would cut
            let gap = rigid.sim.model().params().gap;
            samples.push(((t - start.time()) / period, gap / scale.0));
        }
        x = run.state;
        clock = next;
        samples.push(((clock.time() - start.time()) / period, tip * x[0] / scale.0));
    }
    let extremes = samples
        .iter()
        .fold((f64::NEG_INFINITY, f64::INFINITY), |(hi, lo), s| (hi.max(s.1), lo.min(s.1)));
    Ok(OneMode {
        restitution: r,
        kind: settled.kind,
        chatters: settled.chatters,
        impact_phases: phases,
        impact_velocities: velocities,
        extremes,
        samples,
    })
}

fn case(panel: &'static str, reading: Reading, p: &Fig6Params) -> Result<Case, Error> {
    let f = forced(panel, reading, p.modes)?;
    let model = f.model()?;
    let scale = model.free_tip_amplitude();
    let sim = Simulator::new(model)?;
    let period = sim.period();
    let (base, o) = probe(&sim, &DVector::zeros(2 * p.modes), p, p.transient)?;
    let m = match o.kind {
        OrbitKind::Periodic { m, .. } => m,
        OrbitKind::NotPeriodic => 1,
    };
    let start = sim.clock_at_cycle(o.cycle);
    let mut samples = ModeOneSamples {
        per_period: p.samples_per_period,
        samples: Vec::new(),
    };
    sim.run_from(&DVector::from_vec(o.state.clone()), start, m, &mut samples)?;
    let t0 = start.time();
    let phase = |t: f64| (t - t0) / period;
    let contacts = o
        .contacts
        .iter()
        .map(|c| {
            (
                c.entry.map_or(0.0, phase),
                c.exit.map_or(m as f64, phase),
            )
        })
        .collect();
    let extremes = samples
        .samples
        .iter()
        .fold((f64::NEG_INFINITY, f64::INFINITY), |(hi, lo), s| (hi.max(s.1), lo.min(s.1)));
    let diagnostics = diagnostics(panel, reading, p, &base)?;
    let (uncertainty, truncation) = uncertainty(&base, &diagnostics, p.modes).unzip();
    let one_mode = base
        .value()
        .map(|r| one_mode(panel, reading, r, p, scale))
        .transpose()?;
    Ok(Case {
        panel,
        reading,
        paper_r_e: if panel == "a" { 0.036 } else { 0.74 },
        gap_over_free_amplitude: f.gap / scale.0,
        free_amplitude: scale,
        kind: o.kind,
        residual: o.residual,
        coefficient: o.coefficient,
        energy_change_coefficient: o.energy_change_coefficient,
        contact_coefficients: o
            .contacts
            .iter()
            .map(|c| c.coefficient().and_then(|r| r.value()))
            .collect(),
        contacts,
        entry_velocities: o
            .contacts
            .iter()
            .filter_map(|c| c.tip_velocity)
            .map(|v| v / scale.1)
            .collect(),
        extremes: (extremes.0 / scale.0, extremes.1 / scale.0),
        diagnostics,
        uncertainty,
        truncation,
        one_mode,
        samples: samples
            .samples
            .iter()
            .map(|&(t, d, m1, c)| (phase(t), d / scale.0, m1 / scale.0, c))
            .collect(),
    })
}

fn scan_point(rho: f64, index: usize, p: &Fig6Params) -> Result<ScanPoint, Error> {
    let model = scanned(rho, p.scan_modes)?.model()?;
    let v_free = model.free_tip_amplitude().1;
    let sim = Simulator::new(model)?;
    let (rest, o) = probe(&sim, &DVector::zeros(2 * p.scan_modes), p, p.transient)?;
    let x0 = random_start(&sim, p, 2, index as u64);
    let random = probe(&sim, &x0, p, p.transient)?.0;
    let entry_velocity = o
        .contacts
        .iter()
        .filter_map(|c| c.tip_velocity)
        .fold(None, |a: Option<f64>, v| Some(a.map_or(v, |a| a.max(v))))
        .map(|v| v / v_free);
    Ok(ScanPoint {
        gap_over_free_amplitude: rho,
        rest,
        random,
        entry_velocity,
    })
}

/// Runs the scene: the cases (in parallel), then the scan (in parallel, with progress).
///
/// # Errors
/// A model out of range (`Error::Parameter`), a flow that cannot be built, a run the
/// simulator refuses, or a failed continuation of the (1,1) branch in d₀.
pub fn compute(p: &Fig6Params, progress: &dyn Progress) -> Result<Fig6Data, Error> {
    let specs = [
        ("a", Reading::PrintedEq37),
        ("a", Reading::UnitAtForcingFrequency),
        ("a", Reading::UnitAtResonance),
        ("b", Reading::Homogeneous),
    ];
    let task = progress.task("fig6 cases", specs.len() as u64);
    let cases = specs
        .par_iter()
        .map(|&(panel, reading)| {
            let c = case(panel, reading, p);
            task.advance(1);
            c
        })
        .collect::<Result<Vec<_>, Error>>()?;
    drop(task);
    let task = progress.task("fig6 scan of d0/A_free", p.scan.len() as u64);
    let scan = p
        .scan
        .par_iter()
        .enumerate()
        .map(|(i, &rho)| {
            let s = scan_point(rho, i, p);
            task.advance(1);
            s
        })
        .collect::<Result<Vec<_>, Error>>()?;
    drop(task);
    let task = progress.task("fig6 (1,1) branch in d0", 1);
    let gap_branch = super::branch::compute(&scan, p)?;
    task.advance(1);
    Ok(Fig6Data {
        params: p.clone(),
        cases,
        scan,
        gap_branch,
    })
}
