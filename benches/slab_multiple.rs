//! The slab scene's `multiple` term (light scattered 2 … K times on its
//! way to the floor, docs/math.md §14.9): bridges against path tracing with
//! next event estimation, run time against error and at equal time.
//!
//! `cargo bench --bench slab_multiple` (options after `--`):
//!
//! - `--phases G1,G2,…`: the Henyey–Greenstein g of each variant (default
//!   0.5,0.9,0.98); everything else is the default scene (`omnee
//!   default-scene`: σs = 0.5, σa = 0.05, a light of radius 0.01 at 0.95 m
//!   over the floor, the perforated plate between them), with `--terms
//!   multiple --vertices auto --max-vertices 8` (orders 2 … 8);
//! - `--resolution WxH` (default 160x120);
//! - `--max-log2 K`: each method renders 1, 2, 4, … 2^K spp (default 7);
//! - `--reference-spp N`: the reference, the mean of two bridge renders of
//!   N spp with different seeds on two threads (default 1024); its own
//!   relMSE is estimated from their difference (`relMSE(A, B)/4`) and
//!   reported, and a path-traced render of N spp is compared with it (the
//!   two methods estimate the same image);
//! - `--budget S`: the equal CPU time of the side-by-side figure (default 1 s).
//!
//! Each method renders on one thread (a one-thread rayon pool); time is the
//! process's CPU time (`cpu-time`), since the machine is shared. The error
//! of an image `I` against the reference `R` is the per-pixel relative MSE of
//! the mean of R, G and B, `mean((I − R)²/(R² + ε))` with
//! ε = (0.01 · mean R)², over the pixels where the reference is not black.
//! Efficiency is the median over spp ≥ 16 of `1/(relMSE · seconds)`.
//!
//! Writes `docs/results/slab_multiple.md`, `docs/figures/slab-multiple.svg`
//! (relMSE against CPU seconds) and `docs/figures/slab-multiple-equal-time.png`
//! (per g: bridges, path tracing, reference).

mod common;

use common::curve::{Curve, Point};
use common::{COLORS, arg, docs_path, fmt_opt, fmt3, loglog, ratio};
use cpu_time::ProcessTime;
use omnee::method::MultipleMethod;
use omnee::names::Named;
use omnee::term::Term;
use omnee_render::error::Spelling;
use omnee_render::files::write_png;
use omnee_render::image::tone_map;
use omnee_render::render::budget::RenderBudget;
use omnee_render::scenes::slab::DEFAULT_SCENE;
use omnee_render::scenes::{RenderSettings, Scene};
use omnee_render::vertices::VertexNumber;
use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;

/// Spp from which on the efficiency median is taken.
const EFF_SPP: u64 = 16;

/// The compared methods, in table and figure order.
const METHODS: [MultipleMethod; 2] = [MultipleMethod::Bridge, MultipleMethod::PathTracing];

/// The default scene with HG `g` and its settings for the multiple term
/// at `width × height`.
fn scene(g: f64, (width, height): (u32, u32)) -> (Scene, RenderSettings) {
    let text = DEFAULT_SCENE.replacen("\"hg:0.98\"", &format!("\"hg:{g}\""), 1);
    let scene = Scene::parse(&text).expect("the default scene with another g");
    let mut s = scene.settings();
    s.terms = vec![Term::Multiple];
    s.vertices = VertexNumber::Auto { max: 8 };
    (s.width, s.height) = (width, height);
    (scene, s)
}

/// The multiple layer's per-pixel mean of R, G, B after `spp` passes of
/// `method` with `seed` on `threads` threads, the layer itself, and the
/// process's CPU seconds.
fn timed(
    (scene, settings): &(Scene, RenderSettings),
    method: MultipleMethod,
    spp: u32,
    seed: u64,
    threads: usize,
) -> (Vec<f64>, Vec<f32>, f64) {
    let mut s = settings.clone();
    s.multiple = method;
    s.budget = RenderBudget::Spp(spp);
    s.seed = seed;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let go = AtomicBool::new(false);
    let before = ProcessTime::now();
    let (out, _) = pool
        .install(|| scene.render(&s, Spelling::Fields, &|_| {}, &go))
        .expect("the render runs");
    let cpu = before.elapsed().as_secs_f64();
    let rgb = out
        .layers
        .get("multiple")
        .expect("the multiple layer")
        .to_vec();
    let lum = rgb
        .chunks_exact(3)
        .map(|p| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0)
        .collect();
    (lum, rgb, cpu)
}

/// `mean((I − R)²/(R² + ε))` over the pixels where `R > 0`, ε = (0.01 mean R)².
fn rel_mse(img: &[f64], reference: &[f64]) -> f64 {
    let lit: Vec<(f64, f64)> = img
        .iter()
        .zip(reference)
        .filter(|(_, r)| **r > 0.0)
        .map(|(a, b)| (*a, *b))
        .collect();
    let mean = lit.iter().map(|p| p.1).sum::<f64>() / lit.len() as f64;
    let eps = (0.01 * mean).powi(2);
    lit.iter()
        .map(|(i, r)| (i - r).powi(2) / (r * r + eps))
        .sum::<f64>()
        / lit.len() as f64
}

/// What one variant measured.
struct Row {
    g: f64,
    reference_noise: f64,
    /// Path tracing's long render against the reference: relMSE and the
    /// ratio of the image sums.
    check: (f64, f64),
    curves: Vec<Curve>,
    /// Equal time: per method (spp, CPU s, relMSE, layer).
    equal: Vec<(u32, f64, f64, Vec<f32>)>,
    reference: Vec<f32>,
}

fn measure(g: f64, resolution: (u32, u32), max_log2: u32, reference_spp: u32, budget: f64) -> Row {
    let v = scene(g, resolution);
    let (a, ra, _) = timed(&v, MultipleMethod::Bridge, reference_spp, 9_000_001, 2);
    let (b, rb, _) = timed(&v, MultipleMethod::Bridge, reference_spp, 9_000_002, 2);
    let reference: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 0.5 * (x + y)).collect();
    let reference_rgb: Vec<f32> = ra.iter().zip(&rb).map(|(x, y)| 0.5 * (x + y)).collect();
    let reference_noise = rel_mse(&a, &b) / 4.0;
    let (pt, _, _) = timed(&v, MultipleMethod::PathTracing, reference_spp, 9_000_003, 2);
    let check = (
        rel_mse(&pt, &reference),
        pt.iter().sum::<f64>() / reference.iter().sum::<f64>(),
    );
    eprintln!(
        "g = {g}: reference noise {reference_noise:.3e}, path tracing at {reference_spp} spp: relMSE {:.3e}, sum ratio {:.4}",
        check.0, check.1
    );
    let mut curves = Vec::new();
    let mut equal = Vec::new();
    for (m, method) in METHODS.into_iter().enumerate() {
        let mut curve = Curve::new(0.0);
        for k in 0..=max_log2 {
            let spp = 1u32 << k;
            let (img, _, cpu) = timed(&v, method, spp, 1000 + 100 * m as u64 + k as u64, 1);
            let e = rel_mse(&img, &reference);
            eprintln!("g = {g} {method} spp {spp}: {cpu:.3} s, relMSE {e:.4e}");
            curve.points.push(Point {
                count: spp as u64,
                cpu_seconds: cpu,
                wall_seconds: cpu,
                rel_mse: e,
            });
        }
        let spp = ((budget / curve.seconds_per_sample()).round() as u32).max(1);
        let (img, rgb, cpu) = timed(&v, method, spp, 5000 + m as u64, 1);
        equal.push((spp, cpu, rel_mse(&img, &reference), rgb));
        curves.push(curve);
    }
    Row {
        g,
        reference_noise,
        check,
        curves,
        equal,
        reference: reference_rgb,
    }
}

/// Per row (one g): bridges, path tracing and the reference side by side,
/// with the reference's exposure.
fn figure(rows: &[Row], (w, h): (usize, usize)) -> Vec<u8> {
    let gap = 4;
    let (out_w, out_h) = (3 * w + 2 * gap, rows.len() * h + (rows.len() - 1) * gap);
    let mut out = vec![255u8; out_w * out_h * 3];
    for (r, row) in rows.iter().enumerate() {
        let (_, ev) = tone_map(&row.reference, None);
        let panels = [&row.equal[0].3, &row.equal[1].3, &row.reference];
        for (k, img) in panels.into_iter().enumerate() {
            let (srgb, _) = tone_map(img, Some(ev));
            for y in 0..h {
                let o = ((r * (h + gap) + y) * out_w + k * (w + gap)) * 3;
                out[o..o + 3 * w].copy_from_slice(&srgb[y * w * 3..(y + 1) * w * 3]);
            }
        }
    }
    out
}

fn main() {
    let phases: String = arg("--phases", "0.5,0.9,0.98".to_string());
    let resolution: String = arg("--resolution", "160x120".to_string());
    let (w, h) = resolution
        .split_once('x')
        .map(|(w, h)| (w.parse().unwrap(), h.parse().unwrap()))
        .expect("--resolution WxH");
    let max_log2: u32 = arg("--max-log2", 7);
    let reference_spp: u32 = arg("--reference-spp", 1024);
    let budget: f64 = arg("--budget", 1.0);
    let rows: Vec<Row> = phases
        .split(',')
        .map(|g| {
            measure(
                g.parse().expect("a number"),
                (w, h),
                max_log2,
                reference_spp,
                budget,
            )
        })
        .collect();
    let names: Vec<&str> = METHODS.iter().map(|m| m.name()).collect();
    let mut md = String::new();
    writeln!(
        md,
        "# The slab scene's multiple term: bridges against path tracing\n\n\
         Output of `cargo bench --bench slab_multiple -- --phases {phases} --resolution {resolution} \
         --max-log2 {max_log2} --reference-spp {reference_spp} --budget {budget}`. The default scene \
         with HG g, `--terms multiple --vertices auto --max-vertices 8` (orders 2 … 8), each method on \
         one thread, CPU time of the process. Reference: two bridge renders of {reference_spp} spp; \
         \"ref. noise\" is its own relMSE. \"PT check\": a path-traced render of {reference_spp} spp \
         against the reference (relMSE, and its image sum over the reference's). Efficiency: median \
         over spp ≥ {EFF_SPP} of 1/(relMSE · CPU s).\n\n\
         | g | ref. noise | PT check relMSE | PT check sum ratio | CPU s/spp bridge | CPU s/spp PT | \
         efficiency bridge | efficiency PT | bridge ÷ PT | equal time: spp bridge / PT | relMSE bridge | relMSE PT |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    let mut json_rows = Vec::new();
    for row in &rows {
        let eff: Vec<Option<f64>> = row.curves.iter().map(|c| c.efficiency(EFF_SPP)).collect();
        writeln!(
            md,
            "| {} | {} | {} | {:.4} | {} | {} | {} | {} | {} | {} / {} | {} | {} |",
            row.g,
            fmt3(row.reference_noise),
            fmt3(row.check.0),
            row.check.1,
            fmt3(row.curves[0].seconds_per_sample()),
            fmt3(row.curves[1].seconds_per_sample()),
            fmt_opt(eff[0]),
            fmt_opt(eff[1]),
            fmt_opt(ratio(eff[0], eff[1])),
            row.equal[0].0,
            row.equal[1].0,
            fmt3(row.equal[0].2),
            fmt3(row.equal[1].2),
        )
        .unwrap();
        json_rows.push(serde_json::json!({
            "g": row.g,
            "reference_noise": row.reference_noise,
            "path_tracing_check": {"rel_mse": row.check.0, "sum_ratio": row.check.1},
            "methods": METHODS.iter().zip(&row.curves).zip(&row.equal).map(|((m, c), e)| serde_json::json!({
                "method": m.name(), "efficiency": c.efficiency(EFF_SPP), "points": c.points_json("spp"),
                "equal_time": {"spp": e.0, "cpu_seconds": e.1, "rel_mse": e.2},
            })).collect::<Vec<_>>(),
        }));
    }
    writeln!(
        md,
        "\n![relMSE against CPU seconds](../figures/slab-multiple.svg)\n\n\
         ![equal time: bridges, path tracing, reference](../figures/slab-multiple-equal-time.png)\n\n\
         Equal time (about {budget} s of one core each), one row per g ({phases}), left to right: \
         bridges, path tracing, reference; one exposure per row."
    )
    .unwrap();
    for row in &rows {
        writeln!(md, "\nrelMSE against spp, g = {}:\n\n| spp | bridge CPU s | bridge relMSE | PT CPU s | PT relMSE |\n|---|---|---|---|---|", row.g).unwrap();
        for (a, b) in row.curves[0].points.iter().zip(&row.curves[1].points) {
            writeln!(
                md,
                "| {} | {:.3} | {} | {:.3} | {} |",
                a.count,
                a.cpu_seconds,
                fmt3(a.rel_mse),
                b.cpu_seconds,
                fmt3(b.rel_mse)
            )
            .unwrap();
        }
    }
    print!("{md}");
    std::fs::write(docs_path("results/slab_multiple.md"), &md).expect("write the table");
    std::fs::write(
        docs_path("results/slab_multiple.json"),
        serde_json::to_string_pretty(&json_rows).unwrap(),
    )
    .expect("write the JSON");
    let panels: Vec<loglog::Panel> = rows
        .iter()
        .map(|row| loglog::Panel {
            caption: format!("multiple term, hg:{}", row.g),
            curves: row.curves.iter().map(Curve::time_error).collect(),
        })
        .collect();
    let layout = loglog::Layout {
        names: &names,
        colors: &COLORS[..2],
        cols: 3,
        panel: (420, 260),
        legend_step: 200,
        x_desc: "CPU seconds (one core)",
    };
    loglog::svg(&docs_path("figures/slab-multiple.svg"), &layout, &panels).expect("the figure");
    let png = figure(&rows, (w as usize, h as usize));
    write_png(
        &docs_path("figures/slab-multiple-equal-time.png"),
        3 * w as usize + 8,
        rows.len() * (h as usize + 4) - 4,
        &png,
    )
    .expect("the side-by-side figure");
}
