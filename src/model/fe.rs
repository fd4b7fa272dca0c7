//! An independent discretisation of the beam of §2.1 and §5.1, eqs (1) and (31)–(33):
//! Euler–Bernoulli finite elements, sharing no basis with the Galerkin model.
//!
//! The unit beam (EI = ρA = 1 on 0 ≤ s ≤ 1, clamped at s = 0) is cut into n equal elements
//! with Hermite cubic shape functions (nodal deflection w and slope w'), consistent mass:
//!
//! ```text
//! K_e = 1/h³ [12 6h −12 6h; 6h 4h² −6h 2h²; −12 −6h 12 −6h; 6h 2h² −6h 4h²],
//! M_e = h/420 [156 22h 54 −13h; 22h 4h² 13h −3h²; 54 13h 156 −22h; −13h −3h² −22h 4h²].
//! ```
//!
//! The PDE's damping is C = 2αM + γK (viscous α of eq 1, material γ of eq 31; the stop is
//! undamped, as in the Galerkin model), the stop a one-sided spring k/4 on the tip
//! deflection, the load vector b_i = ∫N_i f ds. The simulation uses the *exact* transform to
//! the 2n free modes of the discrete beam, KΦ = MΦΛ with ΦᵀMΦ = I: then C is diagonal
//! (2α + γλ_j), the stop is the rank-one term (k/4)ttᵀ with t_j the modes' tip deflections,
//! and the engine's exact flow and certified switches apply unchanged
//! ([`GalerkinModel::from_modes`]). All 2n modes are kept, so this is the full
//! finite-element model, not a truncation of it.
//!
//! The eigenproblem is solved through the flexibility form: with K = LLᵀ (Cholesky),
//! L⁻¹ML⁻ᵀq = λ⁻¹q. The low modes are its *largest* eigenvalues and so keep full relative
//! accuracy; the stiffness form would lose eps·λ_max/λ₁ ≈ 10⁻⁶ on mode 1 at n = 100.

use crate::base::numerics::Quadrature;
use crate::error::{self, ParameterError};
use crate::model::continuum;
use crate::model::galerkin::{FreeModes, GalerkinModel, GalerkinParams, SpatialProfile};
use nalgebra::{DMatrix, DVector};

/// Most elements accepted (2n = 400 degrees of freedom). Refining further does not help:
/// the stiffness matrix's round-off grows like eps·h⁻⁴ (mode 1 is 2e-9 off at n = 128,
/// where the h⁴ discretisation error is 6e-11), so beyond n ≈ 64 the error rises again.
pub const MAX_ELEMENTS: usize = 200;

/// Gauss points per element for load vectors: exact for polynomials of degree 15, and
/// accurate to round-off for the smooth profiles used here once h·β ≲ 1.
const GAUSS_PER_ELEMENT: usize = 8;

/// The discretised beam and its free modes.
#[derive(Debug, Clone)]
pub struct FeBeam {
    elements: usize,
    /// λ_j, increasing.
    lambda: Vec<f64>,
    /// Φ: the mass-normalised free modes as columns (nodal w, w' of nodes 1..n), each with
    /// a positive tip deflection.
    shapes: DMatrix<f64>,
}

impl FeBeam {
    /// Assembles the beam with `elements` elements and solves for its free modes.
    ///
    /// # Errors
    /// [`ParameterError`] for `elements` out of 1…[`MAX_ELEMENTS`], or if the generalised
    /// eigenproblem does not converge.
    pub fn new(elements: usize) -> Result<Self, ParameterError> {
        let n = error::count_in_range("finite elements", elements, MAX_ELEMENTS)?;
        let (k, m) = assemble(n);
        let (lambda, shapes) = generalized_eigen(&k, &m).ok_or_else(|| {
            ParameterError::new("finite elements", n, "a count whose eigenproblem converges")
        })?;
        Ok(Self {
            elements: n,
            lambda,
            shapes,
        })
    }

    /// n, the number of elements.
    pub fn elements(&self) -> usize {
        self.elements
    }

    /// The free eigenvalues λ_j (squared frequencies), j = 1..2n.
    pub fn eigenvalues(&self) -> &[f64] {
        &self.lambda
    }

    /// The eigenvalues with a stop spring k/4 on the tip held on (both sides, linear): the
    /// discrete counterpart of (β_i⁺)⁴ from eq (3) at k⁺ = k.
    pub fn contact_eigenvalues(&self, stop_stiffness: f64) -> Option<Vec<f64>> {
        let (mut k, m) = assemble(self.elements);
        let tip = 2 * self.elements - 2;
        k[(tip, tip)] += stop_stiffness / 4.0;
        generalized_eigen(&k, &m).map(|(l, _)| l)
    }

    /// The tip deflection t_j of each mass-normalised mode.
    pub fn tip(&self) -> Vec<f64> {
        self.shapes
            .row(2 * self.elements - 2)
            .iter()
            .copied()
            .collect()
    }

    /// Φᵀb with b_i = ∫₀¹ N_i g ds: the modal coordinates of the L² projection of g onto the
    /// elements (u = M⁻¹b, η = ΦᵀMu = Φᵀb), and also the functional η ↦ ∫g w ds of a
    /// discrete deflection w = Σ_i N_i(Φη)_i.
    ///
    /// # Errors
    /// [`ParameterError`] when a modal coordinate is not finite (`g` not finite somewhere).
    pub fn project(&self, g: &dyn Fn(f64) -> f64) -> Result<DVector<f64>, ParameterError> {
        let b = load_vector(self.elements, g);
        let eta = self.shapes.tr_mul(&b);
        for x in eta.iter() {
            error::finite("projected profile", *x)?;
        }
        Ok(eta)
    }

    /// The modal state [η; η̇] of a beam with deflection w(s) and velocity w_t(s).
    ///
    /// # Errors
    /// [`ParameterError`] when a projection of either profile is not finite.
    pub fn modal_state(
        &self,
        displacement: &dyn Fn(f64) -> f64,
        velocity: &dyn Fn(f64) -> f64,
    ) -> Result<DVector<f64>, ParameterError> {
        let (eta, vel) = (self.project(displacement)?, self.project(velocity)?);
        Ok(DVector::from_iterator(
            2 * eta.len(),
            eta.iter().chain(vel.iter()).copied(),
        ))
    }

    /// The model for the engine, with the PDE parameters of `params` (its `modes` is
    /// ignored: every mode of the discrete beam is kept). Forcing profiles are re-projected
    /// onto the elements; modal amplitudes of the continuum modes are refused.
    ///
    /// # Errors
    /// [`ParameterError`] for α or γ negative or not finite, a forcing given as modal amplitudes,
    /// the printed eq (37) profile without damping, a projection that is not finite, or the checks
    /// of [`GalerkinModel::from_modes`] (a bad k, d₀ or ω).
    pub fn model(&self, params: &GalerkinParams) -> Result<GalerkinModel, ParameterError> {
        let (alpha, gamma) = (params.viscous_damping, params.material_damping);
        error::finite_non_negative("viscous damping α", alpha)?;
        error::finite_non_negative("material damping γ", gamma)?;
        let forcing = match &params.forcing {
            None => DVector::zeros(self.lambda.len()),
            Some(f) => self.project(&profile(&f.profile, alpha, gamma)?)?,
        };
        let modes = FreeModes {
            stiffness: self.lambda.clone(),
            tip: self.tip(),
            damping: self
                .lambda
                .iter()
                .map(|l| 2.0 * alpha + gamma * l)
                .collect(),
            forcing: forcing.iter().copied().collect(),
        };
        GalerkinModel::from_modes(&modes, params.clone())
    }
}

/// The continuum forcing profile f(s) of eq (37), with the continuum's C₁₁ = 2α + γ(β₁⁻)⁴,
/// so both discretisations are driven by the same PDE load.
fn profile(
    p: &SpatialProfile,
    alpha: f64,
    gamma: f64,
) -> Result<Box<dyn Fn(f64) -> f64 + '_>, ParameterError> {
    let phi1 = continuum::free_mode(1)?;
    let b1 = phi1.beta;
    let c11 = 2.0 * alpha + gamma * b1.powi(4);
    Ok(match p {
        SpatialProfile::UnitTipAtResonance => {
            let a = c11 * b1 * b1 / 2.0;
            Box::new(move |s| a * phi1.value(s))
        }
        SpatialProfile::PaperEq37AsPrinted => {
            let zeta1 =
                error::finite_positive("first-mode damping ratio ζ₁", c11 / (2.0 * b1 * b1))?;
            let a = b1.powi(4) / (4.0 * zeta1);
            Box::new(move |s| a * phi1.value(s))
        }
        SpatialProfile::Function(f) => Box::new(move |s| f(s)),
        SpatialProfile::Modal(_) => {
            return Err(ParameterError::new(
                "forcing profile",
                "amplitudes of the continuum modes",
                "a function of s for the finite-element beam",
            ))
        }
    })
}

/// Global K and M with the clamp's two degrees of freedom removed (2n × 2n).
fn assemble(n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
    let h = 1.0 / n as f64;
    let (h2, h3) = (h * h, h * h * h);
    let ke = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h2, -6.0 * h, 2.0 * h2],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h2, -6.0 * h, 4.0 * h2],
    ];
    let me = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h2, 13.0 * h, -3.0 * h2],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h2, -22.0 * h, 4.0 * h2],
    ];
    let dof = 2 * n;
    let (mut k, mut m) = (DMatrix::zeros(dof, dof), DMatrix::zeros(dof, dof));
    for e in 0..n {
        // element e joins nodes e and e + 1; node i's dofs are 2i − 2, 2i − 1 after the clamp
        for a in 0..4 {
            for b in 0..4 {
                let (ga, gb) = (2 * e + a, 2 * e + b);
                if ga < 2 || gb < 2 {
                    continue;
                }
                k[(ga - 2, gb - 2)] += ke[a][b] / h3;
                m[(ga - 2, gb - 2)] += me[a][b] * h / 420.0;
            }
        }
    }
    (k, m)
}

/// Hermite cubics on an element of length h at ξ ∈ [0, 1].
fn shape(xi: f64, h: f64) -> [f64; 4] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        h * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        h * (x3 - x2),
    ]
}

/// b_i = ∫₀¹ N_i g ds, Gauss–Legendre on each element.
fn load_vector(n: usize, g: &dyn Fn(f64) -> f64) -> DVector<f64> {
    let h = 1.0 / n as f64;
    let quad = Quadrature::composite(GAUSS_PER_ELEMENT, n);
    let mut b = DVector::zeros(2 * n);
    for (&s, &w) in quad.nodes.iter().zip(&quad.weights) {
        let e = ((s / h) as usize).min(n - 1);
        let nv = shape(s / h - e as f64, h);
        let gv = g(s);
        for (a, na) in nv.iter().enumerate() {
            let ga = 2 * e + a;
            if ga >= 2 {
                b[ga - 2] += w * na * gv;
            }
        }
    }
    b
}

/// Kφ = λMφ for symmetric positive definite K and M, through the flexibility form (see the
/// module doc): λ increasing, Φ mass-normalised with positive tip deflection.
fn generalized_eigen(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let chol = k.clone().cholesky()?;
    let l = chol.l();
    let x = l.solve_lower_triangular(m)?;
    let g = l.solve_lower_triangular(&x.transpose())?;
    let g = (&g + g.transpose()) * 0.5;
    let eig = g.symmetric_eigen();
    let dof = k.nrows();
    let mut order: Vec<usize> = (0..dof).collect();
    // largest flexibility eigenvalue first = lowest mode first
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let lt = l.transpose();
    let mut lambda = Vec::with_capacity(dof);
    let mut shapes = DMatrix::zeros(dof, dof);
    for (col, &j) in order.iter().enumerate() {
        let nu = eig.eigenvalues[j];
        if nu.is_nan() || nu <= 0.0 {
            return None;
        }
        let phi = lt.solve_upper_triangular(&eig.eigenvectors.column(j).into_owned())?;
        let sign = if phi[dof - 2] < 0.0 { -1.0 } else { 1.0 };
        shapes
            .column_mut(col)
            .copy_from(&(phi * (sign / nu.sqrt())));
        lambda.push(1.0 / nu);
    }
    Some((lambda, shapes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_are_mass_orthonormal_and_stiffness_diagonal() {
        let beam = FeBeam::new(6).unwrap();
        let (k, m) = assemble(6);
        let phi = &beam.shapes;
        let mm = phi.transpose() * &m * phi;
        let kk = phi.transpose() * &k * phi;
        for i in 0..12 {
            for j in 0..12 {
                let id = if i == j { 1.0 } else { 0.0 };
                // the flexibility form's round-off: eigenvector residuals of eps·ν_max in
                // G, divided by √(ν_iν_j) — so eps·√(λ_iλ_j)/λ₁, times the dimension
                let scale = (beam.lambda[i] * beam.lambda[j]).sqrt();
                let bound = 12.0 * f64::EPSILON * scale / beam.lambda[0];
                assert!(
                    (mm[(i, j)] - id).abs() < bound,
                    "M {i} {j} {:e}",
                    mm[(i, j)] - id
                );
                let want = if i == j { beam.lambda[i] } else { 0.0 };
                assert!((kk[(i, j)] - want).abs() < 1e-12 * scale, "K {i} {j}");
            }
        }
    }

    #[test]
    fn load_of_a_constant_integrates_the_shape_functions() {
        // ∫N_w = h on interior nodes and h/2 at the tip: Σ over deflection dofs = 1 − h/2
        let n = 5;
        let b = load_vector(n, &|_| 1.0);
        let total: f64 = (0..n).map(|i| b[2 * i]).sum();
        assert!((total - (1.0 - 0.5 / n as f64)).abs() < 1e-14);
    }
}
