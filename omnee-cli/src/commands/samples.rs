//! `omnee samples`: the `x1` of a technique's draws with their pdf, weight
//! and estimate, as CSV or JSON.

use super::args::check_count;
use super::estimate::{Lobe, LobeArgs, STREAM, lobe_technique_json, with_lobe};
use super::problem::{Precision, Problem, ProblemArgs, with_sampler, x1_f64};
use super::summary::choice_json;
use crate::error::{CliError, Result};
use crate::parallel::{CHUNK, chunks};
use crate::rng::Rng;
use clap::{Args, ValueEnum};
use omnee_core::Real;
use serde_json::{Value, json};
use std::io::Write;

/// Output formats of `samples`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SampleFormat {
    /// comma-separated values with a header line
    Csv,
    /// a JSON object with a `samples` array
    Json,
}

/// The options of `omnee samples`.
#[derive(Args, Debug)]
pub struct SamplesArgs {
    /// The problem.
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// A lobe at x0.
    #[command(flatten)]
    pub lobe: LobeArgs,
    /// Number of draws (draws that give no x1 are not listed).
    #[arg(long, default_value_t = 1000)]
    pub count: u64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = SampleFormat::Csv)]
    pub format: SampleFormat,
}

/// One listed vertex: its draw, which of the draw's vertices it is (0: the
/// technique's own, 1: the MIS companion), the three uniform numbers that
/// placed it, `x1`, its pdf, weight and `f_c·weight`.
struct Row {
    draw: u64,
    vertex: usize,
    u: [f64; 3],
    x1: [f64; 3],
    pdf: f64,
    weight: f64,
    estimate: f64,
}

/// `omnee samples`.
pub fn run(a: SamplesArgs) -> Result<()> {
    let count = check_count("--count", a.count)?;
    let p = Problem::new(&a.problem)?;
    let lobe = a.lobe.check()?;
    let (rows, c) = match (&lobe, a.problem.precision) {
        (None, Precision::F32) => (rows::<f32>(&a.problem, &p, count)?, None),
        (None, Precision::F64) => (rows::<f64>(&a.problem, &p, count)?, None),
        (Some(l), Precision::F32) => lobe_rows::<f32>(&a.problem, &p, l, count)?,
        (Some(l), Precision::F64) => lobe_rows::<f64>(&a.problem, &p, l, count)?,
    };
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let w = |r: std::io::Result<()>| {
        r.map_err(|e| CliError::Io(format!("cannot write to stdout: {e}")))
    };
    match a.format {
        SampleFormat::Csv => {
            w(writeln!(
                out,
                "draw,vertex,u0,u1,u2,x,y,z,pdf,weight,estimate"
            ))?;
            for r in &rows {
                let (u, x) = (r.u, r.x1);
                w(writeln!(
                    out,
                    "{},{},{},{},{},{},{},{},{},{},{}",
                    r.draw,
                    r.vertex,
                    u[0],
                    u[1],
                    u[2],
                    x[0],
                    x[1],
                    x[2],
                    r.pdf,
                    r.weight,
                    r.estimate
                ))?;
            }
        }
        SampleFormat::Json => {
            let list: Vec<Value> = rows
                .iter()
                .map(|r| {
                    json!({"draw": r.draw, "vertex": r.vertex, "u": r.u, "x1": r.x1, "pdf": r.pdf,
                           "weight": r.weight, "estimate": r.estimate})
                })
                .collect();
            let (mut tech, requested, mut reason) = choice_json(&p.choice);
            if let Some(c) = c {
                (tech, reason) = lobe_technique_json(a.problem.technique, c);
            }
            let v = json!({
                "technique": tech, "technique_requested": requested, "auto_reason": reason,
                "draws": count, "returned": rows.len(), "samples": list,
                "x0_phase": lobe.as_ref().map(|l| l.phase.to_string()),
                "x0_incoming": lobe.as_ref().map(|l| l.incoming), "lobe_probability": c,
            });
            w(writeln!(out, "{v}"))?;
        }
    }
    w(out.flush())
}

/// The vertices of `count` draws in precision `F`, drawn in the chunks and
/// streams of `estimate` (the same seed lists the draws it averages).
fn rows<F: Real>(a: &ProblemArgs, p: &Problem, count: u64) -> Result<Vec<Row>> {
    with_sampler::<F, _>(a, p, |sampler| {
        let mut rows = Vec::new();
        for (k, n) in chunks(count) {
            let mut rng = Rng::stream(a.seed, k, STREAM);
            for j in 0..n {
                let draw = sampler.draw(&mut rng);
                for (v, vertex) in draw.vertices.iter().enumerate() {
                    if let (Some(s), Some(u)) = (vertex, draw.vertex_numbers(v)) {
                        rows.push(Row {
                            draw: k * CHUNK + j,
                            vertex: v,
                            u: u.map(|x| x.to_f64()),
                            x1: x1_f64(s),
                            pdf: s.pdf.to_f64(),
                            weight: s.weight.to_f64(),
                            estimate: sampler.estimate(s),
                        });
                    }
                }
            }
        }
        rows
    })
}

/// The vertices of `count` draws with a lobe at `x0` (one vertex a draw,
/// from three uniform numbers, in the streams of `estimate`), and the lobe
/// technique's probability.
fn lobe_rows<F: Real>(
    a: &ProblemArgs,
    p: &Problem,
    lobe: &Lobe,
    count: u64,
) -> Result<(Vec<Row>, Option<f64>)> {
    with_lobe::<F, _>(a, p, lobe, |t, problem| {
        let mut rows = Vec::new();
        for (k, n) in chunks(count) {
            let mut rng = Rng::stream(a.seed, k, STREAM);
            for j in 0..n {
                let u: [F; 3] = [rng.uniform(), rng.uniform(), rng.uniform()];
                if let Some(s) = t.sample(u) {
                    rows.push(Row {
                        draw: k * CHUNK + j,
                        vertex: 0,
                        u: u.map(|x| x.to_f64()),
                        x1: x1_f64(&s),
                        pdf: s.pdf.to_f64(),
                        weight: s.weight.to_f64(),
                        estimate: problem.estimate(&s).to_f64(),
                    });
                }
            }
        }
        Ok((rows, Some(t.probability())))
    })
}
