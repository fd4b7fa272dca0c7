//! Properties over random inputs, not only examples: the invariants a user relies on, each
//! tried on random valid model specifications (N, k up to 1e12k₁, ζ₁, ω, the gap, every
//! rigid law and r) and starts, and bad input on random invalid ones.
//!
//! - observing never perturbs: events, strobe and final state are the same bits with and
//!   without dense output and the energy budget (or the same error);
//! - a reported orbit re-simulates to its residual, at its least period;
//! - the exact energy budget closes within its round-off bound;
//! - the rigid tip never passes the stop beyond round-off;
//! - the tip's row of a run's Jacobian (what a grazing curve's Newton step uses) is the
//!   derivative of the tip at that time;
//! - the command line's JSON gives the library's numbers, bit for bit;
//! - bad input gives an error naming it, never a panic.
//!
//! Case counts are bounded in the fast tier (`cargo test`); `--features thorough` (on in the
//! README's test command and CI) tries eight times as many. A failing case is printed with
//! its inputs; proptest shrinks it first.

use crate::common::cli;

use impacting_cantilever::analysis::continuation::{TipAt, TipRowAt};
use impacting_cantilever::analysis::find_orbit::{find_orbit, OrbitOptions};
use impacting_cantilever::analysis::shooting::{LEAST_PERIOD, TOLERANCE};
use impacting_cantilever::analysis::simulate::{simulate, SimulateOptions};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::built::{BuiltModel, Variant};
use impacting_cantilever::engine::map::{relative_residual, PeriodMap};
use impacting_cantilever::engine::sim::{Dense, Energy, Events, Simulator, Strobe, TipMax};
use impacting_cantilever::error::Error;
use impacting_cantilever::model::problems::Forced;
use impacting_cantilever::model::spec::{
    Cantilever, DampingReading, ForcingSpec, GapUnit, Law, ModelSpec, Named, Start, Stop, Structure,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// Cases per property: bounded in the fast tier, eight times more with `thorough`. The
/// stream of cases is fixed (the same cases on every machine and run: a failure in CI is
/// a failure here); `PROPTEST_RNG_SEED=random` (or a number) explores others.
fn cases(fast: u32) -> ProptestConfig {
    let factor = if cfg!(feature = "thorough") { 8 } else { 1 };
    let seed = match std::env::var("PROPTEST_RNG_SEED").ok().as_deref() {
        Some("random") => RngSeed::Random,
        Some(s) => s.parse().map_or(RngSeed::Fixed(2013), RngSeed::Fixed),
        None => RngSeed::Fixed(2013),
    };
    ProptestConfig {
        cases: fast * factor,
        failure_persistence: None,
        rng_seed: seed,
        ..ProptestConfig::default()
    }
}

fn cantilever(modes: usize, gap: f64, zeta1: f64, omega: f64, stop: Stop) -> ModelSpec {
    ModelSpec {
        structure: Structure::Cantilever(Cantilever {
            modes,
            // in units of the free amplitude at ω, so that the stop is within reach at any ω
            gap,
            gap_unit: GapUnit::Free,
            zeta1,
            damping_reading: DampingReading::Fig9,
            viscous: 0.0,
            omega,
            forcing: ForcingSpec::Unit,
        }),
        stop,
    }
}

/// k/k₁ log-uniform over 1e-1 … 1e12, or 0.
fn stiffness() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 9 => (-1.0f64..=12.0).prop_map(|e| 10f64.powf(e))]
}

fn compliant() -> impl Strategy<Value = ModelSpec> {
    (
        1usize..=6,
        stiffness(),
        -0.5f64..1.5,
        1e-3f64..0.2,
        0.3f64..3.0,
    )
        .prop_map(|(n, k, gap, zeta1, omega)| {
            cantilever(n, gap, zeta1, omega, Stop::Compliant { stop_stiffness: k })
        })
}

fn law() -> impl Strategy<Value = Law> {
    prop_oneof![
        Just(Law::StiffnessLimit),
        Just(Law::ImpulseResponse),
        Just(Law::Collocation),
        Just(Law::Newton)
    ]
}

/// r uniform in [0, 1], with the plastic (0) and elastic (1) impacts as cases of their own.
fn restitution() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 1 => Just(1.0), 6 => 0.0f64..=1.0]
}

/// The gap in units of A_free(ω): at the rest position (0) as a case of its own.
fn rigid_gap() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 3 => 0.0f64..1.5]
}

fn rigid() -> impl Strategy<Value = ModelSpec> {
    (
        1usize..=5,
        law(),
        restitution(),
        rigid_gap(),
        1e-3f64..0.2,
        0.3f64..3.0,
    )
        .prop_map(|(n, law, r, gap, zeta1, omega)| {
            let n = if law == Law::Newton { 1 } else { n };
            cantilever(
                n,
                gap,
                zeta1,
                omega,
                Stop::Rigid {
                    law,
                    restitution: r,
                },
            )
        })
}

fn any_model() -> impl Strategy<Value = ModelSpec> {
    prop_oneof![compliant(), rigid()]
}

fn start() -> impl Strategy<Value = Option<u64>> {
    prop_oneof![Just(None), any::<u64>().prop_map(Some)]
}

/// The model and its start (a seed the rigid model refuses falls back to rest).
fn built(spec: &ModelSpec, seed: Option<u64>) -> (BuiltModel, nalgebra::DVector<f64>) {
    let model = BuiltModel::build(spec).expect("a valid specification builds");
    let x0 = match seed.map(|s| model.start(&Start::Seed(s))) {
        Some(Ok((x, _))) => x,
        _ => model.start(&Start::Rest).expect("rest is a start").0,
    };
    (model, x0)
}

proptest! {
    #![proptest_config(cases(24))]

    #[test]
    fn observing_never_perturbs(spec in any_model(), seed in start(), periods in 0u64..12, record in 1u64..6, per in 1usize..50) {
        let (model, x0) = built(&spec, seed);
        let run = |dense: Option<usize>, energy: bool| {
            let o = SimulateOptions { periods, record, dense_per_period: dense, energy, ..SimulateOptions::default() };
            simulate(&model, &x0, &o, &Silent).map_err(|e| e.to_string())
        };
        // the engine itself: a run's events and end are the same bits whatever observes it
        if let Variant::Compliant(sim) = model.variant() {
            let plain = sim.run(&x0, periods + record, &mut ()).map(|e| e.state);
            let mut events = Events::with_states();
            let mut all = (Strobe::default(), Dense::new(per), Energy::default(), TipMax::default());
            let observed = sim.run(&x0, periods + record, &mut (&mut events, &mut all)).map(|e| e.state);
            let mut alone = Events::default();
            let _ = sim.run(&x0, periods + record, &mut alone);
            prop_assert_eq!(plain.map_err(|e| e.to_string()), observed.map_err(|e| e.to_string()));
            let times = |e: &Events| e.events.iter().map(|e| (e.time, e.tip_velocity)).collect::<Vec<_>>();
            prop_assert_eq!(times(&alone), times(&events));
        }
        let plain = run(None, false);
        for observed in [run(Some(per), false), run(None, true), run(Some(per), true)] {
            match (&plain, &observed) {
                (Ok(a), Ok(b)) => {
                    prop_assert_eq!(&a.events, &b.events);
                    prop_assert_eq!(&a.final_state, &b.final_state);
                    prop_assert_eq!((a.period_m, a.periodicity_residual), (b.period_m, b.periodicity_residual));
                    prop_assert_eq!(a.ending, b.ending);
                }
                (Err(a), Err(b)) => prop_assert_eq!(a, b),
                (a, b) => prop_assert!(false, "one run failed, the other not: {:?} / {:?}", a.as_ref().err(), b.as_ref().err()),
            }
        }
    }

    #[test]
    fn the_energy_budget_closes_within_its_round_off_bound(spec in compliant(), seed in start(), periods in 0u64..30) {
        let (model, x0) = built(&spec, seed);
        let o = SimulateOptions { periods, record: 4, ..SimulateOptions::default() };
        match simulate(&model, &x0, &o, &Silent) {
            Ok(s) => {
                let (e, b) = (s.energy_imbalance.unwrap(), s.energy_imbalance_bound.unwrap());
                prop_assert!(e <= b, "imbalance {:e} above its bound {:e}", e, b);
            }
            // a stiff stop beyond the contact cap is refused with the reason: not a result
            Err(Error::Chatter(_)) => {}
            Err(e) => prop_assert!(false, "{}", e),
        }
    }

}

proptest! {
    #![proptest_config(cases(12))]

    #[test]
    fn a_reported_orbit_re_simulates_to_its_residual_at_its_least_period(spec in any_model(), seed in start()) {
        let (model, x0) = built(&spec, seed);
        let o = OrbitOptions { transient: 200, ..OrbitOptions::default() };
        let found = match find_orbit(&model, &x0, &o) {
            Ok(f) => f,
            // not every start settles, converges or flies clear: those are refused by kind
            Err(Error::NoPeriod(_) | Error::NotConverged { .. } | Error::Chatter(_) | Error::Unsupported(_)) => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        let m = found.period_m;
        let again = model.advance(&found.state, 0, m, false).unwrap().state;
        let residual = relative_residual(&again, &found.state);
        prop_assert!(residual <= TOLERANCE, "P^m(x) is {:e} from x (reported {:e})", residual, found.residual);
        for d in (1..m).filter(|d| m % d == 0) {
            let pd = model.advance(&found.state, 0, d, false).unwrap().state;
            prop_assert!(relative_residual(&pd, &found.state) > LEAST_PERIOD, "period {} is not least: {} repeats", m, d);
        }
    }

    #[test]
    fn bad_input_is_an_error_naming_it_never_a_panic(
        modes in prop_oneof![Just(0usize), 1usize..=8, Just(401usize)],
        k in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(-1.0), Just(1e13), 0.0f64..1e12],
        gap in prop_oneof![Just(f64::NAN), Just(2e6), -0.5f64..1.5],
        zeta1 in prop_oneof![Just(0.0), Just(-1.0), Just(f64::NAN), Just(1e4), 1e-3f64..0.5],
        omega in prop_oneof![Just(0.0), Just(1e-300), Just(f64::INFINITY), Just(2e4), 0.3f64..3.0],
        r in prop_oneof![Just(-0.1), Just(1.5), Just(f64::NAN), 0.0f64..=1.0],
        law in law(),
        rigid in any::<bool>(),
        periods in prop_oneof![Just(u64::MAX), 0u64..3],
        record in prop_oneof![Just(0u64), Just(1_000_000u64), 1u64..3],
    ) {
        let stop = if rigid { Stop::Rigid { law, restitution: r } } else { Stop::Compliant { stop_stiffness: k } };
        let spec = cantilever(modes, gap, zeta1, omega, stop);
        let outcome = std::panic::catch_unwind(|| {
            let model = BuiltModel::build(&spec)?;
            let (x0, _) = model.start(&Start::Rest)?;
            let o = SimulateOptions { periods, record, ..SimulateOptions::default() };
            simulate(&model, &x0, &o, &Silent).map(|_| ())
        });
        match outcome {
            Err(_) => prop_assert!(false, "panicked on {:?}", spec),
            // an error is one line naming what was wrong
            Ok(Err(e)) => prop_assert!(!e.to_string().contains('\n') && !e.to_string().is_empty()),
            Ok(Ok(())) => {}
        }
    }
}

proptest! {
    #![proptest_config(cases(4))]

    #[test]
    fn the_command_lines_json_is_the_librarys_numbers(spec in any_model(), seed in any::<u64>(), periods in 0u64..20) {
        let (model, _) = built(&spec, None);
        // the seed as the command line takes it; the rigid model may refuse it: rest then
        let start = match model.start(&Start::Seed(seed)) { Ok(_) => Some(seed), Err(_) => None };
        let x0 = model.start(&start.map_or(Start::Rest, Start::Seed)).unwrap().0;
        let o = SimulateOptions { periods, record: 4, ..SimulateOptions::default() };
        let library = simulate(&model, &x0, &o, &Silent);
        let Structure::Cantilever(c) = &spec.structure else { unreachable!() };
        let (modes, gap, zeta1, omega) = (c.modes.to_string(), c.gap.to_string(), c.zeta1.to_string(), c.omega.to_string());
        let periods_text = periods.to_string();
        let mut args = vec!["simulate", "--json", "--modes", &modes, "--gap", &gap, "--gap-unit", "free",
            "--zeta1", &zeta1, "--omega", &omega, "--periods", &periods_text, "--record", "4"];
        let (k, r, seed_text);
        match spec.stop {
            Stop::Compliant { stop_stiffness } => { k = stop_stiffness.to_string(); args.extend(["--stop-stiffness", &k]); }
            Stop::Rigid { law, restitution } => {
                r = restitution.to_string();
                args.extend(["--model", "rigid", "--law", law.name(), "--restitution", &r]);
            }
        }
        if let Some(s) = start { seed_text = s.to_string(); args.extend(["--seed", &seed_text]); }
        let (code, out, err) = cli::cantilever(&args);
        match library {
            Ok(s) => {
                prop_assert!(code == 0 || !s.ending.to_string().starts_with("completed"), "{}", err);
                let v: serde_json::Value = serde_json::from_str(&out).unwrap();
                let events: Vec<f64> = v["events"].as_array().unwrap().iter().map(|e| e["time"].as_f64().unwrap()).collect();
                let ours: Vec<f64> = s.events.iter().map(|e| e.time).collect();
                prop_assert_eq!(events, ours);
                prop_assert_eq!(v["final_time"].as_f64().unwrap(), s.final_clock.time());
                prop_assert_eq!(v["period_m"].as_u64(), s.period_m);
                prop_assert_eq!(v["energy_imbalance"].as_f64(), s.energy_imbalance);
                prop_assert_eq!(v["max_tip"].as_f64(), s.max_tip.map(|m| m.value));
            }
            Err(e) => {
                prop_assert_eq!(code as u8, e.exit_code(), "{}", err);
            }
        }
    }
}

proptest! {
    // rigid runs are cheap: more of them, so the plastic and elastic corner cases come up
    #![proptest_config(cases(96))]

    #[test]
    fn the_rigid_tip_never_passes_the_stop(spec in rigid(), seed in start(), periods in 0u64..20) {
        let (model, x0) = built(&spec, seed);
        let o = SimulateOptions { periods, record: 3, dense_per_period: Some(64), ..SimulateOptions::default() };
        let s = match simulate(&model, &x0, &o, &Silent) {
            Ok(s) => s,
            // a law without a sticking limit may stop at a chatter: said so, not a result
            Err(Error::Chatter(_)) => return Ok(()),
            // anything else (a flight through the stop is an `Invariant`) is a failure
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        let gap = model.galerkin().params().gap;
        let dense = s.dense.unwrap();
        let n = model.modes();
        for (i, tip) in dense.tip.iter().enumerate() {
            // round-off of the length scale, as the model's admission test judges it
            let eta = nalgebra::DVector::from_column_slice(&dense.states[2 * n * i..2 * n * i + n]);
            let scale = model.galerkin().length_scale(eta.rows(0, n));
            prop_assert!(tip - gap <= 1e-9 * scale, "tip {} beyond d₀ = {} at t = {} (in contact: {})", tip, gap, dense.t[i], dense.in_contact[i]);
        }
    }
}

proptest! {
    #![proptest_config(cases(16))]

    /// Over random compliant models (k/k₁ from 0.1 to 10⁴, the atlas's range: at stiffer
    /// stops a central difference no longer resolves the contact), starts and times within
    /// two periods: the row from the product of the segments' exponentials equals central
    /// differences of the tip at that time, to their own error.
    #[test]
    fn the_tip_row_is_the_derivative_of_the_tip_at_its_time(
        modes in 1usize..=6,
        k in (-1.0f64..=4.0).prop_map(|e| 10f64.powf(e)),
        gap in -0.5f64..1.5,
        zeta1 in 1e-3f64..0.2,
        omega in 0.3f64..3.0,
        start in proptest::collection::vec(-1.0f64..1.0, 12),
        at in 0.02f64..1.98,
    ) {
        let forced = Forced { modes, k_over_k1: k, zeta1, omega_over_w1: omega, gap, printed_eq37_amplitude: false };
        let sim = Simulator::new(forced.model().unwrap()).unwrap();
        let x0 = nalgebra::DVector::from_fn(2 * modes, |i, _| start[i]);
        let t = at * sim.period();
        let mut obs = TipRowAt::new(t);
        sim.run(&x0, 2, &mut obs).unwrap();
        let row = obs.finish().unwrap();
        let tip = |x: &nalgebra::DVector<f64>| {
            let mut obs = TipAt::new(&sim, t);
            sim.run(x, 2, &mut obs).unwrap();
            obs.finish().unwrap()
        };
        // a central difference errs by its truncation, c·h² where the flow is smooth (between
        // switches; C¹ across them) with c large at a stiff stop (2.8e-6 at h = 1e-5 at
        // k = 4e3k₁), and by its round-off: the tip carries an absolute error of a few ε times
        // the size m of the state and the stop, ~ε·m/h in the quotient. Richardson's
        // extrapolation of the differences at h and 2h removes the h² term; what is left is
        // bounded by 1e-6 of the row's largest entry plus 10³ε·m/h (2e-8·m at h = 1e-5)
        let h = 1e-5;
        let m = x0.amax().max(gap.abs()).max(tip(&x0).abs()).max(1.0);
        let tolerance = 1e-6 * row.amax() + 1e3 * f64::EPSILON * m / h;
        for j in 0..2 * modes {
            let central = |h: f64| {
                let mut e = nalgebra::DVector::zeros(2 * modes);
                e[j] = h;
                (tip(&(&x0 + &e)) - tip(&(&x0 - &e))) / (2.0 * h)
            };
            let fd = (4.0 * central(h) - central(2.0 * h)) / 3.0;
            prop_assert!((fd - row[j]).abs() <= tolerance, "column {}: {} against {} (tolerance {:e})", j, fd, row[j], tolerance);
        }
    }
}
