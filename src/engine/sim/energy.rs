//! The exact energy budget of a run: work done by the forcing = energy dissipated + change
//! of stored energy (kinetic + modal strain + stop), each segment's integrals in closed
//! form. It needs no reference solution and catches most integrator and event bugs.

use crate::base::numerics::{exp_integral, exprel_series, polar, EXPREL_SERIES_BELOW};
use crate::engine::flow::{decay, Block2, RegionFlow, TermKind};
use crate::model::galerkin::GalerkinModel;
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

    /// What round-off alone explains of [`Self::relative_imbalance`]: each segment starts
    /// from a state good to about κε (κ the eigenvectors' condition), and independent errors
    /// of that size add up like √(segments): κε√(segments + 1). An imbalance above it means
    /// the flow or the integrals are less accurate than that, and the report says so.
    ///
    /// It is a loose bound, not a model of the error: the integrals agree with quadrature
    /// of the same segments, and what is left is at most 0.1 of it where κ is small
    /// (N ≤ 10 at 100k₁: 1e-15…1e-13) and 1e-3…1e-6 of it at stiff stops (N = 10…400, up
    /// to 1e12k₁: at most 3e-9), there mostly the re-projection at each entry into contact.
    /// Imbalances near or above it came from a contact flow that was the exact flow of a
    /// slightly different beam — its particular solution and eigenpairs from dense solves
    /// with backward error ε‖A⁺‖ ~ εkN — which gained ~1e-6 of the stored energy over each
    /// long contact: an error that grew with the contact time, not like √(segments)
    /// (N = 20 at 1e11k₁, d₀ = 0.006: 1.6e-6 at 8 700 segments, above the bound, and the
    /// same relative imbalance over 100 more periods, within it; N = 400 at 100k₁: 7e-8,
    /// 7 times the bound; see [`crate::engine::flow`]).
    pub fn round_off_bound(condition: f64, segments: u64) -> f64 {
        condition * f64::EPSILON * ((segments + 1) as f64).sqrt()
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
/// conjugate) and, with forcing, the two forced ones ±iω — plus, for each nearly defective
/// pair (a block), P e^{Bs} y. Only the c_m and y depend on the segment, so everything
/// quadratic in p_m and P is computed once per region.
#[derive(Debug, Clone)]
pub struct EnergyTables {
    /// μ_m.
    exponents: Vec<Complex64>,
    /// The dissipation's terms, one per pair of conjugate classes (see [`DissipationTerm`]).
    dissipation: Vec<DissipationTerm>,
    /// fᵀp_m.
    forcing: Vec<Complex64>,
    /// The blocks' tables.
    blocks: Vec<BlockTables>,
}

/// One term c_a c_y G_ay ∫e^{(μ_a+μ_y)s} of the dissipation, with what does not depend on
/// the segment. The exponentials come in conjugate classes ({m, m̄}, or one real m) and G is
/// symmetric, so of the M² terms Σ_ab c_a c_b G_ab ∫e^{(μ_a+μ_b)s} it suffices to take, for
/// each pair of classes A ≤ B with representative a of A, the terms (a, y) for y in B: the
/// others are these or their conjugates. `weight` is (2 if A ≠ B) × (2 if A is a pair), and
/// the dissipation is Σ weight · Re(term): M²/4 terms.
#[derive(Debug, Clone, Copy)]
struct DissipationTerm {
    a: usize,
    y: usize,
    weight: f64,
    /// μ_a + μ_y, its reciprocal (0 when μ = 0: then the series is always used) and |μ|².
    mu: Complex64,
    inverse_mu: Complex64,
    mu_norm2: f64,
    /// G_ay = p_aᵀCp_y.
    gram: Complex64,
}

/// A block's tables: B, its slot, and its Gram products with the exponentials and with the
/// blocks after it.
#[derive(Debug, Clone)]
struct BlockTables {
    block: Block2,
    slot: usize,
    /// P_aᵀCp_m for every exponential m.
    with_exponentials: Vec<[Complex64; 2]>,
    /// P_aᵀCP_b for this block and every later one.
    with_blocks: Vec<[[f64; 2]; 2]>,
    /// fᵀP_a.
    forcing: [f64; 2],
}

impl EnergyTables {
    /// The tables of `flow`, a region flow of `model`.
    pub fn new(flow: &RegionFlow, model: &GalerkinModel) -> Self {
        Self::weighted(flow, model.damping(), model.forcing_amplitude())
    }

    /// The tables of mode j alone (0-based): its own dissipation c_jη̇_j² and forcing work
    /// f_jη̇_j cos ωt, for the energy balance of that mode (the damping is diagonal in the
    /// modal coordinates).
    pub fn for_mode(flow: &RegionFlow, model: &GalerkinModel, j: usize) -> Self {
        let only =
            |v: &DVector<f64>| DVector::from_fn(v.len(), |i, _| if i == j { v[i] } else { 0.0 });
        Self::weighted(
            flow,
            &only(model.damping()),
            &only(model.forcing_amplitude()),
        )
    }

    /// The tables for dissipation ∫η̇ᵀdiag(c)η̇ and forcing work ∫fᵀη̇ cos ωt.
    fn weighted(flow: &RegionFlow, c: &DVector<f64>, f: &DVector<f64>) -> Self {
        let n = flow.modes();
        let basis = flow.eigenvectors();
        let velocity =
            |col: &dyn Fn(usize) -> Complex64| -> Vec<Complex64> { (0..n).map(col).collect() };
        let mut p: Vec<Vec<Complex64>> = Vec::new();
        let mut exponents = Vec::new();
        // conjugate classes: (representative, its conjugate when a pair)
        let mut classes: Vec<(usize, Option<usize>)> = Vec::new();
        let mut block_parts: Vec<(Block2, usize, [Vec<f64>; 2])> = Vec::new();
        for t in flow.terms() {
            if let TermKind::Block { block, columns, .. } = t.kind {
                let part = columns.map(|c| (0..n).map(|i| basis[(n + i, c)].re).collect());
                block_parts.push((block, t.slot, part));
                continue;
            }
            let v = velocity(&|i| basis[(n + i, t.index)]);
            if t.is_pair() {
                p.push(v.iter().map(|z| z.conj()).collect());
                exponents.push(t.lambda.conj());
                classes.push((p.len(), Some(p.len() - 1)));
            } else {
                classes.push((p.len(), None));
            }
            p.push(v);
            exponents.push(t.lambda);
        }
        if flow.omega() > 0.0 {
            let x = velocity(&|i| flow.forced()[n + i]);
            p.push(x.iter().map(|z| z.conj()).collect());
            exponents.push(Complex64::new(0.0, -flow.omega()));
            classes.push((p.len(), Some(p.len() - 1)));
            p.push(x);
            exponents.push(Complex64::new(0.0, flow.omega()));
        }
        // G = Pᵀ diag(C) P as one blocked product (O(N³), seconds at N = 400 as loops)
        let pm = faer::Mat::<Complex64>::from_fn(n, p.len(), |i, m| p[m][i]);
        let cp = faer::Mat::<Complex64>::from_fn(n, p.len(), |i, m| p[m][i] * c[i]);
        let g = pm.transpose() * &cp;
        let mut dissipation = Vec::with_capacity(classes.len() * (classes.len() + 1));
        for (i, &(a, a_conj)) in classes.iter().enumerate() {
            for &(b, b_conj) in &classes[i..] {
                let weight =
                    if a == b { 1.0 } else { 2.0 } * if a_conj.is_some() { 2.0 } else { 1.0 };
                for y in std::iter::once(b).chain(b_conj) {
                    let mu = exponents[a] + exponents[y];
                    let inverse_mu = if mu == Complex64::new(0.0, 0.0) {
                        mu
                    } else {
                        1.0 / mu
                    };
                    dissipation.push(DissipationTerm {
                        a,
                        y,
                        weight,
                        mu,
                        inverse_mu,
                        mu_norm2: mu.norm_sqr(),
                        gram: g[(a, y)],
                    });
                }
            }
        }
        let forcing = p
            .iter()
            .map(|pm| (0..n).map(|i| pm[i] * f[i]).sum())
            .collect();
        let blocks = (0..block_parts.len())
            .map(|a| {
                let (block, slot, pa) = &block_parts[a];
                let with_exponentials = p
                    .iter()
                    .map(|pm| [0, 1].map(|r| (0..n).map(|i| pa[r][i] * c[i] * pm[i]).sum()))
                    .collect();
                let with_blocks = block_parts[a..]
                    .iter()
                    .map(|(_, _, pb)| {
                        [0, 1].map(|r| {
                            [0, 1].map(|q| (0..n).map(|i| pa[r][i] * c[i] * pb[q][i]).sum())
                        })
                    })
                    .collect();
                let forcing = [0, 1].map(|r| (0..n).map(|i| pa[r][i] * f[i]).sum());
                BlockTables {
                    block: *block,
                    slot: *slot,
                    with_exponentials,
                    with_blocks,
                    forcing,
                }
            })
            .collect();
        Self {
            exponents,
            dissipation,
            forcing,
            blocks,
        }
    }
}

/// ∫₀^S e^{Ks} ds · v for a small matrix K, given w = e^{KS}v: by its power series
/// Σ_j K^j S^{j+1}/(j+1)! v when ‖K‖S < 1/2 (no cancellation), else by solving
/// K·X = w − v (K is then well away from singular: a block's eigenvalues have Re < 0,
/// and the sums used here stay away from zero).
fn matrix_integral(
    k: &DMatrix<Complex64>,
    s: f64,
    v: &DVector<Complex64>,
    w: &DVector<Complex64>,
) -> DVector<Complex64> {
    if k.norm() * s < 0.5 {
        let mut term = v * Complex64::new(s, 0.0);
        let mut sum = term.clone();
        for j in 1..40 {
            term = k * term * Complex64::new(s / (j + 1) as f64, 0.0);
            sum += &term;
            if term.norm() <= 1e-18 * sum.norm() {
                break;
            }
        }
        sum
    } else {
        k.clone()
            .lu()
            .solve(&(w - v))
            .unwrap_or_else(|| DVector::from_element(v.len(), Complex64::new(f64::NAN, 0.0)))
    }
}

fn complex2(m: [[f64; 2]; 2], transpose: bool) -> DMatrix<Complex64> {
    DMatrix::from_fn(2, 2, |i, j| {
        let x = if transpose { m[j][i] } else { m[i][j] };
        Complex64::new(x, 0.0)
    })
}

/// Exact forcing work and dissipation over [0, S] of a segment of `flow` starting at
/// modal coordinates y and forcing phase θ₀: with η̇(s) = Σ_m c_m p_m e^{μ_m s},
/// ∫ η̇ᵀCη̇ = Σ_mn c_m c_n G_mn ∫e^{(μ_m+μ_n)s} and ∫ fᵀη̇ cos ωt = Σ_m c_m fᵀp_m ∫ e^{μ_m s}
/// cos(θ₀ + ωs), all in closed form; e^{(μ_m+μ_n)S} is the product of the two factors
/// e^{μS}, so a segment costs O(N²) products and O(N) exponentials. A block's terms are
/// integrals of e^{Bᵀs}Ge^{μs} and e^{B_aᵀs}Ge^{B_b s}: small Sylvester-type integrals
/// (`matrix_integral`).
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
        if let TermKind::Block { .. } = t.kind {
            continue;
        }
        let w = flow.coefficient(y, t);
        if t.is_pair() {
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
    let mut dissipated = 0.0;
    let s2 = s_end * s_end;
    for t in &tables.dissipation {
        let z2 = t.mu_norm2 * s2;
        let integral = if z2 < EXPREL_SERIES_BELOW {
            exprel_series(t.mu * s_end, z2) * s_end
        } else {
            (growth[t.a] * growth[t.y] - 1.0) * t.inverse_mu
        };
        dissipated += t.weight * (coefficients[t.a] * coefficients[t.y] * t.gram * integral).re;
    }
    let mut dissipated = Complex64::new(dissipated, 0.0);
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
    if !tables.blocks.is_empty() {
        let (w, d) = block_energy(
            tables,
            y,
            &coefficients,
            &growth,
            forcing_phase,
            omega,
            s_end,
        );
        work += w;
        dissipated += d;
    }
    (work.re, dissipated.re)
}

/// The blocks' share of [`segment_energy`]: their cross terms with every exponential,
/// with each other and with themselves, and their forcing work.
fn block_energy(
    tables: &EnergyTables,
    y: &DVector<f64>,
    coefficients: &[Complex64],
    growth: &[Complex64],
    forcing_phase: Complex64,
    omega: f64,
    s_end: f64,
) -> (Complex64, Complex64) {
    let one = Complex64::new(1.0, 0.0);
    let (mut work, mut dissipated) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
    for (a, ta) in tables.blocks.iter().enumerate() {
        let ya = DVector::from_vec(vec![
            Complex64::new(y[ta.slot], 0.0),
            Complex64::new(y[ta.slot + 1], 0.0),
        ]);
        let bt = complex2(ta.block.b, true);
        let ebt = complex2(ta.block.exp(s_end), true);
        // with each exponential m: 2 c_m y_aᵀ ∫ e^{(Bᵀ + μ_m)s} ds g
        for ((g, &c), (&mu, &gm)) in ta
            .with_exponentials
            .iter()
            .zip(coefficients)
            .zip(tables.exponents.iter().zip(growth))
        {
            let gv = DVector::from_vec(g.to_vec());
            let k = &bt + DMatrix::identity(2, 2) * mu;
            let w = &ebt * &gv * gm;
            let x = matrix_integral(&k, s_end, &gv, &w);
            dissipated += 2.0 * c * ya.dot(&x);
        }
        // with itself and every later block: y_aᵀ X y_b, vec X = ∫e^{Ks}ds vec G with
        // K = I⊗B_aᵀ + B_bᵀ⊗I (column-major vec)
        for (offset, g) in ta.with_blocks.iter().enumerate() {
            let tb = &tables.blocks[a + offset];
            let bb = complex2(tb.block.b, false);
            let ebb = complex2(tb.block.exp(s_end), false);
            let gm = complex2(*g, false);
            let k = DMatrix::identity(2, 2).kronecker(&bt)
                + bb.transpose().kronecker(&DMatrix::identity(2, 2));
            let v = DVector::from_iterator(4, gm.iter().cloned());
            let w = DVector::from_iterator(4, (&ebt * &gm * &ebb).iter().cloned());
            let x = matrix_integral(&k, s_end, &v, &w);
            let xm = DMatrix::from_column_slice(2, 2, x.as_slice());
            let yb = DVector::from_vec(vec![
                Complex64::new(y[tb.slot], 0.0),
                Complex64::new(y[tb.slot + 1], 0.0),
            ]);
            let weight = if offset == 0 { 1.0 } else { 2.0 };
            dissipated += weight * (ya.transpose() * xm * yb)[(0, 0)];
        }
        if omega > 0.0 {
            // fᵀP ∫ e^{Bs} y cos(θ₀ + ωs): through e^{(B ± iω)s}
            let b = complex2(ta.block.b, false);
            let eb = complex2(ta.block.exp(s_end), false);
            let fp = DVector::from_vec(ta.forcing.map(|f| Complex64::new(f, 0.0)).to_vec());
            for (sign, phase) in [(1.0, forcing_phase), (-1.0, forcing_phase.conj())] {
                let iw = Complex64::new(0.0, sign * omega);
                let k = &b + DMatrix::identity(2, 2) * iw;
                let w = &eb * &ya * polar(1.0, sign * omega * s_end);
                let x = matrix_integral(&k, s_end, &ya, &w);
                work += phase * fp.dot(&x) * one;
            }
        }
    }
    (work, dissipated)
}
