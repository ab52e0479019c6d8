//! The underwater scene: the equal-time comparison of the
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
//! - `--skips`: also what skipping saves (a flat surface, σs = 0, one term);
//! - `--spread K`: also each layer's variance over K renders of 4 passes
//!   with different seeds (one thread): the relMSE and nMSE of one render
//!   against the K renders' mean, which heavy-tailed weights (fireflies) blow up;
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
use omnee::method::LobeMethod;
use omnee::term::Term;
use omnee_render::files::write_png;
use omnee_render::image::{Layers, tone_map};
use omnee_render::phase::TableStorage;
use omnee_render::render::budget::RenderBudget;
use omnee_render::render::{Options, render};
use omnee_render::scenes::underwater::transport::CausticsMethod;
use omnee_render::scenes::underwater::{
    UNDERWATER_SCENE, UNDERWATER_TERMS, UnderwaterScene, UnderwaterStats, UnderwaterWorld,
};
use std::sync::atomic::AtomicBool;

/// A finished render of the underwater scene.
type Rendered = omnee_render::render::Rendered<UnderwaterStats>;
use std::fmt::Write as _;
use std::time::Instant;

/// A compared variant: its label and how it sets up the world.
type Variant = (&'static str, fn(&mut UnderwaterWorld<'_>));

/// `caustics-once-more`'s techniques (mis with the scene's defaults and
/// with the built-in scene's rate 1 over all θ).
const ONCE_MORE: [Variant; 4] = [
    ("omnee", |w| w.once_more.method = CausticsMethod::Omnee),
    ("equiangular", |w| {
        w.once_more.method = CausticsMethod::Equiangular
    }),
    ("mis", |w| {
        w.once_more.method = CausticsMethod::Mis;
        w.once_more.mis_rate = 0.05;
        w.once_more.mis_theta_min = 0.75 * std::f32::consts::PI;
    }),
    ("mis (rate 1, all θ)", two_sample_mis),
];

/// Two-sample MIS of OMNEE and camera-ray equiangular over the whole range:
/// `caustics-once-more`'s reference.
fn two_sample_mis(w: &mut UnderwaterWorld<'_>) {
    w.once_more.method = CausticsMethod::Mis;
    w.once_more.mis_rate = 1.0;
    w.once_more.mis_theta_min = 0.0;
}

/// `shafts-once-more`'s techniques; the reference is the second.
const LOBE: [Variant; 2] = [
    ("omnee (lobe in the weight)", |w| w.lobe = LobeMethod::Omnee),
    ("lobe-mis", |w| w.lobe = LobeMethod::LobeMis),
];

/// Renders `world` for `spp` passes with `seed` on a pool of `threads`,
/// returning the image and the CPU seconds it took.
fn timed(world: &UnderwaterWorld<'_>, spp: u32, seed: u64, threads: usize) -> (Rendered, f64) {
    let (w, h) = (world.camera.width, world.camera.height);
    let opt = Options {
        budget: RenderBudget::Spp(spp),
        seed,
        crop: [0, 0, w, h],
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let before = ProcessTime::now();
    let go = AtomicBool::new(false);
    let out = pool
        .install(|| render(world, &opt, &|_| {}, &go))
        .expect("not cancelled");
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

/// `Σ(I − R)² / ΣR²`.
fn n_mse(img: &[f64], reference: &[f64]) -> f64 {
    let num: f64 = img
        .iter()
        .zip(reference)
        .map(|(i, r)| (i - r).powi(2))
        .sum();
    num / reference.iter().map(|r| r * r).sum::<f64>()
}

/// One render of a technique: passes, CPU seconds, relMSE and nMSE.
#[derive(Clone, Copy, Debug)]
struct Point {
    spp: u32,
    cpu: f64,
    rel: f64,
    n: f64,
}

/// Which error of a [`Point`].
type Error = fn(&Point) -> f64;

/// An error at `budget` seconds, log-log interpolated between the renders,
/// with slope −1 beyond them.
fn at_time(curve: &[Point], budget: f64, error: Error) -> f64 {
    let pts: Vec<(f64, f64)> = curve.iter().map(|p| (p.cpu.max(0.01), error(p))).collect();
    let (first, last) = (pts[0], pts[pts.len() - 1]);
    if budget <= first.0 {
        return first.1 * first.0 / budget;
    }
    for w in pts.windows(2) {
        let ((t0, r0), (t1, r1)) = (w[0], w[1]);
        if budget >= t0 && budget <= t1 && t1 > t0 {
            let f = (budget / t0).ln() / (t1 / t0).ln();
            return (r0.ln() + f * (r1 / r0).ln()).exp();
        }
    }
    last.1 * last.0 / budget
}

/// What skipping saves: the built-in scene at `w × h`, 8 passes on one
/// thread, against the same with a flat surface (no marching, no wave-band
/// tests) and with σs = 0 (no scattering terms), and with each term alone.
fn skips(md: &mut String, w: u32, h: u32) {
    let base = UNDERWATER_SCENE;
    let flat = {
        let cut = base.find("\n[[surface.waves]]").expect("waves");
        let end = base.find("\n[water]").expect("water");
        format!("{}{}", &base[..cut], &base[end..]).replace("kind = \"sine\"", "kind = \"flat\"")
    };
    let clear = base.replace("sigma_s = [0.25, 0.25, 0.25]", "sigma_s = 0.0");
    let mut variants: Vec<(String, String)> = vec![
        ("built-in scene, all terms".into(), base.to_string()),
        ("flat surface".into(), flat),
        ("water.sigma_s = 0 (scattering terms skipped)".into(), clear),
    ];
    for term in UNDERWATER_TERMS {
        let only = base.replace(
            "terms = [\"caustics\", \"caustics-once-more\", \"shafts\"]",
            &format!("terms = [\"{term}\"]"),
        );
        variants.push((format!("{term} alone"), only));
    }
    let _ = writeln!(
        md,
        "## What skipping saves\n\n`cargo bench --bench underwater_time_vs_error -- --skips`: the built-in \
         scene at {w}x{h}, 8 passes on one thread, CPU seconds:\n\n| variant | CPU s | relative |\n|---|---|---|"
    );
    let mut first = None;
    for (label, text) in variants {
        let scene = UnderwaterScene::parse(&text).expect("variant parses");
        let mut storage = TableStorage::<f32>::default();
        let phase = scene.phase.instantiate::<f32>(&mut storage).expect("phase");
        let world = UnderwaterWorld::new(&scene, phase, w, h);
        let (_, cpu) = timed(&world, 8, 3, 1);
        let base_cpu = *first.get_or_insert(cpu);
        println!("{label:<48} {cpu:>7.2} s CPU");
        let _ = writeln!(md, "| {label} | {cpu:.2} | {} |", fmt3(cpu / base_cpu));
    }
    let _ = writeln!(md);
}

/// Each layer's spread: `k` renders of 4 passes with different seeds at
/// `w × h` on one thread; per layer the relMSE and nMSE of one render
/// against the renders' mean `M` (the variance of one render over `M²`,
/// times `k/(k − 1)`), over the pixels where `M > 0`.
fn spread(md: &mut String, k: usize, w: u32, h: u32) {
    let scene = UnderwaterScene::builtin();
    let mut storage = TableStorage::<f32>::default();
    let phase = scene.phase.instantiate::<f32>(&mut storage).expect("phase");
    let world = UnderwaterWorld::new(&scene, phase, w, h);
    let mut names: Vec<String> = world.layers.iter().map(Term::to_string).collect();
    names.push(String::new());
    let renders: Vec<(Rendered, f64)> = (0..k)
        .map(|i| timed(&world, 4, 1000 + i as u64, 1))
        .collect();
    let cpu = renders.iter().map(|r| r.1).sum::<f64>() / k as f64;
    let _ = writeln!(
        md,
        "## The spread of each layer\n\n`cargo bench --bench underwater_time_vs_error -- --spread {k}`: \
         the built-in scene at {w}x{h}, {k} renders of 4 passes with different seeds on one thread \
         ({cpu:.2} s CPU each); per layer the error of one render against the renders' mean, \
         relMSE and nMSE as below, times k/(k − 1):\n\n| layer | relMSE | nMSE |\n|---|---|---|"
    );
    for name in names {
        let images: Vec<Vec<f64>> = renders
            .iter()
            .map(|r| luminance(&r.0.layers, &name))
            .collect();
        let n = images[0].len();
        let mean: Vec<f64> = (0..n)
            .map(|p| images.iter().map(|i| i[p]).sum::<f64>() / k as f64)
            .collect();
        let scale = k as f64 / (k - 1) as f64 / k as f64;
        let rel = scale * images.iter().map(|i| rel_mse(i, &mean)).sum::<f64>();
        let nm = scale * images.iter().map(|i| n_mse(i, &mean)).sum::<f64>();
        let label = if name.is_empty() { "sum" } else { &name };
        println!("spread {label:<20} relMSE {rel:.4} nMSE {nm:.4}");
        let _ = writeln!(md, "| {label} | {} | {} |", fmt3(rel), fmt3(nm));
    }
    let _ = writeln!(md);
}

/// How long the comparisons run.
#[derive(Clone, Copy, Debug)]
struct Settings {
    /// Passes of each of the reference's two renders.
    reference_spp: u32,
    /// Each variant renders 1, 2, … 2^max_log2 passes.
    max_log2: u32,
    /// The equal CPU time of the table and the figure (s).
    budget: f64,
}

/// The equal-time comparison of `variants` on `world` (its one term
/// `term`): a reference of two renders set up by `reference`, each
/// variant's renders of 1, 2, … passes on one thread with relMSE and nMSE
/// against it, the table at equal CPU time (after `intro`), every render,
/// and the figure `docs/figures/<figure>.png` (the variants at about the
/// budget and the reference, side by side).
#[allow(clippy::too_many_arguments)]
fn equal_time(
    md: &mut String,
    world: &mut UnderwaterWorld<'_>,
    term: Term,
    variants: &[Variant],
    reference: fn(&mut UnderwaterWorld<'_>),
    intro: &str,
    figure: &str,
    rest: &Settings,
) {
    let Settings {
        reference_spp,
        max_log2,
        budget,
    } = *rest;
    let (w, h) = (world.camera.width, world.camera.height);
    reference(world);
    let (ref_a, ta) = timed(world, reference_spp, 1001, 2);
    let (ref_b, tb) = timed(world, reference_spp, 2002, 2);
    let name = &term.to_string();
    let (la, lb) = (
        luminance(&ref_a.layers, name),
        luminance(&ref_b.layers, name),
    );
    let reference: Vec<f64> = la.iter().zip(&lb).map(|(a, b)| 0.5 * (a + b)).collect();
    let (ref_rel, ref_n) = (rel_mse(&la, &lb) / 4.0, n_mse(&la, &lb) / 4.0);
    println!(
        "reference: 2 x {reference_spp} passes in {:.0} s CPU, own relMSE {}, nMSE {}",
        ta + tb,
        fmt3(ref_rel),
        fmt3(ref_n)
    );
    let mut curves: Vec<Vec<Point>> = Vec::new();
    let mut images: Vec<Option<Layers>> = Vec::new();
    for (label, set) in variants {
        set(world);
        let mut curve = Vec::new();
        let mut at_budget: Option<Layers> = None;
        for k in 0..=max_log2 {
            let spp = 1u32 << k;
            let (out, cpu) = timed(world, spp, 7 + k as u64, 1);
            let lum = luminance(&out.layers, name);
            let p = Point {
                spp,
                cpu,
                rel: rel_mse(&lum, &reference),
                n: n_mse(&lum, &reference),
            };
            println!(
                "{label:<20} {spp:>5} passes {cpu:>8.2} s CPU relMSE {} nMSE {}",
                fmt3(p.rel),
                fmt3(p.n)
            );
            curve.push(p);
            if cpu <= budget * 1.5 {
                at_budget = Some(out.layers);
            }
        }
        curves.push(curve);
        images.push(at_budget);
    }
    let efficiency = |c: &[Point], error: Error| {
        let mut e: Vec<f64> = c
            .iter()
            .filter(|p| p.spp >= 4)
            .map(|p| 1.0 / (error(p) * p.cpu.max(0.01)))
            .collect();
        if e.is_empty() {
            return f64::NAN;
        }
        median(&mut e)
    };
    let rel: Error = |p| p.rel;
    let n: Error = |p| p.n;
    let (base_rel, base_n) = (efficiency(&curves[0], rel), efficiency(&curves[0], n));
    let _ = writeln!(
        md,
        "{intro} The reference's own error, from the difference of its two renders: relMSE {}, nMSE {}.\n",
        fmt3(ref_rel),
        fmt3(ref_n)
    );
    let _ = writeln!(
        md,
        "| technique | relMSE at {budget} s | nMSE at {budget} s | efficiency (relMSE) | relative | \
         efficiency (nMSE) | relative |\n|---|---|---|---|---|---|---|"
    );
    for ((label, _), c) in variants.iter().zip(&curves) {
        let (er, en) = (efficiency(c, rel), efficiency(c, n));
        let _ = writeln!(
            md,
            "| {label} | {} | {} | {} | {} | {} | {} |",
            fmt3(at_time(c, budget, rel)),
            fmt3(at_time(c, budget, n)),
            fmt3(er),
            fmt3(er / base_rel),
            fmt3(en),
            fmt3(en / base_n)
        );
    }
    let _ = writeln!(md, "\nEvery render (passes: CPU seconds, relMSE, nMSE):\n");
    for ((label, _), c) in variants.iter().zip(&curves) {
        let _ = writeln!(
            md,
            "- {label}: {}",
            c.iter()
                .map(|p| format!("{}: {:.2} s, {}, {}", p.spp, p.cpu, fmt3(p.rel), fmt3(p.n)))
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
    let total_w = panels.len() * pw + (panels.len() - 1) * gap;
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
    let fig = docs_path(&format!("figures/{figure}.png"));
    write_png(&fig, total_w, ph, &canvas).expect("png");
    let _ = writeln!(
        md,
        "\n`docs/figures/{figure}.png`: from left to right {} at about {budget} s CPU each \
         (the largest power-of-two pass count within 1.5× of it), and the reference; one exposure for all.\n",
        variants.iter().map(|t| t.0).collect::<Vec<_>>().join(", ")
    );
    println!("figure {}", fig.display());
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
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let _ = writeln!(
        md,
        "# The underwater scene: time against error\n\nMeasured by `cargo bench --bench underwater_time_vs_error{}` \
         on a 2-core machine shared with other jobs (load average at the start: {}).\n",
        if args.is_empty() {
            String::new()
        } else {
            format!(" -- {}", args.join(" "))
        },
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );

    if flag("--render") {
        let (dw, dh) = (scene.camera.width, scene.camera.height);
        let world = UnderwaterWorld::new(&scene, phase, dw, dh);
        let spp = scene.render.spp;
        let start = Instant::now();
        let (out, cpu) = timed(&world, spp, scene.render.seed, 2);
        let wall = start.elapsed().as_secs_f64();
        let (srgb, ev) = tone_map(out.layers.get("").expect("sum"), scene.render.exposure);
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("omnee-cli/docs/underwater.png");
        write_png(&path, dw as usize, dh as usize, &srgb).expect("png");
        for term in world.layers.iter() {
            let (srgb, _) = tone_map(out.layers.get(&term.to_string()).expect("layer"), Some(ev));
            let p = docs_path(&format!("figures/underwater-{term}.png"));
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
             ({} paths) on 2 threads: **{wall:.1} s wall**, {cpu:.1} s CPU. Paths with no start point {}, \
             started beyond the core region {}, lost at the surface {}, floor hits {}; splats: {}; \
             wave-band visibility tests {}.\n",
            st.paths,
            st.no_start,
            st.beyond_core,
            st.lost_at_surface,
            st.floor_hits,
            st.splats_by_term(),
            st.surface_tests
        );
    }

    if flag("--skips") {
        skips(&mut md, w, h);
    }

    let k: usize = arg("--spread", 0);
    if k >= 2 {
        spread(&mut md, k, w, h);
    }

    // The comparisons: each term alone.
    let rest = Settings {
        reference_spp,
        max_log2,
        budget,
    };
    scene.render.terms = [false, true, false, false];
    let phase = scene.phase.instantiate::<f32>(&mut storage).expect("phase");
    let mut world = UnderwaterWorld::new(&scene, phase, w, h);
    let intro = format!(
        "## Equal time: the once-more techniques on `caustics-once-more`\n\n\
         The built-in scene at {w}x{h}, `caustics-once-more` only (phase `{}`, σs = 0.25 /m, floor 4 m \
         down, {} draws per floor point). Each technique renders 1, 2, …, {} passes on one thread; time is \
         CPU time. Reference: two renders of {reference_spp} passes with two-sample MIS (OMNEE and \
         camera-ray equiangular, both always, balance heuristic over the whole range). Errors: relMSE = \
         mean over pixels of (I − R)²/(R² + ε), ε = (0.01 mean R)², which the sparse dark water pixels \
         dominate, and nMSE = Σ(I − R)²/ΣR², which the bright floor dominates; both at {budget} s CPU \
         (log-log interpolated between the renders), and the efficiencies 1/(error · s), medians over the \
         renders of ≥ 4 passes, relative to OMNEE's.",
        scene.phase,
        scene.render.once_more_samples,
        1u32 << max_log2,
    );
    equal_time(
        &mut md,
        &mut world,
        Term::CausticsOnceMore,
        &ONCE_MORE,
        two_sample_mis,
        &intro,
        "underwater-equal-time",
        &rest,
    );

    scene.render.terms = [false, false, false, true];
    let phase = scene.phase.instantiate::<f32>(&mut storage).expect("phase");
    let mut world = UnderwaterWorld::new(&scene, phase, w, h);
    let intro = format!(
        "## Equal time: the lobe at x0 on `shafts-once-more`\n\n\
         The built-in scene at {w}x{h}, `shafts-once-more` only: {} vertices x0 on each refracted sun ray \
         (free flight), each connected once more to the eye, x1 by OMNEE with the phase function's lobe \
         about the sun's refracted direction at x0 in its weight, or by the core's recommended combination \
         of OMNEE and the lobe technique (`LobeMis::recommended`, docs/math.md §12.4). Passes 1, 2, …, {} on \
         one thread, CPU time; reference: two renders of {reference_spp} passes with `lobe-mis`; errors and \
         efficiencies as above, relative to OMNEE's.",
        scene.render.once_more_samples,
        1u32 << max_log2,
    );
    equal_time(
        &mut md,
        &mut world,
        Term::ShaftsOnceMore,
        &LOBE,
        LOBE[1].1,
        &intro,
        "underwater-shafts-once-more",
        &rest,
    );

    let out = docs_path("results/underwater.md");
    std::fs::write(&out, md).expect("write results");
    println!("wrote {}", out.display());
}
