//! Bifurcations between consecutive points of a branch, each located by linear
//! interpolation of its test function between the two points (so it lies in `between`).

use super::BranchPoint;
use serde::Serialize;

/// What happens at a bifurcation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum BifurcationKind {
    /// The branch turns back in p (the tangent's p component changes sign); a multiplier
    /// passes +1 there.
    Fold,
    /// A real multiplier passes −1.
    PeriodDoubling,
    /// A complex pair of multipliers passes the unit circle.
    NeimarkSacker,
    /// A real multiplier passes +1 without a fold (symmetry-breaking or transcritical).
    BranchPoint,
    /// A contact appears (a near miss in free flight touches the stop) or disappears (a
    /// contact's penetration depth reaches 0): the number of contacts per period changes.
    Grazing,
}

impl std::fmt::Display for BifurcationKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BifurcationKind::Fold => "fold",
            BifurcationKind::PeriodDoubling => "period doubling",
            BifurcationKind::NeimarkSacker => "Neimark–Sacker",
            BifurcationKind::BranchPoint => "branch point",
            BifurcationKind::Grazing => "grazing",
        })
    }
}

/// A bifurcation found between points `index` and `index + 1` of a branch.
#[derive(Debug, Clone, Serialize)]
pub struct Bifurcation {
    /// Its kind.
    pub kind: BifurcationKind,
    /// The parameter p, interpolated.
    pub parameter: f64,
    /// The parameters of the two points it lies between.
    pub between: (f64, f64),
    /// The first of the two points.
    pub index: usize,
    /// Contacts per period before and after.
    pub impacts: (usize, usize),
    /// Stable before and after.
    pub stable: (bool, bool),
}

/// Multipliers on the real axis: |Im μ| below this times max(1, |μ|). The eigensolver
/// returns real eigenvalues of the real monodromy with Im = 0 or round-off (~1e-16‖M‖), and
/// a genuine complex pair near the real axis is about to become real anyway (a collision,
/// not a crossing of the unit circle), so the threshold only needs to sit between the two.
const REAL: f64 = 1e-9;

/// The largest modulus among real negative, real positive and complex multipliers (0 when
/// there are none).
fn leading(p: &BranchPoint) -> [f64; 3] {
    let mut out = [0.0f64; 3];
    for z in &p.multipliers {
        let r = z[0].hypot(z[1]);
        let slot = if z[1].abs() > REAL * r.max(1.0) {
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

/// Where f crosses 0 between (u_a, f_a) and (u_b, f_b), linearly in ln p.
fn interpolate(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (ua, ub) = (a.0.ln(), b.0.ln());
    let w = if a.1 == b.1 { 0.5 } else { a.1 / (a.1 - b.1) };
    (ua + w.clamp(0.0, 1.0) * (ub - ua)).exp()
}

/// Where the grazing lies: the grazing distance is positive on both sides and 0 at the
/// grazing, so it is interpolated as +g_a → −g_b.
pub(crate) fn grazing_location(a: &BranchPoint, b: &BranchPoint) -> f64 {
    let g = |p: &BranchPoint| p.shape.grazing_distance.unwrap_or(0.0);
    interpolate((a.parameter, g(a)), (b.parameter, -g(b)))
}

/// The bifurcations along a branch.
pub fn bifurcations(points: &[BranchPoint]) -> Vec<Bifurcation> {
    let mut out = Vec::new();
    for (i, w) in points.windows(2).enumerate() {
        let (a, b) = (&w[0], &w[1]);
        let mut push = |kind, parameter| {
            out.push(Bifurcation {
                kind,
                parameter,
                between: (a.parameter, b.parameter),
                index: i,
                impacts: (a.impacts_n, b.impacts_n),
                stable: (a.stable, b.stable),
            })
        };
        let (la, lb) = (leading(a), leading(b));
        let crosses = |x: f64, y: f64| (x > 1.0) != (y > 1.0);
        let fold = a.tangent_u.signum() != b.tangent_u.signum();
        if fold {
            push(
                BifurcationKind::Fold,
                interpolate((a.parameter, a.tangent_u), (b.parameter, b.tangent_u)),
            );
        }
        if crosses(la[0], lb[0]) {
            push(
                BifurcationKind::PeriodDoubling,
                interpolate((a.parameter, la[0] - 1.0), (b.parameter, lb[0] - 1.0)),
            );
        }
        if crosses(la[1], lb[1]) && !fold {
            push(
                BifurcationKind::BranchPoint,
                interpolate((a.parameter, la[1] - 1.0), (b.parameter, lb[1] - 1.0)),
            );
        }
        if crosses(la[2], lb[2]) {
            push(
                BifurcationKind::NeimarkSacker,
                interpolate((a.parameter, la[2] - 1.0), (b.parameter, lb[2] - 1.0)),
            );
        }
        if a.impacts_n != b.impacts_n {
            push(BifurcationKind::Grazing, grazing_location(a, b));
        }
    }
    out
}
