//! The certified maximum of the tip displacement over a segment.
//!
//! With the best value B attained so far, the certified search (`super::crossing`) for a
//! zero of d − (B + δ) either finds none (then d ≤ B + δ on the whole segment) or finds
//! where d rises through it; an ascent from there raises B to a local maximum, and the
//! search resumes from that crossing at the new level. δ = 64ε times the signal's scale.

use super::crossing::first_crossing;
use super::signal::{Target, TipSignal};
use super::Stats;

/// The largest tip displacement on [0, s_end] if it exceeds `floor` (a value already
/// attained elsewhere), as (s, d(s)); with the slack `tol` of the certificate.
pub fn maximum(
    sig: &TipSignal,
    s_end: f64,
    floor: Option<f64>,
    h_min: f64,
    stats: &mut Stats,
) -> (Option<(f64, f64)>, f64) {
    let tol = 64.0 * f64::EPSILON * sig.tip_local(0.0).scale;
    let mut best: Option<(f64, f64)> = None;
    let mut level = floor.unwrap_or(f64::NEG_INFINITY);
    for s in [0.0, s_end] {
        let d = sig.tip(s).0;
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
        match first_crossing(sig, target, from, s_end, h_min, 1e-6, stats) {
            None => break,
            Some(crossing) => {
                let (s, d) = ascend(sig, crossing, s_end, stats);
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
fn ascend(sig: &TipSignal, s: f64, s_end: f64, stats: &mut Stats) -> (f64, f64) {
    let mut p = sig.tip_local(s);
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
            let q = sig.tip_local(candidate);
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
