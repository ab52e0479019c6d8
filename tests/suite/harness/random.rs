//! The suite's seeded generator: the core's SplitMix64 with the draws the
//! tests need (uniform numbers in either precision, ranges, unit vectors).
//! Every test seeds its own stream, so results do not depend on test order
//! or threads.

use glam::DVec3;
use omnee::Real;
use omnee::rng::SplitMix64;

/// A seeded stream ([`SplitMix64`] with the seed as its state).
pub struct Rng(SplitMix64);

impl Rng {
    /// A stream from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(SplitMix64::new(seed))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in `[0, 1)` with the precision's full mantissa (24 or 53
    /// bits): [`omnee::sampling::uniform`].
    pub fn uniform<F: Real>(&mut self) -> F {
        omnee::sampling::uniform(&mut self.0)
    }

    /// Three uniform numbers.
    pub fn u3<F: Real>(&mut self) -> [F; 3] {
        [self.uniform(), self.uniform(), self.uniform()]
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform::<f64>()
    }

    /// A uniformly distributed unit vector.
    pub fn unit(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, core::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}
