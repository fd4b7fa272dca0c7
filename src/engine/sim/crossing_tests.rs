//! Unit tests of the certified crossing search on synthetic exponential sums, where the
//! roots are known in closed form or by brute force.

use super::*;
use crate::engine::sim::signal::{Term, TipSignal};
use num_complex::Complex64;
use std::f64::consts::PI;

/// A signal with its bounds scaled by `factor`: a mutation of the certificate. With
/// `factor` < 1 the search takes steps its bounds no longer justify.
struct ScaledBounds<'a>(&'a TipSignal, f64);

impl Signal for ScaledBounds<'_> {
    fn local(&self, s: f64, target: Target) -> Local {
        let mut l = self.0.local(s, target);
        l.bound2 *= self.1;
        l.bound3 *= self.1;
        l
    }
}

fn find(sig: &dyn Signal, level: f64, s_max: f64) -> Option<f64> {
    let target = Target { sign: 1.0, level };
    let mut stats = Stats::default();
    first_crossing(sig, target, 0.0, s_max, 1e-13 * s_max, 1e-15, &mut stats)
}

/// d(s) = −A cos Ωs (a pair with λ = iΩ, a = −A): a trough at s = 0, crests at
/// s = (2j + 1)π/Ω.
fn cosine(amplitude: f64, omega: f64) -> TipSignal {
    let terms = [Term::Pair {
        a: Complex64::new(-amplitude, 0.0),
        lambda: Complex64::new(0.0, omega),
    }];
    TipSignal::new(0.0, 0.0, Complex64::new(0.0, 0.0), 0.0, amplitude, terms)
}

#[test]
fn near_tangencies_are_found_at_every_depth_down_to_1e_14() {
    // The level sits a relative depth δ below the crest: the tip is above it only for
    // |Ωs − π| < acos(1 − δ) ≈ √(2δ), a window of 2.8e-7 of the period at δ = 1e-14.
    let (a, omega) = (0.7, 40.0);
    let sig = cosine(a, omega);
    for depth in [1e-6, 1e-8, 1e-10, 1e-12, 1e-14] {
        let c = 1.0 - depth;
        let level = a * c;
        // first root of −A cos Ωs = A c
        let exact = (PI - c.acos()) / omega;
        let found = find(&sig, level, 3.0 * PI / omega).expect("a crossing exists");
        // conditioning of the root: an error of 16ε·A in g moves it by 16ε·A/|ġ(s*)|
        let slope = a * omega * (1.0 - c * c).sqrt();
        let tol = 16.0 * f64::EPSILON * 2.0 * a / slope + 4.0 * f64::EPSILON * exact;
        assert!(
            (found - exact).abs() <= tol,
            "depth {depth:e}: {found} vs {exact} (tol {tol:e})"
        );
    }
}

#[test]
fn a_level_above_the_crest_is_never_crossed_and_a_tangency_is_at_most_touched() {
    let (a, omega) = (1.3, 7.0);
    let sig = cosine(a, omega);
    // the crest misses the level by 1e-10 relative (far above g's round-off, 1e-15):
    // no crossing over five periods
    assert_eq!(find(&sig, a * (1.0 + 1e-10), 10.0 * PI / omega), None);
    // a double root (the level exactly at the crest): either no crossing, or a touch at
    // one of the crests, within √(round-off/curvature) ≈ 1e-7 rad of it — never a point
    // between crests
    if let Some(s) = find(&sig, a, 10.0 * PI / omega) {
        let phase = s * omega - PI;
        let off = phase - (phase / (2.0 * PI)).round() * 2.0 * PI;
        assert!(off.abs() < 1e-6, "touch reported {off:e} rad from a crest");
    }
}

/// The first root of `sig` − level in (0, s_max] by brute force: sign changes on a grid
/// of step h, then bisection to the last bit.
fn brute_force(sig: &TipSignal, level: f64, s_max: f64, h: f64) -> Option<f64> {
    let g = |s: f64| sig.tip(s).0 - level;
    let steps = (s_max / h).ceil() as usize;
    for i in 0..steps {
        let (lo, hi) = (i as f64 * h, ((i + 1) as f64 * h).min(s_max));
        if g(lo) < 0.0 && g(hi) >= 0.0 {
            let (mut lo, mut hi) = (lo, hi);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if g(mid) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Some(hi);
        }
    }
    None
}

/// The ripple families: (Ω/ω₁, ripple size r, relative depth δ of the level below the
/// ripple's crests). The level is 1 − 10⁻³ + (1 − δ)r.
const FAMILIES: [(f64, f64, f64); 2] = [(300.0, 1e-3, 1e-4), (57.0, 0.1, 0.2)];

/// A slow carrier near its crest (d = 1 at s = π/ω₁) plus a fast ripple of size r at
/// Ω with phase φ, and a level just above the carrier's crest: only the ripple's peaks
/// reach it, each for a small fraction of one fast period — a root hidden between any
/// coarse samples (as in the simulator's mode-5 double-crossing test).
fn carrier_with_ripple(phase: f64, (ratio, ripple, depth): (f64, f64, f64)) -> (TipSignal, f64) {
    let w1 = 3.5;
    let terms = [
        Term::Pair {
            a: Complex64::new(-1.0, 0.0),
            lambda: Complex64::new(-1e-3, w1),
        },
        Term::Pair {
            a: Complex64::from_polar(ripple, phase),
            lambda: Complex64::new(-0.02, ratio * w1),
        },
    ];
    let sig = TipSignal::new(0.0, 0.0, Complex64::new(0.0, 0.0), 0.0, 1.0, terms);
    (sig, 1.0 - 1e-3 + (1.0 - depth) * ripple)
}

const PHASES: usize = 24;

fn phase(i: usize) -> f64 {
    i as f64 * 2.0 * PI / PHASES as f64
}

#[test]
fn roots_hidden_between_samples_agree_with_brute_force() {
    let s_max = 2.0 * PI / 3.5;
    for family in FAMILIES {
        let mut crossings = 0;
        for i in 0..PHASES {
            let (sig, level) = carrier_with_ripple(phase(i), family);
            // 2000 samples per fast period: the windows above the level span ≥ 0.4% of it
            let h = 2.0 * PI / (family.0 * 3.5) / 2e3;
            let reference = brute_force(&sig, level, s_max, h);
            let found = find(&sig, level, s_max);
            match (found, reference) {
                (Some(a), Some(b)) => {
                    crossings += 1;
                    // both polished/bisected to round-off: 1e-12 absolute (s ~ 1)
                    assert!((a - b).abs() < 1e-12, "{family:?} phase {i}: {a} vs {b}");
                }
                (None, None) => {}
                other => panic!(
                    "{family:?} phase {i}: certified {:?}, brute force {:?}",
                    other.0, other.1
                ),
            }
        }
        assert!(crossings > PHASES / 2, "{family:?}: {crossings} crossings");
    }
}

#[test]
fn many_modes_over_twelve_decades() {
    // 30 pairs, amplitudes from 1 down to 1e-12, beam-like frequencies (2j − 1)², light
    // damping, plus a forced harmonic and two over-damped real terms; the level is
    // crossed where the smallest terms still shape the signal.
    let terms: Vec<Term> = (0..30)
        .map(|j| {
            let amp = 10f64.powf(-12.0 * j as f64 / 29.0);
            let w = ((2 * j + 1) as f64).powi(2);
            Term::Pair {
                a: Complex64::from_polar(amp, 0.3 * j as f64),
                lambda: Complex64::new(-0.01 * w, w),
            }
        })
        .chain([
            Term::Real {
                a: 0.4,
                lambda: -50.0,
            },
            Term::Real {
                a: -1e-9,
                lambda: -2e4,
            },
        ])
        .collect();
    let sig = TipSignal::new(2.0, 0.4, Complex64::new(0.3, -0.2), 0.05, 1.0, terms);
    let s_max = 3.0;
    // the search starts below the level (as in a region): levels above d(0)
    let d0 = sig.tip(0.0).0;
    // the levels side by side: the brute force is this test's cost (~10⁶ samples a level)
    std::thread::scope(|scope| {
        for level in [d0 + 0.05, d0 + 0.3, d0 + 0.6, d0 + 0.9] {
            let sig = &sig;
            scope.spawn(move || {
                // the fastest pair has period 2π/3481: 400 samples of it per step
                let reference = brute_force(sig, level, s_max, 2.0 * PI / 3481.0 / 400.0);
                let found = find(sig, level, s_max);
                match (found, reference) {
                    (Some(a), Some(b)) => {
                        assert!((a - b).abs() < 1e-12, "level {level}: {a} vs {b}")
                    }
                    (None, None) => {}
                    other => panic!("level {level}: {other:?}"),
                }
            });
        }
    });
}

#[test]
fn halving_the_bounds_makes_the_search_miss_roots() {
    // The families of `roots_hidden_between_samples_agree_with_brute_force`, with the
    // certificate's bounds halved: steps then jump over ripple peaks (measured: 6 and 5
    // of 24 answers change), so that test is sensitive to the bound, not only to the
    // polish.
    let s_max = 2.0 * PI / 3.5;
    for family in FAMILIES {
        let changed = (0..PHASES)
            .filter(|&i| {
                let (sig, level) = carrier_with_ripple(phase(i), family);
                let honest = find(&sig, level, s_max);
                let mutated = find(&ScaledBounds(&sig, 0.5), level, s_max);
                match (honest, mutated) {
                    (Some(a), Some(b)) => (a - b).abs() > 1e-12,
                    (None, None) => false,
                    _ => true,
                }
            })
            .count();
        assert!(
            changed > 0,
            "{family:?}: halving the bound changed no answer"
        );
    }
}
