//! What a camera ray sees: the radiance of each transport term along it.

use super::SlabStats;
use super::{Hit, OnceMore, Roulette, SlabWorld};
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::term::Term;

/// How the terms are estimated along camera rays.
#[derive(Clone, Copy, Debug)]
pub struct Transport {
    /// The once-more term's technique and θmax.
    pub once_more: OnceMore,
    /// Russian roulette threshold in W/(m²·sr) (0: off).
    pub roulette: f32,
}

/// A diffuse surface point seen from the eye.
struct Receiver {
    p: Vec3,
    n: Vec3,
    /// `albedo/π`: radiance per unit irradiance.
    brdf: Vec3,
    /// Transmittance from the point to the eye.
    t_cam: f32,
    /// The roulette for irradiance estimates at the point, which become
    /// radiance `t_cam · max(brdf) · E` at the eye.
    roulette: Roulette,
}

impl Hit {
    /// The ray parameter of the hit (infinite for a miss).
    pub fn t(&self) -> f32 {
        match *self {
            Hit::Miss => f32::INFINITY,
            Hit::Light { t } | Hit::Surface { t, .. } => t,
        }
    }
}

impl SlabWorld<'_> {
    /// One sample of the radiance along the camera ray `o + t d` (unit `d`)
    /// for each of `terms` (distinct, in [`Term`] order, which is the order
    /// they draw their random numbers in): `out[k]` for `terms[k]`.
    pub fn radiance(
        &self,
        (o, d): (Vec3, Vec3),
        terms: &[Term],
        how: &Transport,
        rng: &mut Rng,
        stats: &mut SlabStats,
        out: &mut [Vec3],
    ) {
        let hit = self.intersect(o, d);
        let receiver = match hit {
            Hit::Surface { p, n, albedo, .. } => {
                let t_cam = self.transmittance(o, p);
                let brdf = albedo * std::f32::consts::FRAC_1_PI;
                let scale = t_cam * brdf.max_element();
                // A surface that sends nothing to the eye gets no estimates.
                (scale > 0.0).then(|| Receiver {
                    p,
                    n,
                    brdf,
                    t_cam,
                    roulette: Roulette::new(how.roulette).scaled(scale),
                })
            }
            _ => None,
        };
        for (term, value) in terms.iter().zip(out.iter_mut()) {
            *value = match term {
                Term::Direct => match (hit, &receiver) {
                    (Hit::Light { t }, _) => {
                        Vec3::splat(self.light.radiance * self.transmittance(o, o + d * t))
                    }
                    (_, Some(r)) => {
                        r.brdf * (r.t_cam * self.direct(r.p, r.n, rng, r.roulette, stats))
                    }
                    _ => Vec3::ZERO,
                },
                Term::OnceMore => match &receiver {
                    Some(r) => {
                        let e = self.once_more(r.p, r.n, how.once_more, rng, r.roulette, stats);
                        r.brdf * (r.t_cam * e)
                    }
                    None => Vec3::ZERO,
                },
                Term::View => {
                    let roulette = Roulette::new(how.roulette);
                    Vec3::splat(self.view(o, d, hit.t(), rng, roulette, stats))
                }
                // The underwater scene's terms: `render` refuses them for
                // this scene (term::check) before any sample is drawn.
                Term::Caustics | Term::CausticsOnceMore | Term::Shafts | Term::ShaftsOnceMore => {
                    Vec3::ZERO
                }
            };
        }
    }
}
