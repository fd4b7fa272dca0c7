//! One interface for every model variant: the stroboscopic map P (§5.2), the state sampled
//! once per forcing period, with what happened on the way. Implemented by the compliant
//! Galerkin model and every model built with `GalerkinModel::from_modes` (the
//! finite-element beam) through [`Simulator`], by the rigid-impact model with any law
//! ([`RigidImpact`]) and by the two-basis truncation ([`TwoBasisModel`]). The analyses —
//! settling and period detection ([`crate::analysis::orbit`]), Newton shooting and Floquet
//! multipliers ([`crate::analysis::shooting`]) — are written once against it.
//!
//! A model that cannot give the Jacobian of P^m (the two-basis truncation: its switches
//! project the state, and the projection's derivative at a switch is not derived here)
//! says so through [`PeriodMap::map_with_jacobian`]'s error rather than guess.

use crate::base::progress::{Progress, Task};
use crate::engine::rigid::{Outcome, RigidEvent, RigidImpact};
use crate::engine::sim::{Clock, Events, Simulator, Strobe};
use crate::engine::ticker::Ticker;
use crate::engine::two_basis::{TwoBasisModel, TwoBasisState};
use crate::error::{Error, ParameterError};
use crate::model::galerkin::Region;
use nalgebra::{DMatrix, DVector};

/// ‖a − b‖∞ / max(‖a‖∞, ‖b‖∞) (0 when both are zero): §5.2's periodicity test on the
/// orbit's own scale; ∞ for vectors of different lengths (never the same state).
pub fn relative_residual(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let scale = a.amax().max(b.amax());
    if scale == 0.0 {
        0.0
    } else {
        (a - b).amax() / scale
    }
}

/// What `periods` applications of P recorded.
#[derive(Debug, Clone, Default)]
pub struct Periods {
    /// The state after the last period.
    pub state: DVector<f64>,
    /// The state at each period boundary, the start included (when recorded).
    pub strobe: Vec<DVector<f64>>,
    /// Entries into contact (impacts, for the rigid model) in each period, grazing touches
    /// excluded (when recorded).
    pub entries: Vec<u64>,
    /// The tip velocity of each entry into contact, in order, in the model's units (when
    /// recorded).
    pub entry_velocities: Vec<f64>,
    /// Chatters (impacts accumulating in finite time, the rigid model) in all (when
    /// recorded).
    pub chatters: u64,
}

/// A model advanced by whole forcing periods: the stroboscopic map P, x ↦ x(t₀ + T).
pub trait PeriodMap: Sync {
    /// What the model is, for messages ("the compliant model", "the rigid-impact model").
    fn name(&self) -> String;
    /// The length of a state.
    fn dimension(&self) -> usize;
    /// The forcing period T.
    fn period(&self) -> f64;
    /// The state at rest (undeflected, no velocity).
    fn rest(&self) -> DVector<f64> {
        DVector::zeros(self.dimension())
    }
    /// P^`periods` of `x` taken at the start of forcing cycle `cycle`; with `record`, the
    /// strobe, the entries into contact per period and their tip velocities too.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a bad state; a run's failure: [`Error::Chatter`] (contacts beyond
    /// a period's cap, or a rigid chatter with no sticking limit or past the impact limit),
    /// [`Error::Invariant`] or [`Error::Interrupted`].
    fn advance(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        record: bool,
    ) -> Result<Periods, Error>;
    /// P^`periods` of `x` from cycle `cycle`, as [`Self::advance`] without recording gives
    /// it, reporting the periods done to `task` and ending with [`Error::Interrupted`] when
    /// `progress` is cancelled (a transient of 10⁸ periods must show its progress and stop
    /// on Ctrl-C). By default the whole run is one report at its end.
    ///
    /// # Errors
    /// As [`Self::advance`]; [`Error::Interrupted`].
    fn advance_reporting(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        task: &dyn Task,
        progress: &dyn Progress,
    ) -> Result<DVector<f64>, Error> {
        if progress.cancelled() {
            return Err(Error::Interrupted);
        }
        let state = self.advance(x, cycle, periods, false)?.state;
        task.advance(periods);
        Ok(state)
    }
    /// How far apart two states are, relative to their size (∞ if they cannot be the same
    /// point of the orbit).
    fn residual(&self, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
        relative_residual(a, b)
    }
    /// P^m(x) from the start of cycle 0, its Jacobian (the monodromy matrix) and the
    /// entries into contact on the way.
    ///
    /// # Errors
    /// [`Error::Unsupported`] by default (a model without a Jacobian); an implementation's run
    /// errors otherwise, and [`Error::Chatter`] for a rigid orbit that chatters or sticks.
    fn map_with_jacobian(
        &self,
        _x: &DVector<f64>,
        _m: u64,
    ) -> Result<(DVector<f64>, DMatrix<f64>, u64), Error> {
        Err(Error::Unsupported(format!(
            "{} gives no Jacobian of its period map: shooting and Floquet multipliers need one",
            self.name()
        )))
    }
    /// Checks a state: its length and that every entry is finite.
    ///
    /// # Errors
    /// [`ParameterError`] naming `what` for a state of the wrong length or with an entry that is
    /// not finite.
    fn check_state(&self, what: &str, x: &DVector<f64>) -> Result<(), ParameterError> {
        if x.len() != self.dimension() {
            return Err(ParameterError::new(
                what,
                format!("a vector of length {}", x.len()),
                &format!("a state of length {} for {}", self.dimension(), self.name()),
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(ParameterError::new(
                what,
                format!("entry {i} = {}", x[i]),
                "finite entries",
            ));
        }
        Ok(())
    }
}

impl PeriodMap for Simulator {
    fn name(&self) -> String {
        format!("the {}-mode compliant model", self.model().modes())
    }
    fn dimension(&self) -> usize {
        2 * self.model().modes()
    }
    fn period(&self) -> f64 {
        Simulator::period(self)
    }
    fn advance(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        record: bool,
    ) -> Result<Periods, Error> {
        let start = self.clock_at_cycle(cycle);
        // (`advance_reporting` makes this same run, observed)
        if !record {
            let state = self.run_from(x, start, periods, &mut ())?.state;
            return Ok(Periods {
                state,
                ..Periods::default()
            });
        }
        let (mut events, mut strobe) = (Events::default(), Strobe::default());
        let state = self
            .run_from(x, start, periods, &mut (&mut events, &mut strobe))?
            .state;
        let mut entries = vec![0; periods as usize];
        let mut entry_velocities = Vec::new();
        for e in events.events.iter().filter(|e| e.entering && !e.grazing) {
            let k = (e.clock.cycles - cycle).clamp(0, periods as i64 - 1) as usize;
            entries[k] += 1;
            entry_velocities.push(e.tip_velocity);
        }
        Ok(Periods {
            state,
            strobe: strobe.states(),
            entries,
            entry_velocities,
            chatters: 0,
        })
    }
    fn advance_reporting(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        task: &dyn Task,
        progress: &dyn Progress,
    ) -> Result<DVector<f64>, Error> {
        let mut ticker = Ticker::new(task, progress, cycle);
        Ok(self
            .run_from(x, self.clock_at_cycle(cycle), periods, &mut ticker)?
            .state)
    }
    fn map_with_jacobian(
        &self,
        x: &DVector<f64>,
        m: u64,
    ) -> Result<(DVector<f64>, DMatrix<f64>, u64), Error> {
        let (mut mono, mut events) = (crate::engine::sim::Monodromy::default(), Events::default());
        let end = self.run(x, m, &mut (&mut mono, &mut events))?;
        let entries = events
            .events
            .iter()
            .filter(|e| e.entering && !e.grazing)
            .count() as u64;
        let dim = x.len();
        Ok((
            end.state,
            mono.matrix.unwrap_or_else(|| DMatrix::identity(dim, dim)),
            entries,
        ))
    }
}

impl PeriodMap for RigidImpact {
    fn name(&self) -> String {
        format!("the {}-mode rigid-impact model", self.sim.model().modes())
    }
    fn dimension(&self) -> usize {
        2 * self.sim.model().modes()
    }
    fn period(&self) -> f64 {
        self.sim.period()
    }
    fn advance(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        record: bool,
    ) -> Result<Periods, Error> {
        let period = self.sim.period();
        let mut out = Periods {
            state: x.clone(),
            ..Periods::default()
        };
        if record {
            out.strobe.push(x.clone());
        }
        // period by period when recording (the strobe), in one run otherwise
        let steps: Vec<(i64, i64)> = if record {
            (0..periods as i64)
                .map(|c| (cycle + c, cycle + c + 1))
                .collect()
        } else {
            vec![(cycle, cycle + periods as i64)]
        };
        for (a, b) in steps {
            let run = self.run_until(
                &out.state,
                Clock::at_cycle(period, a),
                Clock::at_cycle(period, b),
            )?;
            completed(self, run.outcome)?;
            if record {
                let mut count = 0;
                for e in &run.events {
                    match e {
                        RigidEvent::Impact { incoming, .. } => {
                            count += 1;
                            out.entry_velocities.push(*incoming);
                        }
                        RigidEvent::Chatter { .. } => out.chatters += 1,
                        _ => {}
                    }
                }
                out.entries.push(count);
                out.strobe.push(run.state.clone());
            }
            out.state = run.state;
        }
        Ok(out)
    }
    fn advance_reporting(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        task: &dyn Task,
        progress: &dyn Progress,
    ) -> Result<DVector<f64>, Error> {
        // the one run `advance` makes without recording, observed
        let period = self.sim.period();
        let run = self.run_observed(
            x,
            Clock::at_cycle(period, cycle),
            Clock::at_cycle(period, cycle + periods as i64),
            &mut Ticker::new(task, progress, cycle),
        )?;
        completed(self, run.outcome)?;
        Ok(run.state)
    }
    fn map_with_jacobian(
        &self,
        x: &DVector<f64>,
        m: u64,
    ) -> Result<(DVector<f64>, DMatrix<f64>, u64), Error> {
        RigidImpact::map_with_jacobian(self, x, m)
    }
}

/// A rigid run that did not complete, as the error of the period map: after a chatter with
/// no sticking limit, or past the impact limit, the state is not defined.
fn completed(model: &RigidImpact, outcome: Outcome) -> Result<(), Error> {
    match outcome {
        Outcome::Completed => Ok(()),
        Outcome::Chatter(t) => Err(Error::Chatter(format!(
            "{} chatters at t = {t:.6e} under a law with no sticking limit (N > 1 with [R]_N \
             or [R]_C): the state after it is not defined",
            model.name()
        ))),
        Outcome::ImpactLimit => Err(Error::Chatter(format!(
            "{} made more than {} impacts between sticking phases, or {} in one forcing period",
            model.name(),
            model.settings.max_impacts,
            model.settings.max_impacts_per_period
        ))),
    }
}

/// The two-basis model's state as one vector: the modal state in the basis of its region,
/// then 0 (free basis) or 1 (constrained basis).
fn pack(s: &TwoBasisState) -> DVector<f64> {
    let n = s.x.len();
    let mut v = DVector::zeros(n + 1);
    v.rows_mut(0, n).copy_from(&s.x);
    v[n] = if s.region == Region::Contact {
        1.0
    } else {
        0.0
    };
    v
}

fn unpack(v: &DVector<f64>) -> TwoBasisState {
    let n = v.len() - 1;
    TwoBasisState {
        region: if v[n] == 1.0 {
            Region::Contact
        } else {
            Region::Free
        },
        x: v.rows(0, n).into_owned(),
    }
}

impl PeriodMap for TwoBasisModel {
    fn name(&self) -> String {
        format!("the {}-mode two-basis model", self.modes())
    }
    /// 2N modal coordinates in the basis of the region, and the region (0 free, 1 contact).
    fn dimension(&self) -> usize {
        2 * self.modes() + 1
    }
    fn period(&self) -> f64 {
        TwoBasisModel::period(self)
    }
    /// At rest, in the region the start rule gives (in contact when d₀ ≤ 0).
    fn rest(&self) -> DVector<f64> {
        pack(&self.start(&DVector::zeros(2 * self.modes()), 0.0).0)
    }
    fn advance(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        record: bool,
    ) -> Result<Periods, Error> {
        self.check_state("state", x)?;
        let period = TwoBasisModel::period(self);
        let clock = |c: i64| Clock::at_cycle(period, c);
        let mut state = unpack(x);
        let mut out = Periods::default();
        if !record {
            state = self
                .run_until(state, clock(cycle), clock(cycle + periods as i64))?
                .state;
            out.state = pack(&state);
            return Ok(out);
        }
        out.strobe.push(x.clone());
        for c in 0..periods as i64 {
            let run = self.run_until(state, clock(cycle + c), clock(cycle + c + 1))?;
            let entering: Vec<f64> = run
                .switches
                .iter()
                .filter(|s| s.entering)
                .map(|s| s.tip_velocity)
                .collect();
            out.entries.push(entering.len() as u64);
            out.entry_velocities.extend(entering);
            state = run.state;
            out.strobe.push(pack(&state));
        }
        out.state = pack(&state);
        Ok(out)
    }
    /// Samples in different bases are never the same point of an orbit.
    fn residual(&self, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
        if a.len() != b.len() || a.is_empty() {
            return f64::INFINITY;
        }
        let n = a.len() - 1;
        if a[n] != b[n] {
            return f64::INFINITY;
        }
        relative_residual(&a.rows(0, n).into_owned(), &b.rows(0, n).into_owned())
    }
}
