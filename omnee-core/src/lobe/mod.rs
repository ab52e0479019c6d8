//! Once-more connections from a vertex with a lobe of its own
//! (docs/math.md §12).
//!
//! When `x0` is itself a scattering vertex (a light-path vertex in water, the
//! sun's refracted ray scattering on its way down), light arrives there along
//! the propagation direction `ω_in` and leaves towards `x1` with the lobe
//! `p0(ω_in · ω01)`, `ω01 = (x1 − x0)/d1`. The once-more integral becomes
//!
//! `I = ∫ σs p0(ω_in · ω01) p1(ω01 · ω12) T(x0, x1) T(x1, x2) / (d1² d2²) dx1`,
//!
//! whose *kernel* (what the techniques here return `k/pdf` of) is
//!
//! `k(x1) = p0(ω_in · ω01) p1(θ) / (d1² d2²)` for θ < θmax, else 0,
//!
//! and `f_c = σs T T [cos θ2]` as in [`crate::reference`]. OMNEE samples
//! `p1` and the arc; `p0` stays in its weight, which degrades by orders of
//! magnitude once `ω_in` is tilted from the axis and `p0` is peaked.
//!
//! - [`Lobe`]: the slot for what scatters at `x0` (a sample / pdf / invert
//!   trio over directions); [`PhaseLobe`] fills it with a phase function
//!   about `ω_in`, a BSDF lobe could fill it later;
//! - [`LobeRay`]: the direction at `x0` from the lobe, then the deflection
//!   at `x1` from `p1` restricted to `[α, θmax)` ([`Restricted`]), which
//!   fixes the distance along the ray: `p0 · p1` sampled exactly;
//! - [`WithLobe`]: any technique of [`crate::sampling`] (OMNEE) used for this
//!   kernel, the lobe multiplied into its weight;
//! - [`LobeMis`]: the recommended combination, one-sample balance-heuristic
//!   MIS of OMNEE and [`LobeRay`] with a per-connection selection probability;
//! - [`LobeToPoint`]: the test problem and its three-dimensional quadrature
//!   reference.
//!
//! ## Example
//!
//! Light arriving at `x0` 0.5 rad off the axis towards `x2`, HG 0.9 at both
//! vertices: the recommended combination against the reference.
//!
//! ```
//! use glam::DVec3;
//! use omnee_core::lobe::{LobeMis, LobeToPoint, PhaseLobe};
//! use omnee_core::medium::Homogeneous;
//! use omnee_core::phase::HenyeyGreenstein;
//! use omnee_core::reference::PointToPoint;
//! use omnee_core::sampling::{Connection, Technique};
//!
//! # fn main() -> Result<(), omnee_core::Error> {
//! let connection = Connection::new(DVec3::ZERO, DVec3::Z, core::f64::consts::PI)?;
//! let water = HenyeyGreenstein::new(0.9)?;
//! let incoming = DVec3::new(0.5f64.sin(), 0.0, 0.5f64.cos());
//! let lobe = PhaseLobe::new(water, incoming)?;
//! let point = PointToPoint::new(connection, Homogeneous::new(0.5, 0.05)?, None)?;
//! let problem = LobeToPoint::new(point, Some(lobe))?;
//! let mis = LobeMis::recommended(connection, lobe, water);
//!
//! let n = 64;
//! let mut sum = 0.0;
//! for i in 0..n * n * 16 {
//!     // Stratified in (u0, u1), a golden-ratio sequence in u2.
//!     let (a, b) = ((i % n) as f64 + 0.5, ((i / n) % n) as f64 + 0.5);
//!     let u = [a / n as f64, b / n as f64, (i as f64 * 0.618_034).fract()];
//!     if let Some(sample) = mis.sample(u) {
//!         sum += problem.estimate(&sample); // f_c · k/q, p0 included
//!     }
//! }
//! let estimate = sum / (n * n * 16) as f64;
//! let reference = problem.integral(&water);
//! assert!((estimate / reference - 1.0).abs() < 0.03, "{estimate} vs {reference}");
//! # Ok(())
//! # }
//! ```

mod combined;
mod problem;
mod ray;
mod restricted;
#[cfg(test)]
mod tests;

pub use combined::LobeMis;
pub use problem::LobeToPoint;
pub use ray::LobeRay;
pub use restricted::Restricted;

use crate::error::Error;
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, Vector, unit_vector};
use crate::sampling::{Omnee, Sample, Technique, Unit, Vertex, saturate, unit_normal};

/// A direction drawn from a [`Lobe`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeSample<F: Real> {
    /// The unit propagation direction ω leaving `x0`.
    pub omega: F::Vec3,
    /// The lobe's value there, [`Lobe::eval`]`(ω)`.
    pub value: F,
    /// The solid-angle density of the draw, [`Lobe::pdf`]`(ω)`.
    pub pdf: F,
}

/// What scatters light at `x0`: its value per steradian for each outgoing
/// propagation direction, and a sampler of directions (the trio of
/// [`Technique`], over the sphere).
///
/// A phase function with an exact sampler ([`PhaseLobe`]) has `eval = pdf`;
/// a table-sampled one (docs/math.md §11) has its table's `q` as pdf; a BSDF lobe would
/// return its value times the cosine in `eval` and its own sampling density
/// in `pdf`, and the techniques of this module would weight by their ratio.
pub trait Lobe<F: Real> {
    /// The lobe's value for light leaving `x0` along the unit vector ω.
    fn eval(&self, omega: F::Vec3) -> F;

    /// A unit direction from `u ∈ [0, 1)²` with the lobe's value and the
    /// draw's density; `None` where the lobe has no direction to give.
    fn sample(&self, u: [F; 2]) -> Option<LobeSample<F>>;

    /// The solid-angle density of [`sample`](Self::sample) at the unit vector ω.
    fn pdf(&self, omega: F::Vec3) -> F;

    /// The `u` that [`sample`](Self::sample) maps to ω, where invertible.
    fn invert(&self, omega: F::Vec3) -> Option<[F; 2]>;

    /// The unit direction the lobe is concentrated about (and, for a
    /// backward lobe, opposite to): quadratures split their panels there.
    fn axis(&self) -> F::Vec3;

    /// The lobe's largest value (an upper estimate will do), against which
    /// [`LobeMis::recommended`] compares its value along the connection.
    fn peak(&self) -> F;
}

/// A phase function at `x0` for light arriving along the unit propagation
/// direction `ω_in`: `eval(ω) = p0(θ0)`, θ0 the deflection between `ω_in`
/// and ω, sampled as θ0 from `p0` and an azimuth `φ0 = 2π u1` about `ω_in`:
///
/// `ω = cos θ0 ω_in + sin θ0 (cos φ0 t + sin φ0 b)`, `pdf(ω) = p0(θ0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseLobe<F: Real, P> {
    /// The phase function at `x0`.
    pub phase: P,
    incoming: F::Vec3,
    tangent: F::Vec3,
    bitangent: F::Vec3,
}

impl<F: Real, P: PhaseFunction<F>> PhaseLobe<F, P> {
    /// The lobe of `phase` for light arriving along `incoming` (a propagation
    /// direction: towards `x0`), normalised here; it must be finite and
    /// non-zero (field `"incoming"`).
    pub fn new(phase: P, incoming: F::Vec3) -> Result<Self, Error> {
        // Any finite, non-zero length: neither 1e30 nor 1e-45 over- or
        // underflows on the way to unit length.
        let incoming = unit_normal::<F>(incoming, "incoming")?;
        let (tangent, bitangent) = incoming.orthonormal_pair();
        Ok(Self {
            phase,
            incoming,
            tangent,
            bitangent,
        })
    }

    /// The unit incoming propagation direction `ω_in`.
    #[inline]
    pub fn incoming(&self) -> F::Vec3 {
        self.incoming
    }

    /// The deflection θ0 between `ω_in` and the unit vector ω.
    #[inline]
    fn deflection(&self, omega: F::Vec3) -> Deflection<F> {
        Deflection::between(self.incoming, omega)
    }
}

impl<F: Real, P: PhaseFunction<F>> Lobe<F> for PhaseLobe<F, P> {
    /// `p0(θ0)`, θ0 between `ω_in` and ω.
    #[inline]
    fn eval(&self, omega: F::Vec3) -> F {
        self.phase.eval(self.deflection(omega))
    }

    /// θ0 from the phase function with `u0`, `φ0 = 2π u1` (each clamped to
    /// `[0, 1]`, NaN to 0); pdf is the density `q` of the draw and value
    /// `p0 = q · (p0/q)` from [`PhaseFunction::sample_ratio`]: the same
    /// number for an exact sampler (ratio 1), the phase function's own value
    /// for a table-sampled one (docs/math.md §11), whose `q` is not `p0`.
    #[inline]
    fn sample(&self, u: [F; 2]) -> Option<LobeSample<F>> {
        let (d, pdf, ratio) = self
            .phase
            .sample_ratio(u[0].clamp_to(F::ZERO, F::ONE_MINUS_EPSILON));
        let (sin_phi, cos_phi) = (F::TAU * u[1].clamp_to(F::ZERO, F::ONE)).sin_cos();
        let radial = self.tangent * cos_phi + self.bitangent * sin_phi;
        let omega = self.incoming * d.cos() + radial * d.sin();
        (omega.is_finite() && pdf > F::ZERO).then_some(LobeSample {
            omega,
            value: pdf * ratio,
            pdf,
        })
    }

    /// `p0(θ0)`.
    #[inline]
    fn pdf(&self, omega: F::Vec3) -> F {
        self.phase.pdf(self.deflection(omega))
    }

    /// `(invert(θ0), φ0/2π)`; `None` for a phase function whose sampler is
    /// not invertible (mixtures).
    #[inline]
    fn invert(&self, omega: F::Vec3) -> Option<[F; 2]> {
        let u0 = self.phase.invert(self.deflection(omega))?;
        let mut phi = omega.dot(self.bitangent).atan2(omega.dot(self.tangent));
        if phi < F::ZERO {
            phi += F::TAU;
        }
        Some([u0, (phi / F::TAU).clamp_to(F::ZERO, F::ONE)])
    }

    /// `ω_in`.
    #[inline]
    fn axis(&self) -> F::Vec3 {
        self.incoming
    }

    /// `max(p0(0), p0(π))`: the peak of every monotone phase function (HG,
    /// two-term HG, Fournier–Forand, Rayleigh, Draine); for a table an
    /// estimate.
    #[inline]
    fn peak(&self) -> F {
        let forward = self.phase.eval(Deflection::from_versines(F::ZERO, F::TWO));
        let backward = self.phase.eval(Deflection::from_versines(F::TWO, F::ZERO));
        forward.max(backward)
    }
}

impl<F: Real, L: Lobe<F> + ?Sized> Lobe<F> for &L {
    #[inline]
    fn eval(&self, omega: F::Vec3) -> F {
        (**self).eval(omega)
    }
    #[inline]
    fn sample(&self, u: [F; 2]) -> Option<LobeSample<F>> {
        (**self).sample(u)
    }
    #[inline]
    fn pdf(&self, omega: F::Vec3) -> F {
        (**self).pdf(omega)
    }
    #[inline]
    fn invert(&self, omega: F::Vec3) -> Option<[F; 2]> {
        (**self).invert(omega)
    }
    #[inline]
    fn axis(&self) -> F::Vec3 {
        (**self).axis()
    }
    #[inline]
    fn peak(&self) -> F {
        (**self).peak()
    }
}

/// The lobe at `x0` evaluated towards `x1`, `eval((x1 − x0)/d1)` with the
/// direction normalised at any length ([`unit_vector`]); 0 where `x1` is
/// `x0` or `x1 − x0` is not finite.
#[inline]
fn eval_towards<F: Real, L: Lobe<F>>(lobe: &L, x0: F::Vec3, x1: F::Vec3) -> F {
    match unit_vector::<F>(x1 - x0) {
        Some(omega) => lobe.eval(omega),
        None => F::ZERO,
    }
}

/// A technique of [`crate::sampling`] (OMNEE, equiangular, ...) used for the
/// kernel with a lobe at `x0`: it does not sample the lobe, so the lobe's
/// value `p0(ω01)` multiplies its weight, `k/pdf = p0 · (p1/(d1² d2²))/pdf`;
/// pdf and invert are the technique's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WithLobe<F: Real, T, L> {
    /// The technique placing `x1`.
    pub technique: T,
    /// The lobe at `x0`.
    pub lobe: L,
    /// The vertex the lobe sits at.
    pub x0: F::Vec3,
}

impl<F: Real, T: Technique<F>, L: Lobe<F>> WithLobe<F, T, L> {
    /// `technique` with the lobe `lobe` at `x0` multiplied into its weight.
    pub fn new(technique: T, lobe: L, x0: F::Vec3) -> Self {
        Self {
            technique,
            lobe,
            x0,
        }
    }

    /// `p0(ω01)` at `x1`; 0 at `x0` itself.
    #[inline]
    pub fn lobe_at(&self, x1: F::Vec3) -> F {
        eval_towards(&self.lobe, self.x0, x1)
    }
}

impl<F: Real, P: PhaseFunction<F>, L: Lobe<F>> WithLobe<F, Omnee<F, P>, L> {
    /// OMNEE's sample with its vertex and the density per `L³` of `unit` it
    /// was drawn with, the lobe in its weight (for [`LobeMis`]).
    #[inline]
    pub(crate) fn sample_vertex_unit(
        &self,
        u: [F; 3],
        unit: &Unit<F>,
    ) -> Option<(Sample<F>, Vertex<F>, F)> {
        let (s, v, density) = self.technique.sample_vertex_unit(u, unit)?;
        let s = Sample {
            weight: saturate(s.weight * self.lobe_at(s.x1)),
            ..s
        };
        Some((s, v, density))
    }
}

impl<F: Real, T: Technique<F>, L: Lobe<F>> Technique<F> for WithLobe<F, T, L> {
    /// The technique's sample, its weight times `p0(ω01)`.
    #[inline]
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        let s = self.technique.sample(u)?;
        Some(Sample {
            weight: saturate(s.weight * self.lobe_at(s.x1)),
            ..s
        })
    }
    /// The technique's density.
    #[inline]
    fn pdf(&self, x1: F::Vec3) -> F {
        self.technique.pdf(x1)
    }
    /// The technique's density at a vertex.
    #[inline]
    fn pdf_vertex(&self, v: &Vertex<F>) -> F {
        self.technique.pdf_vertex(v)
    }
    /// The technique's density per `L³`.
    #[inline]
    fn pdf_vertex_unit(&self, v: &Vertex<F>, unit: &Unit<F>) -> F {
        self.technique.pdf_vertex_unit(v, unit)
    }
    /// The technique's inverse.
    #[inline]
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        self.technique.invert(x1)
    }
}
