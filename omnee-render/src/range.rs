//! Intervals of allowed values: the range checks of scene fields and
//! options, printed in interval notation in their error messages.

use crate::error::{RenderError, Result};
use std::fmt;

/// An interval of allowed values, printed in interval notation.
#[derive(Clone, Copy, Debug)]
pub struct Range {
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
}

impl Range {
    /// `[lo, hi]`.
    pub const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: false,
            hi_open: false,
        }
    }
    /// `(lo, hi)`.
    pub const fn open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: true,
        }
    }
    /// `(lo, hi]`.
    pub const fn open_closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: false,
        }
    }
    /// Any finite number.
    pub const FINITE: Self = Self::open(f64::NEG_INFINITY, f64::INFINITY);
    /// `[0, inf)`.
    pub const NON_NEGATIVE: Self = Self::closed(0.0, f64::INFINITY);
    /// `(0, inf)`.
    pub const POSITIVE: Self = Self::open(0.0, f64::INFINITY);
    /// `[0, 1]`: albedos, fractions.
    pub const UNIT: Self = Self::closed(0.0, 1.0);
    /// `(0, π]`: the once-more integrand's restriction θmax.
    pub const THETA_MAX: Self = Self::open_closed(0.0, std::f64::consts::PI);
    /// `[0, 1e20]`: emitted radiance, intensity and irradiance. The sun's
    /// radiance is about 2e7 W/(m²·sr); the bound keeps every pixel sum of
    /// the f32 renderers finite (f32 overflows at 3.4e38).
    pub const EMISSION: Self = Self::closed(0.0, 1e20);
    /// `(−64, 64)`: a PNG exposure in stops.
    pub const EXPOSURE: Self = Self::open(-64.0, 64.0);

    /// Whether `x` is finite and inside.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && (if self.lo_open {
                x > self.lo
            } else {
                x >= self.lo
            })
            && (if self.hi_open {
                x < self.hi
            } else {
                x <= self.hi
            })
    }

    /// Checks `x`, naming `field` on failure.
    pub fn check(&self, field: &str, x: f64) -> Result<f64> {
        if self.contains(x) {
            Ok(x)
        } else {
            Err(RenderError::range(field, number(x), self))
        }
    }
}

/// A number as messages print it: plainly, or in scientific notation from
/// 10⁹ on and below 10⁻⁶ (`1e39`, `1e-300`, not hundreds of digits).
pub(crate) fn number(x: f64) -> String {
    if (x.abs() >= 1e9 || (x != 0.0 && x.abs() < 1e-6)) && x.is_finite() {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.lo == f64::NEG_INFINITY && self.hi == f64::INFINITY {
            return f.write_str("any finite number");
        }
        let end = |x: f64| {
            if x == f64::INFINITY {
                "inf".to_string()
            } else if x == f64::NEG_INFINITY {
                "-inf".to_string()
            } else {
                number(x)
            }
        };
        write!(
            f,
            "{}{}, {}{}",
            if self.lo_open || self.lo.is_infinite() {
                '('
            } else {
                '['
            },
            end(self.lo),
            end(self.hi),
            if self.hi_open || self.hi.is_infinite() {
                ')'
            } else {
                ']'
            }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_display() {
        assert_eq!(Range::open_closed(0.0, 3.5).to_string(), "(0, 3.5]");
        assert_eq!(Range::NON_NEGATIVE.to_string(), "[0, inf)");
        assert_eq!(Range::FINITE.to_string(), "any finite number");
        assert_eq!(Range::EMISSION.to_string(), "[0, 1e20]");
    }

    #[test]
    fn ranges_reject_nan_infinity_and_their_open_ends() {
        assert!(!Range::FINITE.contains(f64::NAN));
        assert!(!Range::NON_NEGATIVE.contains(f64::INFINITY));
        assert!(!Range::POSITIVE.contains(0.0) && Range::NON_NEGATIVE.contains(0.0));
        assert!(Range::THETA_MAX.contains(std::f64::consts::PI) && !Range::THETA_MAX.contains(0.0));
        let e = Range::UNIT.check("f", 2.0).unwrap_err().to_string();
        assert_eq!(e, "f = 2 is out of range; allowed: [0, 1]");
    }
}
