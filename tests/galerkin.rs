//! Code verification of the Galerkin model (§2.2, §5.1): matrices, forcing projection,
//! the corrected eq (37) amplitude, and the K⁺ eigenvalues of Fig 2.

use impacting_cantilever::model::continuum;
use impacting_cantilever::model::galerkin::{
    self, Forcing, GalerkinModel, GalerkinParams, Region, SpatialProfile,
};
use nalgebra::{DVector, SymmetricEigen};
use std::sync::Arc;

fn k1() -> f64 {
    galerkin::first_modal_stiffness()
}

#[test]
fn secular_eigenvalues_match_a_dense_symmetric_solver() {
    for n in [1, 3, 10, 50] {
        for ratio in [1e-2, 1.0, 100.0, 1e6] {
            let model = GalerkinModel::new(GalerkinParams::new(n, ratio * k1())).unwrap();
            let kp = model.stiffness(Region::Contact);
            let mut dense = SymmetricEigen::new(kp.clone())
                .eigenvalues
                .as_slice()
                .to_vec();
            dense.sort_by(f64::total_cmp);
            let ours =
                galerkin::contact_eigenvalues(model.modal_stiffness().as_slice(), ratio * k1());
            // A backward-stable dense solver is accurate to ~n·ε·‖K⁺‖ in absolute terms.
            let bound = 8.0 * n as f64 * f64::EPSILON * kp.norm();
            for (a, b) in ours.iter().zip(&dense) {
                assert!((a - b).abs() < bound, "n={n} k={ratio}k1: {a} vs {b}");
            }
        }
    }
}

#[test]
fn highest_eigenvalue_tends_to_kn_with_uniform_eigenvector() {
    // §2.3: as k → ∞, λ_N → kN with eigenvector 𝟙/√N. λ_N/(kN) − 1 = O(k_N/(kN)).
    for n in [1, 3, 10] {
        let k = 1e8 * k1();
        let model = GalerkinModel::new(GalerkinParams::new(n, k)).unwrap();
        let lambda = galerkin::contact_eigenvalues(model.modal_stiffness().as_slice(), k);
        let top = lambda[n - 1];
        let kn = model.modal_stiffness()[n - 1];
        assert!((top / (k * n as f64) - 1.0).abs() < 2.0 * kn / (k * n as f64));
        let v = DVector::from_element(n, 1.0 / (n as f64).sqrt());
        let residual = (model.stiffness(Region::Contact) * &v - top * &v).norm() / top;
        assert!(
            residual < 2.0 * kn / (k * n as f64),
            "n={n} residual {residual:e}"
        );
    }
}

#[test]
fn n_equals_one_eigenvalue_is_k1_plus_k() {
    for ratio in [0.01, 1.0, 1e6] {
        let lambda = galerkin::contact_eigenvalues(&[k1()], ratio * k1());
        assert!((lambda[0] / (k1() * (1.0 + ratio)) - 1.0).abs() < 1e-14);
    }
}

#[test]
fn state_matrix_has_the_block_form_of_eq_35() {
    let p = GalerkinParams::new(4, 3.0 * k1())
        .with_zeta1(0.01)
        .with_viscous_damping(0.1);
    let m = GalerkinModel::new(p).unwrap();
    for region in [Region::Free, Region::Contact] {
        let a = m.state_matrix(region);
        let k = m.stiffness(region);
        for i in 0..4 {
            for j in 0..4 {
                assert_eq!(a[(i, j)], 0.0);
                assert_eq!(a[(i, 4 + j)], if i == j { 1.0 } else { 0.0 });
                assert_eq!(a[(4 + i, j)], -k[(i, j)]);
                let c = if i == j {
                    0.2 + m.params().material_damping * m.modal_stiffness()[i]
                } else {
                    0.0
                };
                assert!((a[(4 + i, 4 + j)] + c).abs() <= 4.0 * f64::EPSILON * c.abs());
            }
        }
    }
    // C₁₁ = 2α + 2ζ₁(β₁⁻)²
    let w1 = galerkin::first_frequency();
    assert!((m.damping()[0] - (0.2 + 0.02 * w1)).abs() < 1e-14 * m.damping()[0]);
}

#[test]
fn the_stop_force_is_one_sided_and_continuous_across_the_surface() {
    // The + and − right-hand sides of eq (35), A^±x + F^±, differ by the stop force
    // −(k/4)φ(1)(φ(1)ᵀη − d₀) (eq 1 with the sign of erratum E1): zero on the surface
    // φ(1)ᵀη = d₀, so the vector field is continuous there, and pushing the tip back
    // (negative) when it penetrates.
    let (k, gap) = (10.0, 0.5);
    let m = GalerkinModel::new(GalerkinParams::new(3, k).with_gap(gap)).unwrap();
    let rhs = |region: Region, x: &DVector<f64>| {
        let mut f = m.state_matrix(region) * x;
        let force = m.force(0.3, region);
        for j in 0..3 {
            f[3 + j] += force[j];
        }
        f
    };
    for penetration in [0.0, 0.01, 0.2] {
        // η with φ(1)ᵀη = 2Ση = d₀ + penetration, and some velocity
        let eta = [0.1, 0.2, (gap + penetration) / 2.0 - 0.3];
        let x = DVector::from_vec(vec![eta[0], eta[1], eta[2], 0.4, -0.1, 0.7]);
        assert!(
            (m.switching_function(&x.rows(0, 3).into_owned()).unwrap() - penetration).abs() < 1e-15
        );
        let jump = rhs(Region::Contact, &x) - rhs(Region::Free, &x);
        // round-off of the two right-hand sides: a few ε of their largest term
        let scale = (m.state_matrix(Region::Contact).abs() * x.abs()).amax()
            + m.force(0.3, Region::Contact).amax();
        for j in 0..3 {
            // the stop force on mode j: −(k/4)·φ_j(1)·penetration = −(k/2)·penetration
            let err = (jump[3 + j] + k / 2.0 * penetration).abs();
            assert!(err < 8.0 * f64::EPSILON * scale, "{penetration}: {err:e}");
            assert_eq!(jump[j], 0.0, "displacement rows do not see the stop");
        }
    }
}

#[test]
fn corrected_eq37_forcing_gives_unit_tip_amplitude_at_resonance() {
    let zeta1 = 0.01;
    let w1 = galerkin::first_frequency();
    let p = GalerkinParams::new(10, 100.0 * k1())
        .with_zeta1(zeta1)
        .with_forcing(Forcing::paper(w1));
    let m = GalerkinModel::new(p).unwrap();
    // projects purely onto mode 1 (quadrature error only) with f₁ = ζ₁k₁
    assert!((m.forcing_amplitude()[0] / (zeta1 * k1()) - 1.0).abs() < 1e-13);
    for j in 1..10 {
        assert!(m.forcing_amplitude()[j].abs() < 1e-13 * m.forcing_amplitude()[0]);
    }
    // unconstrained steady-state tip amplitude Σ φ_j(1) |f_j / (k_j − ω² + i C_jj ω)|
    let amp: f64 = (0..10)
        .map(|j| {
            let re = m.modal_stiffness()[j] - w1 * w1;
            let im = m.damping()[j] * w1;
            2.0 * m.forcing_amplitude()[j] / (re * re + im * im).sqrt()
        })
        .sum();
    assert!((amp - 1.0).abs() < 1e-12, "tip amplitude {amp}");
}

#[test]
fn printed_eq37_amplitude_gives_one_over_four_zeta_squared() {
    // Erratum E2: the printed amplitude does not give a unit tip amplitude.
    for zeta1 in [0.01, 0.1] {
        let w1 = galerkin::first_frequency();
        let p = GalerkinParams::new(1, 0.0)
            .with_zeta1(zeta1)
            .with_forcing(Forcing {
                omega: w1,
                profile: SpatialProfile::PaperEq37AsPrinted,
            });
        let m = GalerkinModel::new(p).unwrap();
        let amp = 2.0 * m.forcing_amplitude()[0] / (m.damping()[0] * w1);
        let expected = 1.0 / (4.0 * zeta1 * zeta1);
        assert!((amp / expected - 1.0).abs() < 1e-12, "{amp} vs {expected}");
    }
}

#[test]
fn uniform_load_projection_reproduces_the_static_tip_deflection() {
    // Static cantilever under unit uniform load: w(1) = 1/8 (EI = L = 1). The modal sum
    // Σ φ_j(1) f_j / k_j converges like Σ j⁻⁵; the tail beyond N = 50 is ≈ 5e-10.
    let p = GalerkinParams::new(50, 0.0).with_forcing(Forcing {
        omega: 1.0,
        profile: SpatialProfile::Function(Arc::new(|_| 1.0)),
    });
    let m = GalerkinModel::new(p).unwrap();
    let tip: f64 = (0..50)
        .map(|j| 2.0 * m.forcing_amplitude()[j] / m.modal_stiffness()[j])
        .sum();
    assert!((tip - 0.125).abs() < 1e-8, "tip {tip}");
    // and ∫ψ_j = −2σ_j/β_j (checked by mpmath quadrature for j = 1..3), so with
    // φ_j = (−1)^j ψ_j the projections are ∫φ_j = (−1)^{j+1} 2σ_j/β_j
    for j in 1..=5 {
        let mode = continuum::free_mode(j).unwrap();
        let sign = if j % 2 == 0 { -1.0 } else { 1.0 };
        let expected = sign * 2.0 * mode.sigma / mode.beta;
        assert!(
            (m.forcing_amplitude()[j - 1] - expected).abs() < 1e-13,
            "j={j}"
        );
    }
}

/// Mode 1's damping ratio read off the free-flight state matrix A⁻: its eigenvalue pair
/// of smallest modulus is ω₁(−ζ ± i√(1 − ζ²)), so ζ = −Re λ/|λ|.
fn mode_one_damping_ratio(m: &GalerkinModel) -> f64 {
    let lambda = m.state_matrix(Region::Free).complex_eigenvalues();
    let slowest = lambda
        .iter()
        .min_by(|a, b| a.norm().total_cmp(&b.norm()))
        .unwrap();
    -slowest.re / slowest.norm()
}

#[test]
fn damping_ratio_reading_of_fig9_caption() {
    // Erratum E3: γ = 2ζ₁/(β₁⁻)² gives mode 1 the damping ratio ζ₁ (the Fig 9 caption's
    // ζ₁ = γ(β₁⁻)²/2); the Fig 4 caption's γ = 0.02(β₁⁻)², read literally, gives
    // ζ₁ = 0.01·k₁ ≈ 0.124 instead of 0.01. Both read off the eigenvalues of A⁻; a
    // Hessenberg–QR eigenvalue of a well-separated 2 × 2 block is good to ~1e-15.
    let with_zeta = GalerkinModel::new(GalerkinParams::new(4, 0.0).with_zeta1(0.01)).unwrap();
    assert!((mode_one_damping_ratio(&with_zeta) - 0.01).abs() < 1e-13);
    let mut literal = GalerkinParams::new(4, 0.0);
    literal.material_damping = 0.02 * galerkin::first_frequency();
    let literal = GalerkinModel::new(literal).unwrap();
    let zeta = mode_one_damping_ratio(&literal);
    assert!((zeta - 0.01 * k1()).abs() < 1e-12, "{zeta}");
}

#[test]
fn sign_convention_of_phi() {
    // Erratum E5: ψ_i(1) = 2(−1)^i for the printed ψ_i, so φ_i = (−1)^i ψ_i (not (−1)^{i+1}).
    for i in 1..=6 {
        let psi = continuum::ModeShape::printed(continuum::free_root(i).unwrap());
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        assert!((psi.value(1.0) - 2.0 * sign).abs() < 1e-13);
    }
}

/// The unit of the forced scenes' plots, A_free, is one number for every truncation: the
/// forcing of eq (37) has mode 1's shape, so only mode 1 is forced (to quadrature
/// round-off), and mode 1's free dynamics do not depend on N.
#[test]
fn the_free_tip_amplitude_does_not_depend_on_the_truncation() {
    use impacting_cantilever::model::problems;
    let a1 = problems::figure4(1).model().unwrap().free_tip_amplitude();
    for n in [2, 3, 10, 40] {
        let an = problems::figure4(n).model().unwrap().free_tip_amplitude();
        assert!((an.0 / a1.0 - 1.0).abs() < 1e-12, "N={n}: {an:?} vs {a1:?}");
        assert!((an.1 / a1.1 - 1.0).abs() < 1e-12, "N={n}");
    }
}

#[test]
fn the_quoted_k1_is_the_first_modal_stiffness_to_its_printed_figures() {
    let k1 = impacting_cantilever::model::galerkin::first_modal_stiffness();
    assert!((k1 - 12.3624).abs() <= 0.5e-4, "{k1}");
    assert!(impacting_cantilever::base::report::unit_meaning("k₁")
        .unwrap()
        .contains("12.3624"));
}
