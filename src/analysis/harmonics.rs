//! The harmonic spectrum of the tip velocity, exactly (Figure 9(b), §6).
//!
//! Over a run of whole forcing periods the Fourier coefficients of the tip velocity at the
//! forcing's harmonics are c_n = (2/T_run)∫ v(t) e^{−inωt} dt, and V_n = |c_n| is the
//! amplitude of harmonic n. Inside each segment of the exact solution
//! ([`crate::engine::flow`]) v is a sum of exponentials — Re(a_k λ_k e^{λ_k s}) per eigenvalue pair,
//! a_jλ_j e^{λ_j s} per real one, cᵀBe^{Bs}y per 2 × 2 block, and the forced
//! Re(iωP e^{i(θ₀+ωs)}) — so each integral against e^{−inωs} is in closed form:
//! ∫₀^S e^{(μ−inω)s} ds, and cᵀB(B − inωI)⁻¹(e^{(B−inω)S} − I)y for a block. No sampling,
//! no aliasing. (Checked against a discrete Fourier transform of dense samples, whose own
//! error falls like the square of the sample spacing because v has corners at the
//! switches: `tests/harmonics.rs`.)

use crate::base::numerics::{exp_integral, polar};
use crate::engine::flow::TermKind;
use crate::engine::sim::{Observer, SegmentView};
use num_complex::Complex64;

/// Observes ∫ v(t) e^{−inωt} dt for n = 1 … `harmonics` over a run.
#[derive(Debug, Clone)]
pub struct TipHarmonics {
    /// The number of harmonics.
    pub harmonics: usize,
    /// ∫ v e^{−inωt} dt, n = 1 … harmonics.
    pub integrals: Vec<Complex64>,
    /// The observed duration.
    pub duration: f64,
}

impl TipHarmonics {
    /// Harmonics 1 … `harmonics`.
    pub fn new(harmonics: usize) -> Self {
        Self {
            harmonics,
            integrals: vec![Complex64::new(0.0, 0.0); harmonics],
            duration: 0.0,
        }
    }

    /// c_n = (2/T_run)∫ v e^{−inωt} dt: v ≈ Σ Re(c_n e^{inωt}) (plus the mean, which is 0
    /// for a periodic velocity).
    pub fn coefficients(&self) -> Vec<Complex64> {
        self.integrals
            .iter()
            .map(|c| c * (2.0 / self.duration))
            .collect()
    }

    /// V_n = |c_n|.
    pub fn amplitudes(&self) -> Vec<f64> {
        self.coefficients().iter().map(|c| c.norm()).collect()
    }
}

/// ∫₀^S Re(A e^{μs}) e^{−iνs} ds for a conjugate-symmetric term: ½(A E(μ − iν) + Ā E(μ̄ − iν)).
fn real_part_integral(a: Complex64, mu: Complex64, nu: f64, s: f64) -> Complex64 {
    let i_nu = Complex64::new(0.0, nu);
    let e = |m: Complex64| exp_integral(m, s, polar((m.re * s).exp(), m.im * s));
    0.5 * (a * e(mu - i_nu) + a.conj() * e(mu.conj() - i_nu))
}

impl Observer for TipHarmonics {
    fn segment(&mut self, seg: &SegmentView) {
        let flow = seg.flow();
        let y = seg.modal_coordinates();
        let omega = flow.omega();
        let s = seg.end;
        let theta0 = seg.phase();
        self.duration += s;
        for n in 1..=self.harmonics {
            let nu = n as f64 * omega;
            let mut sum = Complex64::new(0.0, 0.0);
            for t in flow.terms() {
                match t.kind {
                    TermKind::Pair => {
                        // d = Re(tip·w e^{λs}) → v = Re(tip·w·λ e^{λs})
                        let a = t.tip * flow.coefficient(y, t) * t.lambda;
                        sum += real_part_integral(a, t.lambda, nu, s);
                    }
                    TermKind::Real => {
                        let a = t.tip.re * y[t.slot] * t.lambda.re;
                        let mu = Complex64::new(t.lambda.re, -nu);
                        let growth = polar((t.lambda.re * s).exp(), -nu * s);
                        sum += a * exp_integral(mu, s, growth);
                    }
                    TermKind::Block { block, tip, .. } => {
                        // cᵀB ∫ e^{(B − iν)s} ds y = cᵀB (B − iν)⁻¹ (e^{BS}e^{−iνS} − I) y
                        let b = block.b;
                        let e = block.exp(s);
                        let rot = polar(1.0, -nu * s);
                        let yv = [y[t.slot], y[t.slot + 1]];
                        let rhs = [0, 1].map(|r| {
                            Complex64::new(e[r][0] * yv[0] + e[r][1] * yv[1], 0.0) * rot - yv[r]
                        });
                        // (B − iνI) x = rhs, 2 × 2
                        let m = [
                            [Complex64::new(b[0][0], -nu), Complex64::new(b[0][1], 0.0)],
                            [Complex64::new(b[1][0], 0.0), Complex64::new(b[1][1], -nu)],
                        ];
                        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
                        let x = [
                            (rhs[0] * m[1][1] - m[0][1] * rhs[1]) / det,
                            (m[0][0] * rhs[1] - m[1][0] * rhs[0]) / det,
                        ];
                        // cᵀB x
                        let cb = [
                            tip[0] * b[0][0] + tip[1] * b[1][0],
                            tip[0] * b[0][1] + tip[1] * b[1][1],
                        ];
                        sum += cb[0] * x[0] + cb[1] * x[1];
                    }
                }
            }
            if omega > 0.0 {
                // d ∋ Re(P e^{i(θ₀+ωs)}) → v ∋ Re(iωP e^{iθ₀} e^{iωs})
                let q = Complex64::new(0.0, omega) * flow.tip_forced() * polar(1.0, theta0);
                sum += real_part_integral(q, Complex64::new(0.0, omega), nu, s);
            }
            // e^{−inωt₀} = e^{−inθ₀}: whole periods drop out
            self.integrals[n - 1] += sum * polar(1.0, -(n as f64) * theta0);
        }
    }
}
