//! Speed of the exact simulator (issue targets, single-threaded): 1000 forcing periods of
//! the Figure 4 model with N = 10 (target ≤ 10 ms) and of the Figure 6(b) model, N = 20 at
//! k = 1000 k₁ (target ≤ 30 ms); and the reference integrator on the same runs.

use criterion::{criterion_group, criterion_main, Criterion};
use impacting_cantilever::engine::dopri5::{self, Tolerances};
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::model::galerkin::GalerkinModel;
use impacting_cantilever::model::problems;
use nalgebra::DVector;
use std::hint::black_box;

fn fig4() -> GalerkinModel {
    problems::figure4(10).model().unwrap()
}

fn fig6b() -> GalerkinModel {
    problems::figure6b(20).model().unwrap()
}

fn simulate(c: &mut Criterion) {
    let mut g = c.benchmark_group("exact_1000_periods");
    g.sample_size(20);
    for (label, model) in [("fig4_N10", fig4()), ("fig6b_N20", fig6b())] {
        let x0 = DVector::zeros(2 * model.modes());
        let sim = Simulator::new(model).unwrap();
        g.bench_function(label, |b| {
            b.iter(|| sim.run(black_box(&x0), 1000, &mut ()).unwrap())
        });
    }
    g.finish();
    let mut g = c.benchmark_group("exact_200_periods");
    let sim = Simulator::new(fig4()).unwrap();
    let x0 = DVector::zeros(20);
    g.bench_function("fig4_N10", |b| {
        b.iter(|| sim.run(black_box(&x0), 200, &mut ()).unwrap())
    });
    // with the exact energy budget (what `simulate` pays unless --no-energy)
    g.bench_function("fig4_N10_energy_budget", |b| {
        b.iter(|| {
            let mut e = impacting_cantilever::engine::sim::Energy::default();
            sim.run(black_box(&x0), 200, &mut e).unwrap();
            e.budget
        })
    });
    g.finish();
    let mut g = c.benchmark_group("setup");
    g.bench_function("flows_N20", |b| b.iter(|| Simulator::new(fig6b()).unwrap()));
    // the start-up of a 400-mode model (24 s in an adversarial report; target ~1 s)
    g.sample_size(10);
    let big = problems::figure4(400).model().unwrap();
    g.bench_function("flows_N400", |b| {
        b.iter(|| Simulator::new(big.clone()).unwrap())
    });
    g.finish();
}

/// Stiff stops (issue target: any k ≤ 1e12 k₁ at N ≤ 20 within 50 ms per forcing period,
/// or refused with the reason). Five periods of the Figure 4 forcing from rest, d₀ = 0 (the
/// tip starts on the stop and is pushed into it) and with gaps (bounces, then a slow release
/// from the stop), without the energy budget, and the slowest of them with it (what
/// `simulate` pays unless --no-energy). N = 10 at 1e12 k₁
/// chatters at the contact frequency (~1e5 entries per period) and is refused by
/// `MAX_CONTACTS_PER_PERIOD` after ~1e4: its bench times that refusal.
fn stiff_stops(c: &mut Criterion) {
    let mut g = c.benchmark_group("stiff_stop_5_periods");
    g.sample_size(10);
    // (N, k/k₁, d₀): from rest on the stop, and with a gap (bounces, then the tip settles
    // on the stop and leaves it slowly: the release that once cost a minute per period)
    for (modes, k, gap) in [
        (3, 1e10, 0.0),
        (10, 1e10, 0.0),
        (20, 1e10, 0.0),
        (3, 1e11, 0.0),
        (10, 1e11, 0.0),
        (20, 1e11, 0.0),
        (3, 1e12, 0.0),
        (10, 1e12, 0.0),
        (20, 1e12, 0.0),
        (1, 1e10, 0.0),
        (10, 1e11, 0.006),
        (15, 1e12, 0.0),
        (15, 1e12, 0.006),
        (20, 1e12, 0.003),
    ] {
        let forced = problems::Forced {
            modes,
            k_over_k1: k,
            zeta1: 0.01,
            omega_over_w1: 2.0,
            gap,
            printed_eq37_amplitude: false,
        };
        let sim = Simulator::new(forced.model().unwrap()).unwrap();
        let x0 = DVector::zeros(2 * modes);
        let name = if gap == 0.0 {
            format!("N{modes}_k{k:e}")
        } else {
            format!("N{modes}_k{k:e}_gap{gap}")
        };
        g.bench_function(&name, |b| {
            b.iter(|| {
                let _ = sim.run(black_box(&x0), 5, &mut ());
            })
        });
        // the slowest with the energy budget (the command line's default)
        if matches!((modes, gap), (15, _) | (20, _) | (3, 0.0)) && k == 1e12
            || modes == 10 && k == 1e11
        {
            g.bench_function(format!("{name}_energy_budget"), |b| {
                b.iter(|| {
                    let mut e = impacting_cantilever::engine::sim::Energy::default();
                    let _ = sim.run(black_box(&x0), 5, &mut e);
                    e.budget
                })
            });
        }
    }
    g.finish();
}

fn reference_integrator(c: &mut Criterion) {
    let mut g = c.benchmark_group("reference_200_periods");
    g.sample_size(10);
    let m = fig4();
    let t_end = 200.0 * 2.0 * std::f64::consts::PI / m.omega();
    for rtol in [1e-6, 1e-9, 1e-12] {
        g.bench_function(format!("fig4_N10_rtol{rtol:e}"), |b| {
            b.iter(|| {
                dopri5::integrate(
                    &m,
                    &DVector::zeros(20),
                    t_end,
                    Tolerances {
                        rtol,
                        atol: rtol * 1e-3,
                    },
                )
                .unwrap()
            })
        });
    }
    g.finish();
    // The Figure 6(b) model at equal accuracy (~1e-12): DP5 is stability-limited by the
    // over-damped modes (λ down to −8e4), so 20 periods stand for 1000 (×50).
    let mut g = c.benchmark_group("reference_20_periods");
    g.sample_size(10);
    let m = fig6b();
    let t_end = 20.0 * 2.0 * std::f64::consts::PI / m.omega();
    g.bench_function("fig6b_N20_rtol1e-12", |b| {
        b.iter(|| {
            dopri5::integrate(
                &m,
                &DVector::zeros(40),
                t_end,
                Tolerances {
                    rtol: 1e-12,
                    atol: 1e-15,
                },
            )
            .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, simulate, stiff_stops, reference_integrator);
criterion_main!(benches);
