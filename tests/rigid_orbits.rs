//! Periodic orbits of the rigid-impact model by Newton shooting, with the saltation
//! matrices at the impacts: against central differences of the map, against the closed
//! form of the impact oscillator's (1,1) orbit and its period-doubling boundary, and
//! against the compliant model's multipliers as the stop stiffens.

use impacting_cantilever::analysis::orbit::{settle_map, OrbitKind};
use impacting_cantilever::analysis::shooting;
use impacting_cantilever::engine::map::PeriodMap;
use impacting_cantilever::engine::rigid::RigidImpact;
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::model::problems::{self, Forced};
use impacting_cantilever::model::restitution;
use nalgebra::{DMatrix, Matrix2};
use num_complex::Complex64;

use crate::common::impact::{oscillator, ClosedForm, C, F, K, R};
use impacting_cantilever::model::galerkin::Oscillator;

fn eigenvalues(m: &Matrix2<f64>) -> Vec<Complex64> {
    let (tr, det) = (m.trace(), m.determinant());
    let disc = Complex64::new(tr * tr / 4.0 - det, 0.0).sqrt();
    let mut v = vec![tr / 2.0 + disc, tr / 2.0 - disc];
    v.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    v
}

#[test]
fn the_monodromy_with_saltation_matches_central_differences() {
    // the impact oscillator, and a two-mode beam with the impulse-response law
    let beam = RigidImpact::new(
        Simulator::new(problems::figure4(2).model().unwrap()).unwrap(),
        restitution::impulse_response(2, 0.7).unwrap(),
    )
    .unwrap();
    let models: [(&dyn PeriodMap, u64); 2] = [(&oscillator(2.0), 1), (&beam, 1)];
    for (model, m) in models {
        let x = model.advance(&model.rest(), 0, 200, false).unwrap().state;
        let (_, jac, impacts) = model.map_with_jacobian(&x, m).unwrap();
        assert!(impacts > 0, "{}: the map crosses impacts", model.name());
        let h = 1e-6 * x.amax();
        let mut fd = DMatrix::zeros(x.len(), x.len());
        for i in 0..x.len() {
            let (mut a, mut b) = (x.clone(), x.clone());
            a[i] += h;
            b[i] -= h;
            let pa = model.advance(&a, 0, m, false).unwrap().state;
            let pb = model.advance(&b, 0, m, false).unwrap().state;
            fd.set_column(i, &((pa - pb) / (2.0 * h)));
        }
        // central differences err by O(h²) and by 1e-16/h of round-off
        let e = (&fd - &jac).amax() / jac.amax();
        assert!(e < 1e-6, "{}: {e:e}", model.name());
    }
}

#[test]
fn the_impact_oscillators_period_one_orbit_is_the_closed_form() {
    for omega in [2.0, 2.4] {
        let exact = ClosedForm { omega, r: R };
        let orbits = exact.orbits();
        assert_eq!(orbits.len(), 1, "ω = {omega}: one admissible (1,1) orbit");
        let (tau, v) = orbits[0];
        let state = exact.state(tau, v);
        let model = oscillator(omega);
        // Newton from 1% off the orbit
        let o = shooting::shoot(&model, &(&state * 1.01), 1).unwrap();
        assert_eq!((o.period_m, o.impacts_n), (1, 1), "ω = {omega}");
        let e = (o.state_vector() - &state).amax() / state.amax();
        assert!(e < 1e-10, "ω = {omega}: state differs by {e:e}");
        let want = eigenvalues(&exact.monodromy(tau, v));
        for (got, want) in o.multipliers_complex().iter().zip(&want) {
            assert!((got - want).norm() < 1e-9, "ω = {omega}: μ {got} vs {want}");
        }
        // det M = det Φ(T) · det S = e^{−cT} r²
        let det: Complex64 = o.multipliers_complex().iter().product();
        let expected = (-C * exact.period()).exp() * R * R;
        assert!(
            (det.re - expected).abs() < 1e-12 && det.im.abs() < 1e-12,
            "{det} vs {expected}"
        );
        assert!(o.stable);
    }
}

#[test]
fn period_doubling_where_the_closed_form_puts_it() {
    // 1 + tr M + det M = 0: a multiplier at −1, between ω = 2.6 and 2.7
    let crossing = |omega: f64| {
        let exact = ClosedForm { omega, r: R };
        let (tau, v) = exact.orbits()[0];
        let m = exact.monodromy(tau, v);
        1.0 + m.trace() + m.determinant()
    };
    let (mut a, mut b) = (2.6, 2.7);
    assert!(crossing(a) * crossing(b) < 0.0);
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if crossing(a) * crossing(m) <= 0.0 {
            b = m;
        } else {
            a = m;
        }
    }
    let omega_pd = 0.5 * (a + b);
    for (omega, stable) in [(omega_pd - 0.01, true), (omega_pd + 0.01, false)] {
        let exact = ClosedForm { omega, r: R };
        let (tau, v) = exact.orbits()[0];
        let model = oscillator(omega);
        let o = shooting::shoot(&model, &exact.state(tau, v), 1).unwrap();
        let lead = o.multipliers_complex()[0];
        assert_eq!(o.stable, stable, "ω = {omega}: μ = {lead}");
        if !stable {
            // through −1: a real multiplier below it
            assert!(lead.im.abs() < 1e-12 && lead.re < -1.0, "{lead}");
            // beyond the doubling a transient from near the orbit settles to period 2
            let near = o.state_vector() * 1.001;
            let settled = settle_map(&model, &near, 2000, 16).unwrap();
            assert!(
                matches!(settled.kind, OrbitKind::Periodic { m: 2, n: 2 }),
                "ω = {omega}: {}",
                settled.kind
            );
        }
    }
}

#[test]
fn the_compliant_models_multipliers_tend_to_the_rigid_ones_as_the_stop_stiffens() {
    // N = 1 under Figure 4's forcing and material damping: the compliant contact conserves
    // energy as k → ∞ (it lasts O(k^-1/2), the damping acts over it), so its limit is the
    // rigid model with Newton's law r = 1
    let base = problems::figure4(1);
    let rigid = RigidImpact::new(
        Simulator::new(base.model().unwrap()).unwrap(),
        restitution::impulse_response(1, 1.0).unwrap(),
    )
    .unwrap();
    let guess = rigid.advance(&rigid.rest(), 0, 1000, false).unwrap().state;
    let limit = shooting::shoot(&rigid, &guess, 1).unwrap();
    assert_eq!((limit.period_m, limit.impacts_n), (1, 1));
    let mut errors = Vec::new();
    for k in [1e3, 1e5, 1e7] {
        let sim = Simulator::new(
            Forced {
                k_over_k1: k,
                ..base
            }
            .model()
            .unwrap(),
        )
        .unwrap();
        let o = shooting::shoot(&sim, &limit.state_vector(), 1).unwrap();
        let e = (o.multipliers_complex()[0] - limit.multipliers_complex()[0]).norm();
        errors.push(e);
    }
    // each factor 100 in k shrinks the contact time, and the difference, by about 10
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!((5.0..20.0).contains(&ratio), "errors {errors:?}");
    }
    assert!(errors[2] < 1e-2, "{errors:?}");
}

#[test]
fn a_sticking_orbit_is_refused_with_the_reason() {
    // a stop just above the rest position of a slowly forced oscillator: the mass lands,
    // chatters and sticks every cycle
    let model = RigidImpact::oscillator(
        &Oscillator {
            stiffness: K,
            damping: C,
            forcing: F,
            omega: 0.1,
            tip_gain: 1.0,
            gap: 0.05,
            stop_stiffness: 0.0,
        },
        0.5,
    )
    .unwrap();
    let x = model.advance(&model.rest(), 0, 20, false).unwrap().state;
    let err = shooting::shoot(&model, &x, 1).unwrap_err();
    assert!(err.to_string().contains("sticks"), "{err}");
}

/// A plastic impact (r = 0) leaves the tip at rest on the stop: it sticks there while the
/// stop pushes. It used to fly on from the surface, where the certified search sees no
/// crossing, with the tip pressed 1 % of the gap beyond the stop for a whole period (found
/// by the property test `the_rigid_tip_never_passes_the_stop`).
#[test]
fn a_plastic_impact_sticks_and_the_tip_never_passes_the_stop() {
    use impacting_cantilever::analysis::simulate::{simulate, SimulateOptions};
    use impacting_cantilever::base::progress::Silent;
    use impacting_cantilever::engine::built::BuiltModel;
    use impacting_cantilever::engine::rigid::RigidEvent;
    use impacting_cantilever::model::spec::{
        Cantilever, DampingReading, ForcingSpec, GapUnit, Law, ModelSpec, Start, Stop, Structure,
    };
    let spec = ModelSpec {
        structure: Structure::Cantilever(Cantilever {
            modes: 3,
            gap: 0.0,
            gap_unit: GapUnit::Free,
            zeta1: 0.001,
            damping_reading: DampingReading::Fig9,
            viscous: 0.0,
            omega: 1.4419247460661715,
            forcing: ForcingSpec::Unit,
        }),
        stop: Stop::Rigid {
            law: Law::ImpulseResponse,
            restitution: 0.0,
        },
    };
    let model = BuiltModel::build(&spec).unwrap();
    let (rest, _) = model.start(&Start::Rest).unwrap();
    let o = SimulateOptions {
        periods: 0,
        record: 3,
        dense_per_period: Some(64),
        ..SimulateOptions::default()
    };
    let s = simulate(&model, &rest, &o, &Silent).unwrap();
    // no sample beyond the stop (d₀ = 0) but by round-off of the state's scale
    let worst = s
        .dense
        .as_ref()
        .unwrap()
        .tip
        .iter()
        .fold(0.0f64, |m, &d| m.max(d));
    assert!(worst <= 1e-15, "the tip {worst:e} beyond the stop");
    // the first impact's outgoing tip speed is zero, and the tip then sticks: no run of
    // micro-impacts with growing speeds (there were 40 in three periods)
    assert!(s.events.len() <= 3, "{} impacts", s.events.len());
    if let impacting_cantilever::engine::built::Variant::Rigid(r) = model.variant() {
        let run = r
            .run_until(
                &rest,
                impacting_cantilever::engine::sim::Clock::at_cycle(r.sim.period(), 0),
                impacting_cantilever::engine::sim::Clock::at_cycle(r.sim.period(), 3),
            )
            .unwrap();
        assert!(
            run.events
                .iter()
                .any(|e| matches!(e, RigidEvent::StickStart { .. })),
            "{:?}",
            run.events
        );
    } else {
        panic!("a rigid specification builds the rigid model");
    }
}
