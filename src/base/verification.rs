//! Shared solution-verification helpers: observed orders of convergence and Richardson
//! extrapolation with a grid convergence index (Roache 1998; ASME V&V 20).

/// Least-squares slope of y against x.
pub fn fitted_slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// Least-squares slope of y against x and its standard error
/// √(Σr²/(n − 2) / Σ(x − x̄)²) (0 for fewer than 3 points).
pub fn fitted_slope_with_error(x: &[f64], y: &[f64]) -> (f64, f64) {
    let slope = fitted_slope(x, y);
    let n = x.len();
    if n < 3 {
        return (slope, 0.0);
    }
    let (mx, my) = (
        x.iter().sum::<f64>() / n as f64,
        y.iter().sum::<f64>() / n as f64,
    );
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let rss: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| {
            let r = b - (my + slope * (a - mx));
            r * r
        })
        .sum();
    (slope, (rss / (n - 2) as f64 / sxx).sqrt())
}

/// The observed order of an error e(h) ∝ h^p: the least-squares slope of log e against
/// log h over the points with e > 0.
pub fn observed_order(h: &[f64], error: &[f64]) -> f64 {
    let (lx, ly): (Vec<f64>, Vec<f64>) = h
        .iter()
        .zip(error)
        .filter(|(_, e)| **e > 0.0)
        .map(|(h, e)| (h.ln(), e.ln()))
        .unzip();
    fitted_slope(&lx, &ly)
}

/// Richardson extrapolation from three solutions on a refinement ladder with constant
/// ratio r > 1: f₁ (finest), f₂, f₃ (coarsest).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum Richardson {
    /// Monotone convergence: observed order p, extrapolated value and the grid convergence
    /// index GCI = 1.25·|(f₁ − f₂)/f₁|/(r^p − 1) (a relative uncertainty of f₁).
    Monotone {
        /// p = ln((f₃ − f₂)/(f₂ − f₁))/ln r.
        order: f64,
        /// f₁ + (f₁ − f₂)/(r^p − 1).
        extrapolated: f64,
        /// The grid convergence index of f₁ (relative).
        gci: f64,
    },
    /// The differences change sign: no order can be fitted; the spread of the three values
    /// is the honest uncertainty.
    Oscillatory {
        /// max − min of the three values.
        spread: f64,
    },
    /// f₁ = f₂ = f₃ to the last bit (converged beyond what the ladder can show).
    Converged,
}

/// The cases without an order: three equal values, or differences of alternating sign (or
/// one of them zero); None for a monotone ladder.
fn not_monotone(f1: f64, f2: f64, f3: f64) -> Option<Richardson> {
    let (d21, d32) = (f2 - f1, f3 - f2);
    if d21 == 0.0 && d32 == 0.0 {
        return Some(Richardson::Converged);
    }
    if d21 == 0.0 || d32 == 0.0 || d21.signum() != d32.signum() {
        let lo = f1.min(f2).min(f3);
        let hi = f1.max(f2).max(f3);
        return Some(Richardson::Oscillatory { spread: hi - lo });
    }
    None
}

/// Richardson extrapolation of (f₁, f₂, f₃) with refinement ratio r (see [`Richardson`]).
pub fn richardson(f1: f64, f2: f64, f3: f64, r: f64) -> Richardson {
    if let Some(outside) = not_monotone(f1, f2, f3) {
        return outside;
    }
    let (d21, d32) = (f2 - f1, f3 - f2);
    let order = (d32 / d21).ln() / r.ln();
    let factor = r.powf(order) - 1.0;
    Richardson::Monotone {
        order,
        extrapolated: f1 - d21 / factor,
        gci: 1.25 * (d21 / f1).abs() / factor,
    }
}

/// Richardson extrapolation in a resolution N (modes, elements) whose error falls as
/// N^(−p), from three solutions at any N₁ > N₂ > N₃ (f₁ at the finest): the ladder need not
/// have a constant ratio (the book's orbit diagnostics use N = 20, 30, 40). The order solves
/// (f₃ − f₂)/(f₂ − f₁) = (h₃ᵖ − h₂ᵖ)/(h₂ᵖ − h₁ᵖ) with hᵢ = 1/Nᵢ (bisection: the right side
/// grows with p); with a constant ratio r this is [`richardson`]'s closed form. An order the
/// bracket [10⁻³, 60] cannot hold is returned at the bracket's end, for the caller's range
/// check to reject.
pub fn richardson_in_resolution(n: [f64; 3], f: [f64; 3]) -> Richardson {
    let [f1, f2, f3] = f;
    if let Some(outside) = not_monotone(f1, f2, f3) {
        return outside;
    }
    let (d21, d32) = (f2 - f1, f3 - f2);
    let h = n.map(|n| 1.0 / n);
    let ratio = |p: f64| (h[2].powf(p) - h[1].powf(p)) / (h[1].powf(p) - h[0].powf(p));
    let target = d32 / d21;
    let (mut lo, mut hi) = (1e-3_f64, 60.0_f64);
    let order = if target <= ratio(lo) {
        lo
    } else if target >= ratio(hi) {
        hi
    } else {
        // 200 halvings of a bracket of width 60 reach the spacing of doubles
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if ratio(mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let coefficient = d21 / (h[1].powf(order) - h[0].powf(order));
    let extrapolated = f1 - coefficient * h[0].powf(order);
    Richardson::Monotone {
        order,
        extrapolated,
        gci: 1.25 * ((f1 - extrapolated) / f1).abs(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_is_its_exponent() {
        let h = [0.1, 0.05, 0.025, 0.0125];
        let e: Vec<f64> = h.iter().map(|h: &f64| 3.0 * h.powi(2)).collect();
        // exact data: only the rounding of the logarithms
        assert!((observed_order(&h, &e) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn richardson_recovers_the_limit_of_an_exact_power_law() {
        // f(h) = 1 + 0.5 h²: with r = 2 from h = 0.1, the extrapolation is exact
        let f = |h: f64| 1.0 + 0.5 * h * h;
        match richardson(f(0.025), f(0.05), f(0.1), 2.0) {
            Richardson::Monotone {
                order,
                extrapolated,
                gci,
            } => {
                assert!((order - 2.0).abs() < 1e-9);
                assert!((extrapolated - 1.0).abs() < 1e-12);
                // GCI = 1.25·|f₁ − f₂|/(3 f₁): a bound on |f₁ − 1|/f₁ here
                assert!(gci > (f(0.025) - 1.0) / f(0.025));
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            richardson(1.0, 1.1, 0.95, 2.0),
            Richardson::Oscillatory { .. }
        ));
        assert_eq!(richardson(1.0, 1.0, 1.0, 2.0), Richardson::Converged);
    }

    #[test]
    fn an_uneven_ladder_recovers_the_order_and_limit_of_a_power_law() {
        // f(N) = 0.7 + 0.3 N^(−2.5) on N = 40, 30, 20: exact data, so only round-off remains
        let f = |n: f64| 0.7 + 0.3 * n.powf(-2.5);
        match richardson_in_resolution([40.0, 30.0, 20.0], [f(40.0), f(30.0), f(20.0)]) {
            Richardson::Monotone {
                order,
                extrapolated,
                ..
            } => {
                assert!((order - 2.5).abs() < 1e-7, "{order}");
                assert!((extrapolated - 0.7).abs() < 1e-12, "{extrapolated}");
            }
            other => panic!("{other:?}"),
        }
        // a constant ratio agrees with the closed form
        let g = |n: f64| 2.0 - n.powf(-1.5);
        let (a, b) = (
            richardson_in_resolution([40.0, 20.0, 10.0], [g(40.0), g(20.0), g(10.0)]),
            richardson(g(40.0), g(20.0), g(10.0), 2.0),
        );
        match (a, b) {
            (
                Richardson::Monotone {
                    order: p,
                    extrapolated: x,
                    gci: u,
                },
                Richardson::Monotone {
                    order: q,
                    extrapolated: y,
                    gci: v,
                },
            ) => {
                assert!((p - q).abs() < 1e-9 && (x - y).abs() < 1e-12 && (u - v).abs() < 1e-9);
            }
            other => panic!("{other:?}"),
        }
    }
}
