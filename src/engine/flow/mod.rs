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
//! by counting whole periods (see [`crate::engine::sim::clock`]).

use crate::base::numerics::polar;
use crate::model::galerkin::{GalerkinModel, Region};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Largest acceptable eigenvector condition estimate ‖V‖‖V⁻¹‖ (1-norms): beyond it the
/// modal solution would lose more than ~6 digits and we refuse rather than mislead.
pub const MAX_EIGENVECTOR_CONDITION: f64 = 1e10;

pub use crate::error::FlowError;

pub mod basis;
pub mod block;

pub use basis::{balance, eigen_balanced, eigenvalues_balanced};
use basis::{conjugate_halves, invert, norm1, solve, ModalBasis};

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

/// X with (iωI − A⁺)X = [0; f] in contact: X_η̇ = iωX_η and (Q + (k/4)φφᵀ)X_η = f with
/// the diagonal Q = diag(d_j − ω² + iωc_j), by Sherman–Morrison — each entry to a few ulps
/// however stiff the stop. `None` in free flight, or where Q or the rank-one correction is
/// singular (then the dense solve decides).
///
/// Measured at N = 20, 1e11k₁, d₀ = 0.006, ω = 2 (κ = 6.9e7): with X and η_s from dense
/// solves (backward error ε‖K⁺‖) and the dense solver's contact eigenpairs, each long
/// contact gained ~1e-6 of the stored energy against a Runge–Kutta integration of the same
/// ODE from the same state, and the run's relative energy imbalance was 1.6e-6; with these
/// solves and the refined eigenpairs ([`basis::contact`]) it is 4e-12. Either alone
/// left it at 0.9e-6 and 2.4e-6.
fn structured_solve(
    model: &GalerkinModel,
    region: Region,
    omega: f64,
) -> Option<DVector<Complex64>> {
    let n = model.modes();
    let (phi, f, c, d) = (
        model.tip(),
        model.forcing_amplitude(),
        model.damping(),
        model.modal_stiffness(),
    );
    if region == Region::Free {
        return None;
    }
    let ks = model.params().stop_stiffness / 4.0;
    let q: Vec<Complex64> = (0..n)
        .map(|j| Complex64::new(d[j] - omega * omega, omega * c[j]))
        .collect();
    let qf: Complex64 = (0..n).map(|j| phi[j] * f[j] / q[j]).sum();
    let qp: Complex64 = (0..n).map(|j| phi[j] * phi[j] / q[j]).sum();
    let coefficient = ks * qf / (1.0 + ks * qp);
    let mut x = DVector::zeros(2 * n);
    for j in 0..n {
        let eta = (f[j] - phi[j] * coefficient) / q[j];
        x[j] = eta;
        x[n + j] = eta * Complex64::new(0.0, omega);
    }
    x.iter()
        .all(|z| z.re.is_finite() && z.im.is_finite())
        .then_some(x)
}

/// The exact flow of one region.
#[derive(Debug, Clone)]
pub struct RegionFlow {
    /// Which region.
    region: Region,
    /// N, the number of modes.
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
    ///
    /// # Errors
    /// [`FlowError::Unstable`] for an eigenvalue with positive real part;
    /// [`FlowError::IllConditioned`] when ‖V‖₁‖V⁻¹‖₁ exceeds [`MAX_EIGENVECTOR_CONDITION`];
    /// [`FlowError::Eigen`] when the eigensolver fails or V, the forced or the static response
    /// cannot be solved for.
    pub fn new(model: &GalerkinModel, region: Region) -> Result<Self, FlowError> {
        let n = model.modes();
        let a = model.state_matrix(region);
        let ModalBasis {
            lambda,
            v,
            blocks,
            plane_residual,
        } = match region {
            Region::Free => basis::free(model),
            Region::Contact => basis::contact(model)?,
        };
        let scale = lambda.iter().map(|l| l.norm()).fold(0.0, f64::max);
        if let Some(l) = lambda.iter().find(|l| l.re > 1e-12 * scale) {
            return Err(FlowError::Unstable(l.re));
        }
        let v_inv = invert(&v)?;
        let condition = norm1(&v) * norm1(&v_inv);
        if !condition.is_finite() || condition > MAX_EIGENVECTOR_CONDITION {
            return Err(FlowError::IllConditioned(condition));
        }
        let omega = model.params().forcing.as_ref().map_or(0.0, |f| f.omega);
        // (iωI − A) X = [0; f] and K⁺η_s = (k d₀/4)φ(1) through the structure of K^± (a
        // diagonal plus, in contact, a rank-one stop): not through V, so they do not
        // inherit the eigenvectors' conditioning, nor through a dense solve, whose backward
        // error ε‖K⁺‖ ~ εkN would act on the flow as a spurious force (see
        // `structured_solve`)
        let unforced = model.forcing_amplitude().iter().all(|f| *f == 0.0);
        let forced = match structured_solve(model, region, omega) {
            Some(x) => x,
            // no force, no forced response: X = 0 even where iωI − A is singular (an
            // undamped model at resonance, whose solve would fail)
            None if unforced => DVector::zeros(2 * n),
            None => {
                let mut m = a.map(|x| Complex64::new(-x, 0.0));
                for i in 0..2 * n {
                    m[(i, i)] += Complex64::new(0.0, omega);
                }
                let mut rhs = DVector::zeros(2 * n);
                for j in 0..n {
                    rhs[n + j] = Complex64::new(model.forcing_amplitude()[j], 0.0);
                }
                solve(&m, &rhs)?
            }
        };
        let preload = model.stop_preload(region);
        let mut static_state = DVector::zeros(2 * n);
        if region == Region::Contact && preload.iter().any(|p| *p != 0.0) {
            // K⁺⁻¹(k d₀/4)φ = (k d₀/4)D⁻¹φ / (1 + (k/4)φᵀD⁻¹φ) (Sherman–Morrison)
            let (phi, d) = (model.tip(), model.modal_stiffness());
            let quarter_k = model.params().stop_stiffness / 4.0;
            let s: f64 = (0..n).map(|j| phi[j] * phi[j] / d[j]).sum();
            let factor = quarter_k * model.params().gap / (1.0 + quarter_k * s);
            for j in 0..n {
                static_state[j] = factor * phi[j] / d[j];
            }
            if static_state.iter().any(|x| !x.is_finite()) {
                return Err(FlowError::Eigen);
            }
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

    /// N, the number of modes.
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
        // over the slices: nalgebra's zipped iterators cost more than the arithmetic here
        let mut x = self.static_state.clone();
        for (xi, f) in x.as_mut_slice().iter_mut().zip(self.forced.as_slice()) {
            *xi += (f * e).re;
        }
        x
    }

    /// The real modal coordinates y of state `x` at forcing phase θ: the real and
    /// imaginary parts of w = V⁻¹(x − x_p(θ)) over the terms.
    pub fn modal(&self, x: &DVector<f64>, phase: f64) -> DVector<f64> {
        // x − x_p in x_p's storage (one allocation fewer)
        let mut d = self.particular(phase);
        for (di, xi) in d.as_mut_slice().iter_mut().zip(x.as_slice()) {
            *di = xi - *di;
        }
        &self.to_modal * d
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

    /// Φ(s) = e^{As}, the flow's Jacobian over a time s (the forcing does not enter it):
    /// F·E(s)·T with T = `to_modal`, F = `from_modal` and E(s) block diagonal — e^{λs}
    /// for a real term, the rotation–scaling of w_k e^{λ_k s} on (Re, Im) for a pair,
    /// e^{Bs} for a block. One real 2N × 2N product after scaling T's rows, where mapping
    /// the 2N unit vectors through [`Self::state`] took 2N + 1 projections.
    pub fn jacobian(&self, s: f64) -> DMatrix<f64> {
        let mut et = self.to_modal.clone();
        self.evolve_rows(s, &mut et);
        &self.from_modal * et
    }

    /// E(s)·m in place: the evolution of the real modal coordinates over s (the block
    /// diagonal E(s) of [`Self::jacobian`]) applied to the rows of m, which are indexed by
    /// the modal coordinates.
    pub fn evolve_rows(&self, s: f64, et: &mut DMatrix<f64>) {
        for t in &self.terms {
            let (i, j) = (t.slot, t.slot + 1);
            let mix = |et: &mut DMatrix<f64>, e: [[f64; 2]; 2]| {
                for c in 0..et.ncols() {
                    let (a, b) = (et[(i, c)], et[(j, c)]);
                    et[(i, c)] = e[0][0] * a + e[0][1] * b;
                    et[(j, c)] = e[1][0] * a + e[1][1] * b;
                }
            };
            match t.kind {
                TermKind::Block { block, .. } => mix(et, block.exp(s)),
                TermKind::Pair => {
                    let c = polar(decay(t.lambda.re * s), t.lambda.im * s);
                    // (a + ib)(c.re + i c.im)
                    mix(et, [[c.re, -c.im], [c.im, c.re]]);
                }
                TermKind::Real => {
                    let e = decay(t.lambda.re * s);
                    et.row_mut(i).scale_mut(e);
                }
            }
        }
    }

    /// T: the real 2N × 2N map from x − x_p to the modal coordinates.
    pub fn to_modal(&self) -> &DMatrix<f64> {
        &self.to_modal
    }

    /// F: the real 2N × 2N map from the modal coordinates back to the state (F·T = I).
    pub fn from_modal(&self) -> &DMatrix<f64> {
        &self.from_modal
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
