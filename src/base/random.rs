//! Seeded random starts: a deterministic stream per sweep point (SplitMix64), so that a
//! sweep's random starts do not depend on the thread count or on a crate's version, and the
//! random modal state every front end draws from a seed.

use nalgebra::DVector;

/// A deterministic pseudo-random stream (SplitMix64, Steele, Lea & Flood 2014): seeded per
/// sweep point, so a diagram does not depend on the thread count or on a crate's version.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    pub fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// A stream for sweep point `(a, b, c)` of `seed`.
    pub fn for_point(seed: u64, a: u64, b: u64, c: u64) -> Self {
        let mut s = SplitMix64(seed ^ a.wrapping_mul(0x1000_0000_01B3));
        s.0 ^= s.next_u64() ^ b.wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        s.0 ^= s.next_u64() ^ c.wrapping_mul(0x1656_67B1_9E37_79F9);
        s
    }
}

/// A random state of tip-displacement scale `amplitude` and frequency scale ω: each η_j
/// uniform in ±amplitude/2 (so the tip, 2Ση, is O(amplitude)), each η̇_j in ±ω·amplitude/2.
pub fn random_state(
    rng: &mut SplitMix64,
    modes: usize,
    amplitude: f64,
    omega: f64,
) -> DVector<f64> {
    DVector::from_fn(2 * modes, |i, _| {
        let scale = if i < modes {
            0.5 * amplitude
        } else {
            0.5 * amplitude * omega
        };
        scale * rng.symmetric() / modes as f64
    })
}
