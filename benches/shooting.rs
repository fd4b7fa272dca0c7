//! Issue target: one converged N = 10 orbit with its multipliers at Figure 4's parameters in
//! ≤ 0.5 ms from a start within the basin (single thread).

use criterion::{criterion_group, criterion_main, Criterion};
use impacting_cantilever::problems;
use impacting_cantilever::shooting;
use impacting_cantilever::sim::Simulator;
use nalgebra::DVector;
use std::hint::black_box;

fn orbit(c: &mut Criterion) {
    let sim = Simulator::new(problems::figure4(10).model().unwrap()).unwrap();
    // a start within the basin: 50 periods from rest, a few Newton steps from the orbit
    let start = sim.run(&DVector::zeros(20), 50, &mut ()).unwrap().state;
    c.bench_function("shooting: N = 10 Fig 4 orbit with multipliers", |b| {
        b.iter(|| shooting::shoot(&sim, black_box(&start), 1).unwrap())
    });
}

criterion_group!(benches, orbit);
criterion_main!(benches);
