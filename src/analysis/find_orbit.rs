//! The researcher's one call: from a model and a start, the periodic orbit it settles on,
//! with its period, its Floquet multipliers and stability, and — for the compliant model —
//! its energetic coefficient of restitution r_E (eq 39). It chains what the crate has
//! once: the transient and the period from the strobe ([`crate::analysis::orbit`]), Newton
//! shooting with the exact monodromy reported at the least period
//! ([`crate::analysis::shooting`]), and the contact work on mode 1
//! ([`crate::analysis::energetic`]).
//!
//! ```
//! use impacting_cantilever::prelude::*;
//! # fn main() -> Result<(), Error> {
//! let sim = Simulator::new(problems::figure4(10).model()?)?;
//! let o = find_orbit(&sim, &sim.rest(), &OrbitOptions { restitution: true, ..Default::default() })?;
//! assert_eq!((o.period_m, o.impacts_n), (1, 1));
//! assert!(o.stable && o.multipliers[0].norm() < 0.55);
//! # Ok(())
//! # }
//! ```

use crate::analysis::energetic::ContactWork;
use crate::analysis::energetic::NO_CONTACT_FORCE;
use crate::analysis::orbit::{detect_period_by, TRANSIENT, WINDOW};
use crate::analysis::shooting::{self, PeriodicOrbit};
use crate::base::progress::{CancelOnly, Progress, Silent};
use crate::engine::built::{BuiltModel, Variant};
use crate::engine::map::PeriodMap;
use crate::engine::rigid::RigidImpact;
use crate::engine::sim::Simulator;
use crate::engine::two_basis::TwoBasisModel;
use crate::error::{Error, ParameterError};
use nalgebra::DVector;
use num_complex::Complex64;

/// What [`find_orbit`] does, by name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitOptions {
    /// Forcing periods run from the start before the orbit is read (0 to 1e8).
    pub transient: u64,
    /// Periods whose strobe gives the period m (2 to 10 000; the longest period found is
    /// one less, at most 64).
    pub window: u64,
    /// The period m, when known (1 to 64); read from the window otherwise.
    pub period: Option<u64>,
    /// How near the window's strobe must repeat for its period to be taken (relative);
    /// Newton then converges the orbit to 1e-12.
    pub period_tolerance: f64,
    /// Newton steps allowed.
    pub max_iterations: usize,
    /// Also r_E (eq 39) over one period of the orbit (the compliant model only).
    pub restitution: bool,
}

impl OrbitOptions {
    /// The options every front end starts from: 1000 transient periods, m read from a
    /// window of 65 (up to 64) to 1e-3, Newton's default steps, no r_E.
    pub const DEFAULTS: OrbitOptions = OrbitOptions {
        transient: 1000,
        window: 65,
        period: None,
        period_tolerance: 1e-3,
        max_iterations: shooting::MAX_ITERATIONS,
        restitution: false,
    };
}

impl Default for OrbitOptions {
    fn default() -> Self {
        Self::DEFAULTS
    }
}

/// Orbit periods run on from a found orbit to see whether its entry count is exact.
pub const COUNTED_REPEATS: u64 = 4;

/// A periodic orbit as [`find_orbit`] gives it.
#[derive(Debug, Clone)]
pub struct FoundOrbit {
    /// The state [η; η̇] at the start of a forcing period on the orbit.
    pub state: DVector<f64>,
    /// m: forcing periods per orbit period (the least).
    pub period_m: u64,
    /// n: entries into contact (impacts, for the rigid model) per orbit period.
    pub impacts_n: u64,
    /// The fewest and most entries in each of [`COUNTED_REPEATS`] periods of the orbit run
    /// on from its state: equal on an orbit whose events round-off cannot change; apart
    /// where it decides one (a micro-bounce whose flight or contact is within round-off of
    /// the stop, as at 1e12k₁: 4244 or 4245 entries per period of an orbit settled to 1e-14).
    pub impacts_n_range: (u64, u64),
    /// The Floquet multipliers, largest modulus first.
    pub multipliers: Vec<Complex64>,
    /// All multipliers inside the unit circle.
    pub stable: bool,
    /// ‖P^m(x) − x‖∞/‖x‖∞ (at most 1e-12).
    pub residual: f64,
    /// Newton steps taken.
    pub iterations: usize,
    /// r_E (eq 39) over one period, when asked for (`None` if the balance has no real
    /// root: mode 1 lost more to the contacts than it brought).
    pub energetic_restitution: Option<f64>,
    /// The orbit as the shooting module reports it (for JSON).
    pub orbit: PeriodicOrbit,
}

impl FoundOrbit {
    /// The largest multiplier modulus.
    pub fn spectral_radius(&self) -> f64 {
        self.multipliers.first().map_or(0.0, |z| z.norm())
    }
}

/// r_E of an orbit, where the model defines it.
pub trait EnergeticRestitution {
    /// Eq (39) over one period of `orbit` (`Ok(None)` when the balance has no real root).
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a model that does not define r_E (rigid, two-basis); for the
    /// compliant model, the errors of the run over the orbit's period.
    fn energetic_restitution(&self, orbit: &PeriodicOrbit) -> Result<Option<f64>, Error>;
}

impl EnergeticRestitution for Simulator {
    fn energetic_restitution(&self, orbit: &PeriodicOrbit) -> Result<Option<f64>, Error> {
        let mut work = ContactWork::for_mode(self.model(), 0)?;
        self.run(&orbit.state_vector(), orbit.period_m, &mut work)?;
        Ok(work.coefficient().value())
    }
}

impl EnergeticRestitution for RigidImpact {
    fn energetic_restitution(&self, _: &PeriodicOrbit) -> Result<Option<f64>, Error> {
        Err(Error::Unsupported(NO_CONTACT_FORCE.into()))
    }
}

impl EnergeticRestitution for BuiltModel {
    fn energetic_restitution(&self, orbit: &PeriodicOrbit) -> Result<Option<f64>, Error> {
        match self.variant() {
            Variant::Compliant(sim) => sim.energetic_restitution(orbit),
            Variant::Rigid(rigid) => rigid.energetic_restitution(orbit),
        }
    }
}

impl EnergeticRestitution for TwoBasisModel {
    fn energetic_restitution(&self, _: &PeriodicOrbit) -> Result<Option<f64>, Error> {
        Err(Error::Unsupported(
            "r_E is not derived for the two-basis model (its switches project the state, so \
             mode 1's energy is not continuous across them)"
                .into(),
        ))
    }
}

/// The periodic orbit `model` settles on from `start`: `options.transient` periods, the
/// period m read from a window of `options.window` periods (or given), Newton shooting with
/// the exact monodromy, the multipliers, and r_E if asked for.
///
/// # Errors
/// [`Error::Parameter`] for bad options or a bad start; [`Error::NoPeriod`] when the window
/// shows no period; [`Error::NotConverged`] when Newton does not converge;
/// [`Error::Unsupported`] for a model without a Jacobian (or without r_E, when asked for);
/// a run's [`Error::Chatter`] or [`Error::Invariant`].
pub fn find_orbit<M: PeriodMap + EnergeticRestitution + ?Sized>(
    model: &M,
    start: &DVector<f64>,
    options: &OrbitOptions,
) -> Result<FoundOrbit, Error> {
    find_orbit_reporting(model, start, options, &Silent)
}

/// [`find_orbit`], reporting the transient's periods to `progress` (a task "orbit:
/// transient periods") and stopping with [`Error::Interrupted`] when it is cancelled: during
/// the transient, and before the window, the shooting and the count. The orbit is the one
/// [`find_orbit`] finds, bit for bit.
///
/// # Errors
/// As [`find_orbit`]; [`Error::Interrupted`].
pub fn find_orbit_reporting<M: PeriodMap + EnergeticRestitution + ?Sized>(
    model: &M,
    start: &DVector<f64>,
    options: &OrbitOptions,
    progress: &dyn Progress,
) -> Result<FoundOrbit, Error> {
    check(options)?;
    model.check_state("start", start)?;
    let task = progress.task("orbit: transient periods", options.transient);
    let x = model.advance_reporting(start, 0, options.transient, task.as_ref(), progress)?;
    drop(task);
    let stop = || {
        if progress.cancelled() {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    };
    stop()?;
    let (x, m) = match options.period {
        Some(m) => (x, m),
        None => {
            let w = model.advance(&x, options.transient as i64, options.window, true)?;
            let (m, best) = detect_period_by(
                &w.strobe,
                options.period_tolerance,
                64.min(options.window as usize - 1),
                &|a, b| model.residual(a, b),
            );
            let m = m.ok_or_else(|| {
                Error::NoPeriod(format!(
                    "{} settles on no period within {} periods after a transient of {} \
                     (best relative residual {best:.1e}, wanted {:.0e}): give the period, a \
                     longer transient, or another start",
                    model.name(),
                    options.window,
                    options.transient,
                    options.period_tolerance
                ))
            })?;
            (w.state, m)
        }
    };
    stop()?;
    let orbit = shooting::shoot_within(model, &x, m, options.max_iterations)?;
    stop()?;
    // the count on further periods of the orbit: one period's count is not exact where
    // round-off decides an event
    let on = model.advance(&orbit.state_vector(), 0, COUNTED_REPEATS * m, true)?;
    let per_orbit_period: Vec<u64> = on
        .entries
        .chunks(m as usize)
        .map(|c| c.iter().sum())
        .collect();
    let n = orbit.impacts_n as u64;
    let impacts_n_range = per_orbit_period
        .iter()
        .fold((n, n), |(lo, hi), &k| (lo.min(k), hi.max(k)));
    let energetic_restitution = if options.restitution {
        model.energetic_restitution(&orbit)?
    } else {
        None
    };
    Ok(FoundOrbit {
        state: orbit.state_vector(),
        period_m: orbit.period_m,
        impacts_n: n,
        impacts_n_range,
        multipliers: orbit.multipliers_complex(),
        stable: orbit.stable,
        residual: orbit.residual,
        iterations: orbit.iterations,
        energetic_restitution,
        orbit,
    })
}

/// [`find_orbit`] of each model from its start, with the same options: a sweep. The models
/// run in parallel (on the caller's rayon pool), each orbit is the one [`find_orbit`] finds
/// for that model alone, bit for bit, whatever the thread count, and a value whose orbit
/// fails (no period, Newton, chatter) has its error as its entry, not the sweep's. Reports
/// a task "sweep: orbits" counted in models, and stops with [`Error::Interrupted`] when
/// `progress` is cancelled.
///
/// # Errors
/// [`Error::Parameter`] for bad options or as many starts as models not given;
/// [`Error::Interrupted`].
pub fn find_orbits<M: PeriodMap + EnergeticRestitution + Sync>(
    models: &[M],
    starts: &[DVector<f64>],
    options: &OrbitOptions,
    progress: &dyn Progress,
) -> Result<Vec<Result<FoundOrbit, Error>>, Error> {
    use rayon::prelude::*;
    check(options)?;
    if starts.len() != models.len() {
        let why = format!("one per model ({})", models.len());
        return Err(ParameterError::new("starts", starts.len(), &why).into());
    }
    let task = progress.task("sweep: orbits", models.len() as u64);
    let quiet = CancelOnly(progress);
    let found: Vec<_> = models
        .par_iter()
        .zip(starts)
        .map(|(model, x)| {
            let r = find_orbit_reporting(model, x, options, &quiet);
            task.advance(1);
            r
        })
        .collect();
    if progress.cancelled() {
        return Err(Error::Interrupted);
    }
    Ok(found)
}

fn check(o: &OrbitOptions) -> Result<(), ParameterError> {
    TRANSIENT.check(o.transient as i128)?;
    WINDOW.check(o.window as i128)?;
    if let Some(m) = o.period {
        if !(1..=64).contains(&m) {
            return Err(ParameterError::new("period m", m, "1 to 64"));
        }
    }
    if !(o.period_tolerance > 0.0 && o.period_tolerance < 1.0) {
        return Err(ParameterError::new(
            "period_tolerance",
            o.period_tolerance,
            "a relative tolerance in (0, 1)",
        ));
    }
    if !(1..=1000).contains(&o.max_iterations) {
        return Err(ParameterError::new(
            "max_iterations",
            o.max_iterations,
            "1 to 1000",
        ));
    }
    Ok(())
}
