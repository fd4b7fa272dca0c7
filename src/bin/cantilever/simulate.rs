//! `cantilever simulate` (the command; the engine is [`impacting_cantilever::sim`]): the paper's forced simulation (§5.2) from rest — discard a
//! transient, record contact events, detect the period m and the contacts per period n.
//!
//! Parameters are in the CLI's units: k/k₁ and ω/(β₁⁻)². The forcing is eq (37) with the
//! corrected amplitude (unit unconstrained tip amplitude at resonance; errata E2), and the
//! damping is material, γ = 2ζ₁/(β₁⁻)² (errata E3).

use impacting_cantilever::error::Error;
use impacting_cantilever::error::{self, ParameterError};
use impacting_cantilever::galerkin::{self, GalerkinModel};
use impacting_cantilever::orbit::{detect_period, MAX_PERIOD, PERIODIC_TOLERANCE};
use impacting_cantilever::problems::Forced;
use impacting_cantilever::sim::{Energy, Event, Events, Simulator, Strobe, TipMax, TipMaximum};
use nalgebra::DVector;
use std::time::Instant;

/// The command's inputs (also its command-line flags).
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// N, the number of modes.
    #[arg(long)]
    pub modes: usize,
    /// Stop stiffness as k/k₁.
    #[arg(long, allow_negative_numbers = true)]
    pub stop_stiffness: f64,
    /// Gap d₀.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub gap: f64,
    /// ζ₁, the first mode's damping ratio (material damping).
    #[arg(long, allow_negative_numbers = true)]
    pub zeta1: f64,
    /// Forcing frequency as ω/(β₁⁻)².
    #[arg(long, allow_negative_numbers = true)]
    pub omega: f64,
    /// Periods simulated (and discarded) before recording.
    #[arg(long)]
    pub periods: u64,
    /// Periods recorded after that.
    #[arg(long, default_value_t = 32)]
    pub record: u64,
}

/// What the command reports.
#[derive(Debug, Clone)]
pub struct Report {
    /// The inputs.
    pub args: Args,
    /// Contact events in the recorded window.
    pub events: Vec<Event>,
    /// The smallest m ≤ min(32, record/2) with ‖x(t₀ + mT) − x(t₀)‖∞ < 1e-9‖x(t₀)‖∞
    /// ([`crate::orbit`]), if any.
    pub period_m: Option<u64>,
    /// The smallest relative residual over those m.
    pub periodicity_residual: f64,
    /// Entries into contact in the last m periods (or in the whole window if not periodic).
    pub impacts_n: u64,
    /// Largest tip displacement in the window, certified (none without a window).
    pub max_tip: Option<TipMaximum>,
    /// Relative energy imbalance over the whole run.
    pub energy_imbalance: f64,
    /// The larger eigenvector condition ‖V‖₁‖V⁻¹‖₁ of the two region flows: the flow is
    /// accurate to about this times ε.
    pub eigenvector_condition: f64,
    /// Wall time of the simulation.
    pub wall_seconds: f64,
}

/// Builds the paper's forced model from CLI units, validating every input.
pub fn model(args: &Args) -> Result<GalerkinModel, ParameterError> {
    error::count_in_range("--modes (N)", args.modes, galerkin::MAX_MODES)?;
    error::finite_non_negative("--stop-stiffness (k/k₁)", args.stop_stiffness)?;
    error::finite("--gap (d₀)", args.gap)?;
    error::finite_positive("--zeta1 (ζ₁)", args.zeta1)?;
    error::finite_positive("--omega (ω/(β₁⁻)²)", args.omega)?;
    if args.periods == 0 && args.record == 0 {
        return Err(ParameterError::new(
            "--periods/--record",
            0,
            "at least one period in all",
        ));
    }
    Forced {
        modes: args.modes,
        k_over_k1: args.stop_stiffness,
        zeta1: args.zeta1,
        omega_over_w1: args.omega,
        gap: args.gap,
        printed_eq37_amplitude: false,
    }
    .model()
}

/// Runs the command.
pub fn run(args: &Args) -> Result<Report, Error> {
    let model = model(args)?;
    let started = Instant::now();
    let sim = Simulator::new(model)?;
    let n2 = 2 * sim.model().modes();
    let rest = DVector::zeros(n2);
    let mut transient = Energy::default();
    let x = sim.run(&rest, args.periods, &mut transient)?.state;
    let start = sim.clock_at_cycle(args.periods as i64);
    let (mut events, mut strobe, mut energy, mut max_tip) = (
        Events::default(),
        Strobe::default(),
        Energy::default(),
        TipMax::default(),
    );
    sim.run_from(
        &x,
        start,
        args.record,
        &mut (&mut events, &mut strobe, &mut energy, &mut max_tip),
    )?;
    let wall_seconds = started.elapsed().as_secs_f64();
    let (period_m, periodicity_residual) = detect_period(
        &strobe.states(),
        PERIODIC_TOLERANCE,
        MAX_PERIOD.min(args.record as usize / 2),
    );
    let last_cycle = start.cycles + args.record as i64;
    let from_cycle = last_cycle - period_m.unwrap_or(args.record) as i64;
    let impacts_n = events
        .events
        .iter()
        .filter(|e| e.entering && !e.grazing && e.clock.cycles >= from_cycle)
        .count() as u64;
    let total = transient.budget.then(&energy.budget);
    Ok(Report {
        args: args.clone(),
        events: events.events,
        period_m,
        periodicity_residual,
        impacts_n,
        max_tip: max_tip.maximum,
        energy_imbalance: total.relative_imbalance(),
        eigenvector_condition: sim.condition(),
        wall_seconds,
    })
}

impl Report {
    /// The JSON form (keys as in the CLI's documentation).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "modes": self.args.modes,
            "stop_stiffness_over_k1": self.args.stop_stiffness,
            "gap": self.args.gap,
            "zeta1": self.args.zeta1,
            "omega_over_w1": self.args.omega,
            "periods": self.args.periods,
            "record": self.args.record,
            "period_m": self.period_m,
            "impacts_n": self.impacts_n,
            "periodicity_residual": self.periodicity_residual,
            "max_tip": self.max_tip.map(|m| m.value),
            "max_tip_time": self.max_tip.map(|m| m.time),
            "max_tip_tolerance": self.max_tip.map(|m| m.tolerance),
            "energy_imbalance": self.energy_imbalance,
            "eigenvector_condition": self.eigenvector_condition,
            "wall_seconds": self.wall_seconds,
            "events": self.events.iter().map(|e| serde_json::json!({
                "time": e.time,
                "cycle": e.clock.cycles,
                "entering": e.entering,
                "grazing": e.grazing,
                "tip_velocity": e.tip_velocity,
            })).collect::<Vec<_>>(),
        })
    }

    /// The text form.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        s.push_str("contact events in the recorded window (t, direction, tip velocity):\n");
        for e in &self.events {
            let dir = match (e.grazing, e.entering) {
                (true, _) => "graze",
                (false, true) => "enter",
                (false, false) => "leave",
            };
            s.push_str(&format!(
                "  t = {:>16.10}  {dir:<5}  v = {:+.6e}\n",
                e.time, e.tip_velocity
            ));
        }
        match self.period_m {
            Some(m) => s.push_str(&format!(
                "orbit: ({m}, {}) — period {m}, {} contacts per period (residual {:.1e})\n",
                self.impacts_n, self.impacts_n, self.periodicity_residual
            )),
            None => s.push_str(&format!(
                "orbit: not periodic within {} periods (best residual {:.1e}); {} contacts recorded\n",
                self.args.record / 2,
                self.periodicity_residual,
                self.impacts_n
            )),
        }
        match self.max_tip {
            Some(m) => s.push_str(&format!(
                "max tip displacement: {:.12e} at t = {:.10} (certified to ±{:.0e})\n",
                m.value, m.time, m.tolerance
            )),
            None => s.push_str("max tip displacement: — (no recorded periods)\n"),
        }
        s.push_str(&format!(
            "energy imbalance: {:.2e}\n",
            self.energy_imbalance
        ));
        s.push_str(&format!(
            "eigenvector condition: {:.1e} (flow accurate to ~{:.0e})\n",
            self.eigenvector_condition,
            self.eigenvector_condition * f64::EPSILON
        ));
        s.push_str(&format!("wall time: {:.4} s\n", self.wall_seconds));
        s
    }
}
