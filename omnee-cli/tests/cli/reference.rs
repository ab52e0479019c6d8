//! A small render against the stored reference (`tests/data/render_reference.json`).

use crate::common::*;
use std::collections::HashMap;
use std::path::Path;

/// Block means of a layer (mean of R, G, B) over the 2 × 2 quadrants.
fn quadrants(ch: &HashMap<String, Vec<f32>>, layer: &str, w: usize, h: usize) -> [f64; 4] {
    let mut out = [0.0; 4];
    for y in 0..h {
        for x in 0..w {
            let q = (y * 2 / h) * 2 + x * 2 / w;
            let i = y * w + x;
            let v: f64 = ["R", "G", "B"]
                .iter()
                .map(|c| ch[&format!("{layer}.{c}")][i] as f64)
                .sum::<f64>()
                / 3.0;
            out[q] += v / (w * h / 4) as f64;
        }
    }
    out
}

const LAYERS: [&str; 3] = ["direct", "once-more", "view"];

/// Mean and standard error of the quadrant means over `seeds` renders of
/// `tests/data/small.toml` with `spp` samples per pixel each.
fn quadrant_stats(
    dir: &Path,
    seeds: std::ops::Range<u64>,
    spp: u32,
) -> HashMap<&'static str, Vec<(f64, f64)>> {
    let mut samples: HashMap<&str, Vec<[f64; 4]>> = HashMap::new();
    let scene = data("small.toml");
    for seed in seeds.clone() {
        let out = dir.join(format!("s{seed}"));
        let o = omnee()
            .args([
                "render",
                "--scene",
                scene.to_str().unwrap(),
                "--format",
                "exr",
                "--progress",
                "never",
            ])
            .args([
                "--spp",
                &spp.to_string(),
                "--seed",
                &seed.to_string(),
                "-o",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let ch = channels(&out.with_extension("exr"));
        for l in LAYERS {
            samples
                .entry(l)
                .or_default()
                .push(quadrants(&ch, l, 32, 24));
        }
    }
    let n = seeds.count() as f64;
    LAYERS
        .iter()
        .map(|&l| {
            let runs = &samples[l];
            let stats = (0..4)
                .map(|q| {
                    let mean = runs.iter().map(|r| r[q]).sum::<f64>() / n;
                    let var = runs.iter().map(|r| (r[q] - mean).powi(2)).sum::<f64>() / (n - 1.0);
                    (mean, (var / n).sqrt())
                })
                .collect();
            (l, stats)
        })
        .collect()
}

#[test]
fn a_small_render_matches_the_stored_reference() {
    // The reference (tests/data/render_reference.json) holds, per layer and
    // image quadrant, the mean and standard error over 64 renders of 256 spp
    // (seeds 1000..1064). Here: 32 renders of 64 spp with other seeds. Each of
    // the 10 comparisons uses z = Δ / √(se² + se_ref²), where se has 31
    // degrees of freedom; |z| < 6.5 bounds a t(31)-distributed z's two-sided
    // tail by 4e-7, 4e-6 for the family, while a 5 % bias in any layer moves
    // z by about 10.
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data("render_reference.json")).unwrap())
            .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let got = quadrant_stats(dir.path(), 1..33, 64);
    for l in LAYERS {
        for (q, &(m, se)) in got[l].iter().enumerate() {
            // The top quadrants of the view layer hold the glow around the
            // light seen through a g = 0.98 medium: a heavy-tailed estimator
            // (relative standard error 15-25 % even in the reference), whose
            // standard error 32 runs cannot estimate reliably. The view
            // estimator is checked against quadrature in world/view.rs instead.
            if l == "view" && q < 2 {
                continue;
            }
            let r = reference[l][q][0].as_f64().unwrap();
            let se_r = reference[l][q][1].as_f64().unwrap();
            let z = (m - r) / (se * se + se_r * se_r).sqrt();
            assert!(
                z.abs() < 6.5,
                "{l} quadrant {q}: {m} ± {se} vs {r} ± {se_r} (z = {z})"
            );
        }
    }
}

/// Rewrites `tests/data/render_reference.json` (run when the renderer's
/// expected output changes on purpose:
/// `cargo test -p omnee-cli --release -- --ignored regenerate`).
#[test]
#[ignore]
fn regenerate_render_reference() {
    let dir = tempfile::tempdir().unwrap();
    let got = quadrant_stats(dir.path(), 1000..1064, 256);
    let v: serde_json::Map<String, serde_json::Value> = LAYERS
        .iter()
        .map(|&l| {
            (
                l.to_string(),
                serde_json::json!(got[l].iter().map(|&(m, s)| [m, s]).collect::<Vec<_>>()),
            )
        })
        .collect();
    std::fs::write(
        data("render_reference.json"),
        serde_json::to_string_pretty(&v).unwrap() + "\n",
    )
    .unwrap();
}
