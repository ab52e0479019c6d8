//! Run time against error for the once-more term of the slab renderer
//! driving the `omnee` binary of `omnee-cli`.
//!
//! Build the renderer first, in the same target directory:
//! `cargo build --release -p omnee-cli && cargo bench --bench slab_time_vs_error`
//! (or pass `-- --omnee PATH`). Options: `--resolution WxH` (default
//! 160x120), `--max-log2 K` (spp 1 … 2^K, default 7), `--reference-spp N`
//! (default 4096, rendered twice), `--only NAME` (one variant), `--crops`
//! (also the equal-time image comparison of the default scene: the centre
//! 240x180 window of the 480x360 image, `--crop-budget S` CPU seconds per
//! technique, default 1, reference `--crop-reference-spp` twice, default 2048).
//!
//! Variants: the default scene (`omnee default-scene`: water-like slab,
//! HG g = 0.98, σs = 0.5, σa = 0.05, light 0.95 m above the floor, so
//! σt·H ≈ 0.52); the same scene with each phase function of `BENCH_PHASES`; and with
//! the default phase function at σt·H ∈ {0.1, 1, 3} (σs/σt kept).
//!
//! Per variant: a reference, the mean of two independent `omnee` (OMNEE,
//! θ < π) renders of `--reference-spp` spp each; its own relMSE is estimated
//! from the difference of the two halves (`relMSE(A, B)/4`) and reported.
//! Then each technique renders `--terms once-more` at spp = 1, 2, 4, … on
//! one thread (`--threads 1`); time is the child's CPU time (user + system,
//! from `/proc/self/stat`, 10 ms ticks) because the machine is shared, and
//! the renderer's own wall time is recorded too. The error of an image I
//! against the reference R is the per-pixel relative MSE on the mean of R, G
//! and B, `mean((I − R)² / (R² + ε))` with ε = (0.01 · mean R)² so that
//! nearly black pixels do not dominate. Efficiency is the median over
//! spp ≥ 16 (≥ 0.1 s, so the 10 ms ticks matter little) of
//! 1/(relMSE · seconds).
//!
//! Writes `docs/results/slab.{md,json}`, `docs/figures/slab.svg` and with
//! `--crops` `docs/figures/slab-equal-time.png`.

mod common;

use common::curve::{Curve, Point};
use common::{
    BENCH_PHASES, COLORS, NAMES, arg, best_other_single, docs_path, flag, fmt_opt, fmt3, loglog,
    ratio,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The child's CPU time comes in ticks of 10 ms.
const TICK: f64 = 0.01;
/// Spp from which on the efficiency median is taken (≥ 0.1 s, ten ticks).
const EFF_SPP: u64 = 16;
/// The default scene's phase function.
const DEFAULT_PHASE: &str = "hg:0.98";
/// Height of the light above the floor in the default scene (m).
const LIGHT_HEIGHT: f64 = 0.95;
/// Albedo σs/σt of the default scene.
const ALBEDO: f64 = 0.5 / 0.55;

/// A scene variant: a name, the phase spec and the optical thickness σt·H
/// (`None`: the default scene's coefficients).
struct Variant {
    name: String,
    phase: &'static str,
    tau: Option<f64>,
}

fn variants() -> Vec<Variant> {
    let mut v = vec![Variant {
        name: format!("default ({DEFAULT_PHASE}, τ≈0.52)"),
        phase: DEFAULT_PHASE,
        tau: None,
    }];
    for p in BENCH_PHASES.into_iter().filter(|&p| p != DEFAULT_PHASE) {
        v.push(Variant {
            name: format!("{p}, τ≈0.52"),
            phase: p,
            tau: None,
        });
    }
    for tau in [0.1, 1.0, 3.0] {
        v.push(Variant {
            name: format!("{DEFAULT_PHASE}, τ={tau}"),
            phase: DEFAULT_PHASE,
            tau: Some(tau),
        });
    }
    v
}

/// The default scene with the variant's phase function and coefficients.
fn scene_text(omnee: &Path, v: &Variant) -> String {
    let out = Command::new(omnee)
        .arg("default-scene")
        .output()
        .expect("run omnee default-scene");
    assert!(out.status.success(), "omnee default-scene failed");
    let text = String::from_utf8(out.stdout).expect("utf-8 scene");
    let mut lines = Vec::new();
    for line in text.lines() {
        let key = line.split('=').next().unwrap_or("").trim();
        let comment = line.find('#').map(|i| &line[i..]).unwrap_or("");
        let l = match (key, v.tau) {
            ("phase", _) if line.starts_with("phase") => {
                format!("phase = \"{}\" {comment}", v.phase)
            }
            ("sigma_s", Some(tau)) if line.starts_with("sigma_s") => {
                format!("sigma_s = {} {comment}", ALBEDO * tau / LIGHT_HEIGHT)
            }
            ("sigma_a", Some(tau)) if line.starts_with("sigma_a") => {
                format!(
                    "sigma_a = {} {comment}",
                    (1.0 - ALBEDO) * tau / LIGHT_HEIGHT
                )
            }
            _ => line.to_string(),
        };
        lines.push(l);
    }
    lines.join("\n")
}

/// CPU time (user + system) of the waited-for children of this process, in
/// seconds (fields 16 and 17 of `/proc/self/stat`, in 1/100 s ticks).
fn children_cpu() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("read /proc/self/stat");
    // The command name (field 2) may contain spaces: split after its ')'.
    let rest = &stat[stat.rfind(')').expect("stat format") + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // rest starts at field 3; cutime, cstime are fields 16, 17.
    let ticks: f64 = fields[13].parse::<f64>().unwrap() + fields[14].parse::<f64>().unwrap();
    ticks / 100.0
}

/// An RGB image of floats.
struct Img {
    width: usize,
    height: usize,
    rgb: Vec<[f32; 3]>,
}

/// The main layer of an EXR written by the renderer
/// ([`omnee_render::files::read_exr`]).
fn read_exr(path: &Path) -> Img {
    let layers = omnee_render::files::read_exr(path).expect("read EXR");
    let rgb = layers
        .get("")
        .expect("the main layer")
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    Img {
        width: layers.width,
        height: layers.height,
        rgb,
    }
}

/// One render: (image, child CPU seconds, renderer's wall seconds).
#[allow(clippy::too_many_arguments)]
fn render(
    omnee: &Path,
    scene: &Path,
    tech: &str,
    spp: u32,
    seed: u64,
    resolution: &str,
    threads: usize,
    extra: &[&str],
    out: &Path,
) -> (Img, f64, f64) {
    let before = children_cpu();
    let output = Command::new(omnee)
        .args(["render", "--scene"])
        .arg(scene)
        .args(["--terms", "once-more", "--technique", tech])
        .args(["--spp", &spp.to_string(), "--seed", &seed.to_string()])
        .args([
            "--resolution",
            resolution,
            "--threads",
            &threads.to_string(),
        ])
        .args(extra)
        .args(["--format", "exr", "--progress", "never", "--json", "-o"])
        .arg(out)
        .output()
        .expect("run omnee render");
    let cpu = children_cpu() - before;
    assert!(
        output.status.success(),
        "omnee render failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("render --json summary");
    let wall = summary["seconds"].as_f64().unwrap_or(f64::NAN);
    (read_exr(&out.with_extension("exr")), cpu, wall)
}

fn luminance(p: [f32; 3]) -> f64 {
    (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0
}

/// Per-pixel relMSE of `img` against `reference`, ε = (0.01 · mean R)².
fn rel_mse(img: &Img, reference: &[f64]) -> f64 {
    let mean = reference.iter().sum::<f64>() / reference.len() as f64;
    let eps = (0.01 * mean).powi(2);
    img.rgb
        .iter()
        .zip(reference)
        .map(|(&p, &r)| (luminance(p) - r).powi(2) / (r * r + eps))
        .sum::<f64>()
        / reference.len() as f64
}

struct Row {
    name: String,
    reference_noise: f64,
    curves: Vec<Curve>,
}

fn plot(rows: &[Row], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    // Times below the 10 ms tick of the CPU clock are drawn at 10 ms.
    let panels: Vec<loglog::Panel> = rows
        .iter()
        .map(|row| loglog::Panel {
            caption: row.name.clone(),
            curves: row.curves.iter().map(Curve::time_error).collect(),
        })
        .collect();
    let layout = loglog::Layout {
        names: &NAMES,
        colors: &COLORS,
        cols: 2,
        panel: (420, 260),
        legend_step: 200,
        x_desc: "CPU seconds (one core)",
    };
    loglog::svg(path, &layout, &panels)
}

/// sRGB encoding of a linear value in [0, 1].
fn srgb(x: f64) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let y = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (y * 255.0 + 0.5) as u8
}

/// The window `[x0, x1) × [y0, y1)` of `img`.
fn window(img: &Img, [x0, y0, x1, y1]: [usize; 4]) -> Img {
    let mut rgb = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        rgb.extend_from_slice(&img.rgb[y * img.width + x0..y * img.width + x1]);
    }
    Img {
        width: x1 - x0,
        height: y1 - y0,
        rgb,
    }
}

/// The equal-time comparison: the centre window of the default scene at
/// 480x360, rendered by each technique with the same CPU time (spp from the
/// measured CPU seconds per spp, scaled by the pixel count), and a
/// reference, side by side with one exposure.
fn crops(
    omnee: &Path,
    scene: &Path,
    dir: &Path,
    curves: &[Curve],
    small_pixels: usize,
    md: &mut String,
) {
    let budget: f64 = arg("--crop-budget", 1.0);
    let reference_spp: u32 = arg("--crop-reference-spp", 2048);
    let win = [120usize, 90, 360, 270];
    let crop = format!("{},{},{},{}", win[0], win[1], win[2], win[3]);
    let extra = ["--crop", crop.as_str()];
    let pixels = (win[2] - win[0]) * (win[3] - win[1]);
    let go = |tech: &str, spp: u32, seed: u64, threads: usize| {
        let (img, cpu, _) = render(
            omnee,
            scene,
            tech,
            spp,
            seed,
            "480x360",
            threads,
            &extra,
            &dir.join(format!("crop-{tech}")),
        );
        (window(&img, win), cpu)
    };
    let (a, _) = go("omnee", reference_spp, 9_000_001, 2);
    let (b, _) = go("omnee", reference_spp, 9_000_002, 2);
    let mut reference = a;
    for (p, q) in reference.rgb.iter_mut().zip(&b.rgb) {
        for (x, y) in p.iter_mut().zip(q) {
            *x = 0.5 * (*x + y);
        }
    }
    let reference_lum: Vec<f64> = reference.rgb.iter().map(|&p| luminance(p)).collect();
    let mut sorted = reference_lum.clone();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let scale = 0.8 / sorted[(sorted.len() as f64 * 0.995) as usize].max(1e-30);
    let (cw, ch) = (reference.width, reference.height);
    let gap = 4;
    let panels = NAMES.len() + 1;
    let (out_w, out_h) = (panels * cw + (panels - 1) * gap, ch);
    let mut out = vec![255u8; out_w * out_h * 3];
    let mut put = |k: usize, img: &Img| {
        for y in 0..ch {
            for x in 0..cw {
                let p = img.rgb[y * cw + x];
                let o = (y * out_w + k * (cw + gap) + x) * 3;
                for c in 0..3 {
                    out[o + c] = srgb(p[c] as f64 * scale);
                }
            }
        }
    };
    writeln!(
        md,
        "\n### Equal-time crops (default scene, window {crop} of 480x360, about {budget} s of one core each)\n\n\
         ![equal-time crops](../figures/slab-equal-time.png)\n\n\
         Left to right: omnee, equiangular, distance, mis, reference (omnee, 2 × {reference_spp} spp). \
         One exposure for all panels.\n\n| technique | spp | CPU s | relMSE |\n|---|---|---|---|"
    )
    .unwrap();
    for (k, tech) in NAMES.iter().enumerate() {
        let per_spp = curves[k].seconds_per_sample() * pixels as f64 / small_pixels as f64;
        let spp = ((budget / per_spp).round() as u32).max(1);
        let (img, cpu) = go(tech, spp, 8_000 + k as u64, 1);
        writeln!(
            md,
            "| {tech} | {spp} | {cpu:.2} | {} |",
            fmt3(rel_mse(&img, &reference_lum))
        )
        .unwrap();
        put(k, &img);
    }
    put(NAMES.len(), &reference);
    let path = docs_path("figures/slab-equal-time.png");
    let file = std::fs::File::create(&path).expect("create png");
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), out_w as u32, out_h as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().expect("png header");
    writer.write_image_data(&out).expect("png data");
}

fn main() {
    let default_bin = std::env::current_exe()
        .ok()
        .and_then(|p| Some(p.parent()?.parent()?.join("omnee")))
        .unwrap_or_else(|| PathBuf::from("omnee"));
    let omnee = PathBuf::from(arg("--omnee", default_bin.display().to_string()));
    if !omnee.exists() {
        eprintln!(
            "{} not found: build the renderer first (`cargo build --release -p omnee-cli` \
             with the same CARGO_TARGET_DIR) or pass `-- --omnee PATH`",
            omnee.display()
        );
        std::process::exit(2);
    }
    let resolution: String = arg("--resolution", "160x120".to_string());
    let max_log2: u32 = arg("--max-log2", 7);
    let reference_spp: u32 = arg("--reference-spp", 4096);
    let only: String = arg("--only", String::new());
    let threads: usize = arg("--threads", 2);
    let dir = std::env::temp_dir().join(format!("omnee-slab-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let started = std::time::Instant::now();

    let mut rows = Vec::new();
    let mut default_reference = None;
    for (vi, v) in variants().into_iter().enumerate() {
        if !only.is_empty() && !v.name.contains(&only) {
            continue;
        }
        let scene = dir.join(format!("scene-{vi}.toml"));
        std::fs::write(&scene, scene_text(&omnee, &v)).expect("write scene");
        // Reference: two independent halves on all threads.
        let reference_run = |seed: u64, name: &str| {
            render(
                &omnee,
                &scene,
                "omnee",
                reference_spp,
                seed,
                &resolution,
                threads,
                &[],
                &dir.join(name),
            )
            .0
        };
        let (a, b) = (
            reference_run(1_000_001, "ref-a"),
            reference_run(2_000_003, "ref-b"),
        );
        let reference: Vec<f64> = a
            .rgb
            .iter()
            .zip(&b.rgb)
            .map(|(&p, &q)| 0.5 * (luminance(p) + luminance(q)))
            .collect();
        let reference_noise =
            rel_mse(&a, &b.rgb.iter().map(|&p| luminance(p)).collect::<Vec<_>>()) / 4.0;
        let mut curves = vec![Curve::new(TICK); NAMES.len()];
        for log2 in 0..=max_log2 {
            let spp = 1u32 << log2;
            for (k, tech) in NAMES.iter().enumerate() {
                let (img, cpu, wall) = render(
                    &omnee,
                    &scene,
                    tech,
                    spp,
                    (vi as u64) << 32 | (k as u64) << 16 | log2 as u64,
                    &resolution,
                    1,
                    &[],
                    &dir.join(format!("run-{tech}")),
                );
                curves[k].points.push(Point {
                    count: spp.into(),
                    cpu_seconds: cpu,
                    wall_seconds: wall,
                    rel_mse: rel_mse(&img, &reference),
                });
            }
        }
        eprintln!(
            "{}: reference noise {:.2e}, efficiency {:?} ({:.0} s)",
            v.name,
            reference_noise,
            curves
                .iter()
                .map(|c| c.efficiency(EFF_SPP))
                .collect::<Vec<_>>(),
            started.elapsed().as_secs_f64()
        );
        if vi == 0 {
            default_reference = Some((scene.clone(), curves.clone(), a.width * a.height));
        }
        rows.push(Row {
            name: v.name,
            reference_noise,
            curves,
        });
    }

    let budget: f64 = arg("--budget", 1.0);
    let mut md = String::new();
    writeln!(
        md,
        "<!-- generated by `cargo bench --bench slab_time_vs_error -- --resolution {resolution} --max-log2 {max_log2} --reference-spp {reference_spp}`; do not edit -->\n\n\
         ### Slab scene, once-more term: relMSE at equal time ({budget} s of one core) and efficiency\n\n\
         Efficiency is the median over spp = {EFF_SPP} … 2^{max_log2} of 1/(relMSE·CPU seconds); `÷ eq.` relative to equiangular, \
         `÷ best single` relative to the best of omnee, equiangular and distance (other than itself). \
         The reference noise is the reference's own relMSE, estimated from its two halves. \
         The relMSE at equal time is interpolated (log-log) between the measured renders around the budget; \
         – where the budget lies outside the measured CPU times or no render qualifies for the efficiency.\n\n\
         | variant | ref. noise | relMSE omnee | relMSE equiangular | relMSE distance | relMSE mis | omnee ÷ eq. | omnee ÷ best other single | distance ÷ eq. | mis ÷ eq. | mis ÷ best single | CPU s per spp omnee / eq. / dist. / mis |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    let mut json = Vec::new();
    for row in &rows {
        let eff: Vec<Option<f64>> = row.curves.iter().map(|c| c.efficiency(EFF_SPP)).collect();
        let best_single = |i: usize| best_other_single(&eff, i);
        let per_spp = |i: usize| row.curves[i].seconds_per_sample();
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} / {} / {} |",
            row.name,
            fmt3(row.reference_noise),
            fmt_opt(row.curves[0].at_time(budget)),
            fmt_opt(row.curves[1].at_time(budget)),
            fmt_opt(row.curves[2].at_time(budget)),
            fmt_opt(row.curves[3].at_time(budget)),
            fmt_opt(ratio(eff[0], eff[1])),
            fmt_opt(ratio(eff[0], best_single(0))),
            fmt_opt(ratio(eff[2], eff[1])),
            fmt_opt(ratio(eff[3], eff[1])),
            fmt_opt(ratio(eff[3], best_single(3))),
            fmt3(per_spp(0)),
            fmt3(per_spp(1)),
            fmt3(per_spp(2)),
            fmt3(per_spp(3)),
        )
        .unwrap();
        json.push(serde_json::json!({
            "variant": row.name,
            "reference_noise": row.reference_noise,
            "curves": row.curves.iter().zip(NAMES).map(|(c, t)| serde_json::json!({
                "technique": t,
                "efficiency": c.efficiency(EFF_SPP),
                "points": c.points_json("spp"),
            })).collect::<Vec<_>>(),
        }));
    }
    if flag("--crops") {
        if let Some((scene, curves, pixels)) = &default_reference {
            crops(&omnee, scene, &dir, curves, *pixels, &mut md);
        }
    }
    writeln!(
        md,
        "\nTotal run time {:.0} s.",
        started.elapsed().as_secs_f64()
    )
    .unwrap();
    std::fs::write(docs_path("results/slab.md"), &md).expect("write md");
    std::fs::write(
        docs_path("results/slab.json"),
        serde_json::to_string_pretty(&serde_json::json!({
            "resolution": resolution, "reference_spp": reference_spp, "rows": json
        }))
        .unwrap(),
    )
    .expect("write json");
    plot(&rows, &docs_path("figures/slab.svg")).expect("plot");
    let _ = std::fs::remove_dir_all(&dir);
    println!("{md}");
}
