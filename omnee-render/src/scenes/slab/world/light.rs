//! The light in f32: a sphere of uniform radiance or a point light, and the
//! ways to choose a point on it: uniform in the solid angle it subtends
//! (`Light::sample_from`, pbrt-v4's sphere sampling), uniform on its area,
//! and favouring the half that faces a ray segment.

use glam::Vec3;
use std::f32::consts::{PI, TAU};

/// A spherical light (radius > 0) or a point light.
#[derive(Clone, Copy, Debug)]
pub struct Light {
    /// Centre.
    pub center: Vec3,
    /// Radius (0: point light).
    pub radius: f32,
    /// Surface radiance (sphere).
    pub radiance: f32,
    /// Intensity (point light; `radiance·π r²` for a sphere).
    pub intensity: f32,
}

/// A point on the light seen from somewhere, with its solid-angle density.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightPoint {
    /// The point.
    pub y: Vec3,
    /// Unit direction from the receiver to `y`.
    pub dir: Vec3,
    /// `L / pdf_ω` for a sphere, `I / dist²` for a point light: the
    /// unoccluded, unattenuated estimate of the irradiance normal to `dir`.
    pub value: f32,
}

/// The cone of directions under which the sphere is seen from a point at
/// distance `dc` from its centre: `sin²θmax = r²/dc²`.
#[derive(Clone, Copy, Debug)]
struct Cone {
    sin2_max: f32,
    /// `1 − cos θmax`, without cancellation: `sin²θmax / (1 + cos θmax)`.
    omc_max: f32,
}

/// The probability of the facing hemisphere in [`Light::sample_facing`].
const FACING: f32 = 0.75;

impl Light {
    /// The cone subtended from distance `dc > r` of the centre.
    fn cone(&self, dc: f32) -> Cone {
        let sin2_max = (self.radius / dc).powi(2);
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        Cone {
            sin2_max,
            omc_max: sin2_max / (1.0 + cos_max),
        }
    }

    /// The sphere's area `4π r²`.
    pub(super) fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// Samples the part of the light visible from `q` uniformly in solid
    /// angle (a sphere's cone of directions, density `1/(2π (1 − cos θmax))`),
    /// or returns the point light.
    pub(super) fn sample_from(&self, q: Vec3, u: [f32; 2]) -> Option<LightPoint> {
        let to_c = self.center - q;
        let dc = to_c.length();
        if self.radius == 0.0 {
            return (dc > 0.0).then(|| LightPoint {
                y: self.center,
                dir: to_c / dc,
                value: self.intensity / (dc * dc),
            });
        }
        if !(dc > self.radius) {
            return None;
        }
        let Cone { sin2_max, omc_max } = self.cone(dc);
        let omc = u[0] * omc_max;
        let cos_t = 1.0 - omc;
        let sin2_t = omc * (2.0 - omc);
        // Angle α at the centre between −wc and the point (pbrt-v4's form).
        let sin_max = sin2_max.sqrt();
        let cos_a = sin2_t / sin_max + cos_t * (1.0 - sin2_t / sin2_max).max(0.0).sqrt();
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let phi = TAU * u[1];
        let wc = to_c / dc;
        let (t1, t2) = wc.any_orthonormal_pair();
        let n = (t1 * (sin_a * phi.cos()) + t2 * (sin_a * phi.sin())) - wc * cos_a;
        let y = self.center + n * self.radius;
        let v = y - q;
        let dist = v.length();
        (dist > 0.0).then(|| LightPoint {
            y,
            dir: v / dist,
            value: self.radiance * TAU * omc_max,
        })
    }

    /// The area density at `y` (on the sphere) of [`Self::sample_from`]`(x)`:
    /// `cos θ_y / (dist² · 2π (1 − cos θmax))` on the cap visible from `x`.
    pub(super) fn cone_area_pdf(&self, x: Vec3, y: Vec3) -> f32 {
        let n = (y - self.center) / self.radius;
        let to_x = x - y;
        let dist2 = to_x.length_squared();
        let cos_y = n.dot(to_x) / dist2.sqrt();
        let dc = (x - self.center).length();
        if !(cos_y > 0.0 && dc > self.radius) {
            return 0.0;
        }
        cos_y / (dist2 * TAU * self.cone(dc).omc_max)
    }

    /// A point of the sphere uniform in area (density `1/(4π r²)`):
    /// `z = 1 − 2u0`, `φ = 2π u1`.
    pub(super) fn sample_area(&self, u: [f32; 2]) -> Vec3 {
        let z = 1.0 - 2.0 * u[0];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = TAU * u[1];
        self.center + Vec3::new(r * phi.cos(), r * phi.sin(), z) * self.radius
    }

    /// The normal of the light's hemisphere that faces the segment
    /// `o + t d`, `t ∈ [ta, tb]` (towards its point closest to the centre).
    fn facing(&self, o: Vec3, d: Vec3, (ta, tb): (f32, f32)) -> Vec3 {
        let c = self.center;
        let foot = o + d * (c - o).dot(d).clamp(ta, tb);
        (foot - c).try_normalize().unwrap_or(-d)
    }

    /// A point on the sphere for single scattering along a ray segment,
    /// `(y, normal at y)`: with probability 3/4 uniform on the hemisphere
    /// facing the segment, else uniform on the whole sphere.
    pub(super) fn sample_facing(
        &self,
        o: Vec3,
        d: Vec3,
        seg: (f32, f32),
        u: [f32; 3],
    ) -> (Vec3, Vec3) {
        let h = self.facing(o, d, seg);
        let z = 1.0 - 2.0 * u[1];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = TAU * u[2];
        let (t1, t2) = h.any_orthonormal_pair();
        let mut n = t1 * (r * phi.cos()) + t2 * (r * phi.sin()) + h * z;
        if u[0] < FACING && n.dot(h) < 0.0 {
            n -= h * (2.0 * n.dot(h)); // mirrored into the facing hemisphere
        }
        (self.center + n * self.radius, n)
    }

    /// The area density of [`Self::sample_facing`] at the point with normal
    /// `n`: `(2·3/4 + 1/4)/(4π r²)` on the facing hemisphere, `(1/4)/(4π r²)`
    /// on the other.
    pub(super) fn facing_pdf(&self, o: Vec3, d: Vec3, seg: (f32, f32), n: Vec3) -> f32 {
        let facing = if n.dot(self.facing(o, d, seg)) >= 0.0 {
            2.0 * FACING
        } else {
            0.0
        };
        (facing + 1.0 - FACING) / self.area()
    }

    /// Whether the segment `a → b` passes through the sphere's interior.
    pub(super) fn blocks(&self, a: Vec3, b: Vec3) -> bool {
        if self.radius == 0.0 {
            return false;
        }
        let d = b - a;
        let len2 = d.length_squared();
        let t = if len2 > 0.0 {
            ((self.center - a).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a + d * t - self.center).length_squared() < self.radius * self.radius * (1.0 - 1e-5)
    }

    /// The first `t > 0` where the ray `o + t d` hits the sphere.
    pub(super) fn hit(&self, o: Vec3, d: Vec3) -> Option<f32> {
        if self.radius == 0.0 {
            return None;
        }
        let oc = o - self.center;
        let b = oc.dot(d);
        // c = |oc|² − r², the discriminant as r² − |oc − b d|² (no cancellation).
        let perp = oc - d * b;
        let disc = self.radius * self.radius - perp.length_squared();
        if disc < 0.0 {
            return None;
        }
        let t = -b - disc.sqrt();
        (t > 0.0).then_some(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn the_sphere_light_cone_sample_lies_on_the_sphere_and_faces_the_receiver() {
        let l = Light {
            center: Vec3::new(0.0, 0.0, 1.0),
            radius: 0.1,
            radiance: 1.0,
            intensity: 0.0,
        };
        let q = Vec3::new(0.2, 0.1, 0.0);
        let mut rng = Rng::stream(1, 2, 3);
        for _ in 0..1000 {
            let lp = l.sample_from(q, [rng.uniform(), rng.uniform()]).unwrap();
            assert!(((lp.y - l.center).length() - 0.1).abs() < 1e-5);
            assert!((lp.y - l.center).dot(q - lp.y) >= -1e-6);
        }
    }
}
