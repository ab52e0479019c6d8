//! `caustics` (the floor point `x0` straight to the eye) and
//! `caustics-once-more` (`x0 → x1 → eye`, `x1` placed by the once-more
//! technique: the blur with depth), docs/math.md §13.6.

use super::{Splat, UnderwaterStats, UnderwaterTerm, UnderwaterWorld, uniform3};
use crate::rng::Rng;
use crate::scenes::underwater::water::EquiangularLine;
use glam::Vec3;
use omnee_core::method::{Choice, Method};
use omnee_core::mis::OmneeMis;
use omnee_core::phase::{Deflection, PhaseFunction};
use omnee_core::sampling::{Connection, Omnee, Sample, Technique};

/// The techniques for the once-more vertex `x1` of `caustics-once-more`:
/// the scene's forms of the [`Method`]s of the same name (its light paths
/// end at the eye, so equiangular sampling starts from camera rays).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CausticsMethod {
    /// OMNEE: the deflection from the phase function, then the circumcircle arc.
    Omnee,
    /// Equiangular from a camera ray through a uniform image point.
    Equiangular,
    /// OMNEE's vertex, and with probability `rate` a camera-ray equiangular
    /// vertex kept behind θ ≥ θmin, balance heuristic there ([`OmneeMis`];
    /// the scene's defaults are [`OmneeMis::recommended`]'s 0.05 and 3π/4).
    Mis,
}

impl CausticsMethod {
    /// The scene's form of `method`; `None` for distance sampling, which
    /// this scene does not offer.
    pub fn of(method: Method) -> Option<Self> {
        match method {
            Method::Omnee => Some(Self::Omnee),
            Method::Equiangular => Some(Self::Equiangular),
            Method::Mis => Some(Self::Mis),
            Method::Distance => None,
        }
    }
}

impl From<CausticsMethod> for Choice {
    /// The name the technique goes by.
    fn from(method: CausticsMethod) -> Self {
        match method {
            CausticsMethod::Omnee => Choice::Omnee,
            CausticsMethod::Equiangular => Choice::Equiangular,
            CausticsMethod::Mis => Choice::Mis,
        }
    }
}

/// How the `caustics-once-more` term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct CausticsTechnique {
    /// The technique for `x1`.
    pub method: CausticsMethod,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
    /// The mis companion's rate `c ∈ [0, 1]`.
    pub mis_rate: f32,
    /// The mis companion's cone edge θmin.
    pub mis_theta_min: f32,
}

impl UnderwaterWorld<'_> {
    /// `caustics`: `L(x0) cos θ0 T(x0, eye) W(ω) / d²`.
    pub(super) fn caustic(
        &self,
        x0: Vec3,
        radiance: Vec3,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let Some(p) = self.camera.project(x0) else {
            return;
        };
        let v = self.camera.eye - x0;
        let d2 = v.length_squared();
        let d = d2.sqrt();
        let cos0 = v.z / d;
        if !(cos0 > 0.0) {
            return;
        }
        let value = radiance * self.water.transmittance(d) * (cos0 * p.importance / d2);
        self.splat(UnderwaterTerm::Caustics, p, value, out, stats);
    }

    /// `caustics-once-more` from the floor point `x0` leaving `radiance`
    /// (the same in every direction): for each vertex `x1` of the technique's
    /// draw, `L(x0) cos θ0 σs T(x0, x1) T(x1, eye) W(ω1) · k/pdf`, with
    /// `k/pdf` the technique's weight (`k = p(θ)/(d1² d2²)`).
    pub fn caustic_once_more(
        &self,
        x0: Vec3,
        radiance: Vec3,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let eye = self.camera.eye;
        let Ok(connection) = Connection::new(x0, eye, self.once_more.theta_max) else {
            return;
        };
        let vertices = self.draw(connection, rng);
        if vertices[0].is_none() {
            stats.no_vertex += 1;
        }
        for s in vertices.into_iter().flatten() {
            self.splat_once_more(
                UnderwaterTerm::CausticsOnceMore,
                x0,
                s,
                radiance,
                true,
                out,
                stats,
            );
        }
    }

    /// The once-more technique's vertices for `connection`.
    fn draw(&self, connection: Connection<f32>, rng: &mut Rng) -> [Option<Sample<f32>>; 2] {
        let omnee = Omnee::new(connection, &self.phase);
        let camera_rays = CameraEquiangular {
            world: self,
            connection,
        };
        match self.once_more.method {
            CausticsMethod::Omnee => [omnee.sample(uniform3(rng)), None],
            CausticsMethod::Equiangular => [camera_rays.sample(uniform3(rng)), None],
            CausticsMethod::Mis => {
                let [a, b, c] = uniform3(rng);
                let [d, e, f] = uniform3(rng);
                let theta_min = Deflection::from_theta(self.once_more.mis_theta_min);
                match OmneeMis::new(omnee, &camera_rays, self.once_more.mis_rate, theta_min) {
                    Ok(mis) => mis.sample([a, b, c, d, e, f]),
                    // The scene parser keeps the rate in [0, 1].
                    Err(_) => [omnee.sample([a, b, c]), None],
                }
            }
        }
    }
}

/// Equiangular sampling of `x1` from a camera ray through a uniform point
/// of the image, towards `x0`: the ray direction with density
/// `p_ω = 1/(4wh cos³θ)` ([`Pinhole::ray_pdf`]), the distance equiangular
/// about `x0` on the ray's water segment; in the volume measure
/// `pdf(x1) = p_ω · pdf(t) / t²`, and the weight `k/pdf = p(θ)/(d1² p_ω pdf(t))`.
struct CameraEquiangular<'w, 'a> {
    world: &'w UnderwaterWorld<'a>,
    connection: Connection<f32>,
}

impl CameraEquiangular<'_, '_> {
    fn line(&self, d: Vec3) -> Option<EquiangularLine> {
        let eye = self.world.camera.eye;
        let len = self.world.water_segment(eye, d);
        EquiangularLine::new(eye, d, len, self.connection.axis.x0)
    }
}

impl Technique<f32> for CameraEquiangular<'_, '_> {
    fn sample(&self, u: [f32; 3]) -> Option<Sample<f32>> {
        let c = &self.world.camera;
        let d = c.ray(u[0] * c.width as f32, u[1] * c.height as f32);
        let line = self.line(d)?;
        let t = line.sample(u[2]);
        if !(t > 0.0) {
            return None;
        }
        let x1 = c.eye + d * t;
        let pdf_w = c.ray_pdf(d);
        let pdf_t = line.pdf(t);
        let (deflection, d1) = self.connection.deflection_along(d, t)?;
        let weight = if deflection.theta < self.connection.theta_max {
            self.world.phase.eval(deflection) / (d1 * d1 * pdf_w * pdf_t)
        } else {
            0.0
        };
        Some(Sample {
            x1,
            pdf: pdf_w * pdf_t / (t * t),
            weight: if weight.is_finite() { weight } else { 0.0 },
        })
    }

    fn pdf(&self, x1: Vec3) -> f32 {
        let c = &self.world.camera;
        let v = x1 - c.eye;
        let t = v.length();
        if c.project(x1).is_none() || !(t > 0.0) {
            return 0.0;
        }
        let d = v / t;
        match self.line(d) {
            Some(line) if t <= self.world.water_segment(c.eye, d) => {
                c.ray_pdf(d) * line.pdf(t) / (t * t)
            }
            _ => 0.0,
        }
    }

    fn invert(&self, x1: Vec3) -> Option<[f32; 3]> {
        let c = &self.world.camera;
        let v = x1 - c.eye;
        let (x, y, _) = c.image_point(v)?;
        let t = v.length();
        let line = self.line(v / t)?;
        Some([x / c.width as f32, y / c.height as f32, line.invert(t)])
    }
}
