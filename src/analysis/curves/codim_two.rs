//! Codimension-two points along a curve: where another multiplier crosses the unit circle,
//! where the number of contacts changes, and the cusps of fold curves.

use super::{CurveKind, CurvePoint};
use serde::Serialize;

/// What a curve meets at a codimension-two point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Meets {
    /// Another multiplier reaches +1.
    Fold,
    /// Another multiplier reaches −1.
    PeriodDoubling,
    /// A complex pair reaches the unit circle.
    NeimarkSacker,
    /// The number of contacts per period changes (fold and period-doubling curves).
    Grazing,
    /// Another fold curve, at a cusp: the fold curve's direction in (p, q) reverses (its
    /// tangent lies in the state alone there).
    Cusp,
}

/// A codimension-two point between points `index` and `index + 1` of a curve.
#[derive(Debug, Clone, Serialize)]
pub struct CodimTwo {
    /// The curve it meets.
    pub meets: Meets,
    /// p and q, interpolated.
    pub p: f64,
    /// q.
    pub q: f64,
    /// The first of the two points.
    pub index: usize,
}

/// The moduli of the leading negative real, positive real and complex multipliers, the
/// critical one (nearest +1 on a fold curve, −1 on a period-doubling curve) left out.
fn others(kind: CurveKind, multipliers: &[[f64; 2]]) -> [f64; 3] {
    let critical = match kind {
        CurveKind::Fold => Some(1.0),
        CurveKind::PeriodDoubling => Some(-1.0),
        CurveKind::Grazing | CurveKind::NeimarkSacker => None,
    };
    let skip = critical.and_then(|c| {
        (0..multipliers.len()).min_by(|&i, &j| {
            let d = |k: usize| (multipliers[k][0] - c).hypot(multipliers[k][1]);
            d(i).total_cmp(&d(j))
        })
    });
    // on a Neimark–Sacker curve the critical pair: the complex multipliers nearest the circle
    let pair = (kind == CurveKind::NeimarkSacker)
        .then(|| {
            (0..multipliers.len())
                .filter(|&k| multipliers[k][1] > 0.0)
                .min_by(|&i, &j| {
                    let d = |k: usize| (multipliers[k][0].hypot(multipliers[k][1]) - 1.0).abs();
                    d(i).total_cmp(&d(j))
                })
        })
        .flatten();
    let is_pair = |i: usize| {
        pair.is_some_and(|p| {
            let (a, b) = (multipliers[p], multipliers[i]);
            i == p || (b[0] == a[0] && b[1] == -a[1])
        })
    };
    let mut out = [0.0f64; 3];
    for (i, z) in multipliers.iter().enumerate() {
        if Some(i) == skip || is_pair(i) {
            continue;
        }
        let r = z[0].hypot(z[1]);
        let slot = if z[1].abs() > 1e-9 * r.max(1.0) {
            2
        } else if z[0] < 0.0 {
            0
        } else {
            1
        };
        out[slot] = out[slot].max(r);
    }
    out
}

/// The codimension-two points along a curve.
pub(super) fn detect(kind: CurveKind, points: &[CurvePoint]) -> Vec<CodimTwo> {
    let mut out = Vec::new();
    for (i, w) in points.windows(2).enumerate() {
        let (a, b) = (&w[0], &w[1]);
        let mut push = |meets, fa: f64, fb: f64| {
            let s = if fa == fb {
                0.5
            } else {
                (fa / (fa - fb)).clamp(0.0, 1.0)
            };
            let lerp = |x: f64, y: f64| (x.ln() + s * (y.ln() - x.ln())).exp();
            out.push(CodimTwo {
                meets,
                p: lerp(a.p, b.p),
                q: lerp(a.q, b.q),
                index: i,
            });
        };
        let (oa, ob) = (others(kind, &a.multipliers), others(kind, &b.multipliers));
        for (slot, meets) in [Meets::PeriodDoubling, Meets::Fold, Meets::NeimarkSacker]
            .into_iter()
            .enumerate()
        {
            if (oa[slot] > 1.0) != (ob[slot] > 1.0) {
                push(meets, oa[slot] - 1.0, ob[slot] - 1.0);
            }
        }
        if kind != CurveKind::Grazing && a.impacts_n != b.impacts_n {
            push(Meets::Grazing, 0.5, -0.5);
        }
    }
    if kind == CurveKind::Fold {
        // a cusp: two consecutive secants in (ln p, ln q) point against each other
        let secant = |a: &CurvePoint, b: &CurvePoint| ((b.p / a.p).ln(), (b.q / a.q).ln());
        for (i, w) in points.windows(3).enumerate() {
            let (s1, s2) = (secant(&w[0], &w[1]), secant(&w[1], &w[2]));
            if s1.0 * s2.0 + s1.1 * s2.1 < 0.0 {
                out.push(CodimTwo {
                    meets: Meets::Cusp,
                    p: w[1].p,
                    q: w[1].q,
                    index: i + 1,
                });
            }
        }
        out.sort_by_key(|c| c.index);
    }
    out
}
