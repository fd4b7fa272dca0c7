//! What Figure 5's "not periodic" band between the Neimark–Sacker pair is: rotation numbers.
//!
//! On the (1,1) branch of every N ≥ 2 a complex pair of Floquet multipliers μ, μ̄ leaves the
//! unit circle at the first Neimark–Sacker point and returns at the second. Between them
//! the diagram finds no periodic orbit. If that motion lies on a torus born at the
//! Neimark–Sacker points, the stroboscopic map P turns it round an invariant closed curve by
//! a rotation number ρ (turns per forcing period), which near each bifurcation is the
//! pair's |arg μ|/2π; a locked window would have a rational ρ = p/q and a period-q orbit.
//!
//! Measured here: after the diagram's transient from rest, P is iterated; the iterates
//! are projected onto the plane in which they spread most (their two principal directions)
//! about the fixed point the curve surrounds, the unstable (1,1) orbit (found by shooting
//! from the iterates' mean); ρ is the mean angle turned per period about it. Its
//! uncertainty is the difference between the two halves of the record (a motion that is
//! not on a closed curve round the fixed point shows as a large difference). The plane and
//! the centre matter: the tip's (d, ḋ) plane, and the impact section's (phase, velocity),
//! each fold the curve over itself in part of the band, where about either centre ρ came
//! out near 0.1 between neighbours near 0.27 or 0.23; the principal plane does not.

use super::{forced, Fig5Data, Fig5Params};
use crate::analysis::motion;
use crate::analysis::orbit::{self, OrbitKind};
use crate::analysis::shooting;
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::engine::sim::Simulator;
use crate::error::Error;
use nalgebra::DVector;
use rayon::prelude::*;
use serde::Serialize;

/// Stroboscopic iterates recorded per point (after the diagram's transient).
pub const ITERATES: usize = 4000;

/// One k inside the band.
#[derive(Debug, Clone, Serialize)]
pub struct RotationPoint {
    /// k/k₁.
    pub k_over_k1: f64,
    /// ρ over the whole record, folded into [0, 1/2] (turns per forcing period).
    pub rotation: f64,
    /// |ρ(first half) − ρ(second half)|.
    pub halves_differ: f64,
}

/// The band of one truncation.
#[derive(Debug, Clone, Serialize)]
pub struct Band {
    /// N.
    pub modes: usize,
    /// The Neimark–Sacker pair, k/k₁.
    pub neimark_sacker: (f64, f64),
    /// |arg μ|/2π of the critical pair at each of them.
    pub onset_rotation: (f64, f64),
    /// The grid values inside the band where the start from rest is not periodic and
    /// enters contact once per period.
    pub points: Vec<RotationPoint>,
    /// Grid values inside the band, not periodic from rest, where no (1,1) fixed point was
    /// found inside the motion (not measured).
    pub other_motion: usize,
}

pub use crate::analysis::motion::rotation_number;

/// |arg μ|/2π of the complex multiplier of largest modulus, in turns.
pub(super) fn pair_rotation(multipliers: &[[f64; 2]]) -> Option<f64> {
    multipliers
        .iter()
        .filter(|z| z[1].abs() > 1e-9 * z[0].hypot(z[1]).max(1.0))
        .max_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1])))
        .map(|z| z[1].atan2(z[0]).abs() / std::f64::consts::TAU)
}

/// ρ at one k from rest, after the diagram's transient. `None` when the fixed point inside
/// (the unstable (1,1) orbit, by shooting from the iterates' mean) is not found.
fn measure(p: &Fig5Params, modes: usize, k_over_k1: f64) -> Result<Option<RotationPoint>, Error> {
    let sim = Simulator::new(forced(p, modes, k_over_k1).model()?)?;
    let s = orbit::settle_map(
        &sim,
        &DVector::zeros(2 * modes),
        p.transient,
        ITERATES as u64,
    )?;
    let iterates = &s.window.strobe[1..];
    let n = iterates.len() as f64;
    let mean = iterates
        .iter()
        .fold(DVector::zeros(2 * modes), |a, x| a + x)
        / n;
    let Ok(fixed) = shooting::shoot(&sim, &mean, 1) else {
        return Ok(None);
    };
    if fixed.period_m != 1 || fixed.impacts_n != 1 {
        return Ok(None);
    }
    let r = motion::rotation_about(iterates, &DVector::from_column_slice(&fixed.state));
    Ok(Some(RotationPoint {
        k_over_k1,
        rotation: r.turns,
        halves_differ: r.halves_differ,
    }))
}

/// The bands of every N ≥ 2 whose (1,1) branch has a Neimark–Sacker pair.
///
/// # Errors
/// A model out of range (`Error::Parameter`), a flow that cannot be built, or a run the
/// simulator refuses; a fixed point not found by shooting is no error (the k is skipped).
pub fn bands(p: &Fig5Params, d: &Fig5Data) -> Result<Vec<Band>, Error> {
    let mut out = Vec::new();
    for set in d.branches.iter().filter(|s| s.modes >= 2) {
        let mut ns: Vec<(f64, f64)> = set
            .branches
            .iter()
            .filter(|b| b.period_m == 1)
            .flat_map(|b| b.neimark_sacker_rotation.iter().copied())
            .collect();
        ns.sort_by(|a, b| a.0.total_cmp(&b.0));
        ns.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-6 * b.0.abs());
        let [(k_a, rho_a), (k_b, rho_b)] = ns[..] else {
            continue;
        };
        let Some(g) = d.diagrams.iter().find(|g| g.modes == set.modes) else {
            continue;
        };
        let inside: Vec<f64> = d
            .k_over_k1
            .iter()
            .zip(&g.columns)
            .filter(|(k, col)| **k > k_a && **k < k_b && col[0].kind == OrbitKind::NotPeriodic)
            .map(|(k, _)| *k)
            .collect();
        let measured = inside
            .par_iter()
            .map(|&k| measure(p, set.modes, k))
            .collect::<Result<Vec<_>, Error>>()?;
        let other_motion = measured.iter().filter(|m| m.is_none()).count();
        let points = measured.into_iter().flatten().collect();
        out.push(Band {
            modes: set.modes,
            neimark_sacker: (k_a, k_b),
            onset_rotation: (rho_a, rho_b),
            points,
            other_motion,
        });
    }
    Ok(out)
}


/// The bands' key numbers: per N, the Neimark–Sacker onsets' rotation and the range of ρ
/// measured inside the band, each ρ good to the larger of its two halves' difference and
/// the unfinished last turn, 1/(ITERATES − 1).
pub(super) fn key_numbers(k: &mut KeyNumbers, d: &Fig5Data) {
    let floor = 1.0 / (ITERATES - 1) as f64;
    let r4 = |x: f64| crate::base::report::round_sig(x, 4);
    if !d.bands.is_empty() {
        k.integer("rotation iterates", ITERATES as i64);
    }
    for b in &d.bands {
        let r = |x: f64| crate::base::report::round_sig(x, 3);
        k.text(
            format!("N={} rotation at the Neimark-Sacker pair", b.modes),
            format!("{} and {}", r(b.onset_rotation.0), r(b.onset_rotation.1)),
        );
        k.integer(
            format!("N={} band k values measured", b.modes),
            b.points.len() as i64,
        );
        k.integer(
            format!("N={} band k values with other motion", b.modes),
            b.other_motion as i64,
        );
        let least = b
            .points
            .iter()
            .min_by(|x, y| x.rotation.total_cmp(&y.rotation));
        let most = b
            .points
            .iter()
            .max_by(|x, y| x.rotation.total_cmp(&y.rotation));
        for (name, q) in [("least", least), ("greatest", most)] {
            let Some(q) = q else { continue };
            k.cited(
                format!("N={} band rotation number, {name}", b.modes),
                q.rotation,
                3,
                Uncertainty::new(
                    q.halves_differ.max(floor),
                    format!(
                        "the two halves of {ITERATES} iterates of P at k = {:.3} k₁",
                        q.k_over_k1
                    ),
                ),
                "",
            );
        }
        // where ρ passes 1/4: the 1:4 resonance, where a period-4 orbit can lock
        let last_above = b
            .points
            .iter()
            .filter(|q| q.rotation > 0.25)
            .map(|q| q.k_over_k1)
            .fold(f64::NAN, f64::max);
        let first_below = b
            .points
            .iter()
            .filter(|q| q.rotation < 0.25)
            .map(|q| q.k_over_k1)
            .fold(f64::NAN, f64::min);
        k.text(
            format!("N={} band rotation passes 1/4 between", b.modes),
            if last_above < first_below {
                format!("{} and {}", r4(last_above), r4(first_below))
            } else {
                "not between two measured values".to_string()
            },
        );
        let isola = d
            .branches
            .iter()
            .filter(|s| s.modes == b.modes)
            .flat_map(|s| &s.branches)
            .find(|br| br.period_m == 4 && br.end.starts_with("closed loop"))
            .map_or("not traced".to_string(), |br| {
                let ks = br.points.iter().map(|q| q.k_over_k1);
                let (lo, hi) = ks.fold((f64::INFINITY, 0.0f64), |(a, c), x| (a.min(x), c.max(x)));
                format!("{} to {}", r4(lo), r4(hi))
            });
        k.text(format!("N={} period-4 isola", b.modes), isola);
    }
}

#[cfg(test)]
mod tests {
    use super::rotation_number;

    #[test]
    fn a_rigid_rotation_of_the_circle_is_measured_to_round_off() {
        // points turned by ρ = 0.1234 about a centre off the origin, on an ellipse
        let rho = 0.1234_f64;
        let pts: Vec<(f64, f64)> = (0..4000)
            .map(|i| {
                let a = std::f64::consts::TAU * rho * f64::from(i);
                (3.0 + 2.0 * a.cos(), -1.0 + 0.5 * a.sin())
            })
            .collect();
        // exact but for the last, unfinished turn: within 1/(n − 1)
        assert!((rotation_number(&pts, (3.0, -1.0)) - rho).abs() < 1.0 / 3999.0);
        // and the other sense of turning, and ρ above one half, fold to the same value
        let back: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, -p.1)).collect();
        assert!((rotation_number(&back, (3.0, 1.0)) - rho).abs() < 1.0 / 3999.0);
    }
}
