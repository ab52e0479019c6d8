//! Once-more scattered NEE: the deflection first, then the circumcircle arc
//! (docs/math.md §3).

use super::{Connection, Sample, Technique, Unit, Vertex, in_unit, saturate};
use crate::circumcircle::Triangle;
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, Vector, sinc_with_sin};

/// A sample with its vertex, its deflection and its density per `L³` of
/// the connection's unit.
pub(crate) type UnitDraw<F> = (Sample<F>, Vertex<F>, Deflection<F>, F);

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

    /// `q = p(θ) sinc θ · s / (d1² d2²)` per `L³`, from `p(θ)` and `d1`,
    /// `d2` in the connection's [`Unit`](super::Unit) (`s/L` of order one):
    /// neither over- nor underflows where the volume density `q L⁻³` is in
    /// range, whatever `s` (docs/math.md §15).
    #[inline]
    fn density_unit(&self, phase_pdf: F, sinc_theta: F, d1: F, d2: F) -> F {
        let r = F::ONE / (d1 * d2);
        phase_pdf * sinc_theta * self.connection.axis.s_unit * r * r
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
    /// The triangle is solved in the connection's [`Unit`](super::Unit)
    /// and its sides scaled to metres by `L` (exact), the density computed
    /// per `L³` and scaled by `L⁻³`, the weight per `1/L` and scaled by
    /// `1/L` (docs/math.md §15): at ordinary scales bit for bit the
    /// computation in metres, at any other the same numbers up to the
    /// rounding of what leaves the range.
    #[inline(always)]
    pub fn sample_vertex_deflection(
        &self,
        u: [F; 3],
    ) -> Option<(Sample<F>, Vertex<F>, Deflection<F>)> {
        self.sample_unit(u).map(|(s, v, d, _)| (s, v, d))
    }

    /// [`sample_vertex_deflection`](Self::sample_vertex_deflection) with the
    /// density per `L³` of the connection's unit (what MIS compares).
    ///
    /// Always inlined (into [`crate::mis::OmneeMis`] too) but on wasm32,
    /// where the browser demo's module is 850 B smaller with the plain hint.
    #[cfg_attr(not(target_arch = "wasm32"), inline(always))]
    #[cfg_attr(target_arch = "wasm32", inline)]
    pub(crate) fn sample_unit(&self, u: [F; 3]) -> Option<UnitDraw<F>> {
        // One branch per draw, on the connection: at ordinary scales
        // (L = 1) the draw has no scaling in it at all (a scaling per value,
        // even a select, lengthens the chain the sample's latency is). The
        // browser demo's module keeps one copy: the scaling path, exact for
        // L = 1 too.
        #[cfg(not(target_arch = "wasm32"))]
        if self.connection.axis.unit.exponent == 0 {
            return self.draw::<false>(u);
        }
        self.draw::<true>(u)
    }

    /// The vertex as placed with the density per `L³` of `unit` it was
    /// drawn with (for [`crate::lobe::LobeMis`]).
    #[inline]
    pub(crate) fn sample_vertex_unit(
        &self,
        u: [F; 3],
        unit: &Unit<F>,
    ) -> Option<(Sample<F>, Vertex<F>, F)> {
        let (s, v, _, density) = self.sample_unit(u)?;
        Some((s, v, in_unit(density, &self.connection.axis.unit, unit)))
    }

    /// [`Self::sample_unit`] with the scalings by `L` (`SCALED`) or
    /// without them (`L = 1`).
    #[inline(always)]
    fn draw<const SCALED: bool>(&self, u: [F; 3]) -> Option<UnitDraw<F>> {
        let axis = &self.connection.axis;
        let (d, phase_pdf, ratio) = self.phase.sample_ratio(u[0]);
        if !(d.theta < self.connection.theta_max) {
            return None;
        }
        // The triangle in the connection's unit (s/L of order one), its
        // sides then in metres: exact scalings by L = 2ᵏ.
        let (unit, sin_beta, cos_beta) = Triangle::solve_with_beta(axis.s_unit, d, u[1])?;
        if !(unit.d1 > F::ZERO && unit.d2 > F::ZERO) {
            return None; // x1 on an end point, where the integrand is singular
        }
        let triangle = if SCALED {
            Triangle {
                d1: unit.d1 * axis.unit.length,
                d2: unit.d2 * axis.unit.length,
                ..unit
            }
        } else {
            unit
        };
        let (sin_phi, cos_phi) = u[2].sin_cos_turn();
        let radial = axis.b1 * cos_phi + axis.b2 * sin_phi;
        let from_x0 = axis.e * (triangle.d1 * triangle.cos_alpha)
            + radial * (triangle.d1 * triangle.sin_alpha);
        let x1 = axis.x0 + from_x0;
        if !x1.is_finite() {
            return None;
        }
        let from_x2 = radial * (triangle.d2 * sin_beta) - axis.e * (triangle.d2 * cos_beta);
        let density = self.density_unit(phase_pdf, unit.sinc_theta, unit.d1, unit.d2);
        let weight = ratio / (axis.s_unit * unit.sinc_theta);
        let sample = if SCALED {
            Sample {
                x1,
                pdf: saturate(density.scale_pow2(-3 * axis.unit.exponent)),
                weight: saturate(weight * axis.unit.inverse),
            }
        } else {
            Sample {
                x1,
                pdf: saturate(density),
                weight: saturate(weight),
            }
        };
        let vertex = Vertex {
            x1,
            from_x0,
            from_x2,
        };
        Some((sample, vertex, d, saturate(density)))
    }

    /// The density per `L³` from a deflection and the distances to the end
    /// points in the connection's unit: `p(θ) sinc θ · s / (d1² d2²)` for
    /// θ < θmax, else 0.
    #[inline]
    fn density_at(&self, found: Option<(Deflection<F>, F, F)>) -> F {
        match found {
            Some((d, d1, d2)) if d.theta < self.connection.theta_max => {
                self.density_unit(self.phase.pdf(d), sinc_with_sin(d.theta, d.sin()), d1, d2)
            }
            _ => F::ZERO,
        }
    }

    /// [`Technique::pdf_vertex_unit`] in OMNEE's own connection's unit
    /// (not saturated).
    #[inline]
    fn pdf_vertex_own_unit(&self, v: &Vertex<F>) -> F {
        self.density_at(self.connection.deflection_at_unit(v))
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
        let unit = &self.connection.axis.unit;
        saturate(unit.density_from_unit(self.density_at(self.connection.deflection_unit(x1))))
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
        let unit = &self.connection.axis.unit;
        saturate(unit.density_from_unit(self.pdf_vertex_own_unit(v)))
    }

    /// The density per `L³` of the given unit, computed in OMNEE's own
    /// connection's unit and converted by the power of two between them.
    #[inline]
    fn pdf_vertex_unit(&self, v: &Vertex<F>, unit: &Unit<F>) -> F {
        in_unit(
            self.pdf_vertex_own_unit(v),
            &self.connection.axis.unit,
            unit,
        )
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
