//! `omnee probe`: the irradiance at a point of a scene, per term, as mean
//! and standard error.

use super::args::{check_count, parse_vec3, unit_normal};
use super::summary::{choice_json, print_result};
use crate::error::{CliError, Result};
use crate::moments::Moments;
use crate::parallel::{chunked, with_threads};
use crate::phase::{PhaseSampling, TableStorage};
use crate::range::Range;
use crate::rng::Rng;
use crate::scene::{self, Scene};
use crate::stats::Stats;
use crate::technique::{self, OnceMore, Technique};
use crate::term::{self, Term};
use crate::world::{Roulette, World};
use clap::Args;
use glam::Vec3;
use omnee_core::phase::PhaseFunction;
use serde_json::json;
use std::time::Instant;

/// The options of `omnee probe`.
#[derive(Args, Debug)]
pub struct ProbeArgs {
    /// The scene: a built-in name or a scene file (TOML).
    #[arg(long, value_parser = scene::Source::parse, default_value = "default")]
    pub scene: scene::Source,
    /// The receiver point X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub point: [f64; 3],
    /// The receiver's normal X,Y,Z (need not be unit length).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,0,1")]
    pub normal: [f64; 3],
    /// Comma-separated terms: direct, once-more (view belongs to a camera
    /// ray, caustics, caustics-once-more and shafts to the underwater scene).
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        value_name = "TERM",
        default_value = "direct,once-more"
    )]
    pub terms: Vec<Term>,
    /// Technique for the once-more term.
    #[arg(long, value_enum, default_value_t = Technique::Auto)]
    pub technique: Technique,
    /// Restrict the once-more integrand to theta < THETA_MAX (default: the scene's render.theta_max).
    #[arg(long)]
    pub theta_max: Option<f64>,
    /// How the once-more term draws deflections from the medium's phase function.
    #[arg(long, value_enum, value_name = "HOW", default_value_t = PhaseSampling::Table)]
    pub phase_sampling: PhaseSampling,
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

/// The terms a probe estimates: the parts of the irradiance at a point.
const PROBE_TERMS: [Term; 2] = [Term::Direct, Term::OnceMore];

/// `terms` as a comma-separated list of their names.
fn names(terms: &[Term]) -> String {
    terms
        .iter()
        .map(Term::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The sums of one chunk: direct, once-more, their total, the counters.
type Chunk = (Moments, Moments, Moments, Stats);

/// `omnee probe`.
pub fn run(a: ProbeArgs) -> Result<()> {
    let scene = Scene::from_source(&a.scene)?;
    let samples = check_count("--samples", a.samples)?;
    let n = unit_normal("--normal", a.normal)?;
    if let Some(t) = a.terms.iter().find(|t| !PROBE_TERMS.contains(t)) {
        return Err(CliError::Input(format!(
            "--terms = \"{t}\" is not a probe term; allowed: {} (view belongs to a camera ray; {} to the \
             underwater scene, which is light traced)",
            names(&PROBE_TERMS),
            names(&term::UNDERWATER),
        )));
    }
    let direct = a.terms.contains(&Term::Direct);
    let theta_max = match a.theta_max {
        Some(t) => Range::THETA_MAX.check("--theta-max", t)?,
        None => scene.render.theta_max,
    };
    let dist = check_point(&scene, a.point)?;
    let mut storage = TableStorage::<f32>::default();
    let phase = (scene.medium.phase).sampled::<f32>(a.phase_sampling, &mut storage)?;
    let world = World::new(&scene, phase)?;
    let g = world.phase().mean_cosine() as f64;
    let choice = technique::choose(a.technique, g, scene.medium.sigma_t() * dist);
    let once_more = a.terms.contains(&Term::OnceMore) && world.scatters();
    let how = OnceMore {
        method: choice.method,
        theta_max: theta_max as f32,
    };
    let v3 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    let (p, nv) = (v3(a.point), v3(n));
    let start = Instant::now();
    let chunks = with_threads(a.threads, || {
        chunked(samples, |k, count| -> Chunk {
            let mut rng = Rng::stream(a.seed, k, 0x7072_6f62);
            let mut st = Stats::default();
            let (mut md, mut mo, mut mt) =
                (Moments::default(), Moments::default(), Moments::default());
            for _ in 0..count {
                let d = if direct {
                    world.direct(p, nv, &mut rng, Roulette::OFF, &mut st) as f64
                } else {
                    0.0
                };
                let o = if once_more {
                    world.once_more(p, nv, how, &mut rng, Roulette::OFF, &mut st) as f64
                } else {
                    0.0
                };
                md.push(d);
                mo.push(o);
                mt.push(d + o);
            }
            (md, mo, mt, st)
        })
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let (mut md, mut mo, mut mt, mut st) = Chunk::default();
    for (d, o, t, s) in &chunks {
        md.add(d);
        mo.add(o);
        mt.add(t);
        st.add(s);
    }
    let (mean, stderr) = mt.mean_stderr(samples);
    let mut terms = serde_json::Map::new();
    if direct {
        let (m, e) = md.mean_stderr(samples);
        terms.insert(Term::Direct.to_string(), json!({"mean": m, "stderr": e}));
    }
    if once_more {
        let (m, e) = mo.mean_stderr(samples);
        terms.insert(Term::OnceMore.to_string(), json!({"mean": m, "stderr": e}));
    }
    let (tech, requested, reason) = choice_json(&choice);
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": samples, "seconds": seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": terms, "units": "W/m^2", "point": a.point, "normal": n, "theta_max": theta_max,
        "phase_sampling": super::render::phase_sampling_json(&world), "seed": a.seed, "visibility_tests": st.visibility_tests,
        "skipped": if !world.scatters() { json!(["sigma_s = 0: once-more term skipped"]) } else { json!([]) },
    });
    print_result(&v, a.json);
    Ok(())
}

/// Checks that `point` is outside the light and on or above the floor;
/// returns its distance from the light's centre.
fn check_point(scene: &Scene, point: [f64; 3]) -> Result<f64> {
    let l = &scene.light;
    let to_light = [0, 1, 2].map(|i| point[i] - l.center[i]);
    let dist = (to_light[0].powi(2) + to_light[1].powi(2) + to_light[2].powi(2)).sqrt();
    let text = || format!("{},{},{}", point[0], point[1], point[2]);
    if !(dist > l.radius) {
        return Err(CliError::range(
            "--point",
            text(),
            format!(
                "outside the light (distance from {:?} > {})",
                l.center, l.radius
            ),
        ));
    }
    if point[2] < scene.floor.z {
        return Err(CliError::range(
            "--point",
            text(),
            format!(
                "z >= floor.z = {} (on or above the opaque floor)",
                scene.floor.z
            ),
        ));
    }
    Ok(dist)
}
