//! The book's one rule for the truncation ± of a value computed with N modes: a convergence
//! estimate over at least three N, never a one-step change.
//!
//! A one-step change |f(N') − f(N)| is not an error bound: where f(N) = f∞ + C N⁻ᵖ with
//! p ≈ 2–3, f(N) may lie further from f∞ than from f(N') (an N → ∞ extrapolation of r_E at
//! ω = 2(β₁⁻)², k = 10³k₁ lies 1.1 × 10⁻⁴ from N = 20, outside the one-step ± 7.7 × 10⁻⁵).
//! So: Richardson extrapolation in N over the three finest N of a ladder with the observed
//! order ([`crate::base::verification::richardson_in_resolution`]), accepted in (0.5, 10) as
//! the refinement studies of [`super::Study`] accept it; the ± of the value at N is its
//! distance from the limit plus the limit's own uncertainty (the grid convergence index of
//! the finest value, factor of safety 1.25). Outside the asymptotic range (differences of
//! alternating sign, an order out of range) the ± is the spread of the whole ladder.

use crate::base::verification::{richardson_in_resolution, Richardson};
use serde::Serialize;

/// A truncation ± and how it was estimated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruncationError {
    /// The N of the value the ± belongs to.
    pub modes: usize,
    /// The ± (absolute, in the value's units).
    pub plus_minus: f64,
    /// The N of the ladder, ascending.
    pub ladder: Vec<usize>,
    /// The observed order p of f(N) − f∞ ∝ N⁻ᵖ, when in (0.5, 10).
    pub order: Option<f64>,
    /// The extrapolated limit f∞, when an order was accepted.
    pub limit: Option<f64>,
}

impl TruncationError {
    /// The basis of the ±, for a cited number ("Richardson over N = 20, 30, 40 …").
    pub fn basis(&self) -> String {
        let list = |ns: &[usize]| {
            ns.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let ns = list(&self.ladder);
        match self.order {
            Some(p) => format!(
                "truncation: Richardson extrapolation over N = {} (observed order {p:.1}); distance of N = {} from the limit plus the limit's uncertainty",
                list(&self.ladder[self.ladder.len().saturating_sub(3)..]),
                self.modes
            ),
            None => format!(
                "truncation: the spread over N = {ns} (no order of convergence in (0.5, 10) yet)"
            ),
        }
    }
}

/// The truncation ± of `ladder`'s value at `modes` N, by the rule above. `ladder` holds
/// (N, value) pairs of one observable (any order, N distinct); `None` with fewer than three
/// N, without the value at `modes`, or with a non-finite value.
pub fn truncation_error(modes: usize, ladder: &[(usize, f64)]) -> Option<TruncationError> {
    let mut ladder = ladder.to_vec();
    ladder.sort_by_key(|&(n, _)| n);
    ladder.dedup_by_key(|&mut (n, _)| n);
    if ladder.len() < 3 || ladder.iter().any(|(_, f)| !f.is_finite()) {
        return None;
    }
    let at = ladder.iter().find(|&&(n, _)| n == modes)?.1;
    let k = ladder.len();
    let [(n1, f1), (n2, f2), (n3, f3)] = [ladder[k - 1], ladder[k - 2], ladder[k - 3]];
    let accepted = match richardson_in_resolution([n1 as f64, n2 as f64, n3 as f64], [f1, f2, f3]) {
        Richardson::Monotone {
            order,
            extrapolated,
            gci,
        } if order > 0.5 && order < 10.0 => Some((order, extrapolated, gci * f1.abs())),
        // equal to the last bit: the ± is round-off of the value itself
        Richardson::Converged => Some((f64::NAN, f1, f64::EPSILON * f1.abs())),
        _ => None,
    };
    let spread = ladder.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max)
        - ladder.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let (plus_minus, order, limit) = match accepted {
        Some((p, limit, u)) => (
            (at - limit).abs() + u,
            p.is_finite().then_some(p),
            Some(limit),
        ),
        None => (spread, None, None),
    };
    Some(TruncationError {
        modes,
        plus_minus,
        ladder: ladder.iter().map(|p| p.0).collect(),
        order,
        limit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plus_minus_covers_the_limit_where_a_one_step_change_does_not() {
        // f(N) = 0.7 + 0.5 N⁻²: |f(20) − f(30)| = 6.9e-4 < |f(20) − f∞| = 1.25e-3
        let f = |n: usize| 0.7 + 0.5 / (n * n) as f64;
        let ladder: Vec<(usize, f64)> = [20, 30, 40].iter().map(|&n| (n, f(n))).collect();
        let e = truncation_error(20, &ladder).unwrap();
        assert!((f(20) - f(30)).abs() < (f(20) - 0.7).abs());
        assert!(e.plus_minus >= (f(20) - 0.7).abs(), "{e:?}");
        // and not grossly above it: the GCI of N = 40 adds 1.25 × its own error
        assert!(
            e.plus_minus < (f(20) - 0.7).abs() + 1.3 * (f(40) - 0.7).abs(),
            "{e:?}"
        );
        assert!((e.order.unwrap() - 2.0).abs() < 1e-6);
        assert!(e.basis().contains("N = 20, 30, 40"));
    }

    #[test]
    fn alternating_differences_give_the_spread() {
        let e = truncation_error(10, &[(10, 1.0), (20, 1.2), (40, 1.1)]).unwrap();
        assert_eq!(e.order, None);
        assert!((e.plus_minus - 0.2).abs() < 1e-15);
        assert!(truncation_error(10, &[(10, 1.0), (20, 1.2)]).is_none());
        assert!(truncation_error(15, &[(10, 1.0), (20, 1.2), (40, 1.1)]).is_none());
    }
}
