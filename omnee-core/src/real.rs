//! The two precisions: [`Real`] for scalars (`f32`, `f64`) and [`Vector`] for
//! their glam 3-vectors (`Vec3`, `DVec3`).
//!
//! Every routine of the core is generic over `F: Real`. `f32` is the renderer's
//! precision; `f64` serves references and accuracy tests (the same code, so an
//! f32-against-f64 comparison checks rounding, not a second implementation).
//!
//! Math goes through `libm` unless the `std` feature is on, in which case the
//! platform's (usually faster) functions are used.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A floating-point scalar: `f32` or `f64`.
pub trait Real:
    Copy
    + Debug
    + Default
    + PartialEq
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
{
    /// The glam 3-vector of this precision.
    type Vec3: Vector<Self>;

    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// 1/2.
    const HALF: Self;
    /// π.
    const PI: Self;
    /// 2π.
    const TAU: Self;
    /// π/2.
    const FRAC_PI_2: Self;
    /// 1/π.
    const FRAC_1_PI: Self;
    /// 1/(4π), the isotropic phase function.
    const FRAC_1_4PI: Self;
    /// Machine epsilon (distance from 1 to the next larger number).
    const EPSILON: Self;
    /// √ε, the scale below which a quantity squared is lost next to 1.
    const SQRT_EPSILON: Self;
    /// Largest finite value.
    const MAX: Self;
    /// Smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// +∞.
    const INFINITY: Self;
    /// The largest number below 1, `1 − ε/2`: the top of a uniform sample's range.
    const ONE_MINUS_EPSILON: Self;

    /// Converts (rounding) from f64; used for constants.
    fn from_f64(x: f64) -> Self;
    /// Converts (exactly) to f64.
    fn to_f64(self) -> f64;
    /// Converts (rounding) from f32.
    fn from_f32(x: f32) -> Self;
    /// Converts (rounding) to f32.
    fn to_f32(self) -> f32;

    /// √x.
    fn sqrt(self) -> Self;
    /// ∛x.
    fn cbrt(self) -> Self;
    /// sin x.
    fn sin(self) -> Self;
    /// cos x.
    fn cos(self) -> Self;
    /// (sin x, cos x).
    fn sin_cos(self) -> (Self, Self);
    /// tan x.
    fn tan(self) -> Self;
    /// asin x.
    fn asin(self) -> Self;
    /// atan x.
    fn atan(self) -> Self;
    /// atan2(self, x): the angle of the point (x, self).
    fn atan2(self, x: Self) -> Self;
    /// eˣ.
    fn exp(self) -> Self;
    /// eˣ − 1, accurate for small x.
    fn exp_m1(self) -> Self;
    /// ln x.
    fn ln(self) -> Self;
    /// ln(1 + x), accurate for small x.
    fn ln_1p(self) -> Self;
    /// xʸ.
    fn powf(self, y: Self) -> Self;
    /// |x|.
    fn abs(self) -> Self;
    /// ⌊x⌋.
    fn floor(self) -> Self;
    /// √(x² + y²) without undue overflow.
    fn hypot(self, y: Self) -> Self;
    /// Magnitude of `self` with the sign of `sign`.
    fn copysign(self, sign: Self) -> Self;
    /// Whether the value is neither infinite nor NaN.
    fn is_finite(self) -> bool;
    /// Whether the value is NaN.
    fn is_nan(self) -> bool;

    /// The smaller of two values (NaN-ignoring, like `f32::min`).
    fn min(self, other: Self) -> Self;
    /// The larger of two values (NaN-ignoring, like `f32::max`).
    fn max(self, other: Self) -> Self;
    /// `self` clamped into `[lo, hi]`; NaN maps to `lo`.
    #[inline]
    fn clamp_to(self, lo: Self, hi: Self) -> Self {
        if self >= lo {
            if self <= hi { self } else { hi }
        } else {
            lo
        }
    }
    /// x².
    #[inline]
    fn sqr(self) -> Self {
        self * self
    }
    /// √max(x, 0): the square root of a quantity that is non-negative up to rounding.
    #[inline]
    fn safe_sqrt(self) -> Self {
        self.max(Self::ZERO).sqrt()
    }
}

/// A 3-vector of a [`Real`] precision: the glam operations the core uses.
pub trait Vector<F: Copy>:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<F, Output = Self>
    + Neg<Output = Self>
{
    /// The vector (x, y, z).
    fn new(x: F, y: F, z: F) -> Self;
    /// The components as an array.
    fn to_array(self) -> [F; 3];
    /// The dot product a · b.
    fn dot(self, other: Self) -> F;
    /// The cross product a × b.
    fn cross(self, other: Self) -> Self;
    /// |a|.
    fn length(self) -> F;
    /// |a|².
    fn length_squared(self) -> F;
    /// Two unit vectors that complete `self` (unit length) to a right-handed
    /// orthonormal basis, branch-free (Duff et al. 2017, as in glam).
    fn orthonormal_pair(self) -> (Self, Self);
    /// Whether every component is finite.
    fn is_finite(self) -> bool;

    /// The vector's x component.
    #[inline]
    fn x(self) -> F {
        self.to_array()[0]
    }
    /// The vector's y component.
    #[inline]
    fn y(self) -> F {
        self.to_array()[1]
    }
    /// The vector's z component.
    #[inline]
    fn z(self) -> F {
        self.to_array()[2]
    }
}

macro_rules! impl_real {
    ($f:ident, $vec:ty, $consts:ident, $libm_suffix:ident, $sqrt_epsilon:expr) => {
        impl Real for $f {
            type Vec3 = $vec;

            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            const PI: Self = core::$f::consts::PI;
            const TAU: Self = core::$f::consts::TAU;
            const FRAC_PI_2: Self = core::$f::consts::FRAC_PI_2;
            const FRAC_1_PI: Self = core::$f::consts::FRAC_1_PI;
            const FRAC_1_4PI: Self = (0.25 * core::f64::consts::FRAC_1_PI) as $f;
            const EPSILON: Self = $f::EPSILON;
            const SQRT_EPSILON: Self = $sqrt_epsilon;
            const MAX: Self = $f::MAX;
            const MIN_POSITIVE: Self = $f::MIN_POSITIVE;
            const INFINITY: Self = $f::INFINITY;
            const ONE_MINUS_EPSILON: Self = 1.0 - 0.5 * $f::EPSILON;

            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $f
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn from_f32(x: f32) -> Self {
                x as $f
            }
            #[inline]
            fn to_f32(self) -> f32 {
                self as f32
            }
            #[inline]
            fn abs(self) -> Self {
                $f::abs(self)
            }
            #[inline]
            fn copysign(self, sign: Self) -> Self {
                $f::copysign(self, sign)
            }
            #[inline]
            fn is_finite(self) -> bool {
                $f::is_finite(self)
            }
            #[inline]
            fn is_nan(self) -> bool {
                $f::is_nan(self)
            }
            #[inline]
            fn min(self, other: Self) -> Self {
                $f::min(self, other)
            }
            #[inline]
            fn max(self, other: Self) -> Self {
                $f::max(self, other)
            }
            impl_real!(@math $f, $libm_suffix);
        }

        impl Vector<$f> for $vec {
            #[inline]
            fn new(x: $f, y: $f, z: $f) -> Self {
                <$vec>::new(x, y, z)
            }
            #[inline]
            fn to_array(self) -> [$f; 3] {
                <$vec>::to_array(&self)
            }
            #[inline]
            fn dot(self, other: Self) -> $f {
                <$vec>::dot(self, other)
            }
            #[inline]
            fn cross(self, other: Self) -> Self {
                <$vec>::cross(self, other)
            }
            #[inline]
            fn length(self) -> $f {
                <$vec>::length(self)
            }
            #[inline]
            fn length_squared(self) -> $f {
                <$vec>::length_squared(self)
            }
            #[inline]
            fn orthonormal_pair(self) -> (Self, Self) {
                <$vec>::any_orthonormal_pair(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$vec>::is_finite(self)
            }
        }
    };
    (@math $f:ident, $m:ident) => {
        #[cfg(feature = "std")]
        impl_real!(@std $f);
        #[cfg(not(feature = "std"))]
        impl_real!(@libm $m);
    };
    (@std $f:ident) => {
        #[inline] fn sqrt(self) -> Self { $f::sqrt(self) }
        #[inline] fn cbrt(self) -> Self { $f::cbrt(self) }
        #[inline] fn sin(self) -> Self { $f::sin(self) }
        #[inline] fn cos(self) -> Self { $f::cos(self) }
        #[inline] fn sin_cos(self) -> (Self, Self) { $f::sin_cos(self) }
        #[inline] fn tan(self) -> Self { $f::tan(self) }
        #[inline] fn asin(self) -> Self { $f::asin(self) }
        #[inline] fn atan(self) -> Self { $f::atan(self) }
        #[inline] fn atan2(self, x: Self) -> Self { $f::atan2(self, x) }
        #[inline] fn exp(self) -> Self { $f::exp(self) }
        #[inline] fn exp_m1(self) -> Self { $f::exp_m1(self) }
        #[inline] fn ln(self) -> Self { $f::ln(self) }
        #[inline] fn ln_1p(self) -> Self { $f::ln_1p(self) }
        #[inline] fn powf(self, y: Self) -> Self { $f::powf(self, y) }
        #[inline] fn floor(self) -> Self { $f::floor(self) }
        #[inline] fn hypot(self, y: Self) -> Self { $f::hypot(self, y) }
    };
    (@libm f32) => {
        #[inline] fn sqrt(self) -> Self { libm::sqrtf(self) }
        #[inline] fn cbrt(self) -> Self { libm::cbrtf(self) }
        #[inline] fn sin(self) -> Self { libm::sinf(self) }
        #[inline] fn cos(self) -> Self { libm::cosf(self) }
        #[inline] fn sin_cos(self) -> (Self, Self) { libm::sincosf(self) }
        #[inline] fn tan(self) -> Self { libm::tanf(self) }
        #[inline] fn asin(self) -> Self { libm::asinf(self) }
        #[inline] fn atan(self) -> Self { libm::atanf(self) }
        #[inline] fn atan2(self, x: Self) -> Self { libm::atan2f(self, x) }
        #[inline] fn exp(self) -> Self { libm::expf(self) }
        #[inline] fn exp_m1(self) -> Self { libm::expm1f(self) }
        #[inline] fn ln(self) -> Self { libm::logf(self) }
        #[inline] fn ln_1p(self) -> Self { libm::log1pf(self) }
        #[inline] fn powf(self, y: Self) -> Self { libm::powf(self, y) }
        #[inline] fn floor(self) -> Self { libm::floorf(self) }
        #[inline] fn hypot(self, y: Self) -> Self { libm::hypotf(self, y) }
    };
    (@libm f64) => {
        #[inline] fn sqrt(self) -> Self { libm::sqrt(self) }
        #[inline] fn cbrt(self) -> Self { libm::cbrt(self) }
        #[inline] fn sin(self) -> Self { libm::sin(self) }
        #[inline] fn cos(self) -> Self { libm::cos(self) }
        #[inline] fn sin_cos(self) -> (Self, Self) { libm::sincos(self) }
        #[inline] fn tan(self) -> Self { libm::tan(self) }
        #[inline] fn asin(self) -> Self { libm::asin(self) }
        #[inline] fn atan(self) -> Self { libm::atan(self) }
        #[inline] fn atan2(self, x: Self) -> Self { libm::atan2(self, x) }
        #[inline] fn exp(self) -> Self { libm::exp(self) }
        #[inline] fn exp_m1(self) -> Self { libm::expm1(self) }
        #[inline] fn ln(self) -> Self { libm::log(self) }
        #[inline] fn ln_1p(self) -> Self { libm::log1p(self) }
        #[inline] fn powf(self, y: Self) -> Self { libm::pow(self, y) }
        #[inline] fn floor(self) -> Self { libm::floor(self) }
        #[inline] fn hypot(self, y: Self) -> Self { libm::hypot(self, y) }
    };
}

// √ε: ε = 2^-23 (f32), 2^-52 (f64), so √ε = 2^-11.5, 2^-26.
impl_real!(f32, glam::Vec3, f32, f32, 3.452_669_8e-4);
impl_real!(f64, glam::DVec3, f64, f64, 1.490_116_119_384_765_6e-8);

/// Converts a scalar between precisions (through f64, exact when widening).
#[inline]
pub fn cast<A: Real, B: Real>(x: A) -> B {
    B::from_f64(x.to_f64())
}

/// Converts a vector between precisions.
#[inline]
pub fn cast_vec<A: Real, B: Real>(v: A::Vec3) -> B::Vec3 {
    let [x, y, z] = v.to_array();
    B::Vec3::new(cast(x), cast(y), cast(z))
}

/// sinc x = sin x / x, with the series 1 − x²/6 + x⁴/120 near 0 (docs/math.md §4),
/// so that it is exactly 1 at x = 0 and correctly rounded nearby.
#[inline]
pub fn sinc<F: Real>(x: F) -> F {
    if sinc_is_series(x) {
        sinc_series(x)
    } else {
        x.sin() / x
    }
}

/// [`sinc`] for a caller who already has `sin x`: `sin_x / x`, or the series
/// where `x` is so small that `sin x / x` could be 0/0 or lose bits to underflow.
#[inline]
pub fn sinc_with_sin<F: Real>(x: F, sin_x: F) -> F {
    if sinc_is_series(x) {
        sinc_series(x)
    } else {
        sin_x / x
    }
}

/// Whether [`sinc`] uses its series at `x`: where the next term x⁶/5040 is
/// far under half an ulp of 1 (|x| below 1.9e-3 in f32, 1.2e-5 in f64).
#[inline]
pub fn sinc_is_series<F: Real>(x: F) -> bool {
    x * x < F::from_f64(1e-2) * F::SQRT_EPSILON
}

/// `1 − x²/6 + x⁴/120`.
#[inline]
fn sinc_series<F: Real>(x: F) -> F {
    let x2 = x * x;
    F::ONE - x2 * (F::from_f64(1.0 / 6.0) - x2 * F::from_f64(1.0 / 120.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinc_matches_its_definition_and_limit() {
        assert_eq!(sinc(0.0f32), 1.0);
        assert_eq!(sinc(0.0f64), 1.0);
        for &x in &[1e-8f64, 1e-4, 3e-3, 0.1, 1.0, 3.0] {
            let exact = x.sin() / x;
            assert!(
                (sinc(x) - exact).abs() <= 2.0 * f64::EPSILON * exact,
                "x = {x}"
            );
            let x32 = x as f32;
            let e32 = ((x32 as f64).sin() / x32 as f64) as f32;
            assert!((sinc(x32) - e32).abs() <= 2.0 * f32::EPSILON, "x = {x}");
        }
    }

    #[test]
    fn sqrt_epsilon_is_the_square_root_of_epsilon() {
        assert_eq!(f32::SQRT_EPSILON, f32::EPSILON.sqrt());
        assert_eq!(f64::SQRT_EPSILON, f64::EPSILON.sqrt());
    }

    #[test]
    fn one_minus_epsilon_is_the_largest_number_below_one() {
        assert_eq!(f32::ONE_MINUS_EPSILON, f32::from_bits(1.0f32.to_bits() - 1));
        assert_eq!(f64::ONE_MINUS_EPSILON, f64::from_bits(1.0f64.to_bits() - 1));
    }
}
