//! The two precisions: [`Real`] for scalars (`f32`, `f64`) and [`Vector`] for
//! their glam 3-vectors (`Vec3`, `DVec3`).
//!
//! Every routine of the core is generic over `F: Real`. `f32` is the renderer's
//! precision; `f64` serves references and accuracy tests (the same code, so an
//! f32-against-f64 comparison checks rounding, not a second implementation).
//!
//! Math goes through `libm` unless the `std` feature is on, in which case the
//! platform's functions are used (not faster on x86-64 with glibc 2.36: see
//! omnee-core's Cargo.toml).

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
    /// The exponent of [`MIN_POSITIVE`](Self::MIN_POSITIVE), `2^MIN_EXPONENT`
    /// the smallest positive normal number (−126, −1022).
    const MIN_EXPONENT: i32;
    /// The exponent of [`MAX`](Self::MAX), `2^MAX_EXPONENT` the largest
    /// power of two (127, 1023).
    const MAX_EXPONENT: i32;

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
    /// `(sin x, cos x)` for an acute or right angle, `|x| ≤ π/2` (a
    /// triangle's smaller angle, half a deflection), to within one ulp like
    /// [`sin_cos`](Self::sin_cos) but without its range reduction.
    ///
    /// f32: [`sin_cos_acute_f32`]; f64: [`sin_cos`](Self::sin_cos).
    #[inline]
    fn sin_cos_acute(self) -> (Self, Self) {
        self.sin_cos()
    }
    /// `(sin 2πt, cos 2πt)` for `t = self ∈ [−1, 1]`, an azimuth in turns
    /// (the sampler's `u = φ/2π`), to within one ulp of the exact values
    /// (the angle `2πt` itself is not rounded first). Outside the range the
    /// result stays bounded but loses accuracy.
    ///
    /// f32: [`sin_cos_turn_f32`]; f64: `(2πt).sin_cos()`.
    #[inline]
    fn sin_cos_turn(self) -> (Self, Self) {
        (Self::TAU * self).sin_cos()
    }
    /// `atan2(√a, √b)` for `a = self ≥ 0`, `b ≥ 0`: the angle in `[0, π/2]`
    /// whose squared tangent is `a/b` (0 for `a = b = 0`, NaN for NaN or a
    /// negative argument). Every deflection is twice such an angle,
    /// `θ = 2 atan2(√(1 − cos θ), √(1 + cos θ))`.
    ///
    /// f32: [`atan2_sqrt_f32`]; f64: `atan2(√a, √b)` by libm.
    #[inline]
    fn atan2_sqrt(self, b: Self) -> Self {
        self.sqrt().atan2(b.sqrt())
    }
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
    /// `self · 2ⁿ`, exact unless the result is subnormal or overflows, where
    /// it is rounded once (C's `scalbn`): the scaling that moves a length
    /// into a connection's unit and a density back (docs/math.md §15).
    fn scale_pow2(self, n: i32) -> Self;
    /// The exponent `k` with `2ᵏ ≤ |x| < 2ᵏ⁺¹` of a finite non-zero `x`,
    /// subnormals included (C's `ilogb`); unspecified for 0, ∞ and NaN.
    fn exponent(self) -> i32;

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
    /// |a|, without overflow or underflow on the way: `√(a·a)` where `a·a`
    /// is a normal number, else `|a 2⁻ᵏ| 2ᵏ` with `2ᵏ` the largest
    /// component's power of two (exact scalings), so that any finite vector
    /// whose length is representable gets it to within an ulp (and a longer
    /// one ∞).
    fn length(self) -> F;
    /// |a|².
    fn length_squared(self) -> F;
    /// Two unit vectors that complete `self` (unit length) to a right-handed
    /// orthonormal basis, branch-free (Duff et al. 2017, as in glam).
    fn orthonormal_pair(self) -> (Self, Self);
    /// Whether every component is finite.
    fn is_finite(self) -> bool;
    /// `max(|x|, |y|, |z|)` (NaN components ignored).
    fn max_abs(self) -> F;
    /// `a · 2ⁿ` component by component ([`Real::scale_pow2`]).
    fn scale_pow2(self, n: i32) -> Self;

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
            const MIN_EXPONENT: i32 = $f::MIN_EXP - 1;
            const MAX_EXPONENT: i32 = $f::MAX_EXP - 1;

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
            fn scale_pow2(self, n: i32) -> Self {
                if (Self::MIN_EXPONENT..=Self::MAX_EXPONENT).contains(&n) {
                    // 2ⁿ is a normal number: one correctly rounded product.
                    self * impl_real!(@pow2 $f, n)
                } else {
                    impl_real!(@scalbn $f)(self, n)
                }
            }
            #[inline]
            fn exponent(self) -> i32 {
                impl_real!(@ilogb $f)(self)
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
            impl_real!(@bounded $f);
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
                let l2 = <$vec>::length_squared(self);
                // Where |a|² is a normal number with room below it for the
                // rounding of subnormal squares, and finite, it is accurate.
                if ($f::MIN_POSITIVE / $f::EPSILON..=$f::MAX).contains(&l2) {
                    Real::sqrt(l2)
                } else {
                    scaled_length::<$f>(self)
                }
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
            #[inline]
            fn max_abs(self) -> $f {
                let [x, y, z] = self.to_array();
                x.abs().max(y.abs()).max(z.abs())
            }
            #[inline]
            fn scale_pow2(self, n: i32) -> Self {
                let [x, y, z] = self.to_array();
                <$vec>::new(x.scale_pow2(n), y.scale_pow2(n), z.scale_pow2(n))
            }
        }
    };
    (@pow2 f32, $n:expr) => { f32::from_bits((($n + 127) as u32) << 23) };
    (@pow2 f64, $n:expr) => { f64::from_bits((($n + 1023) as u64) << 52) };
    (@scalbn f32) => { libm::scalbnf };
    (@scalbn f64) => { libm::scalbn };
    (@ilogb f32) => { libm::ilogbf };
    (@ilogb f64) => { libm::ilogb };
    (@math $f:ident, $m:ident) => {
        #[cfg(feature = "std")]
        impl_real!(@std $f);
        #[cfg(not(feature = "std"))]
        impl_real!(@libm $m);
    };
    (@bounded f32) => {
        #[inline(always)] fn sin_cos_acute(self) -> (Self, Self) { sin_cos_acute_f32(self) }
        #[inline(always)] fn sin_cos_turn(self) -> (Self, Self) { sin_cos_turn_f32(self) }
        #[inline(always)] fn atan2_sqrt(self, b: Self) -> Self { atan2_sqrt_f32(self, b) }
    };
    (@bounded f64) => {};
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

// The f32 kernels below evaluate in f64 with polynomials fitted for f32
// results (errors 2e-11 and 5e-10, far below the final rounding), so each
// result is the exact value rounded about once: within 0.51 ulp (tested).
// Compared with libm's general `sincosf` and `atan2f` they skip the range
// reduction and the branches on the argument's range, which a sampled angle
// mispredicts, and their polynomials are evaluated in Estrin's scheme
// (independent pairs, then powers of z) for a short dependency chain: the
// OMNEE sample is bound by its latency. `libm` stays the implementation for
// f64, the precision of references.

/// `sin x / x = S(x²)` on `|x| ≤ π/2`: degree 5 in `z = x²`, least-squares
/// in the Chebyshev basis on `[0, π²/4]`, maximum error 1.7e-11 (degree 4
/// would give 6.7e-9, 0.1 f32 ulp, and results up to 0.61 ulp off).
pub(crate) const SIN_ACUTE: [f64; 6] = [
    0.999_999_999_982_919_1,
    -0.166_666_666_168_155_67,
    0.008_333_330_974_207_583,
    -0.000_198_408_611_793_195_52,
    2.752_526_981_229_885e-6,
    -2.388_921_777_345_280_6e-8,
];

/// `atan(√w)/√w = Q(w)` on `w ∈ [0, 1]`: degree 10, fitted as
/// [`SIN_ACUTE`], maximum error 4.5e-10.
pub(crate) const ATAN_SQRT: [f64; 11] = [
    0.999_999_999_553_537_6,
    -0.333_333_224_889_115_93,
    0.199_995_581_003_639_82,
    -0.142_785_760_248_079_85,
    0.110_507_712_758_496_6,
    -0.087_850_432_823_628_45,
    0.066_852_815_178_774_24,
    -0.043_928_410_733_267_46,
    0.021_912_945_865_448_393,
    -0.007_030_669_470_424_213,
    0.001_057_607_438_057_242,
];

/// `c0 + c1 z + … + c5 z⁵` by Estrin's scheme (pairs, then powers of z).
#[inline(always)]
fn estrin5(c: &[f64; 6], z: f64) -> f64 {
    let z2 = z * z;
    let z4 = z2 * z2;
    (c[0] + c[1] * z) + z2 * (c[2] + c[3] * z) + z4 * (c[4] + c[5] * z)
}

/// `(sin x, cos x)` in f64 for `|x| ≤ π/2`: `sin x = x S(x²)` and
/// `cos x = sin y = y S(y²)` with `y = π/2 − |x|` ([`SIN_ACUTE`]), so that
/// both are accurate relative to themselves, `cos x` also next to π/2 (where
/// `1 + cos θ = 2 cos²(θ/2)` needs it). `y` is exact for an f32 `x` up to
/// the rounding of π/2 (6e-17), which is below 1.4e-9 of any `y` an f32 `x`
/// can give.
#[inline(always)]
pub(crate) fn sin_cos_acute_f64(x: f64) -> (f64, f64) {
    let y = core::f64::consts::FRAC_PI_2 - x.abs();
    (
        x * estrin5(&SIN_ACUTE, x * x),
        y * estrin5(&SIN_ACUTE, y * y),
    )
}

/// `(sin x, cos x)` in f32 for `|x| ≤ π/2`: `sin_cos_acute_f64` (the
/// polynomial `SIN_ACUTE` at `x` and at `π/2 − |x|`), rounded once.
#[inline(always)]
pub fn sin_cos_acute_f32(x: f32) -> (f32, f32) {
    let (s, c) = sin_cos_acute_f64(x as f64);
    (s as f32, c as f32)
}

/// `(sin 2πt, cos 2πt)` in f32 for `|t| ≤ 1`, in f64: the nearest half turn
/// `j/2` (`j ∈ {−2, …, 2}`), the exact remainder `r = t − j/2 ∈ [−1/4, 1/4]`,
/// and `(sin 2πt, cos 2πt) = (−1)ʲ (sin 2πr, cos 2πr)` with
/// `sin_cos_acute_f64` at `2πr ∈ [−π/2, π/2]`. Branch-free.
#[inline(always)]
pub fn sin_cos_turn_f32(t: f32) -> (f32, f32) {
    const TO_INT: f64 = 1.5 / f64::EPSILON; // adding it rounds to an integer
    let t = t as f64;
    let j = (2.0 * t + TO_INT) - TO_INT;
    let (s, c) = sin_cos_acute_f64(core::f64::consts::TAU * (t - 0.5 * j));
    // (−1)ʲ; `as` saturates for a t far outside the range (and maps NaN to 0).
    let sign = (1 - 2 * (j as i64 & 1)) as f64;
    ((sign * s) as f32, (sign * c) as f32)
}

/// `atan2(√a, √b)` in f32 for `a, b ≥ 0`, in f64 with one division and no
/// branch on the data: `w = min(a, b)/max(a, b) ∈ [0, 1]`,
/// `atan(√w) = √w Q(w)` (`ATAN_SQRT`; the square root runs in parallel
/// with the polynomial), and `π/2 − atan(√w)` if `a > b`
/// (`atan2(√a, √b) = π/2 − atan2(√b, √a)`). `(0, 0)` gives 0; NaN or a
/// negative argument gives NaN.
#[inline(always)]
pub fn atan2_sqrt_f32(a: f32, b: f32) -> f32 {
    if !(a >= 0.0 && b >= 0.0) {
        return f32::NAN;
    }
    let (a, b) = (a as f64, b as f64);
    // `min`/`max`, not comparisons: LLVM turns those into a branch, which a
    // deflection on either side of π/2 mispredicts.
    let w = a.min(b) / a.max(b).max(f64::MIN_POSITIVE);
    // `if a > b { π/2 − t } else { t }` as `base + sign t` with the sign of
    // b − a (+1 for a = b) and `base = (1 − sign) π/4`: no branch.
    let sign = 1.0f64.copysign(b - a);
    let base = (1.0 - sign) * core::f64::consts::FRAC_PI_4;
    let w2 = w * w;
    let w4 = w2 * w2;
    let w8 = w4 * w4;
    let c = &ATAN_SQRT;
    let q = ((c[0] + c[1] * w) + w2 * (c[2] + c[3] * w))
        + w4 * ((c[4] + c[5] * w) + w2 * (c[6] + c[7] * w))
        + w8 * ((c[8] + c[9] * w) + w2 * c[10]);
    (base + sign * (libm::sqrt(w) * q)) as f32
}

/// `eʳ` on `|r| ≤ ln2/2`: degree 7, least-squares in the Chebyshev basis,
/// maximum relative error 5.5e-11.
const EXP_HALF_LN2: [f64; 8] = [
    0.999_999_999_959_561_8,
    0.999_999_999_995_509,
    0.500_000_010_772_916_6,
    0.166_666_667_863_085_87,
    0.041_666_218_319_291_945,
    0.008_333_283_538_708_528,
    0.001_394_857_832_645_979_5,
    0.000_199_075_693_108_482_88,
];

/// `ln m = s L(s²)` with `s = (m − 1)/(m + 1)`, `m ∈ [√½, √2]`
/// (`s² ≤ (3 − 2√2)²`): degree 4, fitted as [`EXP_HALF_LN2`], maximum
/// relative error 4.2e-12.
const LN_ATANH: [f64; 5] = [
    2.000_000_000_008_359_5,
    0.666_666_652_474_875_2,
    0.400_003_846_723_751_9,
    0.285_350_510_378_163_1,
    0.236_163_590_991_459_84,
];

/// `eˣ` in f64 to the accuracy an f32 result needs (5.5e-11 relative), for
/// `x ∈ [−700, 700]` (0 below): `x = k ln2 + r` with `k` the nearest integer
/// to `x/ln2` and ln2 in two parts (the first exact in 33 bits), `eʳ` by
/// [`EXP_HALF_LN2`], and `2ᵏ` from its bits. No branch on the data but the
/// range.
#[inline]
pub(crate) fn exp_f32_grade(x: f64) -> f64 {
    const LN2_HI: f64 = 0.693_147_180_369_123_8; // ln 2 to 33 bits
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10; // ln 2 − LN2_HI
    const TO_INT: f64 = 1.5 / f64::EPSILON;
    if !(x >= -700.0) {
        return if x.is_nan() { x } else { 0.0 };
    }
    let x = x.min(700.0);
    let k = (x * core::f64::consts::LOG2_E + TO_INT) - TO_INT;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    let c = &EXP_HALF_LN2;
    let (r2, r4) = (r * r, r * r * r * r);
    let p = ((c[0] + c[1] * r) + r2 * (c[2] + c[3] * r))
        + r4 * ((c[4] + c[5] * r) + r2 * (c[6] + c[7] * r));
    p * f64::from_bits(((k as i64 + 1023) as u64) << 52)
}

/// `ln x` in f64 to the accuracy an f32 result needs (absolute error below
/// 1e-15 + 4.2e-12 |ln m|), for positive normal `x`: `x = 2ᵉ m` with
/// `m ∈ [√½, √2)` from the bits, `ln x = e ln2 + s L(s²)`,
/// `s = (m − 1)/(m + 1)` ([`LN_ATANH`]). No branch.
#[inline]
pub(crate) fn ln_f32_grade(x: f64) -> f64 {
    const MANTISSA: u64 = (1 << 52) - 1;
    let bits = x.to_bits();
    let m = f64::from_bits((bits & MANTISSA) | (1023 << 52)); // in [1, 2)
    // Halve m above √2 (exact: by 1 or ½), and count it in the exponent.
    let big = f64::from(u8::from(m > core::f64::consts::SQRT_2));
    let m = m * (1.0 - 0.5 * big);
    let e = ((bits >> 52) as i64 - 1023) as f64 + big;
    let s = (m - 1.0) / (m + 1.0);
    let z = s * s;
    let c = &LN_ATANH;
    let z2 = z * z;
    let l = (c[0] + c[1] * z) + z2 * ((c[2] + c[3] * z) + z2 * c[4]);
    e * core::f64::consts::LN_2 + s * l
}

/// `eˣ` in f64 as accurately as a result in `F` needs: libm's for f64,
/// [`exp_f32_grade`] for f32 (the branch folds at compile time).
#[inline]
pub(crate) fn exp_for<F: Real>(x: f64) -> f64 {
    if F::EPSILON.to_f64() > 1e-10 {
        exp_f32_grade(x)
    } else {
        libm::exp(x)
    }
}

/// `ln x` in f64 as accurately as a result in `F` needs: libm's for f64,
/// [`ln_f32_grade`] for f32.
#[inline]
pub(crate) fn ln_for<F: Real>(x: f64) -> f64 {
    if F::EPSILON.to_f64() > 1e-10 {
        ln_f32_grade(x)
    } else {
        libm::log(x)
    }
}

/// `∛x` for a starting value that Newton steps polish:
/// `t = sign(x) exp(ln|x| / 3)`, then one Newton step on `t³ = x`,
/// `t − (t − x/t²)/3`, which leaves it within about an ulp of the cube root
/// (0, ±∞ and NaN as [`Real::cbrt`]). libm's correctly rounded `cbrt` is
/// 1.6 KiB of the browser demo's module with the software `fma` it needs.
#[inline]
pub(crate) fn cbrt_start<F: Real>(x: F) -> F {
    let t = (x.abs().ln() * F::from_f64(1.0 / 3.0)).exp().copysign(x);
    if t.is_finite() && t != F::ZERO {
        t - (t - x / (t * t)) * F::from_f64(1.0 / 3.0)
    } else {
        t
    }
}

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

/// [`Vector::length`] off its fast path: `|a 2⁻ᵏ| 2ᵏ` with `2ᵏ ≤ max |aᵢ|`
/// (exact scalings), `|a|²` itself where a component is not finite.
#[cold]
fn scaled_length<F: Real>(a: F::Vec3) -> F {
    let largest = a.max_abs();
    if !(a.is_finite() && largest > F::ZERO) {
        return a.length_squared().sqrt();
    }
    let k = largest.exponent();
    a.scale_pow2(-k).length_squared().sqrt().scale_pow2(k)
}

/// The unit vector along a finite, non-zero `a` of any length (components
/// from the smallest subnormal to `F::MAX`): `a/|a|` where `|a|²` is a
/// normal number, else computed on `a 2⁻ᵏ` with `2ᵏ` the largest
/// component's power of two, so that neither `|a|²` nor `1/|a|` over- or
/// underflows. `None` for a zero or non-finite vector.
#[inline]
pub fn unit_vector<F: Real>(a: F::Vec3) -> Option<F::Vec3> {
    let l2 = a.length_squared();
    if l2 >= F::MIN_POSITIVE / F::EPSILON && l2 <= F::MAX {
        return Some(a * (F::ONE / l2.sqrt()));
    }
    scaled_unit_vector::<F>(a)
}

/// [`unit_vector`] off its fast path.
#[cold]
fn scaled_unit_vector<F: Real>(a: F::Vec3) -> Option<F::Vec3> {
    let largest = a.max_abs();
    if !(a.is_finite() && largest > F::ZERO) {
        return None;
    }
    let scaled = a.scale_pow2(-largest.exponent());
    Some(scaled * (F::ONE / scaled.length_squared().sqrt()))
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
pub(crate) fn sinc_series<F: Real>(x: F) -> F {
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

    /// |a − exact| in units of the f32 spacing at `exact` (a ulp of the
    /// correctly rounded result).
    fn f32_ulps(a: f32, exact: f64) -> f64 {
        let spacing = |v: f64| {
            let v = (v.abs() as f32).max(f32::MIN_POSITIVE);
            (f32::from_bits(v.to_bits() + 1) - v) as f64
        };
        (a as f64 - exact).abs() / spacing(exact)
    }

    /// The largest error in f32 ulps of a kernel over `xs` against f64 libm.
    fn worst_ulps(xs: impl Iterator<Item = f32>, f: impl Fn(f32) -> (f32, f64)) -> f64 {
        xs.map(|x| {
            let (got, exact) = f(x);
            f32_ulps(got, exact)
        })
        .fold(0.0, f64::max)
    }

    /// Every `step`-th f32 from `lo` to `hi` (non-negative), both included.
    fn floats(lo: f32, hi: f32, step: usize) -> impl Iterator<Item = f32> {
        (lo.to_bits()..=hi.to_bits())
            .step_by(step)
            .chain([hi.to_bits()])
            .map(f32::from_bits)
    }

    #[test]
    fn f32_sin_cos_kernels_are_within_an_ulp() {
        let half_pi = core::f32::consts::FRAC_PI_2;
        let acute = |_: f32| floats(0.0, half_pi, 53).chain(floats(0.0, half_pi, 53).map(|x| -x));
        let sin = worst_ulps(acute(0.0), |x| {
            (sin_cos_acute_f32(x).0, libm::sin(x as f64))
        });
        let cos = worst_ulps(acute(0.0), |x| {
            (sin_cos_acute_f32(x).1, libm::cos(x as f64))
        });
        std::println!("sin_cos_acute_f32: sin {sin:.3} ulp, cos {cos:.3} ulp");
        assert!(sin < 0.51 && cos < 0.51, "{sin} {cos}");
        let turn = || floats(0.0, 1.0, 41).chain(floats(0.0, 1.0, 41).map(|t| -t));
        // The exact values: libm at the exactly reduced angle, 2π(t − j/2)
        // with (−1)ʲ (libm at the rounded 2πt is off near multiples of π).
        let exact = |t: f32| {
            let j = libm::round(2.0 * t as f64);
            let sign = if j as i64 % 2 == 0 { 1.0 } else { -1.0 };
            let (s, c) = libm::sincos(core::f64::consts::TAU * (t as f64 - 0.5 * j));
            (sign * s, sign * c)
        };
        let sin = worst_ulps(turn(), |t| (sin_cos_turn_f32(t).0, exact(t).0));
        let cos = worst_ulps(turn(), |t| (sin_cos_turn_f32(t).1, exact(t).1));
        std::println!("sin_cos_turn_f32: sin {sin:.3} ulp, cos {cos:.3} ulp");
        assert!(sin < 0.51 && cos < 0.51, "{sin} {cos}");
        assert_eq!(sin_cos_acute_f32(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turn_f32(0.0), (0.0, 1.0));
        let (s, c) = sin_cos_turn_f32(f32::NAN);
        assert!(s.is_nan() && c.is_nan());
        // Beyond the documented range it stays bounded.
        for x in [1e3f32, -7e5, 1e6, 1e30] {
            let (s, c) = sin_cos_turn_f32(x);
            assert!(s.abs() <= 1.0 && c.abs() <= 1.0, "{x}: {s} {c}");
        }
    }

    #[test]
    fn f32_atan2_sqrt_is_within_an_ulp() {
        let exact = |a: f32, b: f32| libm::atan2(libm::sqrt(a as f64), libm::sqrt(b as f64));
        // a/b over every 37th f32 against b = 1, and mirrored.
        let mut worst = worst_ulps(floats(0.0, f32::MAX, 37), |t| {
            (atan2_sqrt_f32(t, 1.0), exact(t, 1.0))
        });
        worst = worst.max(worst_ulps(floats(0.0, f32::MAX, 37), |t| {
            (atan2_sqrt_f32(1.0, t), exact(1.0, t))
        }));
        // Versine pairs whose ratio rounds: 1 − cos θ = x, 1 + cos θ = 2 − x.
        worst = worst.max(worst_ulps(floats(0.0, 2.0, 29), |x| {
            (atan2_sqrt_f32(x, 2.0 - x), exact(x, 2.0 - x))
        }));
        std::println!("atan2_sqrt_f32: {worst:.3} ulp");
        assert!(worst < 0.51, "{worst}");
        assert_eq!(atan2_sqrt_f32(0.0, 0.0), 0.0);
        assert_eq!(atan2_sqrt_f32(0.0, 1.0), 0.0);
        assert_eq!(atan2_sqrt_f32(1.0, 0.0), core::f32::consts::FRAC_PI_2);
        assert_eq!(
            atan2_sqrt_f32(f32::INFINITY, 1.0),
            core::f32::consts::FRAC_PI_2
        );
        assert!(atan2_sqrt_f32(f32::NAN, 1.0).is_nan());
        assert!(atan2_sqrt_f32(1.0, -1.0).is_nan());
    }

    #[test]
    fn f32_grade_exp_and_ln_are_accurate_to_1e10() {
        let (mut exp_err, mut ln_err) = (0.0f64, 0.0f64);
        for i in 0..=200_000 {
            let x = -100.0 + 110.0 * i as f64 / 200_000.0;
            exp_err = exp_err.max((exp_f32_grade(x) / libm::exp(x) - 1.0).abs());
        }
        // Logarithms over every 97th f32 from the smallest normal up.
        let mut bits = f32::MIN_POSITIVE.to_bits();
        while bits < f32::MAX.to_bits() {
            let x = f32::from_bits(bits) as f64;
            ln_err =
                ln_err.max((ln_f32_grade(x) - libm::log(x)).abs() / libm::log(x).abs().max(1.0));
            bits += 97;
        }
        std::println!("exp_f32_grade {exp_err:.2e} relative, ln_f32_grade {ln_err:.2e}");
        assert!(exp_err < 1e-10 && ln_err < 1e-11, "{exp_err} {ln_err}");
        assert_eq!(exp_f32_grade(-800.0), 0.0);
        assert!(exp_f32_grade(f64::NAN).is_nan());
        assert_eq!(ln_f32_grade(1.0), 0.0);
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
