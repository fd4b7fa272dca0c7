//! Benchmarks of the foundation: roots of eq (3) and the K⁺ eigenproblem of Fig 2.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use impacting_cantilever::model::{continuum, galerkin};
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use std::hint::black_box;

fn roots(c: &mut Criterion) {
    let k1 = galerkin::first_modal_stiffness();
    let mut g = c.benchmark_group("roots_i1_to_200");
    for (label, k) in [
        ("k=0", 0.0),
        ("k=1e2k1", 1e2 * k1),
        ("k=1e6k1", 1e6 * k1),
        ("k=inf", f64::INFINITY),
    ] {
        g.bench_function(label, |b| {
            b.iter(|| continuum::roots(200, black_box(k)).unwrap())
        });
    }
    g.finish();
}

fn contact_eigenproblem(c: &mut Criterion) {
    let k = 1e3 * galerkin::first_modal_stiffness();
    let mut g = c.benchmark_group("contact_eigenvalues");
    for n in [10, 50, 200] {
        let d: Vec<f64> = (1..=n)
            .map(|j| continuum::modal_stiffness(j).unwrap())
            .collect();
        g.bench_with_input(BenchmarkId::new("secular", n), &d, |b, d| {
            b.iter(|| galerkin::contact_eigenvalues(black_box(d), k))
        });
        let kp =
            DMatrix::from_diagonal(&DVector::from_vec(d.clone())) + DMatrix::from_element(n, n, k);
        g.bench_with_input(BenchmarkId::new("dense_symmetric", n), &kp, |b, kp| {
            b.iter(|| SymmetricEigen::new(black_box(kp.clone())).eigenvalues)
        });
    }
    g.finish();
}

/// `cantilever diff`'s comparison of two key-number sets: linear in the keys (a search per
/// key took 70 s at 80 000); compare the times at 40 000 and 80 000.
fn diff_keys(c: &mut Criterion) {
    use impacting_cantilever::base::report::KeyNumbers;
    use impacting_cantilever::results::diff;
    let make = |n: usize| {
        let mut k = KeyNumbers::default();
        for i in 0..n {
            k.integer(format!("k{i}"), i as i64);
        }
        k
    };
    let mut g = c.benchmark_group("diff");
    g.sample_size(10);
    for n in [40_000, 80_000] {
        let (a, b) = (make(n), make(n));
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |bench, _| {
            bench.iter(|| diff::compare_numbers("big", &a, &b))
        });
    }
    g.finish();
}

criterion_group!(benches, roots, contact_eigenproblem, diff_keys);
criterion_main!(benches);
