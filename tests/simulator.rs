//! Code verification of the exact simulator and of the independent reference integrator:
//! closed forms, certified contact detection, energy balance, cross-verification.

use impacting_cantilever::engine::dopri5::{self as reference, Tolerances};
use impacting_cantilever::engine::sim::{Dense, Energy, Events, Simulator, Strobe, TipMax};
use impacting_cantilever::model::galerkin::{self, Forcing, GalerkinModel, GalerkinParams, Region};
use impacting_cantilever::model::problems::{self, linear_response as oscillator};
use nalgebra::DVector;
use std::f64::consts::PI;

use crate::common::augmented;

fn k1() -> f64 {
    galerkin::first_modal_stiffness()
}
fn w1() -> f64 {
    galerkin::first_frequency()
}

/// The Figure 4 model (k = 100 k₁, ζ₁ = 0.01, d₀ = 0, ω = 2(β₁⁻)²) with N modes.
fn fig4(n: usize) -> GalerkinModel {
    problems::figure4(n).model().unwrap()
}

/// The linear model: the stop out of reach, so the flow never switches.
fn out_of_reach(n: usize, zeta1: f64, omega_over_w1: f64) -> GalerkinModel {
    problems::out_of_reach(n, zeta1, omega_over_w1)
        .model()
        .unwrap()
}

#[test]
fn reference_integrator_matches_the_closed_form_forced_oscillator() {
    // One mode, stop far away (gap 1e6): ẍ + C₁₁ẋ + k₁x = f₁ cos ωt.
    let m = out_of_reach(1, 0.05, 1.3);
    let x0 = DVector::from_vec(vec![0.2, -0.4]);
    let t = 10.0;
    let (xe, ve) = oscillator(
        k1(),
        m.damping()[0],
        m.forcing_amplitude()[0],
        1.3 * w1(),
        0.2,
        -0.4,
        t,
    );
    let mut errors = Vec::new();
    for rtol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let r = reference::integrate(
            &m,
            &x0,
            t,
            Tolerances {
                rtol,
                atol: rtol * 1e-2,
            },
        )
        .unwrap();
        let err = (r.state[0] - xe).abs().max((r.state[1] - ve).abs() / w1());
        errors.push(err);
    }
    // the error follows the tolerance (a 5th-order method under step control) and reaches
    // 1e-10 at rtol = 1e-12 (global error ~ a few × 10 steps' worth of local error)
    assert!(errors[3] < 1e-10, "{errors:?}");
    for w in errors.windows(2) {
        assert!(
            w[1] < w[0] * 0.2,
            "error does not fall with rtol: {errors:?}"
        );
    }
}

#[test]
fn exact_simulator_matches_the_closed_form_forced_oscillator() {
    let m = out_of_reach(1, 0.05, 1.3);
    let sim = Simulator::new(m.clone()).unwrap();
    let x0 = DVector::from_vec(vec![0.2, -0.4]);
    let x = sim.run(&x0, 7, &mut ()).unwrap().state;
    let t = 7.0 * sim.period();
    let (xe, ve) = oscillator(
        k1(),
        m.damping()[0],
        m.forcing_amplitude()[0],
        1.3 * w1(),
        0.2,
        -0.4,
        t,
    );
    // exact method: round-off only (measured ~1e-15)
    assert!((x[0] - xe).abs() < 1e-13 && (x[1] - ve).abs() < 1e-13 * w1());
}

#[test]
fn contact_passage_times_match_the_closed_form() {
    // Undamped, unforced single mode from the surface with upward velocity: contact lasts
    // π/√(k₁ + k), free flight π/√k₁, alternately.
    let k = 100.0 * k1();
    let m = GalerkinModel::new(GalerkinParams::new(1, k)).unwrap();
    let sim = Simulator::new(m.clone()).unwrap();
    let x0 = DVector::from_vec(vec![0.0, 1.0]);
    let mut trace = Events::default();
    sim.run(&x0, 3, &mut trace).unwrap();
    let (tp, tm) = (PI / (k1() + k).sqrt(), PI / k1().sqrt());
    let mut expected = 0.0;
    assert!(trace.events.len() >= 4);
    for (i, e) in trace.events.iter().enumerate() {
        expected += if i % 2 == 0 { tp } else { tm };
        assert_eq!(e.entering, i % 2 == 1);
        // the 1e-12 relative in time
        assert!(
            (e.time - expected).abs() < 1e-12 * expected,
            "event {i}: {} vs {expected}",
            e.time
        );
    }
    let r = reference::integrate(
        &m,
        &x0,
        3.0,
        Tolerances {
            rtol: 1e-12,
            atol: 1e-14,
        },
    )
    .unwrap();
    assert_eq!(r.events.len(), trace.events.len());
    for (a, b) in r.events.iter().zip(&trace.events) {
        // the reference's global error at rtol 1e-12 over ~30 passages
        assert!((a.time - b.time).abs() < 1e-9);
    }
}

#[test]
fn energy_balance_over_1000_periods() {
    // the issue: imbalance ≤ 1e-9 for N = 10 at k = 100 k₁ and for N = 40 at k = 1e5 k₁
    let sim = Simulator::new(fig4(10)).unwrap();
    let mut t = Energy::default();
    sim.run(&DVector::zeros(20), 1000, &mut t).unwrap();
    let e = t.budget;
    assert!(e.dissipated > 0.0 && e.work > 0.0);
    assert!(
        e.relative_imbalance() < 1e-9,
        "N=10: {:e}",
        e.relative_imbalance()
    );

    let stiff = GalerkinModel::new(
        GalerkinParams::new(40, 1e5 * k1())
            .with_zeta1(0.01)
            .with_forcing(Forcing::paper(2.0 * w1())),
    )
    .unwrap();
    let sim = Simulator::new(stiff).unwrap();
    let mut t = Energy::default();
    sim.run(&DVector::zeros(80), 1000, &mut t).unwrap();
    let e = t.budget;
    assert!(
        e.relative_imbalance() < 1e-9,
        "N=40: {:e}",
        e.relative_imbalance()
    );
}

#[test]
fn extreme_cases_balance_energy_to_the_eigenvector_conditioning() {
    // Many modes, a huge stop stiffness, both at once, tiny and heavy damping (the high
    // modes then over-damped), a gap: from rest under the paper's forcing.
    for (n, k_over_k1, zeta1, gap, periods) in [
        (100, 1e3, 0.01, 0.0, 50),
        (20, 1e8, 0.01, 0.0, 50),
        (100, 1e8, 0.01, 0.0, 20),
        (10, 100.0, 1e-5, 0.0, 50),
        (10, 100.0, 0.9, -0.3, 50),
        (10, 100.0, 0.9, 0.3, 50),
    ] {
        let model = GalerkinModel::new(
            GalerkinParams::new(n, k_over_k1 * k1())
                .with_zeta1(zeta1)
                .with_gap(gap)
                .with_forcing(Forcing::paper(2.0 * w1())),
        )
        .unwrap();
        let sim = Simulator::new(model).unwrap();
        let (mut t, mut energy) = (Events::default(), Energy::default());
        let x = sim
            .run(&DVector::zeros(2 * n), periods, &mut (&mut t, &mut energy))
            .unwrap()
            .state;
        let case = format!("N={n} k={k_over_k1:e}k1 zeta1={zeta1} d0={gap}");
        assert!(x.iter().all(|v| v.is_finite()), "{case}");
        assert!(!t.events.is_empty(), "{case}: the stop is reached");
        // contact and free flight alternate (no grazing touch in these runs; from rest at
        // d₀ = 0 the run starts in contact, so the first event may be an exit)
        assert!(t.events.iter().all(|e| !e.grazing), "{case}");
        for (i, pair) in t.events.windows(2).enumerate() {
            assert_ne!(pair[0].entering, pair[1].entering, "{case}: event {i}");
        }
        // Projecting onto an eigenbasis of condition κ loses κε relative per segment, and
        // the imbalance sums those losses over the run's energy flow: allow 10κε. Measured
        // 1.5e-9 at N = 100, 1e8 k₁ (κ = 7e6, κε = 1.6e-9); ≤ 1.3e-10 elsewhere.
        let kappa = sim.condition();
        let imbalance = energy.budget.relative_imbalance();
        assert!(
            imbalance < 10.0 * kappa * f64::EPSILON,
            "{case}: imbalance {imbalance:e}, κ = {kappa:e}"
        );
    }
}

#[test]
fn cross_verification_with_the_reference_integrator_on_figure_4() {
    // The issue: N = 1, 2, 3, 10, 50 periods from rest, the same event sequence, event
    // times agreeing to 1e-8.
    for n in [1, 2, 3, 10] {
        let m = fig4(n);
        let sim = Simulator::new(m.clone()).unwrap();
        let x0 = DVector::zeros(2 * n);
        let mut trace = Events::default();
        let x = sim.run(&x0, 50, &mut trace).unwrap().state;
        let t_end = 50.0 * sim.period();
        let r = reference::integrate(
            &m,
            &x0,
            t_end,
            Tolerances {
                rtol: 1e-13,
                atol: 1e-16,
            },
        )
        .unwrap();
        assert_eq!(r.events.len(), trace.events.len(), "N={n}: event counts");
        let mut worst: f64 = 0.0;
        for (a, b) in r.events.iter().zip(&trace.events) {
            assert_eq!(a.entering, b.entering, "N={n}: direction");
            worst = worst.max((a.time - b.time).abs());
        }
        assert!(worst < 1e-8, "N={n}: worst event-time difference {worst:e}");
        // End states: a time shift δt of a trajectory moves the state by ≈ |ẋ|δt; the
        // event times agree to `worst`, and between events both are accurate flows of a
        // damped system, so the states agree to a few |ẋ|·max(worst, DP5's step error).
        // |ẋ| from the model's right-hand side at the end (in the region of the last event).
        let region = if trace.events.last().is_some_and(|e| e.entering) {
            Region::Contact
        } else {
            Region::Free
        };
        let mut xdot = m.state_matrix(region) * &x;
        let force = m.force(t_end, region);
        for j in 0..n {
            xdot[n + j] += force[j];
        }
        let diff = (&r.state - &x).amax();
        let bound = 4.0 * xdot.amax() * worst.max(1e-13 * t_end);
        assert!(diff < bound, "N={n}: end state {diff:e} vs {bound:e}");
    }
}

/// Crossings a naive detector finds: sign changes of d − d₀ between equally spaced samples.
fn naive_crossings(samples: &[(f64, f64, f64, bool)], gap: f64) -> usize {
    samples
        .windows(2)
        .filter(|w| (w[0].1 - gap).signum() != (w[1].1 - gap).signum())
        .count()
}

#[test]
fn near_grazing_contacts_are_found_and_a_naive_sampler_misses_them() {
    // One undamped mode oscillating with tip amplitude A = 2a; the stop sits 1e-10·A below
    // the crest, so each crest makes a contact of duration ≈ 2√(2e-10)/ω₁.
    let a = 0.5;
    for depth in [1e-6, 1e-8, 1e-10] {
        let gap = 2.0 * a * (1.0 - depth);
        let m = GalerkinModel::new(GalerkinParams::new(1, 100.0 * k1()).with_gap(gap)).unwrap();
        let sim = Simulator::new(m).unwrap();
        let x0 = DVector::from_vec(vec![0.0, a * w1()]);
        let (mut trace, mut dense) = (Events::default(), Dense::new(1000));
        // unforced: one "period" is one time unit; ω₁ ≈ 3.5, so 3 units hold ≥ 1 crest
        sim.run(&x0, 3, &mut (&mut trace, &mut dense)).unwrap();
        // crests at t = (π/2 + 2πj)/ω₁ < 3
        let crests = ((3.0 * w1() - PI / 2.0) / (2.0 * PI)).floor() as usize + 1;
        assert_eq!(
            trace.events.len(),
            2 * crests,
            "depth {depth}: enter and leave per crest"
        );
        assert!(trace.events.iter().all(|e| !e.grazing));
        if depth <= 1e-8 {
            assert_eq!(
                naive_crossings(&dense.samples, gap),
                0,
                "the naive sampler misses them"
            );
        }
    }
}

#[test]
fn double_crossings_inside_one_fast_period_are_found() {
    // Mode 1 at its crest (tip 0.9988) plus a mode-5 ripple (tip ±0.004, ω₅ ≈ 57 ω₁)
    // starting in its trough: the tip rises above the stop at d₀ = 1 for a fraction of
    // one mode-5 period and falls back. Sampling 20 times per unit time misses it.
    let m = GalerkinModel::new(GalerkinParams::new(5, 1000.0 * k1()).with_gap(1.0)).unwrap();
    let sim = Simulator::new(m.clone()).unwrap();
    let w5 = m.beta()[4].powi(2);
    let mut x0 = DVector::zeros(10);
    x0[0] = 0.4994;
    x0[4] = -0.002;
    let (mut trace, mut dense) = (Events::default(), Dense::new(20));
    sim.run(&x0, 1, &mut (&mut trace, &mut dense)).unwrap();
    assert!(
        trace.events.len() >= 2,
        "found {} events",
        trace.events.len()
    );
    let first_two = &trace.events[..2];
    assert!(first_two[0].entering && !first_two[1].entering);
    assert!(
        first_two[1].time < 2.0 * PI / w5,
        "both inside the first mode-5 period"
    );
    assert_eq!(
        naive_crossings(&dense.samples[..3], 1.0),
        0,
        "the naive sampler misses them"
    );
    // the reference integrator, at tight tolerance, agrees on those times
    let r = reference::integrate(
        &m,
        &x0,
        first_two[1].time + 1e-3,
        Tolerances {
            rtol: 1e-12,
            atol: 1e-15,
        },
    )
    .unwrap();
    assert!(r.events.len() >= 2);
    for (a, b) in r.events.iter().zip(first_two) {
        assert!((a.time - b.time).abs() < 1e-9, "{} vs {}", a.time, b.time);
    }
}

#[test]
fn certified_maximum_of_the_linear_response_is_its_amplitude() {
    // Started on the particular solution with the stop out of reach, d(t) = Re(P e^{iωt})
    // + d_s exactly, so max d = |P| + d_s (here d_s = 0).
    for n in [1, 3, 10] {
        let sim = Simulator::new(out_of_reach(n, 0.01, 0.7)).unwrap();
        let free = sim.flow(Region::Free);
        let x0 = free.particular(0.0);
        let mut t = TipMax::default();
        sim.run(&x0, 3, &mut t).unwrap();
        let m = t.maximum.unwrap();
        let amplitude = free.tip_forced().norm();
        // the certificate's slack (64ε of the signal scale) plus round-off of d itself
        assert!(
            (m.value - amplitude).abs() <= m.tolerance + 1e-14 * amplitude,
            "N={n}: {} vs {amplitude}",
            m.value
        );
        // attained where the phase of P e^{iωt} is a multiple of 2π; near the top
        // d = |P|(1 − θ²/2), so a value exact to ~1e-16 fixes θ only to ~1e-8: 1e-6 is that
        // resolution with margin
        let phase = free.tip_forced().arg() + free.omega() * m.time;
        let off = (phase / (2.0 * PI)).round() * 2.0 * PI - phase;
        assert!(off.abs() < 1e-6, "N={n}: phase off by {off:e}");
    }
}

#[test]
fn certified_maximum_bounds_a_fine_sampling_on_impacting_orbits() {
    // On settled Figure 4 orbits (contacts, a stiff stop mode, N up to 20 at 1000k₁) no
    // sample of d at 20 000 points per period may exceed the certified maximum by more
    // than its slack, and the samples' maximum must approach it within the sampling error
    // max|d̈|·Δt²/8 (max|d̈| estimated from the samples' second differences, ×4 for safety).
    for (n, k_over_k1) in [(1, 100.0), (3, 100.0), (10, 100.0), (20, 1000.0)] {
        let model = GalerkinModel::new(
            GalerkinParams::new(n, k_over_k1 * k1())
                .with_zeta1(0.01)
                .with_forcing(Forcing::paper(2.0 * w1())),
        )
        .unwrap();
        let sim = Simulator::new(model).unwrap();
        let x = sim.run(&DVector::zeros(2 * n), 100, &mut ()).unwrap().state;
        let start = sim.clock_at_cycle(100);
        let mut t = TipMax::default();
        sim.run_from(&x, start, 4, &mut t).unwrap();
        let m = t.maximum.unwrap();
        let per_period = 20_000;
        let mut dense = Dense::new(per_period);
        sim.run_from(&x, start, 4, &mut dense).unwrap();
        let d: Vec<f64> = dense.samples.iter().map(|p| p.1).collect();
        let best = d.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let dt = sim.period() / per_period as f64;
        let curvature = d
            .windows(3)
            .map(|w| (w[0] - 2.0 * w[1] + w[2]).abs() / (dt * dt))
            .fold(0.0, f64::max);
        let case = format!("N={n} k={k_over_k1}k1");
        assert!(
            best <= m.value + m.tolerance,
            "{case}: sample {best} above {}",
            m.value
        );
        assert!(
            m.value - best <= 4.0 * curvature * dt * dt / 8.0,
            "{case}: certified {} vs sampled {best}",
            m.value
        );
        assert!(m.time >= start.time() && m.time <= start.time() + 4.0 * sim.period());
    }
}

/// An independent reference for stiff cases, where the explicit DP5 integrator is too slow:
/// exact matrix exponentials of the augmented region systems on a fixed grid (no
/// eigenvectors, no bounds), each sign change of the gap refined by bisection. It misses
/// contacts shorter than `dt`, so a too-coarse grid shows as a different event sequence.
fn expm_grid_events(m: &GalerkinModel, x0: &DVector<f64>, t_end: f64, dt: f64) -> Vec<(f64, bool)> {
    let n = m.modes();
    let systems = [augmented(m, Region::Free), augmented(m, Region::Contact)];
    let steps = [(&systems[0] * dt).exp(), (&systems[1] * dt).exp()];
    let index = |r: Region| usize::from(r == Region::Contact);
    let gap = |z: &DVector<f64>| m.tip().dot(&z.rows(0, n)) - m.params().gap;
    let left = |r: Region, z: &DVector<f64>| match r {
        Region::Free => gap(z) >= 0.0,
        Region::Contact => gap(z) < 0.0,
    };
    let mut z = DVector::zeros(2 * n + 3);
    z.rows_mut(0, 2 * n).copy_from(x0);
    z[2 * n] = 1.0;
    z[2 * n + 2] = 1.0;
    let mut region = m.starting_region(x0, 0.0).unwrap();
    let (mut t, mut events) = (0.0, Vec::new());
    while t < t_end {
        let h = dt.min(t_end - t);
        let next = if h == dt {
            &steps[index(region)] * &z
        } else {
            (&systems[index(region)] * h).exp() * &z
        };
        if !left(region, &next) {
            z = next;
            t += h;
            continue;
        }
        let (mut lo, mut hi) = (0.0, h);
        // bisection to the last bit of τ (60 halvings of dt ≤ 5e-6 reach 4e-24)
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if left(region, &((&systems[index(region)] * mid).exp() * &z)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        z = (&systems[index(region)] * hi).exp() * &z;
        t += hi;
        events.push((t, region == Region::Free));
        region = match region {
            Region::Free => Region::Contact,
            Region::Contact => Region::Free,
        };
    }
    events
}

#[test]
#[cfg_attr(
    not(feature = "published"),
    ignore = "heavy: the README's test command runs it"
)]
fn stiff_cases_agree_with_an_exponential_grid_reference() {
    // N = 20 at 1e6 k₁ and at 1e8 k₁ (stop mode periods 5e-4 and 4e-5, events as close as
    // 1e-5 apart), 5 periods from rest: the same event sequence (33 and 73 events), event
    // times within 1e-8, the cross-verification tolerance. Measured 7e-11 and 4e-10:
    // the grid's own round-off over 0.9e6 and 4.5e6 steps (it grows when dt is halved).
    for (k_over_k1, periods, dt) in [(1e6, 5.0, 5e-6), (1e8, 5.0, 1e-6)] {
        let model = GalerkinModel::new(
            GalerkinParams::new(20, k_over_k1 * k1())
                .with_zeta1(0.01)
                .with_forcing(Forcing::paper(2.0 * w1())),
        )
        .unwrap();
        let sim = Simulator::new(model.clone()).unwrap();
        let x0 = DVector::zeros(40);
        let mut trace = Events::default();
        sim.run(&x0, periods as u64, &mut trace).unwrap();
        let reference = expm_grid_events(&model, &x0, periods * sim.period(), dt);
        let ours: Vec<(f64, bool)> = trace.events.iter().map(|e| (e.time, e.entering)).collect();
        assert_eq!(ours.len(), reference.len(), "k={k_over_k1:e}k1");
        let mut worst: f64 = 0.0;
        for (a, b) in ours.iter().zip(&reference) {
            assert_eq!(a.1, b.1, "k={k_over_k1:e}k1: directions");
            worst = worst.max((a.0 - b.0).abs());
        }
        assert!(
            worst < 1e-8,
            "k={k_over_k1:e}k1: event times differ by {worst:e}"
        );
    }
}

#[test]
fn observers_record_only_what_they_are_for_and_change_nothing() {
    // events alone: no states unless asked for
    let sim = Simulator::new(fig4(3)).unwrap();
    let mut events = Events::default();
    let plain = sim.run(&DVector::zeros(6), 20, &mut events).unwrap();
    assert!(!events.events.is_empty() && events.events.iter().all(|e| e.state.is_none()));
    let (mut with_states, mut strobe) = (Events::with_states(), Strobe::default());
    let mut dense = Dense::new(7);
    let strobed = sim
        .run(
            &DVector::zeros(6),
            20,
            &mut (&mut with_states, &mut strobe, &mut dense),
        )
        .unwrap();
    assert!(with_states.events.iter().all(|e| e.state.is_some()));
    // one sample at the start and one per period; seven per period on the grid
    assert_eq!(strobe.samples.len(), 21);
    assert_eq!(dense.samples.len(), 20 * 7);
    // observing changes nothing: the same segments, the same switches and the same final
    // state, bit for bit (the strobe's states are taken inside segments, not by ending
    // them at period boundaries)
    assert_eq!(strobed.stats.segments, plain.stats.segments);
    assert_eq!(strobed.state, plain.state);
    for (a, b) in events.events.iter().zip(&with_states.events) {
        assert_eq!((a.time, a.tip_velocity), (b.time, b.tip_velocity));
    }
    // and the strobe's last sample is the final state to round-off (it is the exact flow
    // evaluated at the boundary inside the last segment, or that segment's end)
    let last = &strobe.samples.last().unwrap().1;
    assert!((last - &plain.state).amax() <= 1e-13 * plain.state.amax());
}

#[test]
fn forcing_phase_stays_exact_over_long_runs() {
    // Linear (stop out of reach), damped: after 10⁴ periods the transient is e^{-300}
    // and the state at ωt = 0 mod 2π must be the particular solution x_p(0) to round-off.
    let m = out_of_reach(3, 0.01, 2.0);
    let sim = Simulator::new(m).unwrap();
    let x = sim.run(&DVector::zeros(6), 10_000, &mut ()).unwrap().state;
    let xp = sim.flow(Region::Free).particular(0.0);
    let err = (&x - &xp).amax() / xp.amax();
    assert!(err < 1e-12, "relative error {err:e}");
}

#[test]
fn chained_runs_equal_one_long_run() {
    let sim = Simulator::new(fig4(3)).unwrap();
    let x0 = DVector::zeros(6);
    let long = sim.run(&x0, 40, &mut ()).unwrap().state;
    let mut x = x0.clone();
    let mut clock = sim.clock_at_cycle(0);
    for _ in 0..40 {
        let next = sim.run_from(&x, clock, 1, &mut ()).unwrap();
        x = next.state;
        clock = next.clock;
    }
    // the same exact flow split at period boundaries: round-off only
    assert!((&x - &long).amax() < 1e-12 * long.amax());
    // and split at arbitrary times inside periods (run_until): round-off only
    let mut x = x0;
    let mut clock = sim.clock_at_cycle(0);
    for j in 1..=57 {
        let until = impacting_cantilever::engine::sim::Clock::at_time(
            sim.period(),
            j as f64 * 40.0 * sim.period() / 57.0,
        );
        let next = sim.run_until(&x, clock, until, &mut ()).unwrap();
        x = next.state;
        clock = next.clock;
    }
    assert_eq!(clock.cycles, 40);
    assert!((&x - &long).amax() < 1e-11 * long.amax());
}

#[test]
fn a_start_at_rest_on_the_stop_begins_in_contact() {
    // §5.2's x⁺(0) = 0 with d₀ = 0: on the surface, at rest, the forcing (cos 0 = 1 > 0)
    // accelerates the tip into the stop, so the run starts in contact with no event at 0.
    let m = fig4(3);
    assert_eq!(
        m.starting_region(&DVector::zeros(6), 0.0).unwrap(),
        impacting_cantilever::model::galerkin::Region::Contact
    );
    // half a period later the forcing pulls outward: the same state starts in free flight
    let half = PI / (2.0 * w1());
    assert_eq!(
        m.starting_region(&DVector::zeros(6), half).unwrap(),
        impacting_cantilever::model::galerkin::Region::Free
    );
    let sim = Simulator::new(m).unwrap();
    let mut t = Events::default();
    sim.run(&DVector::zeros(6), 1, &mut t).unwrap();
    assert!(
        !t.events[0].entering && t.events[0].time > 0.01,
        "first event: leaving contact"
    );
}

#[test]
fn a_grazing_orbit_touches_the_stop_without_entering() {
    // One undamped mode released at rest with its tip exactly on the stop (d = d₀, ḋ = 0,
    // pulled away): free flight d(t) = d₀ cos ω₁t returns to touch the stop at every
    // period 2π/ω₁ with zero velocity. Each touch is a grazing event — recorded, no switch
    // into contact — at the exact crest time.
    let gap = 0.4;
    let m = GalerkinModel::new(GalerkinParams::new(1, 100.0 * k1()).with_gap(gap)).unwrap();
    let sim = Simulator::new(m).unwrap();
    let x0 = DVector::from_vec(vec![gap / 2.0, 0.0]);
    let mut trace = Events::default();
    // unforced: a "period" is one time unit; 5 units hold 2 crests (2π/ω₁ ≈ 1.79)
    sim.run(&x0, 5, &mut trace).unwrap();
    let crest = 2.0 * PI / w1();
    assert_eq!(trace.events.len(), 2, "{:?}", trace.events);
    for (j, e) in trace.events.iter().enumerate() {
        assert!(e.grazing && e.entering, "touch {j}: {e:?}");
        // located by a Newton step on ḋ from the certified search's last points: the
        // crest of d₀cos ω₁t is flat to second order, so ~1e-8 in time (√ε of the period)
        let expected = (j + 1) as f64 * crest;
        assert!(
            (e.time - expected).abs() < 1e-6,
            "touch {j} at {} vs {expected}",
            e.time
        );
    }
}

/// A tip at rest a hair from the stop (d₀ = 1e-30, 1e-46) is carried through the surface by
/// the forcing at zero velocity: a slow switch, not a touch. Kept in free flight, each new
/// segment found the same crossing a few ulps on (2.8e-24 per segment: days for 14 periods;
/// found by the Python package's property tests). The run now takes as long as at d₀ = 0
/// and gives its events and final state.
#[test]
fn a_start_a_hair_from_the_stop_is_a_slow_switch_not_a_stall() {
    let run = |gap: f64| {
        let p = GalerkinParams::new(1, 2.975 * k1())
            .with_zeta1(0.1814)
            .with_forcing(Forcing::paper(2.4929 * w1()))
            .with_gap(gap);
        let sim = Simulator::new(GalerkinModel::new(p).unwrap()).unwrap();
        let mut trace = Events::default();
        let end = sim.run(&DVector::zeros(2), 14, &mut trace).unwrap();
        (end, trace.events)
    };
    let (reference, events) = run(0.0);
    for gap in [1e-30, 2.3e-46] {
        let (end, e) = run(gap);
        assert!(
            end.stats.segments < 100,
            "d₀ = {gap}: {} segments",
            end.stats.segments
        );
        // the same events from the first release on (at d₀ = 0 the run starts in contact;
        // here it enters it, at a velocity of ~1e-9, within 1e-9 of the start)
        let from_release = |v: &[impacting_cantilever::engine::sim::Event]| {
            let first = v.iter().position(|e| !e.entering).unwrap_or(v.len());
            v[first..].iter().map(|e| e.time).collect::<Vec<_>>()
        };
        let (a, b) = (from_release(&e), from_release(&events));
        assert_eq!(a.len(), b.len(), "d₀ = {gap}");
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-12 * y.max(1.0), "d₀ = {gap}: {x} vs {y}");
        }
        // the gap moves the answer by about itself: round-off of the run
        let diff = (&end.state - &reference.state).amax();
        assert!(diff < 1e-12, "d₀ = {gap}: final states {diff:e} apart");
    }
}
