//! The comparison with other tools: the results of the peer scripts of `peers/` (scipy,
//! Siconos, SUNDIALS CVODE, mpmath references; written by `python3 peers/run.py` into
//! `peers/results/`), read
//! and checked here, and this project's values for the same problems recomputed by the library
//! so that a committed file can be told from a stale one.
//!
//! A file carries a checksum of everything else in it: FNV-1a (64 bit) of a canonical byte
//! encoding of the JSON value (numbers as the 16 hex digits of their IEEE-754 double, strings
//! with their byte length, object keys sorted), the same as `peers/common.py` computes. It
//! detects an edit, not a forgery.

use crate::analysis::shooting::{self, PeriodicOrbit};
use crate::engine::map::PeriodMap;
use crate::engine::rigid::RigidImpact;
use crate::engine::sim::Simulator;
use crate::error::Error;
use crate::model::galerkin::{first_frequency, first_modal_stiffness, Region};
use crate::model::problems::Forced;
use crate::model::restitution;
use nalgebra::{DMatrix, DVector};
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::BTreeMap;

/// The format named in every file (v2: every time the best CPU time of the solve alone;
/// CVODE and this project's Dormand–Prince among the rows).
pub const FORMAT: &str = "impacting-cantilever peer results v2";

/// The `tool` of this project's own Dormand–Prince rows: not a peer.
pub const OWN: &str = "cantilever";

/// The committed files: the simulation problems in the book's order, then the orbits.
pub const FILES: [(&str, &str); 6] = [
    (
        "oscillator",
        include_str!("../../peers/results/oscillator.json"),
    ),
    ("chatter", include_str!("../../peers/results/chatter.json")),
    (
        "rigid-n2",
        include_str!("../../peers/results/rigid-n2.json"),
    ),
    ("fig4-n3", include_str!("../../peers/results/fig4-n3.json")),
    (
        "fig4-n10",
        include_str!("../../peers/results/fig4-n10.json"),
    ),
    ("orbits", include_str!("../../peers/results/orbits.json")),
];

/// FNV-1a, 64 bit, as 16 hex digits.
pub fn fnv1a64(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The canonical encoding of a JSON value (see the module's documentation).
pub fn canonical(v: &Value, out: &mut Vec<u8>) {
    match v {
        Value::Null => out.push(b'n'),
        Value::Bool(true) => out.push(b't'),
        Value::Bool(false) => out.push(b'f'),
        Value::Number(x) => {
            let bits = x.as_f64().unwrap_or(f64::NAN).to_bits();
            out.extend_from_slice(format!("d{bits:016x}").as_bytes());
        }
        Value::String(s) => {
            out.extend_from_slice(format!("s{}:", s.len()).as_bytes());
            out.extend_from_slice(s.as_bytes());
        }
        Value::Array(a) => {
            out.push(b'[');
            a.iter().for_each(|x| canonical(x, out));
            out.push(b']');
        }
        Value::Object(o) => {
            let mut keys: Vec<&String> = o.keys().collect();
            keys.sort();
            out.push(b'{');
            for k in keys {
                canonical(&Value::String(k.clone()), out);
                canonical(&o[k], out);
            }
            out.push(b'}');
        }
    }
}

/// The checksum of a document: of everything in it but its `checksum` field.
pub fn checksum(doc: &Value) -> String {
    let mut body = doc.clone();
    if let Value::Object(o) = &mut body {
        o.remove("checksum");
    }
    let mut bytes = Vec::new();
    canonical(&body, &mut bytes);
    fnv1a64(&bytes)
}

/// The machine the times were measured on.
#[derive(Debug, Clone, Deserialize)]
pub struct Machine {
    /// The CPU model.
    pub cpu: String,
    /// Logical cores.
    pub cores: u64,
    /// Operating system and architecture.
    pub os: String,
    /// The 1, 5 and 15 minute load averages when the problem's runs began.
    pub load_average_at_start: Vec<f64>,
    /// The same when its file was written.
    pub load_average_when_written: Vec<f64>,
}

/// How the runs were timed and compared.
#[derive(Debug, Clone, Deserialize)]
pub struct Protocol {
    /// Runs per setting, alternated between the tools (the best is kept).
    pub repeats: usize,
    /// Solves of a compiled tool (this project, its Dormand–Prince, CVODE) inside each run,
    /// at most (until 1 s of CPU; the best is that run's time).
    pub inner_repeats: usize,
    /// CPU seconds of a run beyond which a tolerance ladder stops.
    pub budget_seconds: f64,
    /// What is timed.
    pub timing: String,
    /// What each tool's time includes: (tool, one sentence).
    pub includes: Vec<(String, String)>,
    /// What the errors measure.
    pub error: String,
}

/// One simulation problem as the peer scripts ran it.
#[derive(Debug, Clone, Deserialize)]
pub struct ProblemSpec {
    /// Its name in the book.
    pub title: String,
    /// `rigid` or `compliant`.
    pub model: String,
    /// The rigid model's law (`newton`, `impulse-response`).
    pub law: Option<String>,
    /// The rigid model's coefficient of restitution.
    pub restitution: Option<f64>,
    /// N.
    pub modes: usize,
    /// ζ₁.
    pub zeta1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_beta1_squared: f64,
    /// d₀.
    pub gap: f64,
    /// k/k₁ (the compliant model).
    pub stop_stiffness_over_k1: Option<f64>,
    /// [η; η̇] at t = 0.
    pub initial_state: Vec<f64>,
    /// Forcing periods run.
    pub periods: u64,
    /// How the independent reference was computed.
    pub reference: String,
}

/// The independent reference.
#[derive(Debug, Clone, Deserialize)]
pub struct Reference {
    /// How.
    pub method: String,
    /// Decimal digits of its arithmetic.
    pub digits: u32,
    /// The state at the end of each period, k = 1 … P.
    pub strobe: Vec<Vec<f64>>,
    /// Events (switches or impacts).
    pub events: usize,
    /// Their times.
    pub event_times: Vec<f64>,
    /// Entering contact (or an impact).
    pub event_kinds: Vec<bool>,
    /// Sticking phases [start, end] (the chatter case; end None: still stuck at the end).
    pub sticking: Vec<Vec<Option<f64>>>,
    /// How far its strobe moves when η̇₁(0) moves by 1e-16: the problem's conditioning.
    #[serde(rename = "strobe_change_for_1e-16_in_initial_velocity")]
    pub sensitivity: f64,
}

/// This project's run, as the command line gave it.
#[derive(Debug, Clone, Deserialize)]
pub struct Ours {
    /// The command (values).
    pub command: String,
    /// The state at the end of each period, k = 1 … P.
    pub strobe: Vec<Vec<f64>>,
    /// The final state.
    pub final_state: Vec<f64>,
    /// Event times.
    pub event_times: Vec<f64>,
    /// Event kinds.
    pub event_kinds: Vec<bool>,
    /// CPU time of the library's run (set-up apart), each repeat: the best of its solves (s).
    pub cpu_seconds: Vec<f64>,
    /// The best of them.
    pub cpu_seconds_best: f64,
    /// Solves in each repeat.
    pub solves_per_repeat: Vec<usize>,
    /// CPU time of building the model and its flows, not counted in the run's (s).
    pub setup_cpu_seconds: f64,
    /// The command timed (`examples/peer_problem.rs`).
    pub timed_command: String,
    /// The timed run's final state (the command line's, checked when written).
    pub timed_final_state: Vec<f64>,
    /// Strobe error against the reference.
    pub strobe_error_vs_reference: Option<f64>,
    /// Event-time error against the reference (None: the sequences differ in number).
    pub event_time_error_vs_reference: Option<f64>,
}

/// One peer run (a rung of a ladder), or a recorded reason it was not run.
#[derive(Debug, Clone, Deserialize)]
pub struct Row {
    /// scipy, siconos, CVODE, or cantilever ([`OWN`]: this project's Dormand–Prince).
    pub tool: String,
    /// The integrator.
    pub method: String,
    /// `rtol` or `steps per period`.
    pub setting_name: String,
    /// Its value (None: not applicable).
    pub setting: Option<f64>,
    /// How the run ended.
    pub outcome: String,
    /// CPU seconds of each repeat (a compiled tool: the best of its solves in it).
    pub cpu_seconds: Option<Vec<f64>>,
    /// The best of them.
    pub cpu_seconds_best: Option<f64>,
    /// A compiled tool: its solves in each repeat.
    pub solves_per_repeat: Option<Vec<usize>>,
    /// A compiled tool: the CPU time of its set-up, not counted in the run's (s).
    pub setup_cpu_seconds: Option<f64>,
    /// A rung not run: its time extrapolated from the two before.
    pub extrapolated_cpu_seconds: Option<f64>,
    /// The state at the end of each period reached.
    pub strobe: Option<Vec<Vec<f64>>>,
    /// The final state.
    pub final_state: Option<Vec<f64>>,
    /// Events found.
    pub events: Option<usize>,
    /// Their times.
    pub event_times: Option<Vec<f64>>,
    /// Their kinds.
    pub event_kinds: Option<Vec<bool>>,
    /// The same number and kinds of events as this project's.
    pub same_events_as_ours: Option<bool>,
    /// Strobe error against this project's values.
    pub strobe_error_vs_ours: Option<f64>,
    /// Strobe error against the reference.
    pub strobe_error_vs_reference: Option<f64>,
    /// Event-time error against this project's values.
    pub event_time_error_vs_ours: Option<f64>,
    /// Event-time error against the reference.
    pub event_time_error_vs_reference: Option<f64>,
}

impl Row {
    /// A run that ended normally and found every event this project found.
    pub fn clean(&self) -> bool {
        self.outcome == "completed" && self.same_events_as_ours == Some(true)
    }
}

/// One simulation problem's file.
#[derive(Debug, Clone, Deserialize)]
pub struct Simulation {
    /// [`FORMAT`].
    pub format: String,
    /// When (UTC).
    pub date: String,
    /// The command that wrote it.
    pub command: String,
    /// Where.
    pub machine: Machine,
    /// Python, numpy, scipy, mpmath, Siconos, rustc, this project and its commit.
    pub versions: BTreeMap<String, Option<String>>,
    /// The problem.
    pub problem: ProblemSpec,
    /// The model's matrices as the library gave them ([`matrices`]).
    pub matrices: Value,
    /// Timing and error definitions.
    pub protocol: Protocol,
    /// The independent reference.
    pub reference: Reference,
    /// This project.
    pub ours: Ours,
    /// The peers.
    pub rows: Vec<Row>,
    /// [`checksum`].
    pub checksum: String,
}

/// One orbit case: a start state and this project's orbit from it.
#[derive(Debug, Clone, Deserialize)]
pub struct OrbitCase {
    /// N.
    pub modes: usize,
    /// Transient periods from rest before the start.
    pub start_periods: u64,
    /// The start.
    pub start_state: Vec<f64>,
    /// The command.
    pub command: String,
    /// ‖P(x) − x‖∞/‖x‖∞ of this project's orbit x under the mpmath period map.
    pub reference_residual_of_ours: f64,
}

/// The orbit problem (Figure 4's parameters).
#[derive(Debug, Clone, Deserialize)]
pub struct OrbitProblem {
    /// Its name.
    pub title: String,
    /// k/k₁.
    pub stop_stiffness_over_k1: f64,
    /// ζ₁.
    pub zeta1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_beta1_squared: f64,
    /// d₀.
    pub gap: f64,
    /// The cases.
    pub cases: Vec<OrbitCase>,
}

/// This project's orbit.
#[derive(Debug, Clone, Deserialize)]
pub struct OurOrbit {
    /// N.
    pub modes: usize,
    /// The case's start.
    pub start_periods: u64,
    /// The orbit's state.
    pub state: Vec<f64>,
    /// Floquet multipliers [re, im], largest first.
    pub multipliers: Vec<[f64; 2]>,
    /// Newton steps.
    pub iterations: usize,
    /// CPU time of the library's shooting (set-up apart), each repeat: the best of its
    /// solves (s).
    pub cpu_seconds: Vec<f64>,
    /// The best of them.
    pub cpu_seconds_best: f64,
    /// Solves in each repeat.
    pub solves_per_repeat: Vec<usize>,
}

/// A peer's orbit.
#[derive(Debug, Clone, Deserialize)]
pub struct OrbitRow {
    /// N.
    pub modes: usize,
    /// The case's start.
    pub start_periods: u64,
    /// scipy.
    pub tool: String,
    /// The integrator and the monodromy.
    pub method: String,
    /// rtol.
    pub setting: f64,
    /// How it ended.
    pub outcome: String,
    /// CPU seconds of each repeat.
    pub cpu_seconds: Option<Vec<f64>>,
    /// The best of them.
    pub cpu_seconds_best: Option<f64>,
    /// The orbit's state.
    pub state: Option<Vec<f64>>,
    /// Its multipliers.
    pub multipliers: Option<Vec<[f64; 2]>>,
    /// Newton steps.
    pub newton_steps: Option<usize>,
    /// Periods integrated in all.
    pub periods_integrated: Option<u64>,
    /// Relative state error against this project's orbit.
    pub state_error_vs_ours: Option<f64>,
    /// Largest multiplier distance from this project's.
    pub multiplier_error_vs_ours: Option<f64>,
}

/// The orbits' file.
#[derive(Debug, Clone, Deserialize)]
pub struct Orbits {
    /// [`FORMAT`].
    pub format: String,
    /// When (UTC).
    pub date: String,
    /// Where.
    pub machine: Machine,
    /// Versions.
    pub versions: BTreeMap<String, Option<String>>,
    /// The problem.
    pub problem: OrbitProblem,
    /// Timing and error definitions.
    pub protocol: Protocol,
    /// This project's orbits, one per case.
    pub ours: Vec<OurOrbit>,
    /// The peers.
    pub rows: Vec<OrbitRow>,
    /// [`checksum`].
    pub checksum: String,
}

fn parse<T: serde::de::DeserializeOwned>(name: &str, text: &str) -> Result<T, String> {
    let doc: Value = serde_json::from_str(text).map_err(|e| format!("{name}: not JSON: {e}"))?;
    if doc["format"] != FORMAT {
        return Err(format!("{name}: format is {}, not {FORMAT}", doc["format"]));
    }
    let stored = doc["checksum"].as_str().unwrap_or("(none)").to_string();
    let computed = checksum(&doc);
    if stored != computed {
        return Err(format!(
            "{name}: checksum {stored} stored, {computed} computed: the file was edited by hand \
             (rerun `python3 peers/run.py --only {name}`)"
        ));
    }
    serde_json::from_value(doc).map_err(|e| format!("{name}: {e}"))
}

/// Parses a simulation problem's file and checks its format and checksum.
///
/// # Errors
/// A message naming `name` when the text is not JSON, its format is not this one, its
/// checksum does not match, or its fields do not read as a [`Simulation`].
pub fn parse_simulation(name: &str, text: &str) -> Result<Simulation, String> {
    parse(name, text)
}

/// Parses the orbits' file and checks its format and checksum.
///
/// # Errors
/// A message when the text is not JSON, its format is not this one, its checksum does not
/// match, or its fields do not read as [`Orbits`].
pub fn parse_orbits(text: &str) -> Result<Orbits, String> {
    parse("orbits", text)
}

/// The committed simulation files (by name) and the orbits' file.
///
/// # Errors
/// The message of [`parse_simulation`] or [`parse_orbits`] for a committed file that does not
/// check.
pub fn committed() -> Result<(Vec<(String, Simulation)>, Orbits), String> {
    let mut sims = Vec::new();
    for (name, text) in &FILES[..5] {
        sims.push((name.to_string(), parse_simulation(name, text)?));
    }
    Ok((sims, parse_orbits(FILES[5].1)?))
}

/// One committed simulation problem's file, by name, parsed and checked.
///
/// # Errors
/// A message for a name that is not a committed problem, or the errors of
/// [`parse_simulation`].
pub fn committed_problem(name: &str) -> Result<Simulation, String> {
    let (_, text) = FILES[..5]
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| format!("{name}: no such committed peer problem"))?;
    parse_simulation(name, text)
}

/// max_k ‖x_k − r_k‖∞ / max_k ‖r_k‖∞ (`peers/run.py`'s strobe error); None when `x` has
/// fewer states than `r`.
pub fn strobe_error(x: &[Vec<f64>], r: &[Vec<f64>]) -> Option<f64> {
    if x.len() < r.len() {
        return None;
    }
    let amax = |v: &[f64]| v.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let scale = r.iter().fold(0.0_f64, |m, s| m.max(amax(s)));
    let worst = x.iter().zip(r).fold(0.0_f64, |m, (a, b)| {
        a.iter().zip(b).fold(m, |m, (p, q)| m.max((p - q).abs()))
    });
    Some(worst / scale)
}

/// The smallest of some times (NaN for none): the best of the repeats.
pub fn best(xs: &[f64]) -> f64 {
    xs.iter().copied().reduce(f64::min).unwrap_or(f64::NAN)
}

/// The largest distance from a multiplier of `reference` to its match in `mu`, matched
/// greedily in the reference's order (`peers/orbits.py`).
pub fn multiplier_error(mu: &[[f64; 2]], reference: &[[f64; 2]]) -> f64 {
    let mut left: Vec<[f64; 2]> = mu.to_vec();
    let mut worst = 0.0_f64;
    for z in reference {
        let distance = |w: &[f64; 2]| (w[0] - z[0]).hypot(w[1] - z[1]);
        let Some(i) =
            (0..left.len()).min_by(|&a, &b| distance(&left[a]).total_cmp(&distance(&left[b])))
        else {
            return f64::INFINITY;
        };
        worst = worst.max(distance(&left[i]));
        left.remove(i);
    }
    worst
}

fn forced(p: &ProblemSpec) -> Forced {
    Forced {
        modes: p.modes,
        k_over_k1: p.stop_stiffness_over_k1.unwrap_or(100.0),
        zeta1: p.zeta1,
        omega_over_w1: p.omega_over_beta1_squared,
        gap: p.gap,
        printed_eq37_amplitude: false,
    }
}

/// The model matrices of a forced problem as the peer scripts read them
/// (`examples/peer_problem.rs` prints them): K^±, C, the modal forcing, φ(1), the contact
/// preload, T, and the restitution laws \[R\]_IR and \[R\]_N with coefficient `r`.
///
/// # Errors
/// [`Error::Parameter`] for a case the model refuses or r outside [0, 1]; [`Error::Flow`]
/// when a region's flow cannot be built.
pub fn matrices(case: &Forced, r: f64) -> Result<Value, Error> {
    let model = case.model()?;
    let n = model.modes();
    let sim = Simulator::new(model.clone())?;
    let matrix = |m: &DMatrix<f64>| -> Vec<Vec<f64>> {
        m.row_iter().map(|r| r.iter().copied().collect()).collect()
    };
    let vector = |v: &DVector<f64>| -> Vec<f64> { v.iter().copied().collect() };
    Ok(json!({
        "source": "examples/peer_problem.rs: problems::Forced::model(), the model `cantilever simulate` builds from the same flags",
        "modes": n,
        "stop_stiffness_over_k1": case.k_over_k1,
        "zeta1": case.zeta1,
        "omega_over_beta1_squared": case.omega_over_w1,
        "gap": case.gap,
        "beta1_squared": first_frequency(),
        "k1": first_modal_stiffness(),
        "stop_stiffness": model.params().stop_stiffness,
        "material_damping_gamma": model.params().material_damping,
        "omega": model.omega(),
        "period": sim.period(),
        "modal_stiffness": vector(model.modal_stiffness()),
        "tip": vector(model.tip()),
        "damping": vector(model.damping()),
        "forcing_amplitude": vector(model.forcing_amplitude()),
        "K_minus": matrix(&model.stiffness(Region::Free)),
        "K_plus": matrix(&model.stiffness(Region::Contact)),
        "contact_preload": vector(&model.stop_preload(Region::Contact)),
        "free_tip_amplitude": model.free_tip_amplitude().0,
        "restitution": r,
        "law_impulse_response": matrix(&restitution::impulse_response(n, r)?),
        "law_stiffness_limit": matrix(&restitution::stiffness_limit(n, r)?),
    }))
}

/// The matrices of a committed problem, as the library gives them now.
///
/// # Errors
/// As [`matrices`].
pub fn problem_matrices(p: &ProblemSpec) -> Result<Value, Error> {
    matrices(&forced(p), p.restitution.unwrap_or(0.8))
}

/// This project's run of a committed problem, recomputed by the library now: the state at
/// the end of each period (k = 1 … P) — the command line's run, through the same models.
///
/// # Errors
/// [`Error::Parameter`] for a problem out of range, a bad initial state or r outside [0, 1];
/// [`Error::Flow`] when a flow cannot be built; a run's [`Error::Chatter`] or
/// [`Error::Invariant`].
pub fn recompute(p: &ProblemSpec) -> Result<Vec<Vec<f64>>, Error> {
    let sim = Simulator::new(forced(p).model()?)?;
    let x0 = DVector::from_column_slice(&p.initial_state);
    let run = if p.model == "rigid" {
        let law = restitution::impulse_response(p.modes, p.restitution.unwrap_or(0.8))?;
        RigidImpact::new(sim, law)?.advance(&x0, 0, p.periods, true)?
    } else {
        sim.advance(&x0, 0, p.periods, true)?
    };
    Ok(run
        .strobe
        .iter()
        .skip(1)
        .map(|x| x.iter().copied().collect())
        .collect())
}

/// This project's orbit of a committed case, recomputed by the library now (`cantilever
/// orbit … --periods 0 --period 1` from the case's start).
///
/// # Errors
/// [`Error::Parameter`] for a case out of range or a bad start; [`Error::Flow`] when a flow
/// cannot be built; the errors of [`shooting::shoot`] ([`Error::NotConverged`], ...).
pub fn recompute_orbit(problem: &OrbitProblem, case: &OrbitCase) -> Result<PeriodicOrbit, Error> {
    let f = Forced {
        modes: case.modes,
        k_over_k1: problem.stop_stiffness_over_k1,
        zeta1: problem.zeta1,
        omega_over_w1: problem.omega_over_beta1_squared,
        gap: problem.gap,
        printed_eq37_amplitude: false,
    };
    let sim = Simulator::new(f.model()?)?;
    shooting::shoot(&sim, &DVector::from_column_slice(&case.start_state), 1)
}
