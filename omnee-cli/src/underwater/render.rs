//! The underwater render loop: passes of light paths, traced in parallel in
//! fixed chunks, their splats added in chunk order, so that the image depends
//! on the seed and never on the thread count.

use super::transport::{Splat, Stats, TERMS, World, layer};
use crate::image::Layers;
use crate::render::budget::Budget;
use crate::render::progress::Progress;
use crate::rng::Rng;
use rayon::prelude::*;
use std::time::Instant;

/// Light paths per chunk: one random stream each, traced by one thread.
pub const CHUNK: u64 = 4096;

/// Everything a render needs besides the world.
#[derive(Clone, Debug)]
pub struct Options {
    /// Passes of `width · height` light paths, or a time budget.
    pub budget: Budget,
    /// Random seed.
    pub seed: u64,
    /// The pixel window `[x0, x1) × [y0, y1)` kept; the rest stays 0. Every
    /// crop traces the same paths, so crops rendered apart sum to the image.
    pub crop: [u32; 4],
    /// Draw a progress bar on stderr.
    pub progress: bool,
}

/// The result of a render.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The sum `""` and one layer per evaluated term.
    pub layers: Layers,
    /// Passes done (light paths per pixel).
    pub passes: u32,
    /// Work counters.
    pub stats: Stats,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// The splats and counters of chunk `chunk` of pass `pass`: paths
/// `[chunk · CHUNK, min((chunk + 1) · CHUNK, n))` with the stream
/// `(seed, chunk, pass)`.
pub fn trace_chunk(
    world: &World<'_>,
    seed: u64,
    pass: u32,
    chunk: u64,
    n: u64,
) -> (Vec<Splat>, Stats) {
    let mut rng = Rng::stream(seed, chunk, pass as u64);
    let mut out = Vec::with_capacity(3 * CHUNK as usize);
    let mut stats = Stats::default();
    for _ in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
        world.trace(&mut rng, &mut out, &mut stats);
    }
    (out, stats)
}

/// Renders the world's terms: each pass traces `width · height` light paths;
/// the image is the sum of the splats over the paths started.
pub fn render(world: &World<'_>, opt: &Options) -> Rendered {
    let start = Instant::now();
    let cam = &world.camera;
    let (w, h) = (cam.width as usize, cam.height as usize);
    let paths_per_pass = (w * h) as u64;
    let chunks = paths_per_pass.div_ceil(CHUNK);
    let mut acc = vec![[0.0f64; 3 * TERMS.len()]; w * h];
    let mut stats = Stats::default();
    let progress = opt.progress.then(|| Progress::start(opt.budget, chunks));
    let [cx0, cy0, cx1, cy1] = opt.crop.map(|v| v as usize);
    let mut pass: u32 = 0;
    loop {
        let results: Vec<(Vec<Splat>, Stats)> = (0..chunks)
            .into_par_iter()
            .map(|c| {
                let r = trace_chunk(world, opt.seed, pass, c, paths_per_pass);
                if let Some(p) = &progress {
                    p.rows(u64::from(pass) * chunks + c + 1);
                }
                r
            })
            .collect();
        // In chunk order, whatever order the threads finished in.
        for (splats, st) in &results {
            stats.add(st);
            for s in splats {
                let (x, y) = (s.pixel as usize % w, s.pixel as usize / w);
                if x >= cx0 && x < cx1 && y >= cy0 && y < cy1 {
                    let a = &mut acc[s.pixel as usize];
                    for j in 0..3 {
                        a[3 * layer(s.term) + j] += s.value[j] as f64;
                    }
                }
            }
        }
        pass += 1;
        if let Some(p) = &progress {
            p.pass(pass);
        }
        let elapsed = start.elapsed().as_secs_f64();
        let done = match opt.budget {
            Budget::Spp(n) => pass >= n,
            Budget::Seconds(s) => elapsed + elapsed / pass as f64 > s,
        };
        if done {
            break;
        }
    }
    if let Some(p) = progress {
        p.finish();
    }
    let inv = 1.0 / (paths_per_pass as f64 * pass as f64);
    let mut sum = vec![0.0f32; w * h * 3];
    let mut layers = vec![(String::new(), Vec::new())];
    for (k, term) in TERMS.into_iter().enumerate() {
        if !world.terms[k] {
            continue;
        }
        let data: Vec<f32> = acc
            .iter()
            .flat_map(|a| (0..3).map(move |j| (a[3 * k + j] * inv) as f32))
            .collect();
        for (s, v) in sum.iter_mut().zip(&data) {
            *s += v;
        }
        layers.push((term.to_string(), data));
    }
    layers[0].1 = sum;
    Rendered {
        layers: Layers {
            width: w,
            height: h,
            layers,
        },
        passes: pass,
        stats,
        seconds: start.elapsed().as_secs_f64(),
    }
}
