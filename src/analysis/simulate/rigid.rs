//! The rigid-impact model's run behind [`super::simulate`] (§3): impacts recorded in the
//! window, chatter and sticking reported as the run's ending, dense samples on request.

use super::*;

/// Dense samples of a rigid run, taken inside its flights and sticking phases; passes the
/// caller's cancellation to the run.
struct RigidSamples<'a> {
    per_period: Option<usize>,
    out: DenseOutput,
    progress: &'a dyn Progress,
}

impl RigidSamples<'_> {
    fn sample(&mut self, model: &RigidImpact, t: f64, contact: bool, x: &DVector<f64>) {
        let tip = model.sim.model().tip();
        let n = tip.len();
        let (d, v) = (tip.dot(&x.rows(0, n)), tip.dot(&x.rows(n, n)));
        self.out.push(t, contact, d, v, x);
    }
}

impl RigidObserver for RigidSamples<'_> {
    fn flight(&mut self, model: &RigidImpact, start: &Clock, x: &DVector<f64>, duration: f64) {
        let Some(per) = self.per_period else { return };
        for (s, t) in start.grid(duration, per) {
            self.sample(model, t, false, &model.coast(x, start, s));
        }
    }
    fn held(&mut self, model: &RigidImpact, start: &Clock, x: &DVector<f64>, duration: f64) {
        let Some(per) = self.per_period else { return };
        for (s, t) in start.grid(duration, per) {
            self.sample(model, t, true, &model.held(x, start, s));
        }
    }
    fn interrupted(&self) -> bool {
        self.progress.cancelled()
    }
}

pub(super) fn rigid(
    model: &RigidImpact,
    x0: &DVector<f64>,
    options: &SimulateOptions,
    task: &dyn Task,
    progress: &dyn Progress,
) -> Result<Simulation, Error> {
    let period = model.sim.period();
    let modes = model.sim.model().modes();
    let (mut x, mut cycle) = (x0.clone(), 0i64);
    let mut outcome = Outcome::Completed;
    let mut final_clock = Clock::at_cycle(period, 0);
    let (mut events, mut strobe) = (Vec::new(), Vec::new());
    let keep = options.period_search_depth() + 1;
    let mut samples = RigidSamples {
        per_period: None,
        out: DenseOutput::default(),
        progress,
    };
    let total = options.periods + options.record;
    let mut done = 0u64;
    while done < total && outcome == Outcome::Completed {
        // the transient in chunks, the window period by period (its strobe)
        let recording = done >= options.periods;
        let step = if recording {
            1
        } else {
            (options.periods - done).min(CHUNK)
        };
        if recording && strobe.is_empty() {
            strobe.push(x.clone());
            samples.per_period = options.dense_per_period;
        }
        let r = model.run_observed(
            &x,
            Clock::at_cycle(period, cycle),
            Clock::at_cycle(period, cycle + step as i64),
            &mut samples,
        )?;
        if recording {
            events.extend(r.events.iter().filter_map(|e| impact(e, period)));
            if events.len() * (2 * modes + 6) > MAX_EVENT_NUMBERS {
                return Err(too_many_events(options, events.len(), modes));
            }
        }
        (outcome, x, final_clock) = (r.outcome, r.state, r.clock);
        if outcome == Outcome::Completed {
            cycle += step as i64;
            done += step;
            if recording {
                strobe.push(x.clone());
                if strobe.len() > keep {
                    strobe.remove(0);
                }
            }
        }
        task.advance(step);
    }
    let ending = match outcome {
        Outcome::Completed => Ending::Completed,
        Outcome::Chatter(t) => Ending::Chatter(t),
        Outcome::ImpactLimit => Ending::ImpactLimit,
    };
    // a run that stopped before its window began recorded nothing: that is no result
    let window_start = options.periods as f64 * period;
    if ending != Ending::Completed && (done < options.periods || final_clock.time() <= window_start)
    {
        let when = match ending {
            Ending::Chatter(t) if t < window_start => {
                format!("at t = {t}, before its window (from t = {window_start})")
            }
            Ending::Chatter(t) => format!("at t = {t}, as its window began"),
            _ => format!("before its window (from t = {window_start})"),
        };
        let why = match ending {
            Ending::ImpactLimit => "more impacts than the policy's limit",
            _ => CHATTER,
        };
        return Err(Error::Chatter(format!(
            "nothing recorded: the run stopped {when}: {why}"
        )));
    }
    let dense = options.dense_per_period.map(|_| {
        if ending != Ending::Completed {
            // the last sample is the stop itself
            samples.sample(model, final_clock.time(), model.at_rest_on_stop(&x), &x);
        }
        samples.out
    });
    let (period_m, periodicity_residual, max_period_searched) = period_search(options, &strobe);
    let impacts = |from: i64| events.iter().filter(|e| e.cycle >= from).count() as u64;
    let counted: Vec<(i64, bool)> = events.iter().map(|e| (e.cycle, true)).collect();
    Ok(Simulation {
        impacts_n_range: period_m.map(|m| impacts_range(&counted, cycle, m, options.record)),
        impacts_n: period_m.map(|m| impacts(cycle - m as i64)),
        contacts_in_window: impacts(cycle - options.record as i64),
        shallow_flights: 0,
        flight_resolution: 0.0,
        events,
        period_m,
        periodicity_residual,
        max_period_searched,
        max_tip: None,
        energy_imbalance: None,
        energy_imbalance_bound: None,
        condition: 0.0,
        ending,
        final_clock,
        final_state: x,
        dense,
        wall_seconds: 0.0,
    })
}

/// A rigid run's impact as an event of the window.
fn impact(e: &RigidEvent, period: f64) -> Option<SimEvent> {
    let RigidEvent::Impact {
        time,
        incoming,
        outgoing,
        before,
        after,
    } = e
    else {
        return None;
    };
    let c = Clock::at_time(period, *time);
    Some(SimEvent {
        time: *time,
        cycle: c.cycles,
        phase: c.offset / period,
        entering: true,
        grazing: false,
        tip_velocity: *incoming,
        outgoing_tip_velocity: Some(*outgoing),
        modal_velocities: before.clone(),
        modal_velocities_after: Some(after.clone()),
    })
}
