//! Code verification of the continuum model (§2.1): roots of eq (3) against independent
//! golden values, mode shapes against their defining properties, and the small-k law (4).

use impacting_cantilever::base::golden::{self, GoldenRoots};
use impacting_cantilever::base::numerics::Quadrature;
use impacting_cantilever::model::continuum::{self, ModeShape};
#[cfg(feature = "plots")]
use impacting_cantilever::results::scenes::spectrum;

/// The accuracy target for roots.
const ROOT_TOL: f64 = 1e-13;

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn roots_match_mpmath_for_k_zero_finite_and_infinite() {
    let g = GoldenRoots::load();
    for (i, b) in GoldenRoots::table(&g.free) {
        assert!(
            rel(continuum::free_root(i).unwrap(), b) < ROOT_TOL,
            "free i={i}"
        );
        assert!(rel(continuum::root(i, 0.0).unwrap(), b) < ROOT_TOL);
    }
    for (i, b) in GoldenRoots::table(&g.clamped_pinned) {
        let ours = continuum::root(i, f64::INFINITY).unwrap();
        assert!(rel(ours, b) < ROOT_TOL, "pinned i={i}");
    }
    let k1: f64 = g.k1.parse().unwrap();
    let mut checked = 0;
    for (ratio, table) in &g.finite_k {
        let r: f64 = ratio.parse().unwrap();
        for (i, b) in GoldenRoots::table(table) {
            let ours = continuum::root(i, r * k1).unwrap();
            assert!(rel(ours, b) < ROOT_TOL, "k={r}k1 i={i}: {ours} vs {b}");
            checked += 1;
        }
    }
    // 6 stiffnesses from 1e-6 k1 to 1e12 k1, each with i up to 200
    assert_eq!(checked, 42);
}

#[test]
fn mpmath_values_agree_with_the_classical_table() {
    // Blevins prints 9 significant figures: half a unit in the last place is the tolerance.
    let g = GoldenRoots::load();
    let free = GoldenRoots::table(&g.free);
    let pinned = GoldenRoots::table(&g.clamped_pinned);
    for i in 0..5 {
        for (table, printed) in [
            (&free, golden::BLEVINS_CLAMPED_FREE[i]),
            (&pinned, golden::BLEVINS_CLAMPED_PINNED[i]),
        ] {
            let half_ulp = 0.5 * 10f64.powi(printed.log10().floor() as i32 - 8);
            assert!(
                (table[i].1 - printed).abs() <= half_ulp * 1.0001,
                "i={}",
                i + 1
            );
        }
    }
}

#[test]
fn large_index_roots_approach_their_asymptotes() {
    // β_i^- − (2i−1)π/2 and β_i^∞ − (4i+1)π/4 are O(e^{−β}): below round-off of β for
    // i ≥ 12, so the roots must equal the asymptotes to a few ulps up to i = 1000.
    use std::f64::consts::PI;
    for i in [12, 100, 500, 1000] {
        let free = (2 * i - 1) as f64 * PI / 2.0;
        let pinned = (4 * i + 1) as f64 * PI / 4.0;
        assert!(rel(continuum::free_root(i).unwrap(), free) < 4.0 * f64::EPSILON);
        assert!(rel(continuum::clamped_pinned_root(i).unwrap(), pinned) < 4.0 * f64::EPSILON);
    }
}

#[test]
fn roots_increase_monotonically_with_stop_stiffness() {
    // Rayleigh: adding stiffness raises every eigenvalue; interlacing bounds it by k = ∞.
    for i in [1, 2, 5, 40] {
        let mut last = continuum::free_root(i).unwrap();
        for e in -6..=12 {
            let b = continuum::root(i, 10f64.powi(e) * 12.36).unwrap();
            assert!(b >= last, "i={i} e={e}");
            last = b;
        }
        assert!(last <= continuum::clamped_pinned_root(i).unwrap());
    }
}

#[test]
fn free_modes_are_orthonormal_by_quadrature() {
    const N: usize = 100;
    let modes: Vec<ModeShape> = (1..=N).map(|i| continuum::free_mode(i).unwrap()).collect();
    let q = Quadrature::for_wavenumber(modes[N - 1].beta);
    let values: Vec<Vec<f64>> = modes
        .iter()
        .map(|m| q.nodes.iter().map(|&s| m.value(s)).collect())
        .collect();
    let mut worst: f64 = 0.0;
    for i in 0..N {
        for j in 0..=i {
            let g: f64 = (0..q.nodes.len())
                .map(|p| q.weights[p] * values[i][p] * values[j][p])
                .sum();
            let expected = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((g - expected).abs());
        }
    }
    // The 1e-10; quadrature (20-point panels per half wave) is at round-off.
    assert!(worst < 1e-10, "worst Gram entry error {worst:e}");
}

#[test]
fn free_modes_have_tip_value_two() {
    for i in 1..=200 {
        let phi = continuum::free_mode(i).unwrap();
        let tip = phi.value(1.0);
        // 1e-12 is the bound; cancellation-free evaluation gives ~1e-15.
        assert!((tip - 2.0).abs() < 1e-12, "phi_{i}(1) = {tip}");
        // the closed-form norm agrees with ∫φ² = 1 (= φ(1)²/4 for the free beam)
        assert!((phi.squared_norm() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn constrained_modes_are_orthonormal_and_satisfy_the_stop_condition() {
    for k_over_k1 in [1.0, 100.0, 1e6] {
        let k = k_over_k1 * continuum::modal_stiffness(1).unwrap();
        let modes: Vec<ModeShape> = (1..=30)
            .map(|i| continuum::constrained_mode(i, k).unwrap())
            .collect();
        let q = Quadrature::for_wavenumber(modes[29].beta);
        for i in 0..30 {
            for j in 0..=i {
                let g = q.integrate(|s| modes[i].value(s) * modes[j].value(s));
                let expected = if i == j { 1.0 } else { 0.0 };
                // the L² orthogonality of a self-adjoint problem, to quadrature round-off
                assert!(
                    (g - expected).abs() < 1e-10,
                    "k={k_over_k1}k1 ({i},{j}) {g}"
                );
            }
            // Shear condition at the stop (d₀ = 0): w'''(1) = +(k/4) w(1). The printed
            // eq (1) has the opposite sign; see the errata chapter.
            let [w, _, w2, w3] = modes[i].derivatives(1.0);
            let scale = modes[i].beta.powi(3);
            assert!((w3 - k / 4.0 * w).abs() < 1e-10 * scale, "stop condition");
            assert!((w3 + k / 4.0 * w).abs() > 1e-3 * (k / 4.0 * w).abs());
            assert!(w2.abs() < 1e-10 * modes[i].beta.powi(2), "moment-free tip");
        }
    }
}

#[test]
fn mode_shapes_stay_finite_and_accurate_for_large_index() {
    // Near the free end, cosh βs ~ e^β overflows a naive evaluation at β ≈ 710; we must
    // stay accurate there. φ_i(1) = 2 holds to round-off even for i = 1000 (β ≈ 3140).
    let phi = continuum::free_mode(1000).unwrap();
    for s in [0.0, 0.3, 0.999, 1.0] {
        assert!(phi.derivatives(s).iter().all(|v| v.is_finite()));
    }
    assert!((phi.value(1.0) - 2.0).abs() < 1e-12);
}

#[test]
#[cfg(feature = "plots")]
fn small_k_law_remainder_is_second_order() {
    let law =
        spectrum::small_k_law(1, &spectrum::SpectrumParams::default().small_k_ladder).unwrap();
    // The issue: fitted slope within 0.1 of 2.
    assert!(
        (law.fitted_order - 2.0).abs() < 0.1,
        "order {}",
        law.fitted_order
    );
    // Second-order perturbation theory fixes the coefficient; at k = 1e-4 k₁ the third-order
    // term is ~k/(k₂ − k₁) ≈ 3e-6 relative, so agreement to 1e-4 is demanded.
    assert!(rel(law.fitted_coefficient, law.predicted_coefficient) < 1e-4);
    for i in [2, 5] {
        let law = spectrum::small_k_law(i, &[1e-4, 1e-3, 1e-2]).unwrap();
        assert!((law.fitted_order - 2.0).abs() < 0.1, "mode {i}");
    }
}

#[test]
fn k2_over_k1_matches_the_paper() {
    // §5.3 prints k₂ ≈ 39.3 k₁: three figures, so ±0.05.
    let r = continuum::modal_stiffness(2).unwrap() / continuum::modal_stiffness(1).unwrap();
    assert!((r - 39.3).abs() < 0.05, "{r}");
}
