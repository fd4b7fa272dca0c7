//! The energetic coefficient of restitution (§5.4, eqs 38–39): the energy that mode 1 loses
//! to the contact, expressed as the restitution coefficient of a one-mode impact model.
//!
//! **Eq (38)**, one contact entered at t_i with mode-1 velocity v₁⁺ and lasting Δ:
//! ½(1 − r̃_E²)(v₁⁺)² + ∫_{t_i}^{t_i+Δ} F_c η̇₁ dt = 0, with F_c = (k/4)(d₀ − d)φ₁(1) the
//! contact force on mode 1 (d > d₀). **Eq (39)**, over a periodic orbit after its
//! transient: ½(1 − r_E²) Σ_i (v₁⁺⁽ⁱ⁾)² + ∫ F_c η̇₁ dt = 0 over one period of the orbit.
//!
//! **The work integral, exactly.** Mode 1 obeys η̈₁ + c₁η̇₁ + k₁η₁ = f₁ cos ωt + F_c (the
//! damping is diagonal in the modal coordinates), so over any stretch of contact
//! ∫ F_c η̇₁ dt = ΔE₁ + ∫ c₁η̇₁² dt − ∫ f₁η̇₁ cos ωt dt, with E₁ = ½η̇₁² + ½k₁η₁².
//! Both integrals are the closed-form segment integrals of the energy budget
//! ([`crate::engine::sim::energy`]) restricted to mode 1, and ΔE₁ comes from the exact states at the
//! segment's ends: no quadrature. (Checked against composite Gauss–Legendre quadrature of
//! F_c η̇₁ on the exact solution in `tests/energetic.rs`.)
//!
//! With N = 1 the contact force is conservative, so r_E = 1 exactly: r_E < 1 measures what
//! the contact hands to the higher modes.

use crate::analysis::orbit::{self, OrbitKind};
use crate::base::progress::{Progress, Silent};
use crate::engine::built::{BuiltModel, Variant};
use crate::engine::map::PeriodMap;
use crate::engine::sim::energy::{segment_energy, EnergyTables};
use crate::engine::sim::{Clock, EventView, Observer, SegmentView, Simulator};
use crate::error::{Error, ParameterError};
use crate::model::galerkin::{GalerkinModel, Region};
use nalgebra::DVector;
use serde::Serialize;

/// One contact: its entry (absent when the observed stretch began inside it), the mode-1
/// velocity v₁⁺ there, the work of the contact force on mode 1 while observed, and its exit
/// (absent when the stretch ended inside it).
#[derive(Debug, Clone, Serialize)]
pub struct Contact {
    /// Entry time.
    pub entry: Option<f64>,
    /// η̇₁ at the entry.
    pub v1: Option<f64>,
    /// The tip velocity φ(1)ᵀη̇ at the entry.
    pub tip_velocity: Option<f64>,
    /// ∫ F_c η̇₁ dt over the observed part of the contact.
    pub work: f64,
    /// Exit time.
    pub exit: Option<f64>,
}

impl Contact {
    /// Eq (38) for a complete contact.
    pub fn coefficient(&self) -> Option<Coefficient> {
        match (self.v1, self.exit) {
            (Some(v), Some(_)) => Some(Coefficient::from_balance(self.work, v * v)),
            _ => None,
        }
    }
}

/// The solution of ½(1 − r²)·v² + W = 0 for r ≥ 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Coefficient {
    /// r = √(1 + 2W/v²).
    Value(f64),
    /// 1 + 2W/v² < 0: mode 1 lost more than its entry kinetic energy, and no real r
    /// exists (the value is r²).
    NoRealValue(f64),
    /// No contact was entered (v² = 0).
    NoContact,
}

impl Coefficient {
    /// From the work W on mode 1 and the sum of (v₁⁺)² over the entries.
    pub fn from_balance(work: f64, v_squared: f64) -> Self {
        if v_squared <= 0.0 {
            return Coefficient::NoContact;
        }
        let r2 = 1.0 + 2.0 * work / v_squared;
        if r2 >= 0.0 {
            Coefficient::Value(r2.sqrt())
        } else {
            Coefficient::NoRealValue(r2)
        }
    }

    /// The value, if real.
    pub fn value(&self) -> Option<f64> {
        match self {
            Coefficient::Value(r) => Some(*r),
            _ => None,
        }
    }
}

/// Observes the contacts of a run and the work of the contact force on one mode (mode 1
/// for eqs 38–39), exactly.
#[derive(Debug, Clone, Default)]
pub struct ContactWork {
    /// The mode, 0-based (0: the paper's mode 1).
    pub mode: usize,
    /// The contacts, in order.
    pub contacts: Vec<Contact>,
    /// ∫ F_c η̇_j dt over the whole observed run.
    pub total_work: f64,
    /// Σ (η̇_j at each entry)² over the run.
    pub entry_v_squared: f64,
    /// The change of mode j's energy ½η̇_j² + ½k_jη_j² while in contact (the contact work
    /// plus the mode's own forcing work, minus its damping, during the contacts).
    pub contact_energy_change: f64,
    tables: Option<EnergyTables>,
}

impl ContactWork {
    /// Observes mode j (0-based) of `model`; a mode the model does not have is bad input.
    ///
    /// # Errors
    /// [`ParameterError`] when `mode` is not below the model's N.
    pub fn for_mode(model: &GalerkinModel, mode: usize) -> Result<Self, ParameterError> {
        if mode >= model.modes() {
            return Err(ParameterError::new(
                "mode j (0-based)",
                mode,
                &format!("a mode of the model, 0 to {}", model.modes() - 1),
            ));
        }
        Ok(Self {
            mode,
            ..Self::default()
        })
    }

    /// Eq (39) over the observed run (one period of a periodic orbit).
    pub fn coefficient(&self) -> Coefficient {
        Coefficient::from_balance(self.total_work, self.entry_v_squared)
    }

    /// The same balance with mode 1's whole energy change during the contacts in place
    /// of the contact force's work: a variant of eq (39) that also charges the impact with
    /// the mode's own damping (and forcing) while it lasts.
    pub fn energy_change_coefficient(&self) -> Coefficient {
        Coefficient::from_balance(self.contact_energy_change, self.entry_v_squared)
    }

    fn mode_energy(&self, model: &GalerkinModel, x: &DVector<f64>) -> f64 {
        let (n, j) = (model.modes(), self.mode);
        0.5 * (x[n + j] * x[n + j] + model.modal_stiffness()[j] * x[j] * x[j])
    }
}

impl Observer for ContactWork {
    fn begin(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>) {
        if sim.model().start_region(x, clock.offset) == Region::Contact {
            self.contacts.push(Contact {
                entry: None,
                v1: None,
                tip_velocity: None,
                work: 0.0,
                exit: None,
            });
        }
    }

    fn segment(&mut self, seg: &SegmentView) {
        if seg.region != Region::Contact {
            return;
        }
        let model = seg.simulator().model();
        let tables = self
            .tables
            .get_or_insert_with(|| EnergyTables::for_mode(seg.flow(), model, self.mode));
        let (forcing, dissipated) = segment_energy(
            seg.flow(),
            seg.modal_coordinates(),
            seg.phase(),
            tables,
            seg.end,
        );
        let change =
            self.mode_energy(model, &seg.state(seg.end)) - self.mode_energy(model, &seg.state(0.0));
        let work = change + dissipated - forcing;
        self.total_work += work;
        self.contact_energy_change += change;
        if let Some(c) = self.contacts.last_mut().filter(|c| c.exit.is_none()) {
            c.work += work;
        }
    }

    fn event(&mut self, e: &EventView) {
        if e.grazing {
            return;
        }
        let n = e.state.len() / 2;
        if e.entering {
            let v = e.state[n + self.mode];
            self.entry_v_squared += v * v;
            self.contacts.push(Contact {
                entry: Some(e.clock.time()),
                v1: Some(v),
                tip_velocity: Some(e.tip_velocity),
                work: 0.0,
                exit: None,
            });
        } else if let Some(c) = self.contacts.last_mut() {
            c.exit = Some(e.clock.time());
        }
    }
}

/// r_E of the orbit a run settles on (eq 39), with the per-contact r̃_E of its contacts
/// (eq 38).
#[derive(Debug, Clone, Serialize)]
pub struct OrbitCoefficient {
    /// The orbit (m, n) after the transient, or not periodic.
    pub kind: OrbitKind,
    /// Its stroboscopic residual.
    pub residual: f64,
    /// Eq (39) over one period of the orbit (absent when it is not periodic: the limit of
    /// eq (39) is then not established by the run).
    pub coefficient: Option<Coefficient>,
    /// The variant of eq (39) with mode 1's whole energy change during the contacts
    /// ([`ContactWork::energy_change_coefficient`]).
    pub energy_change_coefficient: Option<Coefficient>,
    /// The contacts of that period, with their eq (38) values.
    pub contacts: Vec<Contact>,
    /// The state on the orbit at the start of that period.
    pub state: Vec<f64>,
    /// The cycle at which that period starts.
    pub cycle: i64,
}

/// Why the rigid-impact model has no r_E.
pub const NO_CONTACT_FORCE: &str = "r_E (eqs 38–39) weighs the work of the compliant contact \
     force on mode 1; the rigid-impact model has no contact force — its restitution is its law";

/// [`orbit_coefficient`] of a model built from its specification, the options checked: what
/// a front end asks for, so a motion without a period is an error here (as it is for
/// [`crate::analysis::find_orbit`]), not a result without a coefficient.
///
/// # Errors
/// [`Error::Parameter`] for `transient` or `window` out of range
/// ([`orbit::TRANSIENT`], [`orbit::WINDOW`]) or a start of the wrong length;
/// [`Error::Unsupported`] for the rigid-impact model; [`Error::NoPeriod`] when the motion
/// has no period ≤ 32 in the window; the run's errors.
pub fn energetic_restitution(
    model: &BuiltModel,
    x0: &DVector<f64>,
    transient: u64,
    window: u64,
) -> Result<OrbitCoefficient, Error> {
    energetic_restitution_reporting(model, x0, transient, window, &Silent)
}

/// [`energetic_restitution`], reporting the transient's periods to `progress` (a task
/// "r_E: transient periods") and stopping with [`Error::Interrupted`] when it is cancelled.
/// The result is [`energetic_restitution`]'s, bit for bit (the observer changes nothing of
/// the run).
///
/// # Errors
/// As [`energetic_restitution`]; [`Error::Interrupted`].
pub fn energetic_restitution_reporting(
    model: &BuiltModel,
    x0: &DVector<f64>,
    transient: u64,
    window: u64,
    progress: &dyn Progress,
) -> Result<OrbitCoefficient, Error> {
    orbit::TRANSIENT.check(transient as i128)?;
    orbit::WINDOW.check(window as i128)?;
    let sim = match model.variant() {
        Variant::Compliant(sim) => sim,
        Variant::Rigid(_) => return Err(Error::Unsupported(NO_CONTACT_FORCE.into())),
    };
    let task = progress.task("r_E: transient periods", transient);
    let x = sim.advance_reporting(x0, 0, transient, task.as_ref(), progress)?;
    drop(task);
    if progress.cancelled() {
        return Err(Error::Interrupted);
    }
    let found = coefficient_after(sim, &x, transient, window)?;
    if found.kind == OrbitKind::NotPeriodic {
        return Err(Error::NoPeriod(format!(
            "{} settles on no period of at most 32 forcing periods within {window} periods \
             after a transient of {transient} (best relative residual {:.1e}): r_E (eq 39) is \
             defined on a periodic orbit; give a longer transient or window, or another start",
            sim.name(),
            found.residual
        )));
    }
    Ok(found)
}

/// Runs `transient` periods from x0, labels the orbit over a `window` of periods, and if it
/// is periodic (period m) evaluates eq (39) over the m periods that follow.
///
/// # Errors
/// The run's errors ([`orbit::settle`]), a start of the wrong length among them.
pub fn orbit_coefficient(
    sim: &Simulator,
    x0: &DVector<f64>,
    transient: u64,
    window: u64,
) -> Result<OrbitCoefficient, Error> {
    let x = sim.run(x0, transient, &mut ())?.state;
    coefficient_after(sim, &x, transient, window)
}

/// [`orbit_coefficient`] from x, the state after the transient's `transient` periods.
fn coefficient_after(
    sim: &Simulator,
    x: &DVector<f64>,
    transient: u64,
    window: u64,
) -> Result<OrbitCoefficient, Error> {
    let settled = orbit::settle_after(sim, x, transient, window, 0)?;
    let cycle = (transient + window) as i64;
    let mut result = OrbitCoefficient {
        kind: settled.kind,
        residual: settled.residual,
        coefficient: None,
        energy_change_coefficient: None,
        contacts: Vec::new(),
        state: settled.state.as_slice().to_vec(),
        cycle,
    };
    if let OrbitKind::Periodic { m, .. } = settled.kind {
        let mut work = ContactWork::for_mode(sim.model(), 0)?;
        sim.run_from(&settled.state, sim.clock_at_cycle(cycle), m, &mut work)?;
        result.coefficient = Some(work.coefficient());
        result.energy_change_coefficient = Some(work.energy_change_coefficient());
        result.contacts = work.contacts;
    }
    Ok(result)
}
