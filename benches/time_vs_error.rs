//! Run time against error for the point-to-point once-more integral
//! against its f64 quadrature reference.
//!
//! The problem (docs/math.md §5, `omnee::reference::PointToPoint`): a unit point
//! light at `x0 = 0`, a point receiver at `x2 = (0, 0, 1)` (s = 1), an infinite
//! homogeneous medium with σt·s = τ and albedo 1 (relative errors do not
//! depend on σs), the whole range of deflections θ < π. Every technique
//! estimates `I = ∫ σs p(θ) e^{−σt(d1+d2)} / (d1² d2²) dx1` in f32, the
//! renderer's precision, accumulating in f64:
//!
//! - `omnee`: OMNEE over θ < π (the full range: finite variance because of
//!   the attenuation, docs/math.md §3);
//! - `equiangular`: a uniform direction from `x2`, equiangular distance;
//! - `distance`: a uniform direction from `x2`, free flight with σ = σt;
//! - `mis`: the CLI's, `OmneeMis::recommended`: OMNEE's vertex over θ < π,
//!   and with probability 0.05 an equiangular vertex behind the cone
//!   θ ≥ 3π/4 (balance heuristic behind it, OMNEE alone in front); an
//!   estimate is the sum over both.
//!
//! Each estimate is one draw of `omnee::method::Setup`, as a renderer makes
//! it.
//!
//! For each configuration (phase function × τ) and each technique, `REPS`
//! independent runs of N = 2^8 … 2^`MAX` samples are timed on one thread
//! (techniques interleaved, so load changes hit all of them alike). At each N
//! `relMSE = mean over runs of (estimate/I − 1)²` and `time` = mean time of
//! one run, measured as the thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`):
//! the machine is shared, and CPU time does not count the time the thread
//! waits for a core; the wall time is recorded in the JSON next to it. Plain equiangular and distance sampling have infinite
//! variance for a point light (`1/d1²` near `x0`), so their relMSE is dominated
//! by rare samples: the efficiency `1/(relMSE · time)` of a technique is the
//! **median over the sample counts N ≥ 2^12**, and the relMSE at equal time is
//! read off the measured curve (log-log interpolation; `–` where the budget
//! lies outside the measured times, never an extrapolation).
//!
//! It also re-measures the per-sample relative variances of docs/math.md §6.
//!
//! Run: `cargo bench --bench time_vs_error` (about 3 minutes on one core)
//! with optional `-- --reps R --max-log2 M --budget-ms T`. Writes
//! `docs/results/point-to-point.{md,json}` and `docs/figures/point-to-point.svg`.

mod common;

use common::curve::{Curve, Point};
use common::{
    BENCH_PHASES, COLORS, NAMES, arg, best_other_single, docs_path, fmt_opt, fmt3, loglog, phase,
    ratio, seed,
};
use cpu_time::ThreadTime;
use glam::{DVec3, Vec3};
use omnee::medium::{Homogeneous, Region};
use omnee::method::{Method, Setup};
use omnee::phase::Phase;
use omnee::reference::PointToPoint;
use omnee::rng::SplitMix64;
use omnee::sampling::{Connection, Directions, uniform};
use std::fmt::Write as _;
use std::time::Instant;

/// Optical thicknesses σt·s.
const TAUS: [f64; 3] = [0.1, 1.0, 3.0];
/// Number of techniques.
const NT: usize = Method::ALL.len();
/// Smallest sample count, log2.
const MIN_LOG2: u32 = 8;
/// Sample counts from this log2 on enter the efficiency median (timer
/// resolution and fixed costs matter below).
const EFF_LOG2: u32 = 12;

fn problem_f32(tau: f64, sigma_s: f64, theta_max: f32) -> PointToPoint<f32> {
    let c = Connection::new(Vec3::ZERO, Vec3::Z, theta_max).unwrap();
    let m = Homogeneous::from_extinction(sigma_s as f32, tau as f32).unwrap();
    PointToPoint::new(c, m, None).unwrap()
}

fn reference(spec: &str, tau: f64, sigma_s: f64, theta_max: f64) -> f64 {
    let c = Connection::new(DVec3::ZERO, DVec3::Z, theta_max).unwrap();
    let m = Homogeneous::from_extinction(sigma_s, tau).unwrap();
    PointToPoint::new(c, m, None)
        .unwrap()
        .integral(&phase::<f64>(spec))
}

/// The setup of a configuration: `phase` at `x1`, uniform directions from
/// `x2` in an infinite medium of extinction `sigma_t`.
fn setup<'p>(phase: &'p Phase<'static, f32>, sigma_t: f64) -> Setup<f32, &'p Phase<'static, f32>> {
    Setup::new(
        phase,
        Directions::Sphere,
        Region::Everywhere,
        sigma_t as f32,
    )
    .unwrap()
}

/// Mean and (unbiased) variance of `n` estimates, each the sum of
/// `f_c · weight` over the vertices of one draw of `method`.
#[inline(never)]
fn run(
    setup: &Setup<f32, &Phase<'static, f32>>,
    method: Method,
    p: &PointToPoint<f32>,
    n: u64,
    rng: &mut SplitMix64,
) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let e: f64 = setup
            .draw(method, p.connection, || uniform(rng))
            .sum(|s| p.estimate(s) as f64);
        sum += e;
        sum2 += e * e;
    }
    let mean = sum / n as f64;
    let var = if n > 1 {
        (sum2 - sum * mean).max(0.0) / (n - 1) as f64
    } else {
        0.0
    };
    (mean, var)
}

struct Row {
    spec: &'static str,
    tau: f64,
    reference: f64,
    curves: [Curve; NT],
}

fn measure(spec: &'static str, tau: f64, reps: u64, max_log2: u32) -> Row {
    let sigma_s = tau; // albedo 1
    let reference = reference(spec, tau, sigma_s, std::f64::consts::PI);
    let p = phase::<f32>(spec);
    let problem = problem_f32(tau, sigma_s, std::f32::consts::PI);
    let setup = setup(&p, tau);
    let mut curves: [Curve; NT] = Default::default();
    for log2 in MIN_LOG2..=max_log2 {
        let n = 1u64 << log2;
        let mut sq = [0.0f64; NT];
        let mut secs = [0.0f64; NT];
        let mut wall = [0.0f64; NT];
        for rep in 0..reps {
            for (i, &method) in Method::ALL.iter().enumerate() {
                let mut rng = SplitMix64::new(seed(&[
                    spec.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
                    }),
                    tau.to_bits(),
                    i as u64,
                    log2 as u64,
                    rep,
                ]));
                let (start, cpu) = (Instant::now(), ThreadTime::now());
                let (mean, _) = run(&setup, method, &problem, n, &mut rng);
                secs[i] += cpu.elapsed().as_secs_f64();
                wall[i] += start.elapsed().as_secs_f64();
                sq[i] += (mean / reference - 1.0).powi(2);
            }
        }
        for (i, c) in curves.iter_mut().enumerate() {
            c.points.push(Point {
                count: n,
                cpu_seconds: secs[i] / reps as f64,
                wall_seconds: wall[i] / reps as f64,
                rel_mse: sq[i] / reps as f64,
            });
        }
    }
    Row {
        spec,
        tau,
        reference,
        curves,
    }
}

/// docs/math.md §6: per-sample relative variance Var[estimate]/I², 4·10⁵ samples.
fn math_table(out: &mut String) {
    let rows: [(f64, f64, bool, &str); 8] = [
        (0.25, 0.0, true, "1.03"),
        (0.25, 0.9, true, "0.0265"),
        (0.25, 0.98, true, "4.92e-3"),
        (0.25, 0.997, true, "7.91e-4"),
        (0.0, 0.0, false, "3.51"),
        (0.1, 0.9, false, "0.121"),
        (1.0, 0.0, false, "0.305"),
        (1.0, 0.98, false, "4.50e-3"),
    ];
    let n = 400_000;
    writeln!(
        out,
        "| σt·s | g | OMNEE range | OMNEE rel. var. (docs/math.md §6) | OMNEE mean/I | equiangular rel. var. (θ < π) | equiangular mean/I |\n|---|---|---|---|---|---|---|"
    )
    .unwrap();
    for (k, &(tau, g, forward, math)) in rows.iter().enumerate() {
        let spec = format!("hg:{g}");
        let spec: &'static str = Box::leak(spec.into_boxed_str());
        let theta_max = if forward {
            std::f64::consts::FRAC_PI_2
        } else {
            std::f64::consts::PI
        };
        let p = phase::<f32>(spec);
        let fwd = problem_f32(tau, 0.2, theta_max as f32);
        let full = problem_f32(tau, 0.2, std::f32::consts::PI);
        let (i_fwd, i_full) = (
            reference(spec, tau, 0.2, theta_max),
            reference(spec, tau, 0.2, std::f64::consts::PI),
        );
        let setup = setup(&p, tau);
        let (m_o, v_o) = run(
            &setup,
            Method::Omnee,
            &fwd,
            n,
            &mut SplitMix64::new(seed(&[k as u64, 1])),
        );
        let (m_e, v_e) = run(
            &setup,
            Method::Equiangular,
            &full,
            n,
            &mut SplitMix64::new(seed(&[k as u64, 2])),
        );
        writeln!(
            out,
            "| {tau} | {g} | {} | {} ({}) | {} | {} | {} |",
            if forward { "θ < π/2" } else { "θ < π" },
            fmt3(v_o / (i_fwd * i_fwd)),
            math,
            fmt3(m_o / i_fwd),
            fmt3(v_e / (i_full * i_full)),
            fmt3(m_e / i_full),
        )
        .unwrap();
    }
}

fn plot(rows: &[Row], path: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    let panels: Vec<loglog::Panel> = rows
        .iter()
        .map(|row| loglog::Panel {
            caption: format!("{}, τ = {}", row.spec, row.tau),
            curves: row.curves.iter().map(Curve::time_error).collect(),
        })
        .collect();
    let layout = loglog::Layout {
        names: &NAMES,
        colors: &COLORS,
        cols: TAUS.len(),
        panel: (330, 250),
        legend_step: 190,
        x_desc: "CPU seconds",
    };
    loglog::svg(path, &layout, &panels)
}

fn main() {
    let reps: u64 = arg("--reps", 32);
    let max_log2: u32 = arg("--max-log2", 18);
    let budget = arg("--budget-ms", 4.0f64) * 1e-3;
    let started = Instant::now();

    let mut md = String::new();
    writeln!(
        md,
        "<!-- generated by `cargo bench --bench time_vs_error -- --reps {reps} --max-log2 {max_log2}`; do not edit -->\n"
    )
    .unwrap();
    writeln!(
        md,
        "### docs/math.md §6 re-measured (4·10⁵ samples each, σs = 0.2, s = 1, HG; the value of docs/math.md §6 in parentheses)\n"
    )
    .unwrap();
    math_table(&mut md);

    let mut rows = Vec::new();
    for spec in BENCH_PHASES {
        for tau in TAUS {
            let row = measure(spec, tau, reps, max_log2);
            eprintln!(
                "{spec:>22} tau {tau:>3}: reference {:.6e}, eff {:?} ({:.0} s)",
                row.reference,
                row.curves
                    .iter()
                    .map(|c| c.efficiency(1 << EFF_LOG2))
                    .collect::<Vec<_>>(),
                started.elapsed().as_secs_f64()
            );
            rows.push(row);
        }
    }

    writeln!(
        md,
        "\n### relMSE at equal time ({} ms of one core's CPU time)\n\n\
         Read off each technique's measured relMSE-against-time curve ({reps} independent runs per N, \
         N = 2^{MIN_LOG2} … 2^{max_log2}, log-log interpolation; – where the budget lies outside the measured times). \
         ns/sample is the CPU time per sample at the largest N.\n",
        budget * 1e3
    )
    .unwrap();
    writeln!(
        md,
        "| phase | σt·s | reference I | omnee | equiangular | distance | mis | ns/sample omnee / eq. / dist. / mis |\n|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    let mut eff_md = String::new();
    writeln!(
        eff_md,
        "\n### Efficiency 1/(relMSE·time), relative\n\n\
         Efficiency is the median over N = 2^{EFF_LOG2} … 2^{max_log2} of 1/(relMSE·CPU seconds) (– without such N). \
         `÷ eq.`: relative to equiangular; `÷ best single`: relative to the best of omnee, equiangular, distance \
         other than itself.\n\n\
         | phase | σt·s | omnee ÷ eq. | omnee ÷ best other single | distance ÷ eq. | mis ÷ eq. | mis ÷ best single |\n|---|---|---|---|---|---|---|"
    )
    .unwrap();
    let mut json = Vec::new();
    for row in &rows {
        let eff: Vec<Option<f64>> = row
            .curves
            .iter()
            .map(|c| c.efficiency(1 << EFF_LOG2))
            .collect();
        let best_single = |i: usize| best_other_single(&eff, i);
        let ns = |i: usize| row.curves[i].seconds_per_sample() * 1e9;
        writeln!(
            md,
            "| `{}` | {} | {:.5e} | {} | {} | {} | {} | {:.0} / {:.0} / {:.0} / {:.0} |",
            row.spec,
            row.tau,
            row.reference,
            fmt_opt(row.curves[0].at_time(budget)),
            fmt_opt(row.curves[1].at_time(budget)),
            fmt_opt(row.curves[2].at_time(budget)),
            fmt_opt(row.curves[3].at_time(budget)),
            ns(0),
            ns(1),
            ns(2),
            ns(3),
        )
        .unwrap();
        writeln!(
            eff_md,
            "| `{}` | {} | {} | {} | {} | {} | {} |",
            row.spec,
            row.tau,
            fmt_opt(ratio(eff[0], eff[1])),
            fmt_opt(ratio(eff[0], best_single(0))),
            fmt_opt(ratio(eff[2], eff[1])),
            fmt_opt(ratio(eff[3], eff[1])),
            fmt_opt(ratio(eff[3], best_single(3))),
        )
        .unwrap();
        let curves: Vec<serde_json::Value> = row
            .curves
            .iter()
            .zip(NAMES)
            .map(|(c, name)| {
                serde_json::json!({
                    "technique": name,
                    "efficiency": c.efficiency(1 << EFF_LOG2),
                    "points": c.points_json("n"),
                })
            })
            .collect();
        json.push(serde_json::json!({
            "phase": row.spec, "tau": row.tau, "reference": row.reference, "curves": curves,
        }));
    }
    md.push_str(&eff_md);
    writeln!(
        md,
        "\nTotal run time {:.0} s.",
        started.elapsed().as_secs_f64()
    )
    .unwrap();

    let md_path = docs_path("results/point-to-point.md");
    std::fs::write(&md_path, &md).expect("write markdown");
    let json_path = docs_path("results/point-to-point.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&serde_json::json!({
            "reps": reps, "max_log2": max_log2, "rows": json
        }))
        .unwrap(),
    )
    .expect("write json");
    let svg_path = docs_path("figures/point-to-point.svg");
    plot(&rows, &svg_path).expect("plot");
    println!("{md}");
    eprintln!(
        "wrote {}, {}, {}",
        md_path.display(),
        json_path.display(),
        svg_path.display()
    );
}
