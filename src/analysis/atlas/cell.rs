//! The attractors of one (k, ω) cell: stable periodic orbits continued from the previous
//! cell of the row, and those reached from seeded starts, each converged by shooting and
//! kept only if stable and new.

use super::{AtlasParams, Attractor, Cell};
use crate::analysis::motion::{self, MotionOptions};
use crate::analysis::orbit::{random_state, relative_residual, SplitMix64};
use crate::analysis::shooting::{self, PeriodicOrbit};
use crate::engine::sim::{Events, Simulator, Strobe};
use crate::error::Error;
use nalgebra::DVector;

/// Two converged orbits are the same when a strobe point of one matches the other's start
/// to this relative distance: both are converged to 1e-12, and distinct orbits of this
/// model differ at O(1e-2) of their size or more (measured: the closest pair of distinct
/// stable orbits met in the book's atlas are 1.3e-2 apart).
const SAME_ORBIT: f64 = 1e-6;

/// Newton steps per guess. From a settled transient or the previous cell's orbit Newton
/// converges in at most 5 steps for 97% of the converged guesses of the book's atlas (36
/// of 64 000 took all 12); a guess that needs more is not near an orbit, and each step of
/// a period-8 guess costs 8 periods or more.
const NEWTON_STEPS: usize = 12;

/// Before the last third of a transient, Newton is tried only from a start this close to
/// a period-m orbit (its strobe residual): a start so close has almost surely entered the
/// orbit's basin rather than passing near it (the tests confirm every orbit from rest by a
/// 1000-period transient).
const SETTLED: f64 = 1e-4;

/// A transient whose best strobe residual over periods 1…max_m is above this is not near
/// a periodic orbit of period ≤ max_m, and is not handed to Newton. (Newton's basin is
/// wide for this piecewise-linear map: measured, guesses with residuals of 1e-3 converge
/// in 2–5 iterations; 5e-2 leaves room and costs a failed shoot at most.)
const NEAR_PERIODIC: f64 = 5e-2;

/// A stable orbit found in the cell, with its strobe points (to recognise it again and to
/// seed the next cell).
#[derive(Debug, Clone)]
pub struct Found {
    /// What is reported.
    pub attractor: Attractor,
    /// x, P(x), …, P^{m−1}(x).
    pub strobe: Vec<DVector<f64>>,
}

/// How the motion from rest of a cell without a stable orbit of period ≤ max_m is
/// classified: the book's classification ([`MotionOptions::for_model`]) after the atlas's
/// transient (~15 ms a cell at N = 10).
pub fn motion_options(
    p: &AtlasParams,
    model: &crate::model::galerkin::GalerkinModel,
) -> MotionOptions {
    MotionOptions::for_model(model, p.transient)
}

/// What one cell needs to know.
pub struct CellSearch<'a> {
    /// The model at this (k, ω).
    pub sim: &'a Simulator,
    /// Seeded starts, the first at rest.
    pub starts: usize,
    /// Periods of transient before a start's orbit is read.
    pub transient: u64,
    /// Largest period m searched.
    pub max_period: u64,
    /// The stream seed and the cell's place (row, column).
    pub seed: (u64, u64, u64),
    /// How a motion from rest that reaches no stable orbit is classified.
    pub motion: MotionOptions,
}

impl<'a> CellSearch<'a> {
    /// The search of cell (row, column) of the atlas `p`, whose model is `sim`: its starts,
    /// transient, largest period, the cell's seed stream and the classification of a motion
    /// from rest.
    pub fn new(p: &AtlasParams, sim: &'a Simulator, (row, column): (usize, usize)) -> Self {
        Self {
            sim,
            starts: p.starts,
            transient: p.transient,
            max_period: p.max_period,
            seed: (p.seed, row as u64, column as u64),
            motion: motion_options(p, sim.model()),
        }
    }

    /// Searches the cell: first the previous cell's attractors as guesses, then the starts.
    /// Returns the cell and its orbits (the guesses of the next cell).
    ///
    /// # Errors
    /// A run that fails outside Newton ([`Error::Chatter`] beyond the contact cap in a transient,
    /// [`Error::Invariant`]) or [`Error::Flow`] for the multipliers, here or in classifying the
    /// motion from rest; a guess whose Newton fails or
    /// chatters only yields no orbit.
    pub fn run(&self, previous: &[Found]) -> Result<(Cell, Vec<Found>), Error> {
        let mut found: Vec<Found> = Vec::new();
        for guess in previous {
            if let Some(orbit) = self.converge(&guess.strobe[0], guess.attractor.period_m)? {
                let i = self.add(&mut found, orbit)?;
                found[i].attractor.continued = true;
            }
        }
        let mut from_rest = None;
        let mut unsettled = 0;
        for s in 0..self.starts {
            match self.from_start(s)? {
                Some(orbit) => {
                    let i = self.add(&mut found, orbit)?;
                    found[i].attractor.starts.push(s);
                    if s == 0 {
                        from_rest = Some(i);
                    }
                }
                None => unsettled += 1,
            }
        }
        let motion = match from_rest {
            Some(_) => None,
            None => Some(motion::classify(
                self.sim,
                &self.start(0),
                &self.motion,
                &crate::base::progress::Silent,
            )?),
        };
        let cell = Cell {
            attractors: found.iter().map(|f| f.attractor.clone()).collect(),
            from_rest,
            unsettled_starts: unsettled,
            check: None,
            motion,
        };
        Ok((cell, found))
    }

    /// Start s: rest, or a seeded random state of four times the free amplitude.
    pub fn start(&self, s: usize) -> DVector<f64> {
        let model = self.sim.model();
        let n = model.modes();
        if s == 0 {
            return DVector::zeros(2 * n);
        }
        let (row, column) = (self.seed.1, self.seed.2);
        let mut rng = SplitMix64::for_point(self.seed.0, row, column, s as u64);
        random_state(
            &mut rng,
            n,
            4.0 * model.free_tip_amplitude().0,
            self.sim.omega(),
        )
    }

    /// The stable orbit start s settles on, if its period is at most max_period. The
    /// transient runs in thirds: after each, the strobe over 2·max_m periods proposes a
    /// period m, and Newton is tried once the start is within `SETTLED` of a period-m
    /// orbit (after the last third, within `NEAR_PERIODIC`).
    ///
    /// # Errors
    /// As [`Self::run`]: a transient's [`Error::Chatter`] or [`Error::Invariant`], or an error of
    /// shooting other than non-convergence or chatter (e.g. [`Error::Flow`]).
    pub fn from_start(&self, s: usize) -> Result<Option<PeriodicOrbit>, Error> {
        self.from_state(self.start(s))
    }

    /// As [`Self::from_start`], from any state `x` at the start of cycle 0.
    ///
    /// # Errors
    /// As [`Self::from_start`].
    pub fn from_state(&self, x: DVector<f64>) -> Result<Option<PeriodicOrbit>, Error> {
        let mut x = x;
        let chunk = self.transient.div_ceil(3);
        let mut cycle = 0;
        let window = 2 * self.max_period;
        while cycle < self.transient {
            let step = chunk.min(self.transient - cycle);
            x = self
                .sim
                .run_from(&x, self.sim.clock_at_cycle(cycle as i64), step, &mut ())?
                .state;
            cycle += step;
            let mut strobe = Strobe::default();
            let clock = self.sim.clock_at_cycle(cycle as i64);
            x = self.sim.run_from(&x, clock, window, &mut strobe)?.state;
            cycle += window;
            let states = strobe.states();
            let last = &states[states.len() - 1];
            let residuals: Vec<f64> = (1..=self.max_period as usize)
                .map(|m| relative_residual(last, &states[states.len() - 1 - m]))
                .collect();
            let best = residuals.iter().copied().fold(f64::INFINITY, f64::min);
            let final_chunk = cycle >= self.transient;
            if best > if final_chunk { NEAR_PERIODIC } else { SETTLED } {
                continue;
            }
            // the smallest m about as good as the best (its multiples are as good or
            // worse while the transient decays)
            let threshold = (3.0 * best).max(1e-9);
            let m = residuals.iter().position(|&r| r <= threshold).unwrap_or(0) as u64 + 1;
            let orbit = self.converge(last, m)?;
            if orbit.is_some() || final_chunk {
                return Ok(orbit);
            }
        }
        Ok(None)
    }

    /// Shooting from a guess: the orbit (at its least period, [`shooting::shoot_within`])
    /// if Newton converges to a stable one, else None.
    fn converge(&self, guess: &DVector<f64>, m: u64) -> Result<Option<PeriodicOrbit>, Error> {
        match shooting::shoot_within(self.sim, guess, m, NEWTON_STEPS) {
            Ok(o) => Ok(Some(o).filter(|o| o.stable)),
            // Newton did not converge (a guess outside its basin, a multiplier at 1), or the
            // guess chatters on the stop beyond the contact cap: no stable orbit from it
            Err(Error::NotConverged { .. } | Error::Chatter(_)) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Starts `range` (beyond the cell's own) as a check of completeness: how many stable
    /// orbits they reach that `found` does not hold.
    ///
    /// # Errors
    /// As [`Self::from_start`], for any start of `range`.
    pub fn missed(&self, found: &[Found], range: std::ops::Range<usize>) -> Result<usize, Error> {
        let mut all = found.to_vec();
        for s in range {
            if let Some(orbit) = self.from_start(s)? {
                self.add(&mut all, orbit)?;
            }
        }
        Ok(all.len() - found.len())
    }

    /// The tip velocities of the entries into contact among `events`, in units of ωA_free.
    fn entry_velocities(&self, events: &Events) -> Vec<f64> {
        let scale = self.sim.model().free_tip_amplitude().1;
        events
            .events
            .iter()
            .filter(|e| e.entering && !e.grazing)
            .map(|e| e.tip_velocity / scale)
            .collect()
    }

    /// The entry velocities (units of ωA_free) of `orbit` over one period.
    ///
    /// # Errors
    /// The errors of the run over the orbit's period: [`Error::Parameter`] for a state of the
    /// wrong length, [`Error::Chatter`] or [`Error::Invariant`].
    pub fn impact_velocities(&self, orbit: &PeriodicOrbit) -> Result<Vec<f64>, Error> {
        let mut events = Events::default();
        let x = DVector::from_column_slice(&orbit.state);
        self.sim.run(&x, orbit.period_m, &mut events)?;
        Ok(self.entry_velocities(&events))
    }

    /// Adds an orbit unless it is one already found; returns its index.
    ///
    /// # Errors
    /// The errors of the run over the orbit's period ([`Error::Chatter`], [`Error::Invariant`]).
    pub fn add(&self, found: &mut Vec<Found>, orbit: PeriodicOrbit) -> Result<usize, Error> {
        let x = DVector::from_column_slice(&orbit.state);
        if let Some(i) = found.iter().position(|f| {
            f.attractor.period_m == orbit.period_m
                && f.strobe
                    .iter()
                    .any(|p| relative_residual(p, &x) < SAME_ORBIT)
        }) {
            return Ok(i);
        }
        // one orbit period: its strobe points (the first m) and its entries into contact
        let (mut strobe, mut events) = (Strobe::default(), Events::default());
        self.sim
            .run(&x, orbit.period_m, &mut (&mut strobe, &mut events))?;
        let mut points = strobe.states();
        points.truncate(orbit.period_m as usize);
        if points.is_empty() {
            points.push(x);
        }
        found.push(Found {
            attractor: Attractor {
                period_m: orbit.period_m,
                impacts_n: orbit.impacts_n,
                spectral_radius: orbit.spectral_radius(),
                continued: false,
                starts: Vec::new(),
                impact_velocities: self.entry_velocities(&events),
            },
            strobe: points,
        });
        Ok(found.len() - 1)
    }
}
