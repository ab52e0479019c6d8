//! The one error type of the core: a parameter outside its allowed range.

use core::fmt;

/// Why a constructor refused its input. Every variant names the offending field,
/// so a front end can print `field = value, allowed: range` without guessing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Error {
    /// A scalar parameter is NaN, infinite or outside its range.
    OutOfRange {
        /// The parameter's name as documented (e.g. `"g"`, `"theta_max"`).
        field: &'static str,
        /// The value that was given.
        value: f64,
        /// The allowed range in interval notation (e.g. `"(-1, 1)"`).
        allowed: &'static str,
    },
    /// A parameter has a NaN or infinite component (see
    /// [`Error::not_finite`]), or a quantity formed from finite parameters is
    /// not finite (a sum that overflows).
    NotFinite {
        /// The parameter's name (e.g. `"x0"`).
        field: &'static str,
        /// What is not finite, as the message continues after the field's
        /// name (e.g. `"has a non-finite component"`).
        reason: &'static str,
    },
    /// Two points that must differ coincide (e.g. `x0 == x2`).
    Degenerate {
        /// The parameter's name.
        field: &'static str,
        /// What is wrong, in a few words.
        reason: &'static str,
    },
    /// A table has the wrong shape (lengths, ordering, end points).
    Table {
        /// The table's name (e.g. `"theta"`).
        field: &'static str,
        /// What is wrong, in a few words.
        reason: &'static str,
    },
    /// Arrays that go together do not fit each other: slices of a batch
    /// whose lengths differ, or output storage that overlaps an input.
    Arrays {
        /// The call's name for its arrays (e.g. `"batch"`).
        field: &'static str,
        /// What is wrong, in a few words.
        reason: &'static str,
    },
    /// A specification string is malformed (unknown name, wrong number of
    /// parameters, a parameter that is not a number).
    Syntax {
        /// The part of the specification (e.g. `"phase"`, `"g"`).
        field: &'static str,
        /// What is wrong, in a few words.
        reason: &'static str,
    },
    /// An adaptive quadrature spent its evaluation budget before meeting
    /// its tolerance ([`crate::quadrature::Budget`]): the value it had is
    /// not trustworthy and is not returned.
    NotConverged {
        /// What was being computed (e.g. `"reference"`).
        field: &'static str,
        /// The integrand evaluations spent.
        evaluations: u64,
    },
}

impl Error {
    /// [`Error::NotFinite`] for a parameter with a NaN or infinite
    /// component: "`field` has a non-finite component". Not inlined: an
    /// error path, and in the browser demo's module its callers inline
    /// 96 B more.
    #[inline(never)]
    pub const fn not_finite(field: &'static str) -> Self {
        Error::NotFinite {
            field,
            reason: "has a non-finite component",
        }
    }

    /// The name of the offending field.
    pub fn field(&self) -> &'static str {
        match *self {
            Error::OutOfRange { field, .. }
            | Error::NotFinite { field, .. }
            | Error::Degenerate { field, .. }
            | Error::Table { field, .. }
            | Error::Arrays { field, .. }
            | Error::Syntax { field, .. }
            | Error::NotConverged { field, .. } => field,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::OutOfRange {
                field,
                value,
                allowed,
            } => {
                write!(f, "{field} = {value} is out of range; allowed: {allowed}")
            }
            Error::NotFinite { field, reason } => write!(f, "{field} {reason}"),
            Error::Degenerate { field, reason } => write!(f, "{field}: {reason}"),
            Error::Table { field, reason } => write!(f, "table {field}: {reason}"),
            Error::Arrays { field, reason } => write!(f, "{field}: {reason}"),
            Error::Syntax { field, reason } => write!(f, "syntax error in {field}: {reason}"),
            Error::NotConverged { field, evaluations } => write!(
                f,
                "{field}: the quadrature did not converge within its budget of {evaluations} evaluations"
            ),
        }
    }
}

impl core::error::Error for Error {}

/// Checks `lo < value < hi` (open interval), naming `field` on failure.
pub(crate) fn check_open(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<(), Error> {
    if value > lo && value < hi {
        Ok(())
    } else {
        Err(Error::OutOfRange {
            field,
            value,
            allowed,
        })
    }
}

/// Checks `lo <= value <= hi` (closed interval), naming `field` on failure.
pub(crate) fn check_closed(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<(), Error> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::OutOfRange {
            field,
            value,
            allowed,
        })
    }
}
