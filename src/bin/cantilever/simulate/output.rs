//! `simulate`'s inputs from files and its outputs: the initial state (a modal state, profiles
//! or a seed), the JSON and text reports, dense output and the final state (files written
//! atomically).

use super::run::Report;
use super::{ModelKind, SimulateArgs};
use impacting_cantilever::analysis::orbit::{random_state, SplitMix64};
use impacting_cantilever::engine::rigid::beyond_the_stop;
use impacting_cantilever::error::{Error, ParameterError};
use impacting_cantilever::model::galerkin::{first_frequency, GalerkinModel};
use impacting_cantilever::results::scene::write_atomically;
use nalgebra::DVector;
use serde_json::{json, Value};
use std::path::Path;

fn read_json(flag: &str, path: &Path) -> Result<Value, ParameterError> {
    // a state of 2N ≤ 2·MAX_MODES numbers (or a profile) is far below 16 MiB
    let text = impacting_cantilever::results::files::read_capped(
        flag,
        path,
        16 << 20,
        "a readable JSON file",
    )?;
    serde_json::from_str(&text)
        .map_err(|e| ParameterError::new(flag, path.display(), &format!("valid JSON ({e})")))
}

fn numbers(flag: &str, v: &Value, what: &str) -> Result<Vec<f64>, ParameterError> {
    v.as_array()
        .and_then(|a| {
            a.iter()
                .map(|x| x.as_f64().filter(|f| f.is_finite()))
                .collect()
        })
        .ok_or_else(|| ParameterError::new(flag, what, "an array of finite numbers"))
}

/// The initial state and a description of where it came from.
pub fn initial_state(
    args: &SimulateArgs,
    model: &GalerkinModel,
) -> Result<(DVector<f64>, String), ParameterError> {
    let (x, start) = read_initial_state(args, model)?;
    let size = x.amax();
    let flag = if args.initial_profile.is_some() {
        "--initial-profile"
    } else {
        "--initial-state"
    };
    if size > super::MAX_STATE {
        return Err(ParameterError::new(
            flag,
            format!("a state of size {}", impacting_cantilever::error::number(size)),
            "entries of magnitude at most 1e6 (lengths in units of the free tip amplitude at resonance, as |d₀| ≤ 1e6)",
        ));
    }
    if size > 0.0 && size < super::MIN_SCALE {
        return Err(super::tiny(flag, size));
    }
    Ok((x, start))
}

fn read_initial_state(
    args: &SimulateArgs,
    model: &GalerkinModel,
) -> Result<(DVector<f64>, String), ParameterError> {
    let n = model.modes();
    if let Some(path) = &args.initial_state {
        let v = read_json("--initial-state", path)?;
        let state = v.get("state").unwrap_or(&v);
        // a --final-state file says what it is: N and the forcing phase it ended at
        if let Some(m) = v.get("modes") {
            if m.as_u64() != Some(n as u64) {
                return Err(ParameterError::new(
                    "--initial-state",
                    format!("a state of {m} modes"),
                    &format!("a state of the model's N = {n} modes"),
                ));
            }
        }
        if let Some(phase) = v.get("phase").and_then(|p| p.as_f64()) {
            // a run starts at phase 0 of the forcing: a state from mid-period (a run that
            // stopped early) would be continued with the forcing out of phase
            if phase.abs() > 1e-9 && (1.0 - phase).abs() > 1e-9 {
                return Err(ParameterError::new(
                    "--initial-state",
                    format!("a state at phase {phase:.6} of the forcing period"),
                    "a state at the start of a forcing period (phase 0), where every run starts",
                ));
            }
        }
        let x = numbers("--initial-state", state, "the state")?;
        if x.len() != 2 * n {
            return Err(ParameterError::new(
                "--initial-state",
                format!("{} numbers", x.len()),
                &format!("2N = {} numbers [η; η̇]", 2 * n),
            ));
        }
        return Ok((
            DVector::from_vec(x),
            format!("state from {}", path.display()),
        ));
    }
    if let Some(path) = &args.initial_profile {
        let v = read_json("--initial-profile", path)?;
        let get = |key: &str| {
            v.get(key)
                .ok_or_else(|| ParameterError::new("--initial-profile", key, "keys s, w, w_t"))
                .and_then(|a| numbers("--initial-profile", a, key))
        };
        let (s, w, wt) = (get("s")?, get("w")?, get("w_t")?);
        let sorted = s.windows(2).all(|p| p[1] > p[0]);
        if s.len() < 2
            || !sorted
            || s[0] > 0.0
            || s[s.len() - 1] < 1.0
            || w.len() != s.len()
            || wt.len() != s.len()
        {
            return Err(ParameterError::new(
                "--initial-profile",
                path.display(),
                "s increasing from ≤ 0 to ≥ 1, with w and w_t of the same length",
            ));
        }
        let interpolate = |values: &[f64], x: f64| {
            let i = s.partition_point(|&p| p <= x).clamp(1, s.len() - 1);
            let t = (x - s[i - 1]) / (s[i] - s[i - 1]);
            values[i - 1] + t * (values[i] - values[i - 1])
        };
        let x = model.modal_state(&|x| interpolate(&w, x), &|x| interpolate(&wt, x))?;
        return Ok((x, format!("profiles from {}", path.display())));
    }
    if let Some(seed) = args.seed {
        let (amp, _) = model.free_tip_amplitude();
        let mut rng = SplitMix64::for_point(seed, n as u64, 0, 0);
        let x = random_state(&mut rng, n, 4.0 * amp, model.omega());
        // a rigid stop cannot be penetrated: say which option drew the tip beyond it
        if args.model == ModelKind::Rigid {
            if let Some(beyond) = beyond_the_stop(model, &x) {
                return Err(seed_beyond_the_stop(seed, beyond));
            }
        }
        return Ok((x, format!("random state, seed {seed}")));
    }
    Ok((DVector::zeros(2 * n), "rest".into()))
}

/// The refusal of a seed whose random start puts the tip `beyond` a rigid stop.
fn seed_beyond_the_stop(seed: u64, beyond: f64) -> ParameterError {
    ParameterError::new(
        "--seed",
        seed,
        &format!(
            "a seed whose random start has the tip at or before the rigid stop (this one puts \
             it {} beyond d₀; at d₀ = 0 about half the seeds do): another seed, or a start \
             state of your own",
            impacting_cantilever::error::number(beyond)
        ),
    )
}

/// Fails early (exit 2) when an output file cannot be written, before any work.
pub fn check_writable(args: &SimulateArgs) -> Result<(), ParameterError> {
    for (flag, path) in [
        ("--final-state", &args.final_state),
        ("--dense", &args.dense),
    ] {
        if let Some(path) = path {
            impacting_cantilever::results::files::check_writable(flag, path)?;
        }
    }
    // one file for both outputs: the second would silently replace the first (a character
    // device such as /dev/null can take both)
    if let (Some(a), Some(b)) = (&args.final_state, &args.dense) {
        // a path that does not exist yet: its folder's real path and its name
        let real = |p: &std::path::Path| {
            std::fs::canonicalize(p).ok().or_else(|| {
                let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
                let dir = std::fs::canonicalize(dir.unwrap_or(std::path::Path::new("."))).ok()?;
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

/// The model's units and scales, stated with every result.
fn units(report: &Report) -> Value {
    let m = &report.setup.model;
    let (a_free, v_free) = m.free_tip_amplitude();
    let w1 = first_frequency();
    json!({
        "time": "non-dimensional beam time (EI = ρA = L = 1)",
        "length": "non-dimensional; d₀ and tip displacements in the same unit, the free tip amplitude at resonance being 1 with the corrected eq (37) forcing",
        "beta1_squared": w1,
        "first_natural_frequency_f1": w1 / (2.0 * std::f64::consts::PI),
        "k1": w1 * w1,
        "omega": m.omega(),
        "forcing_period_T": 2.0 * std::f64::consts::PI / m.omega(),
        "free_tip_amplitude_at_omega": a_free,
        "free_tip_velocity_amplitude_at_omega": v_free,
    })
}

/// The JSON report without its events (field meanings in `cantilever simulate --help`
/// and the book); [`to_json_text`] adds them.
pub fn to_json(r: &Report) -> Value {
    let a = &r.args;
    json!({
        "inputs": {
            "modes": a.modes,
            "model": a.model,
            "stop_stiffness_over_k1": a.stop_stiffness,
            "gap": a.gap,
            "zeta1": a.zeta1,
            "damping_reading": a.damping_reading,
            "material_damping_gamma": r.setup.model.params().material_damping,
            "viscous_alpha": a.viscous,
            "omega_over_beta1_squared": a.omega,
            "forcing": a.forcing,
            "law": (a.model == ModelKind::Rigid).then_some(a.law),
            "restitution": (a.model == ModelKind::Rigid).then_some(a.restitution),
            "periods": a.periods,
            "record": a.record,
            "start": r.setup.start,
        },
        "units": units(r),
        "outcome": r.outcome,
        "period_m": r.period_m,
        "periodicity_residual": r.periodicity_residual,
        "periodicity_tolerance": a.periodicity_tolerance,
        "max_period_searched": r.max_period_searched,
        "impacts_n": r.impacts_per_period,
        // the same, under its name before schema version 1 (kept for one release)
        "impacts_per_period": r.impacts_per_period,
        "contacts_in_window": r.contacts_in_window,
        "max_tip": r.max_tip.map(|m| m.value),
        "max_tip_time": r.max_tip.map(|m| m.time),
        "max_tip_tolerance": r.max_tip.map(|m| m.tolerance),
        "energy_imbalance": r.energy_imbalance,
        "energy_imbalance_bound": r.energy_imbalance_bound,
        "energy_imbalance_within_bound": r.energy_imbalance.zip(r.energy_imbalance_bound).map(|(e, b)| e <= b),
        "eigenvector_condition": r.condition,
        "wall_seconds": r.wall_seconds,
        "final_time": r.final_clock.time(),
    })
}

/// Writes the JSON report: [`to_json`]'s `head` with the events last, serialized straight
/// from the events into `out` (a `Value` per event took ~5 kB: 1 GB for 2·10⁵ events).
pub fn write_json(
    r: &Report,
    head: Value,
    out: &mut dyn std::io::Write,
) -> Result<(), serde_json::Error> {
    #[derive(serde::Serialize)]
    struct Doc<'a> {
        #[serde(flatten)]
        head: Value,
        events: &'a [super::run::EventOut],
    }
    serde_json::to_writer_pretty(
        out,
        &Doc {
            head,
            events: &r.events,
        },
    )
}

/// The text report.
pub fn to_text(r: &Report) -> String {
    let mut s = String::new();
    let rigid = r.args.model == ModelKind::Rigid;
    s.push_str(if rigid {
        "impacts in the recorded window (t, phase/T, tip velocity before → after):\n"
    } else {
        "contact events in the recorded window (t, phase/T, direction, tip velocity):\n"
    });
    for e in &r.events {
        match e.outgoing {
            Some(out) => s.push_str(&format!(
                "  t = {:>16.10}  {:.6}  v = {:+.6e} → {:+.6e}\n",
                e.time, e.phase, e.tip_velocity, out
            )),
            None => {
                let dir = match (e.grazing, e.entering) {
                    (true, _) => "graze",
                    (false, true) => "enter",
                    (false, false) => "leave",
                };
                s.push_str(&format!(
                    "  t = {:>16.10}  {:.6}  {dir:<5}  v = {:+.6e}\n",
                    e.time, e.phase, e.tip_velocity
                ));
            }
        }
    }
    if r.outcome != "completed" {
        s.push_str(&format!("run {}\n", r.outcome));
    }
    let what = if rigid { "impacts" } else { "contacts" };
    match (r.period_m, r.periodicity_residual) {
        (Some(m), res) => s.push_str(&format!(
            "orbit: ({m}, {}) — period {m}, {} {what} per period (residual {:.1e})\n",
            r.impacts_per_period.unwrap_or(0),
            r.impacts_per_period.unwrap_or(0),
            res.unwrap_or(0.0)
        )),
        (None, Some(res)) => s.push_str(&format!(
            "orbit: no period m ≤ {} within {} recorded periods (best residual {res:.1e}); {} {what} in the window\n",
            r.max_period_searched, r.args.record, r.contacts_in_window
        )),
        (None, None) => s.push_str(&format!(
            "orbit: not tested ({}); {} {what} in the window\n",
            if r.outcome == "completed" {
                "needs at least 2 recorded periods"
            } else {
                "the run stopped before 2 periods were recorded"
            },
            r.contacts_in_window
        )),
    }
    match r.max_tip {
        Some(m) => s.push_str(&format!(
            "max tip displacement: {:.12e} at t = {:.10} (certified to ±{:.0e})\n",
            m.value, m.time, m.tolerance
        )),
        None if !rigid => s.push_str("max tip displacement: — (no recorded periods)\n"),
        None => {}
    }
    match (r.energy_imbalance, r.energy_imbalance_bound) {
        (Some(e), Some(b)) if e > b => s.push_str(&format!(
            "energy imbalance: {e:.2e} — ABOVE its round-off bound {b:.1e} (κε√segments): \
             the flow or the energy integrals are less accurate than κε at this N and k\n"
        )),
        (Some(e), Some(b)) => s.push_str(&format!(
            "energy imbalance: {e:.2e} (within its round-off bound {b:.1e}, κε√segments)\n"
        )),
        (Some(e), None) => s.push_str(&format!("energy imbalance: {e:.2e}\n")),
        _ => {}
    }
    s.push_str(&format!(
        "eigenvector condition: {:.1e} (flow accurate to ~{:.0e})\n",
        r.condition,
        r.condition * f64::EPSILON
    ));
    let (a_free, _) = r.setup.model.free_tip_amplitude();
    s.push_str(&format!(
        "units: T = {:.10}, (β₁⁻)² = {:.10}, free tip amplitude at ω = {a_free:.6e}\n",
        2.0 * std::f64::consts::PI / r.setup.model.omega(),
        first_frequency()
    ));
    s.push_str(&format!("wall time: {:.4} s\n", r.wall_seconds));
    s
}

/// Writes --dense and --final-state, each atomically.
pub fn write_files(r: &Report) -> Result<(), Error> {
    if let Some(path) = &r.args.dense {
        let n = r.args.modes;
        let mut csv = String::from("t,in_contact,tip,tip_velocity");
        for j in 1..=n {
            csv.push_str(&format!(",eta_{j}"));
        }
        for j in 1..=n {
            csv.push_str(&format!(",eta_dot_{j}"));
        }
        csv.push('\n');
        for (t, contact, d, v, x) in &r.dense {
            csv.push_str(&format!(
                "{t:.17e},{},{d:.17e},{v:.17e}",
                u8::from(*contact)
            ));
            for value in x {
                csv.push_str(&format!(",{value:.17e}"));
            }
            csv.push('\n');
        }
        write_atomically(path, &csv)?;
    }
    if let Some(path) = &r.args.final_state {
        let doc = json!({
            "modes": r.args.modes,
            "schema_version": impacting_cantilever::results::scene::SCHEMA_VERSION,
            "time": r.final_clock.time(),
            "cycle": r.final_clock.cycles,
            "phase": r.final_clock.offset / r.final_clock.period,
            "state": r.final_state.iter().collect::<Vec<_>>(),
            "inputs": to_json(r)["inputs"],
        });
        write_atomically(
            path,
            &serde_json::to_string_pretty(&doc).unwrap_or_default(),
        )?;
    }
    Ok(())
}
