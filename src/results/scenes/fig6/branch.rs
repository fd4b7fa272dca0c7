//! Panel (a)'s (1,1) orbit continued in the gap d₀ (issue: is there a near-grazing (1,1)
//! orbit the starts from rest missed?). The scan finds the (1,1) orbit from rest over a
//! band of d₀/A_free; here its branch is traced both ways by pseudo-arclength continuation
//! ([`crate::analysis::continuation`], in ln d₀), stable or not, with its folds, period
//! doublings and grazings, and r_E of eq (39) at every point of the branch.

use super::compute::scanned;
use super::{Fig6Params, ScanPoint};
use crate::analysis::continuation::{trace, Family, Parameter, Settings};
use crate::analysis::energetic::ContactWork;
use crate::analysis::orbit::{self, OrbitKind};
use crate::engine::sim::Simulator;
use crate::error::Error;
use nalgebra::DVector;
use serde::Serialize;

/// One point of the branch.
#[derive(Debug, Clone, Serialize)]
pub struct GapPoint {
    /// d₀/A_free.
    pub gap_over_free_amplitude: f64,
    /// Whether every Floquet multiplier lies inside the unit circle.
    pub stable: bool,
    /// Contacts per period.
    pub contacts: usize,
    /// r_E by eq (39) (None: no real value or no contact).
    pub r_e: Option<f64>,
    /// The smallest entry tip velocity / (ωA_free) (None: no contact).
    pub smallest_entry_velocity: Option<f64>,
}

/// A bifurcation on the branch.
#[derive(Debug, Clone, Serialize)]
pub struct GapBifurcation {
    /// "fold", "period doubling", "Neimark–Sacker", "grazing", "branch point".
    pub kind: String,
    /// d₀/A_free (interpolated between two points of the branch).
    pub gap_over_free_amplitude: f64,
}

/// The (1,1) branch in d₀.
#[derive(Debug, Clone, Serialize)]
pub struct GapBranch {
    /// d₀/A_free of the orbit from rest it starts from.
    pub start: f64,
    /// The points, in order of d₀ along each direction (towards larger d₀ first).
    pub points: Vec<GapPoint>,
    /// Its bifurcations.
    pub bifurcations: Vec<GapBifurcation>,
    /// Why each direction stopped.
    pub ends: Vec<String>,
}

/// The branch through the scan's middle (1,1) orbit from rest, traced over the scan's
/// range of d₀/A_free; None when the scan found no (1,1) orbit.
pub fn compute(scan: &[ScanPoint], p: &Fig6Params) -> Result<Option<GapBranch>, Error> {
    let ones: Vec<f64> = scan
        .iter()
        .filter(|s| matches!(s.rest.kind, OrbitKind::Periodic { m: 1, n: 1 }))
        .map(|s| s.gap_over_free_amplitude)
        .collect();
    let Some(&rho0) = ones.get(ones.len() / 2) else {
        return Ok(None);
    };
    let modes = p.scan_modes;
    // the parameter is d₀/A_free itself: the family scales it to the model's gap
    let family = Family::new(Parameter::Gap, move |rho| Ok(scanned(rho, modes)?.model()?));
    let sim = family.simulator(rho0)?;
    let settled = orbit::settle(&sim, &DVector::zeros(2 * modes), p.transient, p.window, 0)?;
    let lo = scan.iter().map(|s| s.gap_over_free_amplitude).fold(f64::INFINITY, f64::min);
    let hi = scan.iter().map(|s| s.gap_over_free_amplitude).fold(0.0, f64::max);
    let mut settings = Settings::new((lo.max(1e-3), hi));
    settings.max_step = 0.01;
    // the two directions only: period doublings are reported, not followed
    settings.max_branches = 2;
    let branches = trace(&family, &settled.state, rho0, 1, &settings)?;
    let mut points = Vec::new();
    let mut bifurcations = Vec::new();
    let mut ends = Vec::new();
    for b in &branches {
        for pt in &b.points {
            points.push(point(&family, pt.parameter, &pt.state, pt.stable, pt.impacts_n)?);
        }
        bifurcations.extend(b.bifurcations.iter().map(|x| GapBifurcation {
            kind: x.kind.to_string(),
            gap_over_free_amplitude: x.parameter,
        }));
        ends.push(b.end.clone());
    }
    Ok(Some(GapBranch {
        start: rho0,
        points,
        bifurcations,
        ends,
    }))
}

/// r_E and the smallest entry velocity over one period from a state on the orbit.
fn point(family: &Family, rho: f64, state: &[f64], stable: bool, contacts: usize) -> Result<GapPoint, Error> {
    let sim: Simulator = family.simulator(rho)?;
    let mut work = ContactWork::for_mode(sim.model(), 0)?;
    let x = DVector::from_column_slice(state);
    sim.run_from(&x, sim.clock_at_cycle(0), 1, &mut work)?;
    let v_free = sim.model().free_tip_amplitude().1;
    let smallest_entry_velocity = work
        .contacts
        .iter()
        .filter_map(|c| c.tip_velocity)
        .fold(None, |a: Option<f64>, v| Some(a.map_or(v, |a| a.min(v))))
        .map(|v| v / v_free);
    Ok(GapPoint {
        gap_over_free_amplitude: rho,
        stable,
        contacts,
        r_e: work.coefficient().value(),
        smallest_entry_velocity,
    })
}
