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
pub use directions::Directions;
pub use distance::Distance;
pub use draw::Draw;
pub use equiangular::Equiangular;
pub use omnee::Omnee;

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
    /// restricted to θ < `theta_max` ∈ (0, π]. Fails on non-finite or
    /// coincident points and on θmax outside (0, π].
    pub fn new(x0: F::Vec3, x2: F::Vec3, theta_max: F) -> Result<Self, Error> {
        let axis = Axis::new(x0, x2)?;
        // (0, π], where the precision's rounded π counts as π.
        let pi = F::PI.to_f64().max(core::f64::consts::PI);
        check_closed(
            "theta_max",
            theta_max.to_f64(),
            f64::MIN_POSITIVE,
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
    /// `None` if `x1` coincides with an end point or is not finite.
    #[inline]
    pub fn deflection(&self, x1: F::Vec3) -> Option<(Deflection<F>, F, F)> {
        let (a, b) = (x1 - self.axis.x0, self.axis.x2 - x1);
        let (d1, d2) = (a.length(), b.length());
        if !(d1 > F::ZERO && d2 > F::ZERO && d1.is_finite() && d2.is_finite()) {
            return None;
        }
        Some((Deflection::between_segments(a, d1, b, d2), d1, d2))
    }

    /// [`deflection`](Self::deflection) at a vertex from its offsets,
    /// `ω1 ∝ x1 − x0`, `ω2 ∝ x2 − x1` as sampled; `None` if either offset is
    /// zero or not finite.
    #[inline]
    pub fn deflection_at(&self, v: &Vertex<F>) -> Option<(Deflection<F>, F, F)> {
        let (a, b) = (v.from_x0, -v.from_x2);
        let (d1, d2) = (a.length(), b.length());
        if !(d1 > F::ZERO && d2 > F::ZERO && d1.is_finite() && d2.is_finite()) {
            return None;
        }
        Some((Deflection::between_segments(a, d1, b, d2), d1, d2))
    }

    /// The deflection at `x1 = x2 + t ω` (unit ω, t > 0) and `d1`, for the
    /// ray techniques: `ω1 = ((x2 − x0) + t ω)/d1` and `ω2 = −ω`, so that a
    /// vertex next to `x2` keeps its direction (`x1 − x2` of the rounded point
    /// would not). `None` if `x1` is on `x0` or not finite.
    #[inline]
    pub fn deflection_along(&self, omega: F::Vec3, t: F) -> Option<(Deflection<F>, F)> {
        let a = (self.axis.x2 - self.axis.x0) + omega * t;
        let d1 = a.length();
        if !(d1 > F::ZERO && d1.is_finite()) {
            return None;
        }
        Some((Deflection::between_segments(a, d1, -omega, F::ONE), d1))
    }

    /// The kernel `k(x1) = p(θ) / (d1² d2²)` for θ < θmax, else 0 (finite,
    /// saturating).
    #[inline]
    pub fn kernel<P: PhaseFunction<F>>(&self, phase: &P, x1: F::Vec3) -> F {
        match self.deflection(x1) {
            Some((d, d1, d2)) if d.theta < self.theta_max => {
                let r = F::ONE / (d1 * d2);
                saturate(phase.eval(d) * r * r)
            }
            _ => F::ZERO,
        }
    }
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
