//! The multi-tap atlas: the stable periodic orbits of the forced compliant model (§5.2,
//! eq (37)'s forcing) over a grid of stop stiffness k and forcing frequency ω — their
//! period m (in forcing periods) and contacts per period n, and how many coexist.
//!
//! **Method.** Each row is one k, swept up in ω. A cell's attractors come from two
//! sources, every one converged by Newton shooting ([`crate::analysis::shooting`]) to the 1e-12
//! tolerance, reduced to its least period, and kept only if its Floquet multipliers are
//! inside the unit circle:
//! - *continuation*: the previous cell's attractors are the guesses at the next ω
//!   (natural continuation; an attractor is followed until it loses stability or Newton
//!   fails, as in an experiment that sweeps the frequency up slowly);
//! - *seeded starts*: rest and random states of four times the free amplitude, each run
//!   for a transient and handed to Newton with the period m read off the strobe
//!   ([`cell`]). A start that reaches no stable orbit of period ≤ max_m is counted as
//!   unsettled (quasi-periodic, chaotic, a longer period, or a slow transient).
//!
//! Orbits found twice (up to a shift along the orbit) are recognised and counted once.
//!
//! **What the other motions are.** A cell whose start from rest reaches no stable orbit of
//! period ≤ max_m is classified from rest by [`crate::analysis::motion`] with
//! [`cell::motion_options`]: chaotic, quasi-periodic, periodic after all (a longer period or a
//! slower transient), or undecided, with the Lyapunov exponents, the period and the rotation
//! number as its evidence.
//!
//! **Determinism and sharding.** A row depends only on the parameters and its index: its
//! random starts come from streams seeded by (seed, row, column, start). So the atlas
//! does not depend on the number of threads, and rows can be computed in separate
//! processes ([`Shard`]) and merged ([`merge`]) into exactly the unsharded result.
//!
//! **Convergence in N.** On every `check_stride`-th row and column, the orbit from rest
//! is also computed with `check_extra_modes` more modes; the check agrees when it has the
//! same (m, n) as the N-mode orbit from rest and impact velocities within the truncation
//! rule's tolerance.

pub mod across;
pub mod basins;
pub mod cell;
pub mod curves;
pub mod edges;
mod row;
mod shard;

pub use cell::motion_options;
pub use row::row;
pub use shard::{build, compute, compute_shard, merge, Partial, Shard, PARTIAL_FORMAT};

use crate::analysis::motion::Motion;
use crate::base::progress::Progress;
use crate::error::{self, Error, ParameterError};
use crate::model::problems::Forced;
use crate::model::ranges;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// How many modes each row (each k) uses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ModesRule {
    /// The same N at every k.
    Fixed(usize),
    /// max(`minimum`, N*(k)), N*(k) by stiffness matching, the book's one criterion: the
    /// fewest modes that give the one-contact experiment's observables (contact duration,
    /// exit tip velocity, first-mode velocity) to relative accuracy `tolerance`
    /// ([`crate::analysis::convergence::modes_needed`]). Computed at every `stride`-th
    /// row and at the last; each row takes the value of the nearest computed row at or
    /// above its k (N* grows with k, so a row never gets fewer modes than it needs).
    ///
    /// The minimum is there because one contact is not a forced orbit: at soft stops N*
    /// is 2–5, and the atlas's own check (the orbit again with ten more modes) found the
    /// forced orbits' entry velocities moving by more than 1 % from such N, where from
    /// N = 10 (the paper's truncation) they do not. The criterion is necessary, not
    /// sufficient.
    Matched {
        /// The relative accuracy of the one-contact observables.
        tolerance: f64,
        /// Rows between two computations of N*.
        stride: usize,
        /// The fewest modes any row uses.
        minimum: usize,
    },
}

/// Changes to an atlas's grid and search, as a front end gives them (None: keep).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AtlasOverrides {
    /// Rows (k values, log-spaced), 1 to 4096.
    pub k_points: Option<usize>,
    /// Columns (ω values, linear), 1 to 4096.
    pub omega_points: Option<usize>,
    /// Seeded starts per cell (the first at rest), 1 to 64.
    pub starts: Option<usize>,
    /// Seed of the random starts.
    pub seed: Option<u64>,
    /// The same N at every k, 1 to 400 (instead of N matched to k).
    pub modes: Option<usize>,
    /// The relative accuracy of one contact that sets N at each k, 1e-6 to 0.5.
    pub modes_tolerance: Option<f64>,
    /// Boundary curves traced at most, 0 to 256 (0: none); twice as many seeds are tried.
    pub curves: Option<usize>,
    /// Edges the curves leave checked one by one at most, 0 to 4096 (0: none).
    pub edge_checks: Option<usize>,
}

/// What the atlas computes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtlasParams {
    /// N of each row: fixed, or matched to k.
    pub modes: ModesRule,
    /// k/k₁ range (log-spaced, inclusive).
    pub k_over_k1_range: (f64, f64),
    /// Rows (k values).
    pub k_points: usize,
    /// ω/(β₁⁻)² range (linear, inclusive).
    pub omega_range: (f64, f64),
    /// Columns (ω values).
    pub omega_points: usize,
    /// ζ₁.
    pub zeta1: f64,
    /// d₀.
    pub gap: f64,
    /// Seeded starts per cell (the first at rest).
    pub starts: usize,
    /// Transient periods of each start.
    pub transient: u64,
    /// Largest period m searched.
    pub max_period: u64,
    /// Seed of the random starts.
    pub seed: u64,
    /// The convergence check uses the row's N plus this many modes.
    pub check_extra_modes: usize,
    /// Every `check_stride`-th row and column is checked.
    pub check_stride: usize,
    /// Further random starts on checked cells, to estimate how many attractors the cells'
    /// own starts miss.
    pub check_starts: usize,
    /// The boundary curves, each traced at the N of its band of rows ([`curves`]).
    pub curves: curves::CurveSearch,
}

impl AtlasParams {
    /// The book's atlas: k/k₁ 1…10⁴ × ω/(β₁⁻)² 0.5…3 at 128 × 128, Figure 4's ζ₁ = 0.01
    /// and d₀ = 0; N matched to k (1 % accuracy of one contact, N* computed every 8th
    /// row, at least 10); rest and two random starts per cell; checked with 10 more modes.
    pub fn book() -> Self {
        Self {
            modes: ModesRule::Matched {
                tolerance: 1e-2,
                stride: 8,
                minimum: 10,
            },
            k_over_k1_range: (1.0, 1e4),
            k_points: 128,
            omega_range: (0.5, 3.0),
            omega_points: 128,
            zeta1: 0.01,
            gap: 0.0,
            starts: 3,
            transient: 300,
            max_period: 8,
            seed: 2013,
            check_extra_modes: 10,
            check_stride: 16,
            check_starts: 16,
            // 30 curves over the map's three bands of N take about 18 s on two cores and
            // account for 40 % of its boundary edges (measured 2026-11-30: 20 take 9 s for
            // 28 %, 40 take 35 s for 49 %); checking 128 of the edges they leave takes
            // about 9 s and bounds the share located to about ±4 %
            curves: curves::CurveSearch {
                max_curves: 30,
                max_seeds: 60,
                max_points: 120,
                round: 4,
                edge_sample: 128,
            },
        }
    }

    /// A reduced atlas for the tests: 9 × 9 cells over the same ranges, N* computed on
    /// every other row (the book's stride of 8 would leave two of nine rows computed).
    pub fn test() -> Self {
        let book = Self::book();
        Self {
            modes: match book.modes {
                ModesRule::Matched {
                    tolerance, minimum, ..
                } => ModesRule::Matched {
                    tolerance,
                    stride: 2,
                    minimum,
                },
                fixed => fixed,
            },
            k_points: 9,
            omega_points: 9,
            check_stride: 4,
            check_starts: 4,
            curves: curves::CurveSearch {
                max_curves: 2,
                max_seeds: 4,
                max_points: 30,
                round: 2,
                edge_sample: 4,
            },
            ..book
        }
    }

    /// These parameters with a front end's changes to the grid and search, checked.
    ///
    /// # Errors
    /// [`ParameterError`] naming the first parameter out of range, or both a fixed N and a
    /// tolerance for matching N given.
    pub fn with_overrides(&self, o: &AtlasOverrides) -> Result<Self, ParameterError> {
        let mut p = self.clone();
        if let Some(v) = o.k_points {
            p.k_points = v;
        }
        if let Some(v) = o.omega_points {
            p.omega_points = v;
        }
        if let Some(v) = o.starts {
            p.starts = v;
        }
        if let Some(v) = o.seed {
            p.seed = v;
        }
        if let Some(v) = o.curves {
            p.curves.max_curves = v;
            p.curves.max_seeds = 2 * v;
        }
        if let Some(v) = o.edge_checks {
            // the edges checked are those the curves leave: with no curves, none are checked
            if v > 0 && p.curves.max_curves == 0 {
                return Err(ParameterError::new(
                    "edge_checks",
                    v,
                    "0 when no curves are traced",
                ));
            }
            p.curves.edge_sample = v;
        }
        match (o.modes, o.modes_tolerance, p.modes) {
            (Some(_), Some(t), _) => {
                return Err(ParameterError::new(
                    "modes_tolerance",
                    error::number(t),
                    "no tolerance with a fixed N (modes): N is either fixed or matched to k",
                ))
            }
            (Some(n), None, _) => p.modes = ModesRule::Fixed(n),
            (
                None,
                Some(t),
                ModesRule::Matched {
                    stride, minimum, ..
                },
            ) => {
                p.modes = ModesRule::Matched {
                    tolerance: t,
                    stride,
                    minimum,
                }
            }
            (None, Some(t), ModesRule::Fixed(_)) => {
                return Err(ParameterError::new(
                    "modes_tolerance",
                    error::number(t),
                    "no tolerance for an atlas of fixed N",
                ))
            }
            (None, None, _) => {}
        }
        p.validate()?;
        Ok(p)
    }

    /// Every count in range, the ranges positive and increasing.
    ///
    /// # Errors
    /// [`ParameterError`] naming the first parameter out of range.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self.modes {
            ModesRule::Fixed(n) => {
                error::count_in_range("modes (N)", n, crate::model::galerkin::MAX_MODES)?;
            }
            ModesRule::Matched {
                tolerance,
                stride,
                minimum,
            } => {
                error::count_in_range("modes minimum", minimum, crate::model::galerkin::MAX_MODES)?;
                if !(1e-6..=0.5).contains(&tolerance) {
                    return Err(ParameterError::new(
                        "modes_tolerance",
                        error::number(tolerance),
                        "a relative accuracy from 1e-6 to 0.5",
                    ));
                }
                error::count_in_range("modes stride", stride, 4096)?;
            }
        }
        error::count_in_range("check_extra_modes", self.check_extra_modes, 100)?;
        error::count_in_range("k_points", self.k_points, 4096)?;
        error::count_in_range("omega_points", self.omega_points, 4096)?;
        error::count_in_range("starts", self.starts, 64)?;
        error::count_in_range("check_stride", self.check_stride, 4096)?;
        error::count_in_range("check_starts", self.check_starts, 1024)?;
        let c = &self.curves;
        if c.max_curves > 256 {
            return Err(ParameterError::new("curves", c.max_curves, "0 to 256"));
        }
        if c.max_seeds > 1024 || (c.max_curves > 0 && c.max_seeds == 0) {
            return Err(ParameterError::new(
                "curve seeds",
                c.max_seeds,
                "0 to 1024, and at least 1 when curves are traced",
            ));
        }
        if c.edge_sample > 4096 {
            return Err(ParameterError::new(
                "edge_checks",
                c.edge_sample,
                "0 to 4096",
            ));
        }
        if !(2..=2000).contains(&c.max_points) {
            return Err(ParameterError::new(
                "curve points",
                c.max_points,
                "2 to 2000",
            ));
        }
        error::count_in_range("curve seeds per round", c.round, 64)?;
        error::count_in_range("max_period", self.max_period as usize, 32)?;
        if !(1..=1_000_000).contains(&self.transient) {
            return Err(ParameterError::new(
                "transient",
                self.transient,
                "1 to 1000000",
            ));
        }
        for (name, (lo, hi)) in [
            ("k/k₁ range", self.k_over_k1_range),
            ("ω/(β₁⁻)² range", self.omega_range),
        ] {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
                return Err(ParameterError::new(
                    name,
                    format!("{lo}..{hi}"),
                    "0 < lower ≤ upper, finite",
                ));
            }
        }
        // ζ₁ and d₀ in the ranges every model takes (a shard with d₀ = 1e300 or ζ₁ = 0 is
        // not an atlas of this model); the model checks k and ω at the grid's corners
        ranges::ZETA1.check(self.zeta1)?;
        ranges::GAP.check(self.gap)?;
        // each end of the ranges named as given (a model of ω = 1e308 would report ω as inf)
        for omega in [self.omega_range.0, self.omega_range.1] {
            ranges::OMEGA.check(omega)?;
        }
        for k in [self.k_over_k1_range.0, self.k_over_k1_range.1] {
            ranges::STOP_STIFFNESS.check(k)?;
        }
        self.model(1, self.k_over_k1_range.1, self.omega_range.1)?;
        self.model(1, self.k_over_k1_range.0, self.omega_range.0)?;
        Ok(())
    }

    /// N of every row (see [`ModesRule`]). For a matched rule this runs the one-contact
    /// experiment at each computed row (about 0.4 CPU-s each, in parallel).
    ///
    /// # Errors
    /// For a matched rule, the errors of
    /// [`crate::analysis::convergence::matched_modes`] at a computed row: [`Error::Unsupported`]
    /// when N* is unresolved or above the model's largest N, or a parameter out of range.
    pub fn modes_by_row(&self) -> Result<Vec<usize>, Error> {
        self.modes_by_row_reporting(&crate::base::progress::Silent)
    }

    /// [`Self::modes_by_row`], reporting the computed rows to `progress` (a task "atlas:
    /// modes by stiffness matching") and stopping with [`Error::Interrupted`] before the
    /// next row when it is cancelled.
    ///
    /// # Errors
    /// As [`Self::modes_by_row`]; [`Error::Interrupted`].
    pub fn modes_by_row_reporting(&self, progress: &dyn Progress) -> Result<Vec<usize>, Error> {
        let (tolerance, stride, minimum) = match self.modes {
            ModesRule::Fixed(n) => return Ok(vec![n; self.k_points]),
            ModesRule::Matched {
                tolerance,
                stride,
                minimum,
            } => (tolerance, stride, minimum),
        };
        let mut computed: Vec<usize> = (0..self.k_points).step_by(stride).collect();
        if computed.last() != Some(&(self.k_points - 1)) {
            computed.push(self.k_points - 1);
        }
        let task = progress.task("atlas: modes by stiffness matching", computed.len() as u64);
        let needed: Vec<usize> = computed
            .par_iter()
            .map(|&i| {
                if progress.cancelled() {
                    return Err(Error::Interrupted);
                }
                let n = crate::analysis::convergence::matched_modes(
                    self.k_over_k1(i),
                    tolerance,
                    self.zeta1,
                    minimum,
                )?;
                task.advance(1);
                Ok(n)
            })
            .collect::<Result<_, Error>>()?;
        drop(task);
        Ok((0..self.k_points)
            .map(|i| {
                let at = computed
                    .iter()
                    .position(|&c| c >= i)
                    .unwrap_or(computed.len() - 1);
                // (and never fewer than a computed row below: N* is monotone in k, but a
                // scan's answer may dip by a step)
                needed[..=at].iter().copied().max().unwrap_or(minimum)
            })
            .collect())
    }

    /// The relative accuracy that a checked cell's impact velocities must meet between
    /// N and N + `check_extra_modes` (the matched rule's tolerance; 1 % for a fixed N).
    pub fn check_tolerance(&self) -> f64 {
        match self.modes {
            ModesRule::Matched { tolerance, .. } => tolerance,
            ModesRule::Fixed(_) => 1e-2,
        }
    }

    /// The k/k₁ of row i (log-spaced).
    pub fn k_over_k1(&self, i: usize) -> f64 {
        let (lo, hi) = self.k_over_k1_range;
        if self.k_points == 1 {
            return lo;
        }
        lo * (hi / lo).powf(i as f64 / (self.k_points - 1) as f64)
    }

    /// The ω/(β₁⁻)² of column j (linear).
    pub fn omega_over_w1(&self, j: usize) -> f64 {
        let (lo, hi) = self.omega_range;
        if self.omega_points == 1 {
            return lo;
        }
        lo + (hi - lo) * j as f64 / (self.omega_points - 1) as f64
    }

    /// The forced model at N modes, k/k₁ and ω/(β₁⁻)².
    ///
    /// # Errors
    /// [`ParameterError`] when the model refuses N, k, ω or the grid's ζ₁ and d₀
    /// ([`Forced::model`]).
    pub fn model(&self, modes: usize, k: f64, omega: f64) -> Result<Forced, ParameterError> {
        let f = Forced {
            modes,
            k_over_k1: k,
            zeta1: self.zeta1,
            omega_over_w1: omega,
            gap: self.gap,
            printed_eq37_amplitude: false,
        };
        f.model()?;
        Ok(f)
    }
}

/// A stable periodic orbit of a cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Attractor {
    /// m: forcing periods per orbit period (least).
    pub period_m: u64,
    /// n: entries into contact per orbit period.
    pub impacts_n: usize,
    /// The largest Floquet multiplier modulus (< 1).
    pub spectral_radius: f64,
    /// Reached by continuation from the previous cell of the row.
    pub continued: bool,
    /// The seeded starts that reached it (0 = rest).
    pub starts: Vec<usize>,
    /// The tip velocities of its entries into contact over one orbit period, in units of
    /// ωA_free (the free tip velocity amplitude at the cell's ω), in the order they occur.
    pub impact_velocities: Vec<f64>,
}

impl Attractor {
    /// Contacts per forcing period, n/m.
    pub fn taps_per_period(&self) -> f64 {
        self.impacts_n as f64 / self.period_m as f64
    }
}

/// The convergence check of a cell: the orbit from rest with more modes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    /// The number of modes it used.
    pub modes: usize,
    /// Its (m, n), if start 0 reached a stable orbit.
    pub from_rest: Option<(u64, usize)>,
    /// The largest difference of the entry velocities (sorted) between the cell's orbit
    /// from rest and this one, relative to the largest of them, when both have the same
    /// (m, n).
    pub impact_velocity_change: Option<f64>,
    /// Stable orbits (N modes) reached from `check_starts` further random starts that the
    /// cell's search did not find.
    pub missed: usize,
}

/// One (k, ω) cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    /// The distinct stable orbits found, continued ones first.
    pub attractors: Vec<Attractor>,
    /// Which of them start 0 (rest) reached.
    pub from_rest: Option<usize>,
    /// Starts that reached no stable orbit of period ≤ max_m.
    pub unsettled_starts: usize,
    /// The convergence check, on checked cells.
    pub check: Option<Check>,
    /// What the motion from rest is, on cells where rest reaches no stable orbit of period
    /// ≤ max_m ([`cell::motion_options`]).
    pub motion: Option<Motion>,
}

impl Cell {
    /// The orbit reached from rest.
    pub fn rest(&self) -> Option<&Attractor> {
        self.from_rest.map(|i| &self.attractors[i])
    }

    /// Whether the check's orbit from rest is the cell's: the same (m, n) as the cell's
    /// orbit from rest, with entry velocities within `tolerance` of it (None when the
    /// cell is not checked). Both unsettled also agree.
    pub fn check_agrees(&self, tolerance: f64) -> Option<bool> {
        let c = self.check.as_ref()?;
        Some(match (c.from_rest, self.rest()) {
            (Some((m, n)), Some(a)) => {
                a.period_m == m
                    && a.impacts_n == n
                    && c.impact_velocity_change.is_some_and(|d| d <= tolerance)
            }
            (None, None) => true,
            _ => false,
        })
    }
}

/// One row: a k and its cells along ω.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The row's index.
    pub index: usize,
    /// k/k₁.
    pub k_over_k1: f64,
    /// N, the modes this row uses.
    pub modes: usize,
    /// Cells in increasing ω.
    pub cells: Vec<Cell>,
}

/// The atlas.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtlasData {
    /// The parameters.
    pub params: AtlasParams,
    /// ω/(β₁⁻)² of the columns.
    pub omega_over_w1: Vec<f64>,
    /// The rows, in increasing k.
    pub rows: Vec<Row>,
    /// The boundary curves, each at the N of its band of rows (None until traced: a merge
    /// of shards gives the rows, [`with_curves`] the curves).
    pub curves: Option<curves::BoundaryCurves>,
}

/// The atlas with its boundary curves traced ([`curves::trace`]).
///
/// # Errors
/// As [`curves::trace`]: [`Error::Interrupted`] when cancelled.
pub fn with_curves(mut d: AtlasData, progress: &dyn Progress) -> Result<AtlasData, Error> {
    d.curves = Some(curves::trace(&d, &d.params.curves, progress)?);
    Ok(d)
}
