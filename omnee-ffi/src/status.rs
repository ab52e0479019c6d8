//! Status codes, the caller-owned error record, and the one place that turns
//! a result into a status and written outputs.

use core::ffi::c_char;
use core::fmt::{self, Write};
use core::mem::MaybeUninit;
use omnee_core::Error;

/// What a function did. Zero and positive: success (an output may still be
/// "nothing", as Rust's `None`); negative: an error, described in the
/// `omnee_error` record when the caller passed one.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum omnee_status {
    /// Success: every output is written.
    OMNEE_OK = 0,
    /// Success without a result (Rust's `None`): the uniform numbers map to
    /// no vertex that contributes, the point has no preimage, or the phase
    /// function's sampler is not invertible (mixtures). Outputs are zero.
    OMNEE_NONE = 1,
    /// `omnee_phase_parse_*` read `table:PATH`: the caller loads the file and
    /// calls `omnee_phase_table_*`. The phase function is not written.
    OMNEE_TABLE_SPEC = 2,
    /// A parameter is NaN, infinite or outside its range (the record names
    /// it, its value and the allowed range).
    OMNEE_ERROR_OUT_OF_RANGE = -1,
    /// A vector parameter has a NaN or infinite component, finite values
    /// have a sum that is not finite (a table's values near the largest
    /// number), or a result would not be finite.
    OMNEE_ERROR_NOT_FINITE = -2,
    /// Two points that must differ coincide (x0 == x2), or a direction is zero.
    OMNEE_ERROR_DEGENERATE = -3,
    /// A table or array has the wrong shape: lengths that disagree,
    /// unordered or misplaced edges, overlapping arrays.
    OMNEE_ERROR_TABLE = -4,
    /// A phase-function spec string is malformed.
    OMNEE_ERROR_SYNTAX = -5,
    /// A required pointer is NULL.
    OMNEE_ERROR_NULL = -6,
    /// An opaque object was not made by its constructor, or its storage
    /// changed since: zeroed or garbage memory, a failed constructor's
    /// output, the other precision's type, or a valid tag over altered
    /// storage (the tag carries a checksum of the storage, checked on every
    /// use before the storage is read; a random change goes undetected with
    /// probability 2^-64).
    OMNEE_ERROR_UNINITIALISED = -7,
    /// The operation does not exist for these arguments (the batch needs
    /// Henyey–Greenstein).
    OMNEE_ERROR_UNSUPPORTED = -8,
    /// A quadrature reference spent its evaluation budget before meeting
    /// its tolerance (`omnee_problem_reference_*`): no value is returned.
    /// It takes at most a few seconds, never longer.
    OMNEE_ERROR_NOT_CONVERGED = -9,
}

/// Bytes in `omnee_error.field`, with the terminating NUL.
pub const OMNEE_ERROR_FIELD_CAPACITY: usize = 32;
/// Bytes in `omnee_error.message`, with the terminating NUL: every message
/// the library writes fits.
pub const OMNEE_ERROR_MESSAGE_CAPACITY: usize = 512;

/// An error, written by a function that fails (status < 0) when the caller
/// passes a non-NULL `omnee_error *`; untouched on success. Caller-owned,
/// so errors need no global state and threads never share one.
#[repr(C)]
pub struct omnee_error {
    /// The status the function returned (an `omnee_status`).
    pub status: i32,
    /// For `OMNEE_ERROR_OUT_OF_RANGE`: the value that was given; else 0.
    pub value: f64,
    /// The offending parameter's name, NUL-terminated (e.g. "g", "x2",
    /// "theta_max").
    pub field: [c_char; OMNEE_ERROR_FIELD_CAPACITY],
    /// The message, NUL-terminated UTF-8: for the core's errors exactly the
    /// Rust API's `Display` text, e.g. `g = 1 is out of range; allowed: (-1, 1)`.
    pub message: [c_char; OMNEE_ERROR_MESSAGE_CAPACITY],
}

/// Why a call failed: the core's error, or one that only the C boundary has.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Failure {
    /// The core refused the input.
    Core(Error),
    /// A required pointer is NULL.
    Null(&'static str),
    /// An opaque object without its constructor's tag.
    Uninitialised(&'static str),
    /// No such operation for these arguments.
    Unsupported {
        /// The argument.
        field: &'static str,
        /// Why, in a few words.
        reason: &'static str,
    },
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Core(e)
    }
}

impl Failure {
    /// The status code of this failure.
    pub(crate) fn status(&self) -> omnee_status {
        use omnee_status::*;
        match self {
            Failure::Core(Error::OutOfRange { .. }) => OMNEE_ERROR_OUT_OF_RANGE,
            Failure::Core(Error::NotFinite { .. }) => OMNEE_ERROR_NOT_FINITE,
            Failure::Core(Error::Degenerate { .. }) => OMNEE_ERROR_DEGENERATE,
            Failure::Core(Error::Table { .. } | Error::Arrays { .. }) => OMNEE_ERROR_TABLE,
            Failure::Core(Error::Syntax { .. }) => OMNEE_ERROR_SYNTAX,
            Failure::Core(Error::NotConverged { .. }) => OMNEE_ERROR_NOT_CONVERGED,
            Failure::Null(_) => OMNEE_ERROR_NULL,
            Failure::Uninitialised(_) => OMNEE_ERROR_UNINITIALISED,
            Failure::Unsupported { .. } => OMNEE_ERROR_UNSUPPORTED,
        }
    }

    /// The offending argument's name.
    fn field(&self) -> &'static str {
        match *self {
            Failure::Core(e) => e.field(),
            Failure::Null(field) | Failure::Uninitialised(field) => field,
            Failure::Unsupported { field, .. } => field,
        }
    }

    /// The value of an out-of-range parameter, else 0.
    fn value(&self) -> f64 {
        match *self {
            Failure::Core(Error::OutOfRange { value, .. }) => value,
            _ => 0.0,
        }
    }

    /// The record for this failure.
    pub(crate) fn record(&self) -> omnee_error {
        let mut record = omnee_error {
            status: self.status() as i32,
            value: self.value(),
            field: [0; OMNEE_ERROR_FIELD_CAPACITY],
            message: [0; OMNEE_ERROR_MESSAGE_CAPACITY],
        };
        copy_truncated(self.field().as_bytes(), &mut record.field);
        let mut writer = Truncating {
            buffer: &mut record.message,
            len: 0,
        };
        // `Truncating` never fails; a message that does not fit is cut.
        let _ = write!(writer, "{self}");
        record
    }
}

impl fmt::Display for Failure {
    /// The core's `Display` for its errors; the boundary's own in the same
    /// `field: reason` form as the core's `Degenerate`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Core(e) => fmt::Display::fmt(e, f),
            Failure::Null(field) => write!(f, "{field}: null pointer"),
            Failure::Uninitialised(field) => write!(
                f,
                "{field}: not made by its constructor (zeroed, failed, the other precision, or changed since)"
            ),
            Failure::Unsupported { field, reason } => write!(f, "{field}: {reason}"),
        }
    }
}

/// Copies `text` into `buffer` as a NUL-terminated C string, cut at a UTF-8
/// character boundary if it does not fit; returns the bytes copied.
fn copy_truncated(text: &[u8], buffer: &mut [c_char]) -> usize {
    let Some(room) = buffer.len().checked_sub(1) else {
        return 0;
    };
    let mut n = text.len().min(room);
    // Back off to a character boundary (never inside a multi-byte sequence).
    while n < text.len() && n > 0 && (text[n] & 0xC0) == 0x80 {
        n -= 1;
    }
    for (slot, &byte) in buffer.iter_mut().zip(&text[..n]) {
        *slot = byte as c_char;
    }
    buffer[n] = 0;
    n
}

/// A `fmt::Write` into a fixed C buffer that keeps what fits and stays
/// NUL-terminated.
struct Truncating<'a> {
    buffer: &'a mut [c_char],
    len: usize,
}

impl Write for Truncating<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let start = self.len;
        if start < self.buffer.len() {
            self.len += copy_truncated(s.as_bytes(), &mut self.buffer[start..]);
        }
        Ok(())
    }
}

/// The error record's out-parameter: NULL or a writable `omnee_error`.
pub(crate) type ErrorOut<'a> = Option<&'a mut MaybeUninit<omnee_error>>;

/// Finishes a call whose output parameter is called `name`: on `Ok(Some(v))` writes `v` and returns `OMNEE_OK`; on
/// `Ok(None)` writes `T::default()` (zeros) and returns `OMNEE_NONE`; on
/// failure writes zeros (when the output pointer is there), fills the error
/// record (when given) and returns the failure's status.
#[inline]
pub(crate) fn finish<T: Default>(
    out: Option<&mut MaybeUninit<T>>,
    name: &'static str,
    error: ErrorOut<'_>,
    result: Result<Option<T>, Failure>,
) -> omnee_status {
    let Some(out) = out else {
        return fail(error, Failure::Null(name));
    };
    match result {
        Ok(Some(value)) => {
            out.write(value);
            omnee_status::OMNEE_OK
        }
        Ok(None) => {
            out.write(T::default());
            omnee_status::OMNEE_NONE
        }
        Err(failure) => {
            out.write(T::default());
            fail(error, failure)
        }
    }
}

/// Fills the error record (if given) and returns the failure's status.
#[cold]
pub(crate) fn fail(error: ErrorOut<'_>, failure: Failure) -> omnee_status {
    if let Some(error) = error {
        error.write(failure.record());
    }
    failure.status()
}

/// Copies an error record's message into `buffer` (`capacity` bytes, at
/// least 1) as a NUL-terminated string, cut at a character boundary if it does
/// not fit, and stores the message's full length in `*length` (if not NULL),
/// as `snprintf` does. A record never written by a failing call (all zero)
/// has the empty message.
///
/// Returns `OMNEE_OK`, `OMNEE_ERROR_NULL` for a NULL `error` or `buffer`, or
/// `OMNEE_ERROR_TABLE` for `capacity` 0.
///
/// # Safety
/// `buffer` is NULL or points to `capacity` writable bytes that do not
/// overlap `*error` or `*length`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_error_message(
    error: Option<&omnee_error>,
    buffer: *mut c_char,
    capacity: usize,
    length: Option<&mut MaybeUninit<usize>>,
) -> omnee_status {
    let Some(error) = error else {
        return Failure::Null("error").status();
    };
    // SAFETY: buffer is NULL or points to capacity writable bytes that
    // nothing else uses during the call (this function's contract).
    let Some(buffer) = (unsafe { crate::boundary::slice_mut(buffer, capacity) }) else {
        return Failure::Null("buffer").status();
    };
    if buffer.is_empty() {
        return omnee_status::OMNEE_ERROR_TABLE;
    }
    // The record's own message, up to its NUL (or its capacity).
    let bytes = error.message.map(|c| c as u8);
    let full = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    copy_truncated(&bytes[..full], buffer);
    if let Some(length) = length {
        length.write(full);
    }
    omnee_status::OMNEE_OK
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::{String, ToString};

    fn text(buffer: &[c_char]) -> String {
        let bytes: std::vec::Vec<u8> = buffer
            .iter()
            .map(|&c| c as u8)
            .take_while(|&b| b != 0)
            .collect();
        String::from_utf8(bytes).unwrap()
    }

    #[test]
    fn the_record_holds_the_core_display_text() {
        let e = Error::OutOfRange {
            field: "g",
            value: 1.0,
            allowed: "(-1, 1)",
        };
        let r = Failure::Core(e).record();
        assert_eq!(text(&r.message), e.to_string());
        assert_eq!(text(&r.message), "g = 1 is out of range; allowed: (-1, 1)");
        assert_eq!(text(&r.field), "g");
        assert_eq!(r.value, 1.0);
        assert_eq!(r.status, omnee_status::OMNEE_ERROR_OUT_OF_RANGE as i32);
    }

    #[test]
    fn the_longest_messages_fit() {
        // f64's longest Display texts: the subnormal minimum and the maximum.
        for value in [-5e-324, -f64::MIN_POSITIVE, f64::MIN] {
            let e = Error::OutOfRange {
                field: "a_field_name_of_thirty_one_char",
                value,
                allowed: "an allowed range of 31 chars...",
            };
            let full = e.to_string();
            assert!(full.len() < OMNEE_ERROR_MESSAGE_CAPACITY, "{}", full.len());
            assert_eq!(text(&Failure::Core(e).record().message), full);
        }
        let long_reason = Error::Syntax {
            field: "phase",
            reason: "unknown phase function; expected iso, hg, tthg, ff, draine, mie, rayleigh or table",
        };
        assert_eq!(
            text(&Failure::Core(long_reason).record().message),
            long_reason.to_string()
        );
    }

    #[test]
    fn truncation_keeps_whole_characters() {
        let mut buffer = [1 as c_char; 4];
        // "aπb": π is two bytes; three bytes fit, so "aπ" (3 bytes) stays.
        assert_eq!(copy_truncated("aπb".as_bytes(), &mut buffer), 3);
        assert_eq!(text(&buffer), "aπ");
        let mut buffer = [1 as c_char; 3];
        assert_eq!(copy_truncated("aπb".as_bytes(), &mut buffer), 1);
        assert_eq!(text(&buffer), "a");
        assert_eq!(copy_truncated(b"x", &mut []), 0);
    }
}
