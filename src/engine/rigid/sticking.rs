//! The sticking phase of the rigid-impact model: after a chatter the tip rests on the stop
//! (φ(1)ᵀη = d₀, φ(1)ᵀη̇ = 0) while the free motion would push it in, and the beam moves
//! in the N − 1 directions that keep the tip there.
//!
//! **The constrained flow.** With φ = φ(1), a = f cos ωt − Kη − Cη̇ the free acceleration
//! and λ the contact force, η̈ = a − φλ and φᵀη̈ = 0 give λ = φᵀa/|φ|². Writing
//! η = η_c + Wζ with η_c = φd₀/|φ|² and W (N × (N − 1)) an orthonormal basis of φ⊥ that
//! diagonalises WᵀKW = diag(κ_i), the damping stays diagonal too, because the model's
//! damping is proportional, C = 2αI + γK (viscous plus material): WᵀCW = diag(2α + γκ_i).
//! So ζ is N − 1 independent damped oscillators,
//! ζ̈_i + c_iζ̇_i + κ_iζ_i = (w_iᵀf) cos ωt − w_iᵀKη_c,
//! each solved exactly (its homogeneous part by a 2 × 2 block exponential, exact through
//! critical damping, [`crate::engine::flow::Block2`]).
//!
//! **Release** is the first time the contact force would have to pull:
//! L(t) = |φ|²λ = φᵀf cos ωt − φᵀKη_c − Σ_i (φᵀKw_i ζ_i + φᵀCw_i ζ̇_i) falls through zero.
//! L is a harmonic plus constant plus a block (or pair) term per mode, so the certified
//! crossing search of the simulator (`sim::crossing`) finds it.
//!
//! **Entry** at a chatter's accumulation point: the state is carried by free flight to the
//! accumulation time (the remaining impacts only change the tip velocity) and projected
//! onto the constraint orthogonally in the kinetic-energy metric (M = I in modal
//! coordinates): tip at d₀, tip velocity zero, the rest of η̇ unchanged. That is the limit
//! of infinitely many impacts only for a law that leaves the velocity orthogonal to φ
//! unchanged — Newton's law at the tip, the impulse-response \[R\]_IR; [`RigidImpact`]
//! refuses to stick under the other laws.
//!
//! [`RigidImpact`]: super::RigidImpact

use crate::base::numerics::polar;
use crate::engine::flow::Block2;
use crate::engine::sim::crossing::first_crossing;
use crate::engine::sim::signal::{Target, Term, TipSignal};
use crate::engine::sim::{Clock, Stats};
use crate::model::galerkin::GalerkinModel;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use num_complex::Complex64;

/// One constrained mode ζ_i.
#[derive(Debug, Clone)]
struct Mode {
    /// [[0, 1], [−κ, −c]].
    block: Block2,
    /// Z with ζ_p = Re(Z e^{iθ}) + ζ_s.
    forced: Complex64,
    /// ζ_s = −w_iᵀKη_c/κ.
    offset: f64,
    /// (φᵀKw_i, φᵀCw_i): the mode's share of L is −(a ζ + b ζ̇).
    release: [f64; 2],
}

/// The sticking phase of one model.
#[derive(Debug, Clone)]
pub struct Sticking {
    /// W: N × (N − 1), orthonormal, WᵀKW diagonal.
    w: DMatrix<f64>,
    modes: Vec<Mode>,
    /// η_c = φd₀/|φ|².
    eta_c: DVector<f64>,
    /// φ = φ(1).
    phi: DVector<f64>,
    omega: f64,
    /// φᵀf and φᵀKη_c: L = φᵀf cos θ − φᵀKη_c − Σ_i (a_iζ_i + b_iζ̇_i).
    direct: (f64, f64),
    /// L's harmonic amplitude P (L ∋ Re(P e^{iθ})) and constant, with every mode's
    /// particular solution included: the signal's non-homogeneous part.
    release_forced: Complex64,
    release_constant: f64,
}

impl Sticking {
    /// The constrained flow of `model` (its damping must be proportional: it always is for
    /// the Galerkin model, C = 2αI + γK).
    pub fn new(model: &GalerkinModel) -> Self {
        let n = model.modes();
        let phi = model.tip().clone();
        let k = DMatrix::from_diagonal(model.modal_stiffness());
        let c = DMatrix::from_diagonal(model.damping());
        let f = model.forcing_amplitude().clone();
        let omega = model.omega();
        let norm2 = phi.norm_squared();
        let eta_c = &phi * (model.params().gap / norm2);
        // an orthonormal basis of φ⊥: the last N − 1 columns of Q in [φ | I] = QR
        let mut m = DMatrix::identity(n, n);
        m.set_column(0, &phi);
        let q = m.qr().q();
        let q2 = q.columns(1, n - 1).into_owned();
        // (one mode: no free direction; nalgebra's eigensolver rejects an empty matrix)
        let (w, kappas) = if n == 1 {
            (DMatrix::zeros(1, 0), DVector::zeros(0))
        } else {
            let kz = q2.transpose() * &k * &q2;
            let eig = SymmetricEigen::new(0.5 * (&kz + kz.transpose()));
            (&q2 * &eig.eigenvectors, eig.eigenvalues)
        };
        let (phik, phic) = (phi.transpose() * &k, phi.transpose() * &c);
        let mut modes = Vec::with_capacity(n.saturating_sub(1));
        let direct = (phi.dot(&f), (phik.clone() * &eta_c)[(0, 0)]);
        let mut release_forced = Complex64::new(direct.0, 0.0);
        let mut release_constant = -direct.1;
        for i in 0..n.saturating_sub(1) {
            let wi = w.column(i);
            let kappa = kappas[i];
            // WᵀCW is diagonal for proportional damping: take its diagonal
            let ci = (wi.transpose() * &c * wi)[(0, 0)];
            let forcing = wi.dot(&f);
            let offset = -(wi.transpose() * &k * &eta_c)[(0, 0)] / kappa;
            let forced =
                Complex64::new(forcing, 0.0) / Complex64::new(kappa - omega * omega, ci * omega);
            let a = (&phik * wi)[(0, 0)];
            let b = (&phic * wi)[(0, 0)];
            release_forced -= (a + Complex64::new(0.0, omega * b)) * forced;
            release_constant -= a * offset;
            modes.push(Mode {
                block: Block2::new([[0.0, 1.0], [-kappa, -ci]]),
                forced,
                offset,
                release: [a, b],
            });
        }
        Self {
            w,
            modes,
            eta_c,
            phi,
            omega,
            direct,
            release_forced,
            release_constant,
        }
    }

    /// x moved onto the constraint orthogonally in the kinetic-energy metric: tip at d₀,
    /// tip velocity zero, the components orthogonal to φ unchanged.
    pub fn project(&self, x: &DVector<f64>) -> DVector<f64> {
        let n = self.phi.len();
        let norm2 = self.phi.norm_squared();
        let mut y = x.clone();
        let gap = self.phi.dot(&self.eta_c);
        let dp = (self.phi.dot(&x.rows(0, n)) - gap) / norm2;
        let dv = self.phi.dot(&x.rows(n, n)) / norm2;
        for i in 0..n {
            y[i] -= dp * self.phi[i];
            y[n + i] -= dv * self.phi[i];
        }
        y
    }

    /// (ζ, ζ̇) of a state on the constraint.
    fn reduced(&self, x: &DVector<f64>) -> (DVector<f64>, DVector<f64>) {
        let n = self.phi.len();
        let z = self.w.transpose() * (x.rows(0, n) - &self.eta_c);
        let zd = self.w.transpose() * x.rows(n, n);
        (z, zd)
    }

    /// The homogeneous coordinates y_i = (ζ_i − ζ_p,i, ζ̇_i − ζ̇_p,i) at forcing phase θ.
    fn homogeneous(&self, x: &DVector<f64>, phase: f64) -> Vec<[f64; 2]> {
        let (z, zd) = self.reduced(x);
        let e = polar(1.0, phase);
        self.modes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let p = m.forced * e;
                let pd = m.forced * Complex64::new(0.0, self.omega) * e;
                [z[i] - p.re - m.offset, zd[i] - pd.re]
            })
            .collect()
    }

    /// |φ|²λ: the contact force the stop must exert to hold state x at forcing phase θ
    /// (> 0: the beam pushes into the stop).
    pub fn push(&self, x: &DVector<f64>, phase: f64) -> f64 {
        let (z, zd) = self.reduced(x);
        let mut l = self.direct.0 * phase.cos() - self.direct.1;
        for (i, m) in self.modes.iter().enumerate() {
            l -= m.release[0] * z[i] + m.release[1] * zd[i];
        }
        l
    }

    /// The state s after x (on the constraint) at forcing phase θ.
    pub fn state(&self, x: &DVector<f64>, phase: f64, s: f64) -> DVector<f64> {
        let n = self.phi.len();
        let y = self.homogeneous(x, phase);
        let e = polar(1.0, phase + self.omega * s);
        let mut z = DVector::zeros(self.modes.len());
        let mut zd = DVector::zeros(self.modes.len());
        for (i, m) in self.modes.iter().enumerate() {
            let h = m.block.apply(s, y[i]);
            z[i] = (m.forced * e).re + m.offset + h[0];
            zd[i] = (m.forced * Complex64::new(0.0, self.omega) * e).re + h[1];
        }
        let mut out = DVector::zeros(2 * n);
        out.rows_mut(0, n).copy_from(&(&self.eta_c + &self.w * z));
        out.rows_mut(n, n).copy_from(&(&self.w * zd));
        out
    }

    /// L(s) from x at phase θ as an exponential sum (for the certified search).
    fn release_signal(&self, x: &DVector<f64>, phase: f64) -> TipSignal {
        let y = self.homogeneous(x, phase);
        let mut terms = Vec::with_capacity(2 * self.modes.len());
        for (m, y) in self.modes.iter().zip(&y) {
            mode_terms(m.block, [-m.release[0], -m.release[1]], *y, &mut terms);
        }
        TipSignal::new(
            self.omega,
            phase,
            self.release_forced,
            self.release_constant,
            0.0,
            terms,
        )
    }

    /// Holds x (on the constraint) from `clock` for at most `horizon`: the certified time
    /// at which the contact force reaches zero and turns to pulling, if any, and the state
    /// then (or at the horizon).
    pub fn hold(
        &self,
        x: &DVector<f64>,
        clock: &Clock,
        horizon: f64,
        h_min: f64,
        rel_tol: f64,
        stats: &mut Stats,
    ) -> (Option<f64>, DVector<f64>) {
        let phase = self.omega * clock.offset;
        let signal = self.release_signal(x, phase);
        let release = first_crossing(
            &signal,
            Target {
                sign: -1.0,
                level: 0.0,
            },
            0.0,
            horizon,
            h_min,
            rel_tol,
            stats,
        );
        let state = self.state(x, phase, release.unwrap_or(horizon));
        (release, state)
    }
}

/// Two eigenvalues of a constrained mode count as one nearly critical pair, kept as a block,
/// within this distance relative to the larger (as the free flow's nearly defective pairs,
/// `flow::NEAR_DEFECTIVE_SEPARATION`): further apart, the split into eigenvalues is
/// conditioned like 1/separation ≤ 2·(larger magnitude)/(their distance).
const NEAR_CRITICAL_SEPARATION: f64 = 0.5;

/// r·e^{Bs}y of one constrained mode (B = [[0, 1], [−κ, −c]]) as terms of the certified
/// search: a complex pair Re(a e^{λs}) when under-damped, two real exponentials when
/// over-damped, and a block only near critical damping. The split matters for the search's
/// bounds: a block's are ‖(Bᵀ)ᵏr‖ times the size of y, so an over-damped mode (at N = 30
/// a fast rate ~γκ ~ 4e5 beside a slow one ~1/γ ~ 180) would bound g̈ by the fast rate's
/// square long after that part has decayed, and the release search took steps ~10⁻⁵ of
/// what the signal allows (N = 50: ~30 s for two periods).
fn mode_terms(block: Block2, r: [f64; 2], y: [f64; 2], out: &mut Vec<Term>) {
    let (sigma, q) = (block.mu, block.q);
    let root = q.abs().sqrt();
    // the larger |λ|: √κ for a pair (|λ|² = κ), |σ| + √q for real ones
    let scale = if q < 0.0 {
        (sigma * sigma - q).sqrt()
    } else {
        sigma.abs() + root
    };
    if 2.0 * root < NEAR_CRITICAL_SEPARATION * scale {
        out.push(Term::Block { block, tip: r, y });
    } else if q < 0.0 {
        // ζ = Re(Z e^{λs}), λ = σ + iν: Re Z = y₀ and Re(λZ) = y₁ give Z = y₀ − i(y₁ − σy₀)/ν
        let lambda = Complex64::new(sigma, root);
        let z = Complex64::new(y[0], -(y[1] - sigma * y[0]) / root);
        out.push(Term::Pair {
            a: (r[0] + r[1] * lambda) * z,
            lambda,
        });
    } else {
        // λ_fast = σ − √q without cancellation (σ < 0); λ_slow = κ/λ_fast (their product
        // is κ = det B); ζ = A e^{λ_slow s} + B e^{λ_fast s} with A + B = y₀,
        // λ_slow A + λ_fast B = y₁
        let fast = sigma - root;
        let det = block.b[0][0] * block.b[1][1] - block.b[0][1] * block.b[1][0];
        let slow = det / fast;
        let a = (y[1] - fast * y[0]) / (slow - fast);
        let b = (slow * y[0] - y[1]) / (slow - fast);
        out.push(Term::Real {
            a: (r[0] + r[1] * slow) * a,
            lambda: slow,
        });
        out.push(Term::Real {
            a: (r[0] + r[1] * fast) * b,
            lambda: fast,
        });
    }
}
