//! The rigid-impact N-mode model: 1-DOF closed forms, the chattering policy, and the
//! compliant model's convergence to it as k → ∞ (Nordmark).

use impacting_cantilever::engine::rigid::{Outcome, RigidEvent, RigidImpact};
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::model::galerkin::{self, GalerkinModel, GalerkinParams};
use impacting_cantilever::model::problems;
use impacting_cantilever::model::restitution::impulse_response;
use nalgebra::DVector;
use std::f64::consts::PI;

fn one_mode(gap: f64, r: f64) -> RigidImpact {
    let m = GalerkinModel::new(GalerkinParams::new(1, 0.0).with_gap(gap)).unwrap();
    RigidImpact::new(Simulator::new(m).unwrap(), impulse_response(1, r).unwrap()).unwrap()
}

fn impacts(run: &impacting_cantilever::engine::rigid::RigidRun) -> Vec<(f64, f64, f64)> {
    run.impacts()
}

#[test]
fn bouncing_single_mode_matches_the_closed_form() {
    // Undamped, unforced, d₀ = 0, r = 0.8, leaving the stop with tip velocity −2: every
    // flight lasts π/ω₁ whatever its amplitude, and each impact scales the speed by r.
    let w1 = galerkin::first_frequency();
    let model = one_mode(0.0, 0.8);
    let x0 = DVector::from_vec(vec![0.0, -1.0]);
    let run = model.run(&x0, 10.5 * PI / w1).unwrap();
    let hits = impacts(&run);
    assert_eq!(hits.len(), 10);
    for (i, (t, vin, vout)) in hits.iter().enumerate() {
        let n = (i + 1) as f64;
        // certified switching times: 1e-12 relative; velocities through the exact flow
        assert!((t - n * PI / w1).abs() < 1e-12 * t, "impact {i}: t = {t}");
        let expected = 2.0 * 0.8f64.powi(i as i32);
        assert!((vin - expected).abs() < 1e-12, "impact {i}: v = {vin}");
        assert!((vout + 0.8 * vin).abs() < 1e-14);
    }
    assert_eq!(run.outcome, Outcome::Completed);
}

#[test]
fn chattering_single_mode_sticks_at_the_accumulation_point() {
    // The stop sits below the rest position (d₀ = −0.1), so the spring pushes the tip into
    // it: impacts accumulate. Leaving with speed u, a flight lasts (2/ω₁)atan(u/(|d₀|ω₁));
    // speeds fall by r each impact, so t_∞ = Σ_n (2/ω₁)atan(rⁿu₀/(|d₀|ω₁)).
    let (gap, r, u0) = (-0.1, 0.5, 1.0);
    let w1 = galerkin::first_frequency();
    let model = one_mode(gap, r);
    // on the stop (tip = d₀), leaving with tip speed u₀
    let x0 = DVector::from_vec(vec![gap / 2.0, -u0 / 2.0]);
    let t_inf: f64 = (0..200)
        .map(|n| 2.0 / w1 * (r.powi(n) * u0 / (gap.abs() * w1)).atan())
        .sum();
    let run = model.run(&x0, 2.0 * t_inf + 1.0).unwrap();
    let stick = run
        .events
        .iter()
        .find_map(|e| match e {
            RigidEvent::StickStart { time } => Some(*time),
            _ => None,
        })
        .expect("chatter ends in sticking");
    // The geometric extrapolation of the tail, t_∞ = t_n + Δ_n ρ/(1 − ρ) with ρ = Δ_n/Δ_{n−1},
    // is exact to third order in the last speed (~1e-18 here). What remains is round-off
    // in each impact's timing: the tip signal is known to ~8ε of its scale |d₀|, so an
    // impact at speed v is timed to δt = 8ε|d₀|/v — 4e-10 at the last, slowest ones. The
    // extrapolation propagates it: δt_∞ ≤ δt_n + δΔ_n ρ/(1 − ρ) + Δ_n δρ/(1 − ρ)², with
    // δΔ_k ≤ δt_k + δt_{k−1} and δρ ≤ ρ(δΔ_n/Δ_n + δΔ_{n−1}/Δ_{n−1}).
    let hits = impacts(&run);
    let k = hits.len() - 1;
    let dt = |i: usize| 8.0 * f64::EPSILON * gap.abs() / hits[i].1.abs();
    let (d1, d2) = (hits[k].0 - hits[k - 1].0, hits[k - 1].0 - hits[k - 2].0);
    let (dd1, dd2) = (dt(k) + dt(k - 1), dt(k - 1) + dt(k - 2));
    let rho = d1 / d2;
    let drho = rho * (dd1 / d1 + dd2 / d2);
    let bound = dt(k) + dd1 * rho / (1.0 - rho) + d1 * drho / (1.0 - rho).powi(2);
    assert!(
        (stick - t_inf).abs() < 2.0 * bound,
        "stick at {stick}, t_inf {t_inf}, round-off bound {bound:e}"
    );
    assert!(impacts(&run).len() < 100, "finitely many impacts resolved");
    // unforced, the spring keeps pushing into the stop: held to the end, never released
    assert!(!run
        .events
        .iter()
        .any(|e| matches!(e, RigidEvent::StickEnd { .. })));
    assert!((run.state[0] - gap / 2.0).abs() < 1e-15 && run.state[1] == 0.0);
    assert_eq!(run.outcome, Outcome::Completed);
}

#[test]
fn compliant_single_mode_converges_to_the_rigid_impact_oscillator() {
    // Nordmark: the bilinear oscillator tends to the impact oscillator as k → ∞. N = 1 with
    // the Figure 4 damping and forcing but ω = 1.5(β₁⁻)², away from the impact-limit
    // resonance ω = 2(β₁⁻)² where the approach is much slower. The (1,1) orbit's impact
    // velocity approaches the rigid one (r = 1, the compliant contact's limit) like k^(−1/2),
    // the order of the contact duration π/√k.
    use impacting_cantilever::analysis::orbit::{self, OrbitKind};
    let case = |k_over_k1| problems::Forced {
        k_over_k1,
        omega_over_w1: 1.5,
        ..problems::figure4(1)
    };
    let sim = Simulator::new(case(1.0).model().unwrap()).unwrap();
    let rigid = RigidImpact::new(sim.clone(), impulse_response(1, 1.0).unwrap()).unwrap();
    let run = rigid
        .run(&DVector::zeros(2), 1040.0 * sim.period())
        .unwrap();
    let v_rigid = impacts(&run).last().unwrap().1;
    let ks = [1e4, 1e5, 1e6];
    let gaps: Vec<f64> = ks
        .iter()
        .map(|&k| {
            let s = Simulator::new(case(k).model().unwrap()).unwrap();
            let o = orbit::settle(&s, &DVector::zeros(2), 1000, 40, 0).unwrap();
            assert_eq!(o.kind, OrbitKind::Periodic { m: 1, n: 1 }, "k = {k:e} k₁");
            let v = o
                .events
                .iter()
                .rev()
                .find(|e| e.entering)
                .unwrap()
                .tip_velocity;
            (v - v_rigid).abs()
        })
        .collect();
    let lx: Vec<f64> = ks.iter().map(|k| k.ln()).collect();
    let ly: Vec<f64> = gaps.iter().map(|g| g.ln()).collect();
    let rate = impacting_cantilever::base::verification::fitted_slope(&lx, &ly);
    // measured −0.51 over these three decades
    assert!((rate + 0.5).abs() < 0.1, "rate {rate}, gaps {gaps:?}");
}

#[test]
fn multi_mode_chatter_under_a_law_that_moves_the_other_modes_stops_explicitly() {
    // N = 2, the stop below the rest position, the stiffness-limit law: each impact also
    // scales the velocity orthogonal to the tip direction (by 2r_e − 1), so an infinite
    // sequence has no constrained limit to stick in. The run stops at the extrapolated
    // accumulation time instead of looping (module doc).
    use impacting_cantilever::model::restitution::stiffness_limit;
    let gap = -0.1;
    let m = GalerkinModel::new(GalerkinParams::new(2, 0.0).with_gap(gap)).unwrap();
    let model =
        RigidImpact::new(Simulator::new(m).unwrap(), stiffness_limit(2, 0.5).unwrap()).unwrap();
    assert!(!model.can_stick());
    let x0 = DVector::from_vec(vec![gap / 2.0, 0.0, -0.5, 0.0]);
    let run = model.run(&x0, 50.0).unwrap();
    match run.outcome {
        Outcome::Chatter(t_inf) => {
            assert!(t_inf < 50.0 && (run.time - t_inf).abs() < 1e-12 * t_inf.max(1.0));
            assert!(run
                .events
                .iter()
                .any(|e| matches!(e, RigidEvent::Chatter { .. })));
        }
        other => panic!(
            "expected chatter, got {other:?} after {} impacts",
            impacts(&run).len()
        ),
    }
    assert!(impacts(&run).len() < 10_000);
}

/// The forced N-mode model with material damping ζ₁ (paper forcing at ω/(β₁⁻)²), stop
/// stiffness irrelevant for the rigid model.
fn forced(modes: usize, gap: f64, zeta1: f64, omega: f64, k_over_k1: f64) -> GalerkinModel {
    problems::Forced {
        modes,
        k_over_k1,
        zeta1,
        omega_over_w1: omega,
        gap,
        printed_eq37_amplitude: false,
    }
    .model()
    .unwrap()
}

#[test]
fn the_laws_that_can_stick_are_those_that_leave_the_tangential_velocity_alone() {
    use impacting_cantilever::model::restitution::stiffness_limit;
    let sim = |n| Simulator::new(forced(n, 0.0, 0.01, 2.0, 100.0)).unwrap();
    for n in [1, 2, 5] {
        let ir = RigidImpact::new(sim(n), impulse_response(n, 0.6).unwrap()).unwrap();
        assert!(ir.can_stick(), "[R]_IR, N = {n}");
        let sl = RigidImpact::new(sim(n), stiffness_limit(n, 0.6).unwrap()).unwrap();
        // one mode: every law is Newton's law
        assert_eq!(sl.can_stick(), n == 1, "[R]_N, N = {n}");
    }
}

#[test]
fn two_mode_sticking_follows_the_constrained_closed_form() {
    // N = 2 on the stop: η = η_c + wζ with w = (1, −1)/√2 ⊥ φ = (2, 2), η_c = (d₀/4)(1, 1).
    // ζ obeys one damped forced oscillator — κ = wᵀKw, c = wᵀCw, F = wᵀf, offset
    // −wᵀKη_c/κ — solved here by the closed form `linear_response`, independently of the
    // sticking module's eigenbasis and block exponentials. The stop's force is
    // L = φᵀf cos ωt − φᵀKη_c − (φᵀKw ζ + φᵀCw ζ̇); release is where L falls through zero.
    let gap = -0.3;
    let model = forced(2, gap, 0.01, 1.3, 100.0);
    let (k, c, f) = (
        model.modal_stiffness().clone(),
        model.damping().clone(),
        model.forcing_amplitude().clone(),
    );
    let omega = model.omega();
    let sim = Simulator::new(model).unwrap();
    let period = sim.period();
    let rigid = RigidImpact::new(sim, impulse_response(2, 0.5).unwrap()).unwrap();
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let (kz, cz, fz) = (0.5 * (k[0] + k[1]), 0.5 * (c[0] + c[1]), s2 * (f[0] - f[1]));
    let offset = -s2 * (k[0] - k[1]) * gap / 4.0 / kz;
    let (a, b) = (2.0 * s2 * (k[0] - k[1]), 2.0 * s2 * (c[0] - c[1]));
    let (phi_f, phi_k_eta) = (2.0 * (f[0] + f[1]), 2.0 * gap / 4.0 * (k[0] + k[1]));
    // start on the stop, at rest in ζ: the stop must push (L > 0) at t = 0
    let (z0, v0) = (0.01, 0.0);
    let x0 = DVector::from_vec(vec![
        gap / 4.0 + s2 * z0,
        gap / 4.0 - s2 * z0,
        s2 * v0,
        -s2 * v0,
    ]);
    let closed = |t: f64| {
        let (z, zd) = problems::linear_response(kz, cz, fz, omega, z0 - offset, v0, t);
        (z + offset, zd)
    };
    let force = |t: f64| {
        let (z, zd) = closed(t);
        phi_f * (omega * t).cos() - phi_k_eta - a * z - b * zd
    };
    assert!(force(0.0) > 0.0, "the stop pushes at the start");
    assert!(rigid.sticking().push(&x0, 0.0) > 0.0);
    // the release, independently: the first sign change on a fine grid, then bisection
    let dt = period * 1e-4;
    let mut t = 0.0;
    while force(t + dt) > 0.0 {
        t += dt;
        assert!(t < 20.0 * period, "released within 20 periods");
    }
    let (mut lo, mut hi) = (t, t + dt);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if force(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let mut stats = impacting_cantilever::engine::sim::Stats::default();
    let (release, state) = rigid.sticking().hold(
        &x0,
        &impacting_cantilever::engine::sim::Clock::at_cycle(period, 0),
        20.0 * period,
        1e-13 * period,
        1e-15,
        &mut stats,
    );
    let s = release.expect("released");
    // both are polished to round-off of the force's terms; 1e-10 T leaves room for the
    // bisection's own round-off in a sum of O(10²) terms
    assert!(
        (s - lo).abs() < 1e-10 * period,
        "release {s} vs closed form {lo}"
    );
    let (z, zd) = closed(s);
    let expect = [gap / 4.0 + s2 * z, gap / 4.0 - s2 * z, s2 * zd, -s2 * zd];
    for i in 0..4 {
        assert!(
            (state[i] - expect[i]).abs() < 1e-10,
            "state[{i}]: {} vs {}",
            state[i],
            expect[i]
        );
    }
    // held on the stop throughout: tip at d₀, tip velocity zero
    assert!((2.0 * (state[0] + state[1]) - gap).abs() < 1e-13);
    assert!((state[2] + state[3]).abs() < 1e-12);
}

#[test]
fn single_mode_sticking_is_released_where_the_forcing_turns() {
    // N = 1 forced slowly (ω = 0.3(β₁⁻)², quasi-static: free tip amplitude ≈ 0.022), the
    // stop just below the rest position: each cycle the tip lands, chatters and sticks at
    // η = d₀/φ₁(1), and is released when f₁ cos θ − k₁η falls through zero.
    let gap = -0.01;
    let model = forced(1, gap, 0.01, 0.3, 100.0);
    let (f1, k1) = (model.forcing_amplitude()[0], model.modal_stiffness()[0]);
    let omega = model.omega();
    let rigid = RigidImpact::new(
        Simulator::new(model).unwrap(),
        impulse_response(1, 0.5).unwrap(),
    )
    .unwrap();
    let x0 = DVector::from_vec(vec![gap / 2.0, -0.005]);
    let run = rigid.run(&x0, 30.0).unwrap();
    let starts: Vec<f64> = run
        .events
        .iter()
        .filter_map(|e| match e {
            RigidEvent::StickStart { time } => Some(*time),
            _ => None,
        })
        .collect();
    let ends: Vec<f64> = run
        .events
        .iter()
        .filter_map(|e| match e {
            RigidEvent::StickEnd { time } => Some(*time),
            _ => None,
        })
        .collect();
    assert!(!ends.is_empty(), "released at least once");
    let hold = k1 * gap / 2.0;
    for (start, end) in starts.iter().zip(&ends) {
        // the first downward zero of f₁ cos ωt − hold after the start
        let g = |t: f64| f1 * (omega * t).cos() - hold;
        let mut t = *start;
        let dt = 1e-4 / omega;
        while g(t + dt) > 0.0 {
            t += dt;
        }
        let (mut lo, mut hi) = (t, t + dt);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if g(mid) > 0.0 {
                lo = mid
            } else {
                hi = mid
            }
        }
        assert!(
            (end - lo).abs() < 1e-10,
            "release at {end}, closed form {lo}"
        );
    }
    assert_eq!(run.outcome, Outcome::Completed);
}

#[test]
fn three_mode_chatter_sticks_and_is_released() {
    // N = 3 with Newton's law at the tip ([R]_IR), the stop below rest and the forcing
    // turning: the run goes through chatter, sticking and release, and completes
    let gap = -0.01;
    let model = forced(3, gap, 0.01, 0.3, 100.0);
    let rigid = RigidImpact::new(
        Simulator::new(model).unwrap(),
        impulse_response(3, 0.5).unwrap(),
    )
    .unwrap();
    // the tip just before the stop (a rigid stop cannot start penetrated), moving in
    let x0 = DVector::from_vec(vec![(gap - 0.002) / 2.0, 0.0, 0.0, 0.005, 0.0, 0.0]);
    let run = rigid.run(&x0, 30.0).unwrap();
    assert_eq!(run.outcome, Outcome::Completed);
    let count = |f: &dyn Fn(&RigidEvent) -> bool| run.events.iter().filter(|e| f(e)).count();
    assert!(count(&|e| matches!(e, RigidEvent::Chatter { .. })) >= 1);
    assert!(count(&|e| matches!(e, RigidEvent::StickStart { .. })) >= 1);
    assert!(count(&|e| matches!(e, RigidEvent::StickEnd { .. })) >= 1);
}

#[test]
fn sticking_is_the_limit_of_the_compliant_contact_as_k_grows() {
    // From a state on the stop with zero tip velocity that the stop must hold, the rigid
    // model sticks until its force turns. The compliant model, started in the same state
    // pressed into the stop by its quasi-static penetration d − d₀ = 4λ/k (so that its
    // barely damped stop mode is not set ringing), rests in the stop and leaves it near the
    // same time, the closer the stiffer the stop.
    use impacting_cantilever::engine::sim::{Clock, Events};
    let (gap, n) = (-0.3, 3);
    let base = forced(n, gap, 0.01, 1.3, 100.0);
    let sim = Simulator::new(base).unwrap();
    let period = sim.period();
    let rigid = RigidImpact::new(sim, impulse_response(n, 0.5).unwrap()).unwrap();
    let x0 = rigid
        .sticking()
        .project(&DVector::from_vec(vec![gap / 6.0, 0.0, 0.0, 0.0, 0.0, 0.0]));
    assert!(rigid.sticking().push(&x0, 0.0) > 0.0);
    let mut stats = impacting_cantilever::engine::sim::Stats::default();
    let (release, _) = rigid.sticking().hold(
        &x0,
        &Clock::at_cycle(period, 0),
        20.0 * period,
        1e-13 * period,
        1e-15,
        &mut stats,
    );
    let release = release.unwrap();
    let mut gaps = Vec::new();
    let push = rigid.sticking().push(&x0, 0.0);
    // and its rate, by a central difference along the constrained flow, for the initial
    // penetration velocity
    let h = 1e-6 * period;
    let omega = rigid.sim.omega();
    let at = |s: f64| {
        let x = rigid.sticking().state(&x0, 0.0, s);
        rigid.sticking().push(&x, omega * s)
    };
    let rate = (at(h) - at(-h)) / (2.0 * h);
    for k in [1e4, 1e6, 1e8] {
        let model = forced(n, gap, 0.01, 1.3, k);
        let phi = model.tip().clone();
        let stop = model.params().stop_stiffness;
        // λ = L/|φ|², penetration 4λ/k along φ: η += φ·(4λ/k)/|φ|²
        let scale = 4.0 / phi.norm_squared() / stop / phi.norm_squared();
        let mut start = x0.clone();
        for i in 0..n {
            start[i] += phi[i] * push * scale;
            start[n + i] += phi[i] * rate * scale;
        }
        let sim = Simulator::new(model).unwrap();
        let mut events = Events::default();
        sim.run_until(
            &start,
            Clock::at_cycle(period, 0),
            Clock::at_time(period, release + period),
            &mut events,
        )
        .unwrap();
        let exit = events
            .events
            .iter()
            .find(|e| !e.entering && !e.grazing)
            .map(|e| e.time)
            .expect("the compliant tip leaves the stop");
        gaps.push((exit - release).abs() / period);
    }
    // The compliant penetration is the quasi-static 4λ/k plus O(p̈/(kN)) = O(1/k²), and the
    // exit is where it vanishes, so the exit time approaches the release like 1/k: each
    // 100-fold stiffer stop, 100 times closer (measured 2.4e-5, 2.1e-7, 2.1e-9 T); at least
    // 30 times here
    assert!(
        gaps[1] < gaps[0] / 30.0 && gaps[2] < gaps[1] / 30.0,
        "{gaps:?}"
    );
}

#[test]
fn a_generic_impact_oscillator_bounces_as_the_closed_form_says() {
    // ẍ + 4x = 0 (ω₀ = 2), tip gain 3, stop at gx = 0, r = 0.7: every flight lasts π/ω₀
    // whatever its amplitude, and each impact scales the speed by r — any k and g, not only
    // the cantilever's mode 1
    use impacting_cantilever::model::galerkin::Oscillator;
    let o = Oscillator {
        stiffness: 4.0,
        damping: 0.0,
        forcing: 0.0,
        omega: 1.0,
        tip_gain: 3.0,
        gap: 0.0,
        stop_stiffness: 0.0,
    };
    let model = RigidImpact::oscillator(&o, 0.7).unwrap();
    let run = model
        .run(&DVector::from_vec(vec![0.0, -1.0]), 5.5 * PI / 2.0)
        .unwrap();
    let hits = impacts(&run);
    assert_eq!(hits.len(), 5);
    for (i, (t, vin, _)) in hits.iter().enumerate() {
        let n = (i + 1) as f64;
        assert!((t - n * PI / 2.0).abs() < 1e-12 * t, "impact {i} at {t}");
        // tip velocity g·ẋ, ẋ = 1 at the first impact, times r per impact
        assert!((vin - 3.0 * 0.7f64.powi(i as i32)).abs() < 1e-12, "{vin}");
    }
    // a forced oscillator starts from any time and forcing phase: a run split at an
    // arbitrary clock reaches the same state as one run through it
    use impacting_cantilever::engine::sim::Clock;
    let forced = RigidImpact::oscillator(
        &Oscillator {
            damping: 0.1,
            forcing: 1.0,
            omega: 1.3,
            gap: 0.4,
            ..o
        },
        0.7,
    )
    .unwrap();
    let period = forced.sim.period();
    let x0 = DVector::from_vec(vec![0.0, 0.0]);
    let whole = forced.run(&x0, 7.3 * period).unwrap();
    let mid = Clock::at_time(period, 3.1 * period);
    let first = forced
        .run_until(&x0, Clock::at_cycle(period, 0), mid)
        .unwrap();
    let second = forced
        .run_until(&first.state, mid, Clock::at_time(period, 7.3 * period))
        .unwrap();
    assert!(!whole.impacts().is_empty());
    assert!(
        (&whole.state - &second.state).amax() < 1e-12,
        "{} vs {}",
        whole.state,
        second.state
    );
}

#[test]
fn an_oscillator_has_no_beam_profile() {
    use impacting_cantilever::model::galerkin::Oscillator;
    let m = GalerkinModel::oscillator(&Oscillator {
        stiffness: 1.0,
        damping: 0.0,
        forcing: 0.0,
        omega: 1.0,
        tip_gain: 1.0,
        gap: 0.0,
        stop_stiffness: 0.0,
    })
    .unwrap();
    assert!(m.modal_state(&|_| 0.0, &|_| 0.0).is_err());
    assert!(GalerkinModel::oscillator(&Oscillator {
        stiffness: -1.0,
        damping: 0.0,
        forcing: 0.0,
        omega: 1.0,
        tip_gain: 1.0,
        gap: 0.0,
        stop_stiffness: 0.0,
    })
    .is_err());
}

#[test]
fn many_mode_sticking_is_released_in_bounded_work_where_the_force_turns() {
    // Above the sixth, the constrained modes are over-damped by the material damping
    // (c = γκ ≫ 2√κ): a fast rate ~γκ beside a slow one ~1/γ. Searched as 2 × 2 blocks,
    // their bounds carried the fast rate long after it had decayed, and the release search
    // crept (N = 50: 26.9 million certified steps for this release, ~30 s). Split into
    // exponentials it takes 18; the contact force along the constrained state (computed
    // from the state itself, not from the search's signal) is positive until the release
    // and turns negative right after it.
    use impacting_cantilever::engine::sim::{Clock, Stats};
    let (gap, n) = (-0.3, 50);
    let sim = Simulator::new(forced(n, gap, 0.01, 1.3, 100.0)).unwrap();
    let (period, omega) = (sim.period(), sim.omega());
    let rigid = RigidImpact::new(sim, impulse_response(n, 0.5).unwrap()).unwrap();
    let mut start = DVector::zeros(2 * n);
    start[0] = gap / 6.0;
    let x0 = rigid.sticking().project(&start);
    let push0 = rigid.sticking().push(&x0, 0.0);
    assert!(push0 > 0.0);
    let mut stats = Stats::default();
    let (release, _) = rigid.sticking().hold(
        &x0,
        &Clock::at_cycle(period, 0),
        20.0 * period,
        1e-13 * period,
        1e-15,
        &mut stats,
    );
    let release = release.expect("the forcing turns within 20 periods");
    assert!(stats.steps < 1_000, "{stats:?}");
    let push = |s: f64| {
        let x = rigid.sticking().state(&x0, 0.0, s);
        rigid.sticking().push(&x, omega * s)
    };
    // the force is a sum of terms up to ~|push0|·10⁶ (φᵀKw grows like i⁴): its round-off
    let noise = 1e-9 * push0;
    let first_negative = (0..=4000)
        .map(|i| release * i as f64 / 4000.0)
        .find(|&s| push(s) < -noise);
    assert!(
        first_negative.is_none_or(|s| s >= release * (1.0 - 1e-9)),
        "the force pulls at {first_negative:?} before the release at {release}"
    );
    assert!(push(release * (1.0 + 1e-6)) < 0.0 && push(release * (1.0 - 1e-6)) > 0.0);
}
