//! Exact piecewise-linear simulation of the N-mode bilinear model (§5.1–5.2, eqs 34–36)
//! with certified switching times.
//!
//! Within a region the solution is exact ([`crate::flow`]). The tip gap
//! g(s) = ±(φ(1)ᵀη − d₀) (negative while the region holds) is then a sum of exponentials
//! plus a harmonic, g(s) = Re(P e^{iω s}) + Σ_k Re(a_k e^{λ_k s}) + const, so for every
//! s' ≥ s its second derivative is bounded by
//!
//! ```text
//! M(s) = ω²|P| + Σ_k |a_k| |λ_k|² e^{Re λ_k s}     (Re λ_k ≤ 0).
//! ```
//!
//! **Certified advancement.** From s with g < 0, g(s + h) ≤ g + ġh + Mh²/2 < 0 for
//! h < h* = (−ġ + √(ġ² − 2Mg))/M: no root can hide in [s, s + h*). When ġ − M·2h* > 0, g is
//! increasing on [s, s + 2h*] and one evaluation at s + 2h* decides whether the unique root
//! there exists; it is then polished by Halley's method (bracketed) to round-off. The paper instead
//! brackets extrema by golden-section search (§5.2), which has no such guarantee.
//!
//! **Resolution.** Steps are never shorter than `h_min` = 1e-13 of a forcing period, so a
//! contact whose penetration is below M·h_min²/2 (≈ 1e-26·M) may be passed over; every
//! deeper one is found. A touch with zero normal velocity is recorded as a grazing event
//! and does not switch the region.
//!
//! **Maximum.** The largest tip displacement is certified the same way: the search for a
//! zero of d − (B + δ), B the best value so far, either proves d ≤ B + δ on a segment or
//! finds where d rises through it, from where an ascent raises B ([`TipMaximum`]).
//!
//! **Time.** t = cycles·T + offset with offset ∈ [0, T): the forcing phase ω·offset never
//! loses precision over long runs.

use crate::flow::{decay, FlowError, RegionFlow};
use crate::galerkin::{GalerkinModel, Region};
use crate::numerics::polar;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Shortest certified step, as a fraction of the forcing period.
const H_MIN_FRACTION: f64 = 1e-13;

/// Longest segment without a restart, in forcing periods.
const MAX_SEGMENT_PERIODS: i64 = 16;

/// A point in time: t = cycles·period + offset.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Clock {
    /// T = 2π/ω (or 1 without forcing).
    pub period: f64,
    /// Whole periods elapsed.
    pub cycles: i64,
    /// Time since the start of the current period, in [0, T).
    pub offset: f64,
}

impl Clock {
    /// t.
    pub fn time(&self) -> f64 {
        self.cycles as f64 * self.period + self.offset
    }

    /// Advances the clock by s (whole periods are carried into `cycles`).
    pub fn advance(&mut self, s: f64) {
        self.offset += s;
        while self.offset >= self.period {
            self.offset -= self.period;
            self.cycles += 1;
        }
    }
}

/// A switching event.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Event {
    /// When.
    pub clock: Clock,
    /// t.
    pub time: f64,
    /// Entering contact (`true`) or leaving it.
    pub entering: bool,
    /// A grazing touch (zero normal velocity): recorded, no switch.
    pub grazing: bool,
    /// Tip velocity φ(1)ᵀη̇ at the event.
    pub tip_velocity: f64,
    /// The state [η; η̇], if asked for.
    pub state: Option<Vec<f64>>,
}

/// What to record. Nothing is computed that is not asked for.
#[derive(Debug, Clone, Copy, Default)]
pub struct Observe {
    /// Switching events.
    pub events: bool,
    /// The full state at each event.
    pub event_states: bool,
    /// The state at every period boundary (ωt = 0 mod 2π).
    pub strobe: bool,
    /// Samples of (t, tip displacement, tip velocity, region) per period (0: none).
    pub dense_per_period: usize,
    /// The energy budget.
    pub energy: bool,
    /// The largest tip displacement, certified (see [`TipMaximum`]).
    pub max_tip: bool,
}

/// The largest tip displacement d = φ(1)ᵀη of a run, found by certified level crossings:
/// no value of d on the run exceeds `value` by more than `tolerance`, down to the search's
/// resolution (a peak narrower than the shortest step, 1e-13 T, rising less than
/// ≈ M·h_min²/2 above that level could pass unseen; see the module doc).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct TipMaximum {
    /// Where it is attained.
    pub clock: Clock,
    /// t.
    pub time: f64,
    /// max d.
    pub value: f64,
    /// The certificate's slack: 64ε times the tip signal's magnitude scale.
    pub tolerance: f64,
}

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
}

/// Work counters.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Stats {
    /// Region segments propagated.
    pub segments: u64,
    /// Evaluations of the switching function.
    pub evaluations: u64,
    /// Certified advancement steps.
    pub steps: u64,
    /// Of those, steps taken in contact.
    pub contact_steps: u64,
    /// Evaluations spent polishing switching times.
    pub polish_evaluations: u64,
    /// Evaluations spent on the certified maximum of the tip (not in `evaluations`).
    pub maximum_evaluations: u64,
}

/// What a run produced.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    /// Switching events (if observed).
    pub events: Vec<Event>,
    /// States at period boundaries (if observed), with their cycle numbers.
    pub strobe: Vec<(i64, DVector<f64>)>,
    /// (t, tip displacement, tip velocity, in contact) samples (if observed).
    pub dense: Vec<(f64, f64, f64, bool)>,
    /// The energy budget (if observed).
    pub energy: Option<EnergyBudget>,
    /// The largest tip displacement (if observed).
    pub max_tip: Option<TipMaximum>,
    /// Work counters.
    pub stats: Stats,
}

/// Simulation settings.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Relative tolerance of the (Halley) polish of a switching time (default 1e-15).
    pub root_tolerance: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            root_tolerance: 1e-15,
        }
    }
}

/// The simulator: the model and its two exact region flows.
#[derive(Debug, Clone)]
pub struct Simulator {
    /// The model.
    pub model: GalerkinModel,
    /// The − region flow.
    pub free: RegionFlow,
    /// The + region flow.
    pub contact: RegionFlow,
    /// Settings.
    pub settings: Settings,
    /// Tables for the exact energy integrals of the − and + regions.
    energy_tables: [EnergyTables; 2],
}

/// One region's tables for the exact energy integrals. Inside a segment the velocity is
/// η̇(s) = Σ_m c_m p_m e^{μ_m s} over the homogeneous exponentials (a pair as λ_k and its
/// conjugate) and, with forcing, the two forced ones ±iω; only the c_m depend on the
/// segment, so everything quadratic in p_m is computed once per region.
#[derive(Debug, Clone)]
struct EnergyTables {
    /// μ_m.
    exponents: Vec<Complex64>,
    /// G_mn = p_mᵀCp_n.
    gram: DMatrix<Complex64>,
    /// fᵀp_m.
    forcing: Vec<Complex64>,
}

impl EnergyTables {
    fn new(flow: &RegionFlow, model: &GalerkinModel) -> Self {
        let n = flow.modes;
        let velocity =
            |col: &dyn Fn(usize) -> Complex64| -> Vec<Complex64> { (0..n).map(col).collect() };
        let mut p: Vec<Vec<Complex64>> = Vec::new();
        let mut exponents = Vec::new();
        for t in &flow.terms {
            let v = velocity(&|i| flow.v[(n + i, t.index)]);
            if t.pair {
                p.push(v.iter().map(|z| z.conj()).collect());
                exponents.push(t.lambda.conj());
            }
            p.push(v);
            exponents.push(t.lambda);
        }
        if flow.omega > 0.0 {
            let x = velocity(&|i| flow.forced[n + i]);
            p.push(x.iter().map(|z| z.conj()).collect());
            exponents.push(Complex64::new(0.0, -flow.omega));
            p.push(x);
            exponents.push(Complex64::new(0.0, flow.omega));
        }
        let c = &model.damping;
        let gram = DMatrix::from_fn(p.len(), p.len(), |a, b| {
            (0..n).map(|i| p[a][i] * p[b][i] * c[i]).sum()
        });
        let forcing = p
            .iter()
            .map(|pm| (0..n).map(|i| pm[i] * model.forcing_amplitude[i]).sum())
            .collect();
        Self {
            exponents,
            gram,
            forcing,
        }
    }
}

/// A complex-pair term Re(a e^{λs}) of a segment's tip signal.
#[derive(Debug, Clone, Copy)]
struct PairTerm {
    /// a_k = 2 φ(1)ᵀv_k w_k.
    a: Complex64,
    lambda: Complex64,
    a_abs: f64,
    lambda_abs: f64,
    /// From this s on, |a e^{λs}| ≤ the segment's negligible size.
    negligible_from: f64,
}

/// A real-eigenvalue term a e^{λs} of a segment's tip signal (an over-damped mode).
#[derive(Debug, Clone, Copy)]
struct RealTerm {
    a: f64,
    lambda: f64,
    negligible_from: f64,
}

/// The homogeneous and forced tip signal of one segment.
struct Segment<'a> {
    flow: &'a RegionFlow,
    /// Real modal coordinates at the segment's start.
    y: DVector<f64>,
    phase0: f64,
    /// +1 in free flight (g = d − d₀), −1 in contact (g = d₀ − d).
    sign: f64,
    gap: f64,
    pairs: Vec<PairTerm>,
    reals: Vec<RealTerm>,
    /// |φ(1)ᵀX|: the forced tip amplitude.
    forced_amplitude: f64,
    /// A term below this (1e-17 of Σ|a_k| + |φ(1)ᵀX| + |tip static| + |d₀|, the signal's
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

/// The function a search looks for zeros of: g(s) = sign·(d(s) − level), d the tip
/// displacement. The switching surface is sign = ±1 (free flight, contact) at level d₀.
#[derive(Debug, Clone, Copy)]
struct Target {
    sign: f64,
    level: f64,
}

/// g and its derivatives at a point, with bounds valid from that point on.
#[derive(Debug, Clone, Copy)]
struct Local {
    g: f64,
    gd: f64,
    gdd: f64,
    /// ≥ |g̈| on [s, ∞)
    bound2: f64,
    /// ≥ |g⃛| on [s, ∞)
    bound3: f64,
    /// Σ of the magnitudes of g's terms: its round-off scale.
    scale: f64,
}

impl<'a> Segment<'a> {
    fn new(flow: &'a RegionFlow, x: &DVector<f64>, phase0: f64, gap: f64) -> Self {
        let y = flow.modal(x, phase0);
        let (mut pairs, mut reals) = (Vec::new(), Vec::new());
        let mut scale0 = flow.tip_forced.norm() + flow.tip_static.abs() + gap.abs();
        for t in &flow.terms {
            let a = t.tip * flow.coefficient(&y, t);
            if t.pair {
                // |a| without hypot's overflow guard (slow, and amplitudes are O(1))
                let a_abs = a.norm_sqr().sqrt();
                scale0 += a_abs;
                pairs.push(PairTerm {
                    a,
                    lambda: t.lambda,
                    a_abs,
                    lambda_abs: t.lambda.norm_sqr().sqrt(),
                    negligible_from: 0.0,
                });
            } else {
                scale0 += a.re.abs();
                reals.push(RealTerm {
                    a: a.re,
                    lambda: t.lambda.re,
                    negligible_from: 0.0,
                });
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
            flow,
            y,
            phase0,
            sign: if flow.region == Region::Free {
                1.0
            } else {
                -1.0
            },
            gap,
            pairs,
            reals,
            forced_amplitude: flow.tip_forced.norm(),
            negligible,
        }
    }

    /// Everything the search needs at s, in one pass over the spectrum. Re λ ≤ 0, so each
    /// term's magnitude only decreases after s and the bounds hold on [s, ∞).
    fn local(&self, s: f64, target: Target) -> Local {
        let f = self.flow;
        let w = f.omega;
        let pf = f.tip_forced * polar(1.0, self.phase0 + w * s);
        let (mut d, mut v, mut acc) = (pf.re + f.tip_static, -w * pf.im, -w * w * pf.re);
        let amp = self.forced_amplitude;
        let (mut b2, mut b3) = (w * w * amp, w * w * w * amp);
        let mut scale = amp + f.tip_static.abs() + target.level.abs();
        // a decayed term's magnitude is ≤ negligible; twice that absorbs the rounding of
        // its `negligible_from`
        let tiny = 2.0 * self.negligible;
        for t in &self.pairs {
            let l2 = t.lambda_abs * t.lambda_abs;
            let mag = if s >= t.negligible_from {
                tiny
            } else {
                let decay = decay(t.lambda.re * s);
                let z = t.a * polar(decay, t.lambda.im * s);
                let zl = z * t.lambda;
                d += z.re;
                v += zl.re;
                acc += (zl * t.lambda).re;
                t.a_abs * decay
            };
            b2 += mag * l2;
            b3 += mag * l2 * t.lambda_abs;
            scale += mag;
        }
        for t in &self.reals {
            let l2 = t.lambda * t.lambda;
            let mag = if s >= t.negligible_from {
                tiny
            } else {
                let z = t.a * decay(t.lambda * s);
                d += z;
                v += z * t.lambda;
                acc += z * l2;
                z.abs()
            };
            b2 += mag * l2;
            b3 += mag * l2 * t.lambda.abs();
            scale += mag;
        }
        Local {
            g: target.sign * (d - target.level),
            gd: target.sign * v,
            gdd: target.sign * acc,
            bound2: b2,
            bound3: b3,
            scale,
        }
    }

    /// The switching surface of this segment's region.
    fn surface(&self) -> Target {
        Target {
            sign: self.sign,
            level: self.gap,
        }
    }

    /// The first switch into the other region in (0, s_max], certified.
    fn next_switch(&self, s_max: f64, h_min: f64, rel_tol: f64, stats: &mut Stats) -> Option<f64> {
        self.first_crossing(self.surface(), 0.0, s_max, h_min, rel_tol, stats)
    }

    /// Tip displacement, velocity and acceleration at s, with the bound on |d̈| from s on.
    fn tip_local(&self, s: f64) -> Local {
        self.local(
            s,
            Target {
                sign: 1.0,
                level: 0.0,
            },
        )
    }

    /// Tip displacement and velocity at s.
    fn tip(&self, s: f64) -> (f64, f64) {
        let l = self.tip_local(s);
        (l.g, l.gd)
    }

    /// A bound on |ḋ| at s: the scale against which a touch counts as grazing.
    fn velocity_bound(&self, s: f64) -> f64 {
        let f = self.flow;
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
        f.omega * self.forced_amplitude + pairs + reals
    }

    fn state(&self, s: f64) -> DVector<f64> {
        self.flow.state(&self.y, self.phase0, s)
    }

    /// A step h > 0 such that g < 0 on [s, s + h) is proven, from two upper bounds of g:
    /// the quadratic g + ġh + M₂h²/2 and the cubic g + ġh + g̈h²/2 + M₃h³/6 (the larger
    /// certified step wins; the cubic is much longer in smooth free flight).
    fn certified_step(&self, p: &Local, limit: f64) -> f64 {
        let g = p.g.min(0.0);
        let (gd, m2) = (p.gd, p.bound2);
        let quadratic = if m2 > 0.0 {
            (-gd + (gd * gd - 2.0 * m2 * g).sqrt()) / m2
        } else if gd > 0.0 {
            -g / gd
        } else {
            f64::INFINITY
        };
        let mut h = quadratic.min(limit);
        // grow by doubling while the cubic bound stays negative on all of [0, 2h]
        while h < limit && cubic_max(g, gd, p.gdd, p.bound3, (2.0 * h).min(limit)) < 0.0 {
            h = (2.0 * h).min(limit);
        }
        h
    }

    /// The first s in (0, s_max] with g(s) = 0, certified (see the module doc).
    ///
    /// A segment that starts on the surface (after a switch, or at rest on it) has
    /// |g| within round-off there; the starting rule chose the region from the velocity or
    /// acceleration, so values inside g's round-off band near the start are not crossings.
    /// A crossing is accepted once g has been certainly negative (below minus its
    /// round-off floor), or when g is certainly positive.
    /// The search starts at `from` (0 for the switching surface).
    fn first_crossing(
        &self,
        target: Target,
        from: f64,
        s_max: f64,
        h_min: f64,
        rel_tol: f64,
        stats: &mut Stats,
    ) -> Option<f64> {
        let noise = |p: &Local| 8.0 * f64::EPSILON * p.scale;
        let mut s = from;
        let mut p = self.local(from, target);
        stats.evaluations += 1;
        // The last point with g < 0 strictly, with its value; and whether g has been
        // certainly negative yet.
        let mut last_negative = (p.g < 0.0).then_some((from, p.g));
        let mut inside = p.g < -noise(&p);
        while s < s_max {
            stats.steps += 1;
            if target.sign < 0.0 {
                stats.contact_steps += 1;
            }
            let h = self.certified_step(&p, s_max - s).max(h_min).min(s_max - s);
            // Monotone probe: if ġ > 0 throughout [s, s + 2h], one evaluation at s + 2h
            // decides the (unique) root there.
            let probe = (2.0 * h).min(s_max - s);
            let step = if p.gd - p.bound2 * probe > 0.0 && probe > h {
                probe
            } else {
                h
            };
            let next = self.local(s + step, target);
            stats.evaluations += 1;
            if next.g >= 0.0 && (inside || next.g > noise(&next)) {
                // A root in (s, s + step]: unique if the probe's monotonicity held; otherwise
                // only reachable at the h_min floor or at a tangency within round-off.
                let lo = last_negative.or_else(|| self.negative_point(target, s, step, stats));
                return Some(match lo {
                    Some(lo) => self.polish(target, lo, (s + step, next.g), rel_tol, stats),
                    // no negative value at all: the state left the region at its start
                    None => s + step,
                });
            }
            s += step;
            p = next;
            if p.g < 0.0 {
                last_negative = Some((s, p.g));
            }
            inside |= p.g < -noise(&p);
        }
        None
    }

    /// From a start on the surface (g = 0, ġ < 0), a point in (s, s + step) with g < 0:
    /// the quadratic bound makes g(s + h*/2) < 0 for the first certified step h*.
    fn negative_point(
        &self,
        target: Target,
        s: f64,
        step: f64,
        stats: &mut Stats,
    ) -> Option<(f64, f64)> {
        let mut h = step / 2.0;
        for _ in 0..60 {
            stats.evaluations += 1;
            let g = self.local(s + h, target).g;
            if g < 0.0 {
                return Some((s + h, g));
            }
            h /= 2.0;
        }
        None
    }

    /// The root in [lo, hi] (g(lo) < 0 ≤ g(hi)) by Halley's method on the exact ġ and g̈,
    /// safeguarded by bisection so the iterate never leaves the shrinking bracket; it
    /// stops at the requested relative tolerance or at g's round-off floor.
    fn polish(
        &self,
        target: Target,
        (lo, g_lo): (f64, f64),
        (hi, g_hi): (f64, f64),
        rel_tol: f64,
        stats: &mut Stats,
    ) -> f64 {
        let (mut lo, mut hi) = (lo, hi);
        let secant = lo - g_lo * (hi - lo) / (g_hi - g_lo);
        let mut s = if secant > lo && secant < hi {
            secant
        } else {
            0.5 * (lo + hi)
        };
        for _ in 0..200 {
            let p = self.local(s, target);
            stats.evaluations += 1;
            stats.polish_evaluations += 1;
            if p.g.abs() <= 8.0 * f64::EPSILON * p.scale {
                return s;
            }
            if p.g < 0.0 {
                lo = s;
            } else {
                hi = s;
            }
            // Halley's step (cubic convergence; g̈ is exact and free), Newton's if Halley's
            // denominator degenerates, bisection if the step leaves the bracket
            let den = 2.0 * p.gd * p.gd - p.g * p.gdd;
            let step = if den != 0.0 && den.is_finite() {
                2.0 * p.g * p.gd / den
            } else {
                p.g / p.gd
            };
            let candidate = s - step;
            let next = if step.is_finite() && candidate > lo && candidate < hi {
                candidate
            } else {
                0.5 * (lo + hi)
            };
            let tol = (rel_tol * next.abs()).max(2.0 * f64::EPSILON * next.abs());
            if (next - s).abs() <= tol || hi - lo <= tol {
                return next;
            }
            s = next;
        }
        s
    }
}

impl Segment<'_> {
    /// The largest tip displacement on [0, s_end] if it exceeds `floor` (a value already
    /// attained elsewhere), as (s, d(s)); with the slack `tol` of the certificate.
    ///
    /// Certified by level crossings: with the best value B attained so far, the certified
    /// search for a zero of d − (B + tol) either finds none (then d ≤ B + tol on the whole
    /// segment) or finds where d rises through it; an ascent from there raises B to a
    /// local maximum, and the search resumes from that crossing at the new level.
    fn maximum(
        &self,
        s_end: f64,
        floor: Option<f64>,
        h_min: f64,
        stats: &mut Stats,
    ) -> (Option<(f64, f64)>, f64) {
        let tol = 64.0 * f64::EPSILON * self.tip_local(0.0).scale;
        let mut best: Option<(f64, f64)> = None;
        let mut level = floor.unwrap_or(f64::NEG_INFINITY);
        for s in [0.0, s_end] {
            let d = self.tip(s).0;
            stats.evaluations += 1;
            if d > level {
                best = Some((s, d));
                level = d;
            }
        }
        let mut from = 0.0;
        // each round raises the level by at least `tol`, so this bound is never reached in
        // practice; it only guards against an endless loop on a pathological signal
        for _ in 0..10_000 {
            let target = Target {
                sign: 1.0,
                level: level + tol,
            };
            // the crossing itself needs no precision: the ascent starts from it
            match self.first_crossing(target, from, s_end, h_min, 1e-6, stats) {
                None => break,
                Some(crossing) => {
                    let (s, d) = self.ascend(crossing, s_end, stats);
                    if d > level {
                        best = Some((s, d));
                        level = d;
                    } else {
                        level += tol;
                    }
                    from = crossing;
                }
            }
        }
        (best, tol)
    }

    /// Uphill from s to a local maximum of d in [0, s_end]: Newton steps to the vertex of
    /// the local parabola where d is concave, growing steps in the rising direction where
    /// it is not, each accepted only if d increases (halved otherwise).
    fn ascend(&self, s: f64, s_end: f64, stats: &mut Stats) -> (f64, f64) {
        let mut p = self.tip_local(s);
        let mut s = s;
        stats.evaluations += 1;
        let mut reach = (p.gd.abs() / p.bound2.max(f64::MIN_POSITIVE)).max(1e-12 * s_end);
        for _ in 0..200 {
            let mut step = if p.gdd < 0.0 {
                -p.gd / p.gdd
            } else {
                reach.copysign(p.gd)
            };
            let mut improved = false;
            for _ in 0..60 {
                let candidate = (s + step).clamp(0.0, s_end);
                if candidate == s {
                    break;
                }
                let q = self.tip_local(candidate);
                stats.evaluations += 1;
                if q.g > p.g {
                    reach = 2.0 * (candidate - s).abs();
                    s = candidate;
                    p = q;
                    improved = true;
                    break;
                }
                step /= 2.0;
            }
            if !improved {
                break;
            }
        }
        (s, p.g)
    }
}

/// max over h ∈ [0, H] of g + ġh + g̈h²/2 + Jh³/6 (J ≥ 0): at an end or at a critical point.
fn cubic_max(g: f64, gd: f64, gdd: f64, j: f64, big_h: f64) -> f64 {
    let u = |h: f64| g + h * (gd + h * (gdd / 2.0 + h * j / 6.0));
    let mut best = u(0.0).max(u(big_h));
    // U'(h) = ġ + g̈h + Jh²/2
    let (a, b, c) = (j / 2.0, gdd, gd);
    if a > 0.0 {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let r = disc.sqrt();
            for h in [(-b - r) / (2.0 * a), (-b + r) / (2.0 * a)] {
                if h > 0.0 && h < big_h {
                    best = best.max(u(h));
                }
            }
        }
    } else if b != 0.0 {
        let h = -c / b;
        if h > 0.0 && h < big_h {
            best = best.max(u(h));
        }
    }
    best
}

impl Simulator {
    /// Builds both region flows.
    pub fn new(model: GalerkinModel) -> Result<Self, FlowError> {
        let free = RegionFlow::new(&model, Region::Free)?;
        let contact = RegionFlow::new(&model, Region::Contact)?;
        let energy_tables = [
            EnergyTables::new(&free, &model),
            EnergyTables::new(&contact, &model),
        ];
        Ok(Self {
            free,
            contact,
            model,
            settings: Settings::default(),
            energy_tables,
        })
    }

    /// The forcing period T (1 without forcing).
    pub fn period(&self) -> f64 {
        let omega = self.free.omega;
        if omega > 0.0 {
            2.0 * std::f64::consts::PI / omega
        } else {
            1.0
        }
    }

    /// Free flight (the − region's exact flow) from `x` at `clock` for at most `horizon`:
    /// the certified first time the tip reaches d₀, if any, and the state then (or at the
    /// horizon). The rigid-impact model ([`crate::rigid`]) is built on it.
    pub fn free_flight(
        &self,
        x: &DVector<f64>,
        clock: &Clock,
        horizon: f64,
        stats: &mut Stats,
    ) -> (Option<f64>, DVector<f64>) {
        let seg = Segment::new(
            &self.free,
            x,
            self.free.omega * clock.offset,
            self.model.params.gap,
        );
        stats.segments += 1;
        let h_min = H_MIN_FRACTION * self.period();
        let crossing = seg.next_switch(horizon, h_min, self.settings.root_tolerance, stats);
        let state = seg.state(crossing.unwrap_or(horizon));
        (crossing, state)
    }

    fn flow(&self, region: Region) -> &RegionFlow {
        match region {
            Region::Free => &self.free,
            Region::Contact => &self.contact,
        }
    }

    /// Stored energy: ½|η̇|² + ½ηᵀK⁻η + (k/8)(φ(1)ᵀη − d₀)₊².
    pub fn stored_energy(&self, x: &DVector<f64>) -> f64 {
        let n = self.model.modes();
        let (eta, vel) = (x.rows(0, n), x.rows(n, n));
        let strain: f64 = (0..n)
            .map(|j| self.model.modal_stiffness[j] * eta[j] * eta[j])
            .sum();
        let pen = (self.model.tip.dot(&eta) - self.model.params.gap).max(0.0);
        0.5 * vel.norm_squared() + 0.5 * strain + self.model.params.stop_stiffness / 8.0 * pen * pen
    }

    /// Runs `periods` forcing periods from state x at the start of cycle 0 (t = 0).
    pub fn run(&self, x0: &DVector<f64>, periods: u64, observe: Observe) -> (DVector<f64>, Trace) {
        self.run_from(
            x0,
            Clock {
                period: self.period(),
                cycles: 0,
                offset: 0.0,
            },
            periods,
            observe,
        )
    }

    /// Runs from `start` until `periods` whole periods later (ending at a period boundary).
    pub fn run_from(
        &self,
        x0: &DVector<f64>,
        start: Clock,
        periods: u64,
        observe: Observe,
    ) -> (DVector<f64>, Trace) {
        let period = self.period();
        let omega = self.free.omega;
        let gap = self.model.params.gap;
        let h_min = H_MIN_FRACTION * period;
        let end_cycle = start.cycles + periods as i64;
        let mut trace = Trace::default();
        let mut clock = start;
        let mut x = x0.clone();
        let mut region = self.initial_region(&x, &clock);
        let mut budget = observe.energy.then(|| EnergyBudget {
            initial: self.stored_energy(&x),
            ..Default::default()
        });
        if observe.strobe {
            trace.strobe.push((clock.cycles, x.clone()));
        }
        while clock.cycles < end_cycle {
            let flow = self.flow(region);
            let seg = Segment::new(flow, &x, omega * clock.offset, gap);
            trace.stats.segments += 1;
            // Segments end at a period boundary when samples are taken there, and after at
            // most MAX_SEGMENT_PERIODS periods otherwise, so the forcing phase argument
            // ω·(offset + s) stays below 2π·16 and keeps ~14 digits over any run length.
            let periods_ahead = if observe.strobe || observe.dense_per_period > 0 {
                1
            } else {
                (end_cycle - clock.cycles).min(MAX_SEGMENT_PERIODS)
            };
            let horizon = periods_ahead as f64 * period - clock.offset;
            let crossing = seg.next_switch(
                horizon,
                h_min,
                self.settings.root_tolerance,
                &mut trace.stats,
            );
            let s_end = crossing.unwrap_or(horizon);
            if observe.dense_per_period > 0 {
                self.sample_dense(
                    &seg,
                    &clock,
                    s_end,
                    observe.dense_per_period,
                    region,
                    &mut trace,
                );
            }
            if observe.max_tip {
                let mut work = Stats::default();
                let floor = trace.max_tip.map(|m| m.value);
                let (best, tolerance) = seg.maximum(s_end, floor, h_min, &mut work);
                trace.stats.maximum_evaluations += work.evaluations;
                // the certificate's slack is the largest over all segments
                let tolerance = trace
                    .max_tip
                    .map_or(tolerance, |m| m.tolerance.max(tolerance));
                if let Some((s, value)) = best {
                    let mut at = clock;
                    at.advance(s);
                    trace.max_tip = Some(TipMaximum {
                        clock: at,
                        time: at.time(),
                        value,
                        tolerance,
                    });
                } else if let Some(m) = trace.max_tip.as_mut() {
                    m.tolerance = tolerance;
                }
            }
            if let Some(b) = budget.as_mut() {
                let tables = &self.energy_tables[usize::from(region == Region::Contact)];
                let (w, d) = segment_energy(&seg, tables, s_end);
                b.work += w;
                b.dissipated += d;
            }
            x = seg.state(s_end);
            match crossing {
                Some(s) => {
                    clock.advance(s);
                    let (_, v) = seg.tip(s);
                    // A touch whose normal velocity vanishes to round-off (relative to the
                    // tip velocity scale) does not enter the other region.
                    let vscale = 1e-13 * seg.velocity_bound(s);
                    let grazing = v.abs() <= vscale;
                    if observe.events {
                        trace.events.push(Event {
                            clock,
                            time: clock.time(),
                            entering: region == Region::Free,
                            grazing,
                            tip_velocity: v,
                            state: observe.event_states.then(|| x.as_slice().to_vec()),
                        });
                    }
                    if !grazing {
                        region = match region {
                            Region::Free => Region::Contact,
                            Region::Contact => Region::Free,
                        };
                    }
                }
                None => {
                    clock.cycles += ((clock.offset + s_end) / period).round() as i64;
                    clock.offset = 0.0;
                    if observe.strobe {
                        trace.strobe.push((clock.cycles, x.clone()));
                    }
                }
            }
        }
        if let Some(mut b) = budget {
            b.last = self.stored_energy(&x);
            trace.energy = Some(b);
        }
        (x, trace)
    }

    /// The region a state starts in ([`GalerkinModel::starting_region`]).
    pub fn initial_region(&self, x: &DVector<f64>, clock: &Clock) -> Region {
        self.model.starting_region(x, clock.offset)
    }

    fn sample_dense(
        &self,
        seg: &Segment,
        clock: &Clock,
        s_end: f64,
        per_period: usize,
        region: Region,
        trace: &mut Trace,
    ) {
        let dt = self.period() / per_period as f64;
        // samples on the global grid t = j·dt that fall in [offset, offset + s_end)
        let first = (clock.offset / dt).ceil() as i64;
        let mut j = first;
        loop {
            let s = j as f64 * dt - clock.offset;
            if s >= s_end {
                break;
            }
            let (d, v) = seg.tip(s);
            trace
                .dense
                .push((clock.time() + s, d, v, region == Region::Contact));
            j += 1;
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

/// Exact forcing work and dissipation over [0, S] of a segment: with η̇(s) =
/// Σ_m c_m p_m e^{μ_m s}, ∫ η̇ᵀCη̇ = Σ_mn c_m c_n G_mn ∫e^{(μ_m+μ_n)s} and
/// ∫ fᵀη̇ cos ωt = Σ_m c_m fᵀp_m ∫ e^{μ_m s} cos(θ₀ + ωs), all in closed form; e^{(μ_m+μ_n)S}
/// is the product of the two factors e^{μS}, so a segment costs O(N²) products and O(N)
/// exponentials.
fn segment_energy(seg: &Segment, tables: &EnergyTables, s_end: f64) -> (f64, f64) {
    let f = seg.flow;
    let mut coefficients = Vec::with_capacity(tables.exponents.len());
    for t in &f.terms {
        let w = f.coefficient(&seg.y, t);
        if t.pair {
            coefficients.push(w.conj());
        }
        coefficients.push(w);
    }
    let forcing_phase = Complex64::from_polar(0.5, seg.phase0);
    if f.omega > 0.0 {
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
    if f.omega > 0.0 {
        let iw = Complex64::new(0.0, f.omega);
        let forced_growth = polar(1.0, f.omega * s_end);
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
