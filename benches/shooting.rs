//! Issue targets: one converged N = 10 orbit with its multipliers at Figure 4's parameters
//! in ≤ 0.5 ms from a start within the basin (single thread); the four continued Figure 5
//! branch sets (N = 1, 2, 3, 10, seeded from the brute-force diagram) in ≤ 5 s on 2 cores;
//! the book's 128 × 128 atlas at stiffness-matched N in ≤ 120 s on 2 cores (ten samples:
//! about 20 minutes).

use criterion::{criterion_group, criterion_main, Criterion};
use impacting_cantilever::analysis::shooting;
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::model::problems;
use impacting_cantilever::results::scenes::fig5::{self, branches, Fig5Params};
use nalgebra::DVector;
use rayon::prelude::*;
use std::hint::black_box;

fn orbit(c: &mut Criterion) {
    let sim = Simulator::new(problems::figure4(10).model().unwrap()).unwrap();
    // a start within the basin: 50 periods from rest, a few Newton steps from the orbit
    // (already converged to the tolerance from there: no Newton step is taken, so this
    // times one period with its monodromy and the multipliers)
    let start = sim.run(&DVector::zeros(20), 50, &mut ()).unwrap().state;
    c.bench_function("shooting: N = 10 Fig 4 orbit with multipliers", |b| {
        b.iter(|| shooting::shoot(&sim, black_box(&start), 1).unwrap())
    });
    // 10 periods from rest: Newton needs steps (issue target ≤ 80 µs; converged ≤ 30 µs)
    let early = sim.run(&DVector::zeros(20), 10, &mut ()).unwrap().state;
    c.bench_function("shooting: N = 10 Fig 4 orbit from 10 periods", |b| {
        b.iter(|| shooting::shoot(&sim, black_box(&early), 1).unwrap())
    });
}

fn fig5_branches(c: &mut Criterion) {
    // the brute-force diagram is the seeds' source, computed once outside the timing
    let p = Fig5Params::book();
    let d = fig5::compute(&p, &|| {}).unwrap();
    let mut g = c.benchmark_group("continuation");
    g.sample_size(10);
    g.bench_function("Fig 5 branch sets, N = 1, 2, 3, 10 (all threads)", |b| {
        b.iter(|| {
            p.modes
                .par_iter()
                .map(|&n| branches::branch_set(&p, &d, n).unwrap())
                .collect::<Vec<_>>()
        })
    });
    g.finish();
}

fn atlas(c: &mut Criterion) {
    let p = impacting_cantilever::analysis::atlas::AtlasParams::book();
    let mut g = c.benchmark_group("atlas");
    g.sample_size(10);
    g.bench_function("128 x 128 atlas, N matched to k (all threads)", |b| {
        b.iter(|| impacting_cantilever::analysis::atlas::compute(black_box(&p), &Silent).unwrap())
    });
    g.finish();
}

criterion_group!(benches, orbit, fig5_branches, atlas);
criterion_main!(benches);
