//! `omnee estimate`: the point-to-point once-more integral in an infinite
//! homogeneous medium, as mean and standard error, optionally against the
//! core's quadrature reference.
//!
//! [`estimate`] computes (and is the library's entry point: the Python
//! bindings call it), [`run`] prints.

use super::args::check_count;
use super::problem::{Names, Precision, Problem, ProblemArgs, Sampler, with_sampler};
use super::summary::{choice_json, print_result};
use crate::error::Result;
use crate::moments::Moments;
use crate::parallel::{chunked, with_threads};
use crate::phase::{PhaseSpec, TableStorage};
use crate::rng::Rng;
use crate::technique::Choice;
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

/// What [`estimate`] computed: the Monte Carlo estimate of the once-more
/// integral `I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1` over
/// θ < θmax (docs/math.md §1), how it was drawn, and the quadrature
/// reference if asked for. `omnee estimate --json` prints these fields with
/// the problem's options.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// The mean `x̄ = Σx/n` of the `n` per-draw estimates `x = Σ_k f_c(x1_k) · weight_k`.
    pub mean: f64,
    /// The standard error of the mean, `√((Σx² − x̄ Σx)/((n − 1) n))`.
    pub stderr: f64,
    /// The number of draws `n`.
    pub samples: u64,
    /// The draws whose own vertex exists (the MIS companion not counted).
    pub accepted: u64,
    /// The f64 quadrature value of `I` (docs/math.md §5), if asked for.
    pub reference: Option<f64>,
    /// Wall-clock time of the draws and the quadrature, in seconds.
    pub seconds: f64,
    /// The technique: what was asked for, the method used and, for `auto`, why.
    pub choice: Choice,
    /// The phase function, as checked.
    pub phase: PhaseSpec,
    /// The phase function's mean cosine `g = ⟨cos θ⟩`.
    pub mean_cosine: f64,
    /// The optical thickness `τ = σt · |x2 − x0|`.
    pub tau: f64,
    /// The receiver's unit normal, if it has a cosine.
    pub receiver_normal: Option<[f64; 3]>,
    /// The arithmetic precision of the draws.
    pub precision: Precision,
}

/// The estimate of `a.problem` from `a.samples` draws on `a.threads`
/// threads (`a.json` is [`run`]'s only), naming a bad field by `names`.
///
/// Draws come in chunks of [`crate::parallel::CHUNK`], chunk `k` from the
/// stream `(seed, k, STREAM)`, and the chunks' sums are added in chunk
/// order: the result depends on the seed and the sample count, never on the
/// thread count.
pub fn estimate(a: &EstimateArgs, names: Names) -> Result<Estimate> {
    let samples = check_count(&names.of("samples"), a.samples)?;
    let p = Problem::named(&a.problem, names)?;
    let start = Instant::now();
    let (moments, accepted, reference) = match a.problem.precision {
        Precision::F32 => sums::<f32>(a, &p, samples)?,
        Precision::F64 => sums::<f64>(a, &p, samples)?,
    };
    let seconds = start.elapsed().as_secs_f64();
    let (mean, stderr) = moments.mean_stderr(samples);
    Ok(Estimate {
        mean,
        stderr,
        samples,
        accepted,
        reference,
        seconds,
        choice: p.choice,
        phase: p.phase,
        mean_cosine: p.g,
        tau: p.tau,
        receiver_normal: p.normal,
        precision: a.problem.precision,
    })
}

/// `omnee estimate`: [`estimate`], printed.
pub fn run(a: EstimateArgs) -> Result<()> {
    let e = estimate(&a, Names::Options)?;
    let (tech, requested, reason) = choice_json(&e.choice);
    let pa = &a.problem;
    let (mean, stderr) = (e.mean, e.stderr);
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": e.samples, "seconds": e.seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": {"once-more": {"mean": mean, "stderr": stderr}},
        "accepted": e.accepted, "reference": e.reference,
        "x0": pa.x0, "x2": pa.x2, "phase": e.phase.to_string(), "mean_cosine": e.mean_cosine,
        "sigma_s": pa.sigma_s, "sigma_t": pa.sigma_t, "tau": e.tau, "theta_max": pa.theta_max,
        "receiver_normal": e.receiver_normal, "seed": pa.seed,
        "precision": e.precision.to_string(),
    });
    print_result(&v, a.json);
    Ok(())
}

/// The estimator's sums over `samples` draws in precision `F`, the number
/// of draws whose own vertex exists, and the quadrature if asked for.
fn sums<F: Real>(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::Technique;
    use omnee_core::method::Method;

    /// HG 0.9 over a unit distance, 10⁴ draws of `auto` in f64 (the
    /// reference is the integration tests').
    fn args() -> EstimateArgs {
        EstimateArgs {
            problem: ProblemArgs {
                x0: [0.0, 0.0, 1.0],
                x2: [0.0, 0.0, 0.0],
                phase: " hg:0.9 ".into(),
                sigma_s: 0.5,
                sigma_t: 0.55,
                theta_max: std::f64::consts::PI,
                receiver_normal: Some([0.0, 0.0, 2.0]),
                technique: Technique::Auto,
                seed: 3,
                precision: Precision::F64,
            },
            samples: 10_000,
            reference: false,
            threads: 1,
            json: false,
        }
    }

    #[test]
    fn the_estimate_is_independent_of_threads_and_reports_its_problem() {
        let one = estimate(&args(), Names::Fields).unwrap();
        let two = estimate(
            &EstimateArgs {
                threads: 2,
                ..args()
            },
            Names::Fields,
        )
        .unwrap();
        assert_eq!(
            (one.mean, one.stderr, one.accepted),
            (two.mean, two.stderr, two.accepted)
        );
        assert_eq!(
            (one.choice.method, one.choice.requested),
            (Method::Omnee, Technique::Auto)
        );
        assert!(one.choice.reason.is_some());
        assert_eq!(one.phase.to_string(), "hg:0.9");
        assert_eq!((one.mean_cosine, one.tau), (0.9, 0.55));
        assert_eq!(one.receiver_normal, Some([0.0, 0.0, 1.0]));
        assert_eq!((one.samples, one.precision), (10_000, Precision::F64));
        assert_eq!(one.reference, None);
        assert!(one.mean > 0.0 && one.stderr < 0.01 * one.mean, "{one:?}");
    }

    /// A change to [`args`] that makes it invalid.
    type Spoil = fn(&mut EstimateArgs);

    #[test]
    fn bad_fields_are_named_as_the_caller_spells_them() {
        let message = |change: Spoil, names| {
            let mut a = args();
            change(&mut a);
            estimate(&a, names).unwrap_err().to_string()
        };
        let cases: [(Spoil, &str, &str); 6] = [
            (|a| a.samples = 0, "samples = 0", "--samples = 0"),
            (
                |a| a.problem.sigma_s = -1.0,
                "sigma_s = -1",
                "--sigma-s = -1",
            ),
            (
                |a| a.problem.theta_max = 0.0,
                "theta_max = 0",
                "--theta-max = 0",
            ),
            (
                |a| a.problem.x2 = a.problem.x0,
                "x2 = 0,0,1 equals x0",
                "--x2 = 0,0,1 equals --x0",
            ),
            (
                |a| a.problem.x0[1] = f64::NAN,
                "x0 = 0,NaN,1 is not a point",
                "--x0 = 0,NaN,1",
            ),
            (
                |a| a.problem.receiver_normal = Some([0.0; 3]),
                "receiver_normal = 0,0,0 has zero length",
                "--receiver-normal = 0,0,0",
            ),
        ];
        for (change, field, option) in cases {
            assert!(message(change, Names::Fields).starts_with(field), "{field}");
            assert!(
                message(change, Names::Options).starts_with(option),
                "{option}"
            );
        }
    }
}
