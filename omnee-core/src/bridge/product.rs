//! A product of many factors kept as `m · 2^e`, so that it neither
//! overflows nor underflows before its last factor: a bridge's weight
//! `D^{k+1}/(s³ k!)` and estimate `σs^k e^{−τ} · weight` are of order
//! `s^{k−2}` (docs/math.md §14.5), representable where their factors' partial
//! products are not (f32 at s = 1e-30, k = 2: `1/s² = 1e60` times `s² σs²`).

use crate::real::Real;

/// `m · 2^e` with `m` in `[1, 2)`, or `m = 0` (the product is 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Product<F> {
    m: F,
    e: i32,
}

/// Beyond this many binary orders of magnitude no other factor of a bridge
/// (at most `3·(MAX_VERTICES + 2)` factors, each within `2^{±1100}`) brings
/// a product back into f64's range.
const FAR: i32 = 1 << 20;

impl<F: Real> Product<F> {
    /// The empty product, 1.
    pub(crate) const ONE: Self = Self { m: F::ONE, e: 0 };

    /// `x ≥ 0` as a product: `x = m · 2^e`; NaN, negative numbers and 0 are
    /// 0, `+∞` is `2^FAR` (beyond every range).
    #[inline]
    pub(crate) fn of(x: F) -> Self {
        if !(x > F::ZERO) {
            Self { m: F::ZERO, e: 0 }
        } else if !x.is_finite() {
            Self { m: F::ONE, e: FAR }
        } else {
            let e = x.exponent();
            Self {
                m: x.scale_pow2(-e),
                e,
            }
        }
    }

    /// `self · other`: `m m'` in `[1, 4)` renormalised, exponents added.
    #[inline]
    pub(crate) fn times(self, other: Self) -> Self {
        let m = self.m * other.m;
        if !(m > F::ZERO) {
            return Self { m: F::ZERO, e: 0 };
        }
        let j = m.exponent();
        Self {
            m: m.scale_pow2(-j),
            e: (self.e + other.e + j).clamp(-FAR, FAR),
        }
    }

    /// `self · x` for `x ≥ 0`.
    #[inline]
    pub(crate) fn times_real(self, x: F) -> Self {
        self.times(Self::of(x))
    }

    /// `self / x` for `x > 0` (finite): `m/m'` in `(1/2, 2)` renormalised.
    #[inline]
    pub(crate) fn over_real(self, x: F) -> Self {
        let y = Self::of(x);
        if !(y.m > F::ZERO) {
            return Self { m: F::ONE, e: FAR };
        }
        self.times(Self {
            m: F::ONE / y.m,
            e: -y.e,
        })
    }

    /// `e^x` as `e^r · 2^n` with `n = ⌊x/ln 2⌋` and `r = x − n ln 2 ∈
    /// [0, ln 2)`, so that it leaves no range where `e^x` alone would
    /// (|x| > 88 in f32); inside the range `e^x` itself (one rounding);
    /// `x = −∞` is 0, NaN is 0.
    #[inline]
    pub(crate) fn exp(x: F) -> Self {
        let plain = x.exp();
        if plain >= F::MIN_POSITIVE && plain.is_finite() {
            return Self::of(plain);
        }
        let ln2 = F::from_f64(core::f64::consts::LN_2);
        let n = (x / ln2).floor();
        let far = F::from_f64(f64::from(FAR));
        if !(n > -far) {
            return Self { m: F::ZERO, e: 0 };
        }
        if !(n < far) {
            return Self { m: F::ONE, e: FAR };
        }
        let r = (x - n * ln2).max(F::ZERO);
        Self::of(r.exp()).times(Self::pow2(n.to_f64() as i32))
    }

    /// `e^{−x}` for `x ≥ 0` ([`exp`](Self::exp) of `−x`); `x = +∞` is 0.
    #[inline]
    pub(crate) fn exp_neg(x: F) -> Self {
        Self::exp(-x)
    }

    /// `2ⁿ`.
    #[inline]
    pub(crate) fn pow2(n: i32) -> Self {
        Self {
            m: F::ONE,
            e: n.clamp(-FAR, FAR),
        }
    }

    /// The product in `F`: `m · 2^e`, `F::MAX` above the range, 0 (or a
    /// subnormal) below it.
    #[inline]
    pub(crate) fn value(self) -> F {
        let x = self.m.scale_pow2(self.e);
        if x.is_finite() { x } else { F::MAX }
    }

    /// The product in f64, whatever `F`: `m · 2^e` scaled in f64
    /// (`f64::MAX` above its range, 0 below it).
    #[inline]
    pub(crate) fn to_f64(self) -> f64 {
        Product::<f64> {
            m: self.m.to_f64(),
            e: self.e,
        }
        .value()
    }
}
