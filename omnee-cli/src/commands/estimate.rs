//! `omnee estimate`: the point-to-point once-more integral in an infinite
//! homogeneous medium, as mean and standard error, optionally against the
//! core's quadrature reference (the library's
//! [`omnee_render::point::estimate`]).

use super::args::ProblemArgs;
use super::summary::{print_result, technique_json};
use clap::Args;
use omnee_render::Result;
use omnee_render::error::Spelling;
use omnee_render::parallel::with_threads;
use omnee_render::point::estimate::estimate;
use serde_json::{Value, json};
use std::sync::atomic::AtomicBool;

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

/// The `technique` and `auto_reason` fields with a lobe at `x0` drawn with
/// probability `c` by the lobe technique.
pub fn lobe_technique_json(used: &str, c: f64) -> (Value, Value) {
    if used == "omnee" {
        return (json!("omnee"), json!(null));
    }
    (
        json!(used),
        json!(format!(
            "a lobe at x0: OMNEE and the lobe technique, one-sample balance MIS choosing the \
             lobe technique with c = {c} (LobeMis::recommended, docs/math.md §12.4)"
        )),
    )
}

/// `omnee estimate`.
pub fn run(a: EstimateArgs) -> Result<()> {
    let problem = a.problem.problem();
    let go = AtomicBool::new(false);
    let e = with_threads(a.threads, || {
        estimate(&problem, a.samples, a.reference, Spelling::Options, &go)
    })??;
    let (mut tech, requested, mut reason) = technique_json(&e.technique);
    if let Some(c) = e.lobe_probability {
        (tech, reason) = lobe_technique_json(&e.technique.used.to_string(), c);
    }
    let (mean, stderr) = (e.mean, e.stderr);
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": e.samples, "seconds": e.seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": {"once-more": {"mean": mean, "stderr": stderr}},
        "accepted": e.accepted, "reference": e.reference,
        "x0": problem.x0, "x2": problem.x2, "phase": e.phase.to_string(), "mean_cosine": e.mean_cosine,
        "sigma_s": problem.sigma_s, "sigma_t": problem.sigma_t, "tau": e.tau, "theta_max": problem.theta_max,
        "receiver_normal": e.receiver_normal, "seed": problem.seed,
        "precision": e.precision.to_string(),
        "x0_phase": e.lobe.as_ref().map(|l| l.phase.to_string()),
        "x0_incoming": e.lobe.as_ref().map(|l| l.incoming),
        "lobe_probability": e.lobe_probability,
    });
    print_result(&v, a.json);
    Ok(())
}
