//! The render loop's view of the slab scene: one item is a row of the
//! crop, one camera ray per pixel per pass, each pixel sample with its own
//! random stream `(seed, pixel index in the full image, pass)`.

use super::world::camera_ray::Transport;
use super::world::{OnceMore, SlabWorld};
use super::{SlabScene, SlabStats};
use crate::camera::Pinhole;
use crate::error::{RenderError, Result};
use crate::phase::TableStorage;
use crate::render::budget::Budget;
use crate::render::{Integrator, Options, Progress, Rendered, Sums};
use crate::rng::Rng;
use crate::scenes::settings::{RenderReport, RenderSettings};
use crate::technique::Resolved;
use glam::Vec3;
use omnee_core::method::Choice;
use omnee_core::phase::PhaseFunction;
use omnee_core::term::Term;
use std::sync::atomic::AtomicBool;

/// The slab scene as the render loop runs it.
pub struct SlabRender<'w, 'a> {
    /// The scene.
    pub world: &'w SlabWorld<'a>,
    /// The camera.
    pub camera: Pinhole,
    /// The terms, distinct, in [`Term`] order: one layer each.
    pub terms: Vec<Term>,
    /// How the terms are estimated.
    pub transport: Transport,
    /// The pixel window `[x0, x1) × [y0, y1)` rendered.
    pub crop: [u32; 4],
}

impl Integrator for SlabRender<'_, '_> {
    type Stats = SlabStats;
    /// The row and its pixels' samples, term by term.
    type Item = (u32, Vec<Vec3>);

    fn size(&self) -> (u32, u32) {
        (self.camera.width, self.camera.height)
    }

    fn terms(&self) -> &[Term] {
        &self.terms
    }

    fn items(&self) -> u64 {
        u64::from(self.crop[3] - self.crop[1])
    }

    fn per_pass(&self) -> f64 {
        1.0
    }

    fn item(&self, seed: u64, pass: u32, row: u64, stats: &mut SlabStats) -> (u32, Vec<Vec3>) {
        let [x0, y0, x1, _] = self.crop;
        let y = y0 + row as u32;
        let n = self.terms.len();
        let mut out = vec![Vec3::ZERO; (x1 - x0) as usize * n];
        for (x, values) in (x0..x1).zip(out.chunks_exact_mut(n)) {
            let index = u64::from(y) * u64::from(self.camera.width) + u64::from(x);
            let mut rng = Rng::stream(seed, index, pass as u64);
            let (jx, jy): (f32, f32) = (rng.uniform(), rng.uniform());
            let ray = (
                self.camera.eye,
                self.camera.ray(x as f32 + jx, y as f32 + jy),
            );
            self.world
                .radiance(ray, &self.terms, &self.transport, &mut rng, stats, values);
        }
        (y, out)
    }

    fn add(&self, (y, values): &(u32, Vec<Vec3>), sums: &mut Sums) {
        let n = self.terms.len();
        for (x, pixel) in (self.crop[0]..).zip(values.chunks_exact(n)) {
            for (layer, v) in pixel.iter().enumerate() {
                sums.add(x, *y, layer, *v);
            }
        }
    }
}

impl SlabScene {
    /// The scene's render settings: its `[render]` and `[camera]` values.
    pub fn settings(&self) -> RenderSettings {
        let r = &self.render;
        RenderSettings {
            budget: Budget::Spp(r.spp),
            seed: r.seed,
            width: self.camera.width,
            height: self.camera.height,
            crop: None,
            terms: r.terms.clone(),
            technique: r.technique,
            theta_max: r.theta_max,
            russian_roulette: r.russian_roulette,
            phase_sampling: crate::phase::PhaseSampling::Table,
            exposure: r.exposure,
        }
    }
}

/// Renders the slab scene with checked `settings`: the phase function
/// sampled as asked, the technique resolved (`auto` from the mean cosine
/// and the optical thickness from the light to the floor), what the scene
/// does not need skipped (the scattering terms without scattering, the
/// visibility tests without an occluder).
pub fn render(
    scene: &SlabScene,
    settings: &RenderSettings,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
    cancel: &AtomicBool,
) -> Result<(Rendered<SlabStats>, RenderReport)> {
    let mut storage = TableStorage::<f32>::default();
    let phase = (scene.medium.phase).sampled::<f32>(settings.phase_sampling, &mut storage)?;
    let world = SlabWorld::new(scene, phase)?;
    let g = world.phase().mean_cosine() as f64;
    let tau = scene.medium.sigma_t() * (scene.light.center[2] - scene.floor.z);
    let (method, reason) = settings.technique.resolve(g, tau).ok_or_else(|| {
        RenderError::Input(format!("technique = {} needs a lobe", settings.technique))
    })?;
    let mut terms = settings.terms.clone();
    terms.sort();
    terms.dedup();
    let mut skipped = Vec::new();
    let scattering = |t: &Term| matches!(t, Term::OnceMore | Term::View);
    if !world.scatters() && terms.iter().any(scattering) {
        skipped.push("sigma_s = 0: once-more and view terms skipped (no scattering)".to_string());
        terms.retain(|t| !scattering(t));
    }
    if scene.occluder.is_none() {
        skipped.push("no occluder: no visibility tests".to_string());
    }
    let report = RenderReport {
        technique: Resolved {
            requested: settings.technique,
            used: Choice::from(method),
            reason,
        },
        tabulated: world.tabulated(),
        once_more: terms.contains(&Term::OnceMore),
        skipped,
    };
    let slab = SlabRender {
        world: &world,
        camera: scene.camera.pinhole(settings.width, settings.height),
        terms,
        transport: Transport {
            once_more: OnceMore {
                method,
                theta_max: settings.theta_max as f32,
            },
            roulette: (settings.russian_roulette * scene.reference_radiance()) as f32,
        },
        crop: options.crop,
    };
    let rendered = crate::render::render(&slab, options, progress, cancel)?;
    Ok((rendered, report))
}
