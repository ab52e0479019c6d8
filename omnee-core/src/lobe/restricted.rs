//! A phase function restricted to an interval of deflections,
//! `lo ≤ Θ < hi`: what [`super::LobeRay`] draws the deflection at `x1` from
//! once the direction at `x0` has fixed `α = lo` (docs/math.md §12).

use crate::phase::{
    AnyPhase, Deflection, Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture,
    NoTable, PhaseFunction, Rayleigh, Tabulated, dispatch,
};
use crate::real::Real;

/// Sampling Θ conditioned on `lo ≤ Θ < hi`, with density
/// `2π p(θ) sin θ / M` on that interval, `M = P(hi) − P(lo)` its mass.
///
/// The provided methods are those of an inverse-CDF sampler
/// (`sample(P(lo) + u M)`); mixtures choose a lobe in proportion to its
/// weight times its own mass in the interval and sample that lobe
/// restricted, so that every phase function of [`crate::phase`] samples its
/// restriction exactly.
///
/// Not implemented for [`crate::phase::TableSampled`]: its sampler is the
/// table's `q`, not the inverse of its (the phase function's) cdf, and
/// [`super::LobeRay`]'s closed-form weight cancels `p1` against the density
/// it draws with (docs/math.md §11, §12).
pub trait Restricted<F: Real>: PhaseFunction<F> {
    /// `M = P(lo ≤ Θ < hi) = P(hi) − P(lo)`, at least 0.
    #[inline]
    fn mass_between(&self, lo: Deflection<F>, hi: Deflection<F>) -> F {
        (cdf_up_to(self, hi) - self.cdf(lo)).max(F::ZERO)
    }

    /// A deflection in `[lo, hi]` with density `2π p(θ) sin θ / M` from
    /// `u ∈ [0, 1)` (clamped, NaN to 0), and `M`; `None` where `M = 0`
    /// (in the precision at hand: no interval to sample).
    ///
    /// Inverse CDF: `θ = P⁻¹(P(lo) + u M)`, clamped into `[lo, hi]` against
    /// the rounding of `P⁻¹`.
    #[inline]
    fn sample_between(
        &self,
        lo: Deflection<F>,
        hi: Deflection<F>,
        u: F,
    ) -> Option<(Deflection<F>, F)> {
        let below = self.cdf(lo);
        let mass = (cdf_up_to(self, hi) - below).max(F::ZERO);
        if !(mass > F::ZERO) {
            return None;
        }
        let d = self.sample(below + u.clamp_to(F::ZERO, F::ONE) * mass);
        Some((clamp_between(d, lo, hi), mass))
    }

    /// The `u` with `sample_between(lo, hi, u) = d`:
    /// `(P(θ) − P(lo)) / M` for an inverse-CDF sampler; `None` for mixtures.
    #[inline]
    fn invert_between(&self, lo: Deflection<F>, hi: Deflection<F>, d: Deflection<F>) -> Option<F> {
        let u = self.invert(d)?;
        let below = self.cdf(lo);
        let mass = cdf_up_to(self, hi) - below;
        (mass > F::ZERO).then(|| ((u - below) / mass).clamp_to(F::ZERO, F::ONE))
    }
}

/// `P(hi)`: 1 without evaluating it when `hi` is π (the common θmax).
#[inline]
fn cdf_up_to<F: Real, P: PhaseFunction<F> + ?Sized>(p: &P, hi: Deflection<F>) -> F {
    if hi.one_plus_cos > F::ZERO {
        p.cdf(hi)
    } else {
        F::ONE
    }
}

/// `d`, or the nearer end of `[lo, hi]` if rounding put it outside.
#[inline]
fn clamp_between<F: Real>(d: Deflection<F>, lo: Deflection<F>, hi: Deflection<F>) -> Deflection<F> {
    if d.theta < lo.theta {
        lo
    } else if d.theta > hi.theta {
        hi
    } else {
        d
    }
}

impl<F: Real> Restricted<F> for Isotropic {}
impl<F: Real> Restricted<F> for HenyeyGreenstein<F> {}
impl<F: Real> Restricted<F> for Rayleigh {}
impl<F: Real> Restricted<F> for Draine<F> {}
impl<F: Real> Restricted<F> for FournierForand<F> {}
impl<F: Real> Restricted<F> for Tabulated<'_, F> {}

impl<F: Real, A: Restricted<F>, B: Restricted<F>> Restricted<F> for Mixture<A, B> {
    /// `w M_A + (1 − w) M_B`.
    #[inline]
    fn mass_between(&self, lo: Deflection<F>, hi: Deflection<F>) -> F {
        let w = F::from_f64(self.weight());
        w * self.first().mass_between(lo, hi)
            + F::from_f64(1.0 - self.weight()) * self.second().mass_between(lo, hi)
    }

    /// Lobe A with probability `c = w M_A / M` (`u/c`), else lobe B
    /// (`(u − c)/(1 − c)`), each restricted to `[lo, hi)`: the density is
    /// `(w 2π p_A sin θ + (1 − w) 2π p_B sin θ) / M`, the mixture's.
    #[inline]
    fn sample_between(
        &self,
        lo: Deflection<F>,
        hi: Deflection<F>,
        u: F,
    ) -> Option<(Deflection<F>, F)> {
        let w = F::from_f64(self.weight());
        let a = w * self.first().mass_between(lo, hi);
        let b = F::from_f64(1.0 - self.weight()) * self.second().mass_between(lo, hi);
        let mass = a + b;
        if !(mass > F::ZERO) {
            return None;
        }
        let c = a / mass;
        let u = u.clamp_to(F::ZERO, F::ONE);
        let d = if u < c {
            let v = (u / c).min(F::ONE_MINUS_EPSILON);
            self.first().sample_between(lo, hi, v)?.0
        } else {
            let v = ((u - c) / (F::ONE - c)).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON);
            self.second().sample_between(lo, hi, v)?.0
        };
        Some((d, mass))
    }

    /// `None`: the lobe choice consumes part of `u`.
    #[inline]
    fn invert_between(&self, _: Deflection<F>, _: Deflection<F>, _: Deflection<F>) -> Option<F> {
        None
    }
}

impl<F: Real> Restricted<F> for Mie<F> {
    /// The blend's ([`Mie::mixture`]).
    #[inline]
    fn mass_between(&self, lo: Deflection<F>, hi: Deflection<F>) -> F {
        self.mixture().mass_between(lo, hi)
    }
    /// The blend's ([`Mie::mixture`]).
    #[inline]
    fn sample_between(
        &self,
        lo: Deflection<F>,
        hi: Deflection<F>,
        u: F,
    ) -> Option<(Deflection<F>, F)> {
        self.mixture().sample_between(lo, hi, u)
    }
    /// `None` (lobe selection).
    #[inline]
    fn invert_between(&self, _: Deflection<F>, _: Deflection<F>, _: Deflection<F>) -> Option<F> {
        None
    }
}

/// Never called: there is no table.
impl<F: Real> Restricted<F> for NoTable {}

impl<F: Real, T: Restricted<F>> Restricted<F> for AnyPhase<F, T> {
    /// The variant's.
    #[inline]
    fn mass_between(&self, lo: Deflection<F>, hi: Deflection<F>) -> F {
        dispatch!(self, p => p.mass_between(lo, hi))
    }
    /// The variant's.
    #[inline]
    fn sample_between(
        &self,
        lo: Deflection<F>,
        hi: Deflection<F>,
        u: F,
    ) -> Option<(Deflection<F>, F)> {
        dispatch!(self, p => p.sample_between(lo, hi, u))
    }
    /// The variant's.
    #[inline]
    fn invert_between(&self, lo: Deflection<F>, hi: Deflection<F>, d: Deflection<F>) -> Option<F> {
        dispatch!(self, p => p.invert_between(lo, hi, d))
    }
}

impl<F: Real, P: Restricted<F> + ?Sized> Restricted<F> for &P {
    #[inline]
    fn mass_between(&self, lo: Deflection<F>, hi: Deflection<F>) -> F {
        (**self).mass_between(lo, hi)
    }
    #[inline]
    fn sample_between(
        &self,
        lo: Deflection<F>,
        hi: Deflection<F>,
        u: F,
    ) -> Option<(Deflection<F>, F)> {
        (**self).sample_between(lo, hi, u)
    }
    #[inline]
    fn invert_between(&self, lo: Deflection<F>, hi: Deflection<F>, d: Deflection<F>) -> Option<F> {
        (**self).invert_between(lo, hi, d)
    }
}
