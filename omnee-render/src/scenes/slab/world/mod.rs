//! The slab scene in the renderer's precision (f32) and its light
//! transport, shared by `render` and `probe`:
//!
//! - the scene's parts, one file each: [`light`] (sphere or point light and
//!   the ways to choose a point on it), [`slab`] (the medium: transmittance,
//!   reach), [`plate`] (the occluder); the floor is both scenes'
//!   [`Floor`];
//! - the transport terms, one file each: [`direct`], [`once_more`] (the
//!   OMNEE term), [`view`] (single scattering along camera rays),
//!   [`multiple`] (2 … K vertices: bridges or path tracing), with
//!   [`roulette`] before their visibility tests;
//! - [`camera_ray`]: what a camera ray sees, term by term.
//!
//! Units: the light's radiance in W/(m²·sr) (or a point light's intensity in
//! W/sr), lengths in m, coefficients in 1/m; the surface estimators return
//! irradiance (W/m²), the view estimator radiance.

pub mod camera_ray;
pub mod direct;
pub mod light;
pub mod multiple;
pub mod once_more;
pub mod plate;
pub mod roulette;
pub mod slab;
pub mod view;

pub use super::stats::SlabStats;
pub use light::Light;
pub use multiple::Multiple;
pub use once_more::OnceMore;
pub use plate::Plate;
pub use roulette::Roulette;
pub use slab::Slab;

use super::SlabScene;
use crate::error::{RenderError, Result};
use crate::phase::Sampled;
use crate::scenes::floor::{Floor, FloorPattern};
use glam::Vec3;
use omnee_core::method::Setup;
use omnee_core::phase::Phase;
use omnee_core::sampling::Directions;

/// What a camera ray hits first.
#[derive(Clone, Copy, Debug)]
pub enum Hit {
    /// Nothing.
    Miss,
    /// The light's sphere at distance `t`.
    Light {
        /// Ray parameter.
        t: f32,
    },
    /// A diffuse surface.
    Surface {
        /// Ray parameter.
        t: f32,
        /// The point.
        p: Vec3,
        /// Unit normal on the side of the ray origin.
        n: Vec3,
        /// RGB albedo.
        albedo: Vec3,
    },
}

/// The scene in f32, ready to trace.
pub struct SlabWorld<'a> {
    /// The medium.
    pub slab: Slab,
    /// The floor.
    pub floor: Floor,
    /// The light.
    pub light: Light,
    /// The occluder.
    pub plate: Option<Plate>,
    /// The once-more methods' phase function (sampled exactly or through
    /// its table, [`Sampled`]), region and σt, with rays from the receiver
    /// in all directions (OMNEE's; the ray methods get cosine-weighted ones
    /// per receiver).
    setup: Setup<f32, Sampled<'a, f32>>,
}

fn v3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

impl<'a> SlabWorld<'a> {
    /// The scene in f32 with its phase function instantiated by the caller:
    /// a [`Phase`] (sampled exactly) or a [`Sampled`] one
    /// ([`PhaseSpec::sampled`](crate::phase::PhaseSpec::sampled)), which the
    /// once-more term draws its deflections from. Fails when the medium's
    /// coefficients do not fit f32.
    pub fn new(scene: &SlabScene, phase: impl Into<Sampled<'a, f32>>) -> Result<Self> {
        let phase = phase.into();
        let m = &scene.medium;
        let l = &scene.light;
        let slab = Slab {
            z_min: m.z_min as f32,
            z_max: m.z_max as f32,
            sigma_s: m.sigma_s as f32,
            sigma_t: m.sigma_t() as f32,
        };
        let setup =
            Setup::new(phase, Directions::Sphere, slab.region(), slab.sigma_t).map_err(|e| {
                RenderError::Input(format!(
                    "medium.sigma_s + medium.sigma_a in the renderer's f32: {e}"
                ))
            })?;
        let f = &scene.floor;
        Ok(SlabWorld {
            slab,
            floor: Floor {
                z: f.z as f32,
                pattern: FloorPattern::Checker,
                size: f.checker_size as f32,
                albedo_a: v3(f.albedo_a),
                albedo_b: v3(f.albedo_b),
            },
            light: Light {
                center: v3(l.center),
                radius: l.radius as f32,
                radiance: l.radiance as f32,
                intensity: l.intensity as f32,
            },
            plate: scene.occluder.as_ref().map(|o| {
                Plate::new(
                    v3(o.center),
                    [o.size[0] as f32, o.size[1] as f32],
                    o.pattern,
                    o.period as f32,
                    o.opening as f32,
                    v3(o.albedo),
                )
            }),
            setup,
        })
    }

    /// The phase function of the medium.
    pub fn phase(&self) -> &Phase<'a, f32> {
        self.setup.phase().phase()
    }

    /// The phase function as the scattering terms sample it (exactly or
    /// through its table).
    pub fn sampler(&self) -> &Sampled<'a, f32> {
        self.setup.phase()
    }

    /// Whether the once-more term draws deflections from a table.
    pub fn tabulated(&self) -> bool {
        self.setup.phase().is_tabulated()
    }

    /// Whether the medium scatters at all.
    pub fn scatters(&self) -> bool {
        self.slab.scatters()
    }

    /// Transmittance between two points ([`Slab::transmittance`]).
    pub fn transmittance(&self, a: Vec3, b: Vec3) -> f32 {
        self.slab.transmittance(a, b)
    }

    /// Whether the occluder blocks `a → b` (counts the test; no occluder, no test).
    fn occluded(&self, a: Vec3, b: Vec3, stats: &mut SlabStats) -> bool {
        match &self.plate {
            None => false,
            Some(plate) => {
                stats.visibility_tests += 1;
                plate.blocks(a, b)
            }
        }
    }

    /// The first thing the ray `o + t d` (unit `d`) hits.
    pub fn intersect(&self, o: Vec3, d: Vec3) -> Hit {
        let mut best = Hit::Miss;
        let mut t_best = f32::INFINITY;
        if let Some((t, p)) = self.floor.hit(o, d) {
            t_best = t;
            best = Hit::Surface {
                t,
                p,
                n: Vec3::Z,
                albedo: self.floor.albedo(p.truncate()),
            };
        }
        if let Some(plate) = &self.plate
            && let Some((t, p, n)) = plate.hit(o, d).filter(|h| h.0 < t_best)
        {
            t_best = t;
            best = Hit::Surface {
                t,
                p,
                n,
                albedo: plate.albedo,
            };
        }
        if let Some(t) = self.light.hit(o, d).filter(|&t| t < t_best) {
            best = Hit::Light { t };
        }
        best
    }
}
