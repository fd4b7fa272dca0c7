//! The tip signal of one segment as an exponential sum, with derivative bounds.
//!
//! Inside a region the solution is exact ([`crate::engine::flow`], eq 36), so the tip displacement
//! d(s) = φ(1)ᵀη(t₀ + s) is
//!
//! ```text
//! d(s) = Re(P e^{i(θ₀ + ωs)}) + c + Σ_pairs Re(a_k e^{λ_k s}) + Σ_reals a_j e^{λ_j s},
//! ```
//!
//! with Re λ ≤ 0. A search looks for zeros of g(s) = sign·(d(s) − level) (the switching
//! surface is sign = ±1 at level d₀). Since every term's magnitude only decreases, for all
//! s' ≥ s
//!
//! ```text
//! |g̈(s')| ≤ M₂(s) = ω²|P| + Σ |a_k| |λ_k|² e^{Re λ_k s},   |g⃛(s')| ≤ M₃(s) (one more |λ|),
//! ```
//!
//! which is what makes the crossing search ([`super::crossing`]) certified.

use crate::base::numerics::polar;
use crate::engine::flow::{decay, Block2};
use num_complex::Complex64;

/// One term of the homogeneous part, as it enters d(s).
#[derive(Debug, Clone, Copy)]
pub enum Term {
    /// Re(a e^{λs}) for a complex-conjugate pair (Im λ > 0).
    Pair {
        /// a_k (for a pair from eq 36: 2 φ(1)ᵀv_k w_k).
        a: Complex64,
        /// λ_k.
        lambda: Complex64,
    },
    /// a e^{λs} for a real eigenvalue (an over-damped mode).
    Real {
        /// a_j.
        a: f64,
        /// λ_j ≤ 0.
        lambda: f64,
    },
    /// cᵀe^{Bs}y for a nearly defective pair as a 2 × 2 block (critical damping).
    Block {
        /// B.
        block: Block2,
        /// c: the tip displacement per unit of each block coordinate.
        tip: [f64; 2],
        /// y: the block's coordinates at s = 0.
        y: [f64; 2],
    },
}

/// A block term cᵀe^{Bs}y: its k-th derivative is r_kᵀe^{Bs}y with r_k = (Bᵀ)^k c, and
/// for s' ≥ s, |r_kᵀe^{Bs'}y| ≤ |r_k|·K·|e^{Bs}y| with K ≥ sup_τ ‖e^{Bτ}‖ (the block's
/// growth bound), which stays finite through critical damping.
#[derive(Debug, Clone, Copy)]
struct BlockTerm {
    block: Block2,
    y: [f64; 2],
    /// r_0 … r_3.
    r: [[f64; 2]; 4],
    /// |r_k|·K.
    bound: [f64; 4],
}

impl BlockTerm {
    fn new(block: Block2, tip: [f64; 2], y: [f64; 2]) -> Self {
        let b = block.b;
        let mut r = [tip; 4];
        for k in 1..4 {
            let p = r[k - 1];
            // (Bᵀ)p
            r[k] = [
                b[0][0] * p[0] + b[1][0] * p[1],
                b[0][1] * p[0] + b[1][1] * p[1],
            ];
        }
        let growth = block.growth_bound();
        let bound = r.map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt() * growth);
        Self { block, y, r, bound }
    }
}

/// A complex-pair term Re(a e^{λs}).
#[derive(Debug, Clone, Copy)]
struct PairTerm {
    a: Complex64,
    lambda: Complex64,
    a_abs: f64,
    lambda_abs: f64,
    /// From this s on, |a e^{λs}| ≤ the signal's negligible size.
    negligible_from: f64,
}

/// A real-eigenvalue term a e^{λs}.
#[derive(Debug, Clone, Copy)]
struct RealTerm {
    a: f64,
    lambda: f64,
    negligible_from: f64,
}

/// The function a search looks for zeros of: g(s) = sign·(d(s) − level).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// +1: g rises through zero as d rises through `level`; −1: as d falls through it.
    pub sign: f64,
    /// The level of d.
    pub level: f64,
}

/// g and its derivatives at a point, with bounds valid from that point on.
#[derive(Debug, Clone, Copy)]
pub struct Local {
    /// g(s).
    pub g: f64,
    /// ġ(s).
    pub gd: f64,
    /// g̈(s).
    pub gdd: f64,
    /// ≥ |g̈| on [s, ∞).
    pub bound2: f64,
    /// ≥ |g⃛| on [s, ∞).
    pub bound3: f64,
    /// Σ of the magnitudes of g's terms: its round-off scale.
    pub scale: f64,
    /// Σ of the magnitudes of ġ's terms: ġ's round-off scale (g̈'s is at most `bound2`).
    pub scale1: f64,
    /// An absolute error floor of g beyond its round-off: the error of the segment's
    /// modal representation of its start state (see [`TipSignal::with_floor`]).
    pub floor: f64,
}

impl Local {
    /// g's uncertainty: round-off of the sum (8ε·scale) plus the representation floor.
    pub fn noise(&self) -> f64 {
        8.0 * f64::EPSILON * self.scale + self.floor
    }
}

/// Anything the certified crossing search can run on: g with bounds valid on [s, ∞).
pub trait Signal {
    /// g, ġ, g̈ at s and bounds on |g̈|, |g⃛| over [s, ∞).
    fn local(&self, s: f64, target: Target) -> Local;
}

/// The tip signal of one segment.
#[derive(Debug, Clone)]
pub struct TipSignal {
    omega: f64,
    phase0: f64,
    /// P.
    forced: Complex64,
    /// |P|: the forced tip amplitude.
    forced_amplitude: f64,
    /// c: the static tip displacement.
    constant: f64,
    pairs: Vec<PairTerm>,
    reals: Vec<RealTerm>,
    blocks: Vec<BlockTerm>,
    /// The error of the modal representation of the start state, in tip displacement.
    floor: f64,
    /// A term below this (1e-17 of Σ|a_k| + |P| + |c| + `level_scale`, the signal's
    /// magnitude scale at s = 0) is below g's round-off: its value is skipped, and
    /// 2·`negligible` stands in for its magnitude in the bounds, so no exp or sincos is
    /// spent on a decayed mode and certification is unaffected.
    negligible: f64,
}

/// The first s ≥ 0 from which |a| e^{Re λ s} ≤ `negligible` (Re λ ≤ 0).
fn negligible_from(a_abs: f64, lambda_re: f64, negligible: f64) -> f64 {
    if a_abs <= negligible {
        0.0
    } else if lambda_re < 0.0 {
        (negligible / a_abs).ln() / lambda_re
    } else {
        f64::INFINITY
    }
}

impl TipSignal {
    /// The signal Re(P e^{i(θ₀ + ωs)}) + c + Σ terms. `level_scale` is the size of the
    /// levels it will be compared with (|d₀|), part of its round-off scale.
    pub fn new(
        omega: f64,
        phase0: f64,
        forced: Complex64,
        constant: f64,
        level_scale: f64,
        terms: impl IntoIterator<Item = Term>,
    ) -> Self {
        // sized once (a segment is built at every switch: growing the vectors by pushes
        // cost more than filling them)
        let terms = terms.into_iter();
        let count = terms.size_hint().0;
        let (mut pairs, mut reals, mut blocks) = (
            Vec::with_capacity(count),
            Vec::with_capacity(count),
            Vec::new(),
        );
        // the negligible size is relative to the signal itself, not to the levels it is
        // compared with: a gap of 1e14 must not make the transient "negligible"
        let _ = level_scale;
        let mut scale0 = forced.norm() + constant.abs();
        for t in terms {
            match t {
                Term::Pair { a, lambda } => {
                    // |a| without hypot's overflow guard (slow, and amplitudes are O(1))
                    let a_abs = a.norm_sqr().sqrt();
                    scale0 += a_abs;
                    pairs.push(PairTerm {
                        a,
                        lambda,
                        a_abs,
                        lambda_abs: lambda.norm_sqr().sqrt(),
                        negligible_from: 0.0,
                    });
                }
                Term::Real { a, lambda } => {
                    scale0 += a.abs();
                    reals.push(RealTerm {
                        a,
                        lambda,
                        negligible_from: 0.0,
                    });
                }
                Term::Block { block, tip, y } => {
                    let term = BlockTerm::new(block, tip, y);
                    scale0 += term.bound[0] * (y[0] * y[0] + y[1] * y[1]).sqrt();
                    blocks.push(term);
                }
            }
        }
        let negligible = 1e-17 * scale0;
        for p in &mut pairs {
            p.negligible_from = negligible_from(p.a_abs, p.lambda.re, negligible);
        }
        for r in &mut reals {
            r.negligible_from = negligible_from(r.a.abs(), r.lambda, negligible);
        }
        Self {
            omega,
            phase0,
            forced,
            forced_amplitude: forced.norm(),
            constant,
            pairs,
            reals,
            blocks,
            floor: 0.0,
            negligible,
        }
    }

    /// The same signal with an absolute error floor: |d(0) − d_state|, the difference
    /// between the tip displacement the modal representation gives at s = 0 and the one
    /// computed directly from the state (about κε of the state, κ the basis condition). A
    /// start on the switching surface is only known to that accuracy, so the search treats
    /// values inside it as on the surface.
    pub fn with_floor(mut self, floor: f64) -> Self {
        self.floor = floor;
        self
    }

    /// Tip displacement, velocity and acceleration at s, with the bound on |d̈| from s on.
    pub fn tip_local(&self, s: f64) -> Local {
        self.local(
            s,
            Target {
                sign: 1.0,
                level: 0.0,
            },
        )
    }

    /// Tip displacement and velocity at s.
    pub fn tip(&self, s: f64) -> (f64, f64) {
        let l = self.tip_local(s);
        (l.g, l.gd)
    }

    /// A bound on |ḋ| at s: the scale against which a touch counts as grazing.
    pub fn velocity_bound(&self, s: f64) -> f64 {
        let pairs: f64 = self
            .pairs
            .iter()
            .map(|t| t.a_abs * t.lambda_abs * decay(t.lambda.re * s))
            .sum();
        let reals: f64 = self
            .reals
            .iter()
            .map(|t| (t.a * t.lambda * decay(t.lambda * s)).abs())
            .sum();
        let blocks: f64 = self
            .blocks
            .iter()
            .map(|t| {
                let z = t.block.apply(s, t.y);
                (t.r[1][0] * z[0] + t.r[1][1] * z[1]).abs()
            })
            .sum();
        self.omega * self.forced_amplitude + pairs + reals + blocks
    }
}

impl Signal for TipSignal {
    /// Everything the search needs at s, in one pass over the spectrum. Re λ ≤ 0, so each
    /// term's magnitude only decreases after s and the bounds hold on [s, ∞).
    fn local(&self, s: f64, target: Target) -> Local {
        let w = self.omega;
        let pf = self.forced * polar(1.0, self.phase0 + w * s);
        let (mut d, mut v, mut acc) = (pf.re + self.constant, -w * pf.im, -w * w * pf.re);
        let amp = self.forced_amplitude;
        let (mut b2, mut b3) = (w * w * amp, w * w * w * amp);
        let mut scale = amp + self.constant.abs() + target.level.abs();
        let mut scale1 = w * amp;
        // a decayed term's magnitude is ≤ negligible; twice that absorbs the rounding of
        // its `negligible_from`
        let tiny = 2.0 * self.negligible;
        for t in &self.pairs {
            let l2 = t.lambda_abs * t.lambda_abs;
            let mag = if s >= t.negligible_from {
                tiny
            } else {
                // at s = 0 (every segment's start) e^{λs} = 1 + 0i exactly: no exp or sincos
                let (decay, turn) = if s == 0.0 {
                    (1.0, Complex64::new(1.0, 0.0))
                } else {
                    let decay = decay(t.lambda.re * s);
                    (decay, polar(decay, t.lambda.im * s))
                };
                let z = t.a * turn;
                let zl = z * t.lambda;
                d += z.re;
                v += zl.re;
                acc += (zl * t.lambda).re;
                t.a_abs * decay
            };
            b2 += mag * l2;
            b3 += mag * l2 * t.lambda_abs;
            scale += mag;
            scale1 += mag * t.lambda_abs;
        }
        for t in &self.reals {
            let l2 = t.lambda * t.lambda;
            let mag = if s >= t.negligible_from {
                tiny
            } else {
                let z = t.a * if s == 0.0 { 1.0 } else { decay(t.lambda * s) };
                d += z;
                v += z * t.lambda;
                acc += z * l2;
                z.abs()
            };
            b2 += mag * l2;
            b3 += mag * l2 * t.lambda.abs();
            scale += mag;
            scale1 += mag * t.lambda.abs();
        }
        for t in &self.blocks {
            let z = t.block.apply(s, t.y);
            let size = (z[0] * z[0] + z[1] * z[1]).sqrt();
            let dot = |r: [f64; 2]| r[0] * z[0] + r[1] * z[1];
            d += dot(t.r[0]);
            v += dot(t.r[1]);
            acc += dot(t.r[2]);
            b2 += t.bound[2] * size;
            b3 += t.bound[3] * size;
            scale += t.bound[0] * size;
            scale1 += t.bound[1] * size;
        }
        Local {
            g: target.sign * (d - target.level),
            gd: target.sign * v,
            gdd: target.sign * acc,
            bound2: b2,
            bound3: b3,
            scale,
            scale1,
            floor: self.floor,
        }
    }
}
