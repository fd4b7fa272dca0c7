//! How the exact simulator's cost grows with the number of modes N and the stop stiffness
//! k: the Figure 4 problem (ζ₁ = 0.01, d₀ = 0, ω = 2(β₁⁻)²) along N at k = 100k₁, and along
//! k at N = 10, each after a transient from rest.
//!
//! Per period: the wall time of simulating whole periods (no observer, so no energy
//! budget), and the work counters behind it ([`Stats`]): segments (one per region
//! visited), switching-function evaluations and certified steps. Per orbit: the wall time
//! of shooting the period-1 orbit with its Floquet multipliers from the settled state.
//! The counters are exact and the same on every machine; the times are this machine's.
//! Each exponent is the least-squares slope of log cost against log N over the points from
//! N = 20 on (below, the fixed cost of a period hides the growth), or against log k over
//! every k.

use super::best_of;
use crate::analysis::shooting;
use crate::engine::sim::{Simulator, Stats};
use crate::error::Error;
use crate::model::problems;
use nalgebra::DVector;
use serde::Serialize;

/// What the scaling runs cover.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct ScalingParams {
    /// N along the first line (k = 100k₁).
    pub modes: Vec<usize>,
    /// k/k₁ along the second line (N = 10).
    pub stiffness: Vec<f64>,
    /// Periods discarded before the timed runs.
    pub transient: u64,
    /// Periods per timed run.
    pub periods: u64,
}

impl ScalingParams {
    /// The book's: N = 5 … 160, k = 10 … 10⁴k₁.
    pub fn book() -> Self {
        Self {
            modes: vec![5, 10, 20, 40, 80, 160],
            stiffness: vec![10.0, 100.0, 1000.0, 10_000.0],
            transient: 500,
            periods: 1000,
        }
    }

    /// The tests': N = 5 … 80 (three points from N = 20 for the fit), k = 10 … 1000k₁,
    /// short runs.
    pub fn test() -> Self {
        Self {
            modes: vec![5, 10, 20, 40, 80],
            stiffness: vec![10.0, 100.0, 1000.0],
            transient: 50,
            periods: 20,
        }
    }
}

/// One (N, k).
#[derive(Debug, Clone, Serialize)]
pub struct ScalingPoint {
    /// N.
    pub modes: usize,
    /// k/k₁.
    pub k_over_k1: f64,
    /// Wall time per period (s), best of the repeats.
    pub seconds_per_period: f64,
    /// The counters over the timed run.
    pub stats: Stats,
    /// Periods of the timed run.
    pub periods: u64,
    /// Wall time of one orbit with its multipliers by shooting (s), best of the repeats;
    /// `None` when shooting did not converge.
    pub seconds_per_orbit: Option<f64>,
}

impl ScalingPoint {
    /// A counter per period.
    pub fn per_period(&self, count: u64) -> f64 {
        count as f64 / self.periods as f64
    }
}

/// Both lines.
#[derive(Debug, Clone, Serialize)]
pub struct Scaling {
    /// Along N at k = 100k₁.
    pub along_modes: Vec<ScalingPoint>,
    /// Along k at N = 10.
    pub along_stiffness: Vec<ScalingPoint>,
}

fn point(p: &ScalingParams, modes: usize, k_over_k1: f64, repeats: usize) -> Result<ScalingPoint, Error> {
    let case = problems::Forced {
        k_over_k1,
        ..problems::figure4(modes)
    };
    let sim = Simulator::new(case.model()?)?;
    let x = sim.run(&DVector::zeros(2 * modes), p.transient, &mut ())?.state;
    let (run, seconds) = best_of(repeats, || sim.run(&x, p.periods, &mut ()));
    let stats = run?.stats;
    let (orbit, orbit_seconds) = best_of(repeats, || shooting::shoot(&sim, &x, 1));
    Ok(ScalingPoint {
        modes,
        k_over_k1,
        seconds_per_period: seconds / p.periods as f64,
        stats,
        periods: p.periods,
        seconds_per_orbit: orbit.is_ok().then_some(orbit_seconds),
    })
}

/// Runs both lines, one point at a time (the times are meant to be of one core).
///
/// # Errors
/// A model out of range (`Error::Parameter`), a flow that cannot be built, or a run the
/// simulator refuses; shooting that does not converge is recorded, not raised.
pub fn compute(p: &ScalingParams, repeats: usize) -> Result<Scaling, Error> {
    Ok(Scaling {
        along_modes: p
            .modes
            .iter()
            .map(|&n| point(p, n, 100.0, repeats))
            .collect::<Result<_, _>>()?,
        along_stiffness: p
            .stiffness
            .iter()
            .map(|&k| point(p, 10, k, repeats))
            .collect::<Result<_, _>>()?,
    })
}

/// The least-squares slope of log y against log x over the points from index `from` on,
/// and its standard error (NaN with only two points); `None` with fewer than two usable
/// points.
pub fn exponent(points: &[(f64, f64)], from: usize) -> Option<(f64, f64)> {
    let logs: Vec<(f64, f64)> = points[from.min(points.len())..]
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let (mx, my) = logs.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let slope = sxy / sxx;
    let residuals: f64 = logs.iter().map(|(x, y)| (y - my - slope * (x - mx)).powi(2)).sum();
    let error = if logs.len() > 2 { (residuals / (n - 2.0) / sxx).sqrt() } else { f64::NAN };
    Some((slope, error))
}


/// Where the fit of the line along N starts: the first N ≥ 20.
pub fn fit_from(modes: &[usize]) -> usize {
    modes.iter().position(|&n| n >= 20).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::exponent;

    #[test]
    fn the_slope_of_a_power_law_past_its_first_two_points() {
        // y = 3 x^1.5 from the third point on; the first two are off the law (set-up costs)
        let pts: Vec<(f64, f64)> = [5.0, 10.0, 20.0, 40.0, 80.0]
            .iter()
            .enumerate()
            .map(|(i, &x)| (x, if i < 2 { 1.0 } else { 3.0 * f64::powf(x, 1.5) }))
            .collect();
        let (slope, error) = exponent(&pts, 2).unwrap();
        assert!((slope - 1.5).abs() < 1e-12 && error < 1e-12);
        assert_eq!(exponent(&pts[..3], 2), None);
    }
}
