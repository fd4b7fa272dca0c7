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
//! **Critical damping.** Where a pair of eigenvalues nearly coincides on the real axis and
//! its eigenvectors become nearly parallel (a mode at or near critical damping, in either
//! region), the pair is replaced by a 2 × 2 real block on its invariant plane
//! ([`block`]), whose exponential is exact through the coalescence. The eigenvector
//! condition then stays moderate at every damping.
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

pub mod block;

pub use block::Block2;

/// What kind of real term of the homogeneous solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TermKind {
    /// A complex-conjugate pair of eigenvalues: two real modal coordinates, the real and
    /// imaginary part of w_k.
    Pair,
    /// A real eigenvalue: one coordinate.
    Real,
    /// A nearly defective pair (critical damping) as a 2 × 2 real block on its invariant
    /// plane W: two coordinates, evolved by e^{Bs}.
    Block {
        /// B.
        block: Block2,
        /// φ(1)ᵀW_η: the tip displacement per unit of each coordinate.
        tip: [f64; 2],
        /// The two columns of [`RegionFlow::eigenvectors`] that hold W.
        columns: [usize; 2],
    },
}

/// One real term of the homogeneous solution.
#[derive(Debug, Clone, Copy)]
pub struct ModalTerm {
    /// λ_k (the member of a pair with Im λ_k > 0); μ for a block.
    pub lambda: Complex64,
    /// Pair, real eigenvalue or block.
    pub kind: TermKind,
    /// Index of its first real modal coordinate.
    pub slot: usize,
    /// Index k of λ_k in [`RegionFlow::eigenvalues`] and of its column in
    /// [`RegionFlow::eigenvectors`] (for a block, the first of its two columns).
    pub index: usize,
    /// Its tip signal per unit w_k: φ(1)ᵀv_k, doubled for a pair (whose real contribution
    /// is Re(2 φ(1)ᵀv_k w_k e^{λ_k s})); zero for a block (see [`TermKind::Block`]).
    pub tip: Complex64,
}

impl ModalTerm {
    /// A complex-conjugate pair.
    pub fn is_pair(&self) -> bool {
        self.kind == TermKind::Pair
    }
}

/// Two eigenvalues count as one nearly defective pair when their eigenvectors are nearly
/// parallel and the eigenvalues are within this relative distance (a loose bound that only
/// keeps the inverse iteration for the pair's plane from being pulled elsewhere).
const NEAR_DEFECTIVE_SEPARATION: f64 = 0.5;
/// … with |cos| of the angle between their (balanced) eigenvectors above this: an
/// eigendecomposition of a pair at a smaller angle θ is conditioned like 1/θ ≳ 30.
const NEAR_DEFECTIVE_COSINE: f64 = 0.9995;

/// The exact flow of one region.
#[derive(Debug, Clone)]
pub struct RegionFlow {
    /// Which region.
    region: Region,
    /// N.
    modes: usize,
    /// Eigenvalues λ_k of A^± (2N, conjugate pairs adjacent or real).
    lambda: Vec<Complex64>,
    /// The modal basis of the unbalanced A: right eigenvectors (columns), with each
    /// nearly defective pair's two columns replaced by its invariant plane W.
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
    /// ‖V‖₁‖V⁻¹‖₁ of the modal basis.
    condition: f64,
    /// The largest relative residual ‖AW − WB‖/‖A‖ of a block's invariant plane (0 without).
    plane_residual: f64,
}

impl RegionFlow {
    /// Builds the flow of `region` for `model`.
    pub fn new(model: &GalerkinModel, region: Region) -> Result<Self, FlowError> {
        let n = model.modes();
        let a = model.state_matrix(region);
        let eig = eigen_balanced_parts(&a)?;
        let lambda = eig.lambda.clone();
        let scale = lambda.iter().map(|l| l.norm()).fold(0.0, f64::max);
        if let Some(l) = lambda.iter().find(|l| l.re > 1e-12 * scale) {
            return Err(FlowError::Unstable(l.re));
        }
        // nearly defective pairs: replace their two eigenvector columns by a basis W of the
        // invariant plane (computed in balanced coordinates, W = D·Q)
        let mut v = eig.v.clone();
        let mut blocks: Vec<(usize, usize, Block2)> = Vec::new();
        let mut plane_residual: f64 = 0.0;
        for (i, j) in near_defective_pairs(&lambda, &eig.v_balanced) {
            let start = DMatrix::from_fn(2 * n, 2, |r, c| {
                let u = eig.v_balanced[(r, i)];
                let w = eig.v_balanced[(r, j)];
                match (c, lambda[i].im != 0.0) {
                    (0, _) => u.re,
                    (_, true) => u.im,
                    (_, false) => w.re,
                }
            });
            // a real shift a quarter of the way from the pair to the nearest other eigenvalue
            let mid = 0.5 * (lambda[i] + lambda[j]);
            let nearest = (0..lambda.len())
                .filter(|&k| k != i && k != j)
                .map(|k| (lambda[k] - mid).norm())
                .fold(f64::INFINITY, f64::min);
            let sigma = mid.re + 0.25 * nearest.min(mid.norm());
            // a plane that is not invariant to round-off would make the flow inexact: keep
            // the eigenvectors then (their condition is checked below)
            let Some((q, block, residual)) = block::invariant_plane(&eig.balanced, sigma, start)
            else {
                continue;
            };
            if residual > 1e-13 {
                continue;
            }
            plane_residual = plane_residual.max(residual);
            for c in 0..2 {
                let col = if c == 0 { i } else { j };
                for r in 0..2 * n {
                    v[(r, col)] = Complex64::new(q[(r, c)] * eig.d[r], 0.0);
                }
            }
            blocks.push((i, j, block));
        }
        let v_inv = v.clone().try_inverse().ok_or(FlowError::Eigen)?;
        let condition = norm1(&v) * norm1(&v_inv);
        if !condition.is_finite() || condition > MAX_EIGENVECTOR_CONDITION {
            return Err(FlowError::IllConditioned(condition));
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
            if let Some(&(i, j, block)) = blocks.iter().find(|b| b.0 == k || b.1 == k) {
                // a block covers both members of its pair: emitted once
                if terms.iter().any(|t: &ModalTerm| t.index == i) {
                    continue;
                }
                let tip = [0, 1].map(|c| {
                    let col = if c == 0 { i } else { j };
                    (0..n).map(|r| v[(r, col)].re * model.tip()[r]).sum::<f64>()
                });
                for (c, col) in [i, j].into_iter().enumerate() {
                    to_modal
                        .row_mut(slot + c)
                        .copy_from(&v_inv.row(col).map(|z| z.re));
                    from_modal
                        .column_mut(slot + c)
                        .copy_from(&v.column(col).map(|z| z.re));
                }
                terms.push(ModalTerm {
                    lambda: Complex64::new(block.mu, 0.0),
                    kind: TermKind::Block {
                        block,
                        tip,
                        columns: [i, j],
                    },
                    slot,
                    index: i,
                    tip: Complex64::new(0.0, 0.0),
                });
                slot += 2;
                continue;
            }
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
                kind: if pair { TermKind::Pair } else { TermKind::Real },
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
            plane_residual,
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

    /// ‖V‖₁‖V⁻¹‖₁ of the modal basis: the modal solution is accurate to about this
    /// times ε.
    pub fn condition(&self) -> f64 {
        self.condition
    }

    /// The number of nearly defective pairs treated as 2 × 2 blocks.
    pub fn blocks(&self) -> usize {
        self.terms
            .iter()
            .filter(|t| matches!(t.kind, TermKind::Block { .. }))
            .count()
    }

    /// The largest relative residual of a block's invariant plane (0 without blocks).
    pub fn plane_residual(&self) -> f64 {
        self.plane_residual
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

    /// The complex coefficient w_k of a pair or real term (for a block, its first
    /// coordinate).
    pub fn coefficient(&self, y: &DVector<f64>, term: &ModalTerm) -> Complex64 {
        if term.is_pair() {
            Complex64::new(y[term.slot], y[term.slot + 1])
        } else {
            Complex64::new(y[term.slot], 0.0)
        }
    }

    /// The state s after a point with modal coordinates `y` and forcing phase θ.
    pub fn state(&self, y: &DVector<f64>, phase: f64, s: f64) -> DVector<f64> {
        let mut evolved = DVector::zeros(y.len());
        for t in &self.terms {
            if let TermKind::Block { block, .. } = t.kind {
                let z = block.apply(s, [y[t.slot], y[t.slot + 1]]);
                evolved[t.slot] = z[0];
                evolved[t.slot + 1] = z[1];
                continue;
            }
            let e = decay(t.lambda.re * s);
            if e == 0.0 {
                continue;
            }
            if t.is_pair() {
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

/// An eigendecomposition computed on the balanced form D⁻¹AD.
struct BalancedEigen {
    lambda: Vec<Complex64>,
    /// Eigenvectors of A (D times those of the balanced matrix).
    v: DMatrix<Complex64>,
    /// Eigenvectors of the balanced matrix.
    v_balanced: DMatrix<Complex64>,
    /// The balanced matrix.
    balanced: DMatrix<f64>,
    /// D.
    d: Vec<f64>,
}

fn eigen_balanced_parts(a: &DMatrix<f64>) -> Result<BalancedEigen, FlowError> {
    let n = a.nrows();
    let d = balance(a);
    let balanced = DMatrix::from_fn(n, n, |i, j| a[(i, j)] * d[j] / d[i]);
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| balanced[(i, j)]);
    let evd = m.eigen().map_err(|_| FlowError::Eigen)?;
    let s = evd.S();
    let u = evd.U();
    let lambda: Vec<Complex64> = (0..n).map(|k| s[k]).collect();
    let v_balanced = DMatrix::from_fn(n, n, |i, k| u[(i, k)]);
    // eigenvectors of A are D times those of D⁻¹AD
    let v = DMatrix::from_fn(n, n, |i, k| u[(i, k)] * d[i]);
    Ok(BalancedEigen {
        lambda,
        v,
        v_balanced,
        balanced,
        d,
    })
}

/// Eigenvalues and right eigenvectors of a real matrix, computed on its balanced form.
pub fn eigen_balanced(a: &DMatrix<f64>) -> Result<(Vec<Complex64>, DMatrix<Complex64>), FlowError> {
    let e = eigen_balanced_parts(a)?;
    Ok((e.lambda, e.v))
}

/// Nearly defective pairs (i, j): a complex pair whose eigenvector is nearly real up to a
/// phase, or two close real eigenvalues with nearly parallel eigenvectors — both mean a
/// pair near critical damping. Eigenvalues that are merely close (the slow over-damped
/// modes of material damping crowd near −1/γ) have independent eigenvectors and are
/// left alone. Each eigenvalue joins at most one pair.
fn near_defective_pairs(lambda: &[Complex64], v: &DMatrix<Complex64>) -> Vec<(usize, usize)> {
    let n = lambda.len();
    let cosine = |i: usize, j: usize, conjugate: bool| {
        let (a, b) = (v.column(i), v.column(j));
        let dot: Complex64 = if conjugate {
            a.iter().zip(b.iter()).map(|(x, y)| x * y).sum()
        } else {
            a.iter().zip(b.iter()).map(|(x, y)| x.conj() * y).sum()
        };
        dot.norm() / (a.norm() * b.norm())
    };
    let close = |i: usize, j: usize| {
        (lambda[i] - lambda[j]).norm()
            <= NEAR_DEFECTIVE_SEPARATION * lambda[i].norm().max(lambda[j].norm())
    };
    let mut used = vec![false; n];
    let mut pairs = Vec::new();
    // complex pairs near the real axis: v and v̄ are nearly parallel when vᵀv ≈ |v|²
    for i in 0..n {
        if used[i] || lambda[i].im <= 0.0 {
            continue;
        }
        let partner = (0..n).filter(|&j| !used[j] && j != i).min_by(|&a, &b| {
            (lambda[a] - lambda[i].conj())
                .norm()
                .total_cmp(&(lambda[b] - lambda[i].conj()).norm())
        });
        if let Some(j) = partner {
            if close(i, j) && cosine(i, i, true) > NEAR_DEFECTIVE_COSINE {
                used[i] = true;
                used[j] = true;
                pairs.push((i, j));
            }
        }
    }
    // real pairs: neighbours (within two places) in the sorted real spectrum
    let mut reals: Vec<usize> = (0..n).filter(|&i| lambda[i].im == 0.0).collect();
    reals.sort_by(|&a, &b| lambda[a].re.total_cmp(&lambda[b].re));
    for (p, &i) in reals.iter().enumerate() {
        for &j in reals.iter().skip(p + 1).take(2) {
            if !used[i] && !used[j] && close(i, j) && cosine(i, j, false) > NEAR_DEFECTIVE_COSINE {
                used[i] = true;
                used[j] = true;
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs
}
