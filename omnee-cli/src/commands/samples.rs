//! `omnee samples`: the `x1` of a technique's draws with their pdf, weight
//! and estimate, as CSV or JSON (the library's
//! [`omnee_render::point::samples`]).

use super::args::{ProblemArgs, parse_count};
use super::estimate::lobe_technique_json;
use super::summary::technique_json;
use crate::named::closed;
use clap::Args;
use omnee_core::names::Named;
use omnee_render::error::Spelling;
use omnee_render::point::samples::samples;
use omnee_render::{RenderError, Result};
use serde_json::{Value, json};
use std::io::Write;

/// Output formats of `samples`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleFormat {
    /// Comma-separated values with a header line.
    Csv,
    /// A JSON object with a `samples` array.
    Json,
}

impl Named for SampleFormat {
    const ALL: &'static [Self] = &[SampleFormat::Csv, SampleFormat::Json];
    fn name(self) -> &'static str {
        match self {
            SampleFormat::Csv => "csv",
            SampleFormat::Json => "json",
        }
    }
    fn help(self) -> &'static str {
        match self {
            SampleFormat::Csv => "comma-separated values with a header line",
            SampleFormat::Json => "a JSON object with a `samples` array",
        }
    }
}

/// The options of `omnee samples`.
#[derive(Args, Debug)]
pub struct SamplesArgs {
    /// The problem.
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Number of draws, [1, 2^24] (draws that give no x1 are not listed).
    #[arg(long, default_value_t = 1000, value_parser = parse_count, allow_hyphen_values = true)]
    pub count: u64,
    /// Output format.
    #[arg(long, value_parser = closed::<SampleFormat>(), default_value = "csv")]
    pub format: SampleFormat,
}

/// `omnee samples`.
pub fn run(a: SamplesArgs) -> Result<()> {
    let problem = a.problem.problem()?;
    let s = samples(&problem, a.count, Spelling::Options)?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let w = |r: std::io::Result<()>| {
        r.map_err(|e| RenderError::Io(format!("cannot write to stdout: {e}")))
    };
    match a.format {
        SampleFormat::Csv => {
            w(writeln!(
                out,
                "draw,vertex,u0,u1,u2,x,y,z,pdf,weight,estimate"
            ))?;
            for r in &s.rows {
                let (u, x) = (r.u, r.x1);
                w(writeln!(
                    out,
                    // Floats as `{:?}`: shortest round trip, with an exponent
                    // at extreme scales (1e-30, not 30 zeros).
                    "{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
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
            let list: Vec<Value> = s
                .rows
                .iter()
                .map(|r| {
                    json!({"draw": r.draw, "vertex": r.vertex, "u": r.u, "x1": r.x1, "pdf": r.pdf,
                           "weight": r.weight, "estimate": r.estimate})
                })
                .collect();
            let technique = &s.prepared.technique;
            let (mut tech, requested, mut reason) = technique_json(technique);
            if let Some(c) = s.lobe_probability {
                (tech, reason) = lobe_technique_json(&technique.used.to_string(), c);
            }
            if s.prepared.bridges() {
                (tech, reason) = (json!("bridge"), json!(null));
            }
            let lobe = s.prepared.lobe.as_ref();
            let v = json!({
                "technique": tech, "technique_requested": requested, "auto_reason": reason,
                "draws": a.count, "returned": s.rows.len(), "samples": list,
                "x0_phase": lobe.map(|l| l.phase.to_string()),
                "x0_incoming": lobe.map(|l| l.incoming), "lobe_probability": s.lobe_probability,
                "vertices": s.prepared.vertices.to_string(),
            });
            w(writeln!(out, "{v}"))?;
        }
    }
    w(out.flush())?;
    let saturated = s.saturated();
    if saturated > 0 {
        eprintln!(
            "omnee: note: {saturated} of {} rows have a pdf or weight beyond {}'s range, listed \
             as its largest number (their estimates are right, formed in f64); {} f64 lists \
             densities up to 1.8e308",
            s.rows.len(),
            problem.precision,
            Spelling::Options.of("precision"),
        );
    }
    Ok(())
}
