//! # omnee-wasm
//!
//! wasm-bindgen bindings of the `no_std` core [`omnee_core`] and the
//! computations behind the browser demo in `omnee-wasm/web/`:
//! the talk's "waterlevel" triangle, sample clouds of OMNEE and equiangular
//! sampling, histograms of sampled deflections against the phase function,
//! and running estimates of the point-to-point integral against its
//! quadrature reference (Hanika, Weidlich, Droske, "Once-more scattered next
//! event estimation for volume rendering", EGSR 2022).
//!
//! - [`demo`]: the computations, plain Rust, tested natively;
//! - [`bindings`]: the JavaScript interface (errors become thrown `Error`s);
//! - [`rng`]: PCG32, so a seed gives the same numbers natively and in wasm;
//! - [`phase`]: phase functions by specification string.
//!
//! Sampling and references run in f64 (one copy of each routine in the
//! module; README.md has the measured choice).
#![forbid(unsafe_code)]
#![cfg_attr(all(target_arch = "wasm32", not(feature = "std")), no_std)]

extern crate alloc;

pub mod bindings;
pub mod demo;
pub mod phase;
pub mod rng;

pub use bindings::*;

/// The module's allocator: a free list (lol_alloc) instead of std's dlmalloc.
#[cfg(target_arch = "wasm32")]
#[global_allocator]
static ALLOCATOR: lol_alloc::LockedAllocator<lol_alloc::FreeListAllocator> =
    lol_alloc::LockedAllocator::new(lol_alloc::FreeListAllocator::new());

/// Without std (the demo's build): a panic stops the module with a trap.
#[cfg(all(target_arch = "wasm32", not(feature = "std")))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    core::arch::wasm32::unreachable()
}
