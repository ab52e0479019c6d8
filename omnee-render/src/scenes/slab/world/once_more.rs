//! The `once-more` term, OMNEE's: light → `x1` in the slab → surface. A
//! point `x0` on the light, then `x1` by the chosen technique for the
//! connection `x0 → p`, each vertex weighted by its technique (OMNEE's
//! weight `θ/(s sin θ)`, docs/math.md §3; `mis`, §10).

use super::SlabStats;
use super::{Light, Roulette, SlabWorld};
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::method::Method;
use omnee_core::sampling::{Connection, Directions, Sample};

/// How the once-more term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct OnceMore {
    /// The method for `x1`.
    pub method: Method,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
}

/// The light end of a once-more connection.
#[derive(Clone, Copy, Debug)]
struct LightVertex {
    /// The point on the light.
    x0: Vec3,
    /// The sphere's normal at `x0` (`None` for a point light).
    n0: Option<Vec3>,
    /// `L / pdf_A(x0)` for a sphere, `I` for a point light: the factor
    /// `L cos θ0 / pdf_A` without the cosine, which depends on `x1`.
    emitted: f32,
}

/// The probability of choosing `x0` in the cap visible from the receiver.
const CONE: f32 = 0.9;

impl Light {
    /// A point `x0` for a once-more connection to `p`. Sphere: with
    /// probability [`CONE`] a point of the cap visible from `p` (uniform in
    /// solid angle from `p`), else uniform on the whole sphere, so every
    /// point that can light some `x1` has a positive density; its area
    /// density is `CONE · pdf_cone + (1 − CONE)/(4π r²)`.
    fn once_more_origin(&self, p: Vec3, rng: &mut Rng) -> Option<LightVertex> {
        if self.radius == 0.0 {
            return Some(LightVertex {
                x0: self.center,
                n0: None,
                emitted: self.intensity,
            });
        }
        let (u0, u1, u2): (f32, f32, f32) = (rng.uniform(), rng.uniform(), rng.uniform());
        let y = if u0 < CONE {
            self.sample_from(p, [u1, u2])?.y
        } else {
            self.sample_area([u1, u2])
        };
        let pdf = CONE * self.cone_area_pdf(p, y) + (1.0 - CONE) / self.area();
        Some(LightVertex {
            x0: y,
            n0: Some((y - self.center) / self.radius),
            emitted: self.radiance / pdf,
        })
    }
}

impl SlabWorld<'_> {
    /// One-sample estimate of the once-more scattered irradiance at `p`
    /// (normal `n`): light → `x1` in the slab → `p`, the sum of
    /// `once_more_vertex` over the draw's vertices.
    pub fn once_more(
        &self,
        p: Vec3,
        n: Vec3,
        how: OnceMore,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let Some(light) = self.light.once_more_origin(p, rng) else {
            return 0.0;
        };
        stats.connections += 1;
        if !self.slab.may_reach(light.x0, p, how.theta_max) {
            stats.skipped_unreachable += 1;
            return 0.0;
        }
        let Ok(connection) = Connection::new(light.x0, p, how.theta_max) else {
            return 0.0;
        };
        // Ray methods draw cosine-weighted directions about the normal.
        let setup = if how.method == Method::Omnee {
            self.setup
        } else {
            let Ok(directions) = Directions::cosine(n) else {
                return 0.0;
            };
            self.setup.with_directions(directions)
        };
        let [first, companion] = setup
            .draw(how.method, connection, || rng.uniform())
            .vertices;
        if first.is_none() {
            stats.no_vertex += 1;
        }
        [first, companion]
            .into_iter()
            .flatten()
            .map(|s| self.once_more_vertex(light, (p, n), s, rng, roulette, stats))
            .sum()
    }

    /// The contribution `f_c · weight` of one vertex `x1` of a once-more
    /// connection from the light point to the receiver `(p, n)`:
    /// `emitted · cos θ0 · T(x0, x1) · σs · T(x1, p) · cos θ2 · weight`
    /// (closed-form transmittance on both legs), then the roulette and the
    /// visibility tests. 0 for a vertex outside the slab (or below the
    /// opaque floor) or with weight 0.
    fn once_more_vertex(
        &self,
        light: LightVertex,
        (p, n): (Vec3, Vec3),
        sample: Sample<f32>,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let LightVertex { x0, n0, emitted } = light;
        let x1 = sample.x1;
        if !(sample.weight > 0.0 && self.slab.contains(x1) && x1.z >= self.floor.z) {
            return 0.0;
        }
        let (a, b) = (x1 - x0, x1 - p);
        let (d1, d2) = (a.length(), b.length());
        let cos0 = match n0 {
            Some(n0) => n0.dot(a) / d1,
            None => 1.0,
        };
        let cos2 = n.dot(b) / d2;
        if !(cos0 > 0.0 && cos2 > 0.0) {
            return 0.0;
        }
        let e = emitted
            * cos0
            * self.transmittance(x0, x1)
            * self.slab.sigma_s
            * self.transmittance(x1, p)
            * cos2
            * sample.weight;
        if !e.is_finite() {
            return 0.0;
        }
        let Some(e) = roulette.play(e, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x0, x1, stats) || self.occluded(x1, p, stats) || self.light.blocks(x1, p) {
            return 0.0;
        }
        e
    }
}
