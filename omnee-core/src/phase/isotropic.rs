//! The isotropic phase function, p = 1/(4π).

use super::{Deflection, PhaseFunction};
use crate::real::Real;

/// Isotropic scattering: `p(θ) = 1/(4π)`, `cos θ` uniform on `[−1, 1]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Isotropic;

impl<F: Real> PhaseFunction<F> for Isotropic {
    /// `p = 1/(4π)`.
    #[inline]
    fn eval(&self, _d: Deflection<F>) -> F {
        F::FRAC_1_4PI
    }

    /// `1 − cos θ = 2u`, `1 + cos θ = 2(1 − u)`.
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        Deflection::from_versines(F::TWO * u, F::TWO * (F::ONE - u))
    }

    /// `P(Θ ≤ θ) = (1 − cos θ)/2`.
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        d.one_minus_cos * F::HALF
    }

    /// `⟨cos θ⟩ = 0`.
    #[inline]
    fn mean_cosine(&self) -> F {
        F::ZERO
    }
}
