//! Distance sampling: exponential free flight along a ray from the receiver,
//! truncated to the medium segment.

use super::{Connection, Directions, Sample, Technique, Unit, Vertex, in_unit, saturate};
use crate::error::{Error, check_closed};
use crate::medium::Region;
use crate::phase::PhaseFunction;
use crate::real::{Real, Vector};

/// A direction ω from `x2` ([`Directions`]), then the free-flight distance
/// `t ∈ [t_a, t_b]` with density proportional to `σ e^{−σ (t − t_a)}`
/// (pbrt's trimmed exponential):
///
/// `t = t_a − ln(1 − u (1 − e^{−σL})) / σ`, `L = t_b − t_a`,
/// `pdf(t) = σ e^{−σ (t − t_a)} / (1 − e^{−σL})`,
///
/// evaluated with `ln_1p`/`exp_m1`. σ is the free-flight coefficient, usually
/// the medium's σt; σ = 0 gives uniform distances on bounded segments (and no
/// sample on unbounded ones). In the volume measure
/// `pdf(x1) = pdf_ω(ω) pdf(t) / t²`, so the weight is
/// `k/pdf = p(θ) / (d1² pdf_ω(ω) pdf(t))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distance<F: Real, P> {
    /// The end points and θmax.
    pub connection: Connection<F>,
    /// The phase function at `x1` (for the weight only).
    pub phase: P,
    /// How the ray direction is drawn.
    pub directions: Directions<F>,
    /// Where the medium is: the ray is sampled inside it.
    pub region: Region<F>,
    sigma: F,
}

impl<F: Real, P: PhaseFunction<F>> Distance<F, P> {
    /// Distance sampling with free-flight coefficient `sigma ≥ 0` (finite).
    pub fn new(
        connection: Connection<F>,
        phase: P,
        directions: Directions<F>,
        region: Region<F>,
        sigma: F,
    ) -> Result<Self, Error> {
        check_closed("sigma", sigma.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        Ok(Self::with_checked_sigma(
            connection, phase, directions, region, sigma,
        ))
    }

    /// [`Distance::new`] for a σ its caller has checked to be finite and
    /// ≥ 0 ([`crate::method::Setup::new`] checks σt once for every draw).
    #[inline]
    pub(crate) fn with_checked_sigma(
        connection: Connection<F>,
        phase: P,
        directions: Directions<F>,
        region: Region<F>,
        sigma: F,
    ) -> Self {
        Self {
            connection,
            phase,
            directions,
            region,
            sigma,
        }
    }

    /// The free-flight coefficient σ.
    pub fn sigma(&self) -> F {
        self.sigma
    }

    /// σ per the connection's unit, `σ L` (the optical thickness of one
    /// unit; `σ x` is the same number in either unit).
    #[inline]
    fn sigma_unit(&self) -> F {
        self.sigma * self.connection.axis.unit.length
    }
}

/// `1 − e^{−σ len}`, the probability mass of a segment (σ > 0), or `len`
/// itself for σ = 0 (then the density is `1/len`).
#[inline]
fn mass<F: Real>(sigma: F, length: F) -> F {
    if sigma > F::ZERO {
        -(-sigma * length).exp_m1()
    } else {
        length
    }
}

/// The density of the offset `x ≥ 0` from the segment start,
/// `σ e^{−σx} / mass`.
#[inline]
fn density<F: Real>(sigma: F, x: F, length: F) -> F {
    if sigma > F::ZERO {
        sigma * (-sigma * x).exp() / mass(sigma, length)
    } else {
        F::ONE / length
    }
}

impl<F: Real, P: PhaseFunction<F>> Distance<F, P> {
    /// `pdf_ω(ω) pdf(t) / t²` per `L³` at `x1 = x2 + to_x1` with `to_x1`
    /// in the connection's unit (`t = |to_x1|`), inside the medium segment,
    /// else 0 (not saturated).
    fn density_from_x2(&self, to_x1: F::Vec3) -> F {
        let t = to_x1.length();
        if !(t > F::ZERO && t.is_finite()) {
            return F::ZERO;
        }
        let omega = to_x1 * (F::ONE / t);
        let Some((ta, tb)) = self.region.segment(self.connection.axis.x2, omega) else {
            return F::ZERO;
        };
        let inverse = self.connection.axis.unit.inverse;
        let (ta, tb) = (ta * inverse, tb * inverse);
        let (length, sigma) = (tb - ta, self.sigma_unit());
        if !(t >= ta && t <= tb && mass(sigma, length).is_finite()) {
            return F::ZERO;
        }
        self.directions.pdf(omega) * density(sigma, t - ta, length) / (t * t)
    }
}

impl<F: Real, P: PhaseFunction<F>> Distance<F, P> {
    /// [`Technique::sample`] with the density per `L³` of the connection's
    /// unit (not saturated).
    fn sample_unit(&self, u: [F; 3]) -> Option<(Sample<F>, F)> {
        let axis = &self.connection.axis;
        let unit = &axis.unit;
        let omega = self.directions.sample([u[0], u[1]]);
        let pdf_omega = self.directions.pdf(omega);
        let (ta, tb) = self.region.segment(axis.x2, omega)?;
        let (ta, tb) = (ta * unit.inverse, tb * unit.inverse);
        let (length, sigma) = (tb - ta, self.sigma_unit());
        let mass = mass(sigma, length);
        if !(mass.is_finite() && pdf_omega > F::ZERO) {
            return None; // σ = 0 on an unbounded segment
        }
        let u2 = u[2].clamp_to(F::ZERO, F::ONE);
        let x = if sigma > F::ZERO {
            -(-u2 * mass).ln_1p() / sigma
        } else {
            u2 * length
        };
        let t = (ta + x).min(tb);
        let t_metres = t * unit.length;
        if !(t > F::ZERO && t_metres.is_finite()) {
            return None;
        }
        let x1 = axis.x2 + omega * t_metres;
        if !x1.is_finite() {
            return None; // beyond the largest number
        }
        let pdf_t = density(sigma, x, length);
        let (d, d1) = self.connection.deflection_along_unit(omega, t)?;
        let weight = if d.theta < self.connection.theta_max {
            saturate(self.phase.eval(d) / (d1 * d1 * pdf_omega * pdf_t) * unit.inverse)
        } else {
            F::ZERO
        };
        let density = pdf_omega * pdf_t / (t * t);
        let sample = Sample {
            x1,
            pdf: saturate(unit.density_from_unit(density)),
            weight,
        };
        Some((sample, density))
    }
}

impl<F: Real, P: PhaseFunction<F>> Technique<F> for Distance<F, P> {
    /// ω from `(u0, u1)`, `t = t_a − ln_1p(−u2 (1 − e^{−σL})) / σ`; each `u`
    /// clamped to [0, 1] (NaN to 0). Lengths in the connection's unit, σ per
    /// unit (docs/math.md §15).
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        self.sample_unit(u).map(|(s, _)| s)
    }

    /// [`sample`](Technique::sample) with `x1 − x2 = t ω` and
    /// `x1 − x0 = (x2 − x0) + t ω` as placed.
    fn sample_vertex(&self, u: [F; 3], _: &Connection<F>) -> Option<(Sample<F>, Vertex<F>)> {
        let (s, _) = self.sample_unit(u)?;
        let axis = &self.connection.axis;
        let from_x2 = s.x1 - axis.x2; // t ω, exact up to one rounding of x1
        let from_x0 = (axis.x2 - axis.x0) + from_x2;
        let vertex = Vertex {
            x1: s.x1,
            from_x0,
            from_x2,
        };
        Some((s, vertex))
    }

    /// `pdf_ω(ω) pdf(t) / t²` inside the medium segment, else 0.
    fn pdf(&self, x1: F::Vec3) -> F {
        let axis = &self.connection.axis;
        let density = self.density_from_x2(axis.from_x2_unit(x1));
        saturate(axis.unit.density_from_unit(density))
    }

    /// [`pdf`](Technique::pdf) with `t ω = v.from_x2`.
    fn pdf_vertex(&self, v: &Vertex<F>) -> F {
        let unit = &self.connection.axis.unit;
        saturate(unit.density_from_unit(self.density_from_x2(v.from_x2 * unit.inverse)))
    }

    /// The density per `L³` of `unit`, computed in the connection's own
    /// unit and converted by the power of two between them.
    fn pdf_vertex_unit(&self, v: &Vertex<F>, unit: &Unit<F>) -> F {
        let own = &self.connection.axis.unit;
        in_unit(self.density_from_x2(v.from_x2 * own.inverse), own, unit)
    }

    /// `(u0, u1)` from the direction, `u2 = (1 − e^{−σ(t − t_a)}) / (1 − e^{−σL})`.
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        let axis = &self.connection.axis;
        let to_x1 = axis.from_x2_unit(x1);
        let t = to_x1.length();
        if !(t > F::ZERO && t.is_finite()) {
            return None;
        }
        let omega = to_x1 * (F::ONE / t);
        let [u0, u1] = self.directions.invert(omega)?;
        let (ta, tb) = self.region.segment(axis.x2, omega)?;
        let (ta, tb) = (ta * axis.unit.inverse, tb * axis.unit.inverse);
        let (x, length, sigma) = (t - ta, tb - ta, self.sigma_unit());
        let u2 = if sigma > F::ZERO {
            -(-sigma * x).exp_m1() / mass(sigma, length)
        } else {
            x / length
        };
        u2.is_finite()
            .then_some([u0, u1, u2.clamp_to(F::ZERO, F::ONE)])
    }
}
