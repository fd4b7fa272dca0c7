//! Periodic orbits of the rigid-impact model by Newton shooting, with the saltation
//! matrices at the impacts: against central differences of the map, against the closed
//! form of the impact oscillator's (1,1) orbit and its period-doubling boundary, and
//! against the compliant model's multipliers as the stop stiffens.

use impacting_cantilever::analysis::orbit::{settle_map, OrbitKind};
use impacting_cantilever::analysis::shooting;
use impacting_cantilever::engine::map::PeriodMap;
use impacting_cantilever::engine::rigid::RigidImpact;
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::model::galerkin::Oscillator;
use impacting_cantilever::model::problems::{self, Forced};
use impacting_cantilever::model::restitution;
use nalgebra::{DMatrix, DVector, Matrix2, Vector2};
use num_complex::Complex64;

/// ẍ + cẋ + kx = F cos ωt with a stop at x = d and Newton's law r: k = 1, c = 0.1, F = 1,
/// d = 0, r = 0.8 (a stable (1,1) orbit for ω ≲ 2.65, period doubling above).
const K: f64 = 1.0;
const C: f64 = 0.1;
const F: f64 = 1.0;
const D: f64 = 0.0;
const R: f64 = 0.8;

fn oscillator(omega: f64) -> RigidImpact {
    RigidImpact::oscillator(
        &Oscillator {
            stiffness: K,
            damping: C,
            forcing: F,
            omega,
            tip_gain: 1.0,
            gap: D,
            stop_stiffness: 0.0,
        },
        R,
    )
    .unwrap()
}

/// The closed form of the (1,1) orbit, independent of the library: the free flight
/// x(t) = Φ(t − τ)(x(τ) − x_p(τ)) + x_p(t) of the damped oscillator, an impact at phase τ
/// with incoming velocity v, and x(τ + T) = (d, v) after starting from (d, −rv).
struct ClosedForm {
    omega: f64,
}

impl ClosedForm {
    fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }
    fn phi(&self, t: f64) -> Matrix2<f64> {
        let a = C / 2.0;
        let wd = (K - a * a).sqrt();
        let (s, c) = (wd * t).sin_cos();
        (-a * t).exp() * Matrix2::new(c + a / wd * s, s / wd, -K / wd * s, c - a / wd * s)
    }
    /// The particular solution's displacement and velocity at t.
    fn particular(&self, t: f64) -> Vector2<f64> {
        let w = self.omega;
        let m = Matrix2::new(K - w * w, C * w, -C * w, K - w * w);
        let ab = m.lu().solve(&Vector2::new(F, 0.0)).unwrap();
        let (s, c) = (w * t).sin_cos();
        Vector2::new(ab[0] * c + ab[1] * s, -ab[0] * w * s + ab[1] * w * c)
    }
    fn velocity(&self, tau: f64) -> f64 {
        let p = self.phi(self.period());
        let xp = self.particular(tau);
        (p[(1, 0)] * (D - xp[0]) + xp[1] * (1.0 - p[(1, 1)])) / (1.0 + R * p[(1, 1)])
    }
    fn residual(&self, tau: f64) -> f64 {
        let p = self.phi(self.period());
        let xp = self.particular(tau);
        (p[(0, 0)] - 1.0) * (D - xp[0]) - p[(0, 1)] * (R * self.velocity(tau) + xp[1])
    }
    /// The admissible (1,1) orbits: impact phase τ and velocity v > 0, with the free flight
    /// below the stop in between.
    fn orbits(&self) -> Vec<(f64, f64)> {
        let t = self.period();
        let n = 4000;
        let mut out = Vec::new();
        for i in 0..n {
            let (mut a, mut b) = (t * i as f64 / n as f64, t * (i + 1) as f64 / n as f64);
            if self.residual(a) * self.residual(b) > 0.0 {
                continue;
            }
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                if self.residual(a) * self.residual(m) <= 0.0 {
                    b = m;
                } else {
                    a = m;
                }
            }
            let tau = 0.5 * (a + b);
            let v = self.velocity(tau);
            let y0 = Vector2::new(D, -R * v) - self.particular(tau);
            let below = (1..2000).all(|j| {
                let s = t * j as f64 / 2000.0;
                (self.phi(s) * y0)[0] + self.particular(tau + s)[0] < D + 1e-12
            });
            if v > 0.0 && below {
                out.push((tau, v));
            }
        }
        out
    }
    /// The orbit's state at the start of a forcing period.
    fn state(&self, tau: f64, v: f64) -> DVector<f64> {
        let t = self.period();
        let y = self.phi(t - tau) * (Vector2::new(D, -R * v) - self.particular(tau))
            + self.particular(t);
        DVector::from_column_slice(y.as_slice())
    }
    /// The monodromy Φ(T)·S with the saltation S = [[−r, 0], [(a⁺ + r a⁻)/v, −r]].
    fn monodromy(&self, tau: f64, v: f64) -> Matrix2<f64> {
        let force = F * (self.omega * tau).cos();
        let before = -C * v - K * D + force;
        let after = C * R * v - K * D + force;
        let s = Matrix2::new(-R, 0.0, (after + R * before) / v, -R);
        self.phi(self.period()) * s
    }
}

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
        let exact = ClosedForm { omega };
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
        let exact = ClosedForm { omega };
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
        let exact = ClosedForm { omega };
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
