//! The irradiance at a point of a slab scene, per term (`direct`,
//! `once-more`), as mean and standard error: `omnee probe`.

use super::world::{OnceMore, Roulette, SlabWorld};
use super::{SlabScene, SlabStats};
use crate::error::{RenderError, Result};
use crate::moments::Moments;
use crate::parallel::chunked;
use crate::phase::{PhaseSampling, TableStorage};
use crate::point::estimate::check_samples;
use crate::point::problem::unit_vector;
use crate::range::Range;
use crate::render::Counters;
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::method::{AutoReason, Choice, Method};
use omnee_core::names::List;
use omnee_core::phase::PhaseFunction;
use omnee_core::term::Term;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The terms a probe estimates: the parts of the irradiance at a point.
pub const PROBE_TERMS: [Term; 2] = [Term::Direct, Term::OnceMore];

/// What to probe (plain data; checked by [`probe`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeRequest {
    /// The receiver point.
    pub point: [f64; 3],
    /// The receiver's normal (any non-zero length).
    pub normal: [f64; 3],
    /// The terms, some of [`PROBE_TERMS`].
    pub terms: Vec<Term>,
    /// The once-more technique.
    pub technique: Choice,
    /// The once-more integrand's restriction θ < θmax (default: the
    /// scene's).
    pub theta_max: Option<f64>,
    /// How the once-more term draws deflections.
    pub phase_sampling: PhaseSampling,
    /// Number of samples.
    pub samples: u64,
    /// Random seed.
    pub seed: u64,
}

/// A probe's result.
#[derive(Clone, Debug)]
pub struct Probe {
    /// `(mean, standard error)` of the direct irradiance (W/m²), if asked for.
    pub direct: Option<(f64, f64)>,
    /// The same for the once-more irradiance, if asked for and the medium
    /// scatters.
    pub once_more: Option<(f64, f64)>,
    /// The same for their sum.
    pub total: (f64, f64),
    /// The receiver's unit normal.
    pub normal: [f64; 3],
    /// θmax used.
    pub theta_max: f64,
    /// The method used for the once-more term, and for `auto` why.
    pub method: (Method, Option<AutoReason>),
    /// Whether the once-more term drew deflections from a table.
    pub tabulated: bool,
    /// Work counters.
    pub stats: SlabStats,
    /// What was skipped, as sentences.
    pub skipped: Vec<String>,
    /// Wall-clock seconds of the sampling.
    pub seconds: f64,
}

/// The sums of one chunk: direct, once-more, their total, the counters.
type Chunk = (Moments, Moments, Moments, SlabStats);

/// Probes `scene` on the current rayon pool (fields named as the command
/// line's options); [`RenderError::Cancelled`] as soon as `cancel` is set.
pub fn probe(scene: &SlabScene, r: &ProbeRequest, cancel: &AtomicBool) -> Result<Probe> {
    let samples = check_samples("--samples", r.samples)?;
    let n = unit_vector("--normal", r.normal)?;
    if let Some(t) = r.terms.iter().find(|t| !PROBE_TERMS.contains(t)) {
        return Err(RenderError::Input(format!(
            "--terms = \"{t}\" is not a probe term; allowed: {} (view belongs to a camera ray; {} to the \
             underwater scene, which is light traced)",
            List(&PROBE_TERMS),
            List(&crate::scenes::underwater::UNDERWATER_TERMS),
        )));
    }
    let direct = r.terms.contains(&Term::Direct);
    let theta_max = match r.theta_max {
        Some(t) => Range::THETA_MAX.check("--theta-max", t)?,
        None => scene.render.theta_max,
    };
    let dist = check_point(scene, r.point)?;
    let mut storage = TableStorage::<f32>::default();
    let phase = (scene.medium.phase).sampled::<f32>(r.phase_sampling, &mut storage)?;
    let world = SlabWorld::new(scene, phase)?;
    let g = world.phase().mean_cosine() as f64;
    let tau = scene.medium.sigma_t() * dist;
    let method = r.technique.resolve(g, tau).ok_or_else(|| {
        RenderError::range("--technique", r.technique, List(&super::SLAB_TECHNIQUES))
    })?;
    let once_more = r.terms.contains(&Term::OnceMore) && world.scatters();
    let how = OnceMore {
        method: method.0,
        theta_max: theta_max as f32,
    };
    let v3 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    let (p, nv) = (v3(r.point), v3(n));
    let start = Instant::now();
    let chunks = chunked(samples, cancel, |k, count| -> Chunk {
        let mut rng = Rng::stream(r.seed, k, 0x7072_6f62);
        let mut st = SlabStats::default();
        let (mut md, mut mo, mut mt) = (Moments::default(), Moments::default(), Moments::default());
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
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let (mut md, mut mo, mut mt, mut stats) = Chunk::default();
    for (d, o, t, s) in &chunks {
        md.add(d);
        mo.add(o);
        mt.add(t);
        stats.add(s);
    }
    let skipped = if world.scatters() {
        vec![]
    } else {
        vec!["sigma_s = 0: once-more term skipped".to_string()]
    };
    Ok(Probe {
        direct: direct.then(|| md.mean_stderr(samples)),
        once_more: once_more.then(|| mo.mean_stderr(samples)),
        total: mt.mean_stderr(samples),
        normal: n,
        theta_max,
        method,
        tabulated: world.tabulated(),
        stats,
        skipped,
        seconds,
    })
}

/// Checks that `point` is outside the light and on or above the floor;
/// returns its distance from the light's centre.
fn check_point(scene: &SlabScene, point: [f64; 3]) -> Result<f64> {
    let l = &scene.light;
    let to_light = [0, 1, 2].map(|i| point[i] - l.center[i]);
    let dist = (to_light[0].powi(2) + to_light[1].powi(2) + to_light[2].powi(2)).sqrt();
    let text = || format!("{},{},{}", point[0], point[1], point[2]);
    if !(dist > l.radius) {
        return Err(RenderError::range(
            "--point",
            text(),
            format!(
                "outside the light (distance from {:?} > {})",
                l.center, l.radius
            ),
        ));
    }
    if point[2] < scene.floor.z {
        return Err(RenderError::range(
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
