//! Small numerical building blocks shared by the models: a bracketing root finder,
//! composite Gauss–Legendre quadrature on [0, 1], and a fast sine–cosine pair.
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
    ///
    /// # Panics
    /// Never: `order` is raised to 2 before the rule is built.
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

/// sin x and cos x together, to within one unit in the last place of 1 (absolute error
/// ≤ 2.3e-16; measured ≤ 1.2e-16) for |x| ≤ 10⁶, with glibc's `sincos` beyond.
///
/// The exact simulator spends most of its time in e^{λs} for the modal pairs, and glibc's
/// sincos (17 ns here) does a reduction for every argument size; this one (10 ns) covers
/// the range that occurs (|Im λ|·s up to ~10⁶) with fdlibm's medium-size reduction and
/// kernels (Sun Microsystems 1993; as in musl's `__sin`/`__cos`):
/// x = n·π/2 + r, |r| ≤ π/4, with π/2 split into 33-bit parts so that n·P₁ and n·P₂ are
/// exact for |n| < 2²⁰; then the minimax polynomials for sin r and cos r (error < 2⁻⁵⁸
/// relative) and a branch-free choice of quadrant. No crate we measured was faster
/// (pxfm's correctly rounded `f_sincos`: 30 ns).
// fdlibm's published constants, kept verbatim so they can be checked against the source
#[allow(clippy::excessive_precision)]
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17; // first 33 bits of π/2
    const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11; // next 33 bits
    const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21; // π/2 − P₁ − P₂
    const S: [f64; 6] = [
        -1.666_666_666_666_663_243_48e-1,
        8.333_333_333_322_489_461_24e-3,
        -1.984_126_982_985_794_931_34e-4,
        2.755_731_370_707_006_767_89e-6,
        -2.505_076_025_340_686_341_95e-8,
        1.589_690_995_211_550_102_21e-10,
    ];
    const C: [f64; 6] = [
        4.166_666_666_666_660_190_37e-2,
        -1.388_888_888_887_410_957_49e-3,
        2.480_158_728_947_672_941_78e-5,
        -2.755_731_435_139_066_330_35e-7,
        2.087_572_321_298_174_827_90e-9,
        -1.135_964_755_778_819_482_65e-11,
    ];
    // 1.5·2⁵²: adding it rounds to the nearest integer, whose low bits are then the
    // mantissa's (two's complement for negative n)
    const ROUNDER: f64 = 6_755_399_441_055_744.0;
    // beyond the fast range, and NaN or ±∞
    if x.is_nan() || x.abs() > 1.0e6 {
        return x.sin_cos();
    }
    let shifted = x * INV_PIO2 + ROUNDER;
    let quadrant = shifted.to_bits();
    let n = shifted - ROUNDER;
    let r = ((x - n * PIO2_1) - n * PIO2_2) - n * PIO2_2T;
    let z = r * r;
    let w = z * z;
    let rs = S[1] + z * (S[2] + z * S[3]) + z * w * (S[4] + z * S[5]);
    let sin_r = r + z * r * (S[0] + z * rs);
    let rc = z * (C[0] + z * (C[1] + z * C[2])) + w * w * (C[3] + z * (C[4] + z * C[5]));
    let half_z = 0.5 * z;
    let lead = 1.0 - half_z;
    // cos r = 1 − z/2 + z·rc, with the rounding of 1 − z/2 recovered
    let cos_r = lead + (((1.0 - lead) - half_z) + z * rc);
    // quadrant n mod 4: (sin, cos) = (s, c), (c, −s), (−s, −c), (−c, s)
    let (sin, cos) = if quadrant & 1 == 0 {
        (sin_r, cos_r)
    } else {
        (cos_r, sin_r)
    };
    let sin_sign = (quadrant & 2) << 62;
    let cos_sign = ((quadrant + 1) & 2) << 62;
    (
        f64::from_bits(sin.to_bits() ^ sin_sign),
        f64::from_bits(cos.to_bits() ^ cos_sign),
    )
}

/// r·e^{iθ} by [`sin_cos`].
#[inline]
pub fn polar(r: f64, theta: f64) -> num_complex::Complex64 {
    let (sin, cos) = sin_cos(theta);
    num_complex::Complex64::new(r * cos, r * sin)
}

/// ∫₀^S e^{μs} ds given e^{μS}, accurate also when |μS| is small.
pub fn exp_integral(
    mu: num_complex::Complex64,
    s: f64,
    growth: num_complex::Complex64,
) -> num_complex::Complex64 {
    let z = mu * s;
    let z2 = z.norm_sqr();
    if z2 < EXPREL_SERIES_BELOW {
        exprel_series(z, z2) * s
    } else {
        (growth - 1.0) / mu
    }
}

/// |μS|² below which [`exp_integral`] sums the series: at |μS| ≥ 0.1,
/// |e^{μS} − 1| ≥ 1 − e^{−0.1}, so the closed form has no catastrophic cancellation.
pub const EXPREL_SERIES_BELOW: f64 = 0.01;

/// (e^z − 1)/z = Σ zⁿ/(n+1)! for |z|² = `z2` < 0.01, by Horner with as many terms as
/// |z| needs: the first neglected term |z|^{K+1}/(K+2)! stays below 3e-18 (|z| < 10⁻⁶:
/// K = 2; < 10⁻⁴: 3; < 10⁻³: 4; < 10⁻²: 6; < 0.1: 9). Short segments (a chattering contact
/// lasts ~10⁻⁷) mostly need three terms, so the energy budget does not pay for twelve.
#[inline]
pub fn exprel_series(z: num_complex::Complex64, z2: f64) -> num_complex::Complex64 {
    let terms = if z2 < 1e-12 {
        2
    } else if z2 < 1e-8 {
        3
    } else if z2 < 1e-6 {
        4
    } else if z2 < 1e-4 {
        6
    } else {
        9
    };
    // 1/(n+1)! is folded into the Horner steps: 1 + z/2 (1 + z/3 (1 + …))
    let mut acc = num_complex::Complex64::new(1.0, 0.0);
    for n in (2..=terms + 1).rev() {
        acc = acc * z * (1.0 / n as f64) + 1.0;
    }
    acc
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
    fn exprel_series_matches_the_cancellation_free_closed_form() {
        // reference: e^z − 1 = (expm1(x) cos y − 2 sin²(y/2)) + i eˣ sin y has no
        // cancellation beyond a few ulps of |z|; the series' truncation is < 3e-18
        use num_complex::Complex64;
        let mut worst: f64 = 0.0;
        for decade in 0..80 {
            let r = 0.0999 * 10f64.powf(-(decade as f64) / 10.0);
            for k in 0..16 {
                let angle = std::f64::consts::TAU * k as f64 / 16.0 + 0.1;
                let z = Complex64::from_polar(r, angle);
                let (x, y) = (z.re, z.im);
                let half = (y / 2.0).sin();
                let em1 =
                    Complex64::new(x.exp_m1() * y.cos() - 2.0 * half * half, x.exp() * y.sin());
                let reference = em1 / z;
                let got = exprel_series(z, z.norm_sqr());
                worst = worst.max((got - reference).norm() / reference.norm());
            }
        }
        // a few ulps from the reference's own rounding and Horner's
        assert!(worst < 8.0 * f64::EPSILON, "worst relative error {worst:e}");
    }

    #[test]
    fn sin_cos_matches_libm_to_one_unit_of_one() {
        // log-uniform |x| in [1e-6, 1e6], both signs, plus multiples of π/2 (where r
        // cancels) and the fallback range; glibc is within 1 ulp, ours within 1 ulp of 1:
        // together ≤ 2 ulp(1) = 4.4e-16 (measured ≤ 1.2e-16).
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        };
        for _ in 0..200_000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            let magnitude = 10f64.powf(12.0 * u - 6.0);
            check(if state & 1 == 0 {
                magnitude
            } else {
                -magnitude
            });
        }
        for n in -2000..2000 {
            let x = n as f64 * std::f64::consts::FRAC_PI_2;
            check(x);
            check(x * 317.0);
        }
        for x in [0.0, -0.0, 1e6, -1e6, 1.5e6, 3e9] {
            check(x);
        }
        assert!(worst <= 2.0 * f64::EPSILON, "worst {worst:e}");
        assert!(sin_cos(f64::NAN).0.is_nan() && sin_cos(f64::INFINITY).1.is_nan());
    }

    #[test]
    fn quadrature_is_exact_for_high_degree_polynomials() {
        let q = Quadrature::composite(10, 3);
        // degree 19 is integrated exactly; the bound is summation round-off over 30 nodes
        assert!((q.integrate(|x| 20.0 * x.powi(19)) - 1.0).abs() < 1e-14);
    }
}
