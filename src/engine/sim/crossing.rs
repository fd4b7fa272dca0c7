//! The certified crossing search: the first zero of g(s) in (from, s_max] for any
//! [`Signal`] with derivative bounds valid ahead ([`super::signal`]).
//!
//! **Certified advancement.** From s with g < 0, g(s + h) ≤ g + ġh + M₂h²/2 < 0 for
//! h < h* = (−ġ + √(ġ² − 2M₂g))/M₂: no root can hide in [s, s + h*). A cubic bound
//! g + ġh + g̈h²/2 + M₃h³/6 often certifies longer steps (it is used when it does). When
//! ġ − M₂·2h > 0, g is increasing on [s, s + 2h] and one evaluation at s + 2h decides
//! whether the unique root there exists; it is then polished by Halley's method
//! (bracketed) to round-off. The paper instead brackets extrema by golden-section search
//! (§5.2), which has no such guarantee.
//!
//! **Resolution.** Steps are never shorter than `h_min` (1e-13 of a forcing period in the
//! simulator), so a contact whose penetration is below M₂·h_min²/2 may be passed over;
//! every deeper one is found.

use super::signal::{Local, Signal, Target};
use super::Stats;

/// What the search found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Found {
    /// g crosses zero at s: the switching surface is passed.
    Crossing(f64),
    /// g rises to within its uncertainty of zero at s and turns back: a touch of the
    /// surface (grazing) that does not pass it.
    Touch(f64),
}

/// The first crossing or touch of zero in (from, s_max] (see [`first_crossing`]); a touch
/// is a local maximum of g within [`Local::noise`] of zero, located by a Newton step on ġ.
pub fn first_event<S: Signal + ?Sized>(
    sig: &S,
    target: Target,
    from: f64,
    s_max: f64,
    h_min: f64,
    rel_tol: f64,
    stats: &mut Stats,
) -> Option<Found> {
    search(sig, target, from, s_max, h_min, rel_tol, true, stats)
}

/// The first s in (from, s_max] with g(s) = 0, certified (see the module doc).
///
/// A segment that starts on the surface (after a switch, or at rest on it) has
/// |g| within its uncertainty there ([`Local::noise`]: round-off plus the error of the
/// modal representation); the starting rule chose the region from the velocity or
/// acceleration, so values inside that band near the start are not crossings. A crossing
/// is accepted once g has been certainly negative (below minus its uncertainty), or when
/// g is certainly positive.
pub fn first_crossing<S: Signal + ?Sized>(
    sig: &S,
    target: Target,
    from: f64,
    s_max: f64,
    h_min: f64,
    rel_tol: f64,
    stats: &mut Stats,
) -> Option<f64> {
    match search(sig, target, from, s_max, h_min, rel_tol, false, stats) {
        Some(Found::Crossing(s)) => Some(s),
        _ => None,
    }
}

#[allow(clippy::too_many_arguments)]
fn search<S: Signal + ?Sized>(
    sig: &S,
    target: Target,
    from: f64,
    s_max: f64,
    h_min: f64,
    rel_tol: f64,
    touches: bool,
    stats: &mut Stats,
) -> Option<Found> {
    let noise = |p: &Local| p.noise();
    let mut s = from;
    let mut p = sig.local(from, target);
    let start = p;
    stats.evaluations += 1;
    // The last point with g < 0 strictly, with its value; and whether g has been
    // certainly negative yet.
    let mut last_negative = (p.g < 0.0).then_some((from, p.g));
    let mut inside = p.g < -noise(&p);
    let mut last_step: f64 = 0.0;
    while s < s_max {
        stats.steps += 1;
        if target.sign < 0.0 {
            stats.contact_steps += 1;
        }
        // With touches reported, a near-zero maximum of g must not be stepped over: the
        // steps then certify g < −noise, not g < 0, and a rise into the noise band is
        // followed to its top by a Newton step on ġ.
        if touches && inside && p.g >= -noise(&p) && p.gd > 0.0 && p.gdd < 0.0 {
            let top = (s - p.gd / p.gdd).min(s_max);
            let q = sig.local(top, target);
            stats.evaluations += 1;
            if q.g > noise(&q) {
                // it does cross: the root lies between the last negative point and the top
                let lo = last_negative.unwrap_or((s, p.g));
                return Some(Found::Crossing(polish(
                    sig,
                    target,
                    lo,
                    (top, q.g),
                    rel_tol,
                    stats,
                )));
            }
            if q.gd.abs() <= p.gd.abs() && top > s {
                return Some(Found::Touch(top));
            }
        }
        // What the step must not pass over. In the band at the start (g within its
        // uncertainty of zero and never yet certainly negative) a crossing counts only
        // once g is certainly positive, so the step need only keep g below +noise — which
        // lets a segment that leaves the surface tangentially (a release from the stop)
        // take long steps instead of h_min ones through the band. Inside, a crossing
        // counts at zero, and a touch (reported) at −noise.
        let certify = Local {
            g: if !inside {
                p.g - noise(&p)
            } else if touches {
                p.g + noise(&p)
            } else {
                p.g
            },
            ..p
        };
        let certified = certified_step(&certify, s_max - s);
        let h = certified.max(h_min).min(s_max - s);
        // Monotone probe: if ġ > 0 throughout [s, s + 2h], one evaluation at s + 2h
        // decides the (unique) root there.
        let probe = (2.0 * h).min(s_max - s);
        let mut step = if p.gd - p.bound2 * probe > 0.0 && probe > h {
            probe
        } else {
            h
        };
        // Shape step, where the certificate alone would take the h_min floor (g within
        // its uncertainty of zero): on an interval where g is certainly increasing
        // (ġ > 0), or, once g has been certainly negative, certainly convex (g̈ > 0), g has
        // no interior maximum — neither a touch nor a crossing that turns back — and at
        // most one root, so one evaluation at its end decides. This crosses the band of a
        // slow release from a stiff stop (ġ ~ 1e-12 against a band of 1e-17 at 1e11k₁:
        // 4e7 h_min steps for one release) in a few dozen steps. In the start band only
        // from a point with g < 0, which brackets the root with the step's end (from
        // g ≥ 0 the crossing would be put at the step's end), and by monotonicity only (a
        // dip below −noise skipped over would leave `inside` unset). The step at most
        // doubles the last one, so a crossing is bracketed about as tightly as by the
        // certified steps (the polish accepts any point within round-off of zero: over a
        // long bracket that may be a dip's flat bottom rather than the rising root).
        let shape = if certified < h_min && (inside || p.g < 0.0) {
            shape_horizon(&p, inside)
                .min(2.0 * last_step.max(h))
                .min(s_max - s)
        } else {
            0.0
        };
        let shaped = shape > step;
        if shaped {
            step = shape;
        }
        let next = sig.local(s + step, target);
        stats.evaluations += 1;
        // A shape step that lands within the band of zero (touches reported) decides
        // nothing yet: as after the short steps that approach the band, the top of g is
        // sought from there (a touch if it stays within the band, else a crossing).
        let undecided = shaped && touches && inside && next.g <= noise(&next);
        if next.g >= 0.0 && (inside || next.g > noise(&next)) && !undecided {
            // A root in (s, s + step]: unique if the probe's monotonicity held; otherwise
            // only reachable at the h_min floor or at a tangency within round-off. From the
            // start band, whose negative values are round-off, the bracket starts at the
            // bottom of the dip the tip makes on leaving (where ġ = 0) when g is negative
            // there: the root is then the rising one. Sought from a noisy "negative" point
            // near the start instead, the polish may settle on the falling side (a dip of
            // 1e-17 below a tip chattering at 1e10k₁ with N = 1 did: an "entry" moving
            // away from the stop).
            let dip = if inside {
                None
            } else {
                [(from, start), (s, p)].into_iter().find_map(|(at, q)| {
                    let bottom = at - q.gd / q.gdd;
                    if q.gd < 0.0 && q.gdd > 0.0 && bottom > at && bottom < s + step {
                        let b = sig.local(bottom, target);
                        stats.evaluations += 1;
                        (b.g < 0.0).then_some((bottom, b.g))
                    } else {
                        None
                    }
                })
            };
            let lo = dip
                .or(last_negative)
                .or_else(|| negative_point(sig, target, s, step, stats));
            return Some(Found::Crossing(match lo {
                Some(lo) => polish(sig, target, lo, (s + step, next.g), rel_tol, stats),
                // No negative value at all, and g falling again at the step's end: over
                // long steps within its band g rose to just above it and turned back (N =
                // 20 at 1e11k₁, d₀ = 0.006: ġ = −1e-11 there, 7.8e-6 after the start).
                // Put at the step's end the switch would carry a velocity into the region
                // it leaves; at the top of g its velocity vanishes, and the caller judges it
                // a touch within round-off.
                None if p.gd > 0.0 && next.gd < 0.0 => top(sig, target, s, s + step, stats),
                // no negative value at all: the state left the region at its start
                None => s + step,
            }));
        }
        // a touch: g has been certainly negative, rises to within its uncertainty of zero
        // and turns back inside this step (ġ changes sign)
        if touches && inside && p.gd > 0.0 && next.gd <= 0.0 && p.g.max(next.g) >= -noise(&next) {
            let (s0, q) = if p.g >= next.g {
                (s, p)
            } else {
                (s + step, next)
            };
            let top = if q.gdd < 0.0 {
                (s0 - q.gd / q.gdd).clamp(s, s + step)
            } else {
                s0
            };
            return Some(Found::Touch(top));
        }
        s += step;
        last_step = step;
        p = next;
        if p.g < 0.0 {
            last_negative = Some((s, p.g));
        }
        inside |= p.g < -noise(&p);
    }
    None
}

/// A step h > 0 such that g < 0 on [s, s + h) is proven, from two upper bounds of g:
/// the quadratic g + ġh + M₂h²/2 and the cubic g + ġh + g̈h²/2 + M₃h³/6 (the larger
/// certified step wins; the cubic is much longer in smooth free flight).
pub fn certified_step(p: &Local, limit: f64) -> f64 {
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

/// The longest h such that, on [s, s + h], ġ > 0 is proven, or (with `convex`) g̈ > 0,
/// from the lower bounds ġ − M₂τ, ġ + g̈τ − M₃τ²/2 and g̈ − M₃τ, with ġ and g̈ first
/// lowered by their round-off (8ε times the magnitudes of their terms); 0 if neither is.
fn shape_horizon(p: &Local, convex: bool) -> f64 {
    let gd = p.gd - 8.0 * f64::EPSILON * p.scale1;
    let gdd = p.gdd - 8.0 * f64::EPSILON * p.bound2;
    let (m2, m3) = (p.bound2, p.bound3);
    let mut h: f64 = 0.0;
    if gd > 0.0 {
        // ġ − M₂τ > 0
        h = h.max(if m2 > 0.0 { gd / m2 } else { f64::INFINITY });
        // ġ + g̈τ − M₃τ²/2 > 0 up to its positive root
        h = h.max(if m3 > 0.0 {
            (gdd + (gdd * gdd + 2.0 * m3 * gd).sqrt()) / m3
        } else if gdd >= 0.0 {
            f64::INFINITY
        } else {
            -gd / gdd
        });
    }
    if convex && gdd > 0.0 {
        h = h.max(if m3 > 0.0 { gdd / m3 } else { f64::INFINITY });
    }
    h
}

/// The maximum of g in (a, b), given ġ(a) > 0 > ġ(b): bisection on ġ to round-off.
fn top<S: Signal + ?Sized>(sig: &S, target: Target, a: f64, b: f64, stats: &mut Stats) -> f64 {
    let (mut lo, mut hi) = (a, b);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        stats.evaluations += 1;
        if sig.local(mid, target).gd > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// From a start on the surface (g = 0, ġ < 0), a point in (s, s + step) with g < 0:
/// the quadratic bound makes g(s + h*/2) < 0 for the first certified step h*.
fn negative_point<S: Signal + ?Sized>(
    sig: &S,
    target: Target,
    s: f64,
    step: f64,
    stats: &mut Stats,
) -> Option<(f64, f64)> {
    let mut h = step / 2.0;
    for _ in 0..60 {
        stats.evaluations += 1;
        let g = sig.local(s + h, target).g;
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
fn polish<S: Signal + ?Sized>(
    sig: &S,
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
        let p = sig.local(s, target);
        stats.evaluations += 1;
        stats.polish_evaluations += 1;
        // a root of g rising through zero: a point within round-off of zero where g falls
        // (a small excursion of the start band, say) is not it — the bracket goes on
        if p.g.abs() <= 8.0 * f64::EPSILON * p.scale && p.gd >= 0.0 {
            return s;
        }
        // (the representation floor is a fixed offset of g, not noise: the polish goes on
        // to the root of the represented g)
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

#[cfg(test)]
#[path = "crossing_tests.rs"]
mod tests;
