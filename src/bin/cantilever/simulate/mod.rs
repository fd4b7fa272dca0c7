//! `cantilever simulate`: the paper's forced simulation (§5.2) — a transient discarded, then
//! a recorded window: contact events, the period m and contacts per period n, the
//! certified maximum of the tip, the exact energy budget. The engine is
//! [`impacting_cantilever::engine::sim`]; the rigid-impact model is [`impacting_cantilever::engine::rigid`].
//!
//! Units (stated in `--help` and in the JSON): time and frequency of the non-dimensional
//! beam (EI = ρA = L = 1); k in units of k₁ = (β₁⁻)⁴, ω in units of (β₁⁻)²; lengths in units
//! of the free tip amplitude at resonance (1 with the corrected eq (37) forcing, errata E2).

mod output;
mod run;

pub use output::{to_json, to_text, write_json};
pub use run::run;

use impacting_cantilever::error::{self, ParameterError};
use impacting_cantilever::model::galerkin::{
    self, first_frequency, first_modal_stiffness, Forcing, GalerkinModel, GalerkinParams,
    SpatialProfile,
};
use impacting_cantilever::model::restitution;
use nalgebra::{DMatrix, DVector};
use std::path::PathBuf;

/// Largest number of discarded periods (at ~10 µs a period for N = 10, about 20 minutes).
pub const MAX_PERIODS: u64 = 100_000_000;
/// Most numbers in a dense output (~250 MB of CSV, held in memory before it is written).
const MAX_DENSE_NUMBERS: u64 = 10_000_000;

/// Largest number of recorded periods (their events and the strobe are kept in memory).
pub const MAX_RECORD: u64 = 100_000;
/// Supported |d₀| (units of the free tip amplitude at resonance): beyond it the stop is
/// either never reached or the static preload dwarfs the forced response by more than the
/// digits a double holds for both.
pub const MAX_GAP: f64 = 1e6;
/// Supported ζ₁: below 1e-8 a transient outlasts any run (decay time 1/(ζ₁(β₁⁻)²) > 1e7
/// periods) and the paper's forcing, of amplitude ζ₁k₁, sinks into round-off.
pub const ZETA1_RANGE: (f64, f64) = (1e-8, 1e3);
/// Supported ω/(β₁⁻)²: below 1e-3 one forcing period spans over 1e3 periods of the
/// lowest mode and the stop mode must be resolved throughout; above 1e4 the forced
/// response (∝ ω⁻²) falls below 1e-8 of the resonant one and the phase ωt loses digits.
pub const OMEGA_RANGE: (f64, f64) = (1e-3, 1e4);
/// The longest period the window is searched for: `--max-period`, and at most half the
/// recorded periods (a period must be seen twice).
pub fn period_search_depth(args: &SimulateArgs) -> usize {
    args.max_period.min(args.record as usize / 2)
}

/// Supported k/k₁ (compliant model): beyond 1e12 the contact basis loses more than
/// 8 digits (its condition grows like √k).
pub const MAX_STIFFNESS: f64 = 1e12;

/// The model variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// The N-mode compliant (bilinear) model, eq (34).
    Compliant,
    /// The rigid-impact model (§3) with a modal restitution law.
    Rigid,
}

/// The rigid model's impact law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Law {
    /// [R]_N, the stiffness limit (eq 29), with r_e = --restitution.
    StiffnessLimit,
    /// [R]_IR, impulse response (eq 14).
    ImpulseResponse,
    /// [R]_C, collocation at equally spaced points (eq 12).
    Collocation,
    /// Newton's law η̇⁺ = −rη̇⁻ (N = 1 only).
    Newton,
}

/// How ζ₁ sets the material damping γ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DampingReading {
    /// γ = 2ζ₁/(β₁⁻)², so mode 1's damping ratio is ζ₁ (the Fig 9 caption; errata E3).
    Fig9,
    /// The Fig 4 caption taken literally: γ = 2ζ₁(β₁⁻)² (mode 1's ratio is then ζ₁k₁).
    Fig4Literal,
}

/// The command's inputs (also its command-line flags).
#[derive(Debug, Clone, clap::Args)]
pub struct SimulateArgs {
    /// N, the number of modes (1 to 400).
    #[arg(long)]
    pub modes: usize,
    /// Stop stiffness as k/k₁, k₁ = (β₁⁻)⁴ ≈ 12.36 (0 to 1e12; compliant model only).
    #[arg(long, allow_hyphen_values = true, default_value_t = 100.0)]
    pub stop_stiffness: f64,
    /// Gap d₀ between the tip at rest and the stop, in units of the free tip amplitude at
    /// resonance (|d₀| ≤ 1e6; negative: preloaded).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub gap: f64,
    /// ζ₁, the first mode's damping ratio (material damping; 1e-8 to 1e3).
    #[arg(long, allow_hyphen_values = true)]
    pub zeta1: f64,
    /// How ζ₁ sets γ: fig9 (γ = 2ζ₁/(β₁⁻)²) or fig4-literal (γ = 2ζ₁(β₁⁻)²).
    #[arg(long, value_enum, default_value_t = DampingReading::Fig9)]
    pub damping_reading: DampingReading,
    /// Viscous damping α (≥ 0, entering as 2α, eq 1).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub viscous: f64,
    /// Forcing frequency as ω/(β₁⁻)² (1e-3 to 1e4).
    #[arg(long, allow_hyphen_values = true)]
    pub omega: f64,
    /// Forcing amplitude: `unit` (eq 37 corrected: free tip amplitude 1 at resonance),
    /// `printed` (eq 37 as printed, 1/(4ζ₁²) larger), or a number f₁ (the profile φ₁(s),
    /// modal force f₁ cos ωt on mode 1).
    #[arg(long, allow_hyphen_values = true, default_value = "unit")]
    pub forcing: String,
    /// Periods simulated and discarded before recording (≤ 1e8). A run that projects to take
    /// over 10 minutes says so after 2 s, with the time it projects.
    #[arg(long)]
    pub periods: u64,
    /// Periods recorded after that (≤ 1e5).
    #[arg(long, default_value_t = 32)]
    pub record: u64,
    /// Skip the exact energy budget (energy_imbalance is then absent): it adds about 20%
    /// to a run, at Figure 4's N = 10 as at stiff stops up to 1e12k₁ (instructions counted:
    /// 18% at N = 10, 17–21% at 1e11–1e12k₁ with N = 10–20).
    #[arg(long)]
    pub no_energy: bool,
    /// The model: compliant (eq 34) or rigid (§3).
    #[arg(long, value_enum, default_value_t = ModelKind::Compliant)]
    pub model: ModelKind,
    /// The rigid model's law.
    #[arg(long, value_enum, default_value_t = Law::StiffnessLimit)]
    pub law: Law,
    /// The rigid model's coefficient of restitution r (r_e for the stiffness limit), in [0, 1].
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.8)]
    pub restitution: f64,
    /// Start from a modal state [η; η̇] in a JSON file (an array of 2N numbers, or the
    /// object written by --final-state: of the same N, and ended at a period boundary, as
    /// every run starts at phase 0 of the forcing).
    #[arg(long, conflicts_with_all = ["initial_profile", "seed"])]
    pub initial_state: Option<PathBuf>,
    /// Start from displacement and velocity profiles in a JSON file
    /// {"s": [...], "w": [...], "w_t": [...]} on [0, 1], interpolated linearly and projected
    /// onto the N modes.
    #[arg(long, conflicts_with = "seed")]
    pub initial_profile: Option<PathBuf>,
    /// Start from a random state (each η_j uniform in ±2A_free/N, η̇_j in ±2ωA_free/N) of this
    /// seed. The rigid model refuses a seed whose start puts the tip beyond its stop.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Write the final state (JSON) to chain runs or pick one of coexisting attractors.
    #[arg(long)]
    pub final_state: Option<PathBuf>,
    /// Write dense output of the recorded window (CSV: t, region, tip, tip velocity, η_j,
    /// η̇_j) to this file: record × dense-per-period rows, evenly spaced from the window's
    /// start, its end excluded (the end is the final state); a rigid run that stops inside
    /// the window ends with a row at the stop.
    #[arg(long)]
    pub dense: Option<PathBuf>,
    /// Dense samples per forcing period (1 to 10 000).
    #[arg(long, default_value_t = 200)]
    pub dense_per_period: usize,
    /// Relative periodicity tolerance on the stroboscopic map (§5.2's 1e-9, relative).
    #[arg(long, allow_hyphen_values = true, default_value_t = 1e-9)]
    pub periodicity_tolerance: f64,
    /// Largest period m searched (≤ 1000 and ≤ record/2).
    #[arg(long, default_value_t = 32)]
    pub max_period: usize,
}

/// What the model and its start are, validated.
pub struct Setup {
    /// The model.
    pub model: GalerkinModel,
    /// The rigid model's law (None: compliant).
    pub law: Option<DMatrix<f64>>,
    /// The initial state.
    pub x0: DVector<f64>,
    /// Where it came from.
    pub start: String,
}

fn range(name: &str, value: f64, (lo, hi): (f64, f64)) -> Result<f64, ParameterError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(ParameterError::new(
            name,
            error::number(value),
            &format!(
                "a number from {} to {}",
                error::number(lo),
                error::number(hi)
            ),
        ))
    }
}

/// Validates every input against the ranges the method supports (before any work).
pub fn validate(args: &SimulateArgs) -> Result<(), ParameterError> {
    error::count_in_range("--modes (N)", args.modes, galerkin::MAX_MODES)?;
    range(
        "--stop-stiffness (k/k₁)",
        args.stop_stiffness,
        (0.0, MAX_STIFFNESS),
    )?;
    range("--gap (d₀)", args.gap, (-MAX_GAP, MAX_GAP))?;
    range("--zeta1 (ζ₁)", args.zeta1, ZETA1_RANGE)?;
    range("--viscous (α)", args.viscous, (0.0, 1e6))?;
    range("--omega (ω/(β₁⁻)²)", args.omega, OMEGA_RANGE)?;
    range("--restitution (r)", args.restitution, (0.0, 1.0))?;
    if args.periods > MAX_PERIODS {
        return Err(ParameterError::new(
            "--periods",
            args.periods,
            &format!("an integer from 0 to {MAX_PERIODS}"),
        ));
    }
    if args.record > MAX_RECORD {
        return Err(ParameterError::new(
            "--record",
            args.record,
            &format!("an integer from 0 to {MAX_RECORD}"),
        ));
    }
    if args.periods == 0 && args.record == 0 {
        return Err(ParameterError::new(
            "--periods/--record",
            0,
            "at least one period in all",
        ));
    }
    error::count_in_range("--max-period", args.max_period, 1000)?;
    error::count_in_range("--dense-per-period", args.dense_per_period, 10_000)?;
    if args.dense.is_some() {
        // rows of t, region, tip, tip velocity and the 2N state, ~25 bytes a number in the
        // CSV: refused upfront with the projected size rather than run out of memory
        let rows = (args.record * args.dense_per_period as u64).max(1) + 1;
        let numbers = rows.saturating_mul(4 + 2 * args.modes as u64);
        if numbers > MAX_DENSE_NUMBERS {
            return Err(ParameterError::new(
                "--dense",
                format!(
                    "{rows} rows of {} numbers (~{} MB of CSV) for --record {} × --dense-per-period {}",
                    4 + 2 * args.modes,
                    numbers * 25 / 1_000_000,
                    args.record,
                    args.dense_per_period
                ),
                &format!(
                    "at most {MAX_DENSE_NUMBERS} numbers (~250 MB): fewer recorded periods or \
                     samples per period, or the window in pieces (--final-state, then \
                     --initial-state)"
                ),
            ));
        }
    }
    if !(args.periodicity_tolerance > 0.0 && args.periodicity_tolerance < 1.0) {
        return Err(ParameterError::new(
            "--periodicity-tolerance",
            args.periodicity_tolerance,
            "a number in (0, 1)",
        ));
    }
    let from_rest =
        args.initial_state.is_none() && args.initial_profile.is_none() && args.seed.is_none();
    if args.model == ModelKind::Rigid && from_rest && args.gap < 0.0 {
        return Err(ParameterError::new(
            "--gap (d₀)",
            error::number(args.gap),
            "a number ≥ 0 for the rigid model from rest (at rest the tip would start beyond \
             a rigid stop, which cannot be penetrated; a preloaded stop, d₀ < 0, is the \
             compliant model's)",
        ));
    }
    if args.model == ModelKind::Rigid && args.law == Law::Newton && args.modes != 1 {
        return Err(ParameterError::new(
            "--law newton",
            format!("N = {}", args.modes),
            "N = 1 (for N > 1 choose stiffness-limit, impulse-response or collocation)",
        ));
    }
    Ok(())
}

fn forcing(args: &SimulateArgs) -> Result<Forcing, ParameterError> {
    let omega = args.omega * first_frequency();
    let profile = match args.forcing.as_str() {
        "unit" => SpatialProfile::UnitTipAtResonance,
        "printed" => SpatialProfile::PaperEq37AsPrinted,
        other => {
            let f1: f64 = other.parse().map_err(|_| {
                ParameterError::new("--forcing", other, "unit, printed, or a number f₁")
            })?;
            range("--forcing (f₁)", f1, (-1e12, 1e12))?;
            if f1 != 0.0 && f1.abs() < MIN_SCALE {
                return Err(tiny("--forcing (f₁)", f1));
            }
            SpatialProfile::Modal(vec![f1])
        }
    };
    Ok(Forcing { omega, profile })
}

/// The smallest nonzero forcing amplitude or initial state accepted. The model is linear in
/// each region, so a problem this small is the same problem scaled; below about 1e-150 the
/// certified crossing search loses its resolution (measured: 1e-154 runs in 0.03 s per
/// period, 1e-160 does not finish), and 1e-100 leaves fifty decades of margin.
pub const MIN_SCALE: f64 = 1e-100;

/// The largest initial state entry accepted (in units of the free tip amplitude at
/// resonance, like |d₀| ≤ 1e6): beyond it the energies, squares of the state, lose their
/// meaning long before they overflow.
pub const MAX_STATE: f64 = 1e6;

/// A magnitude too small for the method, with the way out.
pub fn tiny(name: &str, value: f64) -> ParameterError {
    ParameterError::new(
        name,
        error::number(value),
        "0 or a magnitude of at least 1e-100 (the model is linear in each region: scale the \
         forcing, the state and the gap together instead)",
    )
}

/// The model the options describe (validated), without the law or the start state.
pub fn model(args: &SimulateArgs) -> Result<GalerkinModel, ParameterError> {
    validate(args)?;
    let mut params = GalerkinParams::new(args.modes, args.stop_stiffness * first_modal_stiffness())
        .with_gap(args.gap)
        .with_viscous_damping(args.viscous)
        .with_forcing(forcing(args)?);
    params.material_damping = match args.damping_reading {
        DampingReading::Fig9 => galerkin::material_damping_from_zeta1(args.zeta1),
        DampingReading::Fig4Literal => 2.0 * args.zeta1 * first_frequency(),
    };
    GalerkinModel::new(params)
}

/// The model, restitution law and start state the options describe.
pub fn setup(args: &SimulateArgs) -> Result<Setup, ParameterError> {
    let model = model(args)?;
    let n = args.modes;
    let law = match args.model {
        ModelKind::Compliant => None,
        ModelKind::Rigid => Some(match args.law {
            Law::StiffnessLimit => restitution::stiffness_limit(n, args.restitution)?,
            Law::ImpulseResponse | Law::Newton => {
                restitution::impulse_response(n, args.restitution)?
            }
            Law::Collocation => restitution::collocation(
                n,
                args.restitution,
                &restitution::equally_spaced_points(n),
            )?,
        }),
    };
    let (x0, start) = output::initial_state(args, &model)?;
    Ok(Setup {
        model,
        law,
        x0,
        start,
    })
}
