//! The rigid-impact N-mode model: 1-DOF closed forms, the chattering policy, and the
//! compliant model's convergence to it as k → ∞ (Nordmark).

use impacting_cantilever::galerkin::{self, GalerkinModel, GalerkinParams};
use impacting_cantilever::problems;
use impacting_cantilever::restitution::impulse_response;
use impacting_cantilever::rigid::{Outcome, RigidEvent, RigidImpact};
use impacting_cantilever::sim::Simulator;
use nalgebra::DVector;
use std::f64::consts::PI;

fn one_mode(gap: f64, r: f64) -> RigidImpact {
    let m = GalerkinModel::new(GalerkinParams::new(1, 0.0).with_gap(gap)).unwrap();
    RigidImpact::new(Simulator::new(m).unwrap(), impulse_response(1, r).unwrap()).unwrap()
}

fn impacts(run: &impacting_cantilever::rigid::RigidRun) -> Vec<(f64, f64, f64)> {
    run.impacts()
}

#[test]
fn bouncing_single_mode_matches_the_closed_form() {
    // Undamped, unforced, d₀ = 0, r = 0.8, leaving the stop with tip velocity −2: every
    // flight lasts π/ω₁ whatever its amplitude, and each impact scales the speed by r.
    let w1 = galerkin::first_frequency();
    let model = one_mode(0.0, 0.8);
    let x0 = DVector::from_vec(vec![0.0, -1.0]);
    let run = model.run(&x0, 10.5 * PI / w1);
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
    let run = model.run(&x0, 2.0 * t_inf + 1.0);
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
    use impacting_cantilever::orbit::{self, OrbitKind};
    let case = |k_over_k1| problems::Forced {
        k_over_k1,
        omega_over_w1: 1.5,
        ..problems::figure4(1)
    };
    let sim = Simulator::new(case(1.0).model().unwrap()).unwrap();
    let rigid = RigidImpact::new(sim.clone(), impulse_response(1, 1.0).unwrap()).unwrap();
    let run = rigid.run(&DVector::zeros(2), 1040.0 * sim.period());
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
    let rate = impacting_cantilever::verification::fitted_slope(&lx, &ly);
    // measured −0.51 over these three decades
    assert!((rate + 0.5).abs() < 0.1, "rate {rate}, gaps {gaps:?}");
}

#[test]
fn multi_mode_chatter_stops_with_an_explicit_outcome() {
    // N = 2, the stop below the rest position: impacts accumulate; the N > 1 policy stops the
    // run at the extrapolated accumulation time instead of looping (module doc).
    let gap = -0.1;
    let m = GalerkinModel::new(GalerkinParams::new(2, 0.0).with_gap(gap)).unwrap();
    let model = RigidImpact::new(
        Simulator::new(m).unwrap(),
        impulse_response(2, 0.5).unwrap(),
    )
    .unwrap();
    let x0 = DVector::from_vec(vec![gap / 2.0, 0.0, -0.5, 0.0]);
    let run = model.run(&x0, 50.0);
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
