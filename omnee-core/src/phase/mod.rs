//! Phase functions: the angular distribution of scattering at the vertex `x1`.
//!
//! Conventions (MATH.md §1): θ is the deflection between the *propagation*
//! directions before and after scattering, `cos θ = ω1 · ω2`; θ = 0 is straight
//! on. Every phase function is normalised over the sphere, `∫ p dω = 1`, i.e.
//! `2π ∫₀^π p(θ) sin θ dθ = 1`, so Henyey–Greenstein with g > 0 peaks at θ = 0.
//! (pbrt and Mitsuba pass both directions pointing away from the vertex: their
//! cosine is `−ω1 · ω2`.)
//!
//! Angles travel as a [`Deflection`], which carries `1 − cos θ` and `1 + cos θ`
//! next to θ: for a forward peak like g = 0.997 the typical `1 − cos θ` is
//! 4.5e-6 and `cos θ` in f32 would keep two digits of it (MATH.md §4).
//!
//! Each phase function implements [`PhaseFunction`]: `eval`, an inverse-CDF
//! `sample`, its `cdf` (so `cdf(sample(u)) = u`), and the mean cosine.

mod draine;
mod fournier_forand;
mod henyey_greenstein;
mod invert;
mod isotropic;
mod mie;
mod mixture;
mod rayleigh;
mod tabulated;
#[cfg(test)]
mod testing;

pub use draine::{DRAINE_ALPHA_MAX, Draine};
pub use fournier_forand::{FF_N_MAX, FF_N_MIN, FournierForand};
pub use henyey_greenstein::HenyeyGreenstein;
pub use isotropic::Isotropic;
pub use mie::{MIE_DIAMETER_MAX_UM, Mie, MieFit, mie_fit};
pub use mixture::{Mixture, TwoTermHg};
pub use rayleigh::Rayleigh;
pub use tabulated::Tabulated;

use crate::real::{Real, Vector};

/// A deflection angle θ ∈ [0, π] in cancellation-free form.
///
/// Invariants (up to rounding): `one_minus_cos = 1 − cos θ = 2 sin²(θ/2)`,
/// `one_plus_cos = 1 + cos θ = 2 cos²(θ/2)`, their sum is 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deflection<F> {
    /// θ in radians, in `[0, π]`.
    pub theta: F,
    /// `1 − cos θ`, accurate to the last bit near θ = 0.
    pub one_minus_cos: F,
    /// `1 + cos θ`, accurate to the last bit near θ = π.
    pub one_plus_cos: F,
}

impl<F: Real> Deflection<F> {
    /// From θ (clamped to `[0, π]`): `1 ∓ cos θ = 2 sin²(θ/2)`, `2 cos²(θ/2)`.
    #[inline]
    pub fn from_theta(theta: F) -> Self {
        let theta = theta.clamp_to(F::ZERO, F::PI);
        let (s, c) = (theta * F::HALF).sin_cos();
        Self {
            theta,
            one_minus_cos: F::TWO * s * s,
            one_plus_cos: F::TWO * c * c,
        }
    }

    /// From both versines, each computed without cancellation by the caller:
    /// `θ = 2 atan2(√(1 − cos θ), √(1 + cos θ))` (stable over all of `[0, π]`).
    #[inline]
    pub fn from_versines(one_minus_cos: F, one_plus_cos: F) -> Self {
        let omc = one_minus_cos.clamp_to(F::ZERO, F::TWO);
        let opc = one_plus_cos.clamp_to(F::ZERO, F::TWO);
        Self {
            theta: F::TWO * omc.sqrt().atan2(opc.sqrt()),
            one_minus_cos: omc,
            one_plus_cos: opc,
        }
    }

    /// From `1 − cos θ` alone (accurate for θ ≤ π/2; `1 + cos θ = 2 − (1 − cos θ)`).
    #[inline]
    pub fn from_one_minus_cos(one_minus_cos: F) -> Self {
        let omc = one_minus_cos.clamp_to(F::ZERO, F::TWO);
        Self::from_versines(omc, F::TWO - omc)
    }

    /// From cos θ (clamped to `[−1, 1]`); loses the digits MATH.md §4 warns
    /// about near θ = 0 and π, so use it only where cos θ is all there is.
    #[inline]
    pub fn from_cos(cos_theta: F) -> Self {
        let c = cos_theta.clamp_to(-F::ONE, F::ONE);
        Self::from_versines(F::ONE - c, F::ONE + c)
    }

    /// Between two *unit* propagation directions:
    /// `1 − ω1·ω2 = |ω1 − ω2|²/2`, `1 + ω1·ω2 = |ω1 + ω2|²/2`, exact where
    /// `1 − ω1·ω2` is not, and `θ = 2 atan2(|ω1 − ω2|, |ω1 + ω2|)`.
    #[inline]
    pub fn between<V: Vector<F>>(omega1: V, omega2: V) -> Self {
        let minus = (omega1 - omega2).length_squared();
        let plus = (omega1 + omega2).length_squared();
        // Renormalise so the pair sums to 2 even for slightly non-unit input.
        let k = F::TWO / (minus + plus);
        Self {
            theta: F::TWO * minus.sqrt().atan2(plus.sqrt()),
            one_minus_cos: minus * F::HALF * k,
            one_plus_cos: plus * F::HALF * k,
        }
    }

    /// cos θ, from whichever versine is smaller (so it is accurate near ±1 in
    /// the absolute sense).
    #[inline]
    pub fn cos(&self) -> F {
        if self.one_minus_cos <= F::ONE {
            F::ONE - self.one_minus_cos
        } else {
            self.one_plus_cos - F::ONE
        }
    }

    /// sin θ = √((1 − cos θ)(1 + cos θ)), accurate at both ends.
    #[inline]
    pub fn sin(&self) -> F {
        (self.one_minus_cos * self.one_plus_cos).sqrt()
    }

    /// Whether all three fields are finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.theta.is_finite() && self.one_minus_cos.is_finite() && self.one_plus_cos.is_finite()
    }
}

/// A phase function p(θ), normalised over the sphere, with exact sampling.
///
/// Every implementation keeps the trio of the core's sampling routines:
/// `sample` draws Θ with density `2π p(θ) sin θ` from one uniform number,
/// `pdf` is that density per solid angle, and `invert` maps a deflection back to
/// the uniform number. For an inverse-CDF sampler `invert = cdf`.
pub trait PhaseFunction<F: Real> {
    /// p(θ) per steradian, `∫ p dω = 1`.
    fn eval(&self, d: Deflection<F>) -> F;

    /// A deflection with solid-angle density `pdf`, from `u ∈ [0, 1)`.
    fn sample(&self, u: F) -> Deflection<F>;

    /// `P(Θ ≤ θ) = 2π ∫₀^θ p(θ') sin θ' dθ'`.
    fn cdf(&self, d: Deflection<F>) -> F;

    /// ⟨cos θ⟩, the mean cosine (the "g" of the function).
    fn mean_cosine(&self) -> F;

    /// The solid-angle density of [`sample`](Self::sample); equal to `eval` for
    /// every phase function of this crate (they sample exactly).
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        self.eval(d)
    }

    /// The `u` with `sample(u) = d`, where `sample` is invertible; `cdf(d)` for
    /// inverse-CDF samplers. Mixtures choose a lobe with `u` and return `None`.
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        Some(self.cdf(d))
    }

    /// The fraction scattered backwards, `B = P(Θ > π/2) = 1 − cdf(π/2)`.
    #[inline]
    fn backscatter_fraction(&self) -> F {
        F::ONE - self.cdf(Deflection::from_versines(F::ONE, F::ONE))
    }
}

impl<F: Real, P: PhaseFunction<F> + ?Sized> PhaseFunction<F> for &P {
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        (**self).eval(d)
    }
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        (**self).sample(u)
    }
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        (**self).cdf(d)
    }
    #[inline]
    fn mean_cosine(&self) -> F {
        (**self).mean_cosine()
    }
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        (**self).pdf(d)
    }
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        (**self).invert(d)
    }
}
