//! Code verification of the exact region flow (eq 36) against nalgebra's matrix
//! exponential of an augmented system that generates the forcing itself.

use impacting_cantilever::engine::flow::RegionFlow;
use impacting_cantilever::model::galerkin::{self, Forcing, GalerkinModel, GalerkinParams, Region};
use nalgebra::DVector;

use crate::common;

/// x(s) from expm of the augmented system ([`common::augmented`]) acting on
/// [x₀; cos θ₀; sin θ₀; 1]: an independent exact solution of ẋ = Ax + b̂ cos ωt + ĉ.
fn expm_solution(
    m: &GalerkinModel,
    region: Region,
    x0: &DVector<f64>,
    phase: f64,
    s: f64,
) -> DVector<f64> {
    let n2 = 2 * m.modes();
    let mut z0 = DVector::zeros(n2 + 3);
    z0.rows_mut(0, n2).copy_from(x0);
    z0[n2] = phase.cos();
    z0[n2 + 1] = phase.sin();
    z0[n2 + 2] = 1.0;
    ((common::augmented(m, region) * s).exp() * z0)
        .rows(0, n2)
        .into_owned()
}

fn check(n: usize, k_over_k1: f64, zeta1: f64, gap: f64, s: f64) -> f64 {
    let k1 = galerkin::first_modal_stiffness();
    let w1 = galerkin::first_frequency();
    let p = GalerkinParams::new(n, k_over_k1 * k1)
        .with_zeta1(zeta1)
        .with_gap(gap)
        .with_forcing(Forcing::paper(2.0 * w1));
    let m = GalerkinModel::new(p).unwrap();
    let mut worst: f64 = 0.0;
    for region in [Region::Free, Region::Contact] {
        let flow = RegionFlow::new(&m, region).unwrap();
        // a deterministic, non-special initial state with O(1) tip displacement
        let x0 = DVector::from_fn(2 * n, |i, _| {
            0.3 * ((i as f64 + 1.0) * 1.7).sin() / (1.0 + i as f64)
        });
        let phase = 0.7;
        let y = flow.modal(&x0, phase);
        let ours = flow.state(&y, phase, s);
        let reference = expm_solution(&m, region, &x0, phase, s);
        let err = (&ours - &reference).amax() / reference.amax().max(x0.amax());
        worst = worst.max(err);
    }
    worst
}

#[test]
fn flow_matches_the_matrix_exponential_for_the_figure_4_parameters() {
    for n in [1, 2, 3, 10] {
        let err = check(n, 100.0, 0.01, 0.0, 0.37);
        // both exact; measured ≤ 2e-13 (N = 10). 1e-12 bounds round-off through cond(V).
        assert!(err < 1e-12, "N={n}: {err:e}");
    }
}

#[test]
fn flow_matches_for_gaps_and_the_damping_range() {
    for zeta1 in [1e-5, 1e-3, 0.1, 0.9] {
        for gap in [0.0, 0.8, -0.3] {
            let err = check(6, 1000.0, zeta1, gap, 0.21);
            // measured ≤ 2e-12 (at ζ₁ = 0.9, where high modes are strongly over-damped)
            assert!(err < 1e-11, "zeta1={zeta1} gap={gap}: {err:e}");
        }
    }
}

#[test]
fn flow_matches_in_stiff_cases() {
    // N = 20 at k = 1e7 k₁ (where unbalanced eigenvectors lose five digits), N = 20 at
    // 1e8 k₁, N = 40 at 1e5 k₁: measured ≤ 4e-11, limited by expm's scaling and
    // squaring of ‖As‖ ~ 1e4; N = 100 measured 1.1e-9 for the same reason.
    assert!(check(20, 1e7, 0.01, 0.0, 2e-4) < 2e-10);
    assert!(check(20, 1e8, 0.01, 0.0, 1e-4) < 2e-10);
    assert!(check(40, 1e5, 0.01, 0.0, 1e-3) < 2e-10);
    assert!(check(100, 1e3, 0.01, 0.0, 1e-2) < 1e-8);
}
