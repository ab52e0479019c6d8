//! The render loop's view of the slab scene: one item is a row of the
//! crop, one camera ray per pixel per pass, each pixel sample with its own
//! random stream `(seed, pixel index in the full image, pass)`. With OMNEE
//! the row runs wavefront-style: the once-more vertices of all its pixels
//! are drawn in one call of the core's batch over connections.

use super::world::camera_ray::{CameraSample, Transport};
use super::world::once_more::{OnceMoreStart, PendingVertex, VertexBatch};
use super::world::{Multiple, OnceMore, SlabWorld};
use super::{SlabScene, SlabStats};
use crate::camera::Pinhole;
use crate::error::{RenderError, Result};
use crate::phase::TableStorage;
use crate::render::budget::RenderBudget;
use crate::render::{Integrator, Options, Progress, Rendered, Sums};
use crate::rng::Rng;
use crate::scenes::settings::{RenderReport, RenderSettings};
use crate::technique::Resolved;
use glam::Vec3;
use omnee_core::method::{Choice, Method};
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

/// A row's buffers between the stages of a wavefront row (OMNEE's vertices
/// drawn for the whole row in one call),
/// reused by the next row a thread renders.
#[derive(Default)]
pub struct Wavefront {
    /// Per pixel: its stream, what its ray saw, whether it waits for a vertex.
    pixels: Vec<(Rng, CameraSample, bool)>,
    /// The connections waiting for their vertex, in pixel order.
    pending: Vec<PendingVertex>,
    /// Their vertices.
    batch: VertexBatch,
}

impl SlabRender<'_, '_> {
    /// Pixel `(x, y)`'s random stream in pass `pass`, its jittered camera
    /// ray, and that ray's first hit.
    fn start(&self, seed: u64, pass: u32, (x, y): (u32, u32)) -> (Rng, CameraSample) {
        let index = u64::from(y) * u64::from(self.camera.width) + u64::from(x);
        let mut rng = Rng::stream(seed, index, pass as u64);
        let (jx, jy): (f32, f32) = (rng.uniform(), rng.uniform());
        let ray = (
            self.camera.eye,
            self.camera.ray(x as f32 + jx, y as f32 + jy),
        );
        let sample = self.world.camera_sample(ray, &self.transport);
        (rng, sample)
    }

    /// Row `y`'s samples, pixel by pixel, term by term.
    fn row(&self, seed: u64, pass: u32, y: u32, stats: &mut SlabStats) -> Vec<Vec3> {
        let [x0, _, x1, _] = self.crop;
        let n = self.terms.len();
        let mut out = vec![Vec3::ZERO; (x1 - x0) as usize * n];
        for (x, values) in (x0..x1).zip(out.chunks_exact_mut(n)) {
            let (mut rng, sample) = self.start(seed, pass, (x, y));
            for (term, value) in self.terms.iter().zip(values) {
                *value = self
                    .world
                    .term(&sample, *term, &self.transport, &mut rng, stats);
            }
        }
        out
    }

    /// Row `y`'s samples wavefront-style, the same numbers as [`Self::row`]
    /// (each pixel keeps its own stream): every pixel up to its once-more
    /// vertex (the terms before it, the light point, the connection, the
    /// vertex's numbers); then the OMNEE vertices of all the row's
    /// connections in one batch call; then every pixel's once-more estimate
    /// from its vertex and the terms after it. `k` is the once-more term's
    /// place among the terms.
    fn row_wavefront(
        &self,
        seed: u64,
        pass: u32,
        y: u32,
        k: usize,
        stats: &mut SlabStats,
        scratch: &mut Wavefront,
    ) -> Vec<Vec3> {
        let [x0, _, x1, _] = self.crop;
        let (n, how) = (self.terms.len(), &self.transport);
        let mut out = vec![Vec3::ZERO; (x1 - x0) as usize * n];
        let Wavefront {
            pixels,
            pending,
            batch,
        } = scratch;
        pixels.clear();
        pending.clear();
        for (x, values) in (x0..x1).zip(out.chunks_exact_mut(n)) {
            let (mut rng, sample) = self.start(seed, pass, (x, y));
            for (term, value) in self.terms[..k].iter().zip(values.iter_mut()) {
                *value = self.world.term(&sample, *term, how, &mut rng, stats);
            }
            let mut waits = false;
            if let Some(r) = sample.receiver {
                let start = self.world.once_more_start(
                    r.p,
                    r.n,
                    how.once_more,
                    &mut rng,
                    r.roulette,
                    stats,
                );
                match start {
                    OnceMoreStart::Done(e) => values[k] = r.radiance(e),
                    OnceMoreStart::Vertex(v) => {
                        pending.push(v);
                        waits = true;
                    }
                }
            }
            pixels.push((rng, sample, waits));
        }
        batch.draw(self.world, pending, how.once_more.theta_max);
        let mut lanes = pending.iter().enumerate();
        for ((rng, sample, waits), values) in pixels.iter_mut().zip(out.chunks_exact_mut(n)) {
            if let (true, Some(r)) = (*waits, sample.receiver)
                && let Some((i, v)) = lanes.next()
            {
                let vertex = batch.sample(i);
                let e = self
                    .world
                    .once_more_finish(v, (r.p, r.n), vertex, rng, r.roulette, stats);
                values[k] = r.radiance(e);
            }
            for (term, value) in self.terms[k + 1..].iter().zip(&mut values[k + 1..]) {
                *value = self.world.term(sample, *term, how, rng, stats);
            }
        }
        out
    }
}

impl Integrator for SlabRender<'_, '_> {
    type Stats = SlabStats;
    /// The row and its pixels' samples, term by term.
    type Item = (u32, Vec<Vec3>);
    type Scratch = Wavefront;

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

    fn item(
        &self,
        seed: u64,
        pass: u32,
        row: u64,
        stats: &mut SlabStats,
        scratch: &mut Wavefront,
    ) -> (u32, Vec<Vec3>) {
        let y = self.crop[1] + row as u32;
        let omnee = self.transport.once_more.method == Method::Omnee;
        match self.terms.iter().position(|t| *t == Term::OnceMore) {
            Some(k) if omnee => (y, self.row_wavefront(seed, pass, y, k, stats, scratch)),
            _ => (y, self.row(seed, pass, y, stats)),
        }
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
            budget: RenderBudget::Spp(r.spp),
            seed: r.seed,
            width: self.camera.width,
            height: self.camera.height,
            crop: None,
            terms: r.terms.clone(),
            technique: r.technique,
            theta_max: r.theta_max,
            multiple: r.multiple,
            vertices: r.vertices,
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
    let scattering = |t: &Term| matches!(t, Term::OnceMore | Term::View | Term::Multiple);
    if !world.scatters() && terms.iter().any(scattering) {
        skipped.push(
            "sigma_s = 0: once-more, view and multiple terms skipped (no scattering)".to_string(),
        );
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
            multiple: Multiple {
                method: settings.multiple,
                vertices: settings.vertices,
                mean_cosine: g as f32,
            },
            roulette: (settings.russian_roulette * scene.reference_radiance()) as f32,
        },
        crop: options.crop,
    };
    let rendered = crate::render::render(&slab, options, progress, cancel)?;
    Ok((rendered, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::slab::SlabScene;

    #[test]
    fn a_wavefront_row_is_the_pixel_by_pixel_row_bit_for_bit() {
        let scene = SlabScene::default_scene();
        for phase in ["hg:0.98", "ff:0.0183,1.1"] {
            let mut scene = scene.clone();
            scene.medium.phase = crate::phase::PhaseSpec::parse(phase).unwrap();
            // Looking up past the light: the sky and the light have no
            // receiver, the floor and the plate have one.
            scene.camera.position = [0.0, -2.5, 0.6];
            scene.camera.look_at = [0.0, 0.0, 0.9];
            scene.camera.fov_deg = 70.0;
            let mut storage = TableStorage::<f32>::default();
            let sampled = scene
                .medium
                .phase
                .sampled::<f32>(crate::phase::PhaseSampling::Table, &mut storage)
                .unwrap();
            let world = SlabWorld::new(&scene, sampled).unwrap();
            let (w, h) = (48, 36);
            let slab = SlabRender {
                world: &world,
                camera: scene.camera.pinhole(w, h),
                terms: vec![Term::Direct, Term::OnceMore, Term::View],
                transport: Transport {
                    once_more: OnceMore {
                        method: Method::Omnee,
                        theta_max: std::f32::consts::PI,
                    },
                    multiple: Multiple {
                        method: omnee_core::method::MultipleMethod::Bridge,
                        vertices: crate::vertices::VertexNumber::Auto { max: 8 },
                        mean_cosine: 0.98,
                    },
                    roulette: (1e-3 * scene.reference_radiance()) as f32,
                },
                crop: [0, 0, w, h],
            };
            let mut scratch = Wavefront::default();
            let mut lanes = 0;
            for pass in 0..3 {
                for y in 0..h {
                    let (mut a, mut b) = (SlabStats::default(), SlabStats::default());
                    let scalar = slab.row(9, pass, y, &mut a);
                    let wavefront = slab.row_wavefront(9, pass, y, 1, &mut b, &mut scratch);
                    assert_eq!(scalar, wavefront, "{phase} pass {pass} row {y}");
                    assert_eq!(a, b, "{phase} pass {pass} row {y}: the counters");
                    lanes += scratch.pending.len();
                }
            }
            // Some pixels wait for a vertex, some do not.
            let pixels = 3 * (w * h) as usize;
            assert!(
                lanes > pixels / 4 && lanes < 3 * pixels / 4,
                "{phase}: {lanes} lanes"
            );
        }
    }
}
