//! The lobe technique: a ray from `x0` drawn from its lobe, then the
//! deflection at `x1` from `p1` restricted to `[α, θmax)` (docs/math.md §12).

use super::{Lobe, Restricted};
use crate::circumcircle::Triangle;
use crate::phase::Deflection;
use crate::real::{Real, Vector};
use crate::sampling::{Connection, Sample, Technique, Unit, Vertex, in_unit, saturate};

/// Sampling `x1` through the lobe at `x0`.
///
/// 1. A unit direction ω from the lobe, density `pdf_ω(ω)`; α is its angle
///    with the axis `e = (x2 − x0)/s`.
/// 2. Along the ray `x0 + t ω` the deflection at `x1` is θ = α + β, β the
///    angle at `x2`, which grows from 0 to π − α as t goes from 0 to ∞, with
///    `dθ/dt = dβ/dt = s sin α / d2²` (the ray passes `x2` at the distance
///    `s sin α`). So θ is drawn from `p1` restricted to `[α, θmax)`
///    ([`Restricted`], density `2π p1(θ) sin θ / M`, `M = P1(θmax) − P1(α)`)
///    and `t = d1 = s sin β / sin θ` (law of sines).
///
/// Its density in the volume measure and the estimator weight are
///
/// `pdf(x1) = pdf_ω(ω) · 2π p1(θ) sin θ · s sin α / (M d1² d2²)`,
///
/// `k / pdf = (eval(ω)/pdf_ω(ω)) · M / (2π s sin α sin θ)`,
///
/// so `p0 · p1` and every `1/d²` cancel; what is left grows where the ray
/// passes close to `x2` (sin α → 0) and where θ → π, the regions OMNEE
/// covers. The weight is computed in closed form, never as `k/pdf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeRay<F: Real, L, P> {
    /// The end points and θmax.
    pub connection: Connection<F>,
    /// The lobe at `x0`.
    pub lobe: L,
    /// The phase function at `x1`.
    pub phase: P,
    /// θmax as a deflection.
    theta_max: Deflection<F>,
}

impl<F: Real, L: Lobe<F>, P: Restricted<F>> LobeRay<F, L, P> {
    /// The lobe technique for `connection`, `lobe` at `x0` and `phase` at `x1`.
    pub fn new(connection: Connection<F>, lobe: L, phase: P) -> Self {
        Self {
            connection,
            lobe,
            phase,
            // θmax = π with versines (2, 0) exactly: no mass above it to evaluate.
            theta_max: if connection.theta_max >= F::PI {
                Deflection::from_versines(F::TWO, F::ZERO)
            } else {
                Deflection::from_theta(connection.theta_max)
            },
        }
    }

    /// α between the axis and `x1 − x0 = a` (length `d1`), both in the
    /// connection's unit.
    #[inline]
    fn alpha(&self, a: F::Vec3, d1: F) -> Deflection<F> {
        let axis = &self.connection.axis;
        let e_unit = (axis.x2 - axis.x0) * axis.unit.inverse;
        Deflection::between_segments(e_unit, axis.s_unit, a, d1)
    }

    /// `pdf_ω · 2π p1(θ) sin θ · s sin α / (M d1² d2²)` per `L³`, with
    /// `s`, `d1`, `d2` in the connection's unit (docs/math.md §15); not
    /// saturated.
    #[inline]
    fn density_unit(
        &self,
        pdf_omega: F,
        theta: Deflection<F>,
        alpha: Deflection<F>,
        mass: F,
        d1: F,
        d2: F,
    ) -> F {
        let r = F::ONE / (d1 * d2);
        let angular = F::TAU * self.phase.pdf(theta) * theta.sin() / mass;
        pdf_omega * angular * (self.connection.axis.s_unit * alpha.sin()) * r * r
    }

    /// The density per `L³` of the connection's unit at `x1` (not
    /// saturated): `pdf_ω · 2π p1(θ) sin θ · s sin α / (M d1² d2²)`, 0 for
    /// θ ≥ θmax, `M = 0` and at the end points.
    fn pdf_own_unit(&self, x1: F::Vec3) -> F {
        let Some((theta, d1, d2)) = self.connection.deflection_unit(x1) else {
            return F::ZERO;
        };
        if !(theta.theta < self.connection.theta_max) {
            return F::ZERO;
        }
        let a = self.connection.axis.from_x0_unit(x1);
        let alpha = self.alpha(a, d1);
        let mass = self.phase.mass_between(alpha, self.theta_max);
        if !(mass > F::ZERO) {
            return F::ZERO;
        }
        let pdf_omega = self.lobe.pdf(a * (F::ONE / d1));
        self.density_unit(pdf_omega, theta, alpha, mass, d1, d2)
    }
}

/// β = θ − α, for α > π/2 as `(π − α) − (π − θ)` with each supplement
/// `π − x = 2 atan2(√(1 + cos x), √(1 − cos x))` from the versines: near π
/// θ − α would lose the absolute rounding of π (2.4e-7 in f32) on a β
/// that may be 1e-4.
#[inline]
fn beta<F: Real>(alpha: Deflection<F>, theta: Deflection<F>) -> F {
    let beta = if alpha.one_plus_cos < F::ONE {
        let supplement =
            |d: Deflection<F>| F::TWO * d.one_plus_cos.sqrt().atan2(d.one_minus_cos.sqrt());
        supplement(alpha) - supplement(theta)
    } else {
        theta.theta - alpha.theta
    };
    beta.max(F::ZERO)
}

impl<F: Real, L: Lobe<F>, P: Restricted<F>> LobeRay<F, L, P> {
    /// [`Technique::sample`] with its density per `L³` of the connection's
    /// unit (not saturated).
    fn sample_unit(&self, u: [F; 3]) -> Option<(Sample<F>, F)> {
        let axis = &self.connection.axis;
        let dir = self.lobe.sample([u[0], u[1]])?;
        let alpha = Deflection::between(axis.e, dir.omega);
        if !(alpha.one_minus_cos > F::ZERO && alpha.one_plus_cos > F::ZERO) {
            return None;
        }
        let (theta, mass) = self.phase.sample_between(alpha, self.theta_max, u[2])?;
        if !(theta.theta < self.connection.theta_max) {
            return None;
        }
        let beta = beta(alpha, theta);
        let ratio = if theta.theta > F::ZERO {
            (beta / theta.theta).min(F::ONE)
        } else {
            F::ZERO
        };
        // The triangle in the connection's unit, d1 then in metres.
        let triangle = Triangle::solve(axis.s_unit, theta, ratio)?;
        let (d1, d2) = (triangle.d1, triangle.d2);
        if !(d1 > F::ZERO && d2 > F::ZERO) {
            return None;
        }
        let x1 = axis.x0 + dir.omega * (d1 * axis.unit.length);
        if !x1.is_finite() {
            return None;
        }
        let sines = F::TAU * axis.s_unit * alpha.sin() * theta.sin();
        let density = self.density_unit(dir.pdf, theta, alpha, mass, d1, d2);
        let sample = Sample {
            x1,
            pdf: saturate(axis.unit.density_from_unit(density)),
            weight: saturate(dir.value / dir.pdf * mass / sines * axis.unit.inverse),
        };
        Some((sample, density))
    }
}

impl<F: Real, L: Lobe<F>, P: Restricted<F>> LobeRay<F, L, P> {
    /// The sample with its vertex and the density per `L³` of `unit` it
    /// was drawn with (for [`super::LobeMis`]).
    pub(crate) fn sample_vertex_unit(
        &self,
        u: [F; 3],
        unit: &Unit<F>,
    ) -> Option<(Sample<F>, Vertex<F>, F)> {
        let (s, density) = self.sample_unit(u)?;
        let own = &self.connection.axis.unit;
        Some((
            s,
            Vertex::at(&self.connection, s.x1),
            in_unit(density, own, unit),
        ))
    }
}

impl<F: Real, L: Lobe<F>, P: Restricted<F>> Technique<F> for LobeRay<F, L, P> {
    /// ω from `(u0, u1)` by the lobe, θ from `u2` by `p1` restricted to
    /// `[α, θmax)`, `β = θ − α`, `x1 = x0 + d1 ω` with `d1` from
    /// [`Triangle::solve`] in the connection's unit; weight
    /// `(eval/pdf_ω) M / (2π s sin α sin θ)`. `None` for a ray along the
    /// axis (sin α = 0), an empty restriction (`M = 0`) or `x1` on an end
    /// point.
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        self.sample_unit(u).map(|(s, _)| s)
    }

    /// `pdf_ω(ω) · 2π p1(θ) sin θ · s sin α / (M d1² d2²)` with ω, α from
    /// `x1 − x0` and θ between `ω1` and `ω2` ([`Connection::deflection`]);
    /// 0 for θ ≥ θmax, `M = 0` and at the end points.
    fn pdf(&self, x1: F::Vec3) -> F {
        saturate(
            self.connection
                .axis
                .unit
                .density_from_unit(self.pdf_own_unit(x1)),
        )
    }

    /// The density per `L³` of `unit` at the vertex's point, computed in
    /// the connection's own unit.
    fn pdf_vertex_unit(&self, v: &Vertex<F>, unit: &Unit<F>) -> F {
        in_unit(self.pdf_own_unit(v.x1), &self.connection.axis.unit, unit)
    }

    /// The lobe's `(u0, u1)` for ω and `u2 = (P1(θ) − P1(α))/M`; `None`
    /// where the lobe or the restricted phase function is not invertible.
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        let (theta, d1, _) = self.connection.deflection_unit(x1)?;
        if !(theta.theta < self.connection.theta_max) {
            return None;
        }
        let a = self.connection.axis.from_x0_unit(x1);
        let [u0, u1] = self.lobe.invert(a * (F::ONE / d1))?;
        let u2 = self
            .phase
            .invert_between(self.alpha(a, d1), self.theta_max, theta)?;
        Some([u0, u1, u2])
    }
}
