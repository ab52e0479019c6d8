//! SplitMix64 (Steele, Lea, Flood, "Fast splittable pseudorandom number
//! generators", OOPSLA 2014): a seeded 64-bit generator in one `u64` of
//! state, and its finaliser [`mix`] for hashing stream coordinates into seeds.
//!
//! The core's samplers take plain uniform numbers and never a generator;
//! this one is here so that tests, benchmarks and front ends share one
//! implementation instead of each writing their own. It passes BigCrush
//! (its authors' tests) and is plenty for Monte Carlo estimates and seeded
//! tests; it is not a cryptographic generator.
//!
//! ```
//! use omnee_core::rng::SplitMix64;
//! use omnee_core::sampling::uniform;
//!
//! let mut rng = SplitMix64::new(2022);
//! let u: f32 = uniform(&mut rng); // any rand_core 0.10 `Rng` works here
//! assert!((0.0..1.0).contains(&u));
//! ```

use core::convert::Infallible;

/// The SplitMix64 generator: the state advances by the odd constant
/// [`SplitMix64::GAMMA`] (2⁶⁴/φ) and each output is [`mix`] of the new state,
///
/// `state ← state + γ`, `output = mix(state)`,
///
/// a sequence of period 2⁶⁴ in which every 64-bit value occurs once.
/// A [`rand_core::Rng`] through `TryRng<Error = Infallible>`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// The increment γ = 0x9e37_79b9_7f4a_7c15, the odd integer nearest
    /// 2⁶⁴/φ (φ the golden ratio).
    pub const GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

    /// The generator whose state is `seed` (its first output is
    /// `mix(seed + γ)`). Nearby seeds give overlapping sequences shifted by
    /// a multiple of γ; hash stream coordinates with [`mix`] into the seed
    /// when many independent streams are needed.
    #[inline]
    pub const fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits: `state ← state + γ`, then [`mix`]`(state)`.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(Self::GAMMA);
        mix(self.state)
    }
}

/// The SplitMix64 finaliser (a variant of MurmurHash3's `fmix64` with
/// Stafford's "Mix13" constants): a bijection on `u64` with full avalanche,
///
/// `z ← (z ⊕ z≫30)·0xbf58476d1ce4e5b9`, `z ← (z ⊕ z≫27)·0x94d049bb133111eb`,
/// `z ⊕ z≫31`,
///
/// so that distinct inputs give distinct, unrelated-looking outputs: for
/// hashing stream coordinates (seed, pixel, pass) into one seed.
#[inline]
pub const fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl rand_core::TryRng for SplitMix64 {
    type Error = Infallible;

    /// The high 32 bits of [`SplitMix64::next_u64`].
    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        Ok((SplitMix64::next_u64(self) >> 32) as u32)
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        Ok(SplitMix64::next_u64(self))
    }

    /// Little-endian bytes of successive [`SplitMix64::next_u64`] outputs
    /// (the last one truncated).
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        for chunk in dst.chunks_mut(8) {
            let bytes = SplitMix64::next_u64(self).to_le_bytes();
            chunk.copy_from_slice(&bytes[..chunk.len()]);
        }
        Ok(())
    }
}

impl rand_core::SeedableRng for SplitMix64 {
    /// The state, little-endian.
    type Seed = [u8; 8];

    fn from_seed(seed: [u8; 8]) -> Self {
        Self::new(u64::from_le_bytes(seed))
    }

    /// [`SplitMix64::new`]: the seed is the state (as in the reference
    /// implementation; not rand_core's PCG expansion).
    fn seed_from_u64(seed: u64) -> Self {
        Self::new(seed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::{Rng, SeedableRng};

    #[test]
    fn matches_the_reference_implementation() {
        // splitmix64.c (Vigna), state seeded with 1234567: the first outputs.
        let mut rng = SplitMix64::new(1_234_567);
        let want = [
            6_457_827_717_110_365_317u64,
            3_203_168_211_198_807_973,
            9_817_491_932_198_370_423,
            4_593_380_528_125_082_431,
            16_408_922_859_458_223_821,
        ];
        for w in want {
            assert_eq!(rng.next_u64(), w);
        }
    }

    #[test]
    fn mix_is_the_output_of_the_advanced_state() {
        let mut rng = SplitMix64::new(42);
        assert_eq!(rng.next_u64(), mix(42u64.wrapping_add(SplitMix64::GAMMA)));
        assert_eq!(mix(0), 0);
        assert_ne!(mix(1), mix(2));
    }

    #[test]
    fn the_rand_core_interface_draws_the_same_stream() {
        let (mut a, mut b) = (SplitMix64::new(9), SplitMix64::seed_from_u64(9));
        assert_eq!(SplitMix64::from_seed(9u64.to_le_bytes()), a);
        let x = a.next_u64();
        assert_eq!(Rng::next_u64(&mut b), x);
        assert_eq!(Rng::next_u32(&mut b), (a.next_u64() >> 32) as u32);
        let mut bytes = [0u8; 11];
        b.fill_bytes(&mut bytes);
        let (first, second) = (a.next_u64().to_le_bytes(), a.next_u64().to_le_bytes());
        assert_eq!(bytes[..8], first);
        assert_eq!(bytes[8..], second[..3]);
    }
}
