//! Lyapunov exponents by QR iteration of the exact period-map Jacobians, checked against
//! what the iteration does not compute: the Floquet multipliers of a stable periodic orbit
//! (λ₁ = ln|μ₁|/(mT) there), and Liouville's formula for the sum of all exponents.

use impacting_cantilever::analysis::lyapunov::{lyapunov, LyapunovOptions};
use impacting_cantilever::analysis::shooting;
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::map::PeriodMap;
use impacting_cantilever::engine::rigid::RigidImpact;
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::model::galerkin::Oscillator;
use impacting_cantilever::model::problems;
use nalgebra::DVector;

/// λ₁ of a trajectory on a stable period-1 orbit against ln|μ₁|/T from shooting's Floquet
/// multipliers: it lies in the run's own 95 % interval, and within 1e-3 relative.
fn check_against_floquet(model: &dyn PeriodMap, x0: &DVector<f64>) {
    let orbit = shooting::shoot(model, x0, 1).unwrap();
    assert_eq!(orbit.period_m, 1);
    assert!(orbit.stable);
    let expected = orbit.spectral_radius().ln() / model.period();
    let options = LyapunovOptions {
        transient: 0,
        segments: 10,
        periods: 100,
        exponents: 1,
    };
    let start = orbit.state_vector();
    let l = lyapunov(model, &start, &options, &Silent).unwrap();
    let (got, hw) = (l.exponents[0], l.half_width[0]);
    assert!(
        (got - expected).abs() <= hw.max(1e-12 * expected.abs()),
        "λ₁ = {got} ± {hw}, Floquet {expected}"
    );
    assert!((got - expected).abs() <= 1e-3 * expected.abs());
}

#[test]
fn on_a_stable_compliant_orbit_the_largest_exponent_is_the_floquet_rate() {
    let sim = Simulator::new(problems::figure4(3).model().unwrap()).unwrap();
    let x = sim.run(&DVector::zeros(6), 1000, &mut ()).unwrap().state;
    check_against_floquet(&sim, &x);
}

#[test]
fn on_a_stable_rigid_orbit_the_largest_exponent_is_the_floquet_rate() {
    // the impact oscillator of tests/rigid_orbits.rs, a stable (1,1) orbit at ω = 2
    let rigid = RigidImpact::oscillator(
        &Oscillator {
            stiffness: 1.0,
            damping: 0.1,
            forcing: 1.0,
            omega: 2.0,
            tip_gain: 1.0,
            gap: 0.0,
            stop_stiffness: 0.0,
        },
        0.8,
    )
    .unwrap();
    let x = rigid.advance(&rigid.rest(), 0, 1000, false).unwrap().state;
    check_against_floquet(&rigid, &x);
}

/// Liouville: the compliant flow's divergence is −tr C in both regions (the stop adds
/// stiffness, not damping), so det DP = e^{−tr C·T} every period and the exponents of the
/// whole spectrum sum to −tr C on any trajectory, periodic or not. Each segment's sum is
/// checked to 1e-9 relative (round-off of 100 QR factorisations of products spanning
/// e^{±30} in their singular values).
#[test]
fn the_whole_spectrum_sums_to_minus_the_trace_of_the_damping() {
    let model = problems::figure4(3).model().unwrap();
    let trace: f64 = model.damping().iter().sum();
    let sim = Simulator::new(model).unwrap();
    let options = LyapunovOptions {
        transient: 0,
        segments: 4,
        periods: 100,
        exponents: 6,
    };
    // from rest: the transient, not an orbit
    let l = lyapunov(&sim, &DVector::zeros(6), &options, &Silent).unwrap();
    for s in &l.segments {
        let sum: f64 = s.iter().sum();
        assert!(
            (sum + trace).abs() <= 1e-9 * trace,
            "sum {sum}, −tr C = {}",
            -trace
        );
    }
    // largest first, within the estimates' own intervals (a pair of equal exponents,
    // such as a complex pair's, may come out in either order over a finite record)
    for j in 1..6 {
        let slack = l.half_width[j - 1] + l.half_width[j];
        assert!(
            l.exponents[j - 1] >= l.exponents[j] - slack,
            "{:?} ± {:?}",
            l.exponents,
            l.half_width
        );
    }
}

#[test]
fn bad_options_are_refused_naming_them() {
    let sim = Simulator::new(problems::figure4(1).model().unwrap()).unwrap();
    let x = DVector::zeros(2);
    let base = LyapunovOptions {
        transient: 0,
        segments: 4,
        periods: 10,
        exponents: 1,
    };
    for (opts, name) in [
        (
            LyapunovOptions {
                segments: 1,
                ..base
            },
            "segments",
        ),
        (
            LyapunovOptions {
                segments: 31,
                ..base
            },
            "segments",
        ),
        (LyapunovOptions { periods: 0, ..base }, "periods"),
        (
            LyapunovOptions {
                exponents: 0,
                ..base
            },
            "exponents",
        ),
        (
            LyapunovOptions {
                exponents: 3,
                ..base
            },
            "exponents",
        ),
    ] {
        let e = lyapunov(&sim, &x, &opts, &Silent).unwrap_err().to_string();
        assert!(e.contains(name), "{e}");
    }
    let e = lyapunov(
        &sim,
        &DVector::from_vec(vec![f64::NAN, 0.0]),
        &base,
        &Silent,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("start state"), "{e}");
}
