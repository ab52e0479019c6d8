//! Techniques that place the scattering vertex `x1` of a once-more scattered
//! connection `x0 → x1 → x2` (docs/math.md §1).
//!
//! Every technique estimates the same integral of the *kernel*
//!
//! `k(x1) = p(cos θ) / (d1² d2²)` for θ < θmax, else 0,
//!
//! times the factors it does not sample, `f_c` (emission and cosine at `x0`,
//! transmittance, σs, the receiver's cosine and importance at `x2`), which the
//! caller multiplies in. Each comes as a trio, as in pbrt-v4's sampling code:
//! [`Technique::sample`] maps three uniform numbers to `x1`, its volume density
//! and the estimator weight `k(x1)/pdf(x1)` in the most stable closed form;
//! [`Technique::pdf`] evaluates that density anywhere; [`Technique::invert`]
//! maps `x1` back to the uniform numbers where the math allows.
//!
//! - [`Omnee`]: angle first, then the circumcircle arc (the new technique);
//! - [`Equiangular`]: a ray from `x2`, distance equiangular towards `x0`
//!   (Kulla & Fajardo 2012);
//! - [`Distance`]: a ray from `x2`, exponential free-flight distance;
//! - [`Omnee::sample_batch`]: OMNEE with Henyey–Greenstein for a batch of
//!   uniform triples in structure-of-arrays form, vectorised.
//!
//! All densities are in the volume measure (m⁻³), so [`crate::mis`] combines
//! any set of them. A [`Draw`] is one estimate's vertices (one, or two for
//! [`crate::mis::OmneeMis`]) with the uniform numbers they took;
//! [`crate::method`] makes draws for a technique chosen by name.

mod batch;
mod connections;
mod directions;
mod distance;
mod draw;
mod equiangular;
mod omnee;

pub use batch::{Uniforms, Vertices};
pub use connections::{
    CHUNK, Connections, Deflections, PhaseBatch, Points, PointsMut, SampleArrays,
};
pub use directions::{Directions, unit_normal};
pub use distance::Distance;
pub use draw::Draw;
pub use equiangular::{DistanceSample, Equiangular, EquiangularSegment};
pub use omnee::Omnee;

pub use crate::circumcircle::Unit;

use crate::circumcircle::Axis;
use crate::error::{Error, check_closed};
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, Vector};

/// A sampled scattering vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample<F: Real> {
    /// The vertex `x1`.
    pub x1: F::Vec3,
    /// Its density in the volume measure (m⁻³), finite (saturates at `F::MAX`).
    pub pdf: F,
    /// The estimator `k(x1) / pdf(x1)` without `f_c` (m⁻¹), finite and ≥ 0.
    pub weight: F,
}

/// A technique for placing `x1`: the sample / pdf / invert trio.
///
/// The trait is object safe, so [`crate::mis`] takes `&dyn Technique<F>`.
pub trait Technique<F: Real> {
    /// `x1` from three uniform numbers in `[0, 1)`; `None` when the numbers map
    /// to no point that contributes (outside θmax, outside the medium, at an
    /// end point).
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>>;

    /// The volume density of [`sample`](Self::sample) at `x1` (0 where it
    /// never samples; finite, saturating at `F::MAX`).
    fn pdf(&self, x1: F::Vec3) -> F;

    /// The uniform numbers that [`sample`](Self::sample) maps to `x1`, where
    /// the map is invertible.
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]>;

    /// [`sample`](Self::sample) with the vertex's offsets from the end points
    /// of `connection`, the connection the technique samples for. The default
    /// subtracts the end points from the rounded `x1`; a technique that
    /// places `x1` as an end point plus an offset returns that offset, which
    /// keeps its digits next to the end point (OMNEE, equiangular, distance).
    #[inline]
    fn sample_vertex(
        &self,
        u: [F; 3],
        connection: &Connection<F>,
    ) -> Option<(Sample<F>, Vertex<F>)> {
        let s = self.sample(u)?;
        Some((s, Vertex::at(connection, s.x1)))
    }

    /// [`pdf`](Self::pdf) at a vertex given with its offsets from the end
    /// points: the default evaluates it at the point `v.x1`; techniques whose
    /// density depends on `d1 = |x1 − x0|`, `d2 = |x1 − x2|` take them from the
    /// offsets, so that the density of a vertex next to an end point does not
    /// inherit the rounding of its absolute coordinates.
    #[inline]
    fn pdf_vertex(&self, v: &Vertex<F>) -> F {
        self.pdf(v.x1)
    }

    /// [`pdf_vertex`](Self::pdf_vertex) per `L³` for the length unit
    /// `unit` (a connection's [`Unit`]), `pdf · L³`: the density MIS
    /// compares, finite wherever the ratio of two techniques' densities is,
    /// at any scale (docs/math.md §15). The default scales the volume
    /// density, which is right wherever that is representable; the core's
    /// techniques evaluate their formulas with every length in the unit, so
    /// that their densities are right where `pdf` itself over- or underflows
    /// (`s` beyond about 1e±12 in f32).
    #[inline]
    fn pdf_vertex_unit(&self, v: &Vertex<F>, unit: &Unit<F>) -> F {
        unit.density_to_unit(self.pdf_vertex(v))
    }

    /// [`sample`](Self::sample) with uniform numbers from a `rand_core` generator.
    #[inline]
    fn sample_with<R: rand_core::Rng + ?Sized>(&self, rng: &mut R) -> Option<Sample<F>>
    where
        Self: Sized,
    {
        self.sample([uniform(rng), uniform(rng), uniform(rng)])
    }
}

/// A vertex `x1` with its offsets from the connection's end points as its
/// sampler computed them: `from_x0 = x1 − x0`, `from_x2 = x1 − x2`.
///
/// In f32 a point next to `x0` or `x2` is stored to about `ε |x0|` in each
/// coordinate, so `x1 − x0` formed from the stored point keeps only the digits
/// of `|x1 − x0| / |x0|` that survive, and a density `∝ 1/(d1² d2²)` evaluated
/// there inherits that error (docs/benchmarks.md §4: 1.5e8 against 1.1e6 in
/// f32 at worst). The offsets as sampled keep their relative precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex<F: Real> {
    /// The point `x1`.
    pub x1: F::Vec3,
    /// `x1 − x0`.
    pub from_x0: F::Vec3,
    /// `x1 − x2`.
    pub from_x2: F::Vec3,
}

impl<F: Real> Vertex<F> {
    /// The vertex at the point `x1`, its offsets formed from the point
    /// (for a point that came without them).
    #[inline]
    pub fn at(connection: &Connection<F>, x1: F::Vec3) -> Self {
        Self {
            x1,
            from_x0: x1 - connection.axis.x0,
            from_x2: x1 - connection.axis.x2,
        }
    }
}

/// A uniform number in `[0, 1)` from a generator: the top 24 (f32) or 53
/// (f64) bits of a 64-bit draw, scaled by `2^−bits`.
#[inline]
pub fn uniform<F: Real, R: rand_core::Rng + ?Sized>(rng: &mut R) -> F {
    let bits = if F::EPSILON.to_f64() < 1e-10 { 53 } else { 24 };
    let x = (rng.next_u64() >> (64 - bits)) as f64;
    F::from_f64(x * libm::exp2(-(bits as f64)))
}

/// The fixed part of the integral: end points, axis frame and the restriction
/// θ < θmax, shared by every technique.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Connection<F: Real> {
    /// The end points and the frame about their axis.
    pub axis: Axis<F>,
    /// The integrand is restricted to deflections θ < θmax, θmax ∈ (0, π].
    pub theta_max: F,
}

impl<F: Real> Connection<F> {
    /// The connection from `x0` (light side) to `x2` (receiver side),
    /// restricted to θ < `theta_max` ∈ (0, π] (any positive θmax, the
    /// smallest subnormal included). Fails on non-finite or coincident
    /// points, on a distance above `F::MAX` ([`Axis::new`]) and on θmax
    /// outside (0, π].
    pub fn new(x0: F::Vec3, x2: F::Vec3, theta_max: F) -> Result<Self, Error> {
        let axis = Axis::new(x0, x2)?;
        // (0, π], where the precision's rounded π counts as π; the lower
        // bound is the smallest positive number of either precision.
        let pi = F::PI.to_f64().max(core::f64::consts::PI);
        check_closed(
            "theta_max",
            theta_max.to_f64(),
            f64::from_bits(1),
            pi,
            "(0, pi]",
        )?;
        Ok(Self {
            axis,
            theta_max: theta_max.min(F::PI),
        })
    }

    /// The talk's default restriction, forward scattering only: θmax = π/2,
    /// the ball with diameter `x0x2` (docs/math.md §2); `new(x0, x2, π/2)`.
    pub fn forward(x0: F::Vec3, x2: F::Vec3) -> Result<Self, Error> {
        Self::new(x0, x2, F::FRAC_PI_2)
    }

    /// The deflection at `x1`: θ between `ω1 = (x1 − x0)/d1` and
    /// `ω2 = (x2 − x1)/d2` in cancellation-free form, with `(d1, d2)`;
    /// `None` if `x1` coincides with an end point or is not finite. The
    /// offsets are formed in the connection's [`Unit`], so that `d1`, `d2`
    /// are right wherever they are finite.
    #[inline]
    pub fn deflection(&self, x1: F::Vec3) -> Option<(Deflection<F>, F, F)> {
        let (d, d1, d2) = self.deflection_unit(x1)?;
        let l = self.axis.unit.length;
        let (d1, d2) = (d1 * l, d2 * l);
        (d1.is_finite() && d2.is_finite()).then_some((d, d1, d2))
    }

    /// [`deflection`](Self::deflection) with `d1`, `d2` in the connection's
    /// [`Unit`] (`|x1 − x0|/L`, `|x1 − x2|/L`).
    #[inline]
    pub fn deflection_unit(&self, x1: F::Vec3) -> Option<(Deflection<F>, F, F)> {
        if !x1.is_finite() {
            return None;
        }
        let axis = &self.axis;
        segments(axis.from_x0_unit(x1), -axis.from_x2_unit(x1))
    }

    /// [`deflection`](Self::deflection) at a vertex from its offsets,
    /// `ω1 ∝ x1 − x0`, `ω2 ∝ x2 − x1` as sampled; `None` if either offset is
    /// zero or not finite.
    #[inline]
    pub fn deflection_at(&self, v: &Vertex<F>) -> Option<(Deflection<F>, F, F)> {
        segments(v.from_x0, -v.from_x2)
    }

    /// [`deflection_at`](Self::deflection_at) with `d1`, `d2` in the
    /// connection's [`Unit`] (the offsets divided by `L`).
    #[inline]
    pub fn deflection_at_unit(&self, v: &Vertex<F>) -> Option<(Deflection<F>, F, F)> {
        let inverse = self.axis.unit.inverse;
        segments(v.from_x0 * inverse, -(v.from_x2 * inverse))
    }

    /// The deflection at `x1 = x2 + t ω` (unit ω, t > 0) and `d1`, for the
    /// ray techniques: `ω1 = ((x2 − x0) + t ω)/d1` and `ω2 = −ω`, so that a
    /// vertex next to `x2` keeps its direction (`x1 − x2` of the rounded point
    /// would not). `None` if `x1` is on `x0` or not finite.
    #[inline]
    pub fn deflection_along(&self, omega: F::Vec3, t: F) -> Option<(Deflection<F>, F)> {
        let axis = &self.axis;
        let (d, d1) = self.deflection_along_unit(omega, t * axis.unit.inverse)?;
        let d1 = d1 * axis.unit.length;
        d1.is_finite().then_some((d, d1))
    }

    /// [`deflection_along`](Self::deflection_along) with `t` and the
    /// returned `d1` in the connection's [`Unit`].
    #[inline]
    pub fn deflection_along_unit(&self, omega: F::Vec3, t: F) -> Option<(Deflection<F>, F)> {
        let axis = &self.axis;
        let a = (axis.x2 - axis.x0) * axis.unit.inverse + omega * t;
        let (d, d1, _) = segments::<F>(a, -omega)?;
        Some((d, d1))
    }
    /// The kernel `k(x1) = p(θ) / (d1² d2²)` for θ < θmax, else 0 (finite,
    /// saturating), with `d1`, `d2` in the connection's [`Unit`] and
    /// `L⁻⁴` applied last.
    #[inline]
    pub fn kernel<P: PhaseFunction<F>>(&self, phase: &P, x1: F::Vec3) -> F {
        match self.deflection_unit(x1) {
            Some((d, d1, d2)) if d.theta < self.theta_max => {
                let r = F::ONE / (d1 * d2);
                saturate((phase.eval(d) * r * r).scale_pow2(-4 * self.axis.unit.exponent))
            }
            _ => F::ZERO,
        }
    }
}

/// The deflection between the directions of two non-zero vectors `a`, `b`
/// of any finite length, with `(|a|, |b|)`: [`Deflection::between_segments`]
/// on `a`, `b` themselves where their lengths lie in
/// `[2^(MIN_EXPONENT/4), 2^(MAX_EXPONENT/4)]` (so that `|a| b` and its
/// square stay normal), else on `a 2⁻ᵏᵃ`, `b 2⁻ᵏᵇ` brought to length one by
/// exact scalings. `None` for a zero or non-finite vector.
#[inline]
pub(crate) fn segments<F: Real>(a: F::Vec3, b: F::Vec3) -> Option<(Deflection<F>, F, F)> {
    let (la, lb) = (a.length(), b.length());
    if !(la > F::ZERO && lb > F::ZERO && la.is_finite() && lb.is_finite()) {
        return None;
    }
    let lo = F::ONE.scale_pow2(F::MIN_EXPONENT / 4);
    let hi = F::ONE.scale_pow2(F::MAX_EXPONENT / 4);
    let d = if la >= lo && la <= hi && lb >= lo && lb <= hi {
        Deflection::between_segments(a, la, b, lb)
    } else {
        scaled_segments(a, la, b, lb)
    };
    Some((d, la, lb))
}

/// The density per `L³` of `unit` a sample `s` of any technique at the
/// vertex `v` was drawn with: its pdf converted where that is a normal
/// number (exact), else `evaluate(v)` (the technique's
/// [`Technique::pdf_vertex_unit`]), where the volume density under- or
/// overflowed. (The core's techniques know the density they computed in
/// the unit while sampling and return it directly.)
#[inline(never)]
pub(crate) fn density_of<F: Real>(
    s: &Sample<F>,
    v: &Vertex<F>,
    unit: &Unit<F>,
    evaluate: &dyn Fn(&Vertex<F>) -> F,
) -> F {
    if s.pdf >= F::MIN_POSITIVE && s.pdf < F::MAX {
        unit.density_to_unit(s.pdf)
    } else {
        evaluate(v)
    }
}

/// A density `q` per `L³` of a connection's unit `own`, as a density per
/// `L³` of `unit`: `q 2^{3(k − k_own)}` (the same number when the units are
/// the same), saturated.
#[inline]
pub(crate) fn in_unit<F: Real>(q: F, own: &Unit<F>, unit: &Unit<F>) -> F {
    saturate(q.scale_pow2(3 * (unit.exponent - own.exponent)))
}

/// [`segments`] off its fast path: the vectors brought to length one by
/// exact scalings first.
#[cold]
fn scaled_segments<F: Real>(a: F::Vec3, la: F, b: F::Vec3, lb: F) -> Deflection<F> {
    let (ka, kb) = (la.exponent(), lb.exponent());
    Deflection::between_segments(
        a.scale_pow2(-ka),
        la.scale_pow2(-ka),
        b.scale_pow2(-kb),
        lb.scale_pow2(-kb),
    )
}

/// A density or weight made safe to return: NaN → 0, +∞ → `F::MAX`.
#[inline]
pub(crate) fn saturate<F: Real>(x: F) -> F {
    if x.is_finite() {
        x
    } else if x > F::ZERO {
        F::MAX
    } else {
        F::ZERO
    }
}

#[cfg(test)]
mod tests;
