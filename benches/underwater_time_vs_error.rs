//! The underwater scene (issue 11): the equal-time comparison of the
//! once-more techniques for `caustics-once-more`, like the talk's results
//! slide, and the default render's time and image.
//!
//! `cargo bench --bench underwater_time_vs_error` (options after `--`):
//!
//! - `--resolution WxH` (default 240x180) for the comparison;
//! - `--max-log2 K`: each technique renders 1, 2, 4, … 2^K passes (default 5);
//! - `--reference-spp N`: the reference, the mean of two OMNEE renders of N
//!   passes each with different seeds (default 512); its own relMSE is
//!   estimated from their difference (`relMSE(A, B)/4`) and reported;
//! - `--budget S`: the equal CPU time for the crops figure (default 4 s);
//! - `--render`: also the default render of the built-in scene at its
//!   resolution and passes on 2 threads: wall time, and the images
//!   `omnee-cli/docs/underwater.png` and `docs/figures/underwater-<term>.png`.
//!
//! Each technique renders on one thread (a one-thread rayon pool); the time
//! is the process's CPU time (`cpu-time`), since the machine is shared. The
//! error of an image `I` against the reference `R` is the per-pixel relative
//! MSE of the mean of R, G and B, `mean((I − R)²/(R² + ε))`, ε = (0.01 mean R)²,
//! over the pixels where the reference is not black. Efficiency is the median
//! over the renders of ≥ 4 passes of `1/(relMSE · seconds)`; the table gives
//! each technique's relMSE interpolated at equal CPU time and its efficiency
//! relative to OMNEE.
//!
//! Writes `docs/results/underwater.md` and `docs/figures/underwater-equal-time.png`
//! (the three techniques' images at the same CPU time and the reference, side
//! by side).

mod common;

use common::{arg, docs_path, flag, fmt3, median};
use cpu_time::ProcessTime;
use omnee_cli::image::{Layers, tone_map, write_png};
use omnee_cli::phase::TableStorage;
use omnee_cli::render::Budget;
use omnee_cli::underwater::render::{Options, Rendered, render};
use omnee_cli::underwater::scene::UnderwaterScene;
use omnee_cli::underwater::transport::{OnceMoreTech, Term, World};
use std::fmt::Write as _;
use std::time::Instant;

const TECHS: [OnceMoreTech; 3] = [
    OnceMoreTech::Omnee,
    OnceMoreTech::Equiangular,
    OnceMoreTech::Mis,
];

/// Renders `world` for `spp` passes with `seed` on a pool of `threads`,
/// returning the image and the CPU seconds it took.
fn timed(world: &World<'_>, spp: u32, seed: u64, threads: usize) -> (Rendered, f64) {
    let (w, h) = (world.camera.width, world.camera.height);
    let opt = Options {
        budget: Budget::Spp(spp),
        seed,
        crop: [0, 0, w, h],
        progress: false,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let before = ProcessTime::now();
    let out = pool.install(|| render(world, &opt));
    (out, before.elapsed().as_secs_f64())
}

/// The per-pixel mean of R, G, B of layer `name`.
fn luminance(l: &Layers, name: &str) -> Vec<f64> {
    l.get(name)
        .expect("layer")
        .chunks_exact(3)
        .map(|p| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0)
        .collect()
}

/// `mean((I − R)²/(R² + ε))` over the pixels where `R > 0`.
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

/// relMSE at `budget` seconds, log-log interpolated between the renders,
/// with slope −1 beyond them.
fn at_time(curve: &[(u32, f64, f64)], budget: f64) -> f64 {
    let (first, last) = (curve[0], curve[curve.len() - 1]);
    if budget <= first.1 {
        return first.2 * first.1 / budget;
    }
    for w in curve.windows(2) {
        let ((_, t0, r0), (_, t1, r1)) = (w[0], w[1]);
        if budget >= t0 && budget <= t1 && t1 > t0 {
            let f = (budget / t0).ln() / (t1 / t0).ln();
            return (r0.ln() + f * (r1 / r0).ln()).exp();
        }
    }
    last.2 * last.1 / budget
}

fn parse_resolution(s: &str) -> (u32, u32) {
    let (w, h) = s.split_once('x').expect("--resolution WxH");
    (w.parse().expect("width"), h.parse().expect("height"))
}

fn main() {
    let (w, h) = parse_resolution(&arg("--resolution", "240x180".to_string()));
    let max_log2: u32 = arg("--max-log2", 5);
    let reference_spp: u32 = arg("--reference-spp", 512);
    let budget: f64 = arg("--budget", 4.0);
    let mut scene = UnderwaterScene::builtin();
    let mut storage = TableStorage::<f32>::default();
    let phase = scene.phase.instantiate::<f32>(&mut storage).expect("phase");
    let mut md = String::new();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let _ = writeln!(
        md,
        "# The underwater scene: time against error\n\nMeasured by `cargo bench --bench underwater_time_vs_error{}` \
         on a 2-core machine shared with other jobs (load average at the start: {}).\n",
        if flag("--render") { " -- --render" } else { "" },
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );

    if flag("--render") {
        let (dw, dh) = (scene.camera.width, scene.camera.height);
        let world = World::new(&scene, phase, dw, dh);
        let spp = scene.render.spp;
        let start = Instant::now();
        let (out, cpu) = timed(&world, spp, scene.render.seed, 2);
        let wall = start.elapsed().as_secs_f64();
        let (srgb, ev) = tone_map(out.layers.get("").expect("sum"), scene.render.exposure);
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("omnee-cli/docs/underwater.png");
        write_png(&path, dw as usize, dh as usize, &srgb).expect("png");
        for term in Term::ALL {
            let (srgb, _) = tone_map(out.layers.get(term.name()).expect("layer"), Some(ev));
            let p = docs_path(&format!("figures/underwater-{}.png", term.name()));
            write_png(&p, dw as usize, dh as usize, &srgb).expect("png");
        }
        let st = out.stats;
        println!(
            "default render {dw}x{dh}, {spp} passes ({} paths): {wall:.1} s wall, {cpu:.1} s CPU on 2 threads",
            st.paths
        );
        let _ = writeln!(
            md,
            "## The default render\n\n`underwater` at {dw}x{dh}, {spp} passes of {dw}·{dh} light paths \
             ({} paths) on 2 threads: **{wall:.1} s wall**, {cpu:.1} s CPU. Paths outside the lit region {}, \
             lost at the surface {}, floor hits {}; splats: caustics {}, caustics-once-more {}, shafts {}; \
             wave-band visibility tests {}.\n",
            st.paths,
            st.outside_region,
            st.lost_at_surface,
            st.floor_hits,
            st.splats[0],
            st.splats[1],
            st.splats[2],
            st.surface_tests
        );
    }

    // The comparison: caustics-once-more only.
    scene.render.terms = [false, true, false];
    let phase = scene.phase.instantiate::<f32>(&mut storage).expect("phase");
    let mut world = World::new(&scene, phase, w, h);
    world.once_more.tech = OnceMoreTech::Omnee;
    let (ref_a, ta) = timed(&world, reference_spp, 1001, 2);
    let (ref_b, tb) = timed(&world, reference_spp, 2002, 2);
    let name = Term::CausticsOnceMore.name();
    let (la, lb) = (
        luminance(&ref_a.layers, name),
        luminance(&ref_b.layers, name),
    );
    let reference: Vec<f64> = la.iter().zip(&lb).map(|(a, b)| 0.5 * (a + b)).collect();
    let ref_noise = rel_mse(&la, &lb) / 4.0;
    println!(
        "reference: 2 x {reference_spp} passes of OMNEE in {:.0} s CPU, own relMSE {}",
        ta + tb,
        fmt3(ref_noise)
    );
    let mut curves = Vec::new();
    let mut images: Vec<Option<Layers>> = Vec::new();
    for tech in TECHS {
        world.once_more.tech = tech;
        let mut curve = Vec::new();
        let mut at_budget: Option<Layers> = None;
        for k in 0..=max_log2 {
            let spp = 1u32 << k;
            let (out, cpu) = timed(&world, spp, 7 + k as u64, 1);
            let e = rel_mse(&luminance(&out.layers, name), &reference);
            println!(
                "{:<12} {spp:>5} passes {cpu:>8.2} s CPU relMSE {}",
                tech.name(),
                fmt3(e)
            );
            curve.push((spp, cpu, e));
            if cpu <= budget * 1.5 {
                at_budget = Some(out.layers);
            }
        }
        curves.push(curve);
        images.push(at_budget);
    }
    let efficiency = |c: &[(u32, f64, f64)]| {
        let mut e: Vec<f64> = c
            .iter()
            .filter(|p| p.0 >= 4)
            .map(|p| 1.0 / (p.2 * p.1.max(0.01)))
            .collect();
        if e.is_empty() {
            return f64::NAN;
        }
        median(&mut e)
    };
    let base = efficiency(&curves[0]);
    let _ = writeln!(
        md,
        "## Equal time: the once-more techniques on `caustics-once-more`\n\n\
         The built-in scene at {w}x{h}, `caustics-once-more` only (Fournier–Forand phase function with \
         Petzold's backscatter fraction, σs = 0.25 /m, floor 4 m down). Each technique renders 1, 2, …, \
         {} passes on one thread; time is CPU time. Reference: two OMNEE renders of {reference_spp} passes \
         (own relMSE {}). relMSE at equal CPU time, log-log interpolated between the renders:\n",
        1u32 << max_log2,
        fmt3(ref_noise)
    );
    let times = [1.0, 4.0, 16.0];
    let _ = writeln!(
        md,
        "| technique | {} | efficiency 1/(relMSE·s) | relative to OMNEE |\n|---|{}---|---|",
        times
            .iter()
            .map(|t| format!("relMSE at {t} s"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(times.len())
    );
    for (tech, c) in TECHS.iter().zip(&curves) {
        let eff = efficiency(c);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} |",
            tech.name(),
            times
                .iter()
                .map(|&t| fmt3(at_time(c, t)))
                .collect::<Vec<_>>()
                .join(" | "),
            fmt3(eff),
            fmt3(eff / base)
        );
    }
    let _ = writeln!(md, "\nEvery render (passes, CPU seconds, relMSE):\n");
    for (tech, c) in TECHS.iter().zip(&curves) {
        let _ = writeln!(
            md,
            "- {}: {}",
            tech.name(),
            c.iter()
                .map(|(s, t, e)| format!("{s}: {t:.2} s, {}", fmt3(*e)))
                .collect::<Vec<_>>()
                .join("; ")
        );
    }

    // The crops figure: each technique's render closest to `budget` below
    // 1.5 budget, and the reference, side by side, at the reference's exposure.
    let (_, ev) = tone_map(ref_a.layers.get(name).expect("layer"), None);
    let mut panels: Vec<Vec<f32>> = images
        .iter()
        .map(|i| {
            i.as_ref()
                .map(|l| l.get(name).expect("layer").to_vec())
                .unwrap_or_else(|| vec![0.0; (w * h * 3) as usize])
        })
        .collect();
    let (a, b) = (
        ref_a.layers.get(name).expect("layer"),
        ref_b.layers.get(name).expect("layer"),
    );
    panels.push(a.iter().zip(b).map(|(x, y)| 0.5 * (x + y)).collect());
    let gap = 4usize;
    let (pw, ph) = (w as usize, h as usize);
    let total_w = 4 * pw + 3 * gap;
    let mut canvas = vec![255u8; total_w * ph * 3];
    for (k, panel) in panels.iter().enumerate() {
        let (srgb, _) = tone_map(panel, Some(ev));
        for y in 0..ph {
            for x in 0..pw {
                for c in 0..3 {
                    canvas[(y * total_w + k * (pw + gap) + x) * 3 + c] = srgb[(y * pw + x) * 3 + c];
                }
            }
        }
    }
    let fig = docs_path("figures/underwater-equal-time.png");
    write_png(&fig, total_w, ph, &canvas).expect("png");
    let _ = writeln!(
        md,
        "\n`docs/figures/underwater-equal-time.png`: from left to right omnee, equiangular, mis at about \
         {budget} s CPU each (the largest power-of-two pass count within 1.5× of it), and the reference; \
         one exposure for all.\n"
    );
    let out = docs_path("results/underwater.md");
    std::fs::write(&out, md).expect("write results");
    println!("wrote {} and {}", out.display(), fig.display());
}
