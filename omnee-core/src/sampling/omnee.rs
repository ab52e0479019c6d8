//! Once-more scattered NEE: the deflection first, then the circumcircle arc
//! (docs/math.md §3).

use super::{Connection, Sample, Technique, Vertex, saturate};
use crate::circumcircle::Triangle;
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, Vector, sinc_with_sin};

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
///
/// A phase function that draws θ from a density `q` other than its own `p`
/// (a [`TableSampled`](crate::phase::TableSampled) one) has `q` in place of
/// `p` in the pdf and the ratio in the weight,
/// `k / pdf = (p(θ)/q(θ)) θ / (s sin θ)` ([`PhaseFunction::sample_ratio`]).
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
        self.sample_vertex_deflection(u).map(|(s, _, d)| (s, d))
    }

    /// [`sample_deflection`](Self::sample_deflection) with the vertex's
    /// offsets as placed, `x1 − x0 = d1 (cos α e + sin α ρ)` and
    /// `x1 − x2 = d2 (sin β ρ − cos β e)` (ρ the radial direction at φ), each
    /// from its own end of the triangle, so both keep their digits next to
    /// that end ([`Vertex`]).
    ///
    /// Always inlined (into [`crate::mis::OmneeMis`] too) but on wasm32,
    /// where the browser demo's module is 850 B smaller with the plain hint.
    #[cfg_attr(not(target_arch = "wasm32"), inline(always))]
    #[cfg_attr(target_arch = "wasm32", inline)]
    pub fn sample_vertex_deflection(
        &self,
        u: [F; 3],
    ) -> Option<(Sample<F>, Vertex<F>, Deflection<F>)> {
        let axis = &self.connection.axis;
        let (d, phase_pdf, ratio) = self.phase.sample_ratio(u[0]);
        if !(d.theta < self.connection.theta_max) {
            return None;
        }
        let (triangle, sin_beta, cos_beta) = Triangle::solve_with_beta(axis.s, d, u[1])?;
        if !(triangle.d1 > F::ZERO && triangle.d2 > F::ZERO) {
            return None; // x1 on an end point, where the integrand is singular
        }
        let (sin_phi, cos_phi) = u[2].sin_cos_turn();
        let radial = axis.b1 * cos_phi + axis.b2 * sin_phi;
        let from_x0 = axis.e * (triangle.d1 * triangle.cos_alpha)
            + radial * (triangle.d1 * triangle.sin_alpha);
        let x1 = axis.x0 + from_x0;
        if !x1.is_finite() {
            return None;
        }
        let from_x2 = radial * (triangle.d2 * sin_beta) - axis.e * (triangle.d2 * cos_beta);
        let sample = Sample {
            x1,
            pdf: self.density(phase_pdf, triangle.sinc_theta, triangle.d1, triangle.d2),
            weight: saturate(ratio / (axis.s * triangle.sinc_theta)),
        };
        let vertex = Vertex {
            x1,
            from_x0,
            from_x2,
        };
        Some((sample, vertex, d))
    }

    /// [`Technique::pdf`] from a deflection and the distances to the end
    /// points: `p(θ) sinc θ · s / (d1² d2²)` for θ < θmax, else 0.
    #[inline]
    fn density_at(&self, found: Option<(Deflection<F>, F, F)>) -> F {
        match found {
            Some((d, d1, d2)) if d.theta < self.connection.theta_max => {
                self.density(self.phase.pdf(d), sinc_with_sin(d.theta, d.sin()), d1, d2)
            }
            _ => F::ZERO,
        }
    }
}

impl<F: Real, P: PhaseFunction<F>> Technique<F> for Omnee<F, P> {
    /// `θ = Θ(u0)` from the phase function, `β/θ = u1`, `φ = 2π u2`;
    /// weight `(p/q) / (s sinc θ)` (`p/q = 1` for exact phase samplers).
    #[inline]
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        self.sample_deflection(u).map(|(sample, _)| sample)
    }

    /// `p(θ) sinc θ · s / (d1² d2²)` with θ between `ω1` and `ω2`
    /// ([`Connection::deflection`]); 0 for θ ≥ θmax and at the end points.
    #[inline]
    fn pdf(&self, x1: F::Vec3) -> F {
        self.density_at(self.connection.deflection(x1))
    }

    /// The vertex as placed ([`Self::sample_vertex_deflection`]).
    #[inline]
    fn sample_vertex(&self, u: [F; 3], _: &Connection<F>) -> Option<(Sample<F>, Vertex<F>)> {
        self.sample_vertex_deflection(u).map(|(s, v, _)| (s, v))
    }

    /// [`pdf`](Technique::pdf) with θ, `d1` and `d2` from the vertex's
    /// offsets ([`Connection::deflection_at`]).
    #[inline]
    fn pdf_vertex(&self, v: &Vertex<F>) -> F {
        self.density_at(self.connection.deflection_at(v))
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
