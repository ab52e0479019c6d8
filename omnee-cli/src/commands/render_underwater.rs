//! `omnee render --scene underwater` (or a scene file with a `[sun]`
//! section): the underwater scene, light traced, each term in its own EXR
//! layer. The options are `render`'s; `--russian-roulette` does not apply
//! and `--technique distance` is not one of this scene's techniques.

use super::render::{Defaults, ProgressMode, RenderArgs, Settings, write_images};
use crate::error::{CliError, Result};
use crate::parallel::with_threads;
use crate::phase::TableStorage;
use crate::scene::{Builtin, Source};
use crate::technique::Technique;
use crate::term::{self, Term};
use crate::underwater::render::{self, Rendered};
use crate::underwater::scene::{TechniqueChoice, UnderwaterScene};
use crate::underwater::transport::{OnceMoreTech, TERMS, World};
use crate::underwater::{choose_technique, skip_notes};
use omnee_core::phase::PhaseFunction;

/// The underwater scene `source` names, if it is one: the built-in
/// `underwater`, or a file with a `[sun]` section.
pub fn scene(source: &Source) -> Result<Option<UnderwaterScene>> {
    match source {
        Source::Builtin(Builtin::Underwater) => Ok(Some(UnderwaterScene::builtin())),
        Source::Builtin(_) => Ok(None),
        Source::File(path) => {
            let Ok(text) = std::fs::read_to_string(path) else {
                return Ok(None); // the slab loader reports it
            };
            let is_underwater = text
                .parse::<toml::Table>()
                .is_ok_and(|root| root.contains_key("sun"));
            if is_underwater {
                UnderwaterScene::parse(&text)
                    .map(Some)
                    .map_err(|e| e.context(&path.display().to_string()))
            } else {
                Ok(None)
            }
        }
    }
}

/// The scene's technique as the CLI's name.
fn requested(t: TechniqueChoice) -> Technique {
    match t {
        TechniqueChoice::Fixed(OnceMoreTech::Omnee) => Technique::Omnee,
        TechniqueChoice::Fixed(OnceMoreTech::Equiangular) => Technique::Equiangular,
        TechniqueChoice::Fixed(OnceMoreTech::Mis) => Technique::Mis,
        TechniqueChoice::Auto => Technique::Auto,
    }
}

/// `omnee render` of an underwater scene.
pub fn run(a: RenderArgs, mut scene: UnderwaterScene) -> Result<()> {
    if let Some(r) = a.russian_roulette {
        return Err(CliError::Input(format!(
            "--russian-roulette = {r} does not apply to the underwater scene (light tracing splats every path); allowed: leave it out"
        )));
    }
    let r = &scene.render;
    let set = Settings::with_defaults(
        &a,
        &Defaults {
            spp: r.spp,
            seed: r.seed,
            width: scene.camera.width,
            height: scene.camera.height,
            terms: term::UNDERWATER
                .iter()
                .zip(r.terms)
                .filter(|(_, on)| *on)
                .map(|(t, _)| *t)
                .collect(),
            theta_max: r.theta_max,
            russian_roulette: 0.0,
            exposure: r.exposure,
            technique: requested(r.technique),
        },
    )?;
    term::check("--terms", &set.terms, &term::UNDERWATER, "underwater")?;
    scene.render.terms = term::UNDERWATER.map(|t| set.terms.contains(&t));
    scene.render.theta_max = set.theta_max;
    scene.render.technique = match set.technique {
        Technique::Omnee => TechniqueChoice::Fixed(OnceMoreTech::Omnee),
        Technique::Equiangular => TechniqueChoice::Fixed(OnceMoreTech::Equiangular),
        Technique::Mis => TechniqueChoice::Fixed(OnceMoreTech::Mis),
        Technique::Auto => TechniqueChoice::Auto,
        Technique::Distance => {
            return Err(CliError::Input(
                "--technique = distance is not a technique of the underwater scene; allowed: omnee, equiangular, mis, auto"
                    .into(),
            ));
        }
    };

    let mut storage = TableStorage::<f32>::default();
    let phase = scene.phase.instantiate::<f32>(&mut storage)?;
    let g = phase.mean_cosine() as f64;
    let world = World::new(&scene, phase, set.width, set.height);
    let reason =
        (scene.render.technique == TechniqueChoice::Auto).then(|| choose_technique(&scene, g).1);
    let notes = skip_notes(&scene);
    let say = |line: &str| {
        if !a.json {
            println!("{line}");
        }
    };
    if world.enabled(Term::CausticsOnceMore) {
        match &reason {
            Some(r) => say(&format!(
                "technique: auto picked {}: {r}",
                world.once_more.tech.name()
            )),
            None => say(&format!("technique: {}", world.once_more.tech.name())),
        }
    }
    for n in &notes {
        say(&format!("skip: {n}"));
    }
    let options = render::Options {
        budget: set.budget,
        seed: set.seed,
        crop: set.crop,
        progress: a.progress == ProgressMode::Auto,
    };
    let out = with_threads(a.threads, || render::render(&world, &options))?;
    let ev = write_images(&a, &set, &out.layers, &say)?;
    if a.json {
        let terms: Vec<String> = set.terms.iter().map(Term::to_string).collect();
        println!(
            "{}",
            summary_json(&set, &terms, &world, reason, &notes, &out, ev)
        );
    } else {
        let st = out.stats;
        let [x0, y0, x1, y1] = set.crop;
        say(&format!(
            "rendered {}x{} ({} pixels), {} passes of {} light paths in {:.2} s",
            set.width,
            set.height,
            (x1 - x0) * (y1 - y0),
            out.passes,
            set.width * set.height,
            out.seconds
        ));
        say(&format!(
            "light paths {}: outside the lit region {}, lost at the surface {}, on the floor {}; \
             splats: {}; no once-more vertex {}; wave-band tests {}",
            st.paths,
            st.outside_region,
            st.lost_at_surface,
            st.floor_hits,
            st.splats_by_term(),
            st.no_vertex,
            st.surface_tests
        ));
        if let Some(path) = &set.exr {
            say(&format!(
                "wrote {} (layers: {})",
                path.display(),
                out.layers.names()
            ));
        }
        if let Some(path) = &set.png {
            say(&format!(
                "wrote {} (exposure {ev:+.2} stops)",
                path.display()
            ));
        }
    }
    Ok(())
}

/// The `--json` summary.
fn summary_json(
    set: &Settings,
    terms: &[String],
    world: &World<'_>,
    reason: Option<String>,
    notes: &[String],
    out: &Rendered,
    ev: f64,
) -> serde_json::Value {
    let st = out.stats;
    serde_json::json!({
        "scene": "underwater",
        "width": set.width, "height": set.height, "crop": set.crop, "spp": out.passes,
        "seconds": out.seconds, "seed": set.seed, "terms": terms,
        "technique": world.once_more.tech.name(), "technique_requested": set.technique.to_string(),
        "auto_reason": reason, "theta_max": set.theta_max, "exposure": ev,
        "skipped": notes,
        "stats": {
            "paths": st.paths, "outside_region": st.outside_region,
            "lost_at_surface": st.lost_at_surface, "floor_hits": st.floor_hits,
            "splats": TERMS.iter().zip(st.splats).map(|(t, n)| (t.to_string(), serde_json::json!(n)))
                .collect::<serde_json::Map<_, _>>(),
            "no_vertex": st.no_vertex, "surface_tests": st.surface_tests,
        },
        "exr": set.exr.as_ref().map(|p| p.display().to_string()),
        "png": set.png.as_ref().map(|p| p.display().to_string()),
    })
}
