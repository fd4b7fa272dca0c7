//! Scene `side-by-side`: error against run time for this project and the tools a researcher
//! would use instead — SUNDIALS CVODE with root finding (BDF and Adams, a compiled C
//! right-hand side), scipy's `solve_ivp` with events (DOP853, Radau with the exact
//! Jacobian, LSODA; a Python right-hand side), Siconos 4.4's event-driven (LSODAR) and
//! Moreau–Jean integrators, and Newton shooting with a finite-difference monodromy — on
//! five shared problems and the Figure 4 orbit with its multipliers; this project's own
//! Dormand–Prince 5(4) with event location beside them on the compliant problems.
//!
//! The peers run outside this library (`peers/run.py`, Python); their committed results
//! ([`crate::results::peers`]) are read here, checked (format, checksum) and drawn. Every
//! error is measured against an independent 40-digit reference (mpmath), this project's
//! included. The scene recomputes this project's values for the committed problems through
//! the library and reports how far the committed ones lie from them, so a stale file shows.
//! Timings are the committed ones (machine-dependent), every tool's the best CPU time of its
//! solve alone, set-up apart, one thread; their ratios are key numbers with the spread
//! of the repeats as their uncertainty.

mod keys;
pub mod render;

use crate::base::report::KeyNumbers;
use crate::error::Error;
use crate::results::peers::{self, Orbits, Simulation, OWN};
use crate::results::scene::{Group, Outcome, Progress, Rendered, Resolution, Scene, Verdict};
use serde::Serialize;

/// What the scene recomputes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct SideBySideParams {
    /// Problems whose values the library recomputes and compares with the committed ones.
    pub recompute: Vec<String>,
    /// Orbit cases (N) whose orbit the library recomputes.
    pub recompute_orbits: Vec<usize>,
}

impl SideBySideParams {
    /// Every problem and every orbit case, at the book's resolution and the tests' alike
    /// (recomputing all of them takes milliseconds).
    pub fn book() -> Self {
        Self {
            recompute: ["oscillator", "chatter", "rigid-n2", "fig4-n3", "fig4-n10"]
                .map(String::from)
                .to_vec(),
            recompute_orbits: vec![3, 10],
        }
    }
}

/// One peer run, as drawn and tabulated.
#[derive(Debug, Clone, Serialize)]
pub struct Point {
    /// The rtol or the steps per period.
    pub setting: Option<f64>,
    /// Best CPU seconds of the solve (None: not run).
    pub seconds: Option<f64>,
    /// The fastest and the slowest of its repeats (s).
    pub seconds_range: Option<(f64, f64)>,
    /// Strobe error against the reference (None: the run did not reach the end).
    pub error: Option<f64>,
    /// Ended normally with every event this project found.
    pub clean: bool,
    /// Events found.
    pub events: Option<usize>,
    /// How it ended.
    pub outcome: String,
}

/// One peer integrator's ladder on one problem.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// CVODE, scipy, siconos, or [`OWN`] (this project's Dormand–Prince).
    pub tool: String,
    /// The integrator.
    pub method: String,
    /// rtol or steps per period.
    pub setting_name: String,
    /// Its runs, loosest first.
    pub points: Vec<Point>,
}

/// One simulation problem.
#[derive(Debug, Clone, Serialize)]
pub struct ProblemData {
    /// The file's name.
    pub name: String,
    /// Its title.
    pub title: String,
    /// N.
    pub modes: usize,
    /// Forcing periods from the start.
    pub periods: u64,
    /// rigid or compliant.
    pub model: String,
    /// This project's best CPU time of the run (set-up apart, s).
    pub ours_seconds: f64,
    /// The fastest and the slowest of its repeats (s).
    pub ours_seconds_range: (f64, f64),
    /// The CPU time of its set-up (the model and its flows), not counted (s).
    pub ours_setup_seconds: f64,
    /// This project's strobe error against the reference.
    pub ours_error: f64,
    /// This project's events.
    pub ours_events: usize,
    /// The reference's events.
    pub reference_events: usize,
    /// The reference's strobe change for 1e-16 in η̇₁(0).
    pub sensitivity: f64,
    /// How the reference was computed.
    pub reference: String,
    /// When the reference's first sticking phase begins (the chatter case).
    pub first_sticking: Option<f64>,
    /// The peers.
    pub series: Vec<Series>,
    /// The largest relative difference between the committed strobe of this project and the
    /// library's now (None: not recomputed at this resolution).
    pub recomputed_difference: Option<f64>,
}

/// A peer's orbit.
#[derive(Debug, Clone, Serialize)]
pub struct OrbitPoint {
    /// The integrator.
    pub method: String,
    /// rtol.
    pub rtol: f64,
    /// Best CPU seconds (None: not run).
    pub seconds: Option<f64>,
    /// The fastest and the slowest of its repeats (s).
    pub seconds_range: Option<(f64, f64)>,
    /// Newton steps.
    pub newton_steps: Option<usize>,
    /// Periods integrated.
    pub periods: Option<u64>,
    /// Relative state error against this project's orbit.
    pub state_error: Option<f64>,
    /// Largest multiplier distance from this project's.
    pub multiplier_error: Option<f64>,
    /// How it ended.
    pub outcome: String,
}

/// One orbit case.
#[derive(Debug, Clone, Serialize)]
pub struct OrbitData {
    /// N.
    pub modes: usize,
    /// Periods from rest before the start.
    pub start_periods: u64,
    /// This project's best CPU time of the shooting (set-up apart, s).
    pub ours_seconds: f64,
    /// The fastest and the slowest of its repeats (s).
    pub ours_seconds_range: (f64, f64),
    /// Its Newton steps.
    pub ours_iterations: usize,
    /// The spectral radius of its multipliers.
    pub ours_spectral_radius: f64,
    /// ‖P(x) − x‖/‖x‖ of its orbit under the mpmath map.
    pub reference_residual: f64,
    /// The peers.
    pub peers: Vec<OrbitPoint>,
    /// The largest difference of the committed orbit (state, multipliers) from the
    /// library's now (None: not recomputed).
    pub recomputed_difference: Option<f64>,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct SideBySideData {
    /// The parameters.
    pub params: SideBySideParams,
    /// The simulation problems.
    pub problems: Vec<ProblemData>,
    /// The orbit cases.
    pub orbits: Vec<OrbitData>,
    /// CPU, cores, OS.
    pub machine: String,
    /// The 1-minute load average at the start of each problem's runs, smallest and largest.
    pub load: (f64, f64),
    /// When the peers ran (first and last file).
    pub dates: (String, String),
    /// The versions.
    pub versions: Vec<(String, String)>,
    /// Runs per setting, alternated.
    pub repeats: usize,
    /// Solves of a compiled tool inside each run, at most.
    pub inner_repeats: usize,
    /// The ladder budget (s).
    pub budget_seconds: f64,
    /// What each tool's time includes: (tool, one sentence), the orbits' after the
    /// problems'.
    pub includes: Vec<(String, String)>,
}

fn problem_data(name: &str, f: &Simulation, recompute: bool) -> Result<ProblemData, Error> {
    let mut series: Vec<Series> = Vec::new();
    for r in &f.rows {
        let point = Point {
            setting: r.setting,
            seconds: r.cpu_seconds_best,
            seconds_range: r.cpu_seconds.as_deref().map(range),
            error: r.strobe_error_vs_reference,
            clean: r.clean(),
            events: r.events,
            outcome: r.outcome.clone(),
        };
        match series
            .iter_mut()
            .find(|s| s.tool == r.tool && s.method == r.method)
        {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                tool: r.tool.clone(),
                method: r.method.clone(),
                setting_name: r.setting_name.clone(),
                points: vec![point],
            }),
        }
    }
    let recomputed_difference = if recompute {
        let now = peers::recompute(&f.problem)?;
        peers::strobe_error(&f.ours.strobe, &now)
    } else {
        None
    };
    Ok(ProblemData {
        name: name.to_string(),
        title: f.problem.title.clone(),
        modes: f.problem.modes,
        periods: f.problem.periods,
        model: f.problem.model.clone(),
        ours_seconds: f.ours.cpu_seconds_best,
        ours_seconds_range: range(&f.ours.cpu_seconds),
        ours_setup_seconds: f.ours.setup_cpu_seconds,
        ours_error: f.ours.strobe_error_vs_reference.unwrap_or(f64::NAN),
        ours_events: f.ours.event_times.len(),
        reference_events: f.reference.events,
        sensitivity: f.reference.sensitivity,
        reference: f.reference.method.clone(),
        first_sticking: f.reference.sticking.first().and_then(|s| s.first().copied().flatten()),
        series,
        recomputed_difference,
    })
}

fn orbit_data(o: &Orbits, recompute: &[usize]) -> Result<Vec<OrbitData>, Error> {
    let mut out = Vec::new();
    for (case, ours) in o.problem.cases.iter().zip(&o.ours) {
        let recomputed_difference = if recompute.contains(&case.modes) {
            let now = peers::recompute_orbit(&o.problem, case)?;
            let state = peers::strobe_error(
                std::slice::from_ref(&ours.state),
                std::slice::from_ref(&now.state),
            );
            let mu = peers::multiplier_error(&ours.multipliers, &now.multipliers);
            state.map(|s| s.max(mu))
        } else {
            None
        };
        let peers = o
            .rows
            .iter()
            .filter(|r| r.modes == case.modes && r.start_periods == case.start_periods)
            .map(|r| OrbitPoint {
                method: r.method.clone(),
                rtol: r.setting,
                seconds: r.cpu_seconds_best,
                seconds_range: r.cpu_seconds.as_deref().map(range),
                newton_steps: r.newton_steps,
                periods: r.periods_integrated,
                state_error: r.state_error_vs_ours,
                multiplier_error: r.multiplier_error_vs_ours,
                outcome: r.outcome.clone(),
            })
            .collect();
        out.push(OrbitData {
            modes: case.modes,
            start_periods: case.start_periods,
            ours_seconds: ours.cpu_seconds_best,
            ours_seconds_range: range(&ours.cpu_seconds),
            ours_iterations: ours.iterations,
            ours_spectral_radius: ours.multipliers.first().map_or(0.0, |z| z[0].hypot(z[1])),
            reference_residual: case.reference_residual_of_ours,
            peers,
            recomputed_difference,
        });
    }
    Ok(out)
}

/// Reads the committed peer results and recomputes this project's values.
///
/// # Errors
/// `Error::Unsupported` when a committed peer file does not check; the errors of
/// [`peers::recompute`] and [`peers::recompute_orbit`] for the runs asked to be recomputed.
pub fn compute(p: &SideBySideParams) -> Result<SideBySideData, Error> {
    let (sims, orbits) = peers::committed().map_err(Error::Unsupported)?;
    let mut problems = Vec::new();
    for (name, f) in &sims {
        problems.push(problem_data(name, f, p.recompute.contains(name))?);
    }
    let first = &sims[0].1;
    let loads: Vec<f64> = sims
        .iter()
        .map(|(_, f)| f.machine.load_average_at_start[0])
        .chain(std::iter::once(orbits.machine.load_average_at_start[0]))
        .collect();
    let mut dates: Vec<String> = sims.iter().map(|(_, f)| f.date.clone()).collect();
    dates.push(orbits.date.clone());
    dates.sort();
    // the versions of every file (Siconos only where it ran)
    let mut versions: Vec<(String, String)> = Vec::new();
    for v in sims.iter().map(|(_, f)| &f.versions).chain([&orbits.versions]) {
        for (k, val) in v {
            if let Some(val) = val {
                if !versions.iter().any(|(a, _)| a == k) {
                    versions.push((k.clone(), val.clone()));
                }
            }
        }
    }
    // what each tool's time includes: the longest list of a problem's file (the compliant
    // problems name every tool), then the orbits' tools under their own names
    let mut includes = sims
        .iter()
        .map(|(_, f)| &f.protocol.includes)
        .max_by_key(|l| l.len())
        .cloned()
        .unwrap_or_default();
    includes.extend(
        orbits
            .protocol
            .includes
            .iter()
            .map(|(tool, what)| (format!("{tool}, periodic orbit"), what.clone())),
    );
    Ok(SideBySideData {
        params: p.clone(),
        orbits: orbit_data(&orbits, &p.recompute_orbits)?,
        problems,
        machine: format!(
            "{}, {} cores, {}",
            first.machine.cpu, first.machine.cores, first.machine.os
        ),
        load: (
            loads.iter().cloned().fold(f64::INFINITY, f64::min),
            loads.iter().cloned().fold(0.0, f64::max),
        ),
        dates: (dates[0].clone(), dates[dates.len() - 1].clone()),
        versions,
        repeats: first.protocol.repeats,
        inner_repeats: first.protocol.inner_repeats,
        budget_seconds: first.protocol.budget_seconds,
        includes,
    })
}

/// The fastest and the slowest of some repeats (each already the best CPU time of its
/// solves for a compiled tool).
fn range(samples: &[f64]) -> (f64, f64) {
    let lo = samples.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = samples.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if samples.is_empty() {
        (f64::NAN, f64::NAN)
    } else {
        (lo, hi)
    }
}

/// The fastest clean run (every event found) of any peer — not this project's own
/// Dormand–Prince — with an error at or below `target`: its series and the run.
pub fn fastest(p: &ProblemData, target: f64) -> Option<(&Series, &Point)> {
    fastest_of(p, target, |tool| tool != OWN)
}

/// [`fastest`] among the series whose tool `which` accepts (`"CVODE"`, `"scipy"`, [`OWN`]).
pub fn fastest_of(
    p: &ProblemData,
    target: f64,
    which: impl Fn(&str) -> bool,
) -> Option<(&Series, &Point)> {
    p.series
        .iter()
        .filter(|s| which(&s.tool))
        .flat_map(|s| {
            s.points
                .iter()
                .filter(|q| q.clean && q.seconds.is_some() && q.error.is_some_and(|e| e <= target))
                .map(move |q| (s, q))
        })
        .min_by(|a, b| a.1.seconds.unwrap_or(f64::INFINITY).total_cmp(&b.1.seconds.unwrap_or(f64::INFINITY)))
}

/// Whether a run counts on its ladder: it found every event — or, in a problem with
/// sticking (`sticking`), where impacts accumulate and no two methods count them alike, it
/// reached the end with the tip never beyond the stop at a period end.
pub fn counts(p: &Point, sticking: bool) -> bool {
    p.clean || (sticking && p.outcome == "completed")
}

/// The smallest error a series reached in a run that [`counts`], if any.
pub fn best_error(s: &Series, sticking: bool) -> Option<f64> {
    s.points
        .iter()
        .filter(|p| counts(p, sticking))
        .filter_map(|p| p.error)
        .min_by(f64::total_cmp)
}

/// The scene.
pub struct SideBySide;

impl Scene for SideBySide {
    const NAME: &'static str = "side-by-side";
    const PAPER: &'static str = "§5.1–5.3 (methods)";
    const TITLE: &'static str = "Side by side with other tools";
    const GIST: &'static str = "— (the paper compares no tools)";
    const GROUP: Group = Group::Methods;
    const SUMMARY: &'static str =
        "error against CPU time: this project beside CVODE, scipy, Siconos and Newton shooting with finite differences";
    const CLAIM: &'static str = "— (the paper compares no tools)";
    const CHAPTER: &'static str = "side-by-side.md";
    const METHOD: &'static str = "the committed results of peers/run.py (SUNDIALS CVODE with root finding, scipy solve_ivp with events, Siconos 4.4 event-driven and Moreau–Jean, Newton shooting with a central-difference monodromy, this project's Dormand–Prince), each run's error against an independent 40-digit mpmath reference, every time the best CPU time of the solve alone; this project's values recomputed by the library and compared with the committed ones";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        (
            "largest error of this project against the 40-digit references",
            "largest error of this project against the references",
        ),
        (
            "largest change of a committed value on recomputation",
            "committed values, largest change on recomputation",
        ),
    ];
    type Params = SideBySideParams;
    type Data = SideBySideData;

    fn params(resolution: Resolution) -> SideBySideParams {
        match resolution {
            Resolution::Book | Resolution::Test => SideBySideParams::book(),
        }
    }

    fn compute(p: &SideBySideParams, _: &dyn Progress) -> Result<SideBySideData, Error> {
        compute(p)
    }

    fn key_numbers(d: &SideBySideData) -> KeyNumbers {
        keys::key_numbers(d)
    }

    fn verdict(d: &SideBySideData) -> Verdict {
        let worst = d.problems.iter().map(|p| p.ours_error).fold(0.0, f64::max);
        let ratio = d
            .problems
            .iter()
            .map(|p| p.ours_error / p.sensitivity.max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max);
        Verdict {
            outcome: Outcome::NoClaim,
            evidence: format!(
                "this project's values agree with independent 40-digit references to {worst:.0e} \
                 or better ({ratio:.0e} times each problem's response to a 1e-16 change of its \
                 start, at most); the peers' errors and times are in the tables"
            ),
        }
    }

    fn render(d: &SideBySideData) -> Result<Rendered, crate::results::render::RenderError> {
        Ok(Rendered {
            extra_tables: vec![
                ("setup", render::setup(d)),
                ("includes", render::includes(d)),
                ("problems", render::problems(d)),
                ("outcomes", render::outcomes(d)),
                ("orbits", render::orbits(d)),
                ("runs", render::runs(d)),
            ],
            ..Rendered::drawn(|layout| render::plot(d, layout), render::headline(d))?
        })
    }
}
