//! The render loop of every scene: progressive passes over a scene's work
//! items (a row of pixels gathered by camera rays, a chunk of light paths
//! splatted into the image), in parallel, each item from its own random
//! stream, its result added to the image in item order. The image therefore
//! depends on the seed and never on the thread count or the order threads
//! finish in, and a crop renders exactly the pixels of the full image.
//!
//! What an item computes is the scene's ([`Integrator`]); the loop owns the
//! passes, the budget, the accumulation in f64, the layers (one per
//! transport term, and their sum), the progress reports and cancellation.

pub mod budget;

use crate::error::{RenderError, Result};
use crate::image::Layers;
use crate::parallel::map_items_with;
use budget::RenderBudget;
use glam::Vec3;
use omnee_core::term::Term;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Work counters of a scene, summed over the items of a render.
pub trait Counters: Default + Copy + Send {
    /// Adds another item's counters.
    fn add(&mut self, other: &Self);
}

/// What a scene computes per work item of a pass.
pub trait Integrator: Sync {
    /// The scene's work counters.
    type Stats: Counters;
    /// What one item gives back for [`Integrator::add`].
    type Item: Send;
    /// Buffers an item may reuse from the item before it on the same
    /// thread (`()` for none); an item's result never depends on them.
    type Scratch: Default;

    /// The image size in pixels.
    fn size(&self) -> (u32, u32);

    /// The terms, one layer each, in [`Term`] order.
    fn terms(&self) -> &[Term];

    /// Work items per pass (rows of pixels, chunks of light paths).
    fn items(&self) -> u64;

    /// Samples per pixel that one pass adds to each pixel's sums: the mean
    /// after `n` passes is the sum over `n · per_pass` (1 for a gathering
    /// renderer, the light paths per pass for a splatting one).
    fn per_pass(&self) -> f64;

    /// Item `item` of pass `pass` with the random streams of `seed`,
    /// counting its work in `stats`, with the thread's `scratch` buffers.
    fn item(
        &self,
        seed: u64,
        pass: u32,
        item: u64,
        stats: &mut Self::Stats,
        scratch: &mut Self::Scratch,
    ) -> Self::Item;

    /// Adds an item's result to the sums.
    fn add(&self, item: &Self::Item, sums: &mut Sums);
}

/// The image's running sums in f64: per pixel, per layer, RGB. Pixels
/// outside the crop are not kept.
#[derive(Clone, Debug)]
pub struct Sums {
    width: usize,
    layers: usize,
    crop: [u32; 4],
    data: Vec<f64>,
}

impl Sums {
    fn new(width: u32, height: u32, layers: usize, crop: [u32; 4]) -> Self {
        let (width, height) = (width as usize, height as usize);
        Self {
            width,
            layers,
            crop,
            data: vec![0.0; width * height * layers * 3],
        }
    }

    /// Adds `value` to layer `layer` of the pixel `(x, y)`, if it is in the
    /// crop.
    #[inline]
    pub fn add(&mut self, x: u32, y: u32, layer: usize, value: Vec3) {
        let [x0, y0, x1, y1] = self.crop;
        if x >= x0 && x < x1 && y >= y0 && y < y1 {
            let i = ((y as usize * self.width + x as usize) * self.layers + layer) * 3;
            for (a, v) in self.data[i..i + 3].iter_mut().zip(value.to_array()) {
                *a += v as f64;
            }
        }
    }

    /// [`Sums::add`] at the pixel index `y · width + x`.
    #[inline]
    pub fn add_at(&mut self, pixel: u32, layer: usize, value: Vec3) {
        let w = self.width as u32;
        self.add(pixel % w, pixel / w, layer, value);
    }
}

/// What the loop needs besides the scene.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Passes, or a time budget.
    pub budget: RenderBudget,
    /// Random seed.
    pub seed: u64,
    /// Pixel window `[x0, x1) × [y0, y1)` kept; the rest stays 0. Every
    /// crop computes the same samples, so crops rendered apart sum to the
    /// image.
    pub crop: [u32; 4],
}

/// Where a render is, for a progress display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Whole passes done.
    pub passes: u32,
    /// Items done in all passes together.
    pub items: u64,
    /// Items in one pass.
    pub items_per_pass: u64,
    /// Seconds since the render started.
    pub seconds: f64,
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct Rendered<S> {
    /// The sum `""` and one layer per term.
    pub layers: Layers,
    /// Passes done.
    pub passes: u32,
    /// Work counters.
    pub stats: S,
    /// Wall-clock seconds.
    pub seconds: f64,
}

impl<S> Rendered<S> {
    /// The same render with its counters mapped by `f`.
    pub fn map_stats<T>(self, f: impl FnOnce(S) -> T) -> Rendered<T> {
        Rendered {
            layers: self.layers,
            passes: self.passes,
            stats: f(self.stats),
            seconds: self.seconds,
        }
    }
}

/// Renders `scene` pass by pass until `options.budget` is spent, calling
/// `progress` after every item and at the end of every pass (from the
/// worker threads: it must be cheap), and stopping with
/// [`RenderError::Cancelled`] as soon as `cancel` is set (checked before
/// every item). Runs on the current rayon pool.
pub fn render<I: Integrator>(
    scene: &I,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
    cancel: &AtomicBool,
) -> Result<Rendered<I::Stats>> {
    let start = Instant::now();
    let (width, height) = scene.size();
    let items = scene.items();
    let mut sums = Sums::new(width, height, scene.terms().len(), options.crop);
    let mut stats = I::Stats::default();
    let mut passes: u32 = 0;
    let report = |passes: u32, items_done: u64| {
        progress(Progress {
            passes,
            items: items_done,
            items_per_pass: items,
            seconds: start.elapsed().as_secs_f64(),
        })
    };
    let done = std::sync::atomic::AtomicU64::new(0);
    loop {
        let results = map_items_with(items, cancel, I::Scratch::default, |scratch, k| {
            let mut st = I::Stats::default();
            let out = scene.item(options.seed, passes, k, &mut st, scratch);
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            report(passes, n);
            (out, st)
        })
        .ok_or(RenderError::Cancelled)?;
        // In item order, whatever order the threads finished in.
        for (out, st) in &results {
            stats.add(st);
            scene.add(out, &mut sums);
        }
        passes += 1;
        report(passes, u64::from(passes) * items);
        if options.budget.done(passes, start.elapsed().as_secs_f64()) {
            break;
        }
    }
    Ok(Rendered {
        layers: layers(scene, &sums, passes),
        passes,
        stats,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The layers from the sums over `passes` passes: each term's mean
/// `sum / (passes · per_pass)` in f32, and `""` their sum (in f32, in term
/// order).
fn layers<I: Integrator>(scene: &I, sums: &Sums, passes: u32) -> Layers {
    let (width, height) = scene.size();
    let (w, h) = (width as usize, height as usize);
    let n = sums.layers;
    let inv = 1.0 / (scene.per_pass() * passes as f64);
    let mut sum = vec![0.0f32; w * h * 3];
    let mut layers = vec![(String::new(), Vec::new())];
    for (k, term) in scene.terms().iter().enumerate() {
        let mut data = vec![0.0f32; w * h * 3];
        for (pixel, (d, s)) in data
            .chunks_exact_mut(3)
            .zip(sum.chunks_exact_mut(3))
            .enumerate()
        {
            let src = (pixel * n + k) * 3;
            for j in 0..3 {
                let v = (sums.data[src + j] * inv) as f32;
                d[j] = v;
                s[j] += v;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// A scene whose every pixel sample is a uniform number: two layers,
    /// one row per item.
    struct Noise;

    #[derive(Clone, Copy, Debug, Default)]
    struct Count(u64);

    impl Counters for Count {
        fn add(&mut self, other: &Self) {
            self.0 += other.0;
        }
    }

    impl Integrator for Noise {
        type Stats = Count;
        type Item = (u32, Vec<f32>);
        type Scratch = ();
        fn size(&self) -> (u32, u32) {
            (5, 4)
        }
        fn terms(&self) -> &[Term] {
            &[Term::Direct, Term::View]
        }
        fn items(&self) -> u64 {
            4
        }
        fn per_pass(&self) -> f64 {
            1.0
        }
        fn item(
            &self,
            seed: u64,
            pass: u32,
            item: u64,
            stats: &mut Count,
            (): &mut (),
        ) -> (u32, Vec<f32>) {
            stats.0 += 5;
            let row = (0..5)
                .map(|x| Rng::stream(seed, item * 5 + x, pass as u64).uniform())
                .collect();
            (item as u32, row)
        }
        fn add(&self, (y, row): &(u32, Vec<f32>), sums: &mut Sums) {
            for (x, v) in row.iter().enumerate() {
                sums.add(x as u32, *y, 0, Vec3::splat(*v));
                sums.add(x as u32, *y, 1, Vec3::splat(1.0));
            }
        }
    }

    #[test]
    fn passes_are_counted_and_the_crop_is_kept() {
        let cancel = AtomicBool::new(false);
        let options = Options {
            budget: RenderBudget::Spp(3),
            seed: 7,
            crop: [1, 0, 4, 4],
        };
        let r = render(&Noise, &options, &|_| {}, &cancel).unwrap();
        assert_eq!((r.passes, r.stats.0), (3, 3 * 4 * 5));
        let main = &r.layers.layers[0].1;
        assert_eq!(main[0], 0.0, "outside the crop");
        assert!(main[3] > 1.0, "inside the crop");
        assert_eq!(r.layers.layers.len(), 3);
        // The constant layer's mean is exactly 1 inside the crop.
        let view = &r.layers.layers[2].1;
        assert_eq!((view[3], view[0], view[12]), (1.0, 0.0, 0.0));
    }

    #[test]
    fn a_cancelled_render_stops_with_an_error() {
        let cancel = AtomicBool::new(true);
        let options = Options {
            budget: RenderBudget::Spp(1000),
            seed: 7,
            crop: [0, 0, 5, 4],
        };
        let r = render(&Noise, &options, &|_| {}, &cancel);
        assert!(matches!(r, Err(RenderError::Cancelled)));
    }
}
