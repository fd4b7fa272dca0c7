//! `cantilever simulate`: flags → the library's [`simulate`] → JSON, text, dense CSV and the
//! final state. The run itself (transient, window, strobe, dense grid, energy budget, stop
//! reasons, chunking) is the library's, the same call the Python package makes.

use crate::model_args::{ModelArgs, StartArgs};
use crate::progress::Bars;
use impacting_cantilever::analysis::simulate::{
    self, simulate, SimulateOptions, Simulation, DEFAULTS, DEFAULT_DENSE_PER_PERIOD,
};
use impacting_cantilever::engine::built::BuiltModel;
use impacting_cantilever::error::{Error, ParameterError};
use impacting_cantilever::model::galerkin::first_frequency;
use impacting_cantilever::model::spec::{ModelSpec, Named, Stop, Structure, Units};
use impacting_cantilever::results::files::write_together;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The command's inputs.
#[derive(Debug, Clone, clap::Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub start: StartArgs,
    /// Periods simulated and discarded before recording (0 to 1e8). A run that projects to
    /// take over 10 minutes says so after 2 s, with the time it projects.
    #[arg(long, value_parser = crate::model_args::whole)]
    pub periods: u64,
    /// Periods recorded after that (0 to 1e5).
    #[arg(long, value_parser = crate::model_args::whole, default_value_t = DEFAULTS.record)]
    pub record: u64,
    /// Skip the exact energy budget (energy_imbalance, energy_imbalance_bound and
    /// energy_imbalance_within_bound are then null): it adds about 20% to a run, at Figure
    /// 4's N = 10 as at stiff stops up to 1e12k₁ (instructions counted: 18% at N = 10,
    /// 17–21% at 1e11–1e12k₁ with N = 10–20). Compliant model only.
    #[arg(long)]
    pub no_energy: bool,
    /// Write the final state (JSON) to chain runs or pick one of coexisting attractors.
    #[arg(long)]
    pub final_state: Option<PathBuf>,
    /// Write dense output of the recorded window (CSV: t, in_contact, tip, tip velocity,
    /// η_j, η̇_j) to this file: record × dense-per-period rows, evenly spaced from the
    /// window's start, its end excluded (the end is the final state); a rigid run that
    /// stops inside the window ends with a row at the stop. At most 1e7 numbers.
    #[arg(long)]
    pub dense: Option<PathBuf>,
    /// Dense samples per forcing period (1 to 10 000; default 200; with --dense).
    #[arg(long, requires = "dense")]
    pub dense_per_period: Option<usize>,
    /// Relative periodicity tolerance on the stroboscopic map (§5.2's 1e-9), in (0, 1).
    #[arg(long, allow_hyphen_values = true, default_value_t = DEFAULTS.periodicity_tolerance)]
    pub periodicity_tolerance: f64,
    /// Largest period m searched (1 to 1000, and at most record/2).
    #[arg(long, default_value_t = DEFAULTS.max_period)]
    pub max_period: usize,
}

/// What the command computed, with what it was asked.
pub struct Report {
    pub args: SimulateArgs,
    pub spec: ModelSpec,
    pub model: BuiltModel,
    pub start: String,
    pub sim: Simulation,
}

impl SimulateArgs {
    /// The library's options.
    pub fn options(&self) -> SimulateOptions {
        SimulateOptions {
            periods: self.periods,
            record: self.record,
            dense_per_period: self
                .dense
                .as_ref()
                .map(|_| self.dense_per_period.unwrap_or(DEFAULT_DENSE_PER_PERIOD)),
            periodicity_tolerance: self.periodicity_tolerance,
            max_period: self.max_period,
            energy: !self.no_energy,
        }
    }
}

/// Parses, checks everything before the work (the outputs' paths too), runs, writes the
/// files.
pub fn run(args: &SimulateArgs) -> Result<Report, Error> {
    let spec = args.model.spec()?;
    if args.no_energy && spec.is_rigid() {
        return Err(ParameterError::new(
            "--no-energy",
            "given",
            "no --no-energy with --model rigid (the rigid model has no energy budget)",
        )
        .into());
    }
    let options = args.options();
    let model = BuiltModel::build(&spec)?;
    options.check(model.modes())?;
    let (start, file) = args.start.start(model.modes())?;
    let (x0, from) = model.start(&start)?;
    check_writable(args)?;
    let sim = simulate(&model, &x0, &options, &Bars::default())?;
    let report = Report {
        args: args.clone(),
        spec,
        model,
        start: file.unwrap_or(from),
        sim,
    };
    write_files(&report)?;
    Ok(report)
}

/// Fails early (exit 2) when an output file cannot be written, before any work.
fn check_writable(args: &SimulateArgs) -> Result<(), ParameterError> {
    use impacting_cantilever::results::files;
    for (flag, path) in [
        ("--final-state", &args.final_state),
        ("--dense", &args.dense),
    ] {
        if let Some(path) = path {
            files::check_writable(flag, path)?;
        }
    }
    // one file for both outputs: the second would silently replace the first (a character
    // device such as /dev/null can take both)
    if let (Some(a), Some(b)) = (&args.final_state, &args.dense) {
        let real = |p: &Path| {
            std::fs::canonicalize(p).ok().or_else(|| {
                let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
                let dir = std::fs::canonicalize(dir.unwrap_or(Path::new("."))).ok()?;
                Some(dir.join(p.file_name()?))
            })
        };
        let same = match (real(a), real(b)) {
            (Some(x), Some(y)) => x == y,
            _ => a == b,
        };
        let device = std::fs::metadata(a).is_ok_and(|m| {
            use std::os::unix::fs::FileTypeExt;
            m.file_type().is_char_device()
        });
        if same && !device {
            return Err(ParameterError::new(
                "--dense",
                b.display(),
                "a file other than --final-state's (one would overwrite the other)",
            ));
        }
    }
    Ok(())
}

/// The inputs as given (the model's parameters by the names this command's JSON has used
/// since schema 1).
fn inputs(r: &Report) -> Value {
    let Structure::Cantilever(c) = &r.spec.structure else {
        // the command line specifies only the cantilever
        return serde_json::to_value(&r.spec).unwrap_or_default();
    };
    let (k, law, restitution) = match r.spec.stop {
        Stop::Compliant { stop_stiffness } => (Some(stop_stiffness), None, None),
        Stop::Rigid { law, restitution } => (None, Some(law.name()), Some(restitution)),
    };
    json!({
        "modes": c.modes,
        "model": r.spec.kind(),
        "stop_stiffness_over_k1": k,
        "gap": c.gap,
        "gap_unit": c.gap_unit.name(),
        "zeta1": c.zeta1,
        "damping_reading": c.damping_reading.name(),
        "material_damping_gamma": r.model.galerkin().params().material_damping,
        "viscous_alpha": c.viscous,
        "omega_over_beta1_squared": c.omega,
        "forcing": r.args.model.forcing,
        "law": law,
        "restitution": restitution,
        "periods": r.args.periods,
        "record": r.args.record,
        "start": r.start,
    })
}

/// The JSON report without its events (field meanings in `cantilever simulate --help` and
/// the book's *Output formats*); [`write_json`] adds them.
pub fn to_json(r: &Report) -> Value {
    let s = &r.sim;
    json!({
        "inputs": inputs(r),
        "units": Units::of(r.model.galerkin()),
        "outcome": s.ending.to_string(),
        "period_m": s.period_m,
        "periodicity_residual": s.periodicity_residual,
        "periodicity_tolerance": r.args.periodicity_tolerance,
        "max_period_searched": s.max_period_searched,
        "impacts_n": s.impacts_n,
        "impacts_n_range": s.impacts_n_range.map(|(lo, hi)| [lo, hi]),
        // the same, under its name before schema version 1 (kept for one release)
        "impacts_per_period": s.impacts_n,
        "contacts_in_window": s.contacts_in_window,
        "shallow_flights": s.shallow_flights,
        "flight_resolution": s.flight_resolution,
        "max_tip": s.max_tip.map(|m| m.value),
        "max_tip_time": s.max_tip.map(|m| m.time),
        "max_tip_tolerance": s.max_tip.map(|m| m.tolerance),
        "energy_imbalance": s.energy_imbalance,
        "energy_imbalance_bound": s.energy_imbalance_bound,
        "energy_imbalance_within_bound": s.energy_imbalance.zip(s.energy_imbalance_bound).map(|(e, b)| e <= b),
        "eigenvector_condition": s.condition,
        "wall_seconds": s.wall_seconds,
        "final_time": s.final_clock.time(),
    })
}

/// Writes the JSON report: `head` with the events last, serialized straight from the
/// events into `out` (a `Value` per event took ~5 kB: 1 GB for 2·10⁵ events).
pub fn write_json(
    r: &Report,
    head: Value,
    out: &mut dyn std::io::Write,
) -> Result<(), serde_json::Error> {
    #[derive(serde::Serialize)]
    struct Doc<'a> {
        #[serde(flatten)]
        head: Value,
        events: &'a [simulate::SimEvent],
    }
    serde_json::to_writer_pretty(
        out,
        &Doc {
            head,
            events: &r.sim.events,
        },
    )
}

/// The text report.
pub fn to_text(r: &Report) -> String {
    let s = &r.sim;
    let mut t = String::new();
    let rigid = r.spec.is_rigid();
    t.push_str(if rigid {
        "impacts in the recorded window (t, phase/T, tip velocity before → after):\n"
    } else {
        "contact events in the recorded window (t, phase/T, direction, tip velocity):\n"
    });
    for e in &s.events {
        match e.outgoing_tip_velocity {
            Some(out) => t.push_str(&format!(
                "  t = {:>16.10}  {:.6}  v = {:+.6e} → {:+.6e}\n",
                e.time, e.phase, e.tip_velocity, out
            )),
            None => {
                let dir = match (e.grazing, e.entering) {
                    (true, _) => "graze",
                    (false, true) => "enter",
                    (false, false) => "leave",
                };
                t.push_str(&format!(
                    "  t = {:>16.10}  {:.6}  {dir:<5}  v = {:+.6e}\n",
                    e.time, e.phase, e.tip_velocity
                ));
            }
        }
    }
    let completed = s.ending == simulate::Ending::Completed;
    if !completed {
        t.push_str(&format!("run {}\n", s.ending));
    }
    let what = if rigid { "impacts" } else { "contacts" };
    match (s.period_m, s.periodicity_residual) {
        (Some(m), res) => {
            let n = match s.impacts_n_range {
                Some((lo, hi)) if lo != hi => format!("{lo}–{hi}"),
                _ => s.impacts_n.unwrap_or(0).to_string(),
            };
            t.push_str(&format!(
                "orbit: ({m}, {n}) — period {m}, {n} {what} per period (residual {:.1e})\n",
                res.unwrap_or(0.0)
            ));
            if let Some((lo, hi)) = s.impacts_n_range.filter(|(lo, hi)| lo != hi) {
                let blocks = if m == 1 {
                    "the window's periods".to_string()
                } else {
                    format!("the window's blocks of {m} periods")
                };
                t.push_str(&format!(
                    "  {lo} to {hi} {what} in {blocks}: round-off decides at least one event (a \
                     flight or contact within round-off of the stop), so the count is not exact\n"
                ));
            }
        }
        (None, Some(res)) => t.push_str(&format!(
            "orbit: no period m ≤ {} within {} recorded periods (best residual {res:.1e}); {} \
             {what} in the window\n",
            s.max_period_searched, r.args.record, s.contacts_in_window
        )),
        (None, None) => t.push_str(&format!(
            "orbit: not tested ({}); {} {what} in the window\n",
            if completed {
                "needs at least 2 recorded periods"
            } else {
                "the run stopped before 2 periods were recorded"
            },
            s.contacts_in_window
        )),
    }
    if s.shallow_flights > 0 {
        t.push_str(&format!(
            "  these counts are not certified: {} flights between contacts rise less than the \
             flow's accuracy bound {:.0e} (κε × the motion's size) from the stop; where such \
             flights are many, round-off decides the counts\n",
            s.shallow_flights, s.flight_resolution
        ));
    }
    match s.max_tip {
        Some(m) => t.push_str(&format!(
            "max tip displacement: {:.12e} at t = {:.10} (certified to ±{:.0e})\n",
            m.value, m.time, m.tolerance
        )),
        None if !rigid => t.push_str("max tip displacement: — (no recorded periods)\n"),
        None => {}
    }
    match (s.energy_imbalance, s.energy_imbalance_bound) {
        (Some(e), Some(b)) if e > b => t.push_str(&format!(
            "energy imbalance: {e:.2e} — ABOVE its round-off bound {b:.1e} (κε√segments): \
             the flow or the energy integrals are less accurate than κε at this N and k\n"
        )),
        (Some(e), Some(b)) => t.push_str(&format!(
            "energy imbalance: {e:.2e} (within its round-off bound {b:.1e}, κε√segments)\n"
        )),
        _ => {}
    }
    t.push_str(&format!(
        "eigenvector condition: {:.1e} (flow accurate to ~{:.0e})\n",
        s.condition,
        s.condition * f64::EPSILON
    ));
    let model = r.model.galerkin();
    t.push_str(&format!(
        "units: T = {:.10}, (β₁⁻)² = {:.10}, free tip amplitude at ω = {:.6e}\n",
        2.0 * std::f64::consts::PI / model.omega(),
        first_frequency(),
        model.free_tip_amplitude().0
    ));
    t.push_str(&format!("wall time: {:.4} s\n", s.wall_seconds));
    t
}

/// Writes --dense and --final-state as one set: both new, or (after a failure or a signal)
/// both as they were.
fn write_files(r: &Report) -> Result<(), Error> {
    let mut outputs: Vec<(&Path, String)> = Vec::new();
    if let (Some(path), Some(dense)) = (&r.args.dense, &r.sim.dense) {
        let n = r.model.modes();
        let mut csv = String::from("t,in_contact,tip,tip_velocity");
        for j in 1..=n {
            csv.push_str(&format!(",eta_{j}"));
        }
        for j in 1..=n {
            csv.push_str(&format!(",eta_dot_{j}"));
        }
        csv.push('\n');
        for i in 0..dense.len() {
            csv.push_str(&format!(
                "{:.17e},{},{:.17e},{:.17e}",
                dense.t[i],
                u8::from(dense.in_contact[i]),
                dense.tip[i],
                dense.tip_velocity[i]
            ));
            for value in &dense.states[2 * n * i..2 * n * (i + 1)] {
                csv.push_str(&format!(",{value:.17e}"));
            }
            csv.push('\n');
        }
        outputs.push((path, csv));
    }
    if let Some(path) = &r.args.final_state {
        let c = r.sim.final_clock;
        let doc = json!({
            "modes": r.model.modes(),
            "schema_version": impacting_cantilever::results::scene::SCHEMA_VERSION,
            "time": c.time(),
            "cycle": c.cycles,
            "phase": c.offset / c.period,
            "state": r.sim.final_state.iter().collect::<Vec<_>>(),
            "inputs": inputs(r),
        });
        outputs.push((path, serde_json::to_string_pretty(&doc).unwrap_or_default()));
    }
    let outputs: Vec<(&Path, &str)> = outputs.iter().map(|(p, t)| (*p, t.as_str())).collect();
    write_together(&outputs)
}
