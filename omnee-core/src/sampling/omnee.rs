//! Once-more scattered NEE: the deflection first, then the circumcircle arc
//! (docs/math.md §3).

use super::{Connection, Sample, Technique, saturate};
use crate::circumcircle::Triangle;
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, sinc_with_sin};

/// OMNEE sampling of `x1` for a [`Connection`].
///
/// 1. θ from the phase function in solid angle (density `2π p(θ) sin θ`),
///    no sample if θ ≥ θmax;
/// 2. `β = u2 θ` (density `1/θ`); 3. `φ = 2π u3`.
///
/// Its density in the volume measure and the estimator weight are
///
/// `pdf(x1) = p(θ) (sin θ / θ) s / (d1² d2²)`,  `k / pdf = θ / (s sin θ)`,
///
/// so every geometric factor cancels and the weight is bounded by
/// `π/(2s)` for θmax = π/2. The weight is computed in closed form, never by
/// dividing by the (near the end points divergent) pdf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Omnee<F: Real, P> {
    /// The end points and θmax.
    pub connection: Connection<F>,
    /// The phase function at `x1`.
    pub phase: P,
}

impl<F: Real, P: PhaseFunction<F>> Omnee<F, P> {
    /// OMNEE for `connection` with `phase` at `x1`.
    pub fn new(connection: Connection<F>, phase: P) -> Self {
        Self { connection, phase }
    }

    /// `pdf = p(θ) sinc θ · s / (d1² d2²)` from `p(θ)`, evaluated in an order that neither
    /// overflows nor underflows for s from 1e-6 to 1e6 in f32.
    #[inline]
    fn density(&self, phase_pdf: F, sinc_theta: F, d1: F, d2: F) -> F {
        let r = F::ONE / (d1 * d2);
        saturate(phase_pdf * sinc_theta * self.connection.axis.s * r * r)
    }
}

impl<F: Real, P: PhaseFunction<F>> Omnee<F, P> {
    /// [`Technique::sample`] with the drawn deflection, for callers that
    /// decide by θ what to do with the sample ([`crate::mis::OmneeMis`]).
    #[inline]
    pub fn sample_deflection(&self, u: [F; 3]) -> Option<(Sample<F>, Deflection<F>)> {
        let axis = &self.connection.axis;
        let (d, phase_pdf) = self.phase.sample_pdf(u[0]);
        if !(d.theta < self.connection.theta_max) {
            return None;
        }
        let triangle = Triangle::solve(axis.s, d, u[1])?;
        if !(triangle.d1 > F::ZERO && triangle.d2 > F::ZERO) {
            return None; // x1 on an end point, where the integrand is singular
        }
        let sample = Sample {
            x1: axis.place(&triangle, F::TAU * u[2])?,
            pdf: self.density(phase_pdf, triangle.sinc_theta, triangle.d1, triangle.d2),
            weight: saturate(F::ONE / (axis.s * triangle.sinc_theta)),
        };
        Some((sample, d))
    }
}

impl<F: Real, P: PhaseFunction<F>> Technique<F> for Omnee<F, P> {
    /// `θ = Θ(u0)` from the phase function, `β/θ = u1`, `φ = 2π u2`;
    /// weight `1 / (s sinc θ)`.
    #[inline]
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        self.sample_deflection(u).map(|(sample, _)| sample)
    }

    /// `p(θ) sinc θ · s / (d1² d2²)` with θ between `ω1` and `ω2`
    /// ([`Connection::deflection`]); 0 for θ ≥ θmax and at the end points.
    #[inline]
    fn pdf(&self, x1: F::Vec3) -> F {
        match self.connection.deflection(x1) {
            Some((d, d1, d2)) if d.theta < self.connection.theta_max => {
                self.density(self.phase.pdf(d), sinc_with_sin(d.theta, d.sin()), d1, d2)
            }
            _ => F::ZERO,
        }
    }
    /// `(cdf(θ), β/θ, φ/2π)`; `None` for θ ≥ θmax or a phase function whose
    /// sampler is not invertible (mixtures).
    #[inline]
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        let angles = self.connection.axis.angles(x1)?;
        if !(angles.theta < self.connection.theta_max) {
            return None;
        }
        let u0 = self.phase.invert(Deflection::from_theta(angles.theta))?;
        Some([u0, angles.beta_ratio, angles.phi / F::TAU])
    }
}
