//! `omnee probe`: the irradiance at a point of a slab scene, per term, as
//! mean and standard error (the library's
//! [`omnee_render::scenes::slab::probe`]).

use super::args::{parse_samples, parse_threads, parse_vec3};
use super::summary::{print_result, technique_json};
use crate::named::closed;
use clap::Args;
use omnee_core::method::Choice;
use omnee_core::term::Term;
use omnee_render::parallel::with_threads;
use omnee_render::phase::PhaseSampling;
use omnee_render::scenes::slab::probe::{ProbeRequest, probe};
use omnee_render::scenes::{Scene, Source};
use omnee_render::technique::Resolved;
use omnee_render::{RenderError, Result};
use serde_json::json;
use std::sync::atomic::AtomicBool;

/// The options of `omnee probe`.
#[derive(Args, Debug)]
pub struct ProbeArgs {
    /// The scene: a built-in name or a scene file (TOML).
    #[arg(long, value_parser = parse_source, default_value = "default")]
    pub scene: Source,
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
        value_parser = closed::<Term>(),
        value_delimiter = ',',
        value_name = "TERM",
        default_value = "direct,once-more"
    )]
    pub terms: Vec<Term>,
    /// Technique for the once-more term.
    #[arg(long, value_parser = closed::<Choice>(), default_value = "auto")]
    pub technique: Choice,
    /// Restrict the once-more integrand to theta < THETA_MAX (default: the scene's render.theta_max).
    #[arg(long, allow_hyphen_values = true)]
    pub theta_max: Option<f64>,
    /// How the once-more term draws deflections from the medium's phase function.
    #[arg(long, value_parser = closed::<PhaseSampling>(), value_name = "HOW", default_value = "table")]
    pub phase_sampling: PhaseSampling,
    /// Number of samples, [1, 2^40].
    #[arg(long, default_value_t = 100_000, value_parser = parse_samples, allow_hyphen_values = true)]
    pub samples: u64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0: one per core; at most 1024).
    #[arg(long, default_value_t = 0, value_parser = parse_threads, allow_hyphen_values = true)]
    pub threads: usize,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// A scene's source, for clap's `value_parser`.
pub fn parse_source(text: &str) -> std::result::Result<Source, String> {
    Ok(Source::parse(text))
}

/// `omnee probe`.
pub fn run(a: ProbeArgs) -> Result<()> {
    let Scene::Slab(scene) = Scene::from_source("--scene", &a.scene)? else {
        return Err(RenderError::Input(
            "--scene: probe needs a slab scene; the underwater scene is light traced, with no \
             receiver point to probe; allowed: default or a slab scene file"
                .into(),
        ));
    };
    let request = ProbeRequest {
        point: a.point,
        normal: a.normal,
        terms: a.terms.clone(),
        technique: a.technique,
        theta_max: a.theta_max,
        phase_sampling: a.phase_sampling,
        samples: a.samples,
        seed: a.seed,
    };
    let go = AtomicBool::new(false);
    let p = with_threads(a.threads, || probe(&scene, &request, &go))??;
    let mut terms = serde_json::Map::new();
    for (term, value) in [(Term::Direct, p.direct), (Term::OnceMore, p.once_more)] {
        if let Some((mean, stderr)) = value {
            terms.insert(term.to_string(), json!({"mean": mean, "stderr": stderr}));
        }
    }
    let (mean, stderr) = p.total;
    let technique = Resolved {
        requested: a.technique,
        used: Choice::from(p.method.0),
        reason: p.method.1,
    };
    let (tech, requested, reason) = technique_json(&technique);
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": a.samples, "seconds": p.seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": terms, "units": "W/m^2", "point": a.point, "normal": p.normal, "theta_max": p.theta_max,
        "phase_sampling": if p.tabulated { "table" } else { "exact" }, "seed": a.seed,
        "visibility_tests": p.stats.visibility_tests, "skipped": p.skipped,
    });
    print_result(&v, a.json);
    Ok(())
}
