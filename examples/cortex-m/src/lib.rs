//! omnee-core on a microcontroller: the pieces the firmware binaries share.
//!
//! - [`scene`]: the fixed point-to-point problem (also read by build.rs);
//! - [`REFERENCE_BITS`]: its quadrature value, computed on the host at build
//!   time;
//! - [`uniform`]: the uniform numbers, from the core's [`SplitMix64`];
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

pub use omnee_core::rng::SplitMix64;

/// A uniform f32 in [0, 1) from the core's generator: the top 24 bits of a
/// draw times 2⁻²⁴, in f32 arithmetic. The same numbers as
/// [`omnee_core::sampling::uniform`], which scales in f64: on the
/// Cortex-M4F (single-precision FPU only) that costs 320 B of flash and
/// software double arithmetic per number.
#[inline]
pub fn uniform(rng: &mut SplitMix64) -> f32 {
    (rng.next_u64() >> 40) as f32 * (1.0 / 16_777_216.0)
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
