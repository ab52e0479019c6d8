//! The Henyey–Greenstein phase function, in the cancellation-free forms of
//! docs/math.md §4.

use super::{Deflection, PhaseFunction};
use crate::error::{Error, check_open};
use crate::real::Real;

/// Henyey–Greenstein (1941):
/// `p(θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2})`, mean cosine `g ∈ (−1, 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein<F> {
    g: F,
}

impl<F: Real> HenyeyGreenstein<F> {
    /// A lobe with mean cosine `g`; `g` must lie in the open interval (−1, 1).
    pub fn new(g: F) -> Result<Self, Error> {
        check_open("g", g.to_f64(), -1.0, 1.0, "(-1, 1)")?;
        Ok(Self { g })
    }

    /// The asymmetry parameter g (the mean cosine).
    #[inline]
    pub fn g(&self) -> F {
        self.g
    }

    /// `1 + g² − 2g cos θ`, written without cancellation for either sign of g:
    /// `(1 − g)² + 2g (1 − cos θ)` for g ≥ 0, `(1 + g)² − 2g (1 + cos θ)` for g < 0.
    #[inline]
    pub(crate) fn denominator(&self, d: Deflection<F>) -> F {
        let g = self.g;
        if g >= F::ZERO {
            (F::ONE - g).sqr() + F::TWO * g * d.one_minus_cos
        } else {
            (F::ONE + g).sqr() - F::TWO * g * d.one_plus_cos
        }
    }
}

impl<F: Real> PhaseFunction<F> for HenyeyGreenstein<F> {
    /// `p(θ) = (1 − g)(1 + g) / (4π D^{3/2})`, `D = 1 + g² − 2g cos θ` in the
    /// cancellation-free form of `denominator`.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        let g = self.g;
        let den = self.denominator(d);
        F::FRAC_1_4PI * (F::ONE - g) * (F::ONE + g) / (den * den.sqrt())
    }

    /// The inverse CDF in θ ([`Self::sample_pdf`] without the density).
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        self.sample_pdf(u).0
    }

    /// The inverse CDF in θ with its density. With `k = 1 + g − 2gu` (so
    /// that `1 + g² − 2g cos θ = ((1 − g²)/k)²` at the drawn angle),
    ///
    /// `1 − cos θ = (1 − g)² u (1 + g + k) / k² = a / k²`,
    /// `1 + cos θ = (1 + g)² (1 − u)(1 − g + k) / k² = b / k²`,
    ///
    /// both products of non-negative factors, free of cancellation and of a
    /// division by g (g = 0 gives the isotropic `1 − cos θ = 2u`). `k` itself
    /// is summed from non-negative terms, `(1 − g) + 2g(1 − u)` for g ≥ 0 and
    /// `(1 + g) − 2gu` for g < 0 (`1 + g − 2gu` cancels for g → 1, u → 1:
    /// 1e-13 relative at g = 0.997). The common `1/k²` cancels in
    /// `θ = 2 atan2(√a, √b)` ([`Real::atan2_sqrt`]), so θ does not wait for
    /// the division. The density is `p = (1 − g²) / (4π q³)` with
    /// `q = (1 − g²)/k`, i.e. `k³ / (4π (1 − g²)²)`.
    #[inline(always)]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        let g = self.g;
        // Outside the contract u ∈ [0, 1) (and for NaN) the nearest end.
        let u = u.clamp_to(F::ZERO, F::ONE);
        let (one_minus_g, one_plus_g) = (F::ONE - g, F::ONE + g);
        let k = if g >= F::ZERO {
            one_minus_g + F::TWO * g * (F::ONE - u)
        } else {
            one_plus_g - F::TWO * g * u
        };
        let a = one_minus_g.sqr() * u * (one_plus_g + k);
        let b = one_plus_g.sqr() * (F::ONE - u) * (one_minus_g + k);
        let inv_k2 = (F::ONE / k).sqr();
        let deflection = Deflection {
            theta: F::TWO * a.atan2_sqrt(b),
            one_minus_cos: (a * inv_k2).min(F::TWO),
            one_plus_cos: (b * inv_k2).min(F::TWO),
        };
        let one_minus_g2 = one_minus_g * one_plus_g;
        let pdf = F::FRAC_1_4PI * (k * k * k) / (one_minus_g2 * one_minus_g2);
        (deflection, pdf)
    }

    /// `P(Θ ≤ θ) = (1 + g)(1 − cos θ) / (√D (√D + 1 − g))`, the textbook
    /// `(1 − g²)/(2g) · (1/(1 − g) − D^{−1/2})` with the g in the denominator
    /// cancelled analytically.
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        let g = self.g;
        let root = self.denominator(d).sqrt();
        ((F::ONE + g) * d.one_minus_cos / (root * (root + F::ONE - g))).min(F::ONE)
    }

    /// `⟨cos θ⟩ = g`.
    #[inline]
    fn mean_cosine(&self) -> F {
        self.g
    }
}
