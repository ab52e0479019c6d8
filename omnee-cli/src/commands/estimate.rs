//! `omnee estimate`: the point-to-point once-more integral in an infinite
//! homogeneous medium, as mean and standard error, optionally against the
//! core's quadrature reference.

use super::args::check_count;
use super::problem::{Precision, Problem, ProblemArgs, Sampler, with_sampler};
use super::summary::{choice_json, print_result};
use crate::error::Result;
use crate::moments::Moments;
use crate::parallel::{chunked, with_threads};
use crate::phase::TableStorage;
use crate::rng::Rng;
use clap::Args;
use omnee_core::Real;
use serde_json::json;
use std::time::Instant;

/// The random streams of `estimate` and `samples`: `(seed, chunk, STREAM)`.
pub const STREAM: u64 = 0x6573_7469;

/// The options of `omnee estimate`.
#[derive(Args, Debug)]
pub struct EstimateArgs {
    /// The problem.
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Number of samples.
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Also compute the quadrature reference (f64, docs/math.md §5).
    #[arg(long)]
    pub reference: bool,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// `omnee estimate`.
pub fn run(a: EstimateArgs) -> Result<()> {
    let samples = check_count("--samples", a.samples)?;
    let p = Problem::new(&a.problem)?;
    let start = Instant::now();
    let (moments, accepted, reference) = match a.problem.precision {
        Precision::F32 => estimate::<f32>(&a, &p, samples)?,
        Precision::F64 => estimate::<f64>(&a, &p, samples)?,
    };
    let seconds = start.elapsed().as_secs_f64();
    let (mean, stderr) = moments.mean_stderr(samples);
    let (tech, requested, reason) = choice_json(&p.choice);
    let pa = &a.problem;
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": samples, "seconds": seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": {"once-more": {"mean": mean, "stderr": stderr}},
        "accepted": accepted, "reference": reference,
        "x0": pa.x0, "x2": pa.x2, "phase": p.phase.to_string(), "mean_cosine": p.g,
        "sigma_s": pa.sigma_s, "sigma_t": pa.sigma_t, "tau": p.tau, "theta_max": pa.theta_max,
        "receiver_normal": p.normal, "seed": pa.seed, "precision": pa.precision.to_string(),
    });
    print_result(&v, a.json);
    Ok(())
}

/// The estimator's sums over `samples` draws in precision `F`, the number
/// of draws whose own vertex exists, and the quadrature if asked for.
fn estimate<F: Real>(
    a: &EstimateArgs,
    p: &Problem,
    samples: u64,
) -> Result<(Moments, u64, Option<f64>)> {
    let seed = a.problem.seed;
    with_sampler::<F, _>(&a.problem, p, |sampler: &Sampler<'_, F>| {
        let chunks = with_threads(a.threads, || {
            chunked(samples, |k, count| {
                let mut rng = Rng::stream(seed, k, STREAM);
                let mut m = Moments::default();
                let mut accepted = 0u64;
                for _ in 0..count {
                    let draw = sampler.draw(&mut rng);
                    accepted += u64::from(draw.vertices[0].is_some());
                    m.push(draw.sum(|s| sampler.estimate(s)));
                }
                (m, accepted)
            })
        })?;
        let mut m = Moments::default();
        let mut accepted = 0;
        for (c, n) in &chunks {
            m.add(c);
            accepted += n;
        }
        let reference = if a.reference {
            let mut st = TableStorage::<f64>::default();
            let phase = p.phase.instantiate::<f64>(&mut st)?;
            Some(sampler.problem.integral(&phase))
        } else {
            None
        };
        Ok((m, accepted, reference))
    })?
}
