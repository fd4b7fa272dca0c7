//! The modal basis of a region: eigenvalues and eigenvectors of A^±, with each nearly
//! defective pair (critical damping) replaced by its invariant plane and a 2 × 2 block.
//!
//! - Free flight (A⁻): the modes are uncoupled, so the basis is written down mode by mode
//!   in closed form — the eigenvalues of [[0, 1], [−k_j, −C_jj]], their eigenvectors, and,
//!   near critical damping (C_jj² ≈ 4k_j), the mode's own plane as a block. No dense
//!   eigensolver, so it costs O(N²) to fill and is exact to round-off at any damping.
//! - Contact (A⁺): a dense eigendecomposition of the balanced matrix (faer), nearly
//!   defective pairs found by the angle between their eigenvectors and replaced by their
//!   invariant plane (inverse subspace iteration, [`super::block`]).

use super::block::{self, Block2};
use super::{FlowError, NEAR_DEFECTIVE_COSINE, NEAR_DEFECTIVE_SEPARATION};
use crate::model::galerkin::{GalerkinModel, Region};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// A region's modal basis.
pub struct ModalBasis {
    /// Eigenvalues (2N).
    pub lambda: Vec<Complex64>,
    /// Eigenvectors as columns, a block's two columns holding its plane W.
    pub v: DMatrix<Complex64>,
    /// Blocks: (column i, column j, B).
    pub blocks: Vec<(usize, usize, Block2)>,
    /// The largest relative residual of a block's plane.
    pub plane_residual: f64,
}

/// Free flight, mode by mode (see the module doc).
pub fn free(model: &GalerkinModel) -> ModalBasis {
    let n = model.modes();
    let mut lambda = vec![Complex64::new(0.0, 0.0); 2 * n];
    let mut v = DMatrix::zeros(2 * n, 2 * n);
    let mut blocks = Vec::new();
    for j in 0..n {
        let (k, c) = (model.modal_stiffness()[j], model.damping()[j]);
        let (i0, i1) = (2 * j, 2 * j + 1);
        let disc = 0.25 * c * c - k;
        // the pair's relative separation 2√|disc|/√k; nearly defective below the same
        // eigenvector angle as in contact (cos θ > 0.9995 ⇔ separation ≲ 0.06)
        if 2.0 * disc.abs().sqrt() < 0.06 * k.sqrt() {
            // the mode's plane with W = [e_η, √k e_η̇]: B = [[0, √k], [−√k, −c]]
            let r = k.sqrt();
            v[(j, i0)] = Complex64::new(1.0, 0.0);
            v[(n + j, i1)] = Complex64::new(r, 0.0);
            let block = Block2::new([[0.0, r], [-r, -c]]);
            let (l1, l2) = block.eigenvalues();
            lambda[i0] = l1;
            lambda[i1] = l2;
            blocks.push((i0, i1, block));
            continue;
        }
        let pair = if disc < 0.0 {
            let l = Complex64::new(-0.5 * c, (-disc).sqrt());
            [l, l.conj()]
        } else {
            // the larger root without cancellation, the smaller from λ₊λ₋ = k
            let fast = -0.5 * c - disc.sqrt();
            [Complex64::new(k / fast, 0.0), Complex64::new(fast, 0.0)]
        };
        for (col, l) in [i0, i1].into_iter().zip(pair) {
            let norm = (1.0 + l.norm_sqr()).sqrt();
            lambda[col] = l;
            v[(j, col)] = Complex64::new(1.0 / norm, 0.0);
            v[(n + j, col)] = l / norm;
        }
    }
    ModalBasis {
        lambda,
        v,
        blocks,
        plane_residual: 0.0,
    }
}

/// Any region: a dense eigendecomposition with nearly defective pairs as blocks (see the
/// module doc).
///
/// # Errors
/// [`FlowError::Eigen`] when the dense eigensolver does not converge.
pub fn general(a: &DMatrix<f64>) -> Result<ModalBasis, FlowError> {
    let n2 = a.nrows();
    let eig = eigen_balanced_parts(a)?;
    let lambda = eig.lambda.clone();
    // nearly defective pairs: replace their two eigenvector columns by a basis W of the
    // invariant plane (computed in balanced coordinates, W = D·Q)
    let mut v = eig.v.clone();
    let mut blocks: Vec<(usize, usize, Block2)> = Vec::new();
    let mut plane_residual: f64 = 0.0;
    for (i, j) in near_defective_pairs(&lambda, &eig.v_balanced) {
        let start = DMatrix::from_fn(n2, 2, |r, c| {
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
        // the eigenvectors then (their condition is checked by the caller)
        let Some((q, block, residual)) = block::invariant_plane(&eig.balanced, sigma, start) else {
            continue;
        };
        if residual > 1e-13 {
            continue;
        }
        plane_residual = plane_residual.max(residual);
        for c in 0..2 {
            let col = if c == 0 { i } else { j };
            for r in 0..n2 {
                v[(r, col)] = Complex64::new(q[(r, c)] * eig.d[r], 0.0);
            }
        }
        blocks.push((i, j, block));
    }
    Ok(ModalBasis {
        lambda,
        v,
        blocks,
        plane_residual,
    })
}

/// Contact (A⁺): the dense decomposition of [`general`], each eigenpair outside a block
/// then refined on the quadratic eigenproblem's secular equation (see `secular_root`),
/// its eigenvector rewritten in closed form, v = [Q(λ)⁻¹φ; λQ(λ)⁻¹φ].
///
/// The dense solver is backward stable for A⁺, whose norm the stop sets (‖A⁺‖ ~ kN/4):
/// at N = 20, 1e11k₁ its slowest pair came out with a relative error of 7e-7 (~50κε), and
/// a flow built on it is the exact flow of a slightly different beam. With the particular
/// solution's own error (see `structured_solve` in [`super`]) each long contact — the tip
/// resting on the stop for a few hundredths — gained ~1e-6 of the stored energy against
/// a Runge–Kutta integration of the same ODE from the same state (which closed its own
/// budget to 1e-18), and the run's energy imbalance was 1.6e-6; refined, 4e-12.
///
/// # Errors
/// [`FlowError::Eigen`] when the dense eigensolver does not converge.
pub fn contact(model: &GalerkinModel) -> Result<ModalBasis, FlowError> {
    let mut basis = general(&model.state_matrix(Region::Contact))?;
    let quarter_k = model.params().stop_stiffness / 4.0;
    if quarter_k <= 0.0 {
        return Ok(basis);
    }
    let n2 = basis.lambda.len();
    let n = n2 / 2;
    let (phi, c, d) = (model.tip(), model.damping(), model.modal_stiffness());
    let mut in_block = vec![false; n2];
    for &(i, j, _) in &basis.blocks {
        in_block[i] = true;
        in_block[j] = true;
    }
    let refined: Vec<Option<Complex64>> = (0..n2)
        .map(|i| {
            (!in_block[i])
                .then(|| secular_root(basis.lambda[i], quarter_k, phi, c, d))
                .flatten()
        })
        .collect();
    for i in 0..n2 {
        let Some(l) = refined[i] else { continue };
        // two starts that converged to one root: keep the dense solver's pair
        let collides = (0..n2)
            .any(|j| j != i && refined[j].is_some_and(|m| (m - l).norm() <= 1e-10 * l.norm()));
        if collides {
            continue;
        }
        // v = [Q(λ)⁻¹φ; λQ(λ)⁻¹φ], Q(λ) = diag(λ² + c_jλ + d_j), scaled to the old
        // column's norm (the condition estimate stays the dense basis's)
        let column: Vec<Complex64> = (0..n).map(|j| phi[j] / (l * l + c[j] * l + d[j])).collect();
        let new_norm = column
            .iter()
            .map(|z| z.norm_sqr() * (1.0 + l.norm_sqr()))
            .sum::<f64>()
            .sqrt();
        let old_norm = basis.v.column(i).norm();
        if !(new_norm.is_finite() && new_norm > 0.0) {
            continue;
        }
        let scale = old_norm / new_norm;
        for (j, &z) in column.iter().enumerate() {
            basis.v[(j, i)] = z * scale;
            basis.v[(n + j, i)] = z * l * scale;
        }
        basis.lambda[i] = l;
    }
    Ok(basis)
}

/// The root near `start` of the contact secular equation
/// h(λ) = 4/k + Σ_j φ_j²/(λ² + c_jλ + d_j) = 0, whose roots are the eigenvalues of
/// λ²I + λC + K⁻ + (k/4)φφᵀ: by Newton, accepted when it converges within 1e-4 relative of
/// the start. The terms are of the size of 1/|λ|², not of k, so the root is found to a
/// few ulps however stiff the stop; a real start stays real.
fn secular_root(
    start: Complex64,
    quarter_k: f64,
    phi: &DVector<f64>,
    c: &DVector<f64>,
    d: &DVector<f64>,
) -> Option<Complex64> {
    let mut l = start;
    for _ in 0..30 {
        let (mut h, mut dh) = (
            Complex64::new(1.0 / quarter_k, 0.0),
            Complex64::new(0.0, 0.0),
        );
        for j in 0..phi.len() {
            let q = l * l + c[j] * l + d[j];
            let t = phi[j] * phi[j] / q;
            h += t;
            dh -= t * (2.0 * l + c[j]) / q;
        }
        let step = h / dh;
        if !(step.re.is_finite() && step.im.is_finite()) {
            return None;
        }
        l -= step;
        if (l - start).norm() > 1e-4 * start.norm() {
            return None;
        }
        if step.norm() <= 4.0 * f64::EPSILON * l.norm() {
            return Some(l);
        }
    }
    None
}

/// Indices of eigenvalues with Im ≥ 0, each marked as a conjugate pair or a real one
/// (an error if a complex eigenvalue has no partner: the eigensolver failed).
///
/// # Errors
/// [`FlowError::Eigen`] when a complex eigenvalue has no unused partner left.
pub fn conjugate_halves(lambda: &[Complex64]) -> Result<Vec<(usize, bool)>, FlowError> {
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

/// x with Mx = b by faer's blocked LU with partial pivoting.
///
/// # Errors
/// [`FlowError::Eigen`] when the solution is not finite (M singular to working precision).
pub fn solve(
    m: &DMatrix<Complex64>,
    b: &DVector<Complex64>,
) -> Result<DVector<Complex64>, FlowError> {
    use faer::linalg::solvers::Solve;
    let n = m.nrows();
    let fm = faer::Mat::<Complex64>::from_fn(n, n, |i, j| m[(i, j)]);
    let fb = faer::Mat::<Complex64>::from_fn(n, 1, |i, _| b[i]);
    let x = fm.partial_piv_lu().solve(&fb);
    let out = DVector::from_fn(n, |i, _| x[(i, 0)]);
    if out.iter().all(|z| z.re.is_finite() && z.im.is_finite()) {
        Ok(out)
    } else {
        Err(FlowError::Eigen)
    }
}

/// V⁻¹ by faer's blocked LU with partial pivoting (nalgebra's unblocked inverse takes
/// seconds at N = 400).
///
/// # Errors
/// [`FlowError::Eigen`] when the inverse is not finite (V singular to working precision).
pub fn invert(v: &DMatrix<Complex64>) -> Result<DMatrix<Complex64>, FlowError> {
    use faer::linalg::solvers::DenseSolveCore;
    let n = v.nrows();
    let m = faer::Mat::<Complex64>::from_fn(n, n, |i, j| v[(i, j)]);
    let inv = m.partial_piv_lu().inverse();
    let out = DMatrix::from_fn(n, n, |i, j| inv[(i, j)]);
    if out.iter().all(|z| z.re.is_finite() && z.im.is_finite()) {
        Ok(out)
    } else {
        Err(FlowError::Eigen)
    }
}

/// The 1-norm of a complex matrix: the largest column sum of moduli.
pub fn norm1(m: &DMatrix<Complex64>) -> f64 {
    m.column_iter()
        .map(|c| c.iter().map(|z| z.norm()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Parlett–Reinsch balancing (radix 2, as LAPACK's gebal without permutation): returns
/// the diagonal d with D⁻¹AD balanced. Powers of two keep the scaling exact.
pub fn balance(a: &DMatrix<f64>) -> Vec<f64> {
    let n = a.nrows();
    // column-major: entry (i, j) at j·n + i; off-diagonal sums read one column and one
    // row of the working copy per index, which is most of the cost for small matrices
    let mut b: Vec<f64> = a.as_slice().to_vec();
    let mut d = vec![1.0; n];
    loop {
        let mut converged = true;
        for i in 0..n {
            // (summed in index order, skipping the diagonal: the same sums, bit for bit, as
            // the textbook loop, so the scaling and every result built on it are unchanged)
            let column = &b[i * n..(i + 1) * n];
            let c: f64 = (0..n).filter(|&j| j != i).map(|j| column[j].abs()).sum();
            let r: f64 = (0..n).filter(|&j| j != i).map(|j| b[j * n + i].abs()).sum();
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
                    b[j * n + i] /= f;
                }
                for x in &mut b[i * n..(i + 1) * n] {
                    *x *= f;
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

/// Eigenvalues of a real matrix (no eigenvectors: Floquet multipliers need none, and the
/// vectors cost five times the values), computed on its balanced form.
///
/// nalgebra's real Schur form (Francis double shift) with an iteration cap, which for the
/// small dense matrices here (2N ≤ 80) takes a fifth of faer's time (10 against 48 µs at
/// 2N = 20, the values equal to ~1e-15); faer's decomposition if it does not converge.
///
/// # Errors
/// [`FlowError::Eigen`] when neither the Schur iteration nor faer's fallback converges.
pub fn eigenvalues_balanced(a: &DMatrix<f64>) -> Result<Vec<Complex64>, FlowError> {
    let n = a.nrows();
    let d = balance(a);
    let balanced = DMatrix::from_fn(n, n, |i, j| a[(i, j)] * d[j] / d[i]);
    // 30 iterations per eigenvalue is LAPACK's cap for the same algorithm (dlahqr)
    if let Some(schur) =
        nalgebra::linalg::Schur::try_new(balanced.clone(), f64::EPSILON, 30 * n.max(1))
    {
        return Ok(schur.complex_eigenvalues().iter().copied().collect());
    }
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| balanced[(i, j)]);
    m.eigenvalues().map_err(|_| FlowError::Eigen)
}

/// Eigenvalues and right eigenvectors of a real matrix, computed on its balanced form.
///
/// # Errors
/// [`FlowError::Eigen`] when the eigensolver does not converge.
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
