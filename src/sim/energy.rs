//! The exact energy budget of a run: work done by the forcing = energy dissipated + change
//! of stored energy (kinetic + modal strain + stop), each segment's integrals in closed
//! form. It needs no reference solution and catches most integrator and event bugs.

use crate::flow::{decay, RegionFlow};
use crate::galerkin::GalerkinModel;
use crate::numerics::polar;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Energy accounting (kinetic + modal strain + stop energy; forcing work; dissipation).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct EnergyBudget {
    /// Stored energy at the start.
    pub initial: f64,
    /// Stored energy at the end.
    pub last: f64,
    /// Work done by the forcing, ∫ Fᵀη̇ dt (exact per segment).
    pub work: f64,
    /// Dissipated energy, ∫ η̇ᵀCη̇ dt (exact per segment).
    pub dissipated: f64,
}

impl EnergyBudget {
    /// |ΔE − W + D| / max(|W|, D, E_initial, E_last): the part of the energy flow that is
    /// not accounted for.
    pub fn relative_imbalance(&self) -> f64 {
        let scale = self
            .work
            .abs()
            .max(self.dissipated)
            .max(self.initial)
            .max(self.last);
        if scale == 0.0 {
            0.0
        } else {
            (self.last - self.initial - self.work + self.dissipated).abs() / scale
        }
    }

    /// The budget of two consecutive runs, this one first.
    pub fn then(&self, next: &EnergyBudget) -> EnergyBudget {
        EnergyBudget {
            initial: self.initial,
            last: next.last,
            work: self.work + next.work,
            dissipated: self.dissipated + next.dissipated,
        }
    }
}

/// Stored energy of state x = [η; η̇]: ½|η̇|² + ½ηᵀK⁻η + (k/8)(φ(1)ᵀη − d₀)₊².
pub fn stored_energy(model: &GalerkinModel, x: &DVector<f64>) -> f64 {
    let n = model.modes();
    let (eta, vel) = (x.rows(0, n), x.rows(n, n));
    let k = model.modal_stiffness();
    let strain: f64 = (0..n).map(|j| k[j] * eta[j] * eta[j]).sum();
    let pen = (model.tip().dot(&eta) - model.params().gap).max(0.0);
    0.5 * vel.norm_squared() + 0.5 * strain + model.params().stop_stiffness / 8.0 * pen * pen
}

/// One region's tables for the exact energy integrals. Inside a segment the velocity is
/// η̇(s) = Σ_m c_m p_m e^{μ_m s} over the homogeneous exponentials (a pair as λ_k and its
/// conjugate) and, with forcing, the two forced ones ±iω; only the c_m depend on the
/// segment, so everything quadratic in p_m is computed once per region.
#[derive(Debug, Clone)]
pub struct EnergyTables {
    /// μ_m.
    exponents: Vec<Complex64>,
    /// G_mn = p_mᵀCp_n.
    gram: DMatrix<Complex64>,
    /// fᵀp_m.
    forcing: Vec<Complex64>,
}

impl EnergyTables {
    /// The tables of `flow`, a region flow of `model`.
    pub fn new(flow: &RegionFlow, model: &GalerkinModel) -> Self {
        let n = flow.modes();
        let velocity =
            |col: &dyn Fn(usize) -> Complex64| -> Vec<Complex64> { (0..n).map(col).collect() };
        let mut p: Vec<Vec<Complex64>> = Vec::new();
        let mut exponents = Vec::new();
        for t in flow.terms() {
            let v = velocity(&|i| flow.eigenvectors()[(n + i, t.index)]);
            if t.pair {
                p.push(v.iter().map(|z| z.conj()).collect());
                exponents.push(t.lambda.conj());
            }
            p.push(v);
            exponents.push(t.lambda);
        }
        if flow.omega() > 0.0 {
            let x = velocity(&|i| flow.forced()[n + i]);
            p.push(x.iter().map(|z| z.conj()).collect());
            exponents.push(Complex64::new(0.0, -flow.omega()));
            p.push(x);
            exponents.push(Complex64::new(0.0, flow.omega()));
        }
        let c = model.damping();
        let gram = DMatrix::from_fn(p.len(), p.len(), |a, b| {
            (0..n).map(|i| p[a][i] * p[b][i] * c[i]).sum()
        });
        let f = model.forcing_amplitude();
        let forcing = p
            .iter()
            .map(|pm| (0..n).map(|i| pm[i] * f[i]).sum())
            .collect();
        Self {
            exponents,
            gram,
            forcing,
        }
    }
}

/// ∫₀^S e^{μs} ds given e^{μS}, accurate also when |μS| is small.
fn exp_integral(mu: Complex64, s: f64, growth: Complex64) -> Complex64 {
    let z = mu * s;
    if z.norm() < 0.1 {
        // S·(1 + z/2 + z²/6 + …), 12 terms: error < 0.1¹²/12! ≈ 2e-21
        let mut term = Complex64::new(s, 0.0);
        let mut sum = term;
        for n in 2..14 {
            term *= z / n as f64;
            sum += term;
        }
        sum
    } else {
        // |e^z − 1| ≥ 1 − e^{−0.1} here: no catastrophic cancellation
        (growth - 1.0) / mu
    }
}

/// Exact forcing work and dissipation over [0, S] of a segment of `flow` starting at
/// modal coordinates y and forcing phase θ₀: with η̇(s) = Σ_m c_m p_m e^{μ_m s},
/// ∫ η̇ᵀCη̇ = Σ_mn c_m c_n G_mn ∫e^{(μ_m+μ_n)s} and ∫ fᵀη̇ cos ωt = Σ_m c_m fᵀp_m ∫ e^{μ_m s}
/// cos(θ₀ + ωs), all in closed form; e^{(μ_m+μ_n)S} is the product of the two factors
/// e^{μS}, so a segment costs O(N²) products and O(N) exponentials.
pub fn segment_energy(
    flow: &RegionFlow,
    y: &DVector<f64>,
    phase0: f64,
    tables: &EnergyTables,
    s_end: f64,
) -> (f64, f64) {
    let omega = flow.omega();
    let mut coefficients = Vec::with_capacity(tables.exponents.len());
    for t in flow.terms() {
        let w = flow.coefficient(y, t);
        if t.pair {
            coefficients.push(w.conj());
        }
        coefficients.push(w);
    }
    let forcing_phase = Complex64::from_polar(0.5, phase0);
    if omega > 0.0 {
        coefficients.push(forcing_phase.conj());
        coefficients.push(forcing_phase);
    }
    let growth: Vec<Complex64> = tables
        .exponents
        .iter()
        .map(|mu| polar(decay(mu.re * s_end), mu.im * s_end))
        .collect();
    let mut dissipated = Complex64::new(0.0, 0.0);
    for (a, (&ca, &ma)) in coefficients.iter().zip(&tables.exponents).enumerate() {
        let mut row = Complex64::new(0.0, 0.0);
        for b in a..coefficients.len() {
            let weight = if a == b { 1.0 } else { 2.0 };
            let mu = ma + tables.exponents[b];
            row += coefficients[b]
                * tables.gram[(a, b)]
                * exp_integral(mu, s_end, growth[a] * growth[b])
                * weight;
        }
        dissipated += ca * row;
    }
    let mut work = Complex64::new(0.0, 0.0);
    if omega > 0.0 {
        let iw = Complex64::new(0.0, omega);
        let forced_growth = polar(1.0, omega * s_end);
        for ((&c, &mu), (&fp, &g)) in coefficients
            .iter()
            .zip(&tables.exponents)
            .zip(tables.forcing.iter().zip(&growth))
        {
            work += c
                * fp
                * (forcing_phase * exp_integral(mu + iw, s_end, g * forced_growth)
                    + forcing_phase.conj()
                        * exp_integral(mu - iw, s_end, g * forced_growth.conj()));
        }
    }
    (work.re, dissipated.re)
}
