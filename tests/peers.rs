//! The committed peer results (`peers/results/*.json`, written by `python3 peers/run.py`) are
//! consistent: every required field is there, no file was edited by hand (its checksum),
//! every timing is the best of its repeats and was measured from a committed build, every
//! tool's time says what it includes, the compiled peer (CVODE) ran every problem, every
//! reported error is what the stored states say, each peer's errors follow its own
//! tolerance ladder, and this project's values in the files are the ones the library
//! computes now — so a stale or edited file fails here.
//!
//! Runs in the fast tier (`cargo test`): the files are parsed once and this project's runs
//! are recomputed for every problem (milliseconds each).

use impacting_cantilever::results::peers::{
    self, best, checksum, multiplier_error, parse_orbits, parse_simulation, strobe_error, Orbits,
    Simulation, OWN,
};
use serde_json::Value;
use std::path::Path;
use std::sync::OnceLock;

/// The files as they are on disk now (not as the library embedded them when it was built).
fn on_disk(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("peers/results")
        .join(format!("{name}.json"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

type Committed = (Vec<(String, Simulation)>, Orbits);

fn committed() -> &'static Committed {
    static FILES: OnceLock<Committed> = OnceLock::new();
    FILES.get_or_init(|| {
        let sims = peers::FILES[..5]
            .iter()
            .map(|(name, _)| {
                let f = parse_simulation(name, &on_disk(name)).unwrap_or_else(|e| panic!("{e}"));
                (name.to_string(), f)
            })
            .collect();
        (
            sims,
            parse_orbits(&on_disk("orbits")).unwrap_or_else(|e| panic!("{e}")),
        )
    })
}

/// Two doubles computed by the same formula from the same doubles (here and in Python) are
/// equal; 4 ulps allow for a different order of a sum.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs())
}

#[test]
fn every_file_parses_and_its_checksum_holds() {
    let (sims, orbits) = committed();
    assert_eq!(sims.len(), 5);
    for (name, f) in sims {
        assert!(!f.rows.is_empty(), "{name}: no peer runs");
        assert!(
            f.machine.cores > 0 && !f.machine.cpu.is_empty(),
            "{name}: machine"
        );
        for v in [
            "python",
            "numpy",
            "scipy",
            "mpmath",
            "cantilever",
            "commit",
            "sundials",
            "cc",
        ] {
            assert!(
                f.versions.get(v).is_some_and(|x| x.is_some()),
                "{name}: version of {v}"
            );
        }
        if f.problem.model == "rigid" {
            assert!(
                f.versions.get("siconos").is_some_and(|x| x.is_some()),
                "{name}: Siconos"
            );
        }
        assert_eq!(
            f.ours.strobe.len() as u64,
            f.problem.periods,
            "{name}: our strobe"
        );
        assert_eq!(
            f.reference.strobe.len() as u64,
            f.problem.periods,
            "{name}: reference"
        );
    }
    assert_eq!(orbits.ours.len(), orbits.problem.cases.len());
}

#[test]
fn an_edited_or_foreign_file_is_refused() {
    let text = on_disk("fig4-n3");
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    // one ulp in one peer's final state
    let x = &mut doc["rows"][0]["final_state"][0];
    let v = x.as_f64().unwrap();
    *x = Value::from(f64::from_bits(v.to_bits() + 1));
    let err = parse_simulation("fig4-n3", &serde_json::to_string(&doc).unwrap()).unwrap_err();
    assert!(err.contains("edited by hand"), "{err}");
    // a field removed, the checksum made to match: the fields are still required
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc["rows"][0].as_object_mut().unwrap().remove("outcome");
    doc["checksum"] = Value::from(checksum(&doc));
    let err = parse_simulation("fig4-n3", &serde_json::to_string(&doc).unwrap()).unwrap_err();
    assert!(err.contains("outcome"), "{err}");
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc["format"] = Value::from("something else");
    assert!(parse_simulation("x", &serde_json::to_string(&doc).unwrap()).is_err());
}

#[test]
fn every_time_is_the_best_of_its_repeats() {
    let (sims, orbits) = committed();
    let check = |what: &str, samples: &[f64], stated: f64, repeats: usize| {
        assert!(repeats >= 3, "{what}: {repeats} repeats, at least 3 wanted");
        assert_eq!(samples.len(), repeats, "{what}: repeats");
        assert!(
            samples.iter().all(|&t| t.is_finite() && t >= 0.0),
            "{what}: {samples:?}"
        );
        assert_eq!(best(samples), stated, "{what}: best of {samples:?}");
    };
    // a compiled tool's repeat is the best of 1 to `inner_repeats` solves
    let solves = |what: &str, counts: &[usize], inner: usize, repeats: usize| {
        assert_eq!(counts.len(), repeats, "{what}: solves per repeat");
        assert!(
            counts.iter().all(|&c| (1..=inner).contains(&c)),
            "{what}: {counts:?} solves, 1 to {inner} wanted"
        );
    };
    for (name, f) in sims {
        let n = f.protocol.repeats;
        let inner = f.protocol.inner_repeats;
        check(
            &format!("{name} ours"),
            &f.ours.cpu_seconds,
            f.ours.cpu_seconds_best,
            n,
        );
        solves(&format!("{name} ours"), &f.ours.solves_per_repeat, inner, n);
        for r in &f.rows {
            let what = format!("{name} {} {} {:?}", r.tool, r.method, r.setting);
            if let Some(c) = &r.solves_per_repeat {
                solves(&what, c, inner, n);
            }
            match (&r.cpu_seconds, r.cpu_seconds_best) {
                (Some(s), Some(m)) => check(&what, s, m, n),
                // a rung not run says why
                _ => assert!(
                    r.outcome.starts_with("not "),
                    "{what}: no time and {}",
                    r.outcome
                ),
            }
        }
    }
    for o in &orbits.ours {
        let n = orbits.protocol.repeats;
        check("orbit ours", &o.cpu_seconds, o.cpu_seconds_best, n);
        solves(
            "orbit ours",
            &o.solves_per_repeat,
            orbits.protocol.inner_repeats,
            n,
        );
    }
    for r in &orbits.rows {
        match (&r.cpu_seconds, r.cpu_seconds_best) {
            (Some(s), Some(m)) => check(&r.method, s, m, orbits.protocol.repeats),
            _ => assert!(r.outcome.starts_with("not "), "{}: {}", r.method, r.outcome),
        }
    }
}

/// The times were measured from a committed build, every tool's time says in a sentence
/// what it includes, and this project's timed run is the command line's run.
#[test]
fn the_timings_come_from_a_committed_build_and_say_what_they_include() {
    let (sims, orbits) = committed();
    let commits: Vec<&str> = sims
        .iter()
        .map(|(_, f)| &f.versions)
        .chain([&orbits.versions])
        .map(|v| v["commit"].as_deref().unwrap_or("(none)"))
        .collect();
    for c in &commits {
        assert!(
            c.len() == 40 && c.chars().all(|x| x.is_ascii_hexdigit()),
            "measured by {c:?}: a clean commit wanted"
        );
    }
    for (name, f) in sims {
        let named = |tool: &str| {
            f.protocol
                .includes
                .iter()
                .any(|(t, what)| t == tool && what.len() > 40)
        };
        assert!(
            named("this project"),
            "{name}: what this project's time includes"
        );
        for r in &f.rows {
            let tool = if r.tool == OWN {
                "this project's Dormand–Prince 5(4)"
            } else {
                r.tool.as_str()
            };
            assert!(named(tool), "{name}: what {tool}'s time includes");
        }
        let moved = strobe_error(
            std::slice::from_ref(&f.ours.timed_final_state),
            std::slice::from_ref(&f.ours.final_state),
        )
        .unwrap();
        // the same flows from the same start: equal up to the round-off of a differently
        // grouped period loop (relative 1e-13, ~500 ulps over 50 periods)
        assert!(moved <= 1e-13, "{name}: the timed run ends {moved:e} away");
    }
    for tool in ["this project", "scipy"] {
        assert!(
            orbits.protocol.includes.iter().any(|(t, _)| t == tool),
            "orbits: what {tool}'s time includes"
        );
    }
}

/// The compiled peer ran every problem at both of its settings (BDF and Adams), every rung
/// of its ladder recorded; this project's own Dormand–Prince ran the compliant problems.
#[test]
fn the_compiled_peer_ran_every_problem() {
    let (sims, _) = committed();
    for (name, f) in sims {
        for method in ["BDF", "Adams"] {
            let rows: Vec<_> = f
                .rows
                .iter()
                .filter(|r| r.tool == "CVODE" && r.method.starts_with(method))
                .collect();
            assert_eq!(rows.len(), 11, "{name}: CVODE {method} rungs");
            assert!(
                rows.iter().any(|r| r.cpu_seconds_best.is_some()),
                "{name}: CVODE {method} never ran"
            );
        }
        let own = f.rows.iter().filter(|r| r.tool == OWN).count();
        let wanted = if f.problem.model == "compliant" {
            11
        } else {
            0
        };
        assert_eq!(own, wanted, "{name}: this project's Dormand–Prince rungs");
    }
}

fn event_error(t: &[f64], k: &[bool], rt: &[f64], rk: &[bool]) -> Option<f64> {
    (t.len() == rt.len() && k == rk).then(|| {
        t.iter()
            .zip(rt)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
    })
}

#[test]
fn every_error_is_what_the_stored_states_say() {
    let (sims, orbits) = committed();
    let agree = |what: &str, stated: Option<f64>, computed: Option<f64>| match (stated, computed) {
        (Some(a), Some(b)) => assert!(same(a, b), "{what}: stated {a:e}, computed {b:e}"),
        (a, b) => assert_eq!(
            a.is_some(),
            b.is_some(),
            "{what}: stated {a:?}, computed {b:?}"
        ),
    };
    for (name, f) in sims {
        let (ours, reference) = (&f.ours, &f.reference);
        agree(
            &format!("{name}: ours against the reference"),
            ours.strobe_error_vs_reference,
            strobe_error(&ours.strobe, &reference.strobe),
        );
        agree(
            &format!("{name}: our event times against the reference"),
            ours.event_time_error_vs_reference,
            event_error(
                &ours.event_times,
                &ours.event_kinds,
                &reference.event_times,
                &reference.event_kinds,
            ),
        );
        for r in f.rows.iter().filter(|r| r.strobe.is_some()) {
            let what = format!("{name} {} {} {:?}", r.tool, r.method, r.setting);
            let strobe = r.strobe.as_ref().unwrap();
            agree(
                &what,
                r.strobe_error_vs_ours,
                strobe_error(strobe, &ours.strobe),
            );
            agree(
                &what,
                r.strobe_error_vs_reference,
                strobe_error(strobe, &reference.strobe),
            );
            let (t, k) = (
                r.event_times.as_ref().unwrap(),
                r.event_kinds.as_ref().unwrap(),
            );
            assert_eq!(r.events, Some(t.len()), "{what}: event count");
            let vs_ours = event_error(t, k, &ours.event_times, &ours.event_kinds);
            agree(&what, r.event_time_error_vs_ours, vs_ours);
            assert_eq!(
                r.same_events_as_ours,
                Some(vs_ours.is_some()),
                "{what}: same events"
            );
            agree(
                &what,
                r.event_time_error_vs_reference,
                event_error(t, k, &reference.event_times, &reference.event_kinds),
            );
        }
    }
    for r in orbits.rows.iter().filter(|r| r.state.is_some()) {
        let ours = orbits
            .ours
            .iter()
            .find(|o| o.modes == r.modes && o.start_periods == r.start_periods)
            .expect("the case of each orbit row");
        let what = format!("orbit N = {} {} {}", r.modes, r.method, r.setting);
        let state = r.state.as_ref().unwrap();
        agree(
            &what,
            r.state_error_vs_ours,
            strobe_error(
                std::slice::from_ref(state),
                std::slice::from_ref(&ours.state),
            ),
        );
        agree(
            &what,
            r.multiplier_error_vs_ours,
            Some(multiplier_error(
                r.multipliers.as_ref().unwrap(),
                &ours.multipliers,
            )),
        );
    }
}

/// Each peer's ladder: the runs that completed with every event found, loosest first (a
/// rung tightens rtol 10×, or refines Moreau–Jean's step 4×). The ladder as a whole must
/// gain — its tightest run's error at most a tenth of its loosest's — unless the loosest is
/// already within 100× of the problem's floor; and no rung may lose more than 100× against
/// the one before. Not 10×: error control does not make the global error proportional to
/// the tolerance, and an explicit method whose step is limited by stability rather than
/// accuracy is not even monotone (DOP853 at N = 10: 2e-9 at rtol 1e-9, 8e-8 at 1e-10,
/// 3e-9 at 1e-11). The floor is the larger of 1e-14 and 1000 × the reference's change for
/// 1e-16 at the start (a double-precision run rounds at every step: hundreds of such
/// changes).
#[test]
fn each_peer_follows_its_tolerance_ladder() {
    let (sims, orbits) = committed();
    for (name, f) in sims {
        let floor = (1e3 * f.reference.sensitivity).max(1e-14);
        let mut methods: Vec<(&str, &str)> = f
            .rows
            .iter()
            .map(|r| (r.tool.as_str(), r.method.as_str()))
            .collect();
        methods.dedup();
        for (tool, method) in methods {
            let ladder: Vec<(f64, f64)> = f
                .rows
                .iter()
                .filter(|r| r.tool == tool && r.method == method && r.clean())
                .filter_map(|r| Some((r.setting?, r.strobe_error_vs_reference?)))
                .collect();
            for w in ladder.windows(2) {
                let ((s0, e0), (s1, e1)) = (w[0], w[1]);
                assert!(
                    e1 <= 100.0 * e0.max(floor),
                    "{name} {tool} {method}: error {e0:.1e} at {s0:e} grew to {e1:.1e} at {s1:e}"
                );
            }
            if let (Some(&(s0, e0)), Some(&(s1, e1))) = (ladder.first(), ladder.last()) {
                assert!(
                    ladder.len() < 2 || e1 <= 0.1 * e0 || e0 <= 100.0 * floor,
                    "{name} {tool} {method}: no gain from {s0:e} ({e0:.1e}) to {s1:e} ({e1:.1e})"
                );
            }
        }
    }
    for case in &orbits.problem.cases {
        for method in ["DOP853", "Radau", "LSODA"] {
            let ladder: Vec<f64> = orbits
                .rows
                .iter()
                .filter(|r| r.modes == case.modes && r.start_periods == case.start_periods)
                .filter(|r| r.method.starts_with(method) && r.outcome == "converged")
                .filter_map(|r| r.multiplier_error_vs_ours)
                .collect();
            // rtol tightens 100× a rung; the central differences' step is rtol^(1/3) of each
            // component, so the monodromy errs by about rtol^(2/3): it must not grow
            for w in ladder.windows(2) {
                assert!(
                    w[1] <= 10.0 * w[0].max(1e-12),
                    "orbit N = {} {method}: {ladder:?}",
                    case.modes
                );
            }
        }
    }
}

/// Why a problem's committed values of this project are not the library's now (None: they
/// are). On the machine that wrote the files they agree to the last bit (measured: 0 for
/// the rigid problems, 1.7e-16 for the compliant ones, whose period ends the command line
/// and the library round differently); elsewhere a last-bit difference of libm moves a run
/// by about the reference's change for 1e-16 at the start, so 100 of those are allowed.
fn stale(name: &str, f: &Simulation) -> Option<String> {
    let strobe = peers::recompute(&f.problem).unwrap();
    let moved = strobe_error(&f.ours.strobe, &strobe).unwrap();
    let allowed = 100.0 * f.reference.sensitivity.max(f64::EPSILON);
    (moved > allowed).then(|| {
        format!(
            "{name}: the committed values are stale: they moved by {moved:.1e} (allowed \
             {allowed:.1e}); rerun `python3 peers/run.py --only {name}`"
        )
    })
}

/// A file whose values of this project were changed — by 1e-9 of one state, checksum
/// recomputed so that it parses — is told from the library's values.
#[test]
fn a_file_with_changed_values_and_a_matching_checksum_is_stale() {
    let mut doc: Value = serde_json::from_str(&on_disk("fig4-n3")).unwrap();
    let x = &mut doc["ours"]["strobe"][7][0];
    let v = x.as_f64().unwrap();
    *x = Value::from(v + 1e-9 * v.abs().max(1.0));
    doc["checksum"] = Value::from(checksum(&doc));
    let f = parse_simulation("fig4-n3", &serde_json::to_string(&doc).unwrap()).unwrap();
    let why = stale("fig4-n3", &f).expect("a changed value is stale");
    assert!(why.contains("stale"), "{why}");
}

/// A peer's error against this project and against the reference differ by no more than
/// this project's own error against the reference (the triangle inequality; the two are
/// relative to slightly different scales, hence the factor): the three stated errors of a
/// file hold together.
#[test]
fn each_peer_error_against_ours_and_against_the_reference_hold_together() {
    let (sims, _) = committed();
    for (name, f) in sims {
        let e = f
            .ours
            .strobe_error_vs_reference
            .expect("ours reach the end");
        for r in &f.rows {
            if let (Some(a), Some(b)) = (r.strobe_error_vs_ours, r.strobe_error_vs_reference) {
                assert!(
                    (a - b).abs() <= 1.01 * e * (1.0 + a + b) + 4.0 * f64::EPSILON * (a + b),
                    "{name} {} {} {:?}: {a:e} against ours, {b:e} against the reference, \
                     ours {e:e} from it",
                    r.tool,
                    r.method,
                    r.setting
                );
            }
        }
    }
}

/// This project's values in the files are the library's now: the matrices the peers
/// integrated, every run's state at each period end ([`stale`]), every orbit.
#[test]
fn our_values_in_the_files_are_the_librarys_now() {
    let (sims, orbits) = committed();
    for (name, f) in sims {
        let now = peers::problem_matrices(&f.problem).unwrap();
        for key in [
            "modal_stiffness",
            "damping",
            "forcing_amplitude",
            "tip",
            "period",
            "omega",
            "K_plus",
            "contact_preload",
            "law_impulse_response",
        ] {
            let flat = |v: &Value| -> Vec<f64> {
                match v {
                    Value::Array(a) => a
                        .iter()
                        .flat_map(|x| match x {
                            Value::Array(b) => b.iter().map(|y| y.as_f64().unwrap()).collect(),
                            y => vec![y.as_f64().unwrap()],
                        })
                        .collect(),
                    y => vec![y.as_f64().unwrap()],
                }
            };
            let (a, b) = (flat(&f.matrices[key]), flat(&now[key]));
            assert_eq!(a.len(), b.len(), "{name}: {key}");
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= 4.0 * f64::EPSILON * x.abs().max(1.0),
                    "{name}: {key} {x} now {y}"
                );
            }
        }
        if let Some(why) = stale(name, f) {
            panic!("{why}");
        }
    }
    for (case, ours) in orbits.problem.cases.iter().zip(&orbits.ours) {
        let now = peers::recompute_orbit(&orbits.problem, case).unwrap();
        // the shooting stops at a residual of 1e-12
        let moved = strobe_error(
            std::slice::from_ref(&ours.state),
            std::slice::from_ref(&now.state),
        )
        .unwrap();
        let mu = multiplier_error(&ours.multipliers, &now.multipliers);
        assert!(
            moved <= 1e-11 && mu <= 1e-11,
            "orbit N = {}: moved {moved:.1e}, multipliers {mu:.1e}",
            case.modes
        );
        assert_eq!(
            ours.iterations, now.iterations,
            "orbit N = {}: Newton steps",
            case.modes
        );
    }
}

/// The point of the independent references: this project agrees with them to within the
/// problem's conditioning (the floor of any double-precision run, see the ladder test).
#[test]
fn our_values_agree_with_the_independent_references() {
    let (sims, orbits) = committed();
    for (name, f) in sims {
        let e = f
            .ours
            .strobe_error_vs_reference
            .expect("ours reach the end");
        let floor = (1e3 * f.reference.sensitivity).max(1e-14);
        assert!(
            e <= floor,
            "{name}: {e:.1e} from the reference, floor {floor:.1e}"
        );
        if f.reference.sticking.is_empty() {
            // the same events, each at the same time to within the run's conditioning
            assert!(
                f.ours.event_time_error_vs_reference.is_some(),
                "{name}: other events than the reference's"
            );
        } else {
            // a chatter: the reference follows it to 1e-12 in velocity, this project to its
            // geometric limit sooner
            assert!(f.ours.event_times.len() <= f.reference.events, "{name}");
        }
    }
    for case in &orbits.problem.cases {
        assert!(
            case.reference_residual_of_ours <= 1e-12,
            "orbit N = {}: {:e}",
            case.modes,
            case.reference_residual_of_ours
        );
    }
}
