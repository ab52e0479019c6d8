//! omnee-core on a microcontroller: the pieces the firmware binaries share.
//!
//! - [`scene`]: the fixed point-to-point problem (also read by build.rs);
//! - [`REFERENCE_BITS`]: its quadrature value, computed on the host at build
//!   time;
//! - [`SplitMix64`]: the uniform numbers;
//! - [`Mean`]: a compensated running mean and variance in f32;
//! - [`report`]: lines of hex numbers over semihosting, without `core::fmt`;
//! - [`stack`]: peak stack use by painting.
#![no_std]

use omnee_core::real::Real;

pub mod scene;
include!(concat!(env!("OUT_DIR"), "/reference.rs"));

pub mod report;
pub mod stack;

#[cfg(target_arch = "arm")]
use cortex_m_semihosting::{debug, hio};
#[cfg(target_arch = "riscv32")]
use riscv_semihosting::{debug, hio};

/// Ends the run through semihosting: QEMU exits with 0 or 1.
pub fn exit(success: bool) -> ! {
    debug::exit(if success {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
}

/// A panic (the core does not panic on this scene) ends the run as a failure.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    exit(false)
}

/// SplitMix64 (Steele, Lea, Flood 2014), as the C example uses.
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform f32 in [0, 1): the top 24 bits times 2⁻²⁴.
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / 16_777_216.0)
    }
}

/// The running mean and variance, with Kahan-compensated sums of `x − shift`
/// and `(x − shift)²` (`shift` the first value), so that 10⁵ f32 terms lose
/// no more than a few ulps (a plain f32 sum would lose ~10⁻³).
#[derive(Default)]
pub struct Mean<F> {
    n: u32,
    shift: F,
    sum: Kahan<F>,
    sum_sq: Kahan<F>,
}

#[derive(Default)]
struct Kahan<F> {
    sum: F,
    carry: F,
}

impl<F: Real> Kahan<F> {
    #[inline]
    fn add(&mut self, x: F) {
        let y = x - self.carry;
        let t = self.sum + y;
        self.carry = (t - self.sum) - y;
        self.sum = t;
    }
}

impl<F: Real> Mean<F> {
    /// Adds one value.
    #[inline]
    pub fn add(&mut self, x: F) {
        if self.n == 0 {
            self.shift = x;
        }
        self.n += 1;
        let d = x - self.shift;
        self.sum.add(d);
        self.sum_sq.add(d * d);
    }

    /// The mean.
    pub fn mean(&self) -> F {
        self.shift + self.sum.sum / F::from_f32(self.n as f32)
    }

    /// The standard error of the mean, √(s²/n).
    pub fn std_error(&self) -> F {
        let n = F::from_f32(self.n as f32);
        let m = self.sum.sum / n;
        let variance = (self.sum_sq.sum / n - m * m) * n / (n - F::ONE);
        (variance / n).max(F::ZERO).sqrt()
    }

    /// Whether the mean lies within `k` standard errors of `reference`.
    pub fn agrees(&self, reference: F, k: F) -> bool {
        (self.mean() - reference).abs() <= k * self.std_error()
    }
}
