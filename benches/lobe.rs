//! The lobe at `x0`: OMNEE, the lobe technique and their
//! combination on the point-to-point problem, per sample and per
//! unit of time, against the 3-D quadrature reference (docs/math.md §12).
//!
//! The problem: `x0 = 0`, `x2 = (0, 0, 1)` (s = 1), an infinite medium with
//! σs = 0.5, σt = 0.55, θ < π, the same phase function at both vertices
//! (and, in extra rows, an isotropic one at `x0`), light arriving at `x0`
//! along `ω_in` tilted from the axis by 0, 0.05, 0.2, 0.5 or 1 rad. Each
//! technique estimates `I = ∫ σs p0 p1 T T / (d1² d2²) dx1` in f32 (the
//! renderer's precision, accumulated in f64) from `--samples` draws
//! (default 10⁶, the issue's):
//!
//! - `omnee`: OMNEE with `p0` in its weight (`lobe::WithLobe`);
//! - `lobe`: `lobe::LobeRay`, direction from `p0`, deflection from `p1`
//!   restricted to `[α, π)`;
//! - `lobe-eq`: the prototype's, direction from `p0`, then an equiangular
//!   distance about `x2` along it (β uniform in `[0, π − α)`), written here
//!   for the comparison only (with its pdf, for `mis-eq`);
//! - `mis-eq`: one-sample balance MIS of `omnee` and `lobe-eq`, each chosen
//!   with 1/2 (`mis::OneSample`): the prototype's combination;
//! - `mis-half`: the same with `lobe` instead of `lobe-eq`
//!   (`LobeMis::new(.., 0.5)`);
//! - `mis`: `LobeMis::recommended`, the combination the core recommends.
//!
//! Reported per technique: the relative variance per sample
//! `Var/I²`, the CPU time per sample (the thread's, `CLOCK_THREAD_CPUTIME_ID`:
//! the machine is shared, so only ratios within one run mean anything) and
//! the efficiency `1/(relvar · time)`, with its ratio to OMNEE's.
//!
//! Two-term HG weights: `tthg:0.990,-0.440,0.954` has mean cosine 0.924, that
//! of Petzold's average ocean phase function; `tthg:0.997,0.960,0.5` gives
//! both lobes half the mass, a needle 0.003 rad wide and a 0.04 rad lobe,
//! the two-scale shape a single HG cannot fit (mean cosine 0.9785).
//!
//! Run: `cargo bench --bench lobe` (25 minutes on the shared 2-core machine,
//! most of it the 30 references), options `-- --samples N --quick` (`--quick`:
//! the HG rows only). Writes `docs/results/lobe.{md,json}`.

mod common;

use common::{arg, docs_path, flag, fmt3, seed};
use cpu_time::ThreadTime;
use glam::{DVec3, Vec3};
use omnee::Vector;
use omnee::lobe::{Lobe, LobeMis, LobeRay, LobeToPoint, PhaseLobe, WithLobe};
use omnee::medium::Homogeneous;
use omnee::mis::{Heuristic, OneSample};
use omnee::phase::{Deflection, Phase, PhaseFunction, Spec};
use omnee::reference::PointToPoint;
use omnee::rng::SplitMix64;
use omnee::sampling::{Connection, Omnee, Sample, Technique, uniform};
use std::fmt::Write as _;

const SIGMA_S: f64 = 0.5;
const SIGMA_T: f64 = 0.55;
const TILTS: [f64; 5] = [0.0, 0.05, 0.2, 0.5, 1.0];
const PHASES: [&str; 5] = [
    "hg:0.5",
    "hg:0.9",
    "hg:0.98",
    "tthg:0.997,0.960,0.5",
    "tthg:0.990,-0.440,0.954",
];
const TECHS: [&str; 6] = ["omnee", "lobe", "lobe-eq", "mis-eq", "mis-half", "mis"];

fn phase<F: omnee::Real>(spec: &str) -> Phase<'static, F> {
    match Spec::<F>::parse(spec).expect("valid spec") {
        Spec::Analytic(p) => p,
        Spec::Table { .. } => unreachable!("no tables here"),
    }
}

fn incoming(tilt: f64) -> DVec3 {
    DVec3::new(tilt.sin(), 0.0, tilt.cos())
}

fn point<F: omnee::Real>() -> PointToPoint<F> {
    let f = F::from_f64;
    let c = Connection::new(
        F::Vec3::new(f(0.0), f(0.0), f(0.0)),
        F::Vec3::new(f(0.0), f(0.0), f(1.0)),
        F::PI,
    )
    .unwrap();
    PointToPoint::new(
        c,
        Homogeneous::from_extinction(f(SIGMA_S), f(SIGMA_T)).unwrap(),
        None,
    )
    .unwrap()
}

/// The prototype's lobe technique: direction from the lobe, then β uniform
/// in `[0, π − α)` (equiangular about `x2` along the ray):
/// `pdf(x1) = pdf_ω · s sin α / ((π − α) d1² d2²)`,
/// `k/pdf = (eval/pdf_ω) p1(θ) (π − α) / (s sin α)`.
struct LobeEquiangular<L, P> {
    connection: Connection<f32>,
    lobe: L,
    phase: P,
}

impl<L: Lobe<f32>, P: PhaseFunction<f32>> Technique<f32> for LobeEquiangular<L, P> {
    fn sample(&self, u: [f32; 3]) -> Option<Sample<f32>> {
        let axis = &self.connection.axis;
        let dir = self.lobe.sample([u[0], u[1]])?;
        let alpha = Deflection::between(axis.e, dir.omega);
        let sin_alpha = alpha.sin();
        if !(sin_alpha > 0.0) {
            return None;
        }
        let beta = u[2] * (std::f32::consts::PI - alpha.theta);
        let theta = Deflection::from_theta(alpha.theta + beta);
        let triangle = omnee::circumcircle::Triangle::solve(axis.s, theta, beta / theta.theta)?;
        let (d1, d2) = (triangle.d1, triangle.d2);
        if !(d1 > 0.0 && d2 > 0.0) {
            return None;
        }
        let span = std::f32::consts::PI - alpha.theta;
        let r = 1.0 / (d1 * d2);
        Some(Sample {
            x1: axis.x0 + dir.omega * d1,
            pdf: dir.pdf * axis.s * sin_alpha / span * r * r,
            weight: dir.value / dir.pdf * self.phase.eval(theta) * span / (axis.s * sin_alpha),
        })
    }
    fn pdf(&self, x1: Vec3) -> f32 {
        let axis = &self.connection.axis;
        let Some((_, d1, d2)) = self.connection.deflection(x1) else {
            return 0.0;
        };
        let omega = (x1 - axis.x0) / d1;
        let alpha = Deflection::between(axis.e, omega);
        let span = std::f32::consts::PI - alpha.theta;
        if !(span > 0.0) {
            return 0.0;
        }
        let r = 1.0 / (d1 * d2);
        self.lobe.pdf(omega) * axis.s * alpha.sin() / span * r * r
    }
    fn invert(&self, _x1: Vec3) -> Option<[f32; 3]> {
        None
    }
}

/// Mean and variance of `n` estimates `f_c · weight` of `t`, and the CPU
/// seconds they took.
#[inline(never)]
fn run(
    t: &dyn Technique<f32>,
    p: &PointToPoint<f32>,
    n: u64,
    rng: &mut SplitMix64,
) -> (f64, f64, f64) {
    let start = ThreadTime::now();
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let u = [uniform(rng), uniform(rng), uniform(rng)];
        let e = t.sample(u).map_or(0.0, |s| p.estimate(&s) as f64);
        sum += e;
        sum2 += e * e;
    }
    let seconds = start.elapsed().as_secs_f64();
    let mean = sum / n as f64;
    let var = (sum2 - sum * mean).max(0.0) / (n - 1) as f64;
    (mean, var, seconds)
}

/// One configuration's measurements per technique: (mean, relvar, seconds
/// per sample).
struct Row {
    p0: String,
    p1: String,
    tilt: f64,
    reference: f64,
    c: f64,
    results: Vec<(f64, f64, f64)>,
}

fn measure(spec0: &str, spec1: &str, tilt: f64, n: u64) -> Row {
    let p64 = point::<f64>();
    let lobe64 = PhaseLobe::new(phase::<f64>(spec0), incoming(tilt)).unwrap();
    let reference = LobeToPoint::new(p64, Some(lobe64))
        .unwrap()
        .integral(&phase::<f64>(spec1));
    let p = point::<f32>();
    let c = p.connection;
    let lobe = PhaseLobe::new(phase::<f32>(spec0), incoming(tilt).as_vec3()).unwrap();
    let p1 = phase::<f32>(spec1);
    let omnee = WithLobe::new(Omnee::new(c, p1), lobe, c.axis.x0);
    let ray = LobeRay::new(c, lobe, p1);
    let eq = LobeEquiangular {
        connection: c,
        lobe,
        phase: p1,
    };
    let mis_eq = OneSample::new(
        [&omnee as &dyn Technique<f32>, &eq],
        [0.5, 0.5],
        Heuristic::Balance,
    )
    .unwrap();
    let half = LobeMis::new(c, lobe, p1, 0.5).unwrap();
    let mis = LobeMis::recommended(c, lobe, p1);
    let techniques: [&dyn Technique<f32>; 6] = [&omnee, &ray, &eq, &mis_eq, &half, &mis];
    let results = techniques
        .iter()
        .map(|t| {
            // Common random numbers: every technique gets the same stream,
            // so with c = 0 the combination repeats OMNEE's estimates exactly.
            let mut rng = SplitMix64::new(seed(&[
                (tilt * 1e3) as u64,
                spec0.len() as u64,
                spec1.len() as u64,
            ]));
            let (mean, var, seconds) = run(*t, &p, n, &mut rng);
            (
                mean / reference,
                var / (reference * reference),
                seconds / n as f64,
            )
        })
        .collect();
    Row {
        p0: spec0.into(),
        p1: spec1.into(),
        tilt,
        reference,
        c: f64::from(mis.probability()),
        results,
    }
}

fn main() {
    let n: u64 = arg("--samples", 1_000_000);
    let quick = flag("--quick");
    let mut rows = Vec::new();
    let phases: Vec<&str> = PHASES
        .iter()
        .copied()
        .filter(|s| !quick || s.starts_with("hg"))
        .collect();
    for &spec in &phases {
        for (spec0, tilts) in [(spec, &TILTS[..]), ("iso", &TILTS[..1])] {
            for &tilt in tilts {
                let start = std::time::Instant::now();
                let row = measure(spec0, spec, tilt, n);
                eprintln!(
                    "{spec0} / {spec} tilt {tilt}: I = {:.6e}, c = {:.3}, {:.1} s",
                    row.reference,
                    row.c,
                    start.elapsed().as_secs_f64()
                );
                for (name, r) in TECHS.iter().zip(&row.results) {
                    eprintln!(
                        "  {name:9} mean/I {:.4} relvar {} time {} ns eff {}",
                        r.0,
                        fmt3(r.1),
                        fmt3(r.2 * 1e9),
                        fmt3(1.0 / (r.1 * r.2))
                    );
                }
                rows.push(row);
            }
        }
    }
    write(&rows, n);
}

/// `docs/results/lobe.{md,json}`.
fn write(rows: &[Row], n: u64) {
    let command = format!("cargo bench --bench lobe -- --samples {n}");
    let mut md = String::new();
    writeln!(
        md,
        "# The lobe at x0: OMNEE, the lobe technique and their combination\n"
    )
    .unwrap();
    writeln!(
        md,
        "Measured by `{command}` (benches/lobe.rs; {n} f32 samples per entry, \
         the 2-core machine shared with other work: times are CPU times of one \
         thread, compare them only within this table). s = 1, σs = {SIGMA_S}, \
         σt = {SIGMA_T}, infinite medium, θ < π, ω_in tilted from the axis by the \
         given angle. relvar = Var/I² per sample against the 3-D quadrature \
         reference; mean/I is the estimate over the reference; eff = \
         1/(relvar · time); × omnee is the efficiency over OMNEE's. c is the \
         probability with which `LobeMis::recommended` draws the lobe technique.\n"
    )
    .unwrap();
    writeln!(
        md,
        "| p0 | p1 | tilt | c | technique | mean/I | relvar | ns/sample | eff | × omnee |\n|---|---|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    let mut json = Vec::new();
    for r in rows {
        let omnee_eff = 1.0 / (r.results[0].1 * r.results[0].2);
        for (name, t) in TECHS.iter().zip(&r.results) {
            let eff = 1.0 / (t.1 * t.2);
            writeln!(
                md,
                "| {} | {} | {} | {} | {name} | {:.4} | {} | {} | {} | {} |",
                r.p0,
                r.p1,
                r.tilt,
                fmt3(r.c),
                t.0,
                fmt3(t.1),
                fmt3(t.2 * 1e9),
                fmt3(eff),
                fmt3(eff / omnee_eff)
            )
            .unwrap();
            json.push(serde_json::json!({
                "p0": r.p0, "p1": r.p1, "tilt": r.tilt, "reference": r.reference,
                "c": r.c, "technique": name, "mean_over_reference": t.0,
                "relvar": t.1, "seconds_per_sample": t.2, "efficiency": eff,
                "efficiency_over_omnee": eff / omnee_eff,
            }));
        }
    }
    let out = serde_json::json!({ "command": command, "samples": n, "rows": json });
    std::fs::write(docs_path("results/lobe.md"), md).unwrap();
    std::fs::write(
        docs_path("results/lobe.json"),
        serde_json::to_string_pretty(&out).unwrap(),
    )
    .unwrap();
    println!("{command}: wrote docs/results/lobe.md and docs/results/lobe.json");
}
