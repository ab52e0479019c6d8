//! Russian roulette before visibility tests: a contribution too small to be
//! worth its tests survives with a probability proportional to it.

use super::SlabStats;
use crate::rng::Rng;

/// Russian roulette on an estimate `e` that still needs visibility tests,
/// judged in the output's units: `c = scale · e` (e.g. the radiance an
/// irradiance estimate becomes at the camera). Below `threshold`, `c`
/// survives with probability `c / threshold` and is then worth `threshold`
/// (unbiased: the expectation stays `c`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roulette {
    /// The output's units per unit of the estimate.
    pub scale: f32,
    /// The threshold in the output's units; 0 switches the roulette off.
    pub threshold: f32,
}

impl Roulette {
    /// No roulette: every estimate is kept as it is.
    pub const OFF: Self = Self {
        scale: 0.0,
        threshold: 0.0,
    };

    /// A roulette for estimates in the output's units (`scale` = 1).
    pub fn new(threshold: f32) -> Self {
        Self {
            scale: 1.0,
            threshold,
        }
    }

    /// The same threshold for estimates that are worth `scale` output units
    /// each.
    pub fn scaled(self, scale: f32) -> Self {
        Self { scale, ..self }
    }

    /// The estimate `e` after the roulette, in its own units, or `None` when
    /// it is dropped. Draws a random number only below the threshold.
    pub fn play(self, e: f32, rng: &mut Rng, stats: &mut SlabStats) -> Option<f32> {
        let c = e * self.scale;
        let c = if c >= self.threshold || self.threshold <= 0.0 {
            c
        } else if rng.uniform::<f32>() * self.threshold < c {
            stats.roulette_kept += 1;
            self.threshold
        } else {
            stats.roulette_dropped += 1;
            return None;
        };
        Some(if self.scale > 0.0 { c / self.scale } else { e })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn off_keeps_every_estimate_and_draws_nothing() {
        let mut rng = Rng::stream(1, 2, 3);
        let mut fresh = rng.clone();
        let mut st = SlabStats::default();
        assert_eq!(Roulette::OFF.play(0.25, &mut rng, &mut st), Some(0.25));
        assert_eq!(Roulette::new(0.5).play(0.75, &mut rng, &mut st), Some(0.75));
        assert_eq!(rng.uniform::<f64>(), fresh.uniform::<f64>());
        assert_eq!(st, SlabStats::default());
    }

    #[test]
    fn below_the_threshold_the_mean_is_kept() {
        // c = 2·0.1 = 0.2 against 0.8: kept with probability 1/4, then
        // worth 0.8/2 = 0.4 in the estimate's units; the mean stays 0.1.
        let r = Roulette::new(0.8).scaled(2.0);
        let mut rng = Rng::stream(4, 5, 6);
        let mut st = SlabStats::default();
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            if let Some(v) = r.play(0.1, &mut rng, &mut st) {
                assert_eq!(v, 0.4);
                sum += v as f64;
            }
        }
        assert_eq!(st.roulette_kept + st.roulette_dropped, n);
        // Binomial(1e5, 1/4) · 0.4 / n: sd 5.5e-4; 6 sd = 3.3e-3.
        assert!((sum / n as f64 - 0.1).abs() < 3.3e-3, "{}", sum / n as f64);
    }
}
