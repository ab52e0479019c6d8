//! The render loop: progressive passes of one sample per pixel, a layer per
//! transport term, independent of what a pixel sample computes (the caller
//! passes that in).
//!
//! Every pixel sample draws from its own random stream, seeded by
//! `(seed, pixel index in the full image, pass)`: the image does not depend
//! on the thread count, and a crop renders exactly the pixels of the full
//! image.

pub mod budget;
pub mod progress;

use crate::image::Layers;
use crate::rng::Rng;
use crate::stats::Stats;
use crate::term::Term;
use budget::Budget;
use glam::Vec3;
use progress::Progress;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Everything the loop needs besides the pixel sample.
#[derive(Clone, Debug)]
pub struct Options {
    /// Samples per pixel or a time budget.
    pub budget: Budget,
    /// Random seed.
    pub seed: u64,
    /// Image size.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Pixel window `[x0, x1) × [y0, y1)` to render; the rest stays 0.
    pub crop: [u32; 4],
    /// The terms, one layer each (distinct, in [`Term`] order).
    pub terms: Vec<Term>,
    /// Draw a progress bar on stderr.
    pub progress: bool,
}

/// The result of a render.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The main layer (sum) and one layer per evaluated term.
    pub layers: Layers,
    /// Samples per pixel done.
    pub spp: u32,
    /// Work counters.
    pub stats: Stats,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Renders layers `""` (the sum) and one per term of `opt.terms`.
/// `sample(x, y, rng, stats, out)` computes one sample of each term's RGB
/// radiance at the image point `(x, y)` (in pixels, jittered in the pixel)
/// into `out[k]` for `opt.terms[k]`.
pub fn render<S>(opt: &Options, sample: S) -> Rendered
where
    S: Fn(f32, f32, &mut Rng, &mut Stats, &mut [Vec3]) + Sync,
{
    let start = Instant::now();
    let [x0, y0, x1, y1] = opt.crop;
    let (cw, ch) = ((x1 - x0) as usize, (y1 - y0) as usize);
    let n = opt.terms.len();
    // Per pixel and term: RGB sums in f64.
    let mut acc = vec![0.0f64; cw * ch * n * 3];
    let mut stats = Stats::default();
    let rows_done = AtomicU64::new(0);
    let progress = opt.progress.then(|| Progress::start(opt.budget, ch as u64));
    let mut pass: u32 = 0;
    loop {
        let row_stats: Vec<Stats> = acc
            .par_chunks_mut(cw * n * 3)
            .enumerate()
            .map(|(r, row)| {
                let py = y0 as usize + r;
                let mut st = Stats::default();
                let mut out = vec![Vec3::ZERO; n];
                for (c, px_acc) in row.chunks_exact_mut(n * 3).enumerate() {
                    let px = x0 as usize + c;
                    let index = (py * opt.width as usize + px) as u64;
                    let mut rng = Rng::stream(opt.seed, index, pass as u64);
                    let (jx, jy): (f32, f32) = (rng.uniform(), rng.uniform());
                    sample(px as f32 + jx, py as f32 + jy, &mut rng, &mut st, &mut out);
                    for (a, v) in px_acc.iter_mut().zip(out.iter().flat_map(|v| v.to_array())) {
                        *a += v as f64;
                    }
                }
                rows_done.fetch_add(1, Ordering::Relaxed);
                if let Some(p) = &progress {
                    p.rows(rows_done.load(Ordering::Relaxed));
                }
                st
            })
            .collect();
        for s in &row_stats {
            stats.add(s);
        }
        pass += 1;
        if let Some(p) = &progress {
            p.pass(pass);
        }
        if opt.budget.done(pass, start.elapsed().as_secs_f64()) {
            break;
        }
    }
    if let Some(p) = progress {
        p.finish();
    }
    Rendered {
        layers: layers(opt, &acc, pass),
        spp: pass,
        stats,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The full-size layers from the crop's sums over `passes` passes: each
/// term's mean, and `""` their sum (in f32, in term order).
fn layers(opt: &Options, acc: &[f64], passes: u32) -> Layers {
    let [x0, y0, x1, y1] = opt.crop;
    let (cw, ch) = ((x1 - x0) as usize, (y1 - y0) as usize);
    let (w, h) = (opt.width as usize, opt.height as usize);
    let n = opt.terms.len();
    let inv = 1.0 / passes as f64;
    let mut sum = vec![0.0f32; w * h * 3];
    let mut layers = vec![(String::new(), Vec::new())];
    for (k, term) in opt.terms.iter().enumerate() {
        let mut data = vec![0.0f32; w * h * 3];
        for r in 0..ch {
            for c in 0..cw {
                let dst = ((y0 as usize + r) * w + x0 as usize + c) * 3;
                let src = ((r * cw + c) * n + k) * 3;
                for j in 0..3 {
                    let v = (acc[src + j] * inv) as f32;
                    data[dst + j] = v;
                    sum[dst + j] += v;
                }
            }
        }
        layers.push((term.to_string(), data));
    }
    layers[0].1 = sum;
    Layers {
        width: w,
        height: h,
        layers,
    }
}
