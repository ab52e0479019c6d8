//! A small deterministic generator, identical on every target, so that a seed
//! chosen in JavaScript reproduces the same samples natively and in the browser.

/// PCG32 (O'Neill 2014, `pcg32_random_r`: 64-bit LCG state, XSH-RR output).
///
/// Every stream (`stream` selects one of 2⁶³ increments) is an independent
/// sequence of period 2⁶⁴; the demo gives each technique its own stream so
/// that one technique's numbers do not depend on how often another was run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

const MULTIPLIER: u64 = 6_364_136_223_846_793_005;

impl Pcg32 {
    /// The generator `pcg32_srandom_r(seed, stream)` of the reference
    /// implementation.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Self {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    /// The next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// A uniform f32 in `[0, 1)`: the top 24 bits scaled by 2⁻²⁴ (exact, and
    /// never 1).
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Three uniform numbers, the input of a sampling technique.
    #[inline]
    pub fn uniform3(&mut self) -> [f32; 3] {
        [self.uniform(), self.uniform(), self.uniform()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_reference_implementation() {
        // pcg32-demo.c: pcg32_srandom_r(&rng, 42u, 54u), first six outputs.
        let mut rng = Pcg32::new(42, 54);
        let want = [
            0xa15c_02b7u32,
            0x7b47_f409,
            0xba1d_3330,
            0x83d2_f293,
            0xbfa4_784b,
            0xcbed_606e,
        ];
        for w in want {
            assert_eq!(rng.next_u32(), w);
        }
    }

    #[test]
    fn uniform_is_in_the_unit_interval_with_the_right_mean() {
        let mut rng = Pcg32::new(7, 1);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let u = rng.uniform();
            assert!((0.0..1.0).contains(&u));
            sum += f64::from(u);
        }
        // Mean 1/2, standard error √(1/12/n) ≈ 9.1e-4; 6 standard errors.
        assert!((sum / n as f64 - 0.5).abs() < 6.0 * 9.2e-4);
    }

    #[test]
    fn streams_differ() {
        let (mut a, mut b) = (Pcg32::new(1, 1), Pcg32::new(1, 2));
        assert!((0..8).any(|_| a.next_u32() != b.next_u32()));
    }
}
