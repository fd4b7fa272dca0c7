//! The library as a researcher uses it: a custom model's orbit, multipliers and r_E in one
//! call ([`find_orbit`]), checked against the routes it chains; bad input as errors, never
//! panics; and the examples run as tests, so that what `examples/` shows works.

use impacting_cantilever::prelude::*;

#[path = "../examples/custom_model.rs"]
mod custom_model;
#[path = "../examples/find_orbit.rs"]
mod find_orbit_example;
#[path = "../examples/rigid_impact.rs"]
mod rigid_impact;
#[path = "../examples/use_cases.rs"]
mod use_cases;

#[test]
fn the_examples_run() {
    custom_model::main().unwrap();
    find_orbit_example::main().unwrap();
    rigid_impact::main().unwrap();
    use_cases::main().unwrap();
}

/// The model of `examples/find_orbit.rs`.
fn custom() -> Simulator {
    let params = GalerkinParams::new(6, 300.0 * first_modal_stiffness())
        .with_zeta1(0.01)
        .with_viscous_damping(0.02)
        .with_forcing(Forcing {
            omega: 1.8 * first_frequency(),
            profile: SpatialProfile::UnitTipAtResonance,
        });
    let model = GalerkinModel::new(params)
        .unwrap()
        .with_gap_over_free(0.5)
        .unwrap();
    Simulator::new(model).unwrap()
}

#[test]
fn find_orbit_agrees_with_the_routes_it_chains() {
    let sim = custom();
    // the gap is half the free tip amplitude at ω, whatever ω is
    let a_free = sim.model().free_tip_amplitude().0;
    assert!((sim.model().params().gap - 0.5 * a_free).abs() <= 1e-15 * a_free);
    let options = OrbitOptions {
        restitution: true,
        ..OrbitOptions::default()
    };
    let o = find_orbit(&sim, &sim.rest(), &options).unwrap();
    assert!(o.residual <= 1e-12 && o.stable);
    // the orbit is what a long transient settles on (§5.2's test) …
    let brute = settle_map(&sim, &sim.rest(), 4000, 8).unwrap();
    assert_eq!(
        brute.kind,
        OrbitKind::Periodic {
            m: o.period_m,
            n: o.impacts_n
        }
    );
    let r = (&brute.state - &o.state).amax() / o.state.amax();
    assert!(r < 1e-8, "transient and shooting differ by {r:e}");
    // … and r_E is eq (39) over one period of it, as the energetic module computes it
    let direct = orbit_coefficient(&sim, &sim.rest(), 4000, 8).unwrap();
    let want = direct.coefficient.and_then(|c| c.value()).unwrap();
    let got = o.energetic_restitution.unwrap();
    assert!((got - want).abs() < 1e-8, "r_E {got} vs {want}");
}

#[test]
fn bad_input_is_an_error_never_a_panic() {
    let sim = custom();
    let rest = sim.rest();
    // a start of the wrong length, or with a NaN
    for start in [DVector::zeros(5), DVector::from_element(12, f64::NAN)] {
        let e = find_orbit(&sim, &start, &OrbitOptions::default()).unwrap_err();
        assert!(matches!(e, Error::Parameter(_)), "{e}");
        let e = sim.run(&start, 1, &mut ()).unwrap_err();
        assert!(matches!(e, Error::Parameter(_)), "{e}");
    }
    // options out of range
    for options in [
        OrbitOptions {
            window: 1,
            ..Default::default()
        },
        OrbitOptions {
            period: Some(0),
            ..Default::default()
        },
        OrbitOptions {
            period: Some(65),
            ..Default::default()
        },
        OrbitOptions {
            period_tolerance: f64::NAN,
            ..Default::default()
        },
        OrbitOptions {
            transient: u64::MAX,
            ..Default::default()
        },
    ] {
        let e = find_orbit(&sim, &rest, &options).unwrap_err();
        assert!(matches!(e, Error::Parameter(_)), "{options:?}: {e}");
    }
    // a mode the model does not have
    assert!(ContactWork::for_mode(sim.model(), 6).is_err());
    // the rigid model: a wrong state is an error, and r_E is refused with the reason
    let rigid = RigidImpact::new(
        Simulator::new(problems::figure4(1).model().unwrap()).unwrap(),
        restitution::impulse_response(1, 0.8).unwrap(),
    )
    .unwrap();
    assert!(rigid.run(&DVector::zeros(3), 1.0).is_err());
    let options = OrbitOptions {
        restitution: true,
        ..OrbitOptions::default()
    };
    let e = find_orbit(&rigid, &rigid.rest(), &options).unwrap_err();
    assert!(e.to_string().contains("no contact force"), "{e}");
    // a gap relative to an unforced model's A_free (0) is refused
    let unforced = GalerkinModel::new(GalerkinParams::new(3, 10.0)).unwrap();
    assert!(unforced.with_gap_over_free(0.5).is_err());
}

#[test]
fn free_amplitudes_of_several_forced_modes_add_as_phasors() {
    // a profile forcing modes 1 and 2 at ω between their resonances: mode 1 responds
    // against the forcing, mode 2 with it, so the tip amplitude is the modulus of the
    // complex sum, not the sum of moduli
    let omega = 10.0 * first_frequency();
    let model = GalerkinModel::new(GalerkinParams::new(2, 0.0).with_zeta1(0.01).with_forcing(
        Forcing {
            omega,
            profile: SpatialProfile::Modal(vec![1.0, 1.0]),
        },
    ))
    .unwrap();
    let k = model.modal_stiffness();
    let (t, c) = (model.tip(), model.damping());
    let phasor = |j: usize| t[j] / Complex64::new(k[j] - omega * omega, c[j] * omega);
    let want = (phasor(0) + phasor(1)).norm();
    let got = model.free_tip_amplitude().0;
    assert!((got - want).abs() <= 1e-14 * want, "{got} vs {want}");
    assert!(got < phasor(0).norm() + phasor(1).norm());
}
