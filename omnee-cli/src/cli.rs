//! The command line: clap's argument structs, the subcommands `render` and
//! `merge`, and the dispatch to [`crate::measure`] for `probe`, `estimate`
//! and `samples`.

use crate::error::{CliError, Result};
use crate::{image, measure, phase, render, scene, technique, world};
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

const PHASE_HELP: &str = "\
Phase function specs (scene files' medium.phase and --phase):
  iso                 isotropic, p = 1/(4 pi)
  hg:G                Henyey-Greenstein, G in (-1, 1) (G > 0: forward)
  tthg:G1,G2,W        two-term HG, W*HG(G1) + (1-W)*HG(G2); G1, G2 in (-1, 1), W in [0, 1]
  ff:B,N              Fournier-Forand, backscatter fraction B in (0, 0.5), refractive index N in [1.001, 1.5]
  draine:G,ALPHA      Draine, G in (-1, 1), ALPHA in [0, 1000]
  mie:DIAMETER_UM     approximate Mie (Jendersie & d'Eon 2023), droplet diameter in (0, 50] micrometres
  rayleigh            Rayleigh, p = 3/(16 pi) (1 + cos^2)
  table:FILE.csv      measured: lines 'angle_deg,value', angles increasing in [0, 180]
Angles are deflections between propagation directions (0 = straight on).

Techniques for the once-more term (--technique):
  omnee        the deflection from the phase function, then x1 on the circumcircle arc
  equiangular  a direction from the receiver, then the distance equiangular towards the light
  distance     a direction from the receiver, then an exponential free-flight distance
  mis          OMNEE over the whole range, and for 5 % of the connections one more, equiangular,
               vertex kept behind theta = 3 pi/4 (multi-sample MIS, balance heuristic there)
  auto         OMNEE, or mis in a thin medium with a broad phase function; says what it picked and why

Exit codes: 0 success, 1 a file could not be written, 2 bad input (the message names
the field, its value and the allowed range).";

/// omnee: once-more scattered next event estimation for volume rendering.
#[derive(Parser, Debug)]
#[command(name = "omnee", version, about, after_help = PHASE_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render the slab scene (default: the embedded one) to EXR (a layer per term) and PNG.
    #[command(after_help = PHASE_HELP)]
    Render(RenderArgs),
    /// Irradiance at a point of a scene, per term, as mean and standard error.
    #[command(after_help = PHASE_HELP)]
    Probe(ProbeArgs),
    /// The point-to-point once-more integral in an infinite homogeneous medium.
    #[command(after_help = PHASE_HELP)]
    Estimate(EstimateArgs),
    /// The x1 samples of a technique with their pdf and weight.
    #[command(after_help = PHASE_HELP)]
    Samples(SamplesArgs),
    /// Sum EXR files rendered with disjoint --crop windows into one image.
    Merge(MergeArgs),
    /// Print the default scene (TOML, every field documented).
    DefaultScene,
}

/// Output formats of `render`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ImageFormat {
    /// OpenEXR and PNG.
    Both,
    /// OpenEXR only.
    Exr,
    /// PNG only.
    Png,
}

/// The options of `omnee render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (TOML); default: the embedded default scene.
    #[arg(long)]
    pub scene: Option<PathBuf>,
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
    /// Comma-separated terms: direct, once-more, view (default: the scene's render.terms).
    #[arg(long, value_delimiter = ',')]
    pub terms: Option<Vec<String>>,
    /// Technique for the once-more term: omnee, equiangular, distance, mis, auto.
    #[arg(long)]
    pub technique: Option<String>,
    /// Restrict the once-more integrand to deflections theta < THETA_MAX (radians, (0, pi]).
    #[arg(long)]
    pub theta_max: Option<f64>,
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
    /// Progress bar on stderr: auto (drawn when stderr is a terminal) or never.
    #[arg(long, default_value = "auto", value_parser = ["auto", "never"])]
    pub progress: String,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The options of `omnee probe`.
#[derive(Args, Debug)]
pub struct ProbeArgs {
    /// Scene file (TOML); default: the embedded default scene.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// The receiver point X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub point: [f64; 3],
    /// The receiver's normal X,Y,Z (need not be unit length).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,0,1")]
    pub normal: [f64; 3],
    /// Comma-separated terms: direct, once-more.
    #[arg(long, value_delimiter = ',', default_value = "direct,once-more")]
    pub terms: Vec<String>,
    /// Technique for the once-more term.
    #[arg(long, default_value = "auto")]
    pub technique: String,
    /// Restrict the once-more integrand to theta < THETA_MAX (default: the scene's render.theta_max).
    #[arg(long)]
    pub theta_max: Option<f64>,
    /// Number of samples.
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Precision of `estimate` and `samples`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Precision {
    /// f32, as the renderer.
    F32,
    /// f64.
    F64,
}

/// The point-to-point problem of `omnee estimate` and `omnee samples`.
#[derive(Args, Debug)]
pub struct ProblemArgs {
    /// The unit-intensity point light x0 = X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x0: [f64; 3],
    /// The point receiver x2 = X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x2: [f64; 3],
    /// Phase function spec (see below).
    #[arg(long, default_value = "iso")]
    pub phase: String,
    /// Scattering coefficient (1/m).
    #[arg(long, allow_hyphen_values = true)]
    pub sigma_s: f64,
    /// Extinction coefficient (1/m), at least sigma-s.
    #[arg(long, allow_hyphen_values = true)]
    pub sigma_t: f64,
    /// The integrand is restricted to theta < THETA_MAX (radians, (0, pi]).
    #[arg(long, allow_hyphen_values = true, default_value_t = std::f64::consts::PI)]
    pub theta_max: f64,
    /// A receiver cosine max(0, n . (x1 - x2)/d2) about this normal.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub receiver_normal: Option<[f64; 3]>,
    /// Technique: omnee, equiangular, distance, mis, auto.
    #[arg(long, default_value = "auto")]
    pub technique: String,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Arithmetic precision of the techniques.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
}

/// The options of `omnee estimate`.
#[derive(Args, Debug)]
pub struct EstimateArgs {
    /// The problem.
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Number of samples.
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Also compute the quadrature reference (f64, MATH.md section 5).
    #[arg(long)]
    pub reference: bool,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Output formats of `samples`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SampleFormat {
    /// Comma-separated values with a header line.
    Csv,
    /// A JSON object with a `samples` array.
    Json,
}

/// The options of `omnee samples`.
#[derive(Args, Debug)]
pub struct SamplesArgs {
    /// The problem.
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Number of draws (draws that give no x1 are not listed).
    #[arg(long, default_value_t = 1000)]
    pub count: u64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = SampleFormat::Csv)]
    pub format: SampleFormat,
}

/// The options of `omnee merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// EXR files rendered with disjoint crop windows of the same image.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Output base name: writes BASE.exr and BASE.png.
    #[arg(short, long, default_value = "merged")]
    pub output: PathBuf,
    /// PNG exposure in stops (default: automatic).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f64>,
}

/// `X,Y,Z` with finite components.
fn parse_vec3(s: &str) -> std::result::Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad =
        || format!("\"{s}\" is not a vector; allowed: three comma-separated finite numbers X,Y,Z");
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0; 3];
    for (slot, p) in v.iter_mut().zip(parts) {
        *slot = p.parse::<f64>().map_err(|_| bad())?;
        if !slot.is_finite() {
            return Err(bad());
        }
    }
    Ok(v)
}

/// `WIDTHxHEIGHT`, each in [1, 16384].
fn parse_resolution(s: &str) -> std::result::Result<(u32, u32), String> {
    let bad = || format!("\"{s}\" is not a resolution; allowed: WIDTHxHEIGHT, each in [1, 16384]");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(1..=16384).contains(&w) || !(1..=16384).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

/// `A,B,C,D` of non-negative integers.
fn parse_u32x4(s: &str) -> std::result::Result<[u32; 4], String> {
    let bad = || format!("\"{s}\" is not a window; allowed: X0,Y0,X1,Y1 (non-negative integers)");
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 4 {
        return Err(bad());
    }
    let mut v = [0u32; 4];
    for (slot, p) in v.iter_mut().zip(parts) {
        *slot = p.parse().map_err(|_| bad())?;
    }
    Ok(v)
}

/// Runs `f` on a rayon pool of `threads` workers (0: one per core).
pub(crate) fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> Result<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::Input(format!("--threads = {threads}: {e}")))?;
    Ok(pool.install(f))
}

/// Parses the command line, runs the subcommand and exits with its code:
/// 0 on success, 1 when a file could not be written, 2 for bad input.
pub fn run() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(a) => run_render(a),
        Command::Probe(a) => measure::probe(a),
        Command::Estimate(a) => measure::estimate(a),
        Command::Samples(a) => measure::samples(a),
        Command::Merge(a) => run_merge(a),
        Command::DefaultScene => {
            print!("{}", scene::DEFAULT_SCENE);
            Ok(())
        }
    };
    if let Err(e) = result {
        eprintln!("omnee: error: {e}");
        std::process::exit(e.exit_code());
    }
}

/// `BASE` with the extension `ext` appended (`out` → `out.exr`, `a.b` → `a.b.exr`).
fn with_ext(base: &std::path::Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn run_render(a: RenderArgs) -> Result<()> {
    use scene::Range;
    let scene = match &a.scene {
        Some(p) => scene::Scene::load(p)?,
        None => scene::Scene::default_scene(),
    };
    let s = &scene.render;
    let budget = match (a.spp, a.time) {
        (Some(n), _) => {
            Range::closed(1.0, (1u64 << 24) as f64).check("--spp", n as f64)?;
            render::Budget::Spp(n)
        }
        (None, Some(t)) => render::Budget::Seconds(Range::POSITIVE.check("--time", t)?),
        (None, None) => render::Budget::Spp(s.spp),
    };
    let (width, height) = a
        .resolution
        .unwrap_or((scene.camera.width, scene.camera.height));
    let crop = a.crop.unwrap_or([0, 0, width, height]);
    if !(crop[0] < crop[2] && crop[1] < crop[3] && crop[2] <= width && crop[3] <= height) {
        return Err(CliError::range(
            "--crop",
            format!("{},{},{},{}", crop[0], crop[1], crop[2], crop[3]),
            format!("X0 < X1 <= {width}, Y0 < Y1 <= {height}"),
        ));
    }
    let terms_names = a.terms.clone().unwrap_or_else(|| s.terms.clone());
    scene::check_terms("--terms", &terms_names)?;
    let theta_max = match a.theta_max {
        Some(t) => Range::open_closed(0.0, std::f64::consts::PI).check("--theta-max", t)?,
        None => s.theta_max,
    };
    let rr = match a.russian_roulette {
        Some(r) => Range::closed(0.0, 1.0).check("--russian-roulette", r)?,
        None => s.russian_roulette,
    };
    let exposure = match a.exposure {
        Some(e) => Some(Range::open(-64.0, 64.0).check("--exposure", e)?),
        None => s.exposure,
    };
    let seed = a.seed.unwrap_or(s.seed);
    let exr_path = with_ext(&a.output, "exr");
    let png_path = with_ext(&a.output, "png");
    let (want_exr, want_png) = match a.format {
        ImageFormat::Both => (true, true),
        ImageFormat::Exr => (true, false),
        ImageFormat::Png => (false, true),
    };
    if want_exr {
        image::check_output("--output", &exr_path)?;
    }
    if want_png || a.png_layers {
        image::check_output("--output", &png_path)?;
    }

    let mut storage = phase::TableStorage::<f32>::default();
    let phase_fn = scene.medium.phase.instantiate::<f32>(&mut storage)?;
    let world = world::World::new(&scene, phase_fn);
    let g = {
        use omnee_core::phase::PhaseFunction;
        world.phase.mean_cosine() as f64
    };
    let height_above_floor = scene.light.center[2] - scene.floor.z;
    let tau = scene.medium.sigma_t() * height_above_floor;
    let technique_name = a.technique.clone().unwrap_or_else(|| s.technique.clone());
    let choice = technique::choose("--technique", &technique_name, g, tau)?;

    // Skip what the scene does not need, and say so.
    let mut terms = render::Terms::from_names(&terms_names);
    let mut notes = Vec::new();
    if !world.scatters() && (terms.once_more || terms.view) {
        notes.push("sigma_s = 0: once-more and view terms skipped (no scattering)".to_string());
        terms.once_more = false;
        terms.view = false;
    }
    if scene.occluder.is_none() {
        notes.push("no occluder: no visibility tests".to_string());
    }
    // Reference radiance: the brightest floor albedo under the light,
    // unattenuated, unoccluded.
    let albedo_max = scene
        .floor
        .albedo_a
        .iter()
        .chain(&scene.floor.albedo_b)
        .fold(0.0f64, |m, &x| m.max(x));
    let h = (height_above_floor - scene.light.radius).max(1e-6);
    let l_ref = albedo_max / std::f64::consts::PI * scene.light.intensity / (h * h);
    let options = render::Options {
        budget,
        seed,
        width,
        height,
        crop,
        terms,
        once_more: world::OnceMore {
            tech: choice.tech,
            theta_max: theta_max as f32,
        },
        roulette: (rr * l_ref) as f32,
        progress: a.progress != "never",
    };
    let say = |line: &str| {
        if !a.json {
            println!("{line}");
        }
    };
    if terms.once_more {
        match &choice.reason {
            Some(r) => say(&format!(
                "technique: auto picked {}: {r}",
                choice.tech.name()
            )),
            None => say(&format!("technique: {}", choice.tech.name())),
        }
    }
    for n in &notes {
        say(&format!("skip: {n}"));
    }
    let out = with_threads(a.threads, || render::render(&scene, &world, &options))?;
    let (srgb, ev) = image::tone_map(out.layers.get("").unwrap_or(&[]), exposure);
    if want_exr {
        image::write_exr(&exr_path, &out.layers)?;
    }
    if want_png {
        image::write_png(&png_path, out.layers.width, out.layers.height, &srgb)?;
    }
    if a.png_layers {
        for (name, data) in out.layers.layers.iter().filter(|(n, _)| !n.is_empty()) {
            let path = with_ext(&a.output, &format!("{name}.png"));
            let (srgb, _) = image::tone_map(data, Some(ev));
            image::write_png(&path, out.layers.width, out.layers.height, &srgb)?;
            say(&format!("wrote {}", path.display()));
        }
    }
    let st = out.stats;
    if a.json {
        let v = serde_json::json!({
            "width": width, "height": height, "crop": crop, "spp": out.spp, "seconds": out.seconds,
            "seed": seed, "terms": terms_names, "technique": choice.tech.name(),
            "technique_requested": choice.requested, "auto_reason": choice.reason,
            "theta_max": theta_max, "exposure": ev, "skipped": notes,
            "stats": {
                "connections": st.connections, "skipped_unreachable": st.skipped_unreachable,
                "no_vertex": st.no_vertex, "roulette_dropped": st.roulette_dropped,
                "roulette_kept": st.roulette_kept, "visibility_tests": st.visibility_tests,
            },
            "exr": want_exr.then(|| exr_path.display().to_string()),
            "png": want_png.then(|| png_path.display().to_string()),
        });
        println!("{v}");
    } else {
        say(&format!(
            "rendered {}x{} ({} pixels), {} spp in {:.2} s",
            width,
            height,
            (crop[2] - crop[0]) * (crop[3] - crop[1]),
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
        if want_exr {
            say(&format!(
                "wrote {} (layers: {})",
                exr_path.display(),
                layer_names(&out.layers)
            ));
        }
        if want_png {
            say(&format!(
                "wrote {} (exposure {ev:+.2} stops)",
                png_path.display()
            ));
        }
    }
    Ok(())
}

fn layer_names(l: &image::Layers) -> String {
    l.layers
        .iter()
        .map(|(n, _)| {
            if n.is_empty() {
                "RGB (sum)".to_string()
            } else {
                n.clone()
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn run_merge(a: MergeArgs) -> Result<()> {
    let exr_path = with_ext(&a.output, "exr");
    let png_path = with_ext(&a.output, "png");
    image::check_output("--output", &exr_path)?;
    let mut total: Option<image::Layers> = None;
    for p in &a.inputs {
        let img = image::read_exr(p)?;
        match &mut total {
            None => total = Some(img),
            Some(t) => {
                let names =
                    |l: &image::Layers| l.layers.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
                if (t.width, t.height) != (img.width, img.height) || names(t) != names(&img) {
                    return Err(CliError::Input(format!(
                        "{}: {}x{} with layers [{}] does not match the first input's {}x{} with [{}]; allowed: crops of one render",
                        p.display(),
                        img.width,
                        img.height,
                        layer_names(&img),
                        t.width,
                        t.height,
                        layer_names(t)
                    )));
                }
                for ((_, dst), (_, src)) in t.layers.iter_mut().zip(&img.layers) {
                    for (d, s) in dst.iter_mut().zip(src) {
                        *d += s;
                    }
                }
            }
        }
    }
    let total = total.expect("clap requires at least one input");
    let (srgb, ev) = image::tone_map(total.get("").unwrap_or(&[]), a.exposure);
    image::write_exr(&exr_path, &total)?;
    image::write_png(&png_path, total.width, total.height, &srgb)?;
    println!(
        "wrote {} and {} (exposure {ev:+.2} stops)",
        exr_path.display(),
        png_path.display()
    );
    Ok(())
}
