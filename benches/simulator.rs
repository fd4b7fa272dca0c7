//! Speed of the exact simulator (issue targets, single-threaded): 1000 forcing periods of
//! the Figure 4 model with N = 10 (target ≤ 10 ms) and of the Figure 6(b) model, N = 20 at
//! k = 1000 k₁ (target ≤ 30 ms); and the reference integrator on the same runs.

use criterion::{criterion_group, criterion_main, Criterion};
use impacting_cantilever::galerkin::{self, Forcing, GalerkinModel, GalerkinParams};
use impacting_cantilever::reference::{self, Tolerances};
use impacting_cantilever::simulator::{Observe, Simulator};
use nalgebra::DVector;
use std::hint::black_box;

fn model(n: usize, k_over_k1: f64, zeta1: f64) -> GalerkinModel {
    let p = GalerkinParams::new(n, k_over_k1 * galerkin::first_modal_stiffness())
        .with_zeta1(zeta1)
        .with_forcing(Forcing::paper(2.0 * galerkin::first_frequency()));
    GalerkinModel::new(p).unwrap()
}

fn simulate(c: &mut Criterion) {
    let mut g = c.benchmark_group("exact_1000_periods");
    g.sample_size(20);
    for (label, n, k, z) in [
        ("fig4_N10", 10, 100.0, 0.01),
        ("fig6b_N20", 20, 1000.0, 0.01),
    ] {
        let sim = Simulator::new(model(n, k, z)).unwrap();
        let x0 = DVector::zeros(2 * n);
        g.bench_function(label, |b| {
            b.iter(|| sim.run(black_box(&x0), 1000, Observe::default()))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("exact_200_periods");
    let sim = Simulator::new(model(10, 100.0, 0.01)).unwrap();
    let x0 = DVector::zeros(20);
    g.bench_function("fig4_N10", |b| {
        b.iter(|| sim.run(black_box(&x0), 200, Observe::default()))
    });
    g.finish();
    let mut g = c.benchmark_group("setup");
    g.bench_function("flows_N20", |b| {
        b.iter(|| Simulator::new(model(20, 1000.0, 0.01)).unwrap())
    });
    g.finish();
}

fn reference_integrator(c: &mut Criterion) {
    let mut g = c.benchmark_group("reference_200_periods");
    g.sample_size(10);
    let m = model(10, 100.0, 0.01);
    let t_end = 200.0 * 2.0 * std::f64::consts::PI / (2.0 * galerkin::first_frequency());
    for rtol in [1e-6, 1e-9, 1e-12] {
        g.bench_function(format!("fig4_N10_rtol{rtol:e}"), |b| {
            b.iter(|| {
                reference::integrate(
                    &m,
                    &DVector::zeros(20),
                    t_end,
                    Tolerances {
                        rtol,
                        atol: rtol * 1e-3,
                    },
                )
            })
        });
    }
    g.finish();
    // The Figure 6(b) model at equal accuracy (~1e-12): DP5 is stability-limited by the
    // over-damped modes (λ down to −8e4), so 20 periods stand for 1000 (×50).
    let mut g = c.benchmark_group("reference_20_periods");
    g.sample_size(10);
    let m = model(20, 1000.0, 0.01);
    let t_end = 20.0 * 2.0 * std::f64::consts::PI / (2.0 * galerkin::first_frequency());
    g.bench_function("fig6b_N20_rtol1e-12", |b| {
        b.iter(|| {
            reference::integrate(
                &m,
                &DVector::zeros(40),
                t_end,
                Tolerances {
                    rtol: 1e-12,
                    atol: 1e-15,
                },
            )
        })
    });
    g.finish();
}

criterion_group!(benches, simulate, reference_integrator);
criterion_main!(benches);
