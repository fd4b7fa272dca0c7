//! Small numerical building blocks shared by the models: a bracketing root finder and
//! composite Gauss–Legendre quadrature on [0, 1].
//!
//! The root finder is hand-written because every caller needs the same contract — a root
//! inside a given sign-changing bracket, to a *relative* tolerance on the abscissa, with the
//! bracket never lost — and the few lines of Brent's method are easier to check than an
//! adapter around a generic crate. Quadrature nodes come from the `gauss-quad` crate.

use gauss_quad::GaussLegendre;

/// Brent's method (Brent 1973, *Algorithms for minimization without derivatives*, ch. 4):
/// inverse quadratic interpolation and secant steps, safeguarded by bisection.
///
/// Requires `f(a)` and `f(b)` of opposite sign (or one of them zero). Returns `x` with
/// `|x − x*| ≤ rel_tol·|x| + 4ε|x|` for a root `x*` in `[a, b]`, or `None` when the
/// bracket does not change sign.
pub fn brent<F: FnMut(f64) -> f64>(mut f: F, a: f64, b: f64, rel_tol: f64) -> Option<f64> {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a), f(b));
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa.signum() == fb.signum() || !fa.is_finite() || !fb.is_finite() {
        return None;
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * rel_tol * b.abs();
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Some(b);
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
    }
    Some(b)
}

/// Composite Gauss–Legendre rule on [0, 1]: `panels` equal panels of `order` points each.
///
/// Exact for polynomials of degree `2·order − 1` on each panel; for the beam modes, which
/// oscillate with wavenumber β, the error falls like `(β/(2·panels))^(2·order)`, so a
/// panel count proportional to β keeps the rule accurate to round-off.
#[derive(Debug, Clone)]
pub struct Quadrature {
    /// Nodes in [0, 1].
    pub nodes: Vec<f64>,
    /// Weights, summing to 1.
    pub weights: Vec<f64>,
}

impl Quadrature {
    /// Builds the rule; `order ≥ 2` and `panels ≥ 1`.
    pub fn composite(order: usize, panels: usize) -> Self {
        let rule = GaussLegendre::new(order.max(2).try_into().expect("order ≥ 2"));
        let h = 1.0 / panels as f64;
        let mut nodes = Vec::with_capacity(order * panels);
        let mut weights = Vec::with_capacity(order * panels);
        for p in 0..panels {
            let left = p as f64 * h;
            for (x, w) in rule.iter() {
                nodes.push(left + 0.5 * h * (x + 1.0));
                weights.push(0.5 * h * w);
            }
        }
        Self { nodes, weights }
    }

    /// A rule resolving functions with wavenumber up to `beta` to round-off:
    /// 20-point panels, one panel per half wavelength at least.
    pub fn for_wavenumber(beta: f64) -> Self {
        let panels = ((beta / std::f64::consts::PI).ceil() as usize).max(4);
        Self::composite(20, panels)
    }

    /// ∫₀¹ f(s) ds.
    pub fn integrate<F: Fn(f64) -> f64>(&self, f: F) -> f64 {
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(&x, &w)| w * f(x))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_cos_root_to_relative_tolerance() {
        let x = brent(f64::cos, 1.0, 2.0, 1e-15).unwrap();
        // tolerance: the requested 1e-15 relative plus the 4ε guard in the stopping test
        assert!((x - std::f64::consts::FRAC_PI_2).abs() < 2e-15);
    }

    #[test]
    fn brent_rejects_a_bracket_without_sign_change() {
        assert!(brent(|x| x * x + 1.0, -1.0, 1.0, 1e-12).is_none());
    }

    #[test]
    fn quadrature_is_exact_for_high_degree_polynomials() {
        let q = Quadrature::composite(10, 3);
        // degree 19 is integrated exactly; the bound is summation round-off over 30 nodes
        assert!((q.integrate(|x| 20.0 * x.powi(19)) - 1.0).abs() < 1e-14);
    }
}
