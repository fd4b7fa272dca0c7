//! Periodic orbits of the forced bilinear model (§5.2–5.3): the stroboscopic Poincaré map
//! (ωt = 0 mod 2π), period detection, and the impact section (d = d₀, ḋ > 0).
//!
//! **Norm.** §5.2 calls an orbit period-m if ‖x(t₀ + 2πm/ω) − x(t₀)‖ < 1e-9. We use the max
//! norm *relative* to ‖x(t₀)‖∞. With d₀ = 0 the model is positively homogeneous (scaling the
//! forcing scales every orbit), and the paper's printed forcing amplitude is off by a factor
//! 1/(4ζ₁²) (errata E2), so an absolute threshold would mean different things at different
//! amplitudes; the relative one does not.
//!
//! An orbit is labelled (m, n): period m forcing cycles, n entries into contact per period.
//! When no m ≤ 32 passes, the orbit is reported as not periodic with its best residual —
//! quasi-periodic, chaotic, or not yet settled — rather than forced into a label. Near a
//! bifurcation the bare test can mislabel a slowly converging orbit (a period-d orbit near
//! its period doubling passes at 2d first); there Newton shooting decides ([`label`]).

pub use crate::base::random::{random_state, SplitMix64};
use crate::engine::map::{PeriodMap, Periods};
use crate::engine::sim::{Dense, Event, Events, Sample, Simulator, Strobe};
use crate::error::Error;
use nalgebra::DVector;
use serde::Serialize;

/// The §5.2 threshold, applied to the relative max norm.
pub const PERIODIC_TOLERANCE: f64 = 1e-9;

/// Largest period searched.
pub const MAX_PERIOD: usize = 32;

pub use crate::engine::map::relative_residual;

/// Forcing periods run from a start before its orbit is read.
pub const TRANSIENT: crate::model::ranges::Count = crate::model::ranges::Count {
    name: "transient",
    symbol: "periods",
    min: 0,
    max: 100_000_000,
    why: "at ~10 µs a period for N = 10, 1e8 periods take about 20 minutes",
};

/// Periods whose strobe gives the period m (the longest m read is one less, at most 64).
pub const WINDOW: crate::model::ranges::Count = crate::model::ranges::Count {
    name: "window",
    symbol: "periods",
    min: 2,
    max: 10_000,
    why: "a period must be seen twice; the strobe of the window is kept in memory",
};

/// The smallest m ≤ max_m with a relative residual below `tol` between the last strobe
/// sample and the one m periods earlier, and the best residual seen.
pub fn detect_period(strobe: &[DVector<f64>], tol: f64, max_m: usize) -> (Option<u64>, f64) {
    detect_period_by(strobe, tol, max_m, &relative_residual)
}

/// [`detect_period`] with the model's own distance between states
/// ([`PeriodMap::residual`]).
pub fn detect_period_by(
    strobe: &[DVector<f64>],
    tol: f64,
    max_m: usize,
    residual: &dyn Fn(&DVector<f64>, &DVector<f64>) -> f64,
) -> (Option<u64>, f64) {
    let Some(last) = strobe.last() else {
        return (None, f64::INFINITY);
    };
    let mut best = f64::INFINITY;
    for m in 1..=max_m.min(strobe.len().saturating_sub(1)) {
        let r = residual(last, &strobe[strobe.len() - 1 - m]);
        best = best.min(r);
        if r < tol {
            return (Some(m as u64), r);
        }
    }
    (None, best)
}

/// A window that is not periodic but returns to within this relative distance of itself
/// after some m periods is checked by shooting ([`label`]): it may be converging, slowly,
/// to a stable orbit (near a bifurcation, where a multiplier nears the unit circle, the
/// transient decays like |μ|ⁿ). Beyond it the window is too far from any orbit for Newton.
pub const SHOOT_BELOW: f64 = 1e-3;

/// The (m, n) label of a window: m from its strobe ([`detect_period_by`]), n the entries
/// into contact of its last m periods; and the best residual.
///
/// **Least period and slow transients.** Near a period doubling of a period-d orbit its
/// multiplier μ of P^d is near −1: a state a distance e from the orbit returns after d
/// periods to about 2e, but after 2d periods to about 2(1 − |μ|)e, so the window passes the
/// test at 2d long before it does at d — a stable period-d orbit labelled with period 2d.
/// Likewise a window that has not settled within the tolerance is "not periodic". So when
/// a proper divisor d of m returns to within [`crate::analysis::shooting::LEAST_PERIOD`], or
/// no m passes but one returns to within [`SHOOT_BELOW`], Newton shooting from the last
/// strobe state decides (for models with a Jacobian): if it converges close by to a
/// *stable* orbit, the window is labelled with that orbit's least period and contacts —
/// the orbit the run is converging to. An unstable orbit close by (a genuine period-2d
/// orbit just past its doubling lies near the unstable period-d one) leaves the label as
/// detected.
pub fn label<M: PeriodMap + ?Sized>(model: &M, window: &Periods) -> (OrbitKind, f64) {
    let (kind, residual, _) = label_with_orbit(model, window);
    (kind, residual)
}

/// [`label`], and the state of the stable orbit at the window's last strobe when shooting
/// decided the label (the run was still converging to it).
pub fn label_with_orbit<M: PeriodMap + ?Sized>(
    model: &M,
    window: &Periods,
) -> (OrbitKind, f64, Option<DVector<f64>>) {
    let distance = |a: &DVector<f64>, b: &DVector<f64>| model.residual(a, b);
    let (m, residual) = detect_period_by(&window.strobe, PERIODIC_TOLERANCE, MAX_PERIOD, &distance);
    let detected = m.map_or(OrbitKind::NotPeriodic, |m| OrbitKind::Periodic {
        m,
        n: window.entries.iter().rev().take(m as usize).sum(),
    });
    let (Some(last), len) = (window.strobe.last(), window.strobe.len()) else {
        return (detected, residual, None);
    };
    let back = |m: u64| distance(last, &window.strobe[len - 1 - m as usize]);
    let check = match m {
        Some(m) => (1..m)
            .any(|d| m.is_multiple_of(d) && back(d) < crate::analysis::shooting::LEAST_PERIOD)
            .then_some(m),
        None if residual < SHOOT_BELOW => {
            (1..=MAX_PERIOD.min(len.saturating_sub(1)) as u64).find(|&m| back(m) == residual)
        }
        None => None,
    };
    let Some(m) = check else {
        return (detected, residual, None);
    };
    // a few Newton steps: the state is close to the orbit if there is one
    match crate::analysis::shooting::shoot_within(model, last, m, 8) {
        Ok(o) if o.stable && distance(&o.state_vector(), last) < SHOOT_BELOW => (
            OrbitKind::Periodic {
                m: o.period_m,
                n: o.impacts_n as u64,
            },
            residual,
            Some(o.state_vector()),
        ),
        _ => (detected, residual, None),
    }
}

/// An orbit of any model variant after its transient ([`settle_map`]).
#[derive(Debug, Clone)]
pub struct Settled {
    /// Its label.
    pub kind: OrbitKind,
    /// The best relative residual of the window's strobe.
    pub residual: f64,
    /// The state at the end of the window; where shooting decided the label
    /// ([`label_with_orbit`]), the orbit's state at that phase instead.
    pub state: DVector<f64>,
    /// The cycle at which the window ends.
    pub cycle: i64,
    /// What the window recorded (strobe, entries per period, their tip velocities).
    pub window: Periods,
}

impl Settled {
    /// The tip velocities of the entries into contact in the orbit's last period (the whole
    /// window when it is not periodic).
    pub fn orbit_entry_velocities(&self) -> &[f64] {
        let periods = match self.kind {
            OrbitKind::Periodic { m, .. } => m as usize,
            OrbitKind::NotPeriodic => self.window.entries.len(),
        };
        let count: u64 = self.window.entries.iter().rev().take(periods).sum();
        let v = &self.window.entry_velocities;
        &v[v.len() - (count as usize).min(v.len())..]
    }
}

/// Runs `transient` periods of `model` from x0 at cycle 0 (recording nothing), then a
/// `window` of periods strobed, and labels the orbit: the one settle of every model
/// variant.
///
/// # Errors
/// [`Error::Parameter`] for an `x0` of the wrong length or not finite; the errors of the
/// model's [`PeriodMap::advance`] ([`Error::Chatter`], [`Error::Invariant`], ...). A window
/// that is not periodic is a label, not an error.
pub fn settle_map<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    transient: u64,
    window: u64,
) -> Result<Settled, Error> {
    model.check_state("initial state", x0)?;
    let x = model.advance(x0, 0, transient, false)?.state;
    window_from(model, &x, transient as i64, window)
}

/// The labelled window of `model` from x at the start of cycle `cycle`.
fn window_from<M: PeriodMap + ?Sized>(
    model: &M,
    x: &DVector<f64>,
    cycle: i64,
    window: u64,
) -> Result<Settled, Error> {
    let w = model.advance(x, cycle, window, true)?;
    let (kind, residual, orbit) = label_with_orbit(model, &w);
    Ok(Settled {
        kind,
        residual,
        state: orbit.unwrap_or_else(|| w.state.clone()),
        cycle: cycle + window as i64,
        window: w,
    })
}

/// The (m, n) label of an orbit, or its absence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum OrbitKind {
    /// Period m, n contacts per period.
    Periodic {
        /// m, the period in forcing periods.
        m: u64,
        /// n, the entries into contact (impacts, for the rigid model) per period m.
        n: u64,
    },
    /// No period ≤ 32 within the window.
    NotPeriodic,
}

impl std::fmt::Display for OrbitKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OrbitKind::Periodic { m, n } => write!(f, "({m},{n})"),
            OrbitKind::NotPeriodic => write!(f, "not periodic"),
        }
    }
}

/// A settled orbit.
#[derive(Debug, Clone)]
pub struct Orbit {
    /// Its label.
    pub kind: OrbitKind,
    /// The best relative residual ‖x(t₀ + mT) − x(t₀)‖∞/‖x(t₀)‖∞.
    pub residual: f64,
    /// Contact events in the recorded window.
    pub events: Vec<Event>,
    /// Dense samples in the window, if asked for.
    pub dense: Vec<Sample>,
    /// The window's first cycle.
    pub window_start: i64,
    /// The state at the end; where shooting decided the label ([`label_with_orbit`]), the
    /// orbit's state at that phase instead, so that what is computed from it is the orbit's.
    pub state: DVector<f64>,
}

impl Orbit {
    /// Entries into contact (grazing touches excluded) in cycles [from, to).
    pub fn entries(&self, from: i64, to: i64) -> impl Iterator<Item = &Event> {
        self.events.iter().filter(move |e| {
            e.entering && !e.grazing && e.clock.cycles >= from && e.clock.cycles < to
        })
    }
}

/// Runs `transient` periods from x0 (observing nothing), then `window` periods recording the
/// strobe, the events and (if `dense_per_period` > 0) dense samples, and labels the orbit.
///
/// # Errors
/// The errors of [`Simulator::run_until`]: [`Error::Parameter`] for a bad `x0`,
/// [`Error::Chatter`], [`Error::Invariant`]. A window that is not periodic is not an error.
pub fn settle(
    sim: &Simulator,
    x0: &DVector<f64>,
    transient: u64,
    window: u64,
    dense_per_period: usize,
) -> Result<Orbit, Error> {
    let x = sim.run(x0, transient, &mut ())?.state;
    settle_after(sim, &x, transient, window, dense_per_period)
}

/// [`settle`] from x, the state after the transient's `transient` periods.
///
/// # Errors
/// As [`settle`].
pub fn settle_after(
    sim: &Simulator,
    x: &DVector<f64>,
    transient: u64,
    window: u64,
    dense_per_period: usize,
) -> Result<Orbit, Error> {
    let start = sim.clock_at_cycle(transient as i64);
    let (mut events, mut strobe, mut dense) = (
        Events::default(),
        Strobe::default(),
        Dense::new(dense_per_period),
    );
    let state = sim
        .run_from(
            x,
            start,
            window,
            &mut (&mut events, &mut strobe, &mut dense),
        )?
        .state;
    // the window as every model's settle sees it, labelled the same way
    let mut entries = vec![0; window as usize];
    for e in events.events.iter().filter(|e| e.entering && !e.grazing) {
        let k = (e.clock.cycles - start.cycles).clamp(0, window as i64 - 1);
        entries[k as usize] += 1;
    }
    let periods = Periods {
        state: state.clone(),
        strobe: strobe.states(),
        entries,
        ..Periods::default()
    };
    let (kind, residual, orbit) = label_with_orbit(sim, &periods);
    Ok(Orbit {
        kind,
        residual,
        events: events.events,
        dense: dense.samples,
        window_start: start.cycles,
        state: orbit.unwrap_or(state),
    })
}

/// [`settle_map`] in chunks: `chunk` more periods at a time until the orbit over the
/// `window` after them is periodic, or `max_transient` periods have been discarded. Returns
/// the orbit and the periods discarded before its window (for lightly damped models, whose
/// transients last thousands of periods, a fixed transient would either waste time or
/// label an unsettled run).
///
/// # Errors
/// As [`settle_map`]; reaching `max_transient` without a period is not an error (the last
/// window is returned, labelled not periodic).
pub fn settle_until_periodic<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    chunk: u64,
    window: u64,
    max_transient: u64,
) -> Result<(Settled, u64), Error> {
    model.check_state("initial state", x0)?;
    let mut x = x0.clone();
    let mut discarded = 0;
    loop {
        // continue from where the last window ended, on the same clock
        x = model.advance(&x, discarded as i64, chunk, false)?.state;
        discarded += chunk;
        let o = window_from(model, &x, discarded as i64, window)?;
        if o.kind != OrbitKind::NotPeriodic || discarded + window >= max_transient {
            return Ok((o, discarded));
        }
        x = o.state.clone();
        discarded += window;
    }
}

/// How long a transient may take: `chunk` periods at a time until the `window` after them
/// is periodic, at most `max` periods in all ([`settle_until_periodic`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct Settling {
    /// Periods discarded per step while not periodic.
    pub chunk: u64,
    /// Periods over which the orbit is labelled.
    pub window: u64,
    /// The most periods discarded.
    pub max: u64,
}

impl Settling {
    /// For lightly damped models (ζ₁ ~ 1e-3, Figure 9 and §6), whose transients last
    /// thousands of forcing periods: 500 at a time, a 40-period window, at most 20 000.
    pub const LIGHTLY_DAMPED: Settling = Settling {
        chunk: 500,
        window: 40,
        max: 20_000,
    };
}

/// The orbit `problem` settles to from rest: its simulator, the settled orbit and the
/// periods discarded before its window.
///
/// # Errors
/// [`Error::Parameter`] for a problem out of range; [`Error::Flow`] when a region's flow
/// cannot be built; the run errors of [`settle_until_periodic`].
pub fn settle_from_rest(
    problem: &crate::model::problems::Forced,
    settling: &Settling,
) -> Result<(Simulator, Settled, u64), Error> {
    let sim = Simulator::new(problem.model()?)?;
    let n = sim.model().modes();
    let (o, discarded) = settle_until_periodic(
        &sim,
        &DVector::zeros(2 * n),
        settling.chunk,
        settling.window,
        settling.max,
    )?;
    Ok((sim, o, discarded))
}

/// A settled orbit of the rigid-impact model.
#[derive(Debug, Clone, Serialize)]
pub struct RigidOrbit {
    /// Its label: period m, impacts per period n.
    pub kind: OrbitKind,
    /// The best relative residual on the stroboscopic map (as for [`Orbit`]).
    pub residual: f64,
    /// The incoming tip velocity of the last impact (the model's units; NaN without one).
    pub impact_velocity: f64,
    /// Chatters (impacts accumulating in finite time) in the recorded window.
    pub chatters: usize,
    /// The state at the end of the window.
    pub state: Vec<f64>,
    /// The cycle at which the window ends.
    pub cycle: i64,
}

/// [`settle_map`] for the rigid-impact model, with what its scenes report.
///
/// # Errors
/// As [`settle_map`]: [`Error::Parameter`] for a bad state or one beyond the stop;
/// [`Error::Chatter`] for a chatter with no sticking limit or past the impact limit.
pub fn settle_rigid(
    model: &crate::engine::rigid::RigidImpact,
    x0: &DVector<f64>,
    transient: u64,
    window: u64,
) -> Result<RigidOrbit, Error> {
    let o = settle_map(model, x0, transient, window)?;
    Ok(RigidOrbit {
        kind: o.kind,
        residual: o.residual,
        impact_velocity: o
            .window
            .entry_velocities
            .last()
            .copied()
            .unwrap_or(f64::NAN),
        chatters: o.window.chatters as usize,
        cycle: o.cycle,
        state: o.state.as_slice().to_vec(),
    })
}

/// Orbits reached from `starts` random initial conditions ([`random_state`] at 4·A_free,
/// seeded by `seed` and N), counted by kind.
///
/// # Errors
/// The first error of [`settle`] from a start ([`Error::Chatter`], [`Error::Invariant`]).
pub fn random_orbits(
    sim: &Simulator,
    starts: usize,
    seed: u64,
    transient: u64,
    window: u64,
) -> Result<Vec<(OrbitKind, usize)>, Error> {
    let n = sim.model().modes();
    let (amp, _) = sim.model().free_tip_amplitude();
    let mut counts: std::collections::BTreeMap<OrbitKind, usize> = Default::default();
    for i in 0..starts {
        let mut rng = SplitMix64::for_point(seed, n as u64, 0, i as u64);
        let x0 = random_state(&mut rng, n, 4.0 * amp, sim.omega());
        let o = settle(sim, &x0, transient, window, 0)?;
        *counts.entry(o.kind).or_default() += 1;
    }
    Ok(counts.into_iter().collect())
}
