//! The exact energy budget of a run: work done by the forcing = energy dissipated + change
//! of stored energy (kinetic + modal strain + stop), each segment's integrals in closed
//! form. It needs no reference solution and catches most integrator and event bugs.

use crate::base::numerics::{exprel_series, polar, sin_cos, EXPREL_SERIES_BELOW};
use crate::engine::flow::{decay, Block2, RegionFlow, TermKind};
use crate::model::galerkin::GalerkinModel;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::cell::RefCell;

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
    /// The gross flow: Σ over segments of |W_s| + D_s. The forcing's work alternates in
    /// sign over a period (it feeds the motion, then takes from it), so this can exceed
    /// the net |W| many times (12× five periods into a lightly damped transient), and it
    /// is the size round-off is relative to.
    pub gross: f64,
}

impl EnergyBudget {
    /// |ΔE − W + D| / max(|W|, D, E_initial, E_last): the part of the energy flow that is
    /// not accounted for.
    pub fn relative_imbalance(&self) -> f64 {
        let scale = self.scale();
        if scale == 0.0 {
            0.0
        } else {
            (self.last - self.initial - self.work + self.dissipated).abs() / scale
        }
    }

    /// What round-off alone explains of [`Self::relative_imbalance`]: each segment starts
    /// from a state good to about κε (κ the eigenvectors' condition), and independent errors
    /// of that size add up like √(segments); each is relative to the energy that flows, not
    /// to the net budget, so the bound is κε√(segments + 1) × (gross flow + E₀ + E₁)/scale
    /// ([`Self::gross`], `scale` the denominator of the relative imbalance). An imbalance
    /// above it means the flow or the integrals are less accurate than that, and the report
    /// says so.
    ///
    /// It is a loose bound, not a model of the error: the integrals agree with quadrature
    /// of the same segments, and what is left is at most a third of it on 3 000 random
    /// models (N ≤ 6, k/k₁ 0 or 0.1…1e12, ζ₁ 1e-3…0.2, ω/(β₁⁻)² 0.3…3, the gap −0.5…1.5
    /// A_free(ω)) and 1e-3…1e-6 of it at stiff stops (N = 10…400, up to 1e12k₁: at most
    /// 3e-9), there mostly the re-projection at each entry into contact. Without the gross
    /// flow it was exceeded 4× by a lightly damped transient (N = 1, ζ₁ = 0.0033: a net
    /// work of 4e-4 out of 5e-3 that flowed).
    /// Imbalances near or above it came from a contact flow that was the exact flow of a
    /// slightly different beam — its particular solution and eigenpairs from dense solves
    /// with backward error ε‖A⁺‖ ~ εkN — which gained ~1e-6 of the stored energy over each
    /// long contact: an error that grew with the contact time, not like √(segments)
    /// (N = 20 at 1e11k₁, d₀ = 0.006: 1.6e-6 at 8 700 segments, above the bound, and the
    /// same relative imbalance over 100 more periods, within it; N = 400 at 100k₁: 7e-8,
    /// 7 times the bound; see [`crate::engine::flow`]).
    pub fn round_off_bound(&self, condition: f64, segments: u64) -> f64 {
        let scale = self.scale();
        let flow = if scale > 0.0 {
            ((self.gross + self.initial + self.last) / scale).max(1.0)
        } else {
            1.0
        };
        condition * f64::EPSILON * ((segments + 1) as f64).sqrt() * flow
    }

    /// max(|W|, D, E₀, E₁): what the relative imbalance is relative to.
    fn scale(&self) -> f64 {
        self.work
            .abs()
            .max(self.dissipated)
            .max(self.initial)
            .max(self.last)
    }

    /// The budget of two consecutive runs, this one first.
    pub fn then(&self, next: &EnergyBudget) -> EnergyBudget {
        EnergyBudget {
            initial: self.initial,
            last: next.last,
            work: self.work + next.work,
            dissipated: self.dissipated + next.dissipated,
            gross: self.gross + next.gross,
        }
    }
}

/// Stored energy of state x = [η; η̇]: ½|η̇|² + ½ηᵀK⁻η + (k/8)(φ(1)ᵀη − d₀)₊².
pub(crate) fn stored_energy(model: &GalerkinModel, x: &DVector<f64>) -> f64 {
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
///
/// The exponentials come in conjugate classes ({m, m̄}, or one real m), and the dissipation
/// Σ_ab c_a c_b G_ab ∫₀^S e^{(μ_a+μ_b)s} ds (G symmetric) needs, for each pair of classes
/// A ≤ B with representative a of A, only the terms (a, y) for y in B: the others are these
/// or their conjugates, so the dissipation is Σ weight · Re(term) with weight (2 if A ≠ B) ×
/// (2 if A is a pair): M²/4 terms. The forcing work Σ_m c_m fᵀp_m ∫ e^{μ_m s} cos(θ₀ + ωs)
/// ds is, with cos = (e^{i(θ₀+ωs)} + e^{−i(θ₀+ωs)})/2, the same kind of sum between the
/// forced class (c = e^{±iθ₀}/2 at μ = ±iω) and every exponential, with fᵀp_y for G_ay:
/// 2 Re of its representative's terms.
///
/// With g = e^{μS} − 1 (each to a few ulps), e^{(μ_a+μ_y)S} − 1 = g_a + e^{μ_a S} g_y, so
/// Σ_y G_ay c_y ∫₀^S e^{(μ_a+μ_y)s} ds = g_a Σ_y (G_ay/μ_ay) c_y + e^{μ_a S} Σ_y (G_ay/μ_ay)
/// c_y g_y (μ_ay = μ_a + μ_y): a class's terms are two sums over a row fixed for the region
/// (a `Row`), with no series and no exponential of their own, good to about (|μ_a| +
/// |μ_y|)/|μ_a + μ_y| times the rounding of g. The terms where that ratio reaches
/// `AMPLIFICATION` = 4 (a mode against its own conjugate, a near resonance) are left out of
/// the rows and summed one by one, by the series while |μ_ay S| < 0.1; a class's own term
/// c_m c_m̄ G_mm̄ ∫e^{2 Re μ_m s} is real and has a cancellation-free closed form.
#[derive(Debug, Clone)]
pub struct EnergyTables {
    /// μ_m.
    exponents: Vec<Complex64>,
    /// The conjugate classes.
    classes: Vec<Class>,
    /// The rows' weights, one row after the other (see [`Row`]).
    weights: Vec<Complex64>,
    /// The dissipation terms left out of the rows.
    dissipation: Vec<Term>,
    /// With forcing, the forced class's representative's row of the work, and the work's
    /// terms left out of it (as `dissipation`).
    work: Option<(Row, Vec<Term>)>,
    /// The blocks' tables.
    blocks: Vec<BlockTables>,
}

/// How much the rows may amplify the rounding of the factors g = e^{μS} − 1: a term
/// (a, y) is in its row when |μ_a| + |μ_y| < AMPLIFICATION·|μ_a + μ_y|.
const AMPLIFICATION: f64 = 4.0;

/// A conjugate class ({m − 1, m} for a pair, the conjugate first; {m} for a real
/// exponential), with its own dissipation term c_m c_m̄ G_mm̄ ∫e^{2 Re μ_m s} (real; c_m² G_mm
/// for a real one) and its row of the others.
#[derive(Debug, Clone)]
struct Class {
    /// Where its coefficient c_m is in the modal coordinates y (c_m = y_slot + i y_slot+1 for
    /// a pair, y_slot for a real one); none for the forced class, c_m = e^{iθ₀}/2.
    slot: Option<usize>,
    pair: bool,
    /// 1/(2 Re μ_m) (0 when Re μ_m = 0).
    half_inverse_rate: f64,
    /// weight · G_mm̄ (weight 2 for a pair).
    own: f64,
    row: Row,
}

/// The terms (a, y) of a class's representative a in the rows: w_y = weight · G_ay/(μ_a +
/// μ_y) (0 for a term not in the row) on the *real* coordinates of the c_y from the class's
/// first exponential on, `first`: c_y and c_ȳ of a pair enter as Re c_y and Im c_y, with
/// w_y + w_ȳ and i(w_y − w_ȳ). The M − first weights are in [`EnergyTables`]'s `weights`
/// from `start` on.
#[derive(Debug, Clone, Copy)]
struct Row {
    a: usize,
    first: usize,
    start: usize,
}

/// A term left out of the rows: c_a c_y G_ay ∫e^{(μ_a+μ_y)s}, `gram` = weight · G_ay.
#[derive(Debug, Clone, Copy)]
struct Term {
    a: usize,
    y: usize,
    /// μ = μ_a + μ_y and |μ|².
    mu: Complex64,
    mu_norm2: f64,
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
        // conjugate classes: (representative, its conjugate when a pair, its slot in y — none
        // for the forced class), the pairs (the forced one last) before the real ones: the
        // rows, each from its class on, then span fewer exponentials
        let mut classes: Vec<(usize, Option<usize>, Option<usize>)> = Vec::new();
        let mut block_parts: Vec<(Block2, usize, [Vec<f64>; 2])> = Vec::new();
        for t in flow.terms() {
            if let TermKind::Block { block, columns, .. } = t.kind {
                let part = columns.map(|c| (0..n).map(|i| basis[(n + i, c)].re).collect());
                block_parts.push((block, t.slot, part));
            }
        }
        let mut pairs: Vec<_> = flow
            .terms()
            .iter()
            .filter(|t| t.is_pair())
            .map(|t| {
                (
                    t.lambda,
                    velocity(&|i| basis[(n + i, t.index)]),
                    Some(t.slot),
                )
            })
            .collect();
        if flow.omega() > 0.0 {
            let x = velocity(&|i| flow.forced()[n + i]);
            pairs.push((Complex64::new(0.0, flow.omega()), x, None));
        }
        for (lambda, v, slot) in pairs {
            p.push(v.iter().map(|z| z.conj()).collect());
            exponents.push(lambda.conj());
            classes.push((p.len(), Some(p.len() - 1), slot));
            p.push(v);
            exponents.push(lambda);
        }
        for t in flow.terms() {
            if t.kind == TermKind::Real {
                classes.push((p.len(), None, Some(t.slot)));
                p.push(velocity(&|i| basis[(n + i, t.index)]));
                exponents.push(t.lambda);
            }
        }
        let len = p.len();
        // G_ay = p_aᵀ diag(C) p_y: entry by entry, for the ~M²/4 the tables use, while that is
        // cheap; else as one blocked product (O(N³), seconds at N = 400 as loops). The
        // product's vector kernels leave the upper halves of the vector registers in use,
        // and the SSE code after them then ran at half speed until something cleared them:
        // the first period after building the tables took twice as long at N = 12 (+50 ms).
        let product = (n * len * len > 40_000_000).then(|| {
            let pm = faer::Mat::<Complex64>::from_fn(n, len, |i, m| p[m][i]);
            let cp = faer::Mat::<Complex64>::from_fn(n, len, |i, m| p[m][i] * c[i]);
            pm.transpose() * &cp
        });
        let g = |a: usize, y: usize| -> Complex64 {
            match &product {
                Some(g) => g[(a, y)],
                None => (0..n).map(|i| p[a][i] * (p[y][i] * c[i])).sum(),
            }
        };
        // the terms of representative a with weight · G_ay for y = the members of `classes`:
        // into the row, or left out
        let mut weights = Vec::new();
        let mut terms =
            |a: usize,
             first: usize,
             gram: &dyn Fn(usize) -> Complex64,
             classes: &[(usize, Option<usize>, Option<usize>)]| {
                let start = weights.len();
                weights.resize(start + len - first, Complex64::new(0.0, 0.0));
                let row = &mut weights[start..];
                let mut left_out = Vec::new();
                for &(b, b_conj, _) in classes {
                    // w_y for y = b and b̄
                    let mut w = [Complex64::new(0.0, 0.0); 2];
                    for (j, y) in std::iter::once(b).chain(b_conj).enumerate() {
                        let (mu, gram) = (exponents[a] + exponents[y], gram(y));
                        if exponents[a].norm() + exponents[y].norm() < AMPLIFICATION * mu.norm() {
                            w[j] = gram / mu;
                        } else {
                            let mu_norm2 = mu.norm_sqr();
                            left_out.push(Term {
                                a,
                                y,
                                mu,
                                mu_norm2,
                                gram,
                            });
                        }
                    }
                    match b_conj {
                        Some(b_conj) => {
                            row[b_conj - first] = w[0] + w[1];
                            row[b - first] = Complex64::new(0.0, 1.0) * (w[0] - w[1]);
                        }
                        None => row[b - first] = w[0],
                    }
                }
                (Row { a, first, start }, left_out)
            };
        let work = classes.iter().find(|c| c.2.is_none()).map(|&(forced, ..)| {
            let fp = |y: usize| 2.0 * (0..n).map(|i| p[y][i] * f[i]).sum::<Complex64>();
            terms(forced, 0, &fp, &classes)
        });
        let mut dissipation = Vec::new();
        let classes: Vec<Class> = classes
            .iter()
            .enumerate()
            .map(|(i, &(a, a_conj, slot))| {
                // weight: 2 if A ≠ B, times 2 if A is a pair; the class's own term (a, ā), or
                // (a, a) for a real one, apart
                let pair = if a_conj.is_some() { 2.0 } else { 1.0 };
                let own = a_conj.unwrap_or(a);
                let gram = |y: usize| match y {
                    _ if y == own => Complex64::new(0.0, 0.0),
                    _ if y == a => pair * g(a, y),
                    _ => 2.0 * pair * g(a, y),
                };
                let (row, left_out) = terms(a, own, &gram, &classes[i..]);
                dissipation.extend(left_out.into_iter().filter(|t| t.y != own));
                let rate = exponents[a].re;
                Class {
                    slot,
                    pair: a_conj.is_some(),
                    half_inverse_rate: if rate == 0.0 { 0.0 } else { 0.5 / rate },
                    own: pair * g(a, own).re,
                    row,
                }
            })
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
            classes,
            weights,
            dissipation,
            work,
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
/// cos(θ₀ + ωs), all in closed form from the factors e^{μS} − 1 (see [`EnergyTables`]), so
/// a segment costs O(N²) products and O(N) exponentials. A block's terms are integrals of
/// e^{Bᵀs}Ge^{μs} and e^{B_aᵀs}Ge^{B_b s}: small Sylvester-type integrals
/// (`matrix_integral`).
pub fn segment_energy(
    flow: &RegionFlow,
    y: &DVector<f64>,
    phase0: f64,
    tables: &EnergyTables,
    s_end: f64,
) -> (f64, f64) {
    let omega = flow.omega();
    let len = tables.exponents.len();
    let zero = Complex64::new(0.0, 0.0);
    let forcing_phase = polar(0.5, phase0);
    SCRATCH.with_borrow_mut(|scratch| {
        // c_m, g_m = e^{μ_m S} − 1, and the real coordinates r of c and rg of c∘g as r + i rg
        // (a pair's Re and Im in its two places)
        scratch.resize(3 * len, zero);
        let (c, rest) = scratch.split_at_mut(len);
        let (g, coordinates) = rest.split_at_mut(len);
        let mut dissipated = 0.0;
        for class in &tables.classes {
            let m = class.row.a;
            let mu = tables.exponents[m];
            // e^{μS} − 1 without cancellation: for μ = α + iβ,
            // (e^{αS} − 1) cos βS − 2 sin²(βS/2) + i e^{αS} sin βS
            let e = (mu.re * s_end).exp_m1();
            let cm = match class.slot {
                Some(slot) if !class.pair => {
                    let cm = y[slot];
                    (c[m], g[m]) = (Complex64::new(cm, 0.0), Complex64::new(e, 0.0));
                    coordinates[m] = Complex64::new(cm, cm * e);
                    cm * cm
                }
                _ => {
                    let cm = class
                        .slot
                        .map_or(forcing_phase, |slot| Complex64::new(y[slot], y[slot + 1]));
                    let (sin, cos) = sin_cos(0.5 * mu.im * s_end);
                    let versine = 2.0 * sin * sin;
                    let gm =
                        Complex64::new(e * (1.0 - versine) - versine, (1.0 + e) * 2.0 * sin * cos);
                    let h = cm * gm;
                    (c[m - 1], c[m], g[m - 1], g[m]) = (cm.conj(), cm, gm.conj(), gm);
                    coordinates[m - 1] = Complex64::new(cm.re, h.re);
                    coordinates[m] = Complex64::new(cm.im, h.im);
                    cm.norm_sqr()
                }
            };
            // its own term: ∫₀^S e^{2αs} ds = (e^{αS} − 1)(e^{αS} + 1)/(2α)
            let integral = if class.half_inverse_rate == 0.0 {
                s_end
            } else {
                e * (2.0 + e) * class.half_inverse_rate
            };
            dissipated += class.own * cm * integral;
        }
        let (c, g, coordinates) = (&*c, &*g, &*coordinates);
        for class in &tables.classes {
            dissipated += row_sum(class.row, &tables.weights, c, g, coordinates);
        }
        dissipated += left_out_sum(&tables.dissipation, c, g, s_end);
        let mut work = 0.0;
        if let Some((row, left_out)) = &tables.work {
            work = row_sum(*row, &tables.weights, c, g, coordinates)
                + left_out_sum(left_out, c, g, s_end);
        }
        if !tables.blocks.is_empty() {
            let growth: Vec<Complex64> = tables
                .exponents
                .iter()
                .map(|mu| polar(decay(mu.re * s_end), mu.im * s_end))
                .collect();
            let (w, d) = block_energy(tables, y, c, &growth, forcing_phase, omega, s_end);
            work += w.re;
            dissipated += d.re;
        }
        (work, dissipated)
    })
}

thread_local! {
    /// [`segment_energy`]'s working arrays, kept from one segment to the next: a chattering
    /// run's budget is mostly very short segments, and allocating them cost 4% of it.
    static SCRATCH: RefCell<Vec<Complex64>> = const { RefCell::new(Vec::new()) };
}

/// Re(a·b).
#[inline]
fn real_product(a: Complex64, b: Complex64) -> f64 {
    a.re * b.re - a.im * b.im
}

/// A row's terms, Re(c_a (g_a Σ_y w_y c_y + e^{μ_a S} Σ_y w_y c_y g_y)), over the real
/// coordinates of c and c∘g.
#[inline]
fn row_sum(
    row: Row,
    weights: &[Complex64],
    c: &[Complex64],
    g: &[Complex64],
    coordinates: &[Complex64],
) -> f64 {
    let coordinates = &coordinates[row.first..];
    let w = &weights[row.start..row.start + coordinates.len()];
    // by pairs of entries, into two sums each that do not wait on each other
    let mut sums = [Complex64::new(0.0, 0.0); 4];
    for (w, x) in w.chunks_exact(2).zip(coordinates.chunks_exact(2)) {
        sums[0] += w[0] * x[0].re;
        sums[1] += w[1] * x[1].re;
        sums[2] += w[0] * x[0].im;
        sums[3] += w[1] * x[1].im;
    }
    if w.len() % 2 == 1 {
        let (w, x) = (w[w.len() - 1], coordinates[w.len() - 1]);
        sums[0] += w * x.re;
        sums[2] += w * x.im;
    }
    let ga = g[row.a];
    real_product(
        c[row.a],
        ga * (sums[0] + sums[1]) + (ga + 1.0) * (sums[2] + sums[3]),
    )
}

/// The terms left out of the rows, c_a c_y G_ay ∫e^{(μ_a+μ_y)s}: by
/// (g_a + g_y + g_a g_y)/(μ_a + μ_y) where |(μ_a + μ_y)S| ≥ 0.1 (no cancellation), else by
/// the series S Σ_k ((μ_a + μ_y)S)^k/(k+1)! ([`exprel_series`]).
fn left_out_sum(terms: &[Term], c: &[Complex64], g: &[Complex64], s_end: f64) -> f64 {
    let s2 = s_end * s_end;
    terms
        .iter()
        .map(|t| {
            let z2 = t.mu_norm2 * s2;
            let integral = if z2 < EXPREL_SERIES_BELOW {
                exprel_series(t.mu * s_end, z2) * s_end
            } else {
                (g[t.a] + g[t.y] + g[t.a] * g[t.y]) / t.mu
            };
            real_product(c[t.a] * c[t.y] * t.gram, integral)
        })
        .sum()
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
