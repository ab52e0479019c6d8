//! `omnee render`: a scene (the slab scene by default, or the underwater
//! one) seen by its camera, each transport term in its own EXR layer,
//! written to `BASE.exr` and a tone-mapped `BASE.png`. The options override
//! the scene's `[render]` and `[camera]` settings; the library checks and
//! renders ([`omnee_render::scenes::Scene::render`]).

use super::args::{
    parse_max_vertices, parse_resolution, parse_spp, parse_threads, parse_u32x4, parse_vertices,
    with_max,
};
use super::probe::parse_source;
use crate::named::closed;
use crate::progress::Bar;
use clap::Args;
use omnee_core::method::{Choice, MultipleMethod};
use omnee_core::names::Named;
use omnee_core::term::Term;
use omnee_render::error::Spelling;
use omnee_render::files::{check_output, with_ext, write_exr, write_png};
use omnee_render::image::{Layers, tone_map};
use omnee_render::parallel::with_threads;
use omnee_render::phase::PhaseSampling;
use omnee_render::render::Rendered;
use omnee_render::render::budget::RenderBudget;
use omnee_render::scenes::underwater::UNDERWATER_TERMS;
use omnee_render::scenes::{RenderReport, RenderSettings, Scene, SceneStats, Source};
use omnee_render::vertices::VertexNumber;
use omnee_render::{RenderError, Result};
use serde_json::json;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// Output formats of `render`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// OpenEXR and PNG.
    Both,
    /// OpenEXR only.
    Exr,
    /// PNG only.
    Png,
}

impl Named for ImageFormat {
    const ALL: &'static [Self] = &[ImageFormat::Both, ImageFormat::Exr, ImageFormat::Png];
    fn name(self) -> &'static str {
        match self {
            ImageFormat::Both => "both",
            ImageFormat::Exr => "exr",
            ImageFormat::Png => "png",
        }
    }
    fn help(self) -> &'static str {
        match self {
            ImageFormat::Both => "OpenEXR and PNG",
            ImageFormat::Exr => "OpenEXR only",
            ImageFormat::Png => "PNG only",
        }
    }
}

/// When `render` draws its progress bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressMode {
    /// On stderr when it is a terminal.
    Auto,
    /// Not at all.
    Never,
}

impl Named for ProgressMode {
    const ALL: &'static [Self] = &[ProgressMode::Auto, ProgressMode::Never];
    fn name(self) -> &'static str {
        match self {
            ProgressMode::Auto => "auto",
            ProgressMode::Never => "never",
        }
    }
    fn help(self) -> &'static str {
        match self {
            ProgressMode::Auto => "on stderr when it is a terminal",
            ProgressMode::Never => "not at all",
        }
    }
}

/// The options of `omnee render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene: a built-in name or a scene file (TOML).
    #[arg(long, value_parser = parse_source, default_value = "default")]
    pub scene: Source,
    /// Samples per pixel, [1, 2^24] and at most 2^40 samples in all (default: the scene's render.spp).
    #[arg(long, conflicts_with = "time", value_parser = parse_spp, allow_hyphen_values = true)]
    pub spp: Option<u32>,
    /// Time budget in seconds, (0, 604800]: whole passes of one sample per pixel until the next would not fit (at most 2^24).
    #[arg(long, allow_hyphen_values = true)]
    pub time: Option<f64>,
    /// Random seed (default: the scene's render.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (0: one per core; at most 1024).
    #[arg(long, default_value_t = 0, value_parser = parse_threads, allow_hyphen_values = true)]
    pub threads: usize,
    /// Resolution WIDTHxHEIGHT (default: the scene's camera.width and height).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Render only the pixels [X0, X1) x [Y0, Y1); the rest of the image is 0 (see `merge`).
    #[arg(long, value_parser = parse_u32x4, value_name = "X0,Y0,X1,Y1")]
    pub crop: Option<[u32; 4]>,
    /// Comma-separated transport terms (default: the scene's render.terms).
    #[arg(long, value_parser = closed::<Term>(), value_delimiter = ',', value_name = "TERM")]
    pub terms: Option<Vec<Term>>,
    /// Technique for the once-more term (default: the scene's render.technique).
    #[arg(long, value_parser = closed::<Choice>())]
    pub technique: Option<Choice>,
    /// Restrict the once-more integrand to deflections theta < THETA_MAX (radians, (0, pi]).
    #[arg(long, allow_hyphen_values = true)]
    pub theta_max: Option<f64>,
    /// How the multiple term is estimated (slab scenes; default: the scene's render.multiple).
    #[arg(long, value_parser = closed::<MultipleMethod>(), value_name = "METHOD")]
    pub multiple: Option<MultipleMethod>,
    /// The multiple term's orders: K in [2, 32] (light scattered exactly K times) or auto (2 ... --max-vertices, drawn per connection by bridges); default: the scene's render.vertices.
    #[arg(long, value_parser = parse_vertices, value_name = "K|auto", allow_hyphen_values = true)]
    pub vertices: Option<VertexNumber>,
    /// The largest order of --vertices auto (default: the scene's render.max_vertices).
    #[arg(long, value_name = "K", value_parser = parse_max_vertices, allow_hyphen_values = true)]
    pub max_vertices: Option<usize>,
    /// How the once-more and view terms draw deflections from the medium's phase function (slab scenes).
    #[arg(long, value_parser = closed::<PhaseSampling>(), value_name = "HOW", default_value = "table")]
    pub phase_sampling: PhaseSampling,
    /// Russian roulette threshold as a fraction of the scene's reference radiance (0: off).
    #[arg(long, allow_hyphen_values = true)]
    pub russian_roulette: Option<f64>,
    /// PNG exposure in stops (default: automatic).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f64>,
    /// Output base name: writes BASE.exr and BASE.png.
    #[arg(short, long, default_value = "omnee")]
    pub output: PathBuf,
    /// Which files to write.
    #[arg(long, value_parser = closed::<ImageFormat>(), default_value = "both")]
    pub format: ImageFormat,
    /// Also write each term's layer as BASE.TERM.png, with the sum's exposure.
    #[arg(long)]
    pub png_layers: bool,
    /// Progress bar on stderr.
    #[arg(long, value_parser = closed::<ProgressMode>(), value_name = "MODE", default_value = "auto")]
    pub progress: ProgressMode,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

impl RenderArgs {
    /// The scene's settings with the options that were given in their place.
    fn settings(&self, scene: &Scene) -> Result<RenderSettings> {
        let mut s = scene.settings();
        if let (Scene::Underwater(_), Some(r)) = (scene, self.russian_roulette) {
            return Err(RenderError::Input(format!(
                "--russian-roulette = {r} does not apply to the underwater scene (light tracing \
                 splats every path); allowed: leave it out"
            )));
        }
        let multiple = self.multiple.is_some() || self.vertices.is_some();
        if matches!(scene, Scene::Underwater(_)) && (multiple || self.max_vertices.is_some()) {
            return Err(RenderError::Input(
                "--multiple, --vertices and --max-vertices apply to the slab scene's multiple \
                 term; allowed: leave them out"
                    .into(),
            ));
        }
        if let Some(n) = self.spp {
            s.budget = RenderBudget::Spp(n);
        } else if let Some(t) = self.time {
            s.budget = RenderBudget::Seconds(t);
        }
        if let Some((w, h)) = self.resolution {
            (s.width, s.height) = (w, h);
        }
        s.crop = self.crop;
        s.seed = self.seed.unwrap_or(s.seed);
        s.terms = self.terms.clone().unwrap_or(s.terms);
        s.technique = self.technique.unwrap_or(s.technique);
        s.theta_max = self.theta_max.unwrap_or(s.theta_max);
        s.multiple = self.multiple.unwrap_or(s.multiple);
        let vertices = match (self.vertices, s.vertices) {
            (Some(VertexNumber::Auto { .. }), scene @ VertexNumber::Auto { .. })
            | (None, scene) => scene,
            (Some(v), _) => v,
        };
        s.vertices = with_max(vertices, self.max_vertices)?;
        s.russian_roulette = self.russian_roulette.unwrap_or(s.russian_roulette);
        s.exposure = self.exposure.or(s.exposure);
        s.phase_sampling = self.phase_sampling;
        Ok(s)
    }

    /// The EXR and PNG paths asked for, their folder checked.
    fn outputs(&self) -> Result<(Option<PathBuf>, Option<PathBuf>)> {
        let exr = matches!(self.format, ImageFormat::Both | ImageFormat::Exr)
            .then(|| with_ext(&self.output, "exr"));
        let png = matches!(self.format, ImageFormat::Both | ImageFormat::Png)
            .then(|| with_ext(&self.output, "png"));
        if let Some(p) = &exr {
            check_output("--output", p)?;
        }
        if png.is_some() || self.png_layers {
            check_output("--output", &with_ext(&self.output, "png"))?;
        }
        Ok((exr, png))
    }
}

/// `omnee render`.
pub fn run(a: RenderArgs) -> Result<()> {
    let scene = Scene::from_source("--scene", &a.scene)?;
    let settings = a.settings(&scene)?;
    let (exr, png) = a.outputs()?;
    let bar = (a.progress == ProgressMode::Auto).then(|| Bar::start(settings.budget));
    let go = AtomicBool::new(false);
    let progress = |p| {
        if let Some(b) = &bar {
            b.report(p);
        }
    };
    let (out, report) = with_threads(a.threads, || {
        scene.render(&settings, Spelling::Options, &progress, &go)
    })??;
    if let Some(b) = bar {
        b.finish();
    }
    let say = |line: &str| {
        if !a.json {
            println!("{line}");
        }
    };
    if report.once_more {
        let t = &report.technique;
        match &t.reason {
            Some(r) => say(&format!("technique: auto picked {}: {r}", t.used)),
            None => say(&format!("technique: {}", t.used)),
        }
        if report.tabulated {
            say("phase sampling: tabulated inverse CDF, p/q in the weight");
        }
    }
    for n in &report.skipped {
        say(&format!("skip: {n}"));
    }
    let ev = write_images(&a, &settings, &out.layers, exr.as_ref(), png.as_ref(), &say)?;
    let files = (exr, png);
    if a.json {
        println!("{}", summary_json(&settings, &report, &out, ev, &files));
    } else {
        summary_text(&settings, &out, ev, &files, &say);
    }
    Ok(())
}

/// Writes the EXR, the PNG and the layer PNGs asked for; returns the PNG's
/// exposure (stops).
fn write_images(
    a: &RenderArgs,
    settings: &RenderSettings,
    layers: &Layers,
    exr: Option<&PathBuf>,
    png: Option<&PathBuf>,
    say: &dyn Fn(&str),
) -> Result<f64> {
    let (srgb, ev) = tone_map(layers.get("").unwrap_or(&[]), settings.exposure);
    if let Some(path) = exr {
        write_exr(path, layers)?;
    }
    if let Some(path) = png {
        write_png(path, layers.width, layers.height, &srgb)?;
    }
    if a.png_layers {
        for (name, data) in layers.layers.iter().filter(|(n, _)| !n.is_empty()) {
            let path = with_ext(&a.output, &format!("{name}.png"));
            let (srgb, _) = tone_map(data, Some(ev));
            write_png(&path, layers.width, layers.height, &srgb)?;
            say(&format!("wrote {}", path.display()));
        }
    }
    Ok(ev)
}

/// The `--json` summary.
fn summary_json(
    s: &RenderSettings,
    report: &RenderReport,
    out: &Rendered<SceneStats>,
    ev: f64,
    (exr, png): &(Option<PathBuf>, Option<PathBuf>),
) -> serde_json::Value {
    let terms: Vec<String> = s.terms.iter().map(Term::to_string).collect();
    let t = &report.technique;
    let mut v = json!({
        "width": s.width, "height": s.height, "crop": s.crop.unwrap_or([0, 0, s.width, s.height]),
        "spp": out.passes, "seconds": out.seconds, "seed": s.seed, "terms": terms,
        "technique": t.used.to_string(), "technique_requested": t.requested.to_string(),
        "auto_reason": t.reason.map(|r| r.to_string()), "theta_max": s.theta_max, "exposure": ev,
        "skipped": report.skipped,
        "multiple": s.terms.contains(&Term::Multiple).then(|| json!({
            "method": s.multiple.to_string(), "vertices": s.vertices.to_string(),
            "max_vertices": s.vertices.range(2).1,
        })),
        "exr": exr.as_ref().map(|p| p.display().to_string()),
        "png": png.as_ref().map(|p| p.display().to_string()),
    });
    match out.stats {
        SceneStats::Slab(st) => {
            v["phase_sampling"] = json!(if report.tabulated { "table" } else { "exact" });
            v["stats"] = json!({
                "connections": st.connections, "skipped_unreachable": st.skipped_unreachable,
                "no_vertex": st.no_vertex, "roulette_dropped": st.roulette_dropped,
                "roulette_kept": st.roulette_kept, "visibility_tests": st.visibility_tests,
            });
        }
        SceneStats::Underwater(st) => {
            v["scene"] = json!("underwater");
            let splats: serde_json::Map<_, _> = UNDERWATER_TERMS
                .iter()
                .zip(st.splats)
                .map(|(t, n)| (t.to_string(), json!(n)))
                .collect();
            v["stats"] = json!({
                "paths": st.paths, "no_start": st.no_start, "beyond_core": st.beyond_core,
                "lost_at_surface": st.lost_at_surface, "floor_hits": st.floor_hits,
                "splats": splats, "no_vertex": st.no_vertex, "surface_tests": st.surface_tests,
            });
        }
    }
    v
}

/// The text summary: size, samples, time, the work counters, the files.
fn summary_text(
    s: &RenderSettings,
    out: &Rendered<SceneStats>,
    ev: f64,
    (exr, png): &(Option<PathBuf>, Option<PathBuf>),
    say: &dyn Fn(&str),
) {
    let [x0, y0, x1, y1] = s.crop.unwrap_or([0, 0, s.width, s.height]);
    let size = format!(
        "{}x{} ({} pixels)",
        s.width,
        s.height,
        (x1 - x0) * (y1 - y0)
    );
    match out.stats {
        SceneStats::Slab(st) => {
            say(&format!(
                "rendered {size}, {} spp in {:.2} s",
                out.passes, out.seconds
            ));
            say(&format!(
                "once-more connections {}, not sampled (theta < theta_max cannot reach the slab) {}, \
                 no vertex {}; roulette dropped {} kept {}; visibility tests {}",
                st.connections,
                st.skipped_unreachable,
                st.no_vertex,
                st.roulette_dropped,
                st.roulette_kept,
                st.visibility_tests
            ));
        }
        SceneStats::Underwater(st) => {
            say(&format!(
                "rendered {size}, {} passes of {} light paths in {:.2} s",
                out.passes,
                s.width * s.height,
                out.seconds
            ));
            say(&format!(
                "light paths {}: no start point {}, started beyond the core region {}, lost at the surface {}, \
                 on the floor {}; splats: {}; no once-more vertex {}; wave-band tests {}",
                st.paths,
                st.no_start,
                st.beyond_core,
                st.lost_at_surface,
                st.floor_hits,
                st.splats_by_term(),
                st.no_vertex,
                st.surface_tests
            ));
        }
    }
    if let Some(path) = exr {
        say(&format!(
            "wrote {} (layers: {})",
            path.display(),
            out.layers.names()
        ));
    }
    if let Some(path) = png {
        say(&format!(
            "wrote {} (exposure {ev:+.2} stops)",
            path.display()
        ));
    }
}
