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
//! Only the forcing *phase* enters x_p, so callers pass the phase ωt mod 2π, kept exactly
//! by counting whole periods (see [`crate::simulator`]).

use crate::galerkin::{GalerkinModel, Region};
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

/// The exact flow of one region.
#[derive(Debug, Clone)]
pub struct RegionFlow {
    /// Which region.
    pub region: Region,
    /// N.
    pub modes: usize,
    /// Eigenvalues λ_k of A^± (2N, conjugate pairs adjacent or real).
    pub lambda: Vec<Complex64>,
    /// Right eigenvectors (columns), for the unbalanced A.
    pub v: DMatrix<Complex64>,
    /// V⁻¹.
    pub v_inv: DMatrix<Complex64>,
    /// Real and imaginary parts of the rows of V⁻¹ at the half-spectrum indices, in the
    /// order of `half`, contiguous: a segment's set-up is two real dot products per row.
    pub v_inv_half: Vec<(Vec<f64>, Vec<f64>)>,
    /// Columns of V for the complex pairs (index, real part, imaginary part), contiguous.
    state_pairs: Vec<(usize, Vec<f64>, Vec<f64>)>,
    /// Columns of V for the real eigenvalues (index, column), real arithmetic.
    state_reals: Vec<(usize, Vec<f64>)>,
    /// X with (iωI − A)X = b̂: the complex amplitude of the forced response.
    pub forced: DVector<Complex64>,
    /// x_s: the static response to the stop preload.
    pub static_state: DVector<f64>,
    /// ω.
    pub omega: f64,
    /// φ(1)ᵀ V_η (the tip displacement of each eigenvector).
    pub tip_of_mode: Vec<Complex64>,
    /// φ(1)ᵀ X_η.
    pub tip_forced: Complex64,
    /// φ(1)ᵀ η_s.
    pub tip_static: f64,
    /// Indices k of the eigenvalues kept in real sums: Im λ_k ≥ 0, with the weight 2 for a
    /// complex pair and 1 for a real eigenvalue.
    pub half: Vec<(usize, f64)>,
    /// ‖V‖₁‖V⁻¹‖₁.
    pub condition: f64,
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
        let omega = model.params.forcing.as_ref().map_or(0.0, |f| f.omega);
        // (iωI − A) X = [0; f], solved directly (not through V, so it does not inherit
        // the eigenvectors' conditioning).
        let mut m = a.map(|x| Complex64::new(-x, 0.0));
        for i in 0..2 * n {
            m[(i, i)] += Complex64::new(0.0, omega);
        }
        let mut rhs = DVector::zeros(2 * n);
        for j in 0..n {
            rhs[n + j] = Complex64::new(model.forcing_amplitude[j], 0.0);
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
        let tip_of_mode = (0..2 * n)
            .map(|k| (0..n).map(|i| v[(i, k)] * model.tip[i]).sum())
            .collect();
        let tip_forced = (0..n).map(|i| forced[i] * model.tip[i]).sum();
        let tip_static = (0..n).map(|i| static_state[i] * model.tip[i]).sum();
        let half = conjugate_halves(&lambda);
        let v_inv_half = half
            .iter()
            .map(|&(k, _)| {
                let row = v_inv.row(k);
                (
                    row.iter().map(|z| z.re).collect(),
                    row.iter().map(|z| z.im).collect(),
                )
            })
            .collect();
        let mut state_pairs = Vec::new();
        let mut state_reals = Vec::new();
        for &(k, weight) in &half {
            let col = v.column(k);
            if weight == 1.0 {
                state_reals.push((k, col.iter().map(|z| z.re).collect()));
            } else {
                state_pairs.push((
                    k,
                    col.iter().map(|z| 2.0 * z.re).collect(),
                    col.iter().map(|z| 2.0 * z.im).collect(),
                ));
            }
        }
        Ok(Self {
            v_inv_half,
            state_pairs,
            state_reals,
            region,
            modes: n,
            lambda,
            v,
            v_inv,
            forced,
            static_state,
            omega,
            tip_of_mode,
            tip_forced,
            tip_static,
            half,
            condition,
        })
    }

    /// x_p at forcing phase θ = ωt: Re(X e^{iθ}) + x_s.
    pub fn particular(&self, phase: f64) -> DVector<f64> {
        let e = Complex64::from_polar(1.0, phase);
        DVector::from_iterator(
            2 * self.modes,
            self.forced
                .iter()
                .zip(self.static_state.iter())
                .map(|(x, s)| (x * e).re + s),
        )
    }

    /// Homogeneous coefficients w = V⁻¹(x − x_p(θ)) for state `x` at phase θ.
    pub fn coefficients(&self, x: &DVector<f64>, phase: f64) -> DVector<Complex64> {
        let r = (x - self.particular(phase)).map(|v| Complex64::new(v, 0.0));
        &self.v_inv * r
    }

    /// The state s after a point with coefficients `w` and phase θ (only the
    /// half-spectrum entries of `w` are read; the others are their conjugates).
    pub fn state(&self, w: &DVector<Complex64>, phase: f64, s: f64) -> DVector<f64> {
        let mut x = self.particular(phase + self.omega * s);
        for (k, re, im) in &self.state_pairs {
            let l = self.lambda[*k];
            let c = w[*k] * Complex64::from_polar(decay(l.re * s), l.im * s);
            for (xi, (a, b)) in x.iter_mut().zip(re.iter().zip(im)) {
                *xi += a * c.re - b * c.im;
            }
        }
        for (k, col) in &self.state_reals {
            let c = w[*k].re * decay(self.lambda[*k].re * s);
            if c != 0.0 {
                for (xi, a) in x.iter_mut().zip(col) {
                    *xi += a * c;
                }
            }
        }
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

/// Indices of eigenvalues with Im ≥ 0 and their weights in a real sum (2 for a pair).
fn conjugate_halves(lambda: &[Complex64]) -> Vec<(usize, f64)> {
    let mut used = vec![false; lambda.len()];
    let mut half = Vec::new();
    for k in 0..lambda.len() {
        if used[k] {
            continue;
        }
        used[k] = true;
        if lambda[k].im == 0.0 {
            half.push((k, 1.0));
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
            .expect("complex eigenvalues of a real matrix come in pairs");
        used[partner] = true;
        half.push((if lambda[k].im > 0.0 { k } else { partner }, 2.0));
    }
    half
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
