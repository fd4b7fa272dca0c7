//! The two-basis switching truncation (§2.2, first half): its projection and damping
//! identities, the energy it loses at a switch, and its convergence to the Galerkin model's
//! limit at fixed k.

use impacting_cantilever::analysis::convergence::{self, two_basis_runs, Discretisation, Setup};
use impacting_cantilever::base::numerics::Quadrature;
use impacting_cantilever::engine::two_basis::{TwoBasisModel, TwoBasisState};
use impacting_cantilever::model::continuum::{self, ModeShape};
use impacting_cantilever::model::galerkin::{first_modal_stiffness, GalerkinParams, Region};
use nalgebra::{DMatrix, DVector};

fn model(n: usize, k_over_k1: f64, zeta1: f64) -> TwoBasisModel {
    let p = GalerkinParams::new(n, k_over_k1 * first_modal_stiffness()).with_zeta1(zeta1);
    TwoBasisModel::new(p).unwrap()
}

fn signed_constrained(i: usize, k: f64) -> ModeShape {
    let mut m = continuum::constrained_mode(i, k).unwrap();
    if m.value(1.0) < 0.0 {
        m.scale = -m.scale;
    }
    m
}

#[test]
fn projection_matches_greens_identity_and_the_stop_condition() {
    let (n, kk) = (8, 100.0);
    let k = kk * first_modal_stiffness();
    let m = model(n, kk, 0.0);
    let mu = m.constrained_stiffness();
    #[allow(clippy::needless_range_loop)] // i indexes P, μ and ψ(1) alike
    for i in 0..n {
        let psi = signed_constrained(i + 1, k);
        let [_, _, _, d3] = psi.derivatives(1.0);
        // the natural condition of the stop: ψ'''(1) = (k/4)ψ(1), to round-off of the O(β³)
        // terms that cancel in ψ'''
        assert!((d3 - k / 4.0 * psi.value(1.0)).abs() < 1e-12 * psi.beta.powi(3));
        for j in 0..n {
            let lambda = continuum::free_root(j + 1).unwrap().powi(4);
            let closed = k / 4.0 * m.constrained_tip()[i] * 2.0 / (mu[i] - lambda);
            // quadrature against the closed form; the closed form's own round-off is
            // ε·μ_i/|μ_i − λ_j| (a few 1e-15 at N = 8)
            let tol = 1e-14 * (1.0 + mu[i] / (mu[i] - lambda).abs());
            assert!(
                (m.projection()[(i, j)] - closed).abs() < tol,
                "P[{i},{j}] = {} against {closed}",
                m.projection()[(i, j)]
            );
        }
    }
    // each constrained mode is a unit vector: its coefficients on many free modes sum to 1
    // (Parseval); the tail beyond 400 modes is Σ (k/2 ψ(1)/λ_j)² ~ 1e-19
    let psi1 = signed_constrained(1, k);
    let quad = Quadrature::for_wavenumber(400.0 * std::f64::consts::PI);
    let total: f64 = (1..=400)
        .map(|j| {
            let phi = continuum::free_mode(j).unwrap();
            quad.integrate(|s| psi1.value(s) * phi.value(s)).powi(2)
        })
        .sum();
    assert!((total - 1.0).abs() < 1e-12, "Σ P_1j² = {total}");
}

#[test]
fn bending_stiffness_is_the_beams_alone_and_its_ritz_form_is_exact() {
    let (n, kk) = (12, 1000.0);
    let k = kk * first_modal_stiffness();
    let m = model(n, kk, 0.01);
    let kb = m.bending_stiffness();
    let modes: Vec<ModeShape> = (1..=n).map(|i| signed_constrained(i, k)).collect();
    let quad = Quadrature::for_wavenumber(modes[n - 1].beta);
    let scale = m.constrained_stiffness()[n - 1];
    for i in 0..n {
        for j in 0..n {
            let direct =
                quad.integrate(|s| modes[i].derivatives(s)[2] * modes[j].derivatives(s)[2]);
            // ∫ψ_i''ψ_j'' is O(μ): round-off ~1e-14 of the largest μ
            assert!((direct - kb[(i, j)]).abs() < 1e-12 * scale, "K_b[{i},{j}]");
        }
    }
    // Q orthogonal, Q diag(κ) Qᵀ = K_b, κ₁ a Ritz value above the free λ₁
    let q = m.ritz_vectors();
    let eye = q.transpose() * q - DMatrix::identity(n, n);
    assert!(eye.amax() < 1e-13, "QᵀQ − I = {:e}", eye.amax());
    let kappa = m.contact_side().model().modal_stiffness();
    let back = q * DMatrix::from_diagonal(kappa) * q.transpose();
    assert!((back - &kb).amax() < 1e-13 * scale);
    let lambda1 = continuum::free_root(1).unwrap().powi(4);
    // κ₁ is a Ritz value of the free beam in the constrained modes: above λ₁ (far above at
    // a stiff stop, whose modes barely move the tip), and the secular solution agrees with a
    // dense symmetric eigensolver to its round-off ε‖K_b‖
    assert!(
        kappa[0] >= lambda1,
        "κ₁ = {} below λ₁ = {lambda1}",
        kappa[0]
    );
    let dense = kb.clone().symmetric_eigen().eigenvalues;
    let lowest = dense.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        (lowest - kappa[0]).abs() < 1e-13 * scale,
        "{lowest} against {}",
        kappa[0]
    );
}

#[test]
fn contact_flow_is_the_constrained_equations_with_coupled_material_damping() {
    // eigenvalues of the contact side (Ritz coordinates) against the q-form
    // [[0, I], [−diag μ, −(2αI + γK_b)]] assembled directly
    let n = 6;
    let m = model(n, 100.0, 0.05);
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    let mu = DVector::from_column_slice(m.constrained_stiffness());
    a.view_mut((n, 0), (n, n))
        .copy_from(&(-DMatrix::from_diagonal(&mu)));
    a.view_mut((n, n), (n, n))
        .copy_from(&(-m.contact_damping()));
    let mut direct: Vec<_> = a.complex_eigenvalues().iter().copied().collect();
    let mut flow: Vec<_> = m
        .contact_side()
        .flow(Region::Contact)
        .eigenvalues()
        .to_vec();
    let key = |z: &num_complex::Complex64| (z.im, z.re);
    direct.sort_by(|x, y| key(x).partial_cmp(&key(y)).unwrap());
    flow.sort_by(|x, y| key(x).partial_cmp(&key(y)).unwrap());
    for (x, y) in direct.iter().zip(&flow) {
        // two eigensolvers on matrices whose entries reach μ₆ ≈ 6e5: round-off ε·‖A‖/|λ|
        // is ~1e-11 relative for the lowest mode; 1e-10 allows ten times that
        assert!((x - y).norm() < 1e-10 * x.norm(), "{x} against {y}");
    }
    // the coupling is real: without it the damping would be diagonal γμ_i
    let c = m.contact_damping();
    assert!(c[(0, 1)].abs() > 1e-3 * c[(0, 0)]);
}

#[test]
fn a_switch_loses_exactly_the_residuals_kinetic_energy() {
    let (n, kk) = (8, 1000.0);
    let k = kk * first_modal_stiffness();
    let m = model(n, kk, 0.0);
    let mut x = DVector::zeros(2 * n);
    x[n] = 0.5; // w_t = φ₁/2
    let free = TwoBasisState {
        region: Region::Free,
        x,
    };
    let (after, sw) = m.switch(&free, 0.0, 1.0);
    assert_eq!(after.region, Region::Contact);
    // the residual w_t − Σψ_i q̇_i, by quadrature
    let phi1 = continuum::free_mode(1).unwrap();
    let psi: Vec<ModeShape> = (1..=n).map(|i| signed_constrained(i, k)).collect();
    let quad = Quadrature::for_wavenumber(psi[n - 1].beta);
    let residual2 = quad.integrate(|s| {
        let kept: f64 = (0..n).map(|i| psi[i].value(s) * after.x[n + i]).sum();
        (0.5 * phi1.value(s) - kept).powi(2)
    });
    let lost = sw.energy_before - sw.energy_after;
    assert!(
        (lost - 0.5 * residual2).abs() < 1e-13,
        "{lost} against {}",
        0.5 * residual2
    );
    assert!((sw.velocity_lost - residual2 / 0.25).abs() < 1e-12);
    assert_eq!(sw.displacement_lost, 0.0);
}

#[test]
fn undamped_energy_is_conserved_except_at_the_switches() {
    let m = model(10, 100.0, 0.0);
    let (_, _, state, switches) = two_basis_runs::one_contact(&m).unwrap();
    let n = m.modes();
    let e0 = 0.125; // ½|η̇|², η̇ = ½e₁
    let lost: f64 = switches
        .iter()
        .map(|s| s.energy_before - s.energy_after)
        .sum();
    let end = m.energy(&TwoBasisState {
        region: Region::Free,
        x: state.clone(),
    });
    // exact flows between switches: the budget closes to round-off
    assert!((e0 - lost - end).abs() < 1e-14, "{e0} − {lost} ≠ {end}");
    // and the energy carried between the switches is the same on both sides
    assert!((switches[0].energy_after - switches[1].energy_before).abs() < 1e-14);
    assert_eq!(state.len(), 2 * n);
}

#[test]
fn energy_lost_per_switch_falls_like_n_to_the_minus_seven() {
    let lost = |n| {
        let (_, _, _, sw) = two_basis_runs::one_contact(&model(n, 100.0, 0.01)).unwrap();
        sw[0].relative_energy_lost()
    };
    let (a, b) = (lost(8), lost(16));
    let slope = (b / a).ln() / 2f64.ln();
    // measured −6.99 over N = 8…128: the squared tail Σ_{i>N} (k/2μ_i)² ∝ k²N⁻⁷
    assert!((slope + 7.0).abs() < 0.1, "slope {slope}");
    // and it grows like k²
    let (_, _, _, sw) = two_basis_runs::one_contact(&model(16, 1000.0, 0.01)).unwrap();
    let ratio = sw[0].relative_energy_lost() / b;
    assert!(
        ratio > 50.0 && ratio < 200.0,
        "k ratio 10 gives loss ratio {ratio}"
    );
}

#[test]
fn converges_to_the_galerkin_limit_at_fixed_k() {
    let setup = Setup {
        k_over_k1: 100.0,
        zeta1: 0.01,
        omega_over_w1: 2.0,
        periods: 10,
    };
    let tb = convergence::observe(Discretisation::TwoBasis(64), &setup).unwrap();
    let g = convergence::observe(Discretisation::Galerkin(128), &setup).unwrap();
    // both are within their order-3 truncation errors of the common limit (the book's
    // Richardson limits at k = 100k₁). Measured differences between the two: exit tip
    // velocity 7.1e-7 (two-basis N = 64 is 3.1e-7 off the limit, Galerkin N = 128 4.0e-7),
    // contact duration 9.2e-7 relative, forced tip 4.2e-9. The bounds are about twice
    // those, far below the 1e-3…1e-2 differences of N = 8 or of a wrong projection.
    assert!((tb.exit_tip_velocity - g.exit_tip_velocity).abs() < 1.5e-6);
    assert!((tb.contact_duration - g.contact_duration).abs() < 2e-6 * g.contact_duration);
    assert!((tb.forced_tip - g.forced_tip).abs() < 1e-8);
}

#[test]
fn bad_input_is_refused_with_the_parameter_named() {
    let k1 = first_modal_stiffness();
    let err = TwoBasisModel::new(GalerkinParams::new(4, 0.0))
        .unwrap_err()
        .to_string();
    assert!(err.contains("stop stiffness"), "{err}");
    let err = TwoBasisModel::new(GalerkinParams::new(201, k1))
        .unwrap_err()
        .to_string();
    assert!(err.contains("modes N"), "{err}");
    let err = TwoBasisModel::new(GalerkinParams::new(4, f64::INFINITY))
        .unwrap_err()
        .to_string();
    assert!(err.contains("stop stiffness"), "{err}");
}
