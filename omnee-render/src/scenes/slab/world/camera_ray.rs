//! What a camera ray sees: the radiance of each transport term along it.

use super::SlabStats;
use super::{Hit, Multiple, OnceMore, Roulette, SlabWorld};
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::term::Term;

/// How the terms are estimated along camera rays.
#[derive(Clone, Copy, Debug)]
pub struct Transport {
    /// The once-more term's technique and θmax.
    pub once_more: OnceMore,
    /// The multiple term's method and orders.
    pub multiple: Multiple,
    /// Russian roulette threshold in W/(m²·sr) (0: off).
    pub roulette: f32,
}

/// A diffuse surface point seen from the eye: where the surface terms
/// estimate irradiance.
#[derive(Clone, Copy, Debug)]
pub struct Receiver {
    /// The point.
    pub p: Vec3,
    /// Its unit normal on the side of the eye.
    pub n: Vec3,
    /// `albedo/π`: radiance per unit irradiance.
    brdf: Vec3,
    /// Transmittance from the point to the eye.
    t_cam: f32,
    /// The roulette for irradiance estimates at the point, which become
    /// radiance `t_cam · max(brdf) · E` at the eye.
    pub roulette: Roulette,
}

impl Receiver {
    /// The radiance at the eye of irradiance `e` at the point:
    /// `brdf · t_cam · e`.
    #[inline]
    pub fn radiance(&self, e: f32) -> Vec3 {
        self.brdf * (self.t_cam * e)
    }
}

/// What a camera ray `o + t d` sees, before any term draws a number: its
/// first hit and, on a surface that sends light to the eye, the receiver.
#[derive(Clone, Copy, Debug)]
pub struct CameraSample {
    o: Vec3,
    d: Vec3,
    hit: Hit,
    /// The surface point the surface terms estimate at.
    pub receiver: Option<Receiver>,
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
        ray: (Vec3, Vec3),
        terms: &[Term],
        how: &Transport,
        rng: &mut Rng,
        stats: &mut SlabStats,
        out: &mut [Vec3],
    ) {
        let sample = self.camera_sample(ray, how);
        for (term, value) in terms.iter().zip(out.iter_mut()) {
            *value = self.term(&sample, *term, how, rng, stats);
        }
    }

    /// The first hit of the camera ray `(o, d)` and its receiver.
    pub fn camera_sample(&self, (o, d): (Vec3, Vec3), how: &Transport) -> CameraSample {
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
        CameraSample {
            o,
            d,
            hit,
            receiver,
        }
    }

    /// One sample of `term` along the camera ray of `sample` (the
    /// once-more term without a receiver is 0; with one it is
    /// [`SlabWorld::once_more`]'s, which a renderer may draw in a batch).
    pub fn term(
        &self,
        sample: &CameraSample,
        term: Term,
        how: &Transport,
        rng: &mut Rng,
        stats: &mut SlabStats,
    ) -> Vec3 {
        let CameraSample {
            o,
            d,
            hit,
            receiver,
        } = *sample;
        match (term, receiver) {
            (Term::Direct, _) => match (hit, receiver) {
                (Hit::Light { t }, _) => {
                    Vec3::splat(self.light.radiance * self.transmittance(o, o + d * t))
                }
                (_, Some(r)) => r.radiance(self.direct(r.p, r.n, rng, r.roulette, stats)),
                _ => Vec3::ZERO,
            },
            (Term::OnceMore, Some(r)) => {
                r.radiance(self.once_more(r.p, r.n, how.once_more, rng, r.roulette, stats))
            }
            (Term::View, _) => {
                let roulette = Roulette::new(how.roulette);
                Vec3::splat(self.view(o, d, hit.t(), rng, roulette, stats))
            }
            (Term::Multiple, Some(r)) => {
                r.radiance(self.multiple((r.p, Some(r.n)), how.multiple, rng, r.roulette, stats))
            }
            // No receiver; or the underwater scene's terms, which the
            // slab scene's settings refuse before any sample is drawn.
            (Term::OnceMore | Term::Multiple, None)
            | (Term::Caustics | Term::CausticsOnceMore | Term::Shafts | Term::ShaftsOnceMore, _) => {
                Vec3::ZERO
            }
        }
    }
}
