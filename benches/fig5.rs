//! The book-resolution Figure 5 sweep (200 k × 8 starts × 1050 periods × N = 1, 2, 3, 10)
//! on all cores. Target (issue): ≤ 60 s on the 2-core machine.

use criterion::{criterion_group, criterion_main, Criterion};
use impacting_cantilever::results::scenes::fig5::{compute, Fig5Params};
use std::time::Duration;

fn fig5(c: &mut Criterion) {
    let mut g = c.benchmark_group("fig5");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(1));
    g.measurement_time(Duration::from_secs(1));
    g.bench_function("book_resolution", |b| {
        b.iter(|| compute(&Fig5Params::book(), &|| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, fig5);
criterion_main!(benches);
