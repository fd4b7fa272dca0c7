//! A nearly defective eigenvalue pair as a 2 × 2 real block (critical damping).
//!
//! At critical damping two eigenvalues of A^± meet on the real axis and their eigenvectors
//! become parallel: an eigendecomposition then loses all accuracy (its condition grows
//! like 1/δ as the pair's separation 2δ → 0). On the pair's invariant plane, spanned by an
//! orthonormal basis W, the flow is the 2 × 2 block B = W⁺AW, with eigenvalues μ ± δ,
//! δ² = q real, and
//!
//! ```text
//! e^{Bs} = e^{μs} [ cosh(δs) I + (sinh(δs)/δ)(B − μI) ],    (B − μI)² = qI,
//! ```
//!
//! which is smooth in q through q = 0 (sinh(δs)/δ → s): over-damped (q > 0), critical
//! (q = 0) and under-damped (q < 0, cosh → cos, sinh/δ → sin/ν) alike.

use nalgebra::DMatrix;
use num_complex::Complex64;

/// A real 2 × 2 block B with eigenvalues μ ± √q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Block2 {
    /// B, row by row.
    pub b: [[f64; 2]; 2],
    /// μ = tr B / 2.
    pub mu: f64,
    /// q = ((b₀₀ − b₁₁)/2)² + b₀₁b₁₀: (B − μI)² = qI.
    pub q: f64,
}

impl Block2 {
    /// The block of matrix `b`.
    pub fn new(b: [[f64; 2]; 2]) -> Self {
        let mu = 0.5 * (b[0][0] + b[1][1]);
        let a = 0.5 * (b[0][0] - b[1][1]);
        Self {
            b,
            mu,
            q: a * a + b[0][1] * b[1][0],
        }
    }

    /// Its eigenvalues μ ± √q.
    pub fn eigenvalues(&self) -> (Complex64, Complex64) {
        let r = Complex64::new(self.q, 0.0).sqrt();
        (self.mu + r, self.mu - r)
    }

    /// (e^{μs} cosh(δs), e^{μs} sinh(δs)/δ) with δ² = q, without overflow or cancellation.
    pub fn cosh_sinh(&self, s: f64) -> (f64, f64) {
        let mu = self.mu;
        if self.q > 0.0 {
            let r = self.q.sqrt();
            if r * s < 1.0 {
                let e = (mu * s).exp();
                (e * (r * s).cosh(), e * (r * s).sinh() / r)
            } else {
                // both exponentials decay (μ + r ≤ 0); e^{(μ−r)s} ≤ e^{−2}·e^{(μ+r)s}
                let (up, down) = (((mu + r) * s).exp(), ((mu - r) * s).exp());
                (0.5 * (up + down), 0.5 * (up - down) / r)
            }
        } else if self.q < 0.0 {
            let nu = (-self.q).sqrt();
            let e = (mu * s).exp();
            let (sin, cos) = (nu * s).sin_cos();
            (e * cos, e * sin / nu)
        } else {
            let e = (mu * s).exp();
            (e, e * s)
        }
    }

    /// e^{Bs}.
    pub fn exp(&self, s: f64) -> [[f64; 2]; 2] {
        let (c, sh) = self.cosh_sinh(s);
        let m = self.mu;
        [
            [c + sh * (self.b[0][0] - m), sh * self.b[0][1]],
            [sh * self.b[1][0], c + sh * (self.b[1][1] - m)],
        ]
    }

    /// e^{Bs} y.
    pub fn apply(&self, s: f64, y: [f64; 2]) -> [f64; 2] {
        let e = self.exp(s);
        [
            e[0][0] * y[0] + e[0][1] * y[1],
            e[1][0] * y[0] + e[1][1] * y[1],
        ]
    }

    /// K ≥ sup_{τ ≥ 0} ‖e^{Bτ}‖₂, for a stable block (both eigenvalues with Re < 0):
    /// with κ = −max Re(μ ± δ) the slowest decay rate, e^{μτ}|cosh δτ| ≤ e^{−κτ} ≤ 1 and
    /// e^{μτ}|sinh(δτ)/δ| ≤ τe^{−κτ} ≤ 1/(eκ), so K = 1 + ‖B − μI‖_F/(eκ). Bounds that
    /// hold from one point on then hold for the block's whole future. Infinite for a
    /// block that does not decay.
    pub fn growth_bound(&self) -> f64 {
        let (l1, l2) = self.eigenvalues();
        let kappa = -(l1.re.max(l2.re));
        if kappa <= 0.0 {
            return f64::INFINITY;
        }
        let m = self.mu;
        let off = ((self.b[0][0] - m).powi(2)
            + (self.b[1][1] - m).powi(2)
            + self.b[0][1].powi(2)
            + self.b[1][0].powi(2))
        .sqrt();
        1.0 + off / (std::f64::consts::E * kappa)
    }
}

/// Orthonormalises the two columns of `q` in place (Gram–Schmidt, twice for accuracy);
/// false if they are (numerically) dependent.
fn orthonormalise(q: &mut DMatrix<f64>) -> bool {
    for _ in 0..2 {
        let n0 = q.column(0).norm();
        if !(n0.is_finite() && n0 > 0.0) {
            return false;
        }
        q.column_mut(0).unscale_mut(n0);
        let proj = q.column(0).dot(&q.column(1));
        let c0 = q.column(0).clone_owned();
        q.column_mut(1).axpy(-proj, &c0, 1.0);
        let n1 = q.column(1).norm();
        if !(n1.is_finite() && n1 > 1e-300) {
            return false;
        }
        q.column_mut(1).unscale_mut(n1);
    }
    true
}

/// The invariant plane of `a` for its two eigenvalues nearest the real shift σ, by inverse
/// subspace iteration from `start` (n × 2): an orthonormal basis Q (n × 2) and the block
/// B = QᵀAQ, with the relative residual ‖AQ − QB‖/‖A‖. Each iteration reduces the
/// unwanted components by |λ_pair − σ|/|λ_other − σ|; the caller places σ a quarter of the
/// way from the pair to the nearest other eigenvalue, so that ratio is below 1/2 while
/// A − σI stays well conditioned on the plane itself (a shift *at* a double eigenvalue
/// would square its conditioning). Iterates until the residual reaches round-off.
pub fn invariant_plane(
    a: &DMatrix<f64>,
    sigma: f64,
    start: DMatrix<f64>,
) -> Option<(DMatrix<f64>, Block2, f64)> {
    let n = a.nrows();
    let scale = a.norm().max(f64::MIN_POSITIVE);
    let mut m = a.clone();
    for i in 0..n {
        m[(i, i)] -= sigma;
    }
    let lu = m.lu();
    let mut q = start;
    if !orthonormalise(&mut q) {
        // the two start vectors coincide (an exactly defective pair's eigenvectors):
        // any second direction works, inverse iteration pulls it into the plane
        for r in 0..n {
            q[(r, 1)] = ((r + 1) as f64 * 0.7548776662466927).sin();
        }
        if !orthonormalise(&mut q) {
            return None;
        }
    }
    let mut best: Option<(DMatrix<f64>, Block2, f64)> = None;
    for _ in 0..60 {
        let z = lu.solve(&q)?;
        if !z.iter().all(|v| v.is_finite()) {
            return None;
        }
        q = z;
        if !orthonormalise(&mut q) {
            return None;
        }
        let b = q.transpose() * a * &q;
        let residual = (a * &q - &q * &b).norm() / scale;
        let block = Block2::new([[b[(0, 0)], b[(0, 1)]], [b[(1, 0)], b[(1, 1)]]]);
        let improved = best.as_ref().is_none_or(|x| residual < x.2);
        if improved {
            best = Some((q.clone(), block, residual));
        }
        if residual < 4.0 * f64::EPSILON || !improved {
            break;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn expm(b: [[f64; 2]; 2], s: f64) -> nalgebra::Matrix2<f64> {
        (nalgebra::Matrix2::new(b[0][0], b[0][1], b[1][0], b[1][1]) * s).exp()
    }

    #[test]
    fn closed_form_exponential_matches_expm_through_critical_damping() {
        // the free mode block [[0, 1], [−k, −c]] at c = 2√k (1 + δ), δ from −1e-3 to 1e-3,
        // including 0 (a Jordan block) and round-off sized offsets
        let k: f64 = 485.0;
        for delta in [-1e-3, -1e-9, -1e-14, 0.0, 1e-14, 1e-9, 1e-3] {
            let c = 2.0 * k.sqrt() * (1.0 + delta);
            let block = Block2::new([[0.0, 1.0], [-k, -c]]);
            for s in [1e-4, 0.01, 0.1, 1.0] {
                let ours = block.exp(s);
                let reference = expm(block.b, s);
                let scale = reference.amax().max(1e-300);
                for i in 0..2 {
                    for j in 0..2 {
                        // expm's scaling and squaring of ‖Bs‖ ≤ 500: ~1e-13 relative
                        assert!(
                            (ours[i][j] - reference[(i, j)]).abs() < 1e-12 * scale,
                            "δ={delta:e} s={s}: {ours:?} vs {reference}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn growth_bound_holds_on_a_fine_grid() {
        for b in [
            [[0.0, 1.0], [-485.0, -44.05]],
            [[-3.0, 40.0], [0.0, -3.0]],
            [[-1.0, 0.5], [-0.5, -1.2]],
        ] {
            let block = Block2::new(b);
            let bound = block.growth_bound();
            for i in 0..4000 {
                let e = expm(b, i as f64 * 1e-3);
                // the spectral norm
                let norm = e.singular_values().max();
                assert!(norm <= bound * (1.0 + 1e-12), "{b:?}: {norm} > {bound}");
            }
        }
    }

    #[test]
    fn the_plane_of_a_jordan_pair_is_found_to_round_off() {
        // a 4 × 4 matrix with an exact Jordan pair at −2 and eigenvalues −7 and −0.3,
        // in a non-orthogonal basis
        let j = DMatrix::from_row_slice(
            4,
            4,
            &[
                -2.0, 1.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0, -7.0, 0.0, 0.0, 0.0, 0.0, -0.3,
            ],
        );
        let p = DMatrix::from_fn(4, 4, |i, k| {
            1.0 / (1.0 + i as f64 + 2.0 * k as f64) + if i == k { 1.0 } else { 0.0 }
        });
        let a = &p * j * p.clone().try_inverse().unwrap();
        let start = DMatrix::from_fn(4, 2, |i, k| ((i + 3 * k) as f64).sin());
        // a quarter of the way to the nearest other eigenvalue, −0.3
        let (q, block, residual) = invariant_plane(&a, -2.0 + 0.25 * 1.7, start).unwrap();
        assert!(residual < 1e-14, "residual {residual:e}");
        let (l1, l2) = block.eigenvalues();
        // a Jordan pair's eigenvalues are only √ε-conditioned; the block's trace is exact
        assert!((block.mu + 2.0).abs() < 1e-12 && (l1 - l2).norm() < 1e-6);
        assert!((q.transpose() * &q - DMatrix::identity(2, 2)).amax() < 1e-15);
    }
}
