//! The third adversarial round: each reproducer of the report (stiff stops, special files,
//! corrupt shards, the rigid model at sticking) with the behaviour it must have now — a
//! correct result in bounded time, or a refusal that names the parameter and what is
//! supported. Numbered as in the report.
#![cfg(feature = "cli")]

use impacting_cantilever::engine::rigid::{RigidEvent, RigidImpact};
use impacting_cantilever::engine::sim::{Clock, Simulator};
use impacting_cantilever::model::problems::Forced;
use impacting_cantilever::model::restitution;
use nalgebra::DVector;

use crate::common::cli;
use cli::cantilever;

/// The one-mode rigid model of item 4: Newton's law r = 0.5, ζ₁ = 0.01, ω = 0.1(β₁⁻)², a
/// stop at d₀ = 0.01 (below the forced amplitude): each cycle the tip chatters onto the
/// stop and sticks until the contact force changes sign, at phase 1/6 of the period.
fn sticking_oscillator(modes: usize) -> RigidImpact {
    let forced = Forced {
        modes,
        k_over_k1: 0.0,
        zeta1: 0.01,
        omega_over_w1: 0.1,
        gap: 0.01,
        printed_eq37_amplitude: false,
    };
    RigidImpact::new(
        Simulator::new(forced.model().unwrap()).unwrap(),
        restitution::impulse_response(modes, 0.5).unwrap(),
    )
    .unwrap()
}

#[test]
fn item_4_sticking_survives_every_restart() {
    for modes in [1, 3] {
        let model = sticking_oscillator(modes);
        let period = model.sim.period();
        let x0 = DVector::zeros(2 * modes);
        // one run of 6 periods, and the same chained one period at a time
        let whole = model.run(&x0, 6.0 * period).unwrap();
        let mut x = x0.clone();
        let mut chained = Vec::new();
        for c in 0..6 {
            let r = model
                .run_until(
                    &x,
                    Clock::at_cycle(period, c),
                    Clock::at_cycle(period, c + 1),
                )
                .unwrap();
            chained.extend(r.impacts());
            x = r.state;
        }
        let impacts = whole.impacts();
        assert_eq!(impacts.len(), chained.len(), "N = {modes}: same impacts");
        for (a, b) in impacts.iter().zip(&chained) {
            assert!(
                (a.0 - b.0).abs() < 1e-9 * period,
                "N = {modes}: {a:?} vs {b:?}"
            );
        }
        let e = (&whole.state - &x).amax() / whole.state.amax();
        assert!(e < 1e-9, "N = {modes}: end states differ by {e:e}");
        // no impact while the stop pushes: after the first cycle's approach from rest,
        // nothing lands between phase 0 and the release at 1/6
        if modes == 1 {
            for (t, _, _) in impacts.iter().filter(|(t, _, _)| *t > 2.0 * period) {
                let phase = (t / period).fract();
                assert!(!(0.0..0.166).contains(&phase), "impact at phase {phase}");
            }
            assert!(whole
                .events
                .iter()
                .any(|e| matches!(e, RigidEvent::StickEnd { .. })));
        }
    }
    // the command line, which restarts every recorded period: impacts only where the free
    // motion brings the tip down, the same number each period
    let (code, out, err) = cantilever(&[
        "simulate",
        "--model",
        "rigid",
        "--modes",
        "1",
        "--law",
        "newton",
        "--restitution",
        "0.5",
        "--zeta1",
        "0.01",
        "--omega",
        "0.1",
        "--gap",
        "0.01",
        "--periods",
        "20",
        "--record",
        "2",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let phases: Vec<f64> = v["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["phase"].as_f64().unwrap())
        .collect();
    assert!(
        phases.iter().all(|p| !(0.0..0.166).contains(p)),
        "{phases:?}"
    );
    assert_eq!(v["period_m"], 1);
    assert_eq!(v["impacts_n"].as_u64().unwrap() * 2, phases.len() as u64);
}

#[test]
fn item_5_a_rigid_stop_below_the_rest_position_is_refused_from_rest() {
    let (code, _, err) = cantilever(&[
        "simulate",
        "--model",
        "rigid",
        "--modes",
        "3",
        "--gap=-0.5",
        "--zeta1",
        "0.01",
        "--omega",
        "1",
        "--periods",
        "0",
        "--record",
        "4",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.starts_with("error: invalid --gap (d₀): got -0.5; allowed: a number ≥ 0 for the rigid model from rest"), "{err}");
    // the library refuses a start beyond the stop whatever the gap
    let model = sticking_oscillator(1);
    assert!(model.run(&DVector::from_vec(vec![0.1, 0.0]), 1.0).is_err());
}

#[test]
fn item_6_the_rigid_model_writes_its_dense_trajectory() {
    let path = std::env::temp_dir().join(format!("rigid-dense-{}.csv", std::process::id()));
    let (code, _, err) = cantilever(&[
        "simulate",
        "--model",
        "rigid",
        "--modes",
        "1",
        "--law",
        "newton",
        "--restitution",
        "0.5",
        "--zeta1",
        "0.01",
        "--omega",
        "0.1",
        "--gap",
        "0.01",
        "--periods",
        "20",
        "--record",
        "2",
        "--dense-per-period",
        "200",
        "--dense",
        path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(
        rows.len(),
        2 * 200,
        "a row per sample from the window's start, its end excluded (as the compliant model's)"
    );
    // the tip never beyond the stop, and resting on it for the sticking phase: from the
    // accumulation near phase 0.87 to the release at 1/6, about 0.3 of each period
    let stuck = rows
        .iter()
        .filter(|r| r.split(',').nth(1) == Some("1"))
        .count();
    assert!((100..140).contains(&stuck), "{stuck} samples on the stop");
    for r in &rows {
        let tip: f64 = r.split(',').nth(2).unwrap().parse().unwrap();
        assert!(tip <= 0.01 * (1.0 + 1e-12), "{r}");
    }
    let _ = std::fs::remove_file(path);
}

/// A state file in this run's scratch folder (removed by a later run once this one is gone).
fn state_file(name: &str, state: &str) -> String {
    let path = cli::scratch(&format!("state-{name}")).join("state.json");
    std::fs::write(&path, state).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn item_2_tiny_scales_are_refused_with_the_way_out() {
    let base = [
        "simulate",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1",
        "--record",
        "1",
    ];
    for extra in [
        vec!["--forcing", "1e-160"],
        vec![
            "--forcing",
            "0",
            "--initial-state",
            &state_file("tiny", "[1e-200,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]"),
        ],
    ] {
        let args: Vec<&str> = base.iter().copied().chain(extra.iter().copied()).collect();
        let (code, _, err) = cantilever(&args);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert!(
            err.contains("scale the forcing, the state and the gap together"),
            "{err}"
        );
    }
    // … and the orbit command the same
    let (code, _, err) = cantilever(&[
        "orbit",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1",
        "--period",
        "1",
        "--forcing",
        "1e-160",
    ]);
    assert_eq!(code, 2, "{err}");
    // 1e-100 still runs, exactly as fast as the unit problem
    let (code, _, err) = cantilever(&[&base[..], &["--forcing", "1e-100"]].concat());
    assert_eq!(code, 0, "{err}");
}

#[test]
fn item_8_a_huge_initial_state_is_refused_not_run_to_nan() {
    let big = state_file("huge", "[1e200, 0, 0, 0, 0, 0]");
    let (code, out, err) = cantilever(&[
        "simulate",
        "--modes",
        "3",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1",
        "--initial-state",
        &big,
        "--json",
    ]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(err.contains("at most 1e6"), "{err}");
    // the library refuses what would overflow its energies
    let sim = Simulator::new(
        impacting_cantilever::model::problems::figure4(3)
            .model()
            .unwrap(),
    )
    .unwrap();
    let x = DVector::from_vec(vec![1e200, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert!(sim.run(&x, 1, &mut ()).is_err());
}

/// The Figure 4 forcing (ζ₁ = 0.01, ω = 2(β₁⁻)², d₀ = 0) with `modes` modes and a stop of
/// `k` k₁, from rest: the tip starts on the stop and is pushed into it.
fn stiff_stop(modes: usize, k: f64) -> Simulator {
    let forced = Forced {
        modes,
        k_over_k1: k,
        zeta1: 0.01,
        omega_over_w1: 2.0,
        gap: 0.0,
        printed_eq37_amplitude: false,
    };
    Simulator::new(forced.model().unwrap()).unwrap()
}

#[test]
fn item_1_a_stiff_stop_costs_bounded_work_or_is_refused_with_the_reason() {
    // N = 20 at 1e12 k₁ from rest: a release from the stop that leaves it tangentially
    // took 8e7 switching-function evaluations (h_min steps through the round-off band) for
    // one period; the band now allows steps that keep g below its uncertainty. Work counts,
    // not times, so the bound is the same on any machine.
    let sim = stiff_stop(20, 1e12);
    let end = sim.run(&DVector::zeros(40), 1, &mut ()).unwrap();
    assert!(end.stats.evaluations < 100_000, "{:?}", end.stats);
    // With a gap, the tip bounces, settles on the stop and leaves it so slowly that g
    // sat inside its round-off band for ~1e-5 time units at ġ ~ 1e-12: 4e7 h_min steps
    // in one contact segment (a minute per period at N = 20, 1e12 k₁). Where g is proven
    // increasing (or convex after being certainly negative) one evaluation decides a
    // whole interval now.
    for (modes, k, gap) in [(20, 1e12, 0.003), (15, 1e12, 0.006), (10, 1e11, 0.006)] {
        let forced = Forced {
            modes,
            k_over_k1: k,
            zeta1: 0.01,
            omega_over_w1: 2.0,
            gap,
            printed_eq37_amplitude: false,
        };
        let sim = Simulator::new(forced.model().unwrap()).unwrap();
        let end = sim.run(&DVector::zeros(2 * modes), 1, &mut ()).unwrap();
        assert!(
            end.stats.steps < 1_000_000,
            "N = {modes}, k = {k:e}, d₀ = {gap}: {:?}",
            end.stats
        );
    }
    // N = 1 at 1e10 k₁: the tip chatters on the stop with free flights of ~1e-8 whose dip
    // is below round-off; every entry must still move into the stop (this broke when the
    // bracket of such a flight started at a noisy "negative" point on its falling side)
    let sim = stiff_stop(1, 1e10);
    let end = sim.run(&DVector::zeros(2), 2, &mut ()).unwrap();
    assert!(
        end.stats.segments > 1000,
        "it does chatter: {:?}",
        end.stats
    );
    // N = 1 at 1e12 k₁: micro-impacts at the contact frequency from the start (the
    // model's true behaviour: the Dormand–Prince reference counts 48 959 entries by
    // t = 0.114): refused in bounded work with the reason. (N = 10 was refused here until
    // the contact flow's particular solution and eigenpairs were computed from K⁺'s
    // structure: its chatter came from the flow's error; the reference leaves the stop at
    // t = 0.2635 and counts 7 220 entries in the second period, and so does it now.)
    let sim = stiff_stop(1, 1e12);
    let err = sim
        .run(&DVector::zeros(2), 2, &mut ())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("entries into contact") && err.contains("contact frequency"),
        "{err}"
    );
    let sim = stiff_stop(10, 1e12);
    assert!(sim.run(&DVector::zeros(20), 2, &mut ()).is_ok());
    // and the command line says so with exit 1 (legal input the method does not support)
    let (code, _, err) = cantilever(&[
        "simulate",
        "--modes",
        "1",
        "--stop-stiffness",
        "1e12",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1",
    ]);
    assert_eq!(code, 5, "{err}");
    assert!(
        err.starts_with("error: chatter: ") && err.contains("--model rigid"),
        "{err}"
    );
}

#[test]
fn item_13_a_gap_at_the_settled_free_maximum_grazes_and_goes_on() {
    // The free tip amplitude at ω = 2(β₁⁻)² in units of the resonant one: the settled
    // free orbit grazes the stop. A grazing contact is legal; the run goes on and labels
    // the orbit (it failed "entered contact with velocity -2.1e-11" in 9 of 15 runs,
    // for gaps within a few ulps of this one).
    let gap: f64 = 0.0066660741530747;
    for ulps in [-2i64, -1, 0, 1, 2] {
        let g = f64::from_bits((gap.to_bits() as i64 + ulps) as u64).to_string();
        let (code, out, err) = cantilever(&[
            "simulate",
            "--modes",
            "10",
            "--stop-stiffness",
            "100",
            "--zeta1",
            "0.01",
            "--omega",
            "2",
            "--periods",
            "2000",
            "--gap",
            &g,
            "--json",
        ]);
        assert_eq!(code, 0, "gap {g}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert!(v["outcome"].is_string(), "{out:.300}");
    }
}

#[test]
fn item_3_the_collocation_law_at_gap_zero_runs_in_bounded_work() {
    // 0.4 CPU-s per period before (impact velocities down to ~1e-9, the chatter never
    // judged as such); now each period's sequence ends in a bounded number of impacts
    let (code, out, err) = cantilever(&[
        "simulate",
        "--model",
        "rigid",
        "--law",
        "collocation",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "1",
        "--periods",
        "0",
        "--record",
        "200",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let mut per_cycle = std::collections::HashMap::new();
    for e in v["events"].as_array().unwrap() {
        *per_cycle.entry(e["cycle"].as_i64().unwrap()).or_insert(0) += 1;
    }
    assert!(per_cycle.values().all(|&n| n <= 64), "{per_cycle:?}");
}

#[test]
fn item_15_the_energy_imbalance_is_judged_against_its_round_off_bound() {
    let (code, out, err) = cantilever(&[
        "simulate",
        "--modes",
        "10",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "0",
        "--record",
        "20",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let (e, b) = (
        v["energy_imbalance"].as_f64().unwrap(),
        v["energy_imbalance_bound"].as_f64().unwrap(),
    );
    assert!(
        e <= b && b > 0.0 && v["energy_imbalance_within_bound"] == true,
        "{e} {b}"
    );
}

/// N = 400 (800 × 800 eigenproblems: the published tier, `--all-features`, runs it): the
/// imbalance was 7e-8, 7
/// times κε√segments, flagged ABOVE, from the contact flow's particular solution and
/// eigenpairs (dense solves of a matrix of norm ~kN); with them computed from K⁺'s
/// structure it is ~1e-13 and within its bound.
#[cfg_attr(
    not(feature = "published"),
    ignore = "heavy: the README's test command runs it"
)]
#[test]
fn item_15_the_n400_imbalance_is_within_its_bound() {
    let (code, out, err) = cantilever(&[
        "simulate",
        "--modes",
        "400",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "0",
        "--record",
        "20",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let e = v["energy_imbalance"].as_f64().unwrap();
    assert!(
        e < 1e-11 && v["energy_imbalance_within_bound"] == true,
        "{e}"
    );
}

/// Issue 36 item 7: at 1e12k₁ one orbit (settled to 1e-14) has 4244 or 4245 entries in
/// alternate periods; `simulate` said (1, 4245) and `orbit` (1, 4244) (or the reverse,
/// depending on the transient). Both now give the range over several periods and say that
/// round-off decides the count. (4000 events per period: the published tier runs it.)
#[cfg_attr(
    not(feature = "published"),
    ignore = "heavy: the README's test command runs it"
)]
#[test]
fn item_7_a_count_round_off_decides_is_a_range_in_simulate_and_orbit() {
    let model = [
        "--modes",
        "10",
        "--stop-stiffness",
        "1e12",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
    ];
    let run = |extra: &[&str]| {
        let args: Vec<&str> = extra.iter().chain(model.iter()).copied().collect();
        let (code, out, err) = cantilever(&args);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let sim = run(&[
        "simulate",
        "--periods",
        "100",
        "--record",
        "6",
        "--no-energy",
        "--json",
    ]);
    let orbit = run(&["orbit", "--periods", "20", "--json"]);
    assert_eq!(sim["period_m"], 1);
    for (what, range) in [
        ("simulate", &sim["impacts_n_range"]),
        ("orbit", &orbit["impacts_n_range"]),
    ] {
        assert_eq!(range, &serde_json::json!([4244, 4245]), "{what}");
    }
    let (_, text, _) = cantilever(
        &["orbit", "--periods", "20"]
            .iter()
            .chain(model.iter())
            .copied()
            .collect::<Vec<_>>(),
    );
    assert!(text.starts_with("(1, 4244–4245) orbit"), "{text}");
    assert!(text.contains("round-off decides"), "{text}");
}
