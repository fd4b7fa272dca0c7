//! The energetic coefficient of restitution (§5.4, eqs 38–39): the exact work integral
//! against quadrature of the contact force on the exact solution, and identities that
//! hold whatever the dynamics.

use impacting_cantilever::analysis::energetic::{orbit_coefficient, Coefficient, ContactWork};
use impacting_cantilever::base::numerics::Quadrature;
use impacting_cantilever::engine::sim::{Observer, SegmentView, Simulator};
use impacting_cantilever::model::galerkin::Region;
use impacting_cantilever::model::problems;
use nalgebra::DVector;

/// ∫ F_c η̇₁ dt over the contact segments by composite Gauss–Legendre quadrature of the
/// exact state: F_c = (k/4)(d₀ − d)φ₁(1), d = φ(1)ᵀη.
struct Quadratured {
    rule: Quadrature,
    work: f64,
}

impl Observer for Quadratured {
    fn segment(&mut self, seg: &SegmentView) {
        if seg.region != Region::Contact {
            return;
        }
        let model = seg.simulator().model();
        let (k, d0) = (model.params().stop_stiffness, model.params().gap);
        let phi = model.tip();
        let n = model.modes();
        let s_end = seg.end;
        self.work += s_end
            * self.rule.integrate(|u| {
                let x = seg.state(u * s_end);
                let d = phi.dot(&x.rows(0, n));
                k / 4.0 * (d0 - d) * phi[0] * x[n]
            });
    }
}

fn settled(sim: &Simulator, transient: u64) -> DVector<f64> {
    let n = sim.model().modes();
    sim.run(&DVector::zeros(2 * n), transient, &mut ())
        .unwrap()
        .state
}

#[test]
fn the_exact_work_integral_agrees_with_quadrature_of_the_contact_force() {
    // Figure 6(b)'s model at N = 10: contacts with several taps and stiff stop modes
    let sim = Simulator::new(problems::figure6b(10).model().unwrap()).unwrap();
    let x = settled(&sim, 200);
    let start = sim.clock_at_cycle(200);
    let mut exact = ContactWork::for_mode(sim.model(), 0).unwrap();
    // the stop mode oscillates at √(λ_N) ≈ √(kN) per unit time; a contact segment is at
    // most a period T = 2π/ω long, so 2000 panels of 20 points resolve it many times over
    let fine = |panels| Quadratured {
        rule: Quadrature::composite(20, panels),
        work: 0.0,
    };
    let (mut q1, mut q2) = (fine(400), fine(800));
    sim.run_from(&x, start, 4, &mut (&mut exact, &mut q1, &mut q2))
        .unwrap();
    assert!(
        exact.contacts.len() >= 4,
        "{} contacts",
        exact.contacts.len()
    );
    // the quadrature's own error, from doubling its panels, is far below the comparison
    let quadrature_error = (q1.work - q2.work).abs();
    let scale = exact.contacts.iter().map(|c| c.work.abs()).sum::<f64>();
    assert!(
        quadrature_error < 1e-12 * scale,
        "{quadrature_error:e} vs {scale:e}"
    );
    // the two routes agree to round-off of the energies involved (the integral is a small
    // difference of mode-1 energies of size ½(v₁⁺)²)
    let v2 = exact.entry_v_squared;
    assert!(
        (exact.total_work - q2.work).abs() < 1e-10 * v2,
        "exact {} quadrature {} (v² = {v2})",
        exact.total_work,
        q2.work
    );
}

#[test]
fn with_one_mode_the_contact_force_is_conservative_and_r_e_is_one() {
    // N = 1: ∫F_c η̇₁ = −Δ(stop energy) = 0 over a whole contact, whatever the damping
    for forced in [problems::figure6b(1), problems::figure4(1)] {
        let sim = Simulator::new(forced.model().unwrap()).unwrap();
        let r = orbit_coefficient(&sim, &DVector::zeros(2), 1000, 20).unwrap();
        let Some(Coefficient::Value(value)) = r.coefficient else {
            panic!("{:?} {:?} {:e}", r.coefficient, r.kind, r.residual)
        };
        assert!((value - 1.0).abs() < 1e-10, "r_E = {value}");
        for c in r.contacts.iter().filter_map(|c| c.coefficient()) {
            assert!((c.value().unwrap() - 1.0).abs() < 1e-10, "{c:?}");
        }
    }
}

#[test]
fn the_contact_force_only_moves_energy_between_modes() {
    // Σ_j ∫F_c,j η̇_j = −Δ(stop energy): zero over whole contacts. Each mode's work comes
    // from its own energy balance, so the sum is a check on every one of them.
    let forced = problems::figure6b(6);
    let sim = Simulator::new(forced.model().unwrap()).unwrap();
    let n = 6;
    let x = settled(&sim, 200);
    let start = sim.clock_at_cycle(200);
    // start and end outside contact so that every contact is whole
    let mut per_mode: Vec<ContactWork> = (0..n)
        .map(|j| ContactWork::for_mode(sim.model(), j).unwrap())
        .collect();
    // a mode the model does not have is bad input, not a panic later
    assert!(ContactWork::for_mode(sim.model(), n).is_err());
    {
        let mut observers: Vec<&mut dyn Observer> = per_mode
            .iter_mut()
            .map(|w| w as &mut dyn Observer)
            .collect();
        let mut all = Many(&mut observers);
        sim.run_from(&x, start, 3, &mut all).unwrap();
    }
    let whole: Vec<usize> = (0..per_mode[0].contacts.len())
        .filter(|&i| {
            per_mode[0].contacts[i].entry.is_some() && per_mode[0].contacts[i].exit.is_some()
        })
        .collect();
    assert!(!whole.is_empty());
    for i in whole {
        let works: Vec<f64> = per_mode.iter().map(|w| w.contacts[i].work).collect();
        let sum: f64 = works.iter().sum();
        let scale: f64 = works.iter().map(|w| w.abs()).sum();
        assert!(
            sum.abs() < 1e-9 * scale,
            "contact {i}: Σ = {sum:e}, scale {scale:e}"
        );
    }
}

/// Several observers behind one.
struct Many<'a, 'b>(&'a mut Vec<&'b mut dyn Observer>);

impl Observer for Many<'_, '_> {
    fn begin(
        &mut self,
        sim: &Simulator,
        clock: &impacting_cantilever::engine::sim::Clock,
        x: &DVector<f64>,
    ) {
        for o in self.0.iter_mut() {
            o.begin(sim, clock, x);
        }
    }
    fn segment(&mut self, seg: &SegmentView) {
        for o in self.0.iter_mut() {
            o.segment(seg);
        }
    }
    fn event(&mut self, e: &impacting_cantilever::engine::sim::EventView) {
        for o in self.0.iter_mut() {
            o.event(e);
        }
    }
}

#[test]
fn the_balance_has_no_real_root_when_mode_one_loses_more_than_it_brought() {
    assert_eq!(
        Coefficient::from_balance(-0.5, 1.0),
        Coefficient::Value(0.0)
    );
    assert_eq!(Coefficient::from_balance(0.0, 0.0), Coefficient::NoContact);
    assert!(matches!(
        Coefficient::from_balance(-0.6, 1.0),
        Coefficient::NoRealValue(r2) if (r2 + 0.2).abs() < 1e-15
    ));
}
