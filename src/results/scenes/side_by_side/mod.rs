//! Scene `side-by-side`: error against run time for this project and the tools a researcher
//! would use instead — scipy's `solve_ivp` with events (DOP853, Radau with the exact
//! Jacobian, LSODA), Siconos 4.4's event-driven (LSODAR) and Moreau–Jean integrators, and
//! Newton shooting with a finite-difference monodromy — on five shared problems and the
//! Figure 4 orbit with its multipliers.
//!
//! The peers run outside this library (`peers/run.py`, Python); their committed results
//! ([`crate::results::peers`]) are read here, checked (format, checksum) and drawn. Every
//! error is measured against an independent 40-digit reference (mpmath), this project's
//! included. The scene recomputes this project's values for the committed problems through
//! the library and reports how far the committed ones lie from them, so a stale file shows.
//! Timings are the committed ones (machine-dependent): they appear in the tables, never in
//! the key numbers.

pub mod render;

use crate::base::report::{KeyNumbers, Uncertainty};
use crate::error::Error;
use crate::results::peers::{self, Orbits, Simulation};
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
    /// Median CPU seconds (None: not run).
    pub seconds: Option<f64>,
    /// The middle half of its repeats (s).
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
    /// scipy or siconos.
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
    /// This project's run time (the command line's own, median, s).
    pub ours_seconds: f64,
    /// The middle half of its repeats (s).
    pub ours_seconds_range: (f64, f64),
    /// This project's process CPU time (start-up included, median, s).
    pub ours_process_seconds: f64,
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
    /// Median CPU seconds (None: not run).
    pub seconds: Option<f64>,
    /// The middle half of its repeats (s).
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
    /// This project's run time (median, s).
    pub ours_seconds: f64,
    /// The middle half of its repeats (s).
    pub ours_seconds_range: (f64, f64),
    /// Its process CPU time (median, s).
    pub ours_process_seconds: f64,
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
    /// Runs per setting.
    pub repeats: usize,
    /// The ladder budget (s).
    pub budget_seconds: f64,
}

fn problem_data(name: &str, f: &Simulation, recompute: bool) -> Result<ProblemData, Error> {
    let mut series: Vec<Series> = Vec::new();
    for r in &f.rows {
        let point = Point {
            setting: r.setting,
            seconds: r.cpu_seconds_median,
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
        ours_seconds: f.ours.run_seconds_median,
        ours_seconds_range: range(&f.ours.run_seconds),
        ours_process_seconds: f.ours.process_cpu_seconds_median,
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
                seconds: r.cpu_seconds_median,
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
            ours_seconds: ours.run_seconds_median,
            ours_seconds_range: range(&ours.run_seconds),
            ours_process_seconds: ours.process_cpu_seconds_median,
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
        budget_seconds: first.protocol.budget_seconds,
    })
}

/// The middle half of some repeats: the second and the second-to-last of them sorted (of
/// five: the 2nd and the 4th). Sub-millisecond wall times on a busy machine are sometimes
/// preempted; this leaves out one such outlier either way.
fn range(samples: &[f64]) -> (f64, f64) {
    let mut v = samples.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let q = if n >= 4 { n / 4 } else { 0 };
    (v[q], v[n - 1 - q])
}

/// The fastest clean run (every event found) of any peer with an error at or below
/// `target`: its series and the run.
pub fn fastest(p: &ProblemData, target: f64) -> Option<(&Series, &Point)> {
    p.series
        .iter()
        .flat_map(|s| {
            s.points
                .iter()
                .filter(|q| q.clean && q.seconds.is_some() && q.error.is_some_and(|e| e <= target))
                .map(move |q| (s, q))
        })
        .min_by(|a, b| a.1.seconds.unwrap_or(f64::INFINITY).total_cmp(&b.1.seconds.unwrap_or(f64::INFINITY)))
}

/// A peer's time over this project's, with the spread of the ratio over the middle half of
/// the repeats of each.
fn time_ratio(
    k: &mut KeyNumbers,
    name: String,
    peer: (f64, (f64, f64)),
    ours: (f64, (f64, f64)),
) {
    let ratio = peer.0 / ours.0;
    let spread = ((peer.1 .1 / ours.1 .0) - ratio)
        .abs()
        .max((ratio - peer.1 .0 / ours.1 .1).abs());
    k.cited(
        name,
        ratio,
        2,
        Uncertainty::new(
            spread,
            "medians of the committed timings (one machine); the ratio's spread over the middle half of the repeats",
        ),
        "",
    );
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

/// A computed error, exact given the committed data (2 figures).
fn error_key(k: &mut KeyNumbers, name: String, value: f64) {
    k.cited(
        name,
        value,
        2,
        Uncertainty::new(0.0, "computed from the committed peer results"),
        "relative",
    );
}

/// The distance of a Floquet multiplier from this project's (multipliers are pure
/// numbers), exact given the committed data (2 figures).
fn multiplier_key(k: &mut KeyNumbers, name: String, value: f64) {
    k.cited(
        name,
        value,
        2,
        Uncertainty::new(0.0, "computed from the committed peer results"),
        "",
    );
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
        "error against run time: this project beside scipy, Siconos and Newton shooting with finite differences";
    const CLAIM: &'static str = "— (the paper compares no tools)";
    const CHAPTER: &'static str = "side-by-side.md";
    const METHOD: &'static str = "the committed results of peers/run.py (scipy solve_ivp with events, Siconos 4.4 event-driven and Moreau–Jean, Newton shooting with a central-difference monodromy), each run's error against an independent 40-digit mpmath reference; this project's values recomputed by the library and compared with the committed ones";
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
        let mut k = KeyNumbers::default();
        let mut worst_ours = 0.0_f64;
        let mut worst_recomputed = 0.0_f64;
        for p in &d.problems {
            let n = &p.name;
            k.integer(format!("{n} periods"), p.periods as i64);
            k.integer(format!("{n} events"), p.ours_events as i64);
            k.integer(format!("{n} reference events"), p.reference_events as i64);
            error_key(&mut k, format!("{n} error of this project"), p.ours_error);
            error_key(&mut k, format!("{n} conditioning"), p.sensitivity);
            worst_ours = worst_ours.max(p.ours_error);
            if let Some(t) = p.first_sticking {
                k.cited(
                    format!("{n} reference: first sticking begins at t"),
                    t,
                    6,
                    Uncertainty::new(1e-12, "the 40-digit reference, chatter followed to 1e-12 in velocity"),
                    "",
                );
            }
            if let Some(r) = p.recomputed_difference {
                worst_recomputed = worst_recomputed.max(r);
            }
            for (target, label) in [(1e-6, "1e-6"), (1e-9, "1e-9")] {
                match fastest(p, target) {
                    Some((s, q)) => {
                        let run = format!("{} {} at {} {}", s.tool, s.method, s.setting_name, q.setting.map_or("—".into(), |v| format!("{v:e}")));
                        k.text(format!("{n} fastest peer to error {label}"), run);
                        time_ratio(
                            &mut k,
                            format!("{n} fastest peer to error {label}, time over this project's"),
                            (q.seconds.unwrap_or(f64::NAN), q.seconds_range.unwrap_or((f64::NAN, f64::NAN))),
                            (p.ours_seconds, p.ours_seconds_range),
                        );
                    }
                    None => k.text(format!("{n} fastest peer to error {label}"), "none"),
                }
            }
            for s in p.series.iter().filter(|s| s.points.iter().any(|q| q.seconds.is_some())) {
                let key = format!("{n} {} {}", s.tool, s.method);
                if let Some(e) = best_error(s, p.first_sticking.is_some()) {
                    error_key(&mut k, format!("{key} best error"), e);
                }
                let ran = s.points.iter().filter(|q| q.seconds.is_some());
                let stopped = ran.clone().filter(|q| !q.outcome.starts_with("completed")).count();
                let missed = ran
                    .filter(|q| q.outcome.starts_with("completed") && !q.clean)
                    .count();
                k.integer(format!("{key} runs"), s.points.iter().filter(|q| q.seconds.is_some()).count() as i64);
                k.integer(format!("{key} runs that stopped early"), stopped as i64);
                k.integer(format!("{key} runs that missed or added events"), missed as i64);
            }
        }
        error_key(
            &mut k,
            "largest error of this project against the references".into(),
            worst_ours,
        );
        for o in &d.orbits {
            let key = format!("orbit N={} from {} periods", o.modes, o.start_periods);
            k.integer(format!("{key}: Newton steps"), o.ours_iterations as i64);
            k.cited(
                format!("{key}: spectral radius"),
                o.ours_spectral_radius,
                6,
                Uncertainty::new(1e-12, "shooting residual ≤ 1e-12 and the exact monodromy"),
                "",
            );
            error_key(&mut k, format!("{key}: residual under the reference map"), o.reference_residual);
            if let Some(best) = o
                .peers
                .iter()
                .filter_map(|q| q.multiplier_error)
                .min_by(f64::total_cmp)
            {
                multiplier_key(&mut k, format!("{key}: best peer multiplier error"), best);
            }
            let converged = || o.peers.iter().filter(|q| q.outcome == "converged" && q.seconds.is_some());
            if let Some(q) = converged().min_by(|a, b| a.seconds.unwrap_or(f64::INFINITY).total_cmp(&b.seconds.unwrap_or(f64::INFINITY))) {
                k.text(format!("{key}: fastest peer"), format!("{} at rtol {:e}", q.method, q.rtol));
                time_ratio(
                    &mut k,
                    format!("{key}: fastest peer, time over this project's"),
                    (q.seconds.unwrap_or(f64::NAN), q.seconds_range.unwrap_or((f64::NAN, f64::NAN))),
                    (o.ours_seconds, o.ours_seconds_range),
                );
                multiplier_key(&mut k, format!("{key}: fastest peer, multiplier error"), q.multiplier_error.unwrap_or(f64::NAN));
            }
            if let Some(r) = o.recomputed_difference {
                worst_recomputed = worst_recomputed.max(r);
            }
        }
        // a difference at or below 1e-13 is round-off of the same computation on another
        // machine; above it the committed file is stale
        k.text(
            "committed values, largest change on recomputation",
            if worst_recomputed == 0.0 {
                "none (bit for bit)".to_string()
            } else if worst_recomputed <= 1e-13 {
                "below 1e-13 (round-off)".to_string()
            } else {
                format!("{worst_recomputed:.1e} (stale: rerun the peers)")
            },
        );
        k
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
                ("problems", render::problems(d)),
                ("outcomes", render::outcomes(d)),
                ("orbits", render::orbits(d)),
                ("runs", render::runs(d)),
            ],
            ..Rendered::drawn(|layout| render::plot(d, layout), render::headline(d))?
        })
    }
}
