//! Observation never perturbs (issue: an observer changed the answer). Over a grid of
//! models — the compliant model at soft and stiff stops, the rigid model with every law,
//! r = 0 among them — the events, the period found on the strobe and the final state are
//! the same bits with and without dense output and the energy budget, through the library
//! and through the command line (with and without --dense and --final-state).

use impacting_cantilever::analysis::simulate::{simulate, SimulateOptions, Simulation};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::built::BuiltModel;
use impacting_cantilever::model::spec::{
    Cantilever, DampingReading, ForcingSpec, GapUnit, Law, ModelSpec, Start, Stop, Structure,
};

use crate::common::cli as common;

fn spec(modes: usize, gap: f64, omega: f64, stop: Stop) -> ModelSpec {
    ModelSpec {
        structure: Structure::Cantilever(Cantilever {
            modes,
            gap,
            gap_unit: GapUnit::Resonance,
            zeta1: 0.01,
            damping_reading: DampingReading::Fig9,
            viscous: 0.0,
            omega,
            forcing: ForcingSpec::Unit,
        }),
        stop,
    }
}

/// The grid: compliant at 0, 1, 100 and 1e8 k₁, with a gap and preloaded; rigid with each law
/// and r = 0, 0.5, 0.8 (the issue's r = 0 impulse-response case and the collocation case).
fn grid() -> Vec<ModelSpec> {
    let mut out = Vec::new();
    for (n, k, gap) in [
        (3, 100.0, 0.0),
        (10, 100.0, 0.0),
        (5, 1e8, 0.003),
        (2, 0.0, 0.0),
        (4, 1.0, -0.003),
    ] {
        out.push(spec(n, gap, 2.0, Stop::Compliant { stop_stiffness: k }));
    }
    for (law, n) in [
        (Law::ImpulseResponse, 3),
        (Law::StiffnessLimit, 3),
        (Law::Collocation, 5),
        (Law::Newton, 1),
    ] {
        for r in [0.0, 0.5, 0.8] {
            out.push(spec(
                n,
                0.5,
                1.0,
                Stop::Rigid {
                    law,
                    restitution: r,
                },
            ));
        }
    }
    out
}

fn run(model: &BuiltModel, dense: Option<usize>, energy: bool) -> Simulation {
    let (x0, _) = model.start(&Start::Rest).unwrap();
    let o = SimulateOptions {
        periods: 13,
        record: 6,
        dense_per_period: dense,
        energy,
        ..SimulateOptions::default()
    };
    simulate(model, &x0, &o, &Silent).unwrap()
}

/// What observing must not change, compared bit for bit.
fn same(a: &Simulation, b: &Simulation, what: &str) {
    assert_eq!(a.events, b.events, "{what}: events");
    assert_eq!(a.final_state, b.final_state, "{what}: final state");
    assert_eq!(a.final_clock, b.final_clock, "{what}: final clock");
    assert_eq!(
        (
            a.period_m,
            a.periodicity_residual,
            a.impacts_n,
            a.contacts_in_window
        ),
        (
            b.period_m,
            b.periodicity_residual,
            b.impacts_n,
            b.contacts_in_window
        ),
        "{what}: period"
    );
    assert_eq!(a.ending, b.ending, "{what}: ending");
    assert_eq!(
        a.max_tip.map(|m| (m.value, m.time)),
        b.max_tip.map(|m| (m.value, m.time)),
        "{what}: max tip"
    );
}

#[test]
fn events_strobe_and_final_state_are_the_same_bits_whatever_is_recorded() {
    for spec in grid() {
        let model = BuiltModel::build(&spec).unwrap();
        let plain = run(&model, None, false);
        let what = format!("{spec:?}");
        same(
            &plain,
            &run(&model, Some(97), false),
            &format!("{what} with dense output"),
        );
        same(
            &plain,
            &run(&model, None, true),
            &format!("{what} with the energy budget"),
        );
        same(
            &plain,
            &run(&model, Some(3), true),
            &format!("{what} with both"),
        );
        // and something happened to observe
        assert!(!plain.events.is_empty(), "{what}: no events");
    }
}

/// Progress observed in whole periods (what `orbit` and `continue` report during a
/// transient) changes nothing: the state after the transient is the unobserved run's, bit for
/// bit, for every model of the grid, and the periods reported add up to the transient.
#[test]
fn a_transient_reported_in_periods_is_the_same_run() {
    use impacting_cantilever::base::progress::{Progress, Task};
    use impacting_cantilever::engine::map::PeriodMap;
    use std::sync::atomic::{AtomicU64, Ordering};
    #[derive(Default)]
    struct Count(AtomicU64);
    impl Task for Count {
        fn advance(&self, units: u64) {
            self.0.fetch_add(units, Ordering::Relaxed);
        }
    }
    for spec in grid() {
        let model = BuiltModel::build(&spec).unwrap();
        let (x0, _) = model.start(&Start::Rest).unwrap();
        let plain = model.advance(&x0, 3, 17, false).unwrap().state;
        let count = Count::default();
        let reported = model
            .advance_reporting(&x0, 3, 17, &count, &Silent)
            .unwrap();
        assert_eq!(plain.as_slice(), reported.as_slice(), "{}", model.name());
        assert_eq!(count.0.load(Ordering::Relaxed), 17, "{}", model.name());
        // a cancelled caller stops it
        struct Cancelled;
        impl Progress for Cancelled {
            fn task(&self, _: &str, _: u64) -> Box<dyn Task + '_> {
                Box::new(Silent)
            }
            fn cancelled(&self) -> bool {
                true
            }
        }
        let stopped = model.advance_reporting(&x0, 3, 17, &count, &Cancelled);
        assert!(
            matches!(
                stopped,
                Err(impacting_cantilever::error::Error::Interrupted)
            ),
            "{}",
            model.name()
        );
    }
}

#[test]
fn the_issues_rigid_reproducers_agree_with_and_without_dense_output() {
    // `simulate --model rigid --law impulse-response --restitution 0 --modes 3 --gap 0.5
    // --zeta1 0.01 --omega 1 --periods 13 --record 1`: 40 impacts with growing velocities
    // plain, 3 then sticking with --dense (the dense pieces restarted the run)
    let base = [
        "simulate",
        "--model",
        "rigid",
        "--modes",
        "3",
        "--gap",
        "0.5",
        "--zeta1",
        "0.01",
        "--omega",
        "1",
        "--periods",
        "13",
        "--record",
        "1",
        "--json",
    ];
    let dir = common::scratch("observation");
    for law in [
        ["--law", "impulse-response", "--restitution", "0"],
        ["--law", "collocation", "--restitution", "0.8"],
    ] {
        let mut plain: Vec<&str> = base.to_vec();
        plain.extend(law);
        if law[1] == "collocation" {
            plain[4] = "5";
        }
        let dense = dir.join("d.csv");
        let state = dir.join("s.json");
        let mut observed = plain.clone();
        observed.extend(["--dense", dense.to_str().unwrap()]);
        observed.extend(["--final-state", state.to_str().unwrap()]);
        let (code_a, a, err_a) = common::cantilever(&plain);
        let (code_b, b, err_b) = common::cantilever(&observed);
        assert_eq!((code_a, code_b), (0, 0), "{err_a}{err_b}");
        let (mut a, mut b): (serde_json::Value, serde_json::Value) = (
            serde_json::from_str(&a).unwrap(),
            serde_json::from_str(&b).unwrap(),
        );
        for v in [&mut a, &mut b] {
            v["wall_seconds"] = serde_json::Value::Null;
        }
        assert_eq!(a, b, "{law:?}");
        let written: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&state).unwrap()).unwrap();
        assert_eq!(written["time"], a["final_time"], "{law:?}");
    }
}

/// Options a command does not use are refused by name, never accepted and ignored:
/// `orbit`/`continue` took --dense and --final-state and wrote nothing; the rigid model
/// echoed --stop-stiffness, the compliant one --law and --restitution.
#[test]
fn options_are_used_or_refused_by_name() {
    let model = ["--modes", "1", "--zeta1", "0.01", "--omega", "2"];
    let cases: [(&[&str], &str); 6] = [
        (&["orbit", "--dense", "x.csv"], "--dense"),
        (&["orbit", "--final-state", "x.json"], "--final-state"),
        (
            &[
                "continue",
                "--parameter",
                "omega",
                "--to",
                "2.2",
                "--dense",
                "x.csv",
            ],
            "--dense",
        ),
        (
            &[
                "simulate",
                "--periods",
                "1",
                "--model",
                "rigid",
                "--stop-stiffness",
                "100",
            ],
            "--stop-stiffness",
        ),
        (&["simulate", "--periods", "1", "--law", "newton"], "--law"),
        (
            &["simulate", "--periods", "1", "--restitution", "0.5"],
            "--restitution",
        ),
    ];
    for (args, flag) in cases {
        let all: Vec<&str> = args.iter().chain(&model).copied().collect();
        let (code, _, err) = common::cantilever(&all);
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(
            err.contains(flag) && err.lines().count() == 1,
            "{all:?}: {err}"
        );
    }
}
