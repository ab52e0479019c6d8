//! The sun: a disc of uniform radiance about a direction, given by its
//! irradiance at normal incidence (docs/math.md §13).

use glam::Vec3;

/// The sun as seen from the water's surface.
#[derive(Clone, Copy, Debug)]
pub struct Sun {
    /// Unit direction towards the sun's centre (`z > 0`).
    pub direction: Vec3,
    /// Irradiance at normal incidence `E` (W/m²).
    pub irradiance: f32,
    /// Angular radius α (rad); 0 is a delta direction.
    pub angular_radius: f32,
    /// `1 − cos α`, without cancellation.
    one_minus_cos: f32,
    tangent: Vec3,
    bitangent: Vec3,
}

impl Sun {
    /// The sun towards `direction` (normalised here) with irradiance `E` at
    /// normal incidence and angular radius α.
    pub fn new(direction: Vec3, irradiance: f32, angular_radius: f32) -> Self {
        let direction = direction.normalize();
        let (tangent, bitangent) = direction.any_orthonormal_pair();
        let s = (0.5 * angular_radius).sin();
        Self {
            direction,
            irradiance,
            angular_radius,
            one_minus_cos: 2.0 * s * s,
            tangent,
            bitangent,
        }
    }

    /// A direction towards a point of the disc, uniform in solid angle over
    /// the cone of half-angle α (density `1/Ω`, `Ω = 2π(1 − cos α)`), and
    /// the flux factor `L · Ω = E Ω / (π sin²α) = 2E / (1 + cos α)` that the
    /// estimate `L (ω·n) Ω` of the irradiance on a plane with normal `n`
    /// needs: a disc of uniform radiance `L` gives `E = ∫ L cos dω = L π sin²α`
    /// at normal incidence. For α = 0 the direction is the centre and the
    /// factor is `E`.
    #[inline]
    pub fn sample(&self, u: [f32; 2]) -> (Vec3, f32) {
        if self.angular_radius == 0.0 {
            return (self.direction, self.irradiance);
        }
        let omc = u[0] * self.one_minus_cos;
        let cos_t = 1.0 - omc;
        let sin_t = (omc * (2.0 - omc)).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * u[1];
        let w = self.direction * cos_t
            + self.tangent * (sin_t * phi.cos())
            + self.bitangent * (sin_t * phi.sin());
        let flux = 2.0 * self.irradiance / (2.0 - self.one_minus_cos);
        (w.normalize(), flux)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_disc_gives_its_irradiance_at_normal_incidence() {
        // Mean of flux · (ω · axis) over the cone = E, for a large disc where
        // the cosine matters (α = 20°) and for the real sun.
        for alpha in [20f32.to_radians(), 0.27f32.to_radians()] {
            let sun = Sun::new(Vec3::new(0.2, 0.1, 1.0), 1000.0, alpha);
            let n = 400;
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                    let (w, flux) = sun.sample(u);
                    assert!(w.dot(sun.direction) >= alpha.cos() - 1e-6);
                    sum += (flux * w.dot(sun.direction)) as f64;
                }
            }
            let e = sum / (n * n) as f64;
            assert!((e - 1000.0).abs() < 1e-3 * 1000.0, "alpha {alpha}: {e}");
        }
    }
}
