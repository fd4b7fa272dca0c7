//! Exact solution of the Galerkin model inside one region: §5.1, eqs (35)–(36).
//!
//! In each region the state x = [η; η̇] obeys the linear, time-invariant
//! ẋ = A x + b̂ cos ωt + ĉ (b̂ = [0; f], ĉ = [0; (k d₀/4)φ(1)] in contact, 0 in free flight).
//! Its solution is written as
//!
//! ```text
//! x(t₀ + s) = x_p(t₀ + s) + V e^{Λs} w,     x_p(t) = Re(X e^{iωt}) + x_s,
//! (iωI − A) X = b̂,   x_s = [K⁻¹(k d₀/4)φ(1); 0],   w = V⁻¹(x(t₀) − x_p(t₀)),
//! ```
//!
//! with A = VΛV⁻¹ from an eigendecomposition (faer) of the *balanced* matrix
//! D⁻¹AD (Parlett–Reinsch, radix 2): the contact matrix couples over-damped high modes
//! with a stiff rank-one stop, and without balancing the eigenvectors lose about five
//! digits at N = 20, k = 10⁷. The paper evaluates the convolution of eq (36) "by parts";
//! the complex solve for X is the same thing in closed form.
//!
//! The coefficients w are carried as 2N real *modal coordinates* (real and imaginary parts
//! of w_k for each conjugate pair, w_k for each real eigenvalue), so projecting a state onto
//! the eigenbasis and back are real 2N×2N matrix–vector products.
//!
//! Only the forcing *phase* enters x_p, so callers pass the phase ωt mod 2π, kept exactly
//! by counting whole periods (see [`crate::sim::clock`]).

use crate::galerkin::{GalerkinModel, Region};
use crate::numerics::polar;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Largest acceptable eigenvector condition estimate ‖V‖‖V⁻¹‖ (1-norms): beyond it the
/// modal solution would lose more than ~6 digits and we refuse rather than mislead.
pub const MAX_EIGENVECTOR_CONDITION: f64 = 1e10;

/// Why a region flow cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlowError {
    /// The eigensolver did not converge.
    #[error("the eigendecomposition of A^± did not converge")]
    Eigen,
    /// The eigenvectors are too ill-conditioned (a nearly defective A, e.g. a mode at
    /// critical damping).
    #[error(
        "the eigenvectors of A^± are too ill-conditioned (condition {0:.1e} > 1e10): a mode is nearly critically damped; perturb ζ₁ slightly"
    )]
    IllConditioned(f64),
    /// An eigenvalue with positive real part: the model would be unstable.
    #[error("A^± has an eigenvalue with positive real part ({0:e}): check the damping")]
    Unstable(f64),
}

/// One real term of the homogeneous solution: a complex-conjugate pair of eigenvalues
/// (two real modal coordinates, the real and imaginary part of w_k) or a real eigenvalue
/// (one coordinate).
#[derive(Debug, Clone, Copy)]
pub struct ModalTerm {
    /// λ_k, the member of a pair with Im λ_k > 0.
    pub lambda: Complex64,
    /// A conjugate pair (`true`) or a real eigenvalue.
    pub pair: bool,
    /// Index of its first real modal coordinate.
    pub slot: usize,
    /// Index k of λ_k in [`RegionFlow::lambda`] and of v_k in [`RegionFlow::v`].
    pub index: usize,
    /// Its tip signal per unit w_k: φ(1)ᵀv_k, doubled for a pair (whose real contribution
    /// is Re(2 φ(1)ᵀv_k w_k e^{λ_k s})).
    pub tip: Complex64,
}

/// The exact flow of one region.
#[derive(Debug, Clone)]
pub struct RegionFlow {
    /// Which region.
    region: Region,
    /// N.
    modes: usize,
    /// Eigenvalues λ_k of A^± (2N, conjugate pairs adjacent or real).
    lambda: Vec<Complex64>,
    /// Right eigenvectors (columns), for the unbalanced A.
    v: DMatrix<Complex64>,
    /// The homogeneous solution's real terms, one per conjugate pair or real eigenvalue.
    terms: Vec<ModalTerm>,
    /// Real 2N×2N map from x − x_p to the real modal coordinates y (the rows of V⁻¹ of
    /// the terms; real and imaginary parts for a pair): one real matrix-vector product.
    to_modal: DMatrix<f64>,
    /// Real 2N×2N map from the evolved coordinates ỹ(s) back to the state: the columns of
    /// V (2 Re v_k and −2 Im v_k for a pair, v_k for a real eigenvalue).
    from_modal: DMatrix<f64>,
    /// X with (iωI − A)X = b̂: the complex amplitude of the forced response.
    forced: DVector<Complex64>,
    /// x_s: the static response to the stop preload.
    static_state: DVector<f64>,
    /// ω.
    omega: f64,
    /// φ(1)ᵀ X_η.
    tip_forced: Complex64,
    /// φ(1)ᵀ η_s.
    tip_static: f64,
    /// ‖V‖₁‖V⁻¹‖₁.
    condition: f64,
}

impl RegionFlow {
    /// Builds the flow of `region` for `model`.
    pub fn new(model: &GalerkinModel, region: Region) -> Result<Self, FlowError> {
        let n = model.modes();
        let a = model.state_matrix(region);
        let (lambda, v) = eigen_balanced(&a)?;
        let v_inv = v.clone().try_inverse().ok_or(FlowError::Eigen)?;
        let condition = norm1(&v) * norm1(&v_inv);
        if !condition.is_finite() || condition > MAX_EIGENVECTOR_CONDITION {
            return Err(FlowError::IllConditioned(condition));
        }
        let scale = lambda.iter().map(|l| l.norm()).fold(0.0, f64::max);
        if let Some(l) = lambda.iter().find(|l| l.re > 1e-12 * scale) {
            return Err(FlowError::Unstable(l.re));
        }
        let omega = model.params().forcing.as_ref().map_or(0.0, |f| f.omega);
        // (iωI − A) X = [0; f], solved directly (not through V, so it does not inherit
        // the eigenvectors' conditioning).
        let mut m = a.map(|x| Complex64::new(-x, 0.0));
        for i in 0..2 * n {
            m[(i, i)] += Complex64::new(0.0, omega);
        }
        let mut rhs = DVector::zeros(2 * n);
        for j in 0..n {
            rhs[n + j] = Complex64::new(model.forcing_amplitude()[j], 0.0);
        }
        let forced = m.lu().solve(&rhs).ok_or(FlowError::Eigen)?;
        let preload = model.stop_preload(region);
        let mut static_state = DVector::zeros(2 * n);
        if region == Region::Contact && preload.iter().any(|p| *p != 0.0) {
            let k = model.stiffness(region);
            let eta = k
                .cholesky()
                .map(|c| c.solve(&preload))
                .ok_or(FlowError::Eigen)?;
            static_state.rows_mut(0, n).copy_from(&eta);
        }
        let tip_of_mode =
            |k: usize| -> Complex64 { (0..n).map(|i| v[(i, k)] * model.tip()[i]).sum() };
        let tip_forced = (0..n).map(|i| forced[i] * model.tip()[i]).sum();
        let tip_static = (0..n).map(|i| static_state[i] * model.tip()[i]).sum();
        let mut terms = Vec::new();
        let mut to_modal = DMatrix::zeros(2 * n, 2 * n);
        let mut from_modal = DMatrix::zeros(2 * n, 2 * n);
        let mut slot = 0;
        for (k, pair) in conjugate_halves(&lambda)? {
            let (row, col) = (v_inv.row(k), v.column(k));
            to_modal.row_mut(slot).copy_from(&row.map(|z| z.re));
            if pair {
                to_modal.row_mut(slot + 1).copy_from(&row.map(|z| z.im));
                // x_h = Re(2 v_k w_k e^{λs}) = 2 Re v_k · Re c − 2 Im v_k · Im c
                from_modal
                    .column_mut(slot)
                    .copy_from(&col.map(|z| 2.0 * z.re));
                from_modal
                    .column_mut(slot + 1)
                    .copy_from(&col.map(|z| -2.0 * z.im));
            } else {
                from_modal.column_mut(slot).copy_from(&col.map(|z| z.re));
            }
            terms.push(ModalTerm {
                lambda: if pair {
                    lambda[k]
                } else {
                    Complex64::new(lambda[k].re, 0.0)
                },
                pair,
                slot,
                index: k,
                tip: tip_of_mode(k) * if pair { 2.0 } else { 1.0 },
            });
            slot += if pair { 2 } else { 1 };
        }
        Ok(Self {
            terms,
            to_modal,
            from_modal,
            region,
            modes: n,
            lambda,
            v,
            forced,
            static_state,
            omega,
            tip_forced,
            tip_static,
            condition,
        })
    }

    /// Which region.
    pub fn region(&self) -> Region {
        self.region
    }

    /// N.
    pub fn modes(&self) -> usize {
        self.modes
    }

    /// Eigenvalues λ_k of A^± (2N, conjugate pairs adjacent or real).
    pub fn eigenvalues(&self) -> &[Complex64] {
        &self.lambda
    }

    /// Right eigenvectors V (columns) of A^±.
    pub fn eigenvectors(&self) -> &DMatrix<Complex64> {
        &self.v
    }

    /// The homogeneous solution's real terms, one per conjugate pair or real eigenvalue.
    pub fn terms(&self) -> &[ModalTerm] {
        &self.terms
    }

    /// X with (iωI − A)X = b̂: the complex amplitude of the forced response.
    pub fn forced(&self) -> &DVector<Complex64> {
        &self.forced
    }

    /// x_s: the static response to the stop preload.
    pub fn static_state(&self) -> &DVector<f64> {
        &self.static_state
    }

    /// ω (0 without forcing).
    pub fn omega(&self) -> f64 {
        self.omega
    }

    /// φ(1)ᵀX_η: the complex amplitude of the forced tip response.
    pub fn tip_forced(&self) -> Complex64 {
        self.tip_forced
    }

    /// φ(1)ᵀη_s: the static tip displacement under the stop preload.
    pub fn tip_static(&self) -> f64 {
        self.tip_static
    }

    /// ‖V‖₁‖V⁻¹‖₁: the modal solution is accurate to about this times ε.
    pub fn condition(&self) -> f64 {
        self.condition
    }

    /// x_p at forcing phase θ = ωt: Re(X e^{iθ}) + x_s.
    pub fn particular(&self, phase: f64) -> DVector<f64> {
        let e = polar(1.0, phase);
        DVector::from_iterator(
            2 * self.modes,
            self.forced
                .iter()
                .zip(self.static_state.iter())
                .map(|(x, s)| (x * e).re + s),
        )
    }

    /// The real modal coordinates y of state `x` at forcing phase θ: the real and
    /// imaginary parts of w = V⁻¹(x − x_p(θ)) over the terms.
    pub fn modal(&self, x: &DVector<f64>, phase: f64) -> DVector<f64> {
        &self.to_modal * (x - self.particular(phase))
    }

    /// The complex coefficient w_k of a term.
    pub fn coefficient(&self, y: &DVector<f64>, term: &ModalTerm) -> Complex64 {
        if term.pair {
            Complex64::new(y[term.slot], y[term.slot + 1])
        } else {
            Complex64::new(y[term.slot], 0.0)
        }
    }

    /// The state s after a point with modal coordinates `y` and forcing phase θ.
    pub fn state(&self, y: &DVector<f64>, phase: f64, s: f64) -> DVector<f64> {
        let mut evolved = DVector::zeros(y.len());
        for t in &self.terms {
            let e = decay(t.lambda.re * s);
            if e == 0.0 {
                continue;
            }
            if t.pair {
                let c = self.coefficient(y, t) * polar(e, t.lambda.im * s);
                evolved[t.slot] = c.re;
                evolved[t.slot + 1] = c.im;
            } else {
                evolved[t.slot] = y[t.slot] * e;
            }
        }
        let mut x = self.particular(phase + self.omega * s);
        x.gemv(1.0, &self.from_modal, &evolved, 1.0);
        x
    }
}

/// e^x for x ≤ 0, flushed to zero below the double range (libm's underflow path is slow,
/// and fast over-damped modes reach x ≪ −745 within one segment).
pub fn decay(x: f64) -> f64 {
    if x < -700.0 {
        0.0
    } else {
        x.exp()
    }
}

/// Indices of eigenvalues with Im ≥ 0, each marked as a conjugate pair or a real one
/// (an error if a complex eigenvalue has no partner: the eigensolver failed).
fn conjugate_halves(lambda: &[Complex64]) -> Result<Vec<(usize, bool)>, FlowError> {
    let mut used = vec![false; lambda.len()];
    let mut half = Vec::new();
    for k in 0..lambda.len() {
        if used[k] {
            continue;
        }
        used[k] = true;
        if lambda[k].im == 0.0 {
            half.push((k, false));
            continue;
        }
        // its conjugate partner: the closest unused eigenvalue to conj(λ_k)
        let partner = (0..lambda.len())
            .filter(|&j| !used[j])
            .min_by(|&a, &b| {
                (lambda[a] - lambda[k].conj())
                    .norm()
                    .total_cmp(&(lambda[b] - lambda[k].conj()).norm())
            })
            .ok_or(FlowError::Eigen)?;
        used[partner] = true;
        half.push((if lambda[k].im > 0.0 { k } else { partner }, true));
    }
    Ok(half)
}

fn norm1(m: &DMatrix<Complex64>) -> f64 {
    m.column_iter()
        .map(|c| c.iter().map(|z| z.norm()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Parlett–Reinsch balancing (radix 2, as LAPACK's gebal without permutation): returns
/// the diagonal d with D⁻¹AD balanced. Powers of two keep the scaling exact.
pub fn balance(a: &DMatrix<f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut b = a.clone();
    let mut d = vec![1.0; n];
    loop {
        let mut converged = true;
        for i in 0..n {
            let c: f64 = (0..n).filter(|&j| j != i).map(|j| b[(j, i)].abs()).sum();
            let r: f64 = (0..n).filter(|&j| j != i).map(|j| b[(i, j)].abs()).sum();
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let s = c + r;
            let (mut f, mut cc) = (1.0, c);
            while cc < r / 2.0 {
                f *= 2.0;
                cc *= 4.0;
            }
            while cc > r * 2.0 {
                f /= 2.0;
                cc /= 4.0;
            }
            if (c * f + r / f) < 0.95 * s {
                converged = false;
                d[i] *= f;
                for j in 0..n {
                    b[(i, j)] /= f;
                    b[(j, i)] *= f;
                }
            }
        }
        if converged {
            return d;
        }
    }
}

/// Eigenvalues and right eigenvectors of a real matrix, computed on its balanced form.
pub fn eigen_balanced(a: &DMatrix<f64>) -> Result<(Vec<Complex64>, DMatrix<Complex64>), FlowError> {
    let n = a.nrows();
    let d = balance(a);
    let balanced = faer::Mat::<f64>::from_fn(n, n, |i, j| a[(i, j)] * d[j] / d[i]);
    let evd = balanced.eigen().map_err(|_| FlowError::Eigen)?;
    let s = evd.S();
    let u = evd.U();
    let lambda: Vec<Complex64> = (0..n).map(|k| s[k]).collect();
    // eigenvectors of A are D times those of D⁻¹AD
    let v = DMatrix::from_fn(n, n, |i, k| u[(i, k)] * d[i]);
    Ok((lambda, v))
}
