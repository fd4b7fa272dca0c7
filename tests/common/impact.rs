//! The rigid impact oscillator and the closed form of its (1,1) orbit, shared by the tests
//! of the rigid model's orbits and of two-parameter continuation.

use impacting_cantilever::engine::rigid::RigidImpact;
use impacting_cantilever::model::galerkin::Oscillator;
use nalgebra::{DVector, Matrix2, Vector2};

/// ẍ + cẋ + kx = F cos ωt with a stop at x = d and Newton's law r: k = 1, c = 0.1, F = 1,
/// d = 0, r = 0.8 (a stable (1,1) orbit for ω ≲ 2.65, period doubling above).
pub const K: f64 = 1.0;
pub const C: f64 = 0.1;
pub const F: f64 = 1.0;
pub const D: f64 = 0.0;
pub const R: f64 = 0.8;

/// The oscillator's parameters at ω.
pub fn parameters(omega: f64) -> Oscillator {
    Oscillator {
        stiffness: K,
        damping: C,
        forcing: F,
        omega,
        tip_gain: 1.0,
        gap: D,
        stop_stiffness: 0.0,
    }
}

/// The oscillator with the law r.
pub fn oscillator_with(omega: f64, r: f64) -> RigidImpact {
    RigidImpact::oscillator(&parameters(omega), r).unwrap()
}

/// The closed form of the (1,1) orbit, independent of the library: the free flight
/// x(t) = Φ(t − τ)(x(τ) − x_p(τ)) + x_p(t) of the damped oscillator, an impact at phase τ
/// with incoming velocity v, and x(τ + T) = (d, v) after starting from (d, −rv).
pub struct ClosedForm {
    /// ω.
    pub omega: f64,
    /// Newton's r.
    pub r: f64,
}

impl ClosedForm {
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }
    pub fn phi(&self, t: f64) -> Matrix2<f64> {
        let a = C / 2.0;
        let wd = (K - a * a).sqrt();
        let (s, c) = (wd * t).sin_cos();
        (-a * t).exp() * Matrix2::new(c + a / wd * s, s / wd, -K / wd * s, c - a / wd * s)
    }
    /// The particular solution's displacement and velocity at t.
    pub fn particular(&self, t: f64) -> Vector2<f64> {
        let w = self.omega;
        let m = Matrix2::new(K - w * w, C * w, -C * w, K - w * w);
        let ab = m.lu().solve(&Vector2::new(F, 0.0)).unwrap();
        let (s, c) = (w * t).sin_cos();
        Vector2::new(ab[0] * c + ab[1] * s, -ab[0] * w * s + ab[1] * w * c)
    }
    pub fn velocity(&self, tau: f64) -> f64 {
        let p = self.phi(self.period());
        let xp = self.particular(tau);
        (p[(1, 0)] * (D - xp[0]) + xp[1] * (1.0 - p[(1, 1)])) / (1.0 + self.r * p[(1, 1)])
    }
    pub fn residual(&self, tau: f64) -> f64 {
        let p = self.phi(self.period());
        let xp = self.particular(tau);
        (p[(0, 0)] - 1.0) * (D - xp[0]) - p[(0, 1)] * (self.r * self.velocity(tau) + xp[1])
    }
    /// The admissible (1,1) orbits: impact phase τ and velocity v > 0, with the free flight
    /// below the stop in between.
    pub fn orbits(&self) -> Vec<(f64, f64)> {
        let t = self.period();
        let n = 4000;
        let mut out = Vec::new();
        for i in 0..n {
            let (mut a, mut b) = (t * i as f64 / n as f64, t * (i + 1) as f64 / n as f64);
            if self.residual(a) * self.residual(b) > 0.0 {
                continue;
            }
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                if self.residual(a) * self.residual(m) <= 0.0 {
                    b = m;
                } else {
                    a = m;
                }
            }
            let tau = 0.5 * (a + b);
            let v = self.velocity(tau);
            let y0 = Vector2::new(D, -self.r * v) - self.particular(tau);
            let below = (1..2000).all(|j| {
                let s = t * j as f64 / 2000.0;
                (self.phi(s) * y0)[0] + self.particular(tau + s)[0] < D + 1e-12
            });
            if v > 0.0 && below {
                out.push((tau, v));
            }
        }
        out
    }
    /// The orbit's state at the start of a forcing period.
    pub fn state(&self, tau: f64, v: f64) -> DVector<f64> {
        let t = self.period();
        let y = self.phi(t - tau) * (Vector2::new(D, -self.r * v) - self.particular(tau))
            + self.particular(t);
        DVector::from_column_slice(y.as_slice())
    }
    /// The monodromy Φ(T)·S with the saltation S = [[−r, 0], [(a⁺ + r a⁻)/v, −r]].
    pub fn monodromy(&self, tau: f64, v: f64) -> Matrix2<f64> {
        let force = F * (self.omega * tau).cos();
        let before = -C * v - K * D + force;
        let after = C * self.r * v - K * D + force;
        let s = Matrix2::new(-self.r, 0.0, (after + self.r * before) / v, -self.r);
        self.phi(self.period()) * s
    }
}

/// The oscillator with r = [`R`].
pub fn oscillator(omega: f64) -> RigidImpact {
    oscillator_with(omega, R)
}
