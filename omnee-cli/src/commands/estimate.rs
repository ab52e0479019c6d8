//! `omnee estimate`: the point-to-point once-more integral in an infinite
//! homogeneous medium, as mean and standard error, optionally against the
//! core's quadrature reference (the library's
//! [`omnee_render::point::estimate`]); with `--vertices` the transfer of
//! K scattering vertices by bridges, against the isotropic closed form.

use super::args::ProblemArgs;
use super::summary::{print_result, technique_json};
use clap::Args;
use omnee_render::Result;
use omnee_render::error::Spelling;
use omnee_render::parallel::with_threads;
use omnee_render::point::bridge::BridgeEstimate;
use omnee_render::point::estimate::estimate;
use omnee_render::vertices::VertexNumber;
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
    /// Also compute the reference: the quadrature (f64, docs/math.md §5), with --vertices other than 1 the isotropic closed form (docs/math.md §14.6).
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

/// The fields of a bridge estimate: `technique`, `auto_reason`, `terms`
/// (one per order) and the rest (`vertices`, `max_vertices`,
/// `vertex_count_mean`, `orders`).
fn bridge_json(b: &BridgeEstimate) -> (Value, Value, Value, Value) {
    let reason = match b.vertices {
        VertexNumber::Fixed(k) => format!(
            "--vertices {k}: bridges of {k} vertices (deflections from the phase function, the \
             chain turned and scaled onto x0 -> x2, docs/math.md §14)"
        ),
        VertexNumber::Auto { max } => format!(
            "--vertices auto: k in 1 ... {max} drawn per sample from a Poisson law of mean {:.4} \
             with a 20 % uniform floor (docs/math.md §14.7), a bridge of k vertices, its estimate \
             divided by P(k)",
            b.mean_count.unwrap_or(0.0)
        ),
    };
    let terms: serde_json::Map<String, Value> = b
        .orders
        .iter()
        .map(|o| {
            (
                format!("k={}", o.k),
                json!({"mean": o.mean, "stderr": o.stderr}),
            )
        })
        .collect();
    let orders: Vec<Value> = b
        .orders
        .iter()
        .map(|o| {
            json!({"k": o.k, "probability": o.probability, "mean": o.mean, "stderr": o.stderr,
                   "reference": o.reference})
        })
        .collect();
    let max = match b.vertices {
        VertexNumber::Auto { max } => json!(max),
        VertexNumber::Fixed(_) => json!(null),
    };
    let rest = json!({"vertices": b.vertices.to_string(), "max_vertices": max,
                      "vertex_count_mean": b.mean_count, "orders": orders});
    (json!("bridge"), json!(reason), Value::Object(terms), rest)
}

/// `omnee estimate`.
pub fn run(a: EstimateArgs) -> Result<()> {
    let problem = a.problem.problem()?;
    let go = AtomicBool::new(false);
    let e = with_threads(a.threads, || {
        estimate(&problem, a.samples, a.reference, Spelling::Options, &go)
    })??;
    let (mut tech, requested, mut reason) = technique_json(&e.technique);
    if let Some(c) = e.lobe_probability {
        (tech, reason) = lobe_technique_json(&e.technique.used.to_string(), c);
    }
    let (mean, stderr) = (e.mean, e.stderr);
    let mut terms = json!({"once-more": {"mean": mean, "stderr": stderr}});
    let mut bridge = json!({"vertices": "1"});
    if let Some(b) = &e.bridge {
        (tech, reason, terms, bridge) = bridge_json(b);
    }
    let mut v = json!({
        "mean": mean, "stderr": stderr, "samples": e.samples, "seconds": e.seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": terms,
        "accepted": e.accepted, "reference": e.reference,
        "x0": problem.x0, "x2": problem.x2, "phase": e.phase.to_string(), "mean_cosine": e.mean_cosine,
        "sigma_s": problem.sigma_s, "sigma_t": problem.sigma_t, "tau": e.tau, "theta_max": problem.theta_max,
        "receiver_normal": e.receiver_normal, "seed": problem.seed,
        "precision": e.precision.to_string(),
        "x0_phase": e.lobe.as_ref().map(|l| l.phase.to_string()),
        "x0_incoming": e.lobe.as_ref().map(|l| l.incoming),
        "lobe_probability": e.lobe_probability,
    });
    if let (Some(v), Value::Object(extra)) = (v.as_object_mut(), bridge) {
        v.extend(extra);
    }
    print_result(&v, a.json);
    Ok(())
}
