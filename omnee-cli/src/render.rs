//! `omnee render`: the slab scene seen by a pinhole camera, each transport
//! term in its own layer, progressive over passes of one sample per pixel.
//!
//! Every pixel sample draws from its own random stream, seeded by
//! `(seed, pixel index in the full image, pass)`: the image does not depend
//! on the thread count, and a crop renders exactly the pixels of the full
//! image.

use crate::image::Layers;
use crate::progress::Progress;
use crate::rng::Rng;
use crate::scene::Scene;
use crate::world::{Hit, OnceMore, Stats, World};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Which transport terms to evaluate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Terms {
    /// Light → surface (and the light seen directly), attenuated.
    pub direct: bool,
    /// Light → `x1` in the slab → surface.
    pub once_more: bool,
    /// Single scattering along the camera ray.
    pub view: bool,
}

impl Terms {
    /// From names (already validated).
    pub fn from_names(names: &[String]) -> Self {
        let has = |n: &str| names.iter().any(|t| t == n);
        Terms {
            direct: has("direct"),
            once_more: has("once-more"),
            view: has("view"),
        }
    }
}

/// When to stop.
#[derive(Clone, Copy, Debug)]
pub enum Budget {
    /// This many samples per pixel.
    Spp(u32),
    /// As many whole passes as fit in this many seconds (at least one).
    Seconds(f64),
}

/// Everything `render` needs besides the scene.
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
    /// Terms to evaluate (already reduced by what the scene needs).
    pub terms: Terms,
    /// How the once-more term is estimated.
    pub once_more: OnceMore,
    /// Russian roulette threshold in W/(m²·sr) (0: off).
    pub roulette: f32,
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

/// A pinhole camera in f32.
struct Camera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half: f32,
    width: f32,
    height: f32,
}

impl Camera {
    fn new(scene: &Scene, width: u32, height: u32) -> Self {
        let c = &scene.camera;
        let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let eye = v(c.position);
        let forward = (v(c.look_at) - eye).normalize();
        let right = forward.cross(v(c.up)).normalize();
        let up = right.cross(forward);
        Camera {
            eye,
            forward,
            right,
            up,
            tan_half: (0.5 * c.fov_deg.to_radians()).tan() as f32,
            width: width as f32,
            height: height as f32,
        }
    }

    /// The unit ray direction through the image point `(x, y)` in pixels.
    fn ray(&self, x: f32, y: f32) -> Vec3 {
        let aspect = self.width / self.height;
        let sx = (2.0 * x / self.width - 1.0) * self.tan_half * aspect;
        let sy = (1.0 - 2.0 * y / self.height) * self.tan_half;
        (self.forward + self.right * sx + self.up * sy).normalize()
    }
}

/// The radiance of one camera sample, per term: `[direct, once-more, view]`.
fn trace(
    world: &World<'_>,
    cam: &Camera,
    x: f32,
    y: f32,
    opt: &Options,
    rng: &mut Rng,
    stats: &mut Stats,
) -> [Vec3; 3] {
    let d = cam.ray(x, y);
    let o = cam.eye;
    let hit = world.intersect(o, d);
    let mut out = [Vec3::ZERO; 3];
    let t_end = match hit {
        Hit::Miss => f32::INFINITY,
        Hit::Light { t } => {
            if opt.terms.direct {
                let t_cam = world.transmittance(o, o + d * t);
                out[0] = Vec3::splat(world.light.radiance * t_cam);
            }
            t
        }
        Hit::Surface { t, p, n, albedo } => {
            let t_cam = world.transmittance(o, p);
            // Radiance per unit irradiance, for the roulette's scale.
            let brdf = albedo * std::f32::consts::FRAC_1_PI;
            let scale = t_cam * brdf.max_element();
            if scale > 0.0 {
                let rr = (scale, opt.roulette);
                if opt.terms.direct {
                    out[0] = brdf * (t_cam * world.direct(p, n, rng, rr, stats));
                }
                if opt.terms.once_more {
                    out[1] = brdf * (t_cam * world.once_more(p, n, opt.once_more, rng, rr, stats));
                }
            }
            t
        }
    };
    if opt.terms.view {
        out[2] = Vec3::splat(world.view(o, d, t_end, rng, opt.roulette, stats));
    }
    out
}

/// Renders `scene` into layers `""` (the sum), `direct`, `once-more`, `view`
/// (the evaluated terms only).
pub fn render(scene: &Scene, world: &World<'_>, opt: &Options) -> Rendered {
    let start = Instant::now();
    let cam = Camera::new(scene, opt.width, opt.height);
    let [x0, y0, x1, y1] = opt.crop;
    let cw = (x1 - x0) as usize;
    let ch = (y1 - y0) as usize;
    // Per pixel: 3 terms × RGB sums in f64.
    let mut acc = vec![[0.0f64; 9]; cw * ch];
    let mut stats = Stats::default();
    let rows_done = AtomicU64::new(0);
    let progress = opt.progress.then(|| Progress::start(opt.budget, ch as u64));
    let mut pass: u32 = 0;
    loop {
        let row_stats: Vec<Stats> = acc
            .par_chunks_mut(cw)
            .enumerate()
            .map(|(r, row)| {
                let py = y0 as usize + r;
                let mut st = Stats::default();
                for (c, px_acc) in row.iter_mut().enumerate() {
                    let px = x0 as usize + c;
                    let index = (py * opt.width as usize + px) as u64;
                    let mut rng = Rng::stream(opt.seed, index, pass as u64);
                    let (jx, jy): (f32, f32) = (rng.uniform(), rng.uniform());
                    let l = trace(
                        world,
                        &cam,
                        px as f32 + jx,
                        py as f32 + jy,
                        opt,
                        &mut rng,
                        &mut st,
                    );
                    for (k, v) in l.iter().enumerate() {
                        for j in 0..3 {
                            px_acc[3 * k + j] += v[j] as f64;
                        }
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
    let (w, h) = (opt.width as usize, opt.height as usize);
    let inv = 1.0 / pass as f64;
    let names = ["direct", "once-more", "view"];
    let enabled = [opt.terms.direct, opt.terms.once_more, opt.terms.view];
    let mut sum = vec![0.0f32; w * h * 3];
    let mut layers: Vec<(String, Vec<f32>)> = Vec::new();
    for (k, name) in names.iter().enumerate() {
        if !enabled[k] {
            continue;
        }
        let mut data = vec![0.0f32; w * h * 3];
        for r in 0..ch {
            for c in 0..cw {
                let dst = ((y0 as usize + r) * w + x0 as usize + c) * 3;
                for j in 0..3 {
                    let v = (acc[r * cw + c][3 * k + j] * inv) as f32;
                    data[dst + j] = v;
                    sum[dst + j] += v;
                }
            }
        }
        layers.push((name.to_string(), data));
    }
    layers.insert(0, (String::new(), sum));
    Rendered {
        layers: Layers {
            width: w,
            height: h,
            layers,
        },
        spp: pass,
        stats,
        seconds: start.elapsed().as_secs_f64(),
    }
}
