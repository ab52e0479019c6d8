//! # omnee-ffi
//!
//! The C ABI of `omnee-core`. The header `include/omnee.h` is generated from
//! this crate by cbindgen (`omnee-ffi/ci.sh` regenerates it and fails when
//! the committed one differs); its top comment states the conventions: names
//! `omnee_<object>_<operation>_<precision>`, a status code from every
//! function, caller-owned memory, no allocation, no global state.
//!
//! Modules, one per part of the header:
//! - [`status`]: `omnee_status` and the caller-owned `omnee_error` record;
//! - [`types`]: the plain-old-data structs and the opaque objects;
//! - [`connection`], [`phase`], [`techniques`], [`problem`],
//!   [`connections`] (the batch over connections), [`bridge`] (bridges of
//!   k vertices, the number k, the isotropic reference): the
//!   exported functions, each pair (`_f32`, `_f64`) a thin shell around one
//!   generic function;
//! - `args`: checks that turn C arguments into the core's values;
//! - `boundary`: the only place that turns raw pointers into Rust values.
//!
//! ## Panics never cross the boundary
//!
//! The library is written not to panic: every failure is a status, outputs
//! are checked finite, and no code path indexes out of bounds or unwraps on
//! input it did not check. Should a panic happen anyway:
//! - on hosted targets (Linux, macOS, Windows) the crate links `std` for its
//!   panic runtime only (its own code uses `core`), and a panic that reaches
//!   an `extern "C"` function aborts the process instead of unwinding into C
//!   (Rust ≥ 1.81);
//! - on bare-metal targets (`target_os = "none"`, firmware) the
//!   `panic-handler` feature (on by default) supplies a handler that traps
//!   (`udf` on Arm, `unimp` on RISC-V), which firmware sees as a fault; turn
//!   it off to link the rlib into firmware that has its own handler.
#![no_std]
// The C names (`omnee_vec3`, `OMNEE_OK`) are the header's, one to one.
#![allow(non_camel_case_types)]

#[cfg(not(target_os = "none"))]
extern crate std;

mod args;
mod boundary;
pub mod bridge;
pub mod connection;
pub mod connections;
pub mod phase;
pub mod problem;
pub mod status;
pub mod techniques;
pub mod types;

pub use status::{omnee_error, omnee_status};

/// On bare metal: trap, the firmware's fault handler takes over.
#[cfg(all(target_os = "none", feature = "panic-handler", not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        // SAFETY: `udf`/`unimp` only raise the fault exception; they touch
        // no memory.
        #[cfg(target_arch = "arm")]
        unsafe {
            core::arch::asm!("udf #0", options(nomem, nostack))
        };
        #[cfg(any(target_arch = "riscv32", target_arch = "riscv64"))]
        unsafe {
            core::arch::asm!("unimp", options(nomem, nostack))
        };
    }
}
