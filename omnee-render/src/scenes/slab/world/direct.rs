//! The `direct` term: light → surface, attenuated and occluded.

use super::SlabStats;
use super::{Roulette, SlabWorld};
use crate::rng::Rng;
use glam::Vec3;

impl SlabWorld<'_> {
    /// One-sample estimate of the direct irradiance at `p` (normal `n`):
    /// the light sampled uniformly in solid angle (`Light::sample_from`),
    /// `E = (L/pdf_ω) · cos θ · T(p, y)`, then the roulette and the
    /// visibility test.
    pub fn direct(
        &self,
        p: Vec3,
        n: Vec3,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let u = [rng.uniform(), rng.uniform()];
        let Some(lp) = self.light.sample_from(p, u) else {
            return 0.0;
        };
        let cos = n.dot(lp.dir);
        if !(cos > 0.0) {
            return 0.0;
        }
        let e = lp.value * cos * self.transmittance(p, lp.y);
        let Some(e) = roulette.play(e, rng, stats) else {
            return 0.0;
        };
        if self.occluded(p, lp.y, stats) {
            return 0.0;
        }
        e
    }
}
