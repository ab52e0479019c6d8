//! The underwater scene of the talk: the sun through a wavy water surface,
//! caustics on the sand floor, blurred with depth by once-more scattered
//! connections to a camera in the water (docs/math.md §13).
//!
//! All light reaching the floor under a wavy surface is caustic: the sun
//! cannot be reached by next event estimation through a refracting surface,
//! so light is traced from the sun ([`transport`]) and each floor point `x0`
//! is connected to the eye directly (`caustics`), once more through a vertex
//! `x1` in the water (`caustics-once-more`), and points on the refracted
//! sun rays are connected to the eye directly (`shafts`) and once more
//! (`shafts-once-more`, with the phase function's lobe at those points).
//!
//! Modules, one per idea: [`surface`] (the waves and ray marching),
//! [`optics`] (refraction and Fresnel), [`sun`], [`water`] (chromatic
//! coefficients and distance sampling), [`transport`] (the light
//! paths and the four terms, and the render loop's view of them) and
//! [`file`](mod@file) (the scene file); the floor is both scenes'
//! [`crate::scenes::floor`], the camera, the pixel measurement and the
//! importance derived from it the library's one pinhole, [`crate::camera`].

pub mod file;
pub mod optics;
pub mod sun;
pub mod surface;
pub mod transport;
pub mod water;

pub use file::{
    SHAFT_TECHNIQUES, UNDERWATER_SCENE, UNDERWATER_TECHNIQUES, UnderwaterScene, UnderwaterSettings,
};
pub use transport::{UNDERWATER_TERMS, UnderwaterStats, UnderwaterWorld};

use crate::camera::Pinhole;
use crate::error::Result;
use crate::phase::TableStorage;
use crate::render::budget::RenderBudget;
use crate::render::{Options, Progress, Rendered};
use crate::scenes::settings::{RenderReport, RenderSettings};
use crate::technique::Resolved;
use omnee_core::method::{AutoReason, Choice, auto};
use omnee_core::phase::{Phase, PhaseFunction};
use omnee_core::term::Term;
use std::sync::atomic::AtomicBool;
use transport::{CausticsMethod, CausticsTechnique};

/// The method `auto` picks for `caustics-once-more`, with the reason: the
/// core's rule ([`auto`]) from the phase function's mean cosine `g` and the
/// optical thickness of the floor's depth in the clearest channel; its
/// `mis` is this scene's.
pub fn choose_technique(scene: &UnderwaterScene, g: f64) -> (CausticsMethod, AutoReason) {
    let depth = (scene.surface.z - scene.floor.z) as f64;
    let tau = scene.water.sigma_t.min_element() as f64 * depth;
    let (method, reason) = auto(g, tau);
    (
        CausticsMethod::of(method).unwrap_or(CausticsMethod::Omnee),
        reason,
    )
}

/// What the scene does not need, as sentences for the render's report:
/// the scattering terms without scattering, the surface marching for a
/// flat surface. [`UnderwaterWorld::new`] skips them.
pub fn skip_notes(scene: &UnderwaterScene) -> Vec<String> {
    let mut notes = Vec::new();
    let r = &scene.render.terms;
    if !scene.water.scatters() && r[1..].iter().any(|on| *on) {
        notes.push(
            "water.sigma_s = 0: caustics-once-more, shafts and shafts-once-more skipped (no scattering)"
                .to_string(),
        );
    }
    if scene.surface.is_flat() {
        notes.push(
            "flat surface: closed-form intersection, no marching and no wave-band visibility tests"
                .to_string(),
        );
    }
    notes
}

/// The defensive start density's tail length ℓ (docs/math.md §13.4): the
/// mean free path `1/σt` of the clearest channel, at most `max_distance`
/// (which also stands in for it in water that does not attenuate). With
/// ℓ σt ≥ 1 in every channel, the tail's density falls no faster than the
/// light a path far away can still bring to the eye.
pub fn tail_length(scene: &UnderwaterScene) -> f32 {
    let clearest = scene.water.sigma_t.min_element();
    let reach = scene.render.max_distance as f32;
    if clearest > 0.0 {
        (1.0 / clearest).min(reach)
    } else {
        reach
    }
}

impl<'a> UnderwaterWorld<'a> {
    /// The scene at `width × height` with its phase function instantiated by
    /// the caller, the terms to evaluate, and the once-more technique
    /// (`auto` resolved).
    pub fn new(scene: &UnderwaterScene, phase: Phase<'a, f32>, width: u32, height: u32) -> Self {
        let c = &scene.camera;
        let r = &scene.render;
        let method = match r.technique.method().and_then(CausticsMethod::of) {
            Some(method) => method,
            None => choose_technique(scene, phase.mean_cosine() as f64).0,
        };
        let mut terms = r.terms;
        if !scene.water.scatters() {
            // Only `caustics` needs no scattering.
            terms = [terms[0], false, false, false];
        }
        let camera = Pinhole::looking_at(c.position, c.look_at, c.up, c.fov, width, height);
        let layers = UNDERWATER_TERMS
            .into_iter()
            .zip(terms)
            .filter_map(|(t, on)| on.then_some(t))
            .collect();
        let mut world = UnderwaterWorld {
            sun: scene.sun,
            surface: scene.surface.clone(),
            ior: scene.ior,
            water: scene.water,
            phase,
            floor: scene.floor,
            camera,
            region: transport::LightRegion {
                tail: transport::TailedRect::new(glam::Vec2::ZERO, glam::Vec2::ONE, 1.0),
                offset: glam::Vec2::ZERO,
                z_top: 0.0,
                beam: glam::Vec3::NEG_Z,
                aim: transport::Aim {
                    camera: 0.0,
                    eye: 0.0,
                    eye_radius: 1.0,
                },
                cells: transport::FloorCells::new(&camera),
            },
            max_distance: r.max_distance as f32,
            terms,
            layers,
            once_more: CausticsTechnique {
                method,
                theta_max: r.theta_max as f32,
                mis_rate: r.mis_rate as f32,
                mis_theta_min: r.mis_theta_min as f32,
            },
            shafts: r.shafts,
            lobe: r.shafts_once_more,
            samples: [r.once_more_samples, r.shaft_samples],
        };
        let aim = transport::Aim {
            camera: r.camera_share as f32,
            eye: r.eye_share as f32,
            eye_radius: r.eye_radius as f32,
        };
        world.region = world.light_region(r.margin as f32, tail_length(scene), aim);
        world
    }
}

impl UnderwaterScene {
    /// The scene's render settings: its `[render]` and `[camera]` values.
    pub fn settings(&self) -> RenderSettings {
        let r = &self.render;
        RenderSettings {
            budget: RenderBudget::Spp(r.spp),
            seed: r.seed,
            width: self.camera.width,
            height: self.camera.height,
            crop: None,
            terms: UNDERWATER_TERMS
                .into_iter()
                .zip(r.terms)
                .filter_map(|(t, on)| on.then_some(t))
                .collect(),
            technique: r.technique,
            theta_max: r.theta_max,
            multiple: omnee_core::method::MultipleMethod::Bridge,
            vertices: crate::vertices::VertexNumber::Auto {
                max: crate::vertices::DEFAULT_MAX_VERTICES,
            },
            russian_roulette: 0.0,
            phase_sampling: crate::phase::PhaseSampling::Exact,
            exposure: r.exposure,
        }
    }
}

/// Renders the underwater scene with checked `settings` (their terms,
/// technique and θmax replace the scene's): light traced, `auto` resolved
/// from the water ([`choose_technique`]), what the scene does not need
/// skipped ([`skip_notes`]).
pub fn render(
    scene: &UnderwaterScene,
    settings: &RenderSettings,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
    cancel: &AtomicBool,
) -> Result<(Rendered<UnderwaterStats>, RenderReport)> {
    let mut scene = scene.clone();
    scene.render.terms = UNDERWATER_TERMS.map(|t| settings.terms.contains(&t));
    scene.render.theta_max = settings.theta_max;
    scene.render.technique = settings.technique;
    let mut storage = TableStorage::<f32>::default();
    let phase = scene.phase.instantiate::<f32>(&mut storage)?;
    let g = phase.mean_cosine() as f64;
    let world = UnderwaterWorld::new(&scene, phase, settings.width, settings.height);
    let reason = (settings.technique == Choice::Auto).then(|| choose_technique(&scene, g).1);
    let report = RenderReport {
        technique: Resolved {
            requested: settings.technique,
            used: Choice::from(world.once_more.method),
            reason,
        },
        tabulated: false,
        once_more: world.layers.contains(&Term::CausticsOnceMore),
        skipped: skip_notes(&scene),
    };
    let rendered = crate::render::render(&world, options, progress, cancel)?;
    Ok((rendered, report))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clear_water_skips_the_scattering_terms_and_says_so() {
        let text = UNDERWATER_SCENE.replacen("sigma_s = [0.25, 0.25, 0.25]", "sigma_s = 0", 1);
        let s = UnderwaterScene::parse(&text).unwrap();
        let notes = skip_notes(&s);
        assert!(notes.iter().any(|n| n.contains("sigma_s = 0")), "{notes:?}");
        let mut storage = crate::phase::TableStorage::<f32>::default();
        let w = UnderwaterWorld::new(&s, s.phase.instantiate(&mut storage).unwrap(), 16, 12);
        assert_eq!(w.terms, [true, false, false, false]);
        assert_eq!(w.layers, [omnee_core::term::Term::Caustics]);
    }

    #[test]
    fn auto_picks_omnee_for_the_forward_peaked_water() {
        let s = UnderwaterScene::builtin();
        let (tech, reason) = choose_technique(&s, 0.9);
        assert_eq!(tech, CausticsMethod::Omnee);
        assert!(reason.to_string().contains("forward-peaked"), "{reason}");
    }
}
