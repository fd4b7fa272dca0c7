//! The model matrices of one forced problem as JSON, for the peer scripts of `peers/`
//! (scipy, Siconos): they integrate exactly the equations this library solves, with the
//! numbers taken from here rather than derived again. The flags are those of
//! `cantilever simulate` (ω in units of (β₁⁻)², k in units of k₁, d₀ in units of the free
//! tip amplitude at resonance, material damping from ζ₁, eq (37) forcing corrected).
//!
//! ```text
//! η̈ + C η̇ + K^± η = f cos ωt + F^±,   K⁺ = K⁻ + (k/4)φ(1)φ(1)ᵀ,   tip = φ(1)ᵀη
//! ```
//!
//! `cargo run --release --example peer_problem -- --modes 10 --stop-stiffness 100 --zeta1 0.01 --omega 2 --gap 0 --restitution 0.8`
//!
//! With a first argument, the same flags name a problem whose run this project's side of
//! the comparison times (`peers/run.py`), each printed as one JSON object:
//!
//! - `time --periods P [--model rigid] [--initial-state X.json] --repeats R`: the library's
//!   run over P periods from t = 0 (`PeriodMap::advance`, the call `cantilever simulate`
//!   makes; the rigid model with the impulse-response law), the model and its flows built
//!   once beforehand;
//! - `dopri5 --periods P --rtol RTOL --repeats R`: the library's Dormand–Prince 5(4) with
//!   event location (`engine::dopri5`, atol = 1e-3 rtol; the compliant model), restarted at
//!   each period end to record the state there; with the states and the switches;
//! - `orbit --initial-state X.json --repeats R`: Newton shooting for the period-1 orbit
//!   from X (`analysis::shooting::shoot`, as `cantilever orbit --periods 0 --period 1`).
//!
//! Each is timed by the process's CPU clock (`clock_gettime(CLOCK_PROCESS_CPUTIME_ID)`)
//! around the computation alone, repeated R times in this process (stopping early once the
//! repeats used 1 s of CPU); the set-up's own CPU time is reported apart. Run it with
//! `RAYON_NUM_THREADS=1` (one thread, as the peers).

use impacting_cantilever::engine::dopri5::{self, Tolerances};
use impacting_cantilever::prelude::*;
use impacting_cantilever::results::peers;
use serde_json::json;

fn flag(args: &[String], name: &str, default: Option<f64>) -> Result<f64, Error> {
    let value = args
        .iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(|v| v.parse::<f64>());
    match (value, default) {
        (Some(Ok(v)), _) => Ok(v),
        (None, Some(d)) => Ok(d),
        _ => Err(ParameterError::new(name, "missing or not a number", "a number").into()),
    }
}

/// The process's CPU time (s): `clock_gettime(CLOCK_PROCESS_CPUTIME_ID)` of the C library
/// that `std` links on Linux (no crate needed for one call).
fn cpu_seconds() -> f64 {
    #[repr(C)]
    struct Timespec {
        tv_sec: i64,
        tv_nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, tp: *mut Timespec) -> i32;
    }
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut ts = Timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec (two 64-bit fields on x86-64 and aarch64
    // Linux) and the clock id is Linux's CLOCK_PROCESS_CPUTIME_ID.
    let rc = unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID)");
    ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64
}

/// `f` timed up to `repeats` times (stopping once they used 1 s of CPU): its last result
/// and the CPU seconds of each run.
fn timed<T>(
    repeats: usize,
    mut f: impl FnMut() -> Result<T, Error>,
) -> Result<(T, Vec<f64>), Error> {
    let mut seconds = Vec::new();
    loop {
        let t0 = cpu_seconds();
        let out = f()?;
        seconds.push(cpu_seconds() - t0);
        if seconds.len() >= repeats.max(1) || seconds.iter().sum::<f64>() > 1.0 {
            return Ok((out, seconds));
        }
    }
}

fn text(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .cloned()
}

fn initial_state(args: &[String], n: usize) -> Result<DVector<f64>, Error> {
    let Some(path) = text(args, "--initial-state") else {
        return Ok(DVector::zeros(2 * n));
    };
    let bad =
        |why: String| ParameterError::new("--initial-state", why, "a JSON list of 2N numbers");
    let doc = std::fs::read_to_string(&path).map_err(|e| bad(format!("{path}: {e}")))?;
    let x: Vec<f64> = serde_json::from_str(&doc).map_err(|e| bad(format!("{path}: {e}")))?;
    if x.len() != 2 * n {
        return Err(bad(format!("{} numbers for N = {n}", x.len())).into());
    }
    Ok(DVector::from_vec(x))
}

fn vector(x: &DVector<f64>) -> Vec<f64> {
    x.iter().copied().collect()
}

/// The timed runs of this project's side (see the module's documentation).
fn timing(mode: &str, args: &[String], case: &Forced) -> Result<serde_json::Value, Error> {
    let repeats = flag(args, "--repeats", Some(10.0))? as usize;
    let periods = flag(args, "--periods", Some(1.0))? as u64;
    let setup_start = cpu_seconds();
    let model = case.model()?;
    let x0 = initial_state(args, case.modes)?;
    let sim = Simulator::new(model.clone())?;
    Ok(match mode {
        "time" if text(args, "--model").as_deref() == Some("rigid") => {
            let law =
                restitution::impulse_response(case.modes, flag(args, "--restitution", Some(0.8))?)?;
            let rigid = RigidImpact::new(sim, law)?;
            let setup = cpu_seconds() - setup_start;
            let (run, seconds) = timed(repeats, || rigid.advance(&x0, 0, periods, false))?;
            json!({"cpu_seconds": seconds, "setup_cpu_seconds": setup, "state": vector(&run.state)})
        }
        "time" => {
            let setup = cpu_seconds() - setup_start;
            let (run, seconds) = timed(repeats, || sim.advance(&x0, 0, periods, false))?;
            json!({"cpu_seconds": seconds, "setup_cpu_seconds": setup, "state": vector(&run.state)})
        }
        "dopri5" => {
            let rtol = flag(args, "--rtol", None)?;
            let tol = Tolerances {
                rtol,
                atol: 1e-3 * rtol,
            };
            let period = sim.period();
            let setup = cpu_seconds() - setup_start;
            let ((strobe, events, evaluations), seconds) = timed(repeats, || {
                let (mut x, mut strobe, mut events, mut evaluations) =
                    (x0.clone(), Vec::new(), Vec::new(), 0);
                for k in 0..periods {
                    let run = dopri5::integrate(&model, &x, period, tol)?;
                    let t0 = k as f64 * period;
                    events.extend(run.events.iter().map(|e| (t0 + e.time, e.entering)));
                    evaluations += run.evaluations;
                    x = run.state;
                    strobe.push(vector(&x));
                }
                Ok((strobe, events, evaluations))
            })?;
            json!({"cpu_seconds": seconds, "setup_cpu_seconds": setup, "strobe": strobe,
                   "state": strobe.last(), "events": events, "rhs_evaluations": evaluations,
                   "outcome": "completed"})
        }
        "orbit" => {
            let setup = cpu_seconds() - setup_start;
            let (orbit, seconds) = timed(repeats, || shoot(&sim, &x0, 1))?;
            json!({"cpu_seconds": seconds, "setup_cpu_seconds": setup, "state": orbit.state,
                   "iterations": orbit.iterations})
        }
        _ => {
            return Err(
                ParameterError::new("mode", mode.to_string(), "time, dopri5 or orbit").into(),
            )
        }
    })
}

pub fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().collect();
    let case = Forced {
        modes: flag(&args, "--modes", None)? as usize,
        k_over_k1: flag(&args, "--stop-stiffness", Some(100.0))?,
        zeta1: flag(&args, "--zeta1", None)?,
        omega_over_w1: flag(&args, "--omega", None)?,
        gap: flag(&args, "--gap", Some(0.0))?,
        printed_eq37_amplitude: false,
    };
    if let Some(mode) = args.get(1).filter(|a| !a.starts_with("--")) {
        println!("{}", timing(mode, &args, &case)?);
        return Ok(());
    }
    let json = peers::matrices(&case, flag(&args, "--restitution", Some(0.8))?)?;
    println!(
        "{}",
        serde_json::to_string_pretty(&json).expect("plain numbers")
    );
    Ok(())
}
