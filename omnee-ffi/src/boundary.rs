//! The only module that turns raw C pointers into Rust values: fixed-length
//! arrays, slices, NUL-terminated strings, and the opaque objects' storage.
//!
//! Every function here is `unsafe fn` with its contract in a `# Safety`
//! section; the exported functions call them under the contract that the
//! header states for every pointer argument (NULL, or valid for the documented
//! extent, and not overlapping an output). NULL is never dereferenced: it
//! comes back as `None`, and the caller turns it into `OMNEE_ERROR_NULL`.

use core::ffi::{CStr, c_char};
use core::mem::{MaybeUninit, align_of, size_of};

/// Reads `N` values from `p`, or `None` for NULL.
///
/// # Safety
/// `p` is NULL or points to `N` initialised, aligned values of `T`.
#[inline]
pub(crate) unsafe fn array<T: Copy, const N: usize>(p: *const T) -> Option<[T; N]> {
    // SAFETY: non-null pointers point to N readable values (the contract).
    (!p.is_null()).then(|| unsafe { p.cast::<[T; N]>().read() })
}

/// `N` writable slots at `p`, or `None` for NULL.
///
/// # Safety
/// `p` is NULL or points to `N` aligned values of `T` that nothing else
/// accesses during the call.
#[inline]
pub(crate) unsafe fn array_out<'a, T, const N: usize>(
    p: *mut T,
) -> Option<&'a mut MaybeUninit<[T; N]>> {
    // SAFETY: non-null pointers point to N writable, unaliased slots (the
    // contract); `MaybeUninit` asks nothing of their contents.
    (!p.is_null()).then(|| unsafe { &mut *p.cast::<MaybeUninit<[T; N]>>() })
}

/// The `len` values at `p` as a slice; an empty slice for `len == 0` (any
/// `p`), `None` for NULL with `len > 0` or a length no slice can have.
///
/// # Safety
/// If `len > 0` and `p` is not NULL, `p` points to `len` initialised, aligned
/// values of `T` that stay unmodified for `'a`.
#[inline]
pub(crate) unsafe fn slice<'a, T>(p: *const T, len: usize) -> Option<&'a [T]> {
    if len == 0 {
        return Some(&[]);
    }
    if p.is_null() || len > isize::MAX as usize / size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: p is non-null and points to len readable values that live and
    // stay unmodified for 'a (the contract); len * size_of::<T>() ≤ isize::MAX.
    Some(unsafe { core::slice::from_raw_parts(p, len) })
}

/// The `len` values at `p` as a mutable slice, like [`slice`].
///
/// # Safety
/// If `len > 0` and `p` is not NULL, `p` points to `len` initialised, aligned
/// values of `T` that nothing else accesses for `'a`.
#[inline]
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, len: usize) -> Option<&'a mut [T]> {
    if len == 0 {
        return Some(&mut []);
    }
    if p.is_null() || len > isize::MAX as usize / size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: p is non-null and points to len values that only this slice
    // accesses for 'a (the contract); len * size_of::<T>() ≤ isize::MAX.
    Some(unsafe { core::slice::from_raw_parts_mut(p, len) })
}

/// The NUL-terminated string at `p`, or `None` for NULL.
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string that stays unmodified
/// for `'a`.
#[inline]
pub(crate) unsafe fn c_str<'a>(p: *const c_char) -> Option<&'a CStr> {
    // SAFETY: non-null pointers point to a NUL-terminated string (the contract).
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) })
}

/// `value` in `N` words of opaque storage, zero-filled first (so that the
/// words past the value, and the padding the write leaves alone, are
/// zero rather than whatever the stack held).
///
/// The storage's size and alignment are checked against `T` at compile time,
/// where this is instantiated: an object that outgrows its C storage does not
/// build (raise the `*_WORDS` constant and regenerate the header).
#[inline]
pub(crate) fn pack<T: Copy, const N: usize>(value: T) -> MaybeUninit<[u64; N]> {
    const {
        assert!(
            size_of::<T>() <= size_of::<[u64; N]>(),
            "opaque storage too small"
        );
        assert!(
            align_of::<T>() <= align_of::<u64>(),
            "opaque storage misaligned"
        );
    }
    let mut storage = MaybeUninit::<[u64; N]>::zeroed();
    // SAFETY: the storage is at least as large and as aligned as T (checked at
    // compile time above) and is a local that nothing else refers to.
    unsafe { storage.as_mut_ptr().cast::<T>().write(value) };
    storage
}

/// The storage's words as integers, for the objects' checksum.
///
/// Each word is read with `read_volatile`, an opaque load: the compiler
/// may assume nothing about the bytes, which for an object that a C caller
/// holds are whatever its memory contains (a constructor's output, a copy,
/// or garbage). For storage that `pack` filled, the bytes outside the
/// value's fields are the zeros it wrote first, except padding inside the
/// value, whose bytes the typed write may leave unspecified; the
/// constructor's checksum reads them from the storage itself, so a later
/// check compares the same bytes.
#[inline]
pub(crate) fn words<const N: usize>(storage: &MaybeUninit<[u64; N]>) -> [u64; N] {
    let first = storage.as_ptr().cast::<u64>();
    core::array::from_fn(|i| {
        let word = first.wrapping_add(i);
        // SAFETY: for i < N `word` lies inside the storage, which is aligned
        // for u64 and live for the borrow. Its bytes are the caller's
        // memory: what a constructor wrote (`pack`'s zeros, then the
        // value), a byte copy of that, or garbage; a padding byte inside a
        // value is whatever the typed write left in memory there. The load
        // is volatile, so the compiler assumes nothing about what it reads.
        unsafe { word.read_volatile() }
    })
}

/// The value that [`pack`] stored.
///
/// # Safety
/// `storage` was filled by `pack::<T, N>` (possibly copied byte for byte
/// since); the objects' tags establish this.
#[inline]
pub(crate) unsafe fn unpack<T: Copy, const N: usize>(storage: &MaybeUninit<[u64; N]>) -> &T {
    // SAFETY: the storage holds a T written by `pack` (the contract), at
    // offset 0, aligned (checked there at compile time).
    unsafe { &*storage.as_ptr().cast::<T>() }
}

/// Whether two memory ranges `[a, a + a_len)`, `[b, b + b_len)` (in elements
/// of `T`) share a byte; empty ranges share none.
pub(crate) fn overlap<T>(a: *const T, a_len: usize, b: *const T, b_len: usize) -> bool {
    let size = size_of::<T>();
    let (a0, b0) = (a as usize, b as usize);
    let (a1, b1) = (
        a0.saturating_add(a_len.saturating_mul(size)),
        b0.saturating_add(b_len.saturating_mul(size)),
    );
    a_len > 0 && b_len > 0 && a0 < b1 && b0 < a1
}
