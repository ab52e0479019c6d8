//! `omnee render`: the scene seen by the pinhole camera, each transport
//! term in its own EXR layer, written to `BASE.exr` and a tone-mapped
//! `BASE.png`.

use super::args::{parse_resolution, parse_u32x4};
use crate::camera::Pinhole;
use crate::error::{CliError, Result};
use crate::image::{self, Layers};
use crate::output::{check_output, with_ext};
use crate::parallel::with_threads;
use crate::phase::{PhaseSampling, TableStorage};
use crate::range::Range;
use crate::render::budget::Budget;
use crate::render::{self, Rendered};
use crate::scene::{self, Scene};
use crate::technique::{self, Choice, OnceMore, Technique};
use crate::term::Term;
use crate::world::World;
use crate::world::camera_ray::Transport;
use clap::{Args, ValueEnum};
use omnee_core::phase::PhaseFunction;
use std::path::PathBuf;

/// Output formats of `render`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ImageFormat {
    /// OpenEXR and PNG
    Both,
    /// OpenEXR only
    Exr,
    /// PNG only
    Png,
}

/// When `render` draws its progress bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProgressMode {
    /// on stderr when it is a terminal
    Auto,
    /// not at all
    Never,
}

/// The options of `omnee render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene: a built-in name or a scene file (TOML).
    #[arg(long, value_parser = scene::Source::parse, default_value = "default")]
    pub scene: scene::Source,
    /// Samples per pixel (default: the scene's render.spp).
    #[arg(long, conflicts_with = "time")]
    pub spp: Option<u32>,
    /// Time budget in seconds: whole passes of one sample per pixel until the next would not fit.
    #[arg(long)]
    pub time: Option<f64>,
    /// Random seed (default: the scene's render.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Resolution WIDTHxHEIGHT (default: the scene's camera.width and height).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Render only the pixels [X0, X1) x [Y0, Y1); the rest of the image is 0 (see `merge`).
    #[arg(long, value_parser = parse_u32x4, value_name = "X0,Y0,X1,Y1")]
    pub crop: Option<[u32; 4]>,
    /// Comma-separated transport terms (default: the scene's render.terms).
    #[arg(long, value_enum, value_delimiter = ',', value_name = "TERM")]
    pub terms: Option<Vec<Term>>,
    /// Technique for the once-more term (default: the scene's render.technique).
    #[arg(long, value_enum)]
    pub technique: Option<Technique>,
    /// Restrict the once-more integrand to deflections theta < THETA_MAX (radians, (0, pi]).
    #[arg(long)]
    pub theta_max: Option<f64>,
    /// How the once-more and view terms draw deflections from the medium's phase function (slab scenes).
    #[arg(long, value_enum, value_name = "HOW", default_value_t = PhaseSampling::Table)]
    pub phase_sampling: PhaseSampling,
    /// Russian roulette threshold as a fraction of the scene's reference radiance (0: off).
    #[arg(long)]
    pub russian_roulette: Option<f64>,
    /// PNG exposure in stops (default: automatic).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f64>,
    /// Output base name: writes BASE.exr and BASE.png.
    #[arg(short, long, default_value = "omnee")]
    pub output: PathBuf,
    /// Which files to write.
    #[arg(long, value_enum, default_value_t = ImageFormat::Both)]
    pub format: ImageFormat,
    /// Also write each term's layer as BASE.TERM.png, with the sum's exposure.
    #[arg(long)]
    pub png_layers: bool,
    /// Progress bar on stderr.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// What a scene gives when an option is left out.
pub(super) struct Defaults {
    pub(super) spp: u32,
    pub(super) seed: u64,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) terms: Vec<Term>,
    pub(super) theta_max: f64,
    pub(super) russian_roulette: f64,
    pub(super) exposure: Option<f64>,
    pub(super) technique: Technique,
}

/// The options checked against their ranges, the scene's settings filled in.
pub(super) struct Settings {
    pub(super) budget: Budget,
    pub(super) seed: u64,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) crop: [u32; 4],
    /// As asked for (reported as given).
    pub(super) terms: Vec<Term>,
    pub(super) theta_max: f64,
    pub(super) russian_roulette: f64,
    pub(super) exposure: Option<f64>,
    pub(super) technique: Technique,
    pub(super) exr: Option<PathBuf>,
    pub(super) png: Option<PathBuf>,
}

impl Settings {
    /// Checks `a`, taking what it leaves out from the scene's `[render]`
    /// and `[camera]`; also checks that the outputs' folder exists.
    fn new(a: &RenderArgs, scene: &Scene) -> Result<Self> {
        let r = &scene.render;
        Self::with_defaults(
            a,
            &Defaults {
                spp: r.spp,
                seed: r.seed,
                width: scene.camera.width,
                height: scene.camera.height,
                terms: r.terms.clone(),
                theta_max: r.theta_max,
                russian_roulette: r.russian_roulette,
                exposure: r.exposure,
                technique: r.technique,
            },
        )
    }

    /// Checks `a`, taking what it leaves out from `s`; also checks that the
    /// outputs' folder exists.
    pub(super) fn with_defaults(a: &RenderArgs, s: &Defaults) -> Result<Self> {
        let budget = match (a.spp, a.time) {
            (Some(n), _) => {
                Range::closed(1.0, (1u64 << 24) as f64).check("--spp", n as f64)?;
                Budget::Spp(n)
            }
            (None, Some(t)) => Budget::Seconds(Range::POSITIVE.check("--time", t)?),
            (None, None) => Budget::Spp(s.spp),
        };
        let (width, height) = a.resolution.unwrap_or((s.width, s.height));
        let crop = a.crop.unwrap_or([0, 0, width, height]);
        if !(crop[0] < crop[2] && crop[1] < crop[3] && crop[2] <= width && crop[3] <= height) {
            return Err(CliError::range(
                "--crop",
                format!("{},{},{},{}", crop[0], crop[1], crop[2], crop[3]),
                format!("X0 < X1 <= {width}, Y0 < Y1 <= {height}"),
            ));
        }
        let optional = |range: Range, field: &str, x: Option<f64>| {
            x.map(|x| range.check(field, x)).transpose()
        };
        let theta_max = optional(Range::THETA_MAX, "--theta-max", a.theta_max)?;
        let roulette = optional(Range::UNIT, "--russian-roulette", a.russian_roulette)?;
        let exposure = optional(Range::EXPOSURE, "--exposure", a.exposure)?;
        let exr = matches!(a.format, ImageFormat::Both | ImageFormat::Exr)
            .then(|| with_ext(&a.output, "exr"));
        let png = matches!(a.format, ImageFormat::Both | ImageFormat::Png)
            .then(|| with_ext(&a.output, "png"));
        if let Some(p) = &exr {
            check_output("--output", p)?;
        }
        if png.is_some() || a.png_layers {
            check_output("--output", &with_ext(&a.output, "png"))?;
        }
        Ok(Settings {
            budget,
            seed: a.seed.unwrap_or(s.seed),
            width,
            height,
            crop,
            terms: a.terms.clone().unwrap_or_else(|| s.terms.clone()),
            theta_max: theta_max.unwrap_or(s.theta_max),
            russian_roulette: roulette.unwrap_or(s.russian_roulette),
            exposure: exposure.or(s.exposure),
            technique: a.technique.unwrap_or(s.technique),
            exr,
            png,
        })
    }
}

/// `omnee render`.
pub fn run(a: RenderArgs) -> Result<()> {
    if let Some(scene) = super::render_underwater::scene(&a.scene)? {
        return super::render_underwater::run(a, scene);
    }
    let scene = Scene::from_source(&a.scene)?;
    let set = Settings::new(&a, &scene)?;
    crate::term::check("--terms", &set.terms, &crate::term::SLAB, "slab")?;
    let mut storage = TableStorage::<f32>::default();
    let phase = (scene.medium.phase).sampled::<f32>(a.phase_sampling, &mut storage)?;
    let world = World::new(&scene, phase)?;
    let g = world.phase().mean_cosine() as f64;
    let tau = scene.medium.sigma_t() * (scene.light.center[2] - scene.floor.z);
    let choice = technique::choose(set.technique, g, tau);

    // Skip what the scene does not need, and say so.
    let mut terms = set.terms.clone();
    terms.sort();
    terms.dedup();
    let mut notes = Vec::new();
    let scattering = |t: &Term| matches!(t, Term::OnceMore | Term::View);
    if !world.scatters() && terms.iter().any(scattering) {
        notes.push("sigma_s = 0: once-more and view terms skipped (no scattering)".to_string());
        terms.retain(|t| !scattering(t));
    }
    if scene.occluder.is_none() {
        notes.push("no occluder: no visibility tests".to_string());
    }
    let say = |line: &str| {
        if !a.json {
            println!("{line}");
        }
    };
    if terms.contains(&Term::OnceMore) {
        match &choice.reason {
            Some(r) => say(&format!(
                "technique: auto picked {}: {r}",
                choice.method.name()
            )),
            None => say(&format!("technique: {}", choice.method.name())),
        }
        if world.tabulated() {
            say("phase sampling: tabulated inverse CDF, p/q in the weight");
        }
    }
    for n in &notes {
        say(&format!("skip: {n}"));
    }

    let transport = Transport {
        once_more: OnceMore {
            method: choice.method,
            theta_max: set.theta_max as f32,
        },
        roulette: (set.russian_roulette * scene.reference_radiance()) as f32,
    };
    let options = render::Options {
        budget: set.budget,
        seed: set.seed,
        width: set.width,
        height: set.height,
        crop: set.crop,
        terms: terms.clone(),
        progress: a.progress == ProgressMode::Auto,
    };
    let camera = Pinhole::new(&scene.camera, set.width, set.height);
    let out = with_threads(a.threads, || {
        render::render(&options, |x, y, rng, stats, radiance| {
            let ray = (camera.eye, camera.ray(x, y));
            world.radiance(ray, &terms, &transport, rng, stats, radiance);
        })
    })?;
    let ev = write_images(&a, &set, &out.layers, &say)?;
    if a.json {
        let sampling = phase_sampling_json(&world);
        println!(
            "{}",
            summary_json(&set, &choice, sampling, &notes, &out, ev)
        );
    } else {
        summary_text(&set, &out, ev, &say);
    }
    Ok(())
}

/// Writes the EXR, the PNG and the layer PNGs asked for; returns the PNG's
/// exposure (stops).
pub(super) fn write_images(
    a: &RenderArgs,
    set: &Settings,
    layers: &Layers,
    say: &dyn Fn(&str),
) -> Result<f64> {
    let (srgb, ev) = image::tone_map(layers.get("").unwrap_or(&[]), set.exposure);
    if let Some(path) = &set.exr {
        image::write_exr(path, layers)?;
    }
    if let Some(path) = &set.png {
        image::write_png(path, layers.width, layers.height, &srgb)?;
    }
    if a.png_layers {
        for (name, data) in layers.layers.iter().filter(|(n, _)| !n.is_empty()) {
            let path = with_ext(&a.output, &format!("{name}.png"));
            let (srgb, _) = image::tone_map(data, Some(ev));
            image::write_png(&path, layers.width, layers.height, &srgb)?;
            say(&format!("wrote {}", path.display()));
        }
    }
    Ok(ev)
}

/// How the once-more term sampled the phase function, for the summaries:
/// `table` or `exact`.
pub(super) fn phase_sampling_json(world: &World<'_>) -> &'static str {
    if world.tabulated() { "table" } else { "exact" }
}

/// The `--json` summary.
fn summary_json(
    set: &Settings,
    choice: &Choice,
    phase_sampling: &str,
    notes: &[String],
    out: &Rendered,
    ev: f64,
) -> serde_json::Value {
    let st = out.stats;
    let terms: Vec<String> = set.terms.iter().map(Term::to_string).collect();
    serde_json::json!({
        "width": set.width, "height": set.height, "crop": set.crop, "spp": out.spp,
        "seconds": out.seconds, "seed": set.seed, "terms": terms,
        "technique": choice.method.name(), "technique_requested": choice.requested.to_string(),
        "auto_reason": choice.reason, "phase_sampling": phase_sampling, "theta_max": set.theta_max, "exposure": ev,
        "skipped": notes,
        "stats": {
            "connections": st.connections, "skipped_unreachable": st.skipped_unreachable,
            "no_vertex": st.no_vertex, "roulette_dropped": st.roulette_dropped,
            "roulette_kept": st.roulette_kept, "visibility_tests": st.visibility_tests,
        },
        "exr": set.exr.as_ref().map(|p| p.display().to_string()),
        "png": set.png.as_ref().map(|p| p.display().to_string()),
    })
}

/// The text summary: size, samples, time, the work counters, the files.
fn summary_text(set: &Settings, out: &Rendered, ev: f64, say: &dyn Fn(&str)) {
    let [x0, y0, x1, y1] = set.crop;
    let st = out.stats;
    say(&format!(
        "rendered {}x{} ({} pixels), {} spp in {:.2} s",
        set.width,
        set.height,
        (x1 - x0) * (y1 - y0),
        out.spp,
        out.seconds
    ));
    say(&format!(
        "once-more connections {}, not sampled (theta < theta_max cannot reach the slab) {}, no vertex {}; \
         roulette dropped {} kept {}; visibility tests {}",
        st.connections,
        st.skipped_unreachable,
        st.no_vertex,
        st.roulette_dropped,
        st.roulette_kept,
        st.visibility_tests
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
