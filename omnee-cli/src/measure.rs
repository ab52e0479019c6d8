//! `probe`, `estimate` and `samples`: Monte Carlo estimates with standard
//! errors, and raw technique samples.
//!
//! Samples are drawn in chunks of [`CHUNK`], chunk `k` from the random stream
//! `(seed, k)`, and the chunks' sums are combined in order: the result
//! depends on the seed and the sample count, never on the thread count.

use crate::cli::{
    EstimateArgs, Precision, ProbeArgs, ProblemArgs, SampleFormat, SamplesArgs, with_threads,
};
use crate::error::{CliError, Result, core_error};
use crate::phase::{PhaseSpec, TableStorage};
use crate::rng::Rng;
use crate::scene::{Range, Scene};
use crate::technique::{Choice, Setup, choose};
use crate::world::{OnceMore, Stats, World};
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::phase::PhaseFunction;
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Directions};
use omnee_core::{Real, Vector};
use rayon::prelude::*;
use serde_json::{Value, json};
use std::time::Instant;

/// Samples per chunk (one random stream each).
pub const CHUNK: u64 = 4096;

/// Running sums of an estimator: `Σx`, `Σx²`.
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    sum: f64,
    sum2: f64,
}

impl Moments {
    fn push(&mut self, x: f64) {
        self.sum += x;
        self.sum2 += x * x;
    }
    fn add(&mut self, o: &Moments) {
        self.sum += o.sum;
        self.sum2 += o.sum2;
    }
    /// `(mean, standard error of the mean)` over `n` samples.
    fn mean_stderr(&self, n: u64) -> (f64, f64) {
        let n = n as f64;
        let mean = self.sum / n;
        let var = ((self.sum2 - self.sum * mean) / (n - 1.0).max(1.0)).max(0.0);
        (mean, (var / n).sqrt())
    }
}

/// Runs `f(chunk index, samples in chunk)` over all chunks in parallel and
/// returns the results in chunk order.
fn chunked<T: Send>(samples: u64, f: impl Fn(u64, u64) -> T + Sync) -> Vec<T> {
    let chunks = samples.div_ceil(CHUNK);
    (0..chunks)
        .into_par_iter()
        .map(|k| f(k, CHUNK.min(samples - k * CHUNK)))
        .collect()
}

fn vec3<F: Real>(a: [f64; 3]) -> F::Vec3 {
    F::Vec3::new(F::from_f64(a[0]), F::from_f64(a[1]), F::from_f64(a[2]))
}

fn check_samples(field: &str, n: u64) -> Result<u64> {
    if (1..=1u64 << 40).contains(&n) {
        Ok(n)
    } else {
        Err(CliError::range(field, n, "[1, 2^40]"))
    }
}

fn unit_normal(field: &str, n: [f64; 3]) -> Result<[f64; 3]> {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !(len > 0.0) {
        return Err(CliError::Input(format!(
            "{field} = {},{},{} has zero length; allowed: any non-zero vector",
            n[0], n[1], n[2]
        )));
    }
    Ok([n[0] / len, n[1] / len, n[2] / len])
}

fn choice_json(c: &Choice) -> (Value, Value, Value) {
    (json!(c.tech.name()), json!(c.requested), json!(c.reason))
}

/// `omnee probe`.
pub fn probe(a: ProbeArgs) -> Result<()> {
    let scene = match &a.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::default_scene(),
    };
    let samples = check_samples("--samples", a.samples)?;
    let n = unit_normal("--normal", a.normal)?;
    let mut direct = false;
    let mut once_more = false;
    for t in &a.terms {
        match t.as_str() {
            "direct" => direct = true,
            "once-more" => once_more = true,
            other => {
                return Err(CliError::Input(format!(
                    "--terms = \"{other}\" is not a probe term; allowed: direct, once-more (view belongs to a camera ray)"
                )));
            }
        }
    }
    let theta_max = match a.theta_max {
        Some(t) => Range::open_closed(0.0, std::f64::consts::PI).check("--theta-max", t)?,
        None => scene.render.theta_max,
    };
    let l = &scene.light;
    let to_light = [0, 1, 2].map(|i| a.point[i] - l.center[i]);
    let dist = (to_light[0].powi(2) + to_light[1].powi(2) + to_light[2].powi(2)).sqrt();
    if !(dist > l.radius) {
        return Err(CliError::range(
            "--point",
            format!("{},{},{}", a.point[0], a.point[1], a.point[2]),
            format!(
                "outside the light (distance from {:?} > {})",
                l.center, l.radius
            ),
        ));
    }
    if a.point[2] < scene.floor.z {
        return Err(CliError::range(
            "--point",
            format!("{},{},{}", a.point[0], a.point[1], a.point[2]),
            format!(
                "z >= floor.z = {} (on or above the opaque floor)",
                scene.floor.z
            ),
        ));
    }
    let mut storage = TableStorage::<f32>::default();
    let world = World::new(&scene, scene.medium.phase.instantiate::<f32>(&mut storage)?);
    let g = world.phase.mean_cosine() as f64;
    let choice = choose(
        "--technique",
        &a.technique,
        g,
        scene.medium.sigma_t() * dist,
    )?;
    let once_more = once_more && world.scatters();
    let how = OnceMore {
        tech: choice.tech,
        theta_max: theta_max as f32,
    };
    let (p, nv) = (vec3::<f32>(a.point), vec3::<f32>(n));
    let start = Instant::now();
    let chunks = with_threads(a.threads, || {
        chunked(samples, |k, count| {
            let mut rng = Rng::stream(a.seed, k, 0x7072_6f62);
            let mut st = Stats::default();
            let (mut md, mut mo, mut mt) =
                (Moments::default(), Moments::default(), Moments::default());
            for _ in 0..count {
                let d = if direct {
                    world.direct(p, nv, &mut rng, (0.0, 0.0), &mut st) as f64
                } else {
                    0.0
                };
                let o = if once_more {
                    world.once_more(p, nv, how, &mut rng, (0.0, 0.0), &mut st) as f64
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
    let (mut md, mut mo, mut mt, mut st) = (
        Moments::default(),
        Moments::default(),
        Moments::default(),
        Stats::default(),
    );
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
        terms.insert("direct".into(), json!({"mean": m, "stderr": e}));
    }
    if once_more {
        let (m, e) = mo.mean_stderr(samples);
        terms.insert("once-more".into(), json!({"mean": m, "stderr": e}));
    }
    let (tech, requested, reason) = choice_json(&choice);
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": samples, "seconds": seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": terms, "units": "W/m^2", "point": a.point, "normal": n, "theta_max": theta_max,
        "seed": a.seed, "visibility_tests": st.visibility_tests,
        "skipped": if !world.scatters() { json!(["sigma_s = 0: once-more term skipped"]) } else { json!([]) },
    });
    print_result(&v, a.json);
    Ok(())
}

fn print_result(v: &Value, as_json: bool) {
    if as_json {
        println!("{v}");
        return;
    }
    println!(
        "{} +- {} ({} samples, {:.3} s, technique {})",
        v["mean"],
        v["stderr"],
        v["samples"],
        v["seconds"].as_f64().unwrap_or(0.0),
        v["technique"]
    );
    if let Some(r) = v["auto_reason"].as_str() {
        println!("auto: {r}");
    }
    if let Some(terms) = v["terms"].as_object() {
        for (k, t) in terms {
            println!("  {k}: {} +- {}", t["mean"], t["stderr"]);
        }
    }
    if !v["reference"].is_null() {
        println!("  reference (quadrature): {}", v["reference"]);
    }
}

/// The validated point-to-point problem in f64.
struct Problem {
    phase: PhaseSpec,
    normal: Option<[f64; 3]>,
    g: f64,
    tau: f64,
    choice: Choice,
}

fn problem(a: &ProblemArgs) -> Result<Problem> {
    let phase = PhaseSpec::parse(&a.phase).map_err(|e| e.context("--phase"))?;
    Range::NON_NEGATIVE.check("--sigma-s", a.sigma_s)?;
    if !(a.sigma_t.is_finite() && a.sigma_t >= a.sigma_s) {
        return Err(CliError::range(
            "--sigma-t",
            a.sigma_t,
            format!("[sigma_s, inf) = [{}, inf)", a.sigma_s),
        ));
    }
    Range::open_closed(0.0, std::f64::consts::PI).check("--theta-max", a.theta_max)?;
    let normal = a
        .receiver_normal
        .map(|n| unit_normal("--receiver-normal", n))
        .transpose()?;
    let d = [0, 1, 2].map(|i| a.x2[i] - a.x0[i]);
    let s = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if !(s > 0.0) {
        return Err(CliError::Input(format!(
            "--x2 = {},{},{} equals --x0; allowed: any other point",
            a.x2[0], a.x2[1], a.x2[2]
        )));
    }
    let mut st = TableStorage::<f64>::default();
    let g = phase.instantiate::<f64>(&mut st)?.mean_cosine();
    let tau = a.sigma_t * s;
    let choice = choose("--technique", &a.technique, g, tau)?;
    Ok(Problem {
        phase,
        normal,
        g,
        tau,
        choice,
    })
}

/// A vertex of a draw: `(x1, pdf, weight, f_c·weight)`.
type Vertex = ([f64; 3], f64, f64, f64);

/// One draw: its uniform numbers and vertices (the technique's own and, for
/// `mis`, the companion's).
type Draw<F> = ([F; 6], [Option<Vertex>; 2]);

/// Runs `f` with a sampler for the problem in precision `F`.
fn with_sampler<F: Real, T>(
    a: &ProblemArgs,
    p: &Problem,
    f: impl FnOnce(&(dyn Fn(&mut Rng) -> Draw<F> + Sync), &PointToPoint<F>) -> T,
) -> Result<T> {
    let connection =
        Connection::<F>::new(vec3::<F>(a.x0), vec3::<F>(a.x2), F::from_f64(a.theta_max))
            .map_err(|e| core_error("--x0/--x2/--theta-max", e))?;
    let medium = Homogeneous::new(F::from_f64(a.sigma_s), F::from_f64(a.sigma_t - a.sigma_s))
        .map_err(|e| core_error("--sigma-s/--sigma-t", e))?;
    let problem = PointToPoint::new(connection, medium, p.normal.map(vec3::<F>))
        .map_err(|e| core_error("--receiver-normal", e))?;
    let mut storage = TableStorage::<F>::default();
    let phase = p.phase.instantiate::<F>(&mut storage)?;
    let directions = match p.normal {
        Some(n) => {
            Directions::cosine(vec3::<F>(n)).map_err(|e| core_error("--receiver-normal", e))?
        }
        None => Directions::Sphere,
    };
    let setup = Setup {
        phase: &phase,
        directions,
        region: Region::Everywhere,
        sigma_t: F::from_f64(a.sigma_t),
    };
    let tech = p.choice.tech;
    let draw = |rng: &mut Rng| -> Draw<F> {
        let d = setup.sample(tech, connection, rng);
        let vertex = |s: &omnee_core::sampling::Sample<F>| {
            let [x, y, z] = s.x1.to_array();
            (
                [x.to_f64(), y.to_f64(), z.to_f64()],
                s.pdf.to_f64(),
                s.weight.to_f64(),
                problem.estimate(s).to_f64(),
            )
        };
        (d.u, d.vertices.map(|v| v.as_ref().map(vertex)))
    };
    Ok(f(&draw, &problem))
}

/// `omnee estimate`.
pub fn estimate(a: EstimateArgs) -> Result<()> {
    let samples = check_samples("--samples", a.samples)?;
    let p = problem(&a.problem)?;
    let start = Instant::now();
    let (moments, accepted, reference) = match a.problem.precision {
        Precision::F32 => run_estimate::<f32>(&a, &p, samples)?,
        Precision::F64 => run_estimate::<f64>(&a, &p, samples)?,
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
        "receiver_normal": p.normal, "seed": pa.seed,
        "precision": match pa.precision { Precision::F32 => "f32", Precision::F64 => "f64" },
    });
    print_result(&v, a.json);
    Ok(())
}

fn run_estimate<F: Real>(
    a: &EstimateArgs,
    p: &Problem,
    samples: u64,
) -> Result<(Moments, u64, Option<f64>)> {
    let seed = a.problem.seed;
    let threads = a.threads;
    let want_reference = a.reference;
    let phase = &p.phase;
    with_sampler::<F, _>(&a.problem, p, |draw, problem| {
        let chunks = with_threads(threads, || {
            chunked(samples, |k, count| {
                let mut rng = Rng::stream(seed, k, 0x6573_7469);
                let mut m = Moments::default();
                let mut accepted = 0u64;
                for _ in 0..count {
                    let (_, vertices) = draw(&mut rng);
                    accepted += u64::from(vertices[0].is_some());
                    m.push(vertices.iter().flatten().map(|v| v.3).sum());
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
        let reference = if want_reference {
            let mut st = TableStorage::<f64>::default();
            let ph = phase.instantiate::<f64>(&mut st)?;
            Some(problem.integral(&ph))
        } else {
            None
        };
        Ok((m, accepted, reference))
    })?
}

/// `omnee samples`.
pub fn samples(a: SamplesArgs) -> Result<()> {
    let count = check_samples("--count", a.count)?;
    let p = problem(&a.problem)?;
    let rows = match a.problem.precision {
        Precision::F32 => sample_rows::<f32>(&a.problem, &p, count)?,
        Precision::F64 => sample_rows::<f64>(&a.problem, &p, count)?,
    };
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    use std::io::Write;
    let w = |r: std::io::Result<()>| {
        r.map_err(|e| CliError::Io(format!("cannot write to stdout: {e}")))
    };
    match a.format {
        SampleFormat::Csv => {
            w(writeln!(
                out,
                "draw,vertex,u0,u1,u2,x,y,z,pdf,weight,estimate"
            ))?;
            for (i, k, u, (x, pdf, weight, e)) in &rows {
                w(writeln!(
                    out,
                    "{i},{k},{},{},{},{},{},{},{pdf},{weight},{e}",
                    u[0], u[1], u[2], x[0], x[1], x[2]
                ))?;
            }
        }
        SampleFormat::Json => {
            let list: Vec<Value> = rows
                .iter()
                .map(|(i, k, u, (x, pdf, weight, e))| {
                    json!({"draw": i, "vertex": k, "u": u, "x1": x, "pdf": pdf, "weight": weight, "estimate": e})
                })
                .collect();
            let (tech, requested, reason) = choice_json(&p.choice);
            let v = json!({
                "technique": tech, "technique_requested": requested, "auto_reason": reason,
                "draws": count, "returned": rows.len(), "samples": list,
            });
            w(writeln!(out, "{v}"))?;
        }
    }
    w(out.flush())
}

/// `(draw, vertex, its three uniform numbers, vertex)`.
type Row = (u64, usize, [f64; 3], Vertex);

fn sample_rows<F: Real>(a: &ProblemArgs, p: &Problem, count: u64) -> Result<Vec<Row>> {
    with_sampler::<F, _>(a, p, |draw, _| {
        let mut rows = Vec::new();
        let chunks = count.div_ceil(CHUNK);
        for k in 0..chunks {
            let mut rng = Rng::stream(a.seed, k, 0x6573_7469);
            for j in 0..CHUNK.min(count - k * CHUNK) {
                let (u, vertices) = draw(&mut rng);
                for (v, vertex) in vertices.into_iter().enumerate() {
                    if let Some(s) = vertex {
                        let own = [u[3 * v], u[3 * v + 1], u[3 * v + 2]].map(|x| x.to_f64());
                        rows.push((k * CHUNK + j, v, own, s));
                    }
                }
            }
        }
        rows
    })
}
