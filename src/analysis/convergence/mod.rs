//! Convergence at a fixed stop stiffness: §2.3's claim that "for fixed k, we have modal
//! convergence as N → ∞", with the criterion (β_N⁺)³ ≫ k.
//!
//! One experiment, run on any discretisation of the beam — the N-mode Galerkin model
//! ([`crate::model::galerkin`]) or the finite-element beam ([`crate::model::fe`]) — so that both can be
//! refined towards the same continuum limit:
//!
//! - **one contact** (the Fig 3 set-up at finite k, unforced): the beam at rest in its
//!   undeflected shape with the velocity profile w_t = V φ₁(s)/φ₁(1), V = 1 (the tip
//!   moving into the stop at d₀ = 0), simulated exactly until the tip leaves. Observables:
//!   the contact duration, the exit tip velocity, and the first-mode velocity ∫φ₁w_t ds
//!   after the contact;
//! - **forced from rest** (eq 37 at ω): the tip displacement and velocity after a fixed
//!   number of periods from x⁺(0) = 0.
//!
//! All exist whether or not the long-time orbit is periodic. The truncation error of the
//! stop's point force is the tail of the tip flexibility, Σ_{j>N} φ_j(1)²/k_j ≈ 4/(3πβ_N³),
//! so errors are expected to fall like k/β_N³ ∝ N⁻³ once (β_N)³ ≫ k — the paper's criterion.

pub mod needed;
pub mod truncation;
pub mod two_basis_runs;

pub use needed::{criterion_modes, matched_modes, modes_needed, ModesNeeded, Needed, SCAN};
pub use truncation::{truncation_error, TruncationError};

use crate::analysis::orbit::{settle_until_periodic, OrbitKind};
use crate::base::verification::{self, Richardson};
use crate::engine::sim::{Events, Simulator, TipMax};
use crate::engine::two_basis::TwoBasisModel;
use crate::error::{Error, ParameterError};
use crate::model::continuum;
use crate::model::fe::FeBeam;
use crate::model::galerkin::{self, Forcing, GalerkinModel, GalerkinParams};
use nalgebra::DVector;
use serde::Serialize;

/// A discretisation of the beam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Discretisation {
    /// The Galerkin model with N free modes.
    Galerkin(usize),
    /// The finite-element beam with this many elements (all 2n modes kept).
    Elements(usize),
    /// The two-basis switching truncation with N free and N constrained modes
    /// ([`crate::engine::two_basis`]).
    TwoBasis(usize),
}

impl Discretisation {
    /// The resolution parameter: N or the element count.
    pub fn size(&self) -> usize {
        match self {
            Self::Galerkin(n) | Self::Elements(n) | Self::TwoBasis(n) => *n,
        }
    }
}

/// The physical set-up (the same PDE for every discretisation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Setup {
    /// k/k₁.
    pub k_over_k1: f64,
    /// ζ₁ (material damping γ = 2ζ₁/(β₁⁻)²).
    pub zeta1: f64,
    /// ω/(β₁⁻)² of the forced run.
    pub omega_over_w1: f64,
    /// Forcing periods of the forced run.
    pub periods: u64,
}

/// The observables (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Observables {
    /// Contact duration of the single contact.
    pub contact_duration: f64,
    /// Tip velocity when the tip leaves the stop (per unit entry velocity; negative).
    pub exit_tip_velocity: f64,
    /// ∫φ₁w_t ds after the contact: the first continuum mode's velocity.
    pub exit_mode1_velocity: f64,
    /// Tip displacement after the forced run.
    pub forced_tip: f64,
    /// Tip velocity after the forced run.
    pub forced_tip_velocity: f64,
}

impl Observables {
    /// The observables as (name, value) pairs, in a fixed order.
    pub fn named(&self) -> [(&'static str, f64); 5] {
        [
            ("contact duration", self.contact_duration),
            ("exit tip velocity", self.exit_tip_velocity),
            ("exit mode-1 velocity", self.exit_mode1_velocity),
            ("forced tip displacement", self.forced_tip),
            ("forced tip velocity", self.forced_tip_velocity),
        ]
    }
}

/// A built discretisation: the model and how to read the continuum's first-mode coordinate.
struct Built {
    free: GalerkinModel,
    forced: GalerkinModel,
    /// r with ∫φ₁ w ds = rᵀη.
    mode1: DVector<f64>,
    /// The one-contact start [η; η̇].
    start: DVector<f64>,
}

fn build(d: Discretisation, s: &Setup) -> Result<Built, ParameterError> {
    let k = crate::error::finite_positive("k/k₁", s.k_over_k1)? * galerkin::first_modal_stiffness();
    let omega =
        crate::error::finite_positive("ω/(β₁⁻)²", s.omega_over_w1)? * galerkin::first_frequency();
    let unforced = GalerkinParams::new(d.size(), k).with_zeta1(s.zeta1);
    let forced = unforced.clone().with_forcing(Forcing::paper(omega));
    let phi1 = continuum::free_mode(1)?;
    // w_t = φ₁/φ₁(1): tip velocity 1 into the stop
    let velocity = |x: f64| phi1.value(x) / 2.0;
    Ok(match d {
        Discretisation::Galerkin(n) | Discretisation::TwoBasis(n) => {
            let mut start = DVector::zeros(2 * n);
            start[n] = 0.5;
            let mut mode1 = DVector::zeros(n);
            mode1[0] = 1.0;
            Built {
                free: GalerkinModel::new(unforced)?,
                forced: GalerkinModel::new(forced)?,
                mode1,
                start,
            }
        }
        Discretisation::Elements(n) => {
            let beam = FeBeam::new(n)?;
            Built {
                free: beam.model(&unforced)?,
                forced: beam.model(&forced)?,
                mode1: beam.project(&|x| phi1.value(x))?,
                start: beam.modal_state(&|_| 0.0, &velocity)?,
            }
        }
    })
}

/// A_free and ωA_free of the forced run (independent of N: the forcing is ∝ φ₁).
///
/// # Errors
/// [`ParameterError`] for ω/(β₁⁻)² not finite and > 0 or out of the model's range, or ζ₁
/// not > 0 (the unit-tip forcing scales with the damping).
pub fn free_amplitude(s: &Setup) -> Result<(f64, f64), ParameterError> {
    let omega =
        crate::error::finite_positive("ω/(β₁⁻)²", s.omega_over_w1)? * galerkin::first_frequency();
    let p = GalerkinParams::new(1, 0.0)
        .with_zeta1(s.zeta1)
        .with_forcing(Forcing::paper(omega));
    Ok(GalerkinModel::new(p)?.free_tip_amplitude())
}

/// The two-basis models (unforced, forced) of a set-up.
fn two_basis(n: usize, s: &Setup) -> Result<(TwoBasisModel, TwoBasisModel), Error> {
    let b = build(Discretisation::Galerkin(n), s)?;
    Ok((
        TwoBasisModel::new(b.free.params().clone())?,
        TwoBasisModel::new(b.forced.params().clone())?,
    ))
}

/// Runs both experiments on discretisation `d`.
///
/// # Errors
/// [`Error::Parameter`] for a set-up or size out of range; [`Error::Flow`] when a flow cannot
/// be built; [`Error::Unsupported`] when the tip does not leave the stop in the run (or a
/// two-basis model cannot be built); a run's [`Error::Chatter`] or [`Error::Invariant`].
pub fn observe(d: Discretisation, s: &Setup) -> Result<Observables, Error> {
    if let Discretisation::TwoBasis(n) = d {
        let (free, forced) = two_basis(n, s)?;
        let (duration, exit_tip, state, _) = two_basis_runs::one_contact(&free)?;
        let (forced_tip, forced_tip_velocity, _) =
            two_basis_runs::forced_from_rest(&forced, s.periods)?;
        return Ok(Observables {
            contact_duration: duration,
            exit_tip_velocity: exit_tip,
            exit_mode1_velocity: state[n],
            forced_tip,
            forced_tip_velocity,
        });
    }
    let b = build(d, s)?;
    let (duration, exit_tip, exit_mode1) = one_contact(&b, d)?;
    let (forced_tip, forced_tip_velocity) = forced(b.forced, s.periods)?;
    Ok(Observables {
        contact_duration: duration,
        exit_tip_velocity: exit_tip,
        exit_mode1_velocity: exit_mode1,
        forced_tip,
        forced_tip_velocity,
    })
}

/// The forced run only: tip displacement and velocity after `s.periods` periods from rest.
///
/// # Errors
/// [`Error::Parameter`] for a set-up or size out of range; [`Error::Flow`] when a flow cannot
/// be built; [`Error::Unsupported`] for a two-basis model that cannot be built; a run's
/// [`Error::Chatter`] or [`Error::Invariant`].
pub fn observe_forced(d: Discretisation, s: &Setup) -> Result<(f64, f64), Error> {
    if let Discretisation::TwoBasis(n) = d {
        let (d, v, _) = two_basis_runs::forced_from_rest(&two_basis(n, s)?.1, s.periods)?;
        return Ok((d, v));
    }
    forced(build(d, s)?.forced, s.periods)
}

/// The state [η; η̇] and the event when the tip first leaves the stop after the start.
fn exit(b: &Built, d: Discretisation) -> Result<crate::engine::sim::Event, Error> {
    let sim = Simulator::new(b.free.clone())?;
    // unforced: one bookkeeping "period" is one time unit, far longer than the contact
    let mut events = Events::with_states();
    sim.run(&b.start, 1, &mut events)?;
    events
        .events
        .into_iter()
        .find(|e| !e.entering && !e.grazing)
        .ok_or_else(|| Error::Unsupported(format!("{d:?}: the tip did not leave the stop")))
}

fn one_contact(b: &Built, d: Discretisation) -> Result<(f64, f64, f64), Error> {
    let m = b.free.modes();
    let e = exit(b, d)?;
    let state = e.state.unwrap_or_default();
    let mode1 = b.mode1.iter().zip(&state[m..]).map(|(r, v)| r * v).sum();
    Ok((e.time, e.tip_velocity, mode1))
}

fn forced(model: GalerkinModel, periods: u64) -> Result<(f64, f64), Error> {
    let m = model.modes();
    let sim = Simulator::new(model)?;
    let end = sim.run(&DVector::zeros(2 * m), periods, &mut ())?;
    let tip = sim.model().tip();
    Ok((
        tip.dot(&end.state.rows(0, m)),
        tip.dot(&end.state.rows(m, m)),
    ))
}

/// The post-contact velocity coordinates η̇ of the Galerkin model after the one contact
/// (for the velocity profile w_t = Σφ_jη̇_j).
///
/// # Errors
/// [`Error::Parameter`] for a set-up or N out of range; [`Error::Flow`] when the flow cannot
/// be built; [`Error::Unsupported`] when the tip does not leave the stop within one time unit;
/// a run's [`Error::Chatter`] or [`Error::Invariant`].
pub fn post_contact_velocities(modes: usize, s: &Setup) -> Result<Vec<f64>, Error> {
    let d = Discretisation::Galerkin(modes);
    let state = exit(&build(d, s)?, d)?.state.unwrap_or_default();
    Ok(state[modes..].to_vec())
}

/// A refinement study of one observable: values on increasing resolutions, the limit by
/// Richardson extrapolation of the finest three of ratio 2 (n/4, n/2, n) and its
/// uncertainty, Roache's grid convergence index (safety factor 1.25) times |f|.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Study {
    /// Resolutions (N, or elements), increasing.
    pub sizes: Vec<usize>,
    /// The observable at each.
    pub values: Vec<f64>,
    /// The extrapolated limit (the finest value if no order could be fitted).
    pub limit: f64,
    /// Its uncertainty (absolute).
    pub uncertainty: f64,
    /// The observed order p on the three finest, if the differences are monotone and p
    /// is in the asymptotic range (0.5, 10).
    pub order: Option<f64>,
    /// |p − p'|, with p' the order observed one step coarser (n/8, n/4, n/2): how far the
    /// order has settled (`None` without both).
    pub order_change: Option<f64>,
    /// The observable's natural scale: errors and tolerances are relative to it.
    pub scale: f64,
}

impl Study {
    /// Builds the study; the sizes must include the finest n, n/2 and n/4. Where
    /// the three finest are not in the asymptotic range (differences of alternating sign, or
    /// an order outside (0.5, 10), as at a round-off floor), the limit is the finest value
    /// and its uncertainty the spread of the three.
    ///
    /// # Errors
    /// [`Error::Unsupported`] unless the finest size n is a multiple of 4 with n/2 and n/4 among
    /// `sizes`, and `values` has one entry per size.
    pub fn new(sizes: Vec<usize>, values: Vec<f64>, scale: f64) -> Result<Self, Error> {
        let n = sizes.len();
        let at = |size: usize| sizes.iter().position(|&m| m == size).map(|i| values[i]);
        let finest = sizes.last().copied().unwrap_or(0);
        let ladder = (finest % 4 == 0 && values.len() == n)
            .then(|| Some((at(finest)?, at(finest / 2)?, at(finest / 4)?)))
            .flatten();
        let Some((f1, f2, f3)) = ladder else {
            return Err(Error::Unsupported(format!(
                "a refinement study needs its finest size n with n/2 and n/4: {sizes:?}"
            )));
        };
        let r = 2.0;
        let spread = f1.max(f2).max(f3) - f1.min(f2).min(f3);
        let (limit, uncertainty, order) = match verification::richardson(f1, f2, f3, r) {
            Richardson::Monotone {
                order,
                extrapolated,
                gci,
            } if order > 0.5 && order < 10.0 => (extrapolated, gci * f1.abs(), Some(order)),
            Richardson::Converged => (f1, f64::EPSILON * f1.abs(), None),
            _ => (f1, spread, None),
        };
        let coarser = at(finest / 8).and_then(|f4| match verification::richardson(f2, f3, f4, r) {
            Richardson::Monotone { order, .. } => Some(order),
            _ => None,
        });
        let order_change = order.zip(coarser).map(|(p, q)| (p - q).abs());
        Ok(Self {
            sizes,
            values,
            limit,
            uncertainty,
            order,
            order_change,
            scale,
        })
    }

    /// |f(size) − limit|/scale at each size.
    pub fn relative_errors(&self) -> Vec<f64> {
        self.values
            .iter()
            .map(|v| (v - self.limit).abs() / self.scale)
            .collect()
    }

    /// The smallest resolution N* from which every scanned value is within `tol`·scale of
    /// the limit. Where the scan does not reach `tol`, or the limit is not known to tol/4,
    /// N* is estimated from the error model e(N) = e(N_max)(N_max/N)^p with the observed
    /// order p and the estimated error of the finest value ([`Self::power_law_needed`]).
    pub fn needed(&self, tol: f64) -> Needed {
        let finest = self.sizes.last().copied().unwrap_or(0) as f64;
        let estimate = || match self.power_law_needed(tol) {
            // an estimate inside the scan means the values would meet `tol` there, but the
            // limit is too uncertain to confirm it against them
            Some(estimate) if estimate.ceil() <= finest => Needed::Unconfirmed { estimate },
            Some(estimate) => Needed::Beyond { estimate },
            None => Needed::Unresolved,
        };
        if self.uncertainty > 0.25 * tol * self.scale {
            return estimate();
        }
        let errors = self.relative_errors();
        match errors.iter().rposition(|e| *e > tol) {
            None => Needed::Scanned(self.sizes[0]),
            Some(i) if i + 1 < self.sizes.len() => Needed::Scanned(self.sizes[i + 1]),
            Some(_) => estimate(),
        }
    }

    /// N* from the error model alone: N_max·(e(N_max)/tol)^{1/p}, with e(N_max) the
    /// Richardson estimate of the finest value's error; `None` without an observed order.
    pub fn power_law_needed(&self, tol: f64) -> Option<f64> {
        let p = self.order?;
        let finest = *self.sizes.last()? as f64;
        let e = (self.values.last()? - self.limit).abs() / self.scale;
        Some(finest * (e / tol).powf(1.0 / p))
    }
}

/// Where the forced run settles to a periodic orbit: its label and two observables.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeriodicObservables {
    /// (m, n), or not periodic.
    pub kind: OrbitKind,
    /// The largest tip velocity entering contact over one period of the orbit.
    pub impact_velocity: f64,
    /// The certified largest tip displacement over one period (`None` for the two-basis
    /// model, whose runs have no certified maximum).
    pub max_tip: Option<f64>,
    /// Periods discarded before the orbit was periodic (to 1e-9, §5.2).
    pub transient: u64,
}

/// Periods run at a time while waiting for the orbit to settle, the strobe window, and the
/// longest transient allowed (ζ₁ = 0.01 decays by e in ≈ 9 periods at ω = 2(β₁⁻)²).
const SETTLE: (u64, u64, u64) = (100, 32, 4000);

/// The forced run from rest continued until periodic ([`crate::analysis::orbit`]).
///
/// # Errors
/// [`Error::Parameter`] for a set-up or size out of range; [`Error::Flow`] when a flow cannot
/// be built; [`Error::Unsupported`] for a two-basis model that cannot be built; a run's
/// [`Error::Chatter`] or [`Error::Invariant`]. An orbit that does not settle is not an error.
pub fn periodic(d: Discretisation, s: &Setup) -> Result<PeriodicObservables, Error> {
    let (chunk, window, max) = SETTLE;
    if let Discretisation::TwoBasis(n) = d {
        return two_basis_runs::settle(&two_basis(n, s)?.1, chunk, window, max);
    }
    let model = build(d, s)?.forced;
    let m = model.modes();
    let sim = Simulator::new(model)?;
    let (orbit, discarded) =
        settle_until_periodic(&sim, &DVector::zeros(2 * m), chunk, window, max)?;
    let OrbitKind::Periodic { m: period, .. } = orbit.kind else {
        return Ok(PeriodicObservables {
            kind: orbit.kind,
            impact_velocity: f64::NAN,
            max_tip: None,
            transient: discarded,
        });
    };
    let start = sim.clock_at_cycle(discarded as i64 + window as i64);
    let (mut events, mut top) = (Events::default(), TipMax::default());
    sim.run_from(&orbit.state, start, period, &mut (&mut events, &mut top))?;
    Ok(PeriodicObservables {
        kind: orbit.kind,
        impact_velocity: events
            .events
            .iter()
            .filter(|e| e.entering && !e.grazing)
            .map(|e| e.tip_velocity)
            .fold(f64::NAN, f64::max),
        max_tip: top.maximum.map(|t| t.value),
        transient: discarded,
    })
}
