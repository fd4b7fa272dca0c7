//! The modal restitution laws (§3–4): every identity the paper states or implies.

use impacting_cantilever::model::restitution::{
    self, collocation, equally_spaced_points, impulse_response, stiffness_limit,
};
use impacting_cantilever::model::{asymptotics, continuum, galerkin};
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Deterministic test vectors (no RNG dependency): smooth but non-special.
fn vectors(n: usize) -> Vec<DVector<f64>> {
    (0..12)
        .map(|k| {
            DVector::from_fn(n, |i, _| {
                ((i * 7 + k * 13) as f64 * 0.61).sin() + 0.3 * (k as f64 - 5.0) / (1.0 + i as f64)
            })
        })
        .collect()
}

/// Round-off bound for an n × n product of O(1) entries.
fn tol(n: usize) -> f64 {
    64.0 * n as f64 * f64::EPSILON
}

/// Φ of eq (12) at the equally spaced points: rows φ(s_j)ᵀ, j < N, and φ(1)ᵀ.
fn collocation_matrix(n: usize) -> DMatrix<f64> {
    let points = equally_spaced_points(n);
    let modes: Vec<_> = (1..=n).map(|i| continuum::free_mode(i).unwrap()).collect();
    DMatrix::from_fn(n, n, |row, j| {
        modes[j].value(if row + 1 == n { 1.0 } else { points[row] })
    })
}

#[test]
fn every_law_obeys_newton_at_the_tip() {
    // φ(1) = 2·𝟙, so the tip velocity is 2·𝟙ᵀη̇ and Newton's law is 𝟙ᵀη̇⁺ = −r 𝟙ᵀη̇⁻.
    for n in [1, 2, 3, 10, 40] {
        for r in [0.0, 0.3, 0.8, 1.0] {
            let laws = [
                impulse_response(n, r).unwrap(),
                stiffness_limit(n, r).unwrap(),
                collocation(n, r, &equally_spaced_points(n)).unwrap(),
            ];
            // the collocation law goes through the inverse of its modal matrix Φ (rows
            // φ(s_j)ᵀ and φ(1)ᵀ): its round-off is amplified by cond(Φ)
            let phi = collocation_matrix(n);
            let sv = phi.clone().singular_values();
            let cond = sv.max() / sv.min();
            for (l, law) in laws.iter().enumerate() {
                let amplification = if l == 2 { cond } else { 1.0 };
                for v in vectors(n) {
                    let post = restitution::apply(law, &v).unwrap();
                    let scale = v.amax() * law.amax().max(1.0);
                    let err = (post.sum() + r * v.sum()).abs();
                    let bound = tol(n) * amplification * scale * n as f64;
                    assert!(
                        err < bound,
                        "law {l} n={n} r={r}: {err:e} (bound {bound:e})"
                    );
                }
            }
        }
    }
}

#[test]
fn stiffness_limit_at_one_equals_impulse_response_at_one() {
    for n in [1, 2, 5, 30] {
        let d = stiffness_limit(n, 1.0).unwrap() - impulse_response(n, 1.0).unwrap();
        assert!(d.amax() < tol(n));
    }
}

#[test]
fn eq24_with_eq21_equals_eq29_and_printed_eq25_is_its_negative() {
    for r_e in [0.0, 0.37, 0.9, 1.0] {
        let v = restitution::two_mode_eigenvectors();
        let eq24 = restitution::from_eigenvectors(&v, r_e).unwrap();
        let eq29 = stiffness_limit(2, r_e).unwrap();
        assert!((&eq24 - &eq29).amax() < tol(2));
        // Erratum E4: eq (25) as printed is −eq (24)
        let printed = restitution::two_mode_eq25_as_printed(r_e);
        assert!((&printed + &eq24).amax() < tol(2));
        if r_e != 1.0 / 3.0 && r_e != 1.0 {
            assert!(
                (&printed - &eq24).amax() > 0.1,
                "the printed sign really differs"
            );
        }
    }
}

#[test]
fn eq28_with_the_eigenvectors_of_k_plus_tends_to_eq29() {
    // "From (26) and given that [V] is orthogonal, it is possible to show (29)": with the
    // actual eigenvectors of K⁺ at finite k the law differs from (29) by O(k_N/(kN)).
    for n in [2, 3, 10] {
        for ratio in [1e4, 1e6, 1e8] {
            let k = ratio * galerkin::first_modal_stiffness();
            let model = galerkin::GalerkinModel::new(galerkin::GalerkinParams::new(n, k)).unwrap();
            let e = SymmetricEigen::new(model.stiffness(galerkin::Region::Contact));
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
            let v = DMatrix::from_fn(n, n, |i, j| e.eigenvectors[(i, order[j])]);
            let law = restitution::from_eigenvectors(&v, 0.8).unwrap();
            let gap = (law - stiffness_limit(n, 0.8).unwrap()).amax();
            let kn = model.modal_stiffness()[n - 1];
            assert!(
                gap < 10.0 * kn / k + 1e-12,
                "n={n} k={ratio}k1: gap {gap:e}"
            );
        }
    }
}

#[test]
fn kinetic_energy_does_not_grow_for_impulse_response_and_stiffness_limit() {
    // KE = |η̇|²/2 (orthonormal modes). −R_IR and −R_N act as −r on 𝟙/√N and as 1 and
    // 2r − 1 on its complement: |·| ≤ 1 for r ∈ [0, 1], and both conserve KE at r = 1.
    for n in [1, 2, 3, 10] {
        for r in [0.0, 0.5, 1.0] {
            for law in [
                impulse_response(n, r).unwrap(),
                stiffness_limit(n, r).unwrap(),
            ] {
                for v in vectors(n) {
                    let (before, after) = (
                        v.norm_squared(),
                        restitution::apply(&law, &v).unwrap().norm_squared(),
                    );
                    assert!(after <= before * (1.0 + tol(n)));
                    if r == 1.0 {
                        assert!(
                            (after - before).abs() <= before * tol(n),
                            "conserved at r = 1"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn collocation_law_can_create_kinetic_energy() {
    // [R]_C is a reflection in a non-orthogonal basis: at r = 1 it does not conserve |η̇|²,
    // and for some velocities it increases it (stated in the restitution-laws chapter).
    let n = 5;
    let law = collocation(n, 1.0, &equally_spaced_points(n)).unwrap();
    let worst = vectors(n)
        .iter()
        .map(|v| restitution::apply(&law, v).unwrap().norm_squared() / v.norm_squared())
        .fold(0.0, f64::max);
    assert!(worst > 1.01, "max KE ratio {worst}");
}

#[test]
fn collocation_keeps_velocities_at_its_points_and_depends_on_them() {
    let n = 4;
    let modes: Vec<_> = (1..=n).map(|i| continuum::free_mode(i).unwrap()).collect();
    let profile =
        |eta: &DVector<f64>, s: f64| -> f64 { (0..n).map(|j| modes[j].value(s) * eta[j]).sum() };
    let points = equally_spaced_points(n);
    let law = collocation(n, 0.6, &points).unwrap();
    for v in vectors(n) {
        let post = restitution::apply(&law, &v).unwrap();
        for &s in &points {
            assert!((profile(&post, s) - profile(&v, s)).abs() < 1e-10 * v.amax());
        }
        assert!((profile(&post, 1.0) + 0.6 * profile(&v, 1.0)).abs() < 1e-10 * v.amax());
    }
    let other = collocation(n, 0.6, &[0.1, 0.2, 0.3]).unwrap();
    assert!(
        (law - other).amax() > 1e-2,
        "non-unique: depends on the points"
    );
}

#[test]
fn bad_inputs_are_errors() {
    assert!(impulse_response(0, 0.5)
        .unwrap_err()
        .to_string()
        .contains("modes N"));
    assert!(stiffness_limit(3, 1.5)
        .unwrap_err()
        .to_string()
        .contains("in [0, 1]"));
    assert!(collocation(3, 0.5, &[0.5])
        .unwrap_err()
        .to_string()
        .contains("N − 1 = 2"));
    assert!(collocation(3, 0.5, &[0.5, 1.0]).is_err());
    assert!(
        collocation(3, 0.5, &[0.5, 0.5]).is_err(),
        "repeated points: singular"
    );
}

#[test]
fn effective_restitution_against_the_exact_one_mode_ratio() {
    // r_e (eq 19) against e^{−απ/ω_d}. Expanding e^{−απε/√(1 + (k₁ − α²)ε²)}:
    // |r_e − exact| = α²π²ε²/2 + [απ(k₁ − α²)/2 − α³π³/6]ε³ + O(ε⁴). The ε³ term overtakes
    // at ε ≈ απ/k₁ ≈ 0.025, so the order is fitted over ε ∈ [1e-5, 1e-3] (where it is
    // < 4%) and must be 2 ± 0.1.
    let (alpha, k1) = (0.1, galerkin::first_modal_stiffness());
    let eps: Vec<f64> = (0..9).map(|i| 10f64.powf(-5.0 + 0.25 * i as f64)).collect();
    let err: Vec<f64> = eps
        .iter()
        .map(|&e| {
            let k = e.powi(-2);
            (asymptotics::effective_restitution(alpha, asymptotics::kappa(k, 1, e), e)
                - asymptotics::exact_one_mode_restitution(alpha, k1, k))
            .abs()
        })
        .collect();
    let lx: Vec<f64> = eps.iter().map(|e| e.ln()).collect();
    let ly: Vec<f64> = err.iter().map(|e| e.ln()).collect();
    let order = impacting_cantilever::base::verification::fitted_slope(&lx, &ly);
    assert!((order - 2.0).abs() < 0.1, "order {order}");
    // the two-term expansion matches up to its remainder, relatively O((k₁ε)²) (measured
    // 1.2e-5 at ε = 1e-3, so 20ε²), plus the round-off of r_e − exact, two numbers near 1
    // (4ε_mach absolute)
    let pi = std::f64::consts::PI;
    for (&e, &err) in eps.iter().zip(&err) {
        let two_terms = alpha * alpha * pi * pi * e * e / 2.0
            + (alpha * pi * (k1 - alpha * alpha) / 2.0 - alpha.powi(3) * pi.powi(3) / 6.0)
                * e.powi(3);
        let bound = 20.0 * e * e + 4.0 * f64::EPSILON / two_terms;
        assert!(
            (err / two_terms - 1.0).abs() < bound,
            "eps={e}: {err:e} vs {two_terms:e}"
        );
    }
}
