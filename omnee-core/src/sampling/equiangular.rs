//! Equiangular sampling (Kulla & Fajardo 2012) along a ray from the receiver:
//! the baseline OMNEE is measured against, and the distance sampler of
//! renderers that trace their own rays ([`EquiangularSegment`]).

use super::{
    Connection, Directions, Sample, Technique, Unit, Vertex, in_unit, saturate, unit_normal,
};
use crate::error::Error;
use crate::medium::Region;
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, Vector};

/// A direction ω from `x2` ([`Directions`]), then the distance `t` along
/// `x2 + t ω` inside the medium with density proportional to `1/d1²`, the
/// inverse squared distance to `x0` (Kulla & Fajardo 2012).
///
/// With `Δ = (x0 − x2)·ω` (foot of `x0` on the ray), `D = |(x0 − x2) × ω|`
/// (its distance from the ray), `v = t − Δ` and the segment `[t_a, t_b]`,
/// i.e. `v ∈ [a, b] = [t_a − Δ, t_b − Δ]`:
///
/// `pdf(t) = c / (D² + v²) = c / d1²`, with `c = D / (θ_b − θ_a)`,
/// `θ_b − θ_a = atan2(D (b − a), D² + ab)` (one stable atan2, no difference of
/// two angles near π/2), and `c = ab/(b − a)` in the limit D → 0.
///
/// In the volume measure `pdf(x1) = pdf_ω(ω) · c / (d1² d2²)`, and the weight
/// `k/pdf = p(θ) / (pdf_ω(ω) · c)` is free of every 1/d² factor.
///
/// The line's lengths (`Δ`, `D`, `a`, `b`, `t`, `v`, `c`) are all measured
/// in the connection's [`Unit`](super::Unit) `L`: `D² + ab` and `d1² d2²`
/// stay in range at any scale, and the density per `L³` and the weight per
/// `1/L` are scaled back once (docs/math.md §15).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equiangular<F: Real, P> {
    /// The end points and θmax.
    pub connection: Connection<F>,
    /// The phase function at `x1` (for the weight only).
    pub phase: P,
    /// How the ray direction is drawn.
    pub directions: Directions<F>,
    /// Where the medium is: the ray is sampled inside it.
    pub region: Region<F>,
}

/// The ray `x2 + t ω` restricted to the medium segment `[t_a, t_b]`, relative
/// to the foot of `x0`, every length in the connection's unit.
#[derive(Clone, Copy, Debug)]
struct Line<F: Real> {
    /// The segment `[t_a, t_b]` (t_b may be ∞).
    ta: F,
    tb: F,
    /// `(x0 − x2) × ω`, of length `D`.
    cross: F::Vec3,
    /// Distance of `x0` from the ray line.
    dist: F,
    /// Segment ends relative to the foot `Δ = (x0 − x2)·ω`: `a = t_a − Δ < b = t_b − Δ`.
    a: F,
    b: F,
    /// The angle `θ_b − θ_a` the segment subtends at `x0` (0 when `dist = 0`).
    subtended: F,
    /// The normalisation `c` of `pdf(t) = c / d1²`.
    c: F,
}

impl<F: Real> Line<F> {
    /// The line along ω from `x2`, with `to_light = x0 − x2`.
    fn new(to_light: F::Vec3, omega: F::Vec3, segment: (F, F)) -> Option<Self> {
        Self::from_foot(to_light.dot(omega), to_light.cross(omega), segment)
    }

    /// The line through a vertex `x1 = x2 + t ω` given with its offset
    /// `x1 − x0`: `x0 − x2 = t ω − (x1 − x0)`, so `Δ = t − (x1 − x0)·ω` and
    /// `(x0 − x2) × ω = ω × (x1 − x0)`, both from the small offset when the
    /// ray passes next to `x0` (where `(x0 − x2) × ω` would cancel).
    fn at_vertex(from_x0: F::Vec3, t: F, omega: F::Vec3, segment: (F, F)) -> Option<Self> {
        Self::from_foot(t - from_x0.dot(omega), omega.cross(from_x0), segment)
    }

    /// The line from `Δ = (x0 − x2)·ω` and `(x0 − x2) × ω`.
    fn from_foot(delta: F, cross: F::Vec3, (ta, tb): (F, F)) -> Option<Self> {
        let dist = cross.length();
        let (a, b) = (ta - delta, tb - delta);
        let subtended = if b.is_finite() {
            (dist * (b - a)).atan2(dist * dist + a * b)
        } else {
            dist.atan2(a)
        };
        let c = if dist > F::ZERO && subtended > F::ZERO {
            dist / subtended
        } else if a > F::ZERO || b < F::ZERO {
            // x0 on the ray's line outside the segment: density ∝ 1/v².
            if b.is_finite() { a * b / (b - a) } else { a }
        } else {
            return None; // the ray passes through x0: a δ-like density
        };
        (c > F::ZERO && c.is_finite()).then_some(Self {
            ta,
            tb,
            cross,
            dist,
            a,
            b,
            subtended,
            c,
        })
    }

    /// The distance `t` for `ξ` and the offset `v = t − Δ` from the foot of
    /// `x0`, `v = D tan(θ_a + ξ(θ_b − θ_a))`, each formed so that nothing
    /// cancels: `t` from the nearer end of the segment (a vertex next to the
    /// receiver keeps its digits) and `v` from the foot (a vertex next to the
    /// light keeps its distance to it). By the tangent addition formula, with
    /// `τ = tan(ξ(θ_b − θ_a))` and `τ' = tan((1 − ξ)(θ_b − θ_a))`:
    ///
    /// ξ ≤ ½: `t − t_a = τ (D² + a²) / (D − a τ)`, `v = D (a + D τ) / (D − a τ)`;
    /// ξ > ½: `t_b − t = τ' (D² + b²) / (D + b τ')`, `v = D (b − D τ') / (D + b τ')`
    /// (`v = D/τ'` if `t_b = ∞`);
    ///
    /// for D = 0, `v = ab / (b + (a − b) ξ)` and `t − t_a = a (b − a) ξ / (b + (a − b) ξ)`.
    fn distance(&self, xi: F) -> (F, F) {
        let (d, a, b) = (self.dist, self.a, self.b);
        let (t, v) = if d > F::ZERO && self.subtended > F::ZERO {
            if xi <= F::HALF {
                let tau = (xi * self.subtended).tan();
                let den = d - a * tau;
                (
                    self.ta + tau * (d * d + a * a) / den,
                    d * (a + d * tau) / den,
                )
            } else {
                let tau = ((F::ONE - xi) * self.subtended).tan();
                if b.is_finite() {
                    let den = d + b * tau;
                    (
                        self.tb - tau * (d * d + b * b) / den,
                        d * (b - d * tau) / den,
                    )
                } else {
                    let v = d / tau;
                    ((self.ta - a) + v, v)
                }
            }
        } else if b.is_finite() {
            let den = b + (a - b) * xi;
            (self.ta + a * (b - a) * xi / den, a * b / den)
        } else {
            let v = a / (F::ONE - xi);
            (self.ta + a * xi / (F::ONE - xi), v)
        };
        (t.clamp_to(self.ta, self.tb), v.clamp_to(a, b))
    }

    /// The inverse of [`distance`](Self::distance), with `t − t_a` formed
    /// directly: `ξ = atan2(D (t − t_a), D² + a v) / (θ_b − θ_a)`, or
    /// `ξ = b (t − t_a) / (v (b − a))` for D = 0.
    fn invert(&self, t: F) -> F {
        let (d, a, b) = (self.dist, self.a, self.b);
        let (from_a, v) = (t - self.ta, t - (self.ta - a));
        let xi = if d > F::ZERO && self.subtended > F::ZERO {
            (d * from_a).atan2(d * d + a * v) / self.subtended
        } else if b.is_finite() {
            b * from_a / (v * (b - a))
        } else {
            from_a / v
        };
        xi.clamp_to(F::ZERO, F::ONE)
    }
}

/// Equiangular sampling of the distance along a ray the caller traced: the
/// one-dimensional part of [`Equiangular`], for a renderer that draws the
/// direction ω itself (from a BSDF or a phase function) and finds the medium
/// segment `[t_a, t_b]` by intersecting its scene.
///
/// Along `x(t) = origin + t ω`, with `d1(t) = |x(t) − x0|`, the density is
///
/// `pdf(t) = c / d1(t)²`, `c = D / (θ_b − θ_a)` on `[t_a, t_b]`, else 0,
///
/// with `D` the distance of `x0` from the ray's line and `θ_b − θ_a` the
/// angle the segment subtends at `x0` (one `atan2`; `c = ab/(b − a)` for
/// `x0` on the line, [`Equiangular`]'s formulas). The caller's vertex then
/// has the volume density `pdf_ω(ω) pdf(t) / t²` about `origin`.
///
/// Lengths are computed in the power-of-two [`Unit`] of `|x0 − origin|`, so
/// scaling the whole problem by `2ᵏ` scales `t` by `2ᵏ` and the density by
/// `2⁻ᵏ` exactly, at any finite scale.
#[derive(Clone, Copy, Debug)]
pub struct EquiangularSegment<F: Real> {
    /// The unit in which `line` is measured.
    unit: Unit<F>,
    /// The ray's line relative to the foot of `x0`, in the unit.
    line: Line<F>,
}

/// A distance drawn along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceSample<F> {
    /// The distance `t` from the ray's origin (m).
    pub t: F,
    /// Its density per metre (finite: saturates at `F::MAX`).
    pub pdf: F,
}

impl<F: Real> EquiangularSegment<F> {
    /// The segment `[t_min, t_max]` of the ray `origin + t ω` (ω of any
    /// finite non-zero length; normalised here), sampled towards `x0`.
    /// `t_min` ∈ [0, `F::MAX`], `t_max` ∈ (`t_min`, ∞] (∞: the ray never
    /// leaves the medium). Fails on non-finite points, a zero direction, and
    /// where `x0` lies on the segment itself (the density would be a δ).
    pub fn new(
        x0: F::Vec3,
        origin: F::Vec3,
        direction: F::Vec3,
        t_min: F,
        t_max: F,
    ) -> Result<Self, Error> {
        if !x0.is_finite() {
            return Err(Error::not_finite("x0"));
        }
        if !origin.is_finite() {
            return Err(Error::not_finite("origin"));
        }
        let omega = unit_normal::<F>(direction, "direction")?;
        if !(t_min >= F::ZERO && t_min.is_finite()) {
            return Err(Error::OutOfRange {
                field: "t_min",
                value: t_min.to_f64(),
                allowed: "[0, max]",
            });
        }
        if !(t_max > t_min) {
            return Err(Error::OutOfRange {
                field: "t_max",
                value: t_max.to_f64(),
                allowed: "(t_min, inf]",
            });
        }
        let to_light = x0 - origin;
        let unit = Unit::of(to_light.length());
        let inverse = unit.inverse;
        let line = Line::new(
            to_light * inverse,
            omega,
            (t_min * inverse, t_max * inverse),
        )
        .ok_or(Error::Degenerate {
            field: "x0",
            reason: "lies on the ray inside the segment",
        })?;
        Ok(Self { unit, line })
    }

    /// `t = Δ + D tan(θ_a + u (θ_b − θ_a))`, formed without cancellation from
    /// the nearer end of the segment, and `pdf(t)`; `u` is clamped to
    /// [0, 1] (NaN to 0). `None` where `t` is not a finite number of metres
    /// (`u = 1` on an infinite segment).
    pub fn sample(&self, u: F) -> Option<DistanceSample<F>> {
        let (t, v) = self.line.distance(u.clamp_to(F::ZERO, F::ONE));
        let t = self.unit.to_metres(t);
        t.is_finite().then(|| DistanceSample {
            t,
            pdf: self.density(v),
        })
    }

    /// `pdf(t) = c / d1(t)²` per metre inside `[t_min, t_max]`, else 0.
    pub fn pdf(&self, t: F) -> F {
        let t = t * self.unit.inverse;
        if !(t >= self.line.ta && t <= self.line.tb) {
            return F::ZERO;
        }
        self.density(t - (self.line.ta - self.line.a))
    }

    /// The `u` that [`sample`](Self::sample) maps to `t`:
    /// `u = atan2(D (t − t_a), D² + a v) / (θ_b − θ_a)` (clamped to [0, 1]).
    pub fn invert(&self, t: F) -> F {
        self.line.invert(t * self.unit.inverse)
    }

    /// `c / (D² + v²)` in metres⁻¹ for the offset `v` from the foot of `x0`
    /// (in the unit).
    fn density(&self, v: F) -> F {
        let d = self.line.dist;
        saturate(self.line.c / (d * d + v * v) * self.unit.inverse)
    }
}

impl<F: Real, P: PhaseFunction<F>> Equiangular<F, P> {
    /// Equiangular sampling for `connection` with rays drawn by `directions`
    /// inside `region`.
    pub fn new(
        connection: Connection<F>,
        phase: P,
        directions: Directions<F>,
        region: Region<F>,
    ) -> Self {
        Self {
            connection,
            phase,
            directions,
            region,
        }
    }

    /// The sample of [`Technique::sample`] with the vertex's offsets and
    /// its density per `L³` (not saturated).
    fn sample_with_offsets(&self, u: [F; 3]) -> Option<(Sample<F>, Vertex<F>, F)> {
        let axis = &self.connection.axis;
        let unit = &axis.unit;
        let omega = self.directions.sample([u[0], u[1]]);
        let pdf_omega = self.directions.pdf(omega);
        let line = self.line(omega)?;
        let (t, v) = line.distance(u[2].clamp_to(F::ZERO, F::ONE));
        if !(t > F::ZERO && t.is_finite() && pdf_omega > F::ZERO) {
            return None;
        }
        let t_metres = t * unit.length;
        if !t_metres.is_finite() {
            return None;
        }
        let x1 = axis.x2 + omega * t_metres;
        if !x1.is_finite() {
            return None; // beyond the largest number
        }
        // x1 − x0 = v ω − (x0 − foot), the perpendicular x0 − foot being
        // ω × ((x0 − x2) × ω): no cancellation next to the light.
        let from_x0 = omega * v - omega.cross(line.cross);
        let d1 = from_x0.length();
        if !(d1 > F::ZERO && d1.is_finite()) {
            return None;
        }
        let d = Deflection::between_segments(from_x0, d1, -omega, F::ONE);
        let r = F::ONE / (d1 * t);
        let weight = if d.theta < self.connection.theta_max {
            saturate(self.phase.eval(d) / (pdf_omega * line.c) * unit.inverse)
        } else {
            F::ZERO
        };
        let density = pdf_omega * line.c * r * r;
        let sample = Sample {
            x1,
            pdf: saturate(unit.density_from_unit(density)),
            weight,
        };
        let vertex = Vertex {
            x1,
            from_x0: from_x0 * unit.length,
            from_x2: omega * t_metres,
        };
        Some((sample, vertex, density))
    }

    /// `pdf_ω(ω) · c / (d1² d2²)` per `L³` at `x1 = x2 + to_x1` with
    /// `d1 = |x1 − x0|` (both in the unit), inside the medium segment, else
    /// 0 (not saturated: ∞ where it overflows).
    fn density(&self, to_x1: F::Vec3, d1: F) -> F {
        let t = to_x1.length();
        if !(t > F::ZERO && d1 > F::ZERO && t.is_finite()) {
            return F::ZERO;
        }
        let omega = to_x1 * (F::ONE / t);
        let Some(line) = self.line(omega) else {
            return F::ZERO;
        };
        if !(t >= line.ta && t <= line.tb) {
            return F::ZERO;
        }
        let r = F::ONE / (d1 * t);
        self.directions.pdf(omega) * line.c * r * r
    }

    /// The line of the ray along ω, in the connection's unit.
    fn line(&self, omega: F::Vec3) -> Option<Line<F>> {
        let axis = &self.connection.axis;
        let inverse = axis.unit.inverse;
        let (ta, tb) = self.region.segment(axis.x2, omega)?;
        Line::new(
            (axis.x0 - axis.x2) * inverse,
            omega,
            (ta * inverse, tb * inverse),
        )
    }

    /// [`Technique::pdf_vertex_unit`] per `L³` of the connection's own
    /// unit (not saturated), with `t ω = v.from_x2`, `d1 = |v.from_x0|` and the ray's line
    /// from the offsets (`Line::at_vertex`), all divided by `L`.
    fn pdf_vertex_own_unit(&self, v: &Vertex<F>) -> F {
        let axis = &self.connection.axis;
        let inverse = axis.unit.inverse;
        let (from_x0, from_x2) = (v.from_x0 * inverse, v.from_x2 * inverse);
        let t = from_x2.length();
        let d1 = from_x0.length();
        if !(t > F::ZERO && d1 > F::ZERO && t.is_finite()) {
            return F::ZERO;
        }
        let omega = from_x2 * (F::ONE / t);
        let line = self
            .region
            .segment(axis.x2, omega)
            .and_then(|(ta, tb)| Line::at_vertex(from_x0, t, omega, (ta * inverse, tb * inverse)));
        let Some(line) = line else {
            return F::ZERO;
        };
        if !(t >= line.ta && t <= line.tb) {
            return F::ZERO;
        }
        let r = F::ONE / (d1 * t);
        self.directions.pdf(omega) * line.c * r * r
    }
}

impl<F: Real, P: PhaseFunction<F>> Technique<F> for Equiangular<F, P> {
    /// ω from `(u0, u1)`, then `t` and `v = t − Δ` from `u2` on the medium
    /// segment (tangent addition from the nearer end); `d1 = |v ω − (x0 − foot)|`, `d2 = t`.
    /// Each `u` is clamped to [0, 1] (NaN to 0).
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        self.sample_with_offsets(u).map(|(s, _, _)| s)
    }

    /// [`sample`](Technique::sample) with `x1 − x2 = t ω` and
    /// `x1 − x0 = v ω − (x0 − foot)` as computed.
    fn sample_vertex(&self, u: [F; 3], _: &Connection<F>) -> Option<(Sample<F>, Vertex<F>)> {
        self.sample_with_offsets(u).map(|(s, v, _)| (s, v))
    }

    /// `pdf_ω(ω) · c / (d1² d2²)` for `x1` inside the medium segment, else 0.
    fn pdf(&self, x1: F::Vec3) -> F {
        let axis = &self.connection.axis;
        let density = self.density(axis.from_x2_unit(x1), axis.from_x0_unit(x1).length());
        saturate(axis.unit.density_from_unit(density))
    }

    /// [`pdf`](Technique::pdf) with `t ω = v.from_x2`, `d1 = |v.from_x0|` and
    /// the ray's line from the offsets (`Line::at_vertex`).
    fn pdf_vertex(&self, v: &Vertex<F>) -> F {
        saturate(
            self.connection
                .axis
                .unit
                .density_from_unit(self.pdf_vertex_own_unit(v)),
        )
    }

    /// The density per `L³` of `unit`, computed in the connection's own
    /// unit and converted by the power of two between them.
    fn pdf_vertex_unit(&self, v: &Vertex<F>, unit: &Unit<F>) -> F {
        in_unit(
            self.pdf_vertex_own_unit(v),
            &self.connection.axis.unit,
            unit,
        )
    }

    /// `(u0, u1)` from the direction, `u2` from the equiangular angle.
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        let to_x1 = self.connection.axis.from_x2_unit(x1);
        let t = to_x1.length();
        if !(t > F::ZERO && t.is_finite()) {
            return None;
        }
        let omega = to_x1 * (F::ONE / t);
        let [u0, u1] = self.directions.invert(omega)?;
        let line = self.line(omega)?;
        Some([u0, u1, line.invert(t)])
    }
}
