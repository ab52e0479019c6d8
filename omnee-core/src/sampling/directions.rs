//! Directions from the receiver `x2`: uniform on the sphere or cosine-weighted
//! about a normal, each as a sample / pdf / invert trio.

use crate::error::Error;
use crate::real::{Real, Vector, unit_vector};

/// The unit vector along a normal or direction given with any finite,
/// non-zero length ([`unit_vector`]: scaled by its largest component's
/// power of two first, so neither `|n|²` nor `1/|n|` over- or underflows).
/// Fails with `NotFinite` for a NaN or infinite component and `Degenerate`
/// ("must be finite and non-zero") for the zero vector, naming `field`.
pub fn unit_normal<F: Real>(n: F::Vec3, field: &'static str) -> Result<F::Vec3, Error> {
    if !n.is_finite() {
        return Err(Error::not_finite(field));
    }
    unit_vector::<F>(n).ok_or(Error::Degenerate {
        field,
        reason: "must be finite and non-zero",
    })
}

/// How a ray direction ω leaving `x2` is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Directions<F: Real> {
    /// Uniform on the sphere, `pdf = 1/(4π)`.
    Sphere,
    /// Cosine-weighted about the unit `normal`, `pdf = max(ω·n, 0)/π`.
    Cosine {
        /// The unit normal n.
        normal: F::Vec3,
        /// A unit tangent t (`t, b, n` right-handed).
        tangent: F::Vec3,
        /// A unit bitangent b.
        bitangent: F::Vec3,
    },
}

impl<F: Real> Directions<F> {
    /// Cosine-weighted directions about `normal`, normalised here
    /// ([`unit_normal`]): any finite, non-zero length (1e-45 or `F::MAX`
    /// per component alike). A NaN or infinite component is `NotFinite`, a
    /// zero normal `Degenerate` (field `"normal"`).
    pub fn cosine(normal: F::Vec3) -> Result<Self, Error> {
        let normal = unit_normal::<F>(normal, "normal")?;
        let (tangent, bitangent) = normal.orthonormal_pair();
        Ok(Directions::Cosine {
            normal,
            tangent,
            bitangent,
        })
    }

    /// A direction from `u ∈ [0, 1)²` (each coordinate clamped to [0, 1],
    /// NaN to 0, so that any input gives a unit vector).
    /// Sphere: `z = 1 − 2u0`, `r = 2√(u0(1 − u0))`, `φ = 2π u1`.
    /// Cosine (Malley): `r = √u0`, `φ = 2π u1`, `cos θ = √(1 − u0)` about n.
    #[inline]
    pub fn sample(&self, u: [F; 2]) -> F::Vec3 {
        let u = [
            u[0].clamp_to(F::ZERO, F::ONE),
            u[1].clamp_to(F::ZERO, F::ONE),
        ];
        let (sin_phi, cos_phi) = (F::TAU * u[1]).sin_cos();
        match *self {
            Directions::Sphere => {
                let z = F::ONE - F::TWO * u[0];
                let r = F::TWO * (u[0] * (F::ONE - u[0])).safe_sqrt();
                F::Vec3::new(r * cos_phi, r * sin_phi, z)
            }
            Directions::Cosine {
                normal,
                tangent,
                bitangent,
            } => {
                let r = u[0].safe_sqrt();
                let z = (F::ONE - u[0]).safe_sqrt();
                tangent * (r * cos_phi) + bitangent * (r * sin_phi) + normal * z
            }
        }
    }

    /// The solid-angle density of [`sample`](Self::sample) at the unit vector ω.
    #[inline]
    pub fn pdf(&self, omega: F::Vec3) -> F {
        match *self {
            Directions::Sphere => F::FRAC_1_4PI,
            Directions::Cosine { normal, .. } => omega.dot(normal).max(F::ZERO) * F::FRAC_1_PI,
        }
    }

    /// The `u` with `sample(u) = ω` (ω unit; `None` below the cosine's horizon).
    #[inline]
    pub fn invert(&self, omega: F::Vec3) -> Option<[F; 2]> {
        let (x, y, u0) = match *self {
            Directions::Sphere => {
                let [x, y, z] = omega.to_array();
                (x, y, (F::ONE - z) * F::HALF)
            }
            Directions::Cosine {
                normal,
                tangent,
                bitangent,
            } => {
                if !(omega.dot(normal) > F::ZERO) {
                    return None;
                }
                let (x, y) = (omega.dot(tangent), omega.dot(bitangent));
                (x, y, x * x + y * y)
            }
        };
        let mut phi = y.atan2(x);
        if phi < F::ZERO {
            phi += F::TAU;
        }
        Some([
            u0.clamp_to(F::ZERO, F::ONE),
            (phi / F::TAU).clamp_to(F::ZERO, F::ONE),
        ])
    }
}
