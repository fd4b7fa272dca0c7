//! Scene `work-precision`: error against run time for the two simulation methods on the
//! Figure 4 model (N = 10, k = 100k₁, ζ₁ = 0.01, d₀ = 0, ω = 2(β₁⁻)², from rest).
//!
//! - the exact piecewise-linear simulator ([`crate::engine::sim`]) at several root
//!   tolerances (its only approximation is where it places each switching time);
//! - the Dormand–Prince 5(4) integrator ([`crate::engine::dopri5`]) at several rtol.
//!
//! Every run, the exact simulator's included, is measured against an independent
//! reference: the same problem (20 periods from rest) solved at 40 digits by mpmath
//! (eigendecomposition of A± in each region, switching times to 40 digits), committed with
//! the side-by-side comparison (`peers/results/fig4-n10.json`, read through
//! [`crate::results::peers`]), so no curve is measured against itself. Wall times are the
//! best of `repeats` runs and are the only machine-dependent numbers of the book.
//!
//! It also counts where the exact simulator's time goes ([`Stats`]) on the two runs of the
//! simulator issue's speed targets: 1000 periods from rest of the Figure 4 model (N = 10)
//! and of the Figure 6(b) model (N = 20, k = 1000k₁).

pub mod render;
pub mod scaling;

use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::engine::dopri5::{self, Tolerances};
use crate::error::{Error, ParameterError};
use crate::model::problems;
use crate::results::peers;
use crate::engine::sim::{Events, Settings, Simulator, Stats};
use nalgebra::DVector;
use serde::Serialize;
use std::time::Instant;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct WorkPrecisionParams {
    /// N, the number of modes.
    pub modes: usize,
    /// Forcing periods simulated from rest.
    pub periods: u64,
    /// Root tolerances of the exact simulator.
    pub root_tolerances: Vec<f64>,
    /// rtol of the reference integrator (atol = rtol·1e-3).
    pub rtols: Vec<f64>,
    /// Timing repeats (best of).
    pub repeats: usize,
    /// Forcing periods of the two cost runs.
    pub cost_periods: u64,
    /// The runs of cost against N and k.
    pub scaling: scaling::ScalingParams,
}

impl WorkPrecisionParams {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            modes: 10,
            periods: 20,
            root_tolerances: vec![1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-15],
            rtols: vec![
                1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13,
            ],
            repeats: 3,
            cost_periods: 1000,
            scaling: scaling::ScalingParams::book(),
        }
    }

    /// A reduced version for the test suite.
    pub fn test() -> Self {
        Self {
            modes: 10,
            periods: 20,
            root_tolerances: vec![1e-2, 1e-6, 1e-15],
            rtols: vec![1e-6, 1e-9, 1e-13],
            repeats: 1,
            cost_periods: 1000,
            scaling: scaling::ScalingParams::test(),
        }
    }
}

/// One run of one method at one setting.
#[derive(Debug, Clone, Serialize)]
pub struct WorkPoint {
    /// "exact" or "DP5" (Dormand–Prince 5(4); the reference of both is the 40-digit solution).
    pub method: String,
    /// The root tolerance or rtol.
    pub tolerance: f64,
    /// Best wall time over the repeats (s).
    pub seconds: f64,
    /// Contact events found.
    pub events: usize,
    /// Whether the event sequence (count and directions) equals the reference's.
    pub same_sequence: bool,
    /// max |t_event − t_event,ref| (∞ when the sequences differ).
    pub event_error: f64,
    /// ‖x(T) − x_ref(T)‖∞ / ‖x_ref(T)‖∞.
    pub state_error: f64,
    /// Switching-function evaluations (exact) or right-hand-side evaluations (DP5).
    pub evaluations: u64,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct WorkPrecisionData {
    /// The parameters used.
    pub params: WorkPrecisionParams,
    /// How the independent reference was computed.
    pub reference: String,
    /// Events of the reference solution.
    pub reference_events: usize,
    /// All runs.
    pub points: Vec<WorkPoint>,
    /// The exact simulator's work on the two cost runs.
    pub costs: Vec<CostRun>,
    /// The most negative eigenvalue of A⁻ (the stiffest over-damped mode).
    pub stiffest_eigenvalue: f64,
    /// The machine the wall times were measured on.
    pub machine: String,
    /// Cost against N and k.
    pub scaling: scaling::Scaling,
}

/// An error as quoted: a bound when it is at round-off (the digits there differ between
/// machines).
fn quoted(error: f64, round_off: f64) -> String {
    if error < round_off {
        format!("below {round_off:.0e}")
    } else {
        format!("{error:.0e}")
    }
}

/// The largest event-time difference of the DP5 run at its tightest rtol from the
/// reference, as quoted.
fn dp5_agreement(d: &WorkPrecisionData) -> Option<String> {
    let best = d.points.iter().rfind(|p| p.method != "exact")?;
    Some(quoted(best.event_error, 1e-11))
}

/// The errors of the exact method at its tightest root tolerance against the independent
/// reference, as quoted: (event times, end state).
fn exact_agreement(d: &WorkPrecisionData) -> Option<(String, String)> {
    let best = d.points.iter().rfind(|p| p.method == "exact")?;
    Some((quoted(best.event_error, 1e-12), quoted(best.state_error, 1e-12)))
}

/// The final state, the switches (time, entering) and how the reference was computed.
type Reference = (DVector<f64>, Vec<(f64, bool)>, String);

/// The independent reference of the scene's problem: the final state and the switches
/// (time, entering) of the committed 40-digit solution, and how it was computed. Only the
/// problem that was solved at 40 digits has one (N = 10, the Figure 4 parameters, from
/// rest, 20 periods).
fn independent_reference(p: &WorkPrecisionParams) -> Result<Reference, Error> {
    let f = peers::committed_problem("fig4-n10").map_err(Error::Unsupported)?;
    let spec = &f.problem;
    let case = problems::figure4(p.modes);
    let same = spec.model == "compliant"
        && spec.modes == p.modes
        && spec.periods == p.periods
        && spec.stop_stiffness_over_k1 == Some(case.k_over_k1)
        && spec.zeta1 == case.zeta1
        && spec.omega_over_beta1_squared == case.omega_over_w1
        && spec.gap == case.gap
        && spec.initial_state.iter().all(|&v| v == 0.0);
    if !same {
        return Err(ParameterError::new(
            "modes and periods",
            format!("N = {}, {} periods", p.modes, p.periods),
            &format!(
                "the problem of the independent reference (N = {}, {} periods from rest)",
                spec.modes, spec.periods
            ),
        )
        .into());
    }
    let end = f.reference.strobe.last().cloned().unwrap_or_default();
    let events = f
        .reference
        .event_times
        .iter()
        .copied()
        .zip(f.reference.event_kinds.iter().copied())
        .collect();
    let how = format!("{} ({} digits)", f.reference.method, f.reference.digits);
    Ok((DVector::from_vec(end), events, how))
}

/// The CPU model and the number of cores, for the record of wall times.
pub fn machine() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "an unidentified CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{model}, {cores} cores, {} {}", std::env::consts::OS, std::env::consts::ARCH)
}

/// The exact simulator's work counters on one run from rest.
#[derive(Debug, Clone, Serialize)]
pub struct CostRun {
    /// Which model.
    pub label: String,
    /// N, the number of modes.
    pub modes: usize,
    /// k/k₁.
    pub stop_stiffness_over_k1: f64,
    /// Forcing periods.
    pub periods: u64,
    /// Switching events.
    pub events: usize,
    /// The counters.
    pub stats: Stats,
    /// Best wall time over the repeats (s).
    pub seconds: f64,
}

/// The result of the first of `repeats` runs (≥ 1) and the best wall time.
fn best_of<T>(repeats: usize, mut f: impl FnMut() -> T) -> (T, f64) {
    let t = Instant::now();
    let out = f();
    let mut best = t.elapsed().as_secs_f64();
    for _ in 1..repeats {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed().as_secs_f64());
    }
    (out, best)
}

/// Runs the scene.
///
/// # Errors
/// `Error::Parameter` for no root tolerances or an N and period count other than the
/// committed reference's; `Error::Unsupported` if that reference does not check; a flow that
/// cannot be built or a run the simulator or the Dormand–Prince reference refuses.
pub fn compute(p: &WorkPrecisionParams) -> Result<WorkPrecisionData, Error> {
    if p.root_tolerances.is_empty() {
        return Err(ParameterError::new("root tolerances", "none", "at least one (the last is the reference)").into());
    }
    let model = problems::figure4(p.modes).model()?;
    let x0 = DVector::zeros(2 * p.modes);
    let run_with_events = |sim: &Simulator, x0: &DVector<f64>, periods: u64| {
        let mut events = Events::default();
        let end = sim.run(x0, periods, &mut events);
        end.map(|end| (end, events.events))
    };
    let mut exact_runs = Vec::new();
    for &tol in &p.root_tolerances {
        let sim = Simulator::new(model.clone())?.with_settings(Settings {
            root_tolerance: tol,
        });
        let (run, secs) = best_of(p.repeats, || run_with_events(&sim, &x0, p.periods));
        let (end, events) = run?;
        let times: Vec<(f64, bool)> = events.iter().map(|e| (e.time, e.entering)).collect();
        exact_runs.push((tol, end.state, times, secs, end.stats.evaluations));
    }
    let (x_ref, ev_ref, reference) = independent_reference(p)?;
    let period = Simulator::new(model.clone())?.period();
    let t_end = p.periods as f64 * period;
    let compare = |x: &DVector<f64>, ev: &[(f64, bool)]| {
        let same = ev.len() == ev_ref.len() && ev.iter().zip(&ev_ref).all(|(a, b)| a.1 == b.1);
        let event_error = if same {
            ev.iter()
                .zip(&ev_ref)
                .map(|(a, b)| (a.0 - b.0).abs())
                .fold(0.0, f64::max)
        } else {
            f64::INFINITY
        };
        (same, event_error, (x - &x_ref).amax() / x_ref.amax())
    };
    let mut points = Vec::new();
    for (tol, x, ev, secs, evals) in &exact_runs {
        let (same, ee, se) = compare(x, ev);
        points.push(WorkPoint {
            method: "exact".into(),
            tolerance: *tol,
            seconds: *secs,
            events: ev.len(),
            same_sequence: same,
            event_error: ee,
            state_error: se,
            evaluations: *evals,
        });
    }
    for &rtol in &p.rtols {
        let tol = Tolerances {
            rtol,
            atol: rtol * 1e-3,
        };
        let (r, secs) = best_of(p.repeats, || dopri5::integrate(&model, &x0, t_end, tol));
        let r = r?;
        let ev: Vec<(f64, bool)> = r.events.iter().map(|e| (e.time, e.entering)).collect();
        let (same, ee, se) = compare(&r.state, &ev);
        points.push(WorkPoint {
            method: "DP5".into(),
            tolerance: rtol,
            seconds: secs,
            events: ev.len(),
            same_sequence: same,
            event_error: ee,
            state_error: se,
            evaluations: r.evaluations,
        });
    }
    let mut costs = Vec::new();
    for (label, case) in [
        ("Figure 4", problems::figure4(10)),
        ("Figure 6(b)", problems::figure6b(20)),
    ] {
        let sim = Simulator::new(case.model()?)?;
        let x0 = DVector::zeros(2 * case.modes);
        let (run, seconds) = best_of(p.repeats, || run_with_events(&sim, &x0, p.cost_periods));
        let (end, events) = run?;
        costs.push(CostRun {
            label: label.into(),
            modes: case.modes,
            stop_stiffness_over_k1: case.k_over_k1,
            periods: p.cost_periods,
            events: events.len(),
            stats: end.stats,
            seconds,
        });
    }
    let stiffest_eigenvalue = Simulator::new(model)?
        .flow(crate::model::galerkin::Region::Free)
        .eigenvalues()
        .iter()
        .map(|l| l.re)
        .fold(0.0, f64::min);
    Ok(WorkPrecisionData {
        params: p.clone(),
        reference,
        reference_events: ev_ref.len(),
        points,
        costs,
        stiffest_eigenvalue,
        machine: machine(),
        scaling: scaling::compute(&p.scaling, p.repeats)?,
    })
}

/// The scene.
pub struct WorkPrecision;

impl Scene for WorkPrecision {
    const NAME: &'static str = "work-precision";
    const PAPER: &'static str = "§5.2 (methods)";
    const TITLE: &'static str = "Error against run time";
    const GIST: &'static str = "— (no error estimates given)";
    const GROUP: Group = Group::Methods;
    const SUMMARY: &'static str =
        "error against run time: exact simulator vs DP5 (Dormand–Prince 5(4)), Fig 4 model, N = 10";
    const CLAIM: &'static str = "— (the paper gives no error estimates)";
    const CHAPTER: &'static str = "work-precision.md";
    const TIMED: bool = true;
    const METHOD: &'static str = "the Figure 4 model (N = 10) simulated 20 periods from rest by the exact simulator at several root tolerances and by the independent Dormand–Prince 5(4) integrator at several rtol; every error against an independent 40-digit reference (mpmath, committed with the side-by-side comparison); wall times best of 3 on the machine that built the book";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[("contact switches in 20 periods", "reference_events"), ("evaluations per period, Figure 4", "Figure 4 evaluations per period")];
    type Params = WorkPrecisionParams;
    type Data = WorkPrecisionData;

    fn params(resolution: Resolution) -> WorkPrecisionParams {
        match resolution {
            Resolution::Book => WorkPrecisionParams::book(),
            Resolution::Test => WorkPrecisionParams::test(),
        }
    }

    fn compute(p: &WorkPrecisionParams, _: &dyn Progress) -> Result<WorkPrecisionData, Error> {
        compute(p)
    }

    fn key_numbers(d: &WorkPrecisionData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        // Only machine-independent numbers: event counts and whether each run reproduces the
        // reference event sequence. Errors and timings are in the table and data.json.
        k.integer("periods", d.params.periods as i64);
        k.integer("reference_events", d.reference_events as i64);
        for p in &d.points {
            let key = format!("{} tol={:e}", p.method, p.tolerance);
            k.integer(format!("{key} events"), p.events as i64);
            k.text(format!("{key} same_sequence"), p.same_sequence.to_string());
            if p.method != "exact" {
                // deterministic for a given tolerance: the work, not the time
                k.integer(format!("{key} right-hand sides"), p.evaluations as i64);
            }
        }
        if let Some((events, state)) = exact_agreement(d) {
            k.text(
                "exact at its tightest tolerance against the independent reference, largest event-time difference",
                events,
            );
            k.text(
                "exact at its tightest tolerance against the independent reference, end-state error",
                state,
            );
        }
        if let Some(agreement) = dp5_agreement(d) {
            k.text(
                "DP5 at its tightest tolerance, largest event-time difference",
                agreement,
            );
        }
        k.cited(
            "stiffest eigenvalue of A-",
            d.stiffest_eigenvalue,
            2,
            Uncertainty::round_off(d.stiffest_eigenvalue, 1e-14, "closed form per mode"),
            "",
        );
        // Work counters of the speed-target runs, per period (exact counts); 2 figures, so a
        // last-ulp difference of libm between machines (which can move one step) does not
        // show.
        for c in &d.costs {
            let per_period = |x: u64| x as f64 / c.periods as f64;
            let counted = || Uncertainty::new(0.0, "an exact count over the run");
            k.cited(
                format!("{} evaluations per period", c.label),
                per_period(c.stats.evaluations),
                2,
                counted(),
                "",
            );
            k.cited(
                format!("{} certified steps per period", c.label),
                per_period(c.stats.steps),
                2,
                counted(),
                "",
            );
            k.cited(
                format!("{} segments per period", c.label),
                per_period(c.stats.segments),
                2,
                counted(),
                "",
            );
        }
        scaling_key_numbers(&mut k, &d.scaling);
        k
    }

    fn verdict(d: &WorkPrecisionData) -> Verdict {
        let all_same = d.points.iter().all(|p| p.same_sequence);
        Verdict {
            outcome: Outcome::NoClaim,
            evidence: format!(
                "every run finds the {} switches of the independent 40-digit reference: {}; at their tightest settings the exact simulator agrees with it in event time to {} and the DP5 integrator to {}",
                d.reference_events,
                if all_same { "yes" } else { "no" },
                exact_agreement(d).map_or_else(|| "(no exact run)".into(), |a| a.0),
                dp5_agreement(d).unwrap_or_else(|| "(no DP5 run)".into())
            ),
        }
    }

    fn render(d: &WorkPrecisionData) -> Result<Rendered, crate::results::render::RenderError> {
        Ok(Rendered {
            extra_tables: vec![
                ("costs", render::costs_table(d)),
                ("timing", render::timing_summary(d)),
                ("scaling", render::scaling_table(d)),
            ],
            ..Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?
        })
    }
}

/// The exponents of the work counters per period against N and k: exact counts, so the
/// same on every machine (the times' exponents are in the table). Each is a least-squares
/// slope; its uncertainty is the slope's standard error over the fitted points.
fn scaling_key_numbers(k: &mut KeyNumbers, s: &scaling::Scaling) {
    type Counter = fn(&Stats) -> u64;
    let counters: [(&str, Counter); 2] = [
        ("segments", |s| s.segments),
        ("evaluations", |s| s.evaluations),
    ];
    let modes: Vec<usize> = s.along_modes.iter().map(|q| q.modes).collect();
    for (line, pts, x, from) in [
        ("N", &s.along_modes, (|q| q.modes as f64) as fn(&scaling::ScalingPoint) -> f64, scaling::fit_from(&modes)),
        ("k", &s.along_stiffness, |q| q.k_over_k1, 0),
    ] {
        for (name, count) in counters {
            let xy: Vec<(f64, f64)> = pts.iter().map(|q| (x(q), q.per_period(count(&q.stats)))).collect();
            let key = format!("{name} per period, exponent in {line}");
            match scaling::exponent(&xy, from) {
                Some((slope, error)) if error.is_finite() => k.cited(
                    key,
                    slope,
                    2,
                    Uncertainty::new(error, "standard error of the least-squares slope of exact counts"),
                    "",
                ),
                _ => k.text(key, "too few points"),
            }
        }
    }
}
