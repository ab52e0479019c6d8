//! Peak stack use by painting: fill the unused stack below the stack
//! pointer with a pattern, run, and find the lowest word that changed.
//!
//! This is the firmware's only `unsafe`: it writes and reads memory below
//! the stack pointer, which nothing else uses (no interrupts are enabled).

/// The pattern written into unused stack.
const PAINT: u32 = 0xa5a5_a5a5;
/// How far below the stack pointer to paint (the painted region also stops
/// at the end of the static data).
const DEPTH: usize = 64 * 1024;

unsafe extern "C" {
    /// The runtime's (cortex-m-rt's, riscv-rt's) initial stack pointer, the
    /// top of the stack.
    static _stack_start: u32;
    /// The end of the static data, where the stack may grow to.
    static __sheap: u32;
}

/// A painted region `[low, sp)` of the stack that ends at `top`.
pub struct Painted {
    low: usize,
    top: usize,
}

/// Paints the stack below the current stack pointer.
#[inline(never)]
pub fn paint() -> Painted {
    let top = (&raw const _stack_start) as usize;
    let heap = (&raw const __sheap) as usize;
    let sp = stack_pointer();
    let low = (heap.max(sp.saturating_sub(DEPTH)) + 3) & !3;
    let high = (sp & !3).saturating_sub(16);
    let mut address = low;
    while address < high {
        // SAFETY: [low, high) lies below the stack pointer and above the
        // static data, memory that no one uses; the address is word-aligned.
        unsafe { (address as *mut u32).write_volatile(PAINT) };
        address += 4;
    }
    Painted { low, top }
}

/// The stack pointer.
#[cfg(target_arch = "arm")]
#[inline(always)]
fn stack_pointer() -> usize {
    cortex_m::register::msp::read() as usize
}

/// An address just above the stack pointer (this frame's local), where the
/// firmware is only built, not run.
#[cfg(not(target_arch = "arm"))]
#[inline(always)]
fn stack_pointer() -> usize {
    let marker = 0u32;
    (core::hint::black_box(&raw const marker) as usize).saturating_sub(256)
}

/// The peak stack use in bytes since [`paint`]: from the top of the stack to
/// the lowest word that no longer holds the pattern (`top − low` if the
/// whole painted region was used: then the true peak may be larger).
pub fn peak(painted: &Painted) -> usize {
    let mut address = painted.low;
    // SAFETY: reads of word-aligned addresses within the RAM region that
    // `paint` wrote, below the current stack pointer or in used stack.
    while address < painted.top && unsafe { (address as *const u32).read_volatile() } == PAINT {
        address += 4;
    }
    painted.top - address
}
