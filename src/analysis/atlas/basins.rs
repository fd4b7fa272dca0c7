//! Basins of attraction of one atlas cell (beyond the paper): which start reaches which
//! stable orbit where several coexist.
//!
//! **Starts.** The beam released in its first mode shape, every other mode at rest: tip
//! displacement d (in units of A_free, the free tip amplitude at the cell's ω) and tip velocity
//! v (in units of ωA_free) on a square grid of odd side centred on rest, so that the centre
//! start is the atlas's start from rest. (The tip of mode j moves by φ_j(1) q_j = 2q_j.)
//!
//! **What each start reaches.** The cell's own search from that start
//! ([`CellSearch::from_state`]: the atlas's transient, read in thirds, the period proposed by
//! the strobe, Newton shooting to 1e-12, kept only if stable), and the orbit recognised
//! among those already met ([`CellSearch::add`], up to a shift along the orbit). Starts run in
//! parallel; orbits are numbered in grid order afterwards, so the result does not depend on
//! the thread count.

use super::cell::{CellSearch, Found};
use super::{AtlasParams, Attractor};
use crate::base::progress::Progress;
use crate::engine::sim::Simulator;
use crate::error::{Error, ParameterError};
use nalgebra::DVector;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What to compute.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BasinParams {
    /// The atlas whose cell this is (its grid, ζ₁, d₀, transient, largest period, seed).
    pub atlas: AtlasParams,
    /// The cell's row (k) and column (ω) in that atlas's grid.
    pub cell: (usize, usize),
    /// N.
    pub modes: usize,
    /// Starts per side (odd, 3–401).
    pub points: usize,
    /// The grid spans ±`extent` in d/A_free and in v/(ωA_free).
    pub extent: f64,
}

/// The basins.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BasinData {
    /// The parameters.
    pub params: BasinParams,
    /// k/k₁ of the cell.
    pub k_over_k1: f64,
    /// ω/(β₁⁻)² of the cell.
    pub omega_over_w1: f64,
    /// The tip displacements of the starts, d/A_free.
    pub displacement: Vec<f64>,
    /// The tip velocities of the starts, v/(ωA_free).
    pub velocity: Vec<f64>,
    /// The stable orbits reached, in the order first met along the grid (velocity rows, then
    /// displacement).
    pub orbits: Vec<Attractor>,
    /// For each velocity (row) and displacement (column): the index of the orbit the start
    /// reached, or None (no stable orbit of period ≤ max_m within the transient).
    pub reached: Vec<Vec<Option<usize>>>,
}

impl BasinParams {
    /// The book's cell: row 49 and column 106 of the book's atlas, k = 34.9k₁ and
    /// ω = 2.587(β₁⁻)², where rest and one random start reach a (2,2) orbit and the other a
    /// (1,1) orbit; its row uses N = 10. 81 × 81 starts within ±4 free tip amplitudes.
    pub fn book() -> Self {
        Self {
            atlas: AtlasParams::book(),
            cell: (49, 106),
            modes: 10,
            points: 81,
            extent: 4.0,
        }
    }

    /// The tests' resolution: the same cell, 11 × 11 starts.
    pub fn test() -> Self {
        Self {
            points: 11,
            ..Self::book()
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`ParameterError`] naming the first out of range.
    pub fn validate(&self) -> Result<(), ParameterError> {
        self.atlas.validate()?;
        if self.cell.0 >= self.atlas.k_points || self.cell.1 >= self.atlas.omega_points {
            return Err(ParameterError::new(
                "basin cell",
                format!("({}, {})", self.cell.0, self.cell.1),
                &format!(
                    "a (row, column) of the atlas's {} × {} grid",
                    self.atlas.k_points, self.atlas.omega_points
                ),
            ));
        }
        if self.points.is_multiple_of(2) || !(3..=401).contains(&self.points) {
            return Err(ParameterError::new(
                "basin points",
                self.points,
                "an odd number from 3 to 401 (odd: rest is the centre start)",
            ));
        }
        if !(self.extent.is_finite() && self.extent > 0.0 && self.extent <= 100.0) {
            return Err(ParameterError::new(
                "basin extent",
                self.extent,
                "0 < extent ≤ 100 (units of the free tip amplitude)",
            ));
        }
        Ok(())
    }
}

impl BasinData {
    /// Starts that reached each orbit, and those that reached none.
    pub fn counts(&self) -> (Vec<usize>, usize) {
        let mut per = vec![0; self.orbits.len()];
        let mut none = 0;
        for r in self.reached.iter().flatten() {
            match r {
                Some(i) => per[*i] += 1,
                None => none += 1,
            }
        }
        (per, none)
    }

    /// The orbit rest (the centre start) reaches.
    pub fn from_rest(&self) -> Option<&Attractor> {
        let c = self.params.points / 2;
        self.reached[c][c].map(|i| &self.orbits[i])
    }
}

/// The basins of one cell; each finished start advances a task "basin starts".
///
/// # Errors
/// [`Error::Parameter`] for parameters out of range; the errors of the cell's search
/// ([`CellSearch::from_state`], [`CellSearch::add`]); [`Error::Interrupted`] when cancelled.
pub fn basins(p: &BasinParams, progress: &dyn Progress) -> Result<BasinData, Error> {
    p.validate()?;
    let a = &p.atlas;
    let (k, w) = (a.k_over_k1(p.cell.0), a.omega_over_w1(p.cell.1));
    let sim = Simulator::new(a.model(p.modes, k, w)?.model()?)?;
    let search = CellSearch::new(a, &sim, p.cell);
    let n = p.points;
    let axis: Vec<f64> = (0..n)
        .map(|i| p.extent * (2.0 * i as f64 / (n - 1) as f64 - 1.0))
        .collect();
    let (amplitude, velocity) = sim.model().free_tip_amplitude();
    let modes = p.modes;
    let task = progress.task("basin starts", (n * n) as u64);
    let ends: Vec<_> = (0..n * n)
        .into_par_iter()
        .map(|idx| {
            if progress.cancelled() {
                return Err(Error::Interrupted);
            }
            let (row, col) = (idx / n, idx % n);
            let mut x = DVector::zeros(2 * modes);
            // the tip moves by φ₁(1) q₁ = 2 q₁
            x[0] = 0.5 * axis[col] * amplitude;
            x[modes] = 0.5 * axis[row] * velocity;
            let orbit = search.from_state(x);
            task.advance(1);
            orbit
        })
        .collect::<Result<_, Error>>()?;
    let mut found: Vec<Found> = Vec::new();
    let mut reached = vec![vec![None; n]; n];
    for (idx, end) in ends.into_iter().enumerate() {
        if let Some(orbit) = end {
            reached[idx / n][idx % n] = Some(search.add(&mut found, orbit)?);
        }
    }
    Ok(BasinData {
        params: p.clone(),
        k_over_k1: k,
        omega_over_w1: w,
        displacement: axis.clone(),
        velocity: axis,
        orbits: found.into_iter().map(|f| f.attractor).collect(),
        reached,
    })
}
