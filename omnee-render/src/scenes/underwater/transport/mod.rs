//! Light tracing under water: sun rays through the surface to the floor, and
//! the four terms that connect them to the camera (docs/math.md §13). One
//! file per idea:
//!
//! - [`aim`]: where light paths start and the density they start with;
//! - [`tail`]: the defensive part of that density, which covers the whole
//!   plane, so that no sunlight is cut;
//! - [`caustics`]: `caustics`, the floor point `x0` straight to the eye, and
//!   `caustics-once-more`, `x0 → x1 → eye` with `x1` placed by the once-more
//!   technique, the blur with depth;
//! - [`shafts`]: a point on the refracted sun ray in the water straight to
//!   the eye, the god rays;
//! - [`shafts_once_more`]: such points connected once more, with the phase
//!   function's lobe at them.
//!
//! This file holds the light path itself ([`UnderwaterWorld::trace`]) and what the
//! terms share. Each light path is one sample of the sun's flux through the
//! whole (infinite) surface; every term splats its contribution to the pixel
//! its last vertex projects to, with the camera's importance
//! ([`crate::camera`]).

pub mod aim;
pub mod caustics;
pub mod shafts;
pub mod shafts_once_more;
pub mod tail;

pub use aim::{Aim, FloorCells, LightRegion, flat_water_offset};
pub use caustics::{CausticsMethod, CausticsTechnique};
pub use shafts::ShaftSampling;
pub use tail::TailedRect;

use super::optics::{fresnel_transmittance, refract};
use super::sun::Sun;
use super::surface::Surface;
use super::water::Water;
use crate::camera::{Pinhole, Projection};
use crate::parallel::CHUNK;
use crate::render::{Counters, Integrator, Sums};
use crate::rng::Rng;
use crate::scenes::floor::Floor;
use glam::Vec3;
use omnee_core::method::LobeMethod;
use omnee_core::phase::Phase;
use omnee_core::sampling::Sample;
use omnee_core::term::Term;

/// The scene's terms in the order of their layers.
pub const UNDERWATER_TERMS: [Term; 4] = [
    Term::Caustics,
    Term::CausticsOnceMore,
    Term::Shafts,
    Term::ShaftsOnceMore,
];

/// A term of the underwater scene: the [`Term`]s a light path of this
/// scene can splat into ([`UNDERWATER_TERMS`], in that order).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnderwaterTerm {
    /// [`Term::Caustics`].
    Caustics,
    /// [`Term::CausticsOnceMore`].
    CausticsOnceMore,
    /// [`Term::Shafts`].
    Shafts,
    /// [`Term::ShaftsOnceMore`].
    ShaftsOnceMore,
}

impl UnderwaterTerm {
    /// The [`Term`].
    pub fn term(self) -> Term {
        UNDERWATER_TERMS[self as usize]
    }
}

/// One contribution to the image: a pixel, a term and its RGB value
/// (radiance times the number of paths, W/(m²·sr)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Pixel index `y · width + x` in the full image.
    pub pixel: u32,
    /// The term.
    pub term: UnderwaterTerm,
    /// The value.
    pub value: Vec3,
}

/// Counters of the work done and skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UnderwaterStats {
    /// Light paths started.
    pub paths: u64,
    /// Paths aimed through the image at a point whose ray looks up: no
    /// start point on the floor (no work).
    pub no_start: u64,
    /// Paths that started outside the core rectangle of the defensive
    /// density (in its tail, or aimed through the image or past the eye
    /// beyond it).
    pub beyond_core: u64,
    /// Paths lost at the surface: refracted back out through a crest
    /// before reaching the troughs' depth, or met from below.
    pub lost_at_surface: u64,
    /// Paths that reached the floor.
    pub floor_hits: u64,
    /// Splats per term in layer order (contributions landing in the image).
    pub splats: [u64; 4],
    /// Once-more draws whose technique gave no vertex.
    pub no_vertex: u64,
    /// Wave-band visibility tests marched (segments with an end above the troughs).
    pub surface_tests: u64,
}

impl UnderwaterStats {
    /// The splat counts by term, `"caustics 12, …"`.
    pub fn splats_by_term(&self) -> String {
        UNDERWATER_TERMS
            .iter()
            .zip(self.splats)
            .map(|(t, n)| format!("{t} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl Counters for UnderwaterStats {
    fn add(&mut self, o: &UnderwaterStats) {
        self.paths += o.paths;
        self.no_start += o.no_start;
        self.beyond_core += o.beyond_core;
        self.lost_at_surface += o.lost_at_surface;
        self.floor_hits += o.floor_hits;
        for (a, b) in self.splats.iter_mut().zip(o.splats) {
            *a += b;
        }
        self.no_vertex += o.no_vertex;
        self.surface_tests += o.surface_tests;
    }
}

/// The underwater scene in f32, ready to trace.
pub struct UnderwaterWorld<'a> {
    /// The sun.
    pub sun: Sun,
    /// The water surface.
    pub surface: Surface,
    /// Refractive index of the water (air is 1).
    pub ior: f32,
    /// The water's coefficients.
    pub water: Water,
    /// The phase function, shared by the channels.
    pub phase: Phase<'a, f32>,
    /// The floor.
    pub floor: Floor,
    /// The camera.
    pub camera: Pinhole,
    /// Where light paths start.
    pub region: LightRegion,
    /// How far from the eye the core rectangle of the start density reaches (m).
    pub max_distance: f32,
    /// Which terms to evaluate, in the order of [`UNDERWATER_TERMS`].
    pub terms: [bool; 4],
    /// The terms evaluated, one image layer each.
    pub layers: Vec<Term>,
    /// The once-more technique.
    pub once_more: CausticsTechnique,
    /// The shafts' sampling.
    pub shafts: ShaftSampling,
    /// The technique for `shafts-once-more`'s vertex `x1`.
    pub lobe: LobeMethod,
    /// Once-more draws per floor point and shaft vertices per refracted ray:
    /// `[once-more, shafts]`, each contribution divided by its count.
    pub samples: [u32; 2],
}

impl UnderwaterWorld<'_> {
    /// The length of the ray `o + t d` from the eye through the water band
    /// below the crests and above the floor (infinite for a level ray).
    fn water_segment(&self, o: Vec3, d: Vec3) -> f32 {
        if d.z < 0.0 {
            (self.floor.z - o.z) / d.z
        } else if d.z > 0.0 {
            (self.surface.crest() - o.z) / d.z
        } else {
            f32::INFINITY
        }
    }

    /// Whether `x` is in the water: above the floor, below the surface.
    fn in_water(&self, x: Vec3) -> bool {
        x.z > self.floor.z
            && (x.z <= self.surface.trough() || x.z < self.surface.height(x.truncate()))
    }

    /// Whether the segment `a → b` between points in the water stays in it
    /// (only segments reaching into the wave band are marched).
    fn clear(&self, a: Vec3, b: Vec3, stats: &mut UnderwaterStats) -> bool {
        let trough = self.surface.trough();
        if a.z <= trough && b.z <= trough {
            return true;
        }
        stats.surface_tests += 1;
        self.surface.segment_under(a, b)
    }

    /// Whether `term` is evaluated.
    #[inline]
    pub fn enabled(&self, term: UnderwaterTerm) -> bool {
        self.terms[term as usize]
    }

    /// The splats and counters of chunk `chunk` of pass `pass`: paths
    /// `[chunk · CHUNK, min((chunk + 1) · CHUNK, n))` of the `n` per pass,
    /// with the stream `(seed, chunk, pass)`.
    pub fn trace_chunk(
        &self,
        seed: u64,
        pass: u32,
        chunk: u64,
        stats: &mut UnderwaterStats,
    ) -> Vec<Splat> {
        let n = self.paths_per_pass();
        let mut rng = Rng::stream(seed, chunk, pass as u64);
        let mut out = Vec::with_capacity(3 * CHUNK as usize);
        for _ in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
            self.trace(&mut rng, &mut out, stats);
        }
        out
    }

    /// Light paths per pass: one per pixel.
    pub fn paths_per_pass(&self) -> u64 {
        u64::from(self.camera.width) * u64::from(self.camera.height)
    }

    /// Traces one light path and appends its splats.
    pub fn trace(&self, rng: &mut Rng, out: &mut Vec<Splat>, stats: &mut UnderwaterStats) {
        stats.paths += 1;
        let Some(xf) = self.start(uniform3(rng)) else {
            stats.no_start += 1;
            return;
        };
        if !self.region.tail.contains(xf.truncate()) {
            stats.beyond_core += 1;
        }
        let (to_sun, flux_factor) = self.sun.sample([rng.uniform(), rng.uniform()]);
        // Flux through the start plane: L Ω (ω · z) / pdf(x_s).
        let power = flux_factor * to_sun.z / self.start_pdf(xf);
        let xs = (xf.truncate() - self.region.offset).extend(self.region.z_top);
        let d = -to_sun;
        let Some((t_hit, point)) = self.surface.hit_from_above(xs, d) else {
            stats.lost_at_surface += 1;
            return;
        };
        let y = xs + d * t_hit;
        let cos_i = -d.dot(point.normal);
        let Some((dt, _)) = refract(d, point.normal, 1.0 / self.ior) else {
            stats.lost_at_surface += 1;
            return;
        };
        if !(dt.z < 0.0 && power.is_finite()) {
            stats.lost_at_surface += 1;
            return;
        }
        let power = power * fresnel_transmittance(cos_i, 1.0, self.ior);
        let t_floor = (self.floor.z - y.z) / dt.z;
        let mut x0 = y + dt * t_floor;
        x0.z = self.floor.z;
        // The refracted ray must not leave through a neighbouring crest.
        if !self.surface.is_flat() {
            stats.surface_tests += 1;
            if !self.surface.segment_under(y + dt * 1e-3, x0) {
                stats.lost_at_surface += 1;
                return;
            }
        }
        stats.floor_hits += 1;
        if self.enabled(UnderwaterTerm::Shafts) {
            self.shafts(y, dt, t_floor, power, rng, out, stats);
        }
        if self.enabled(UnderwaterTerm::ShaftsOnceMore) {
            self.shafts_once_more(y, dt, t_floor, power, rng, out, stats);
        }
        // Flux arriving at x0 per channel, times the floor's BRDF: the
        // radiance leaving x0 in any direction, per unit area density.
        let radiance = self.water.transmittance(t_floor)
            * self.floor.albedo(x0.truncate())
            * (power * std::f32::consts::FRAC_1_PI);
        if self.enabled(UnderwaterTerm::Caustics) {
            self.caustic(x0, radiance, out, stats);
        }
        if self.enabled(UnderwaterTerm::CausticsOnceMore) {
            let k = self.samples[0];
            let share = radiance / k as f32;
            for _ in 0..k {
                self.caustic_once_more(x0, share, rng, out, stats);
            }
        }
    }

    /// Splats the once-more vertex `s` of the connection `x0 → x1 → eye`
    /// for `term`: `value σs T(d1 + d2) cos θ0 W(ω1) · k/pdf`, with `k/pdf`
    /// the technique's weight and `cos θ0` the floor's cosine towards `x1`
    /// when `x0` is on the `floor` (else 1); nothing where `x1` is outside
    /// the water or the image, behind the floor, or a leg leaves the water.
    #[allow(clippy::too_many_arguments)]
    fn splat_once_more(
        &self,
        term: UnderwaterTerm,
        x0: Vec3,
        s: Sample<f32>,
        value: Vec3,
        floor: bool,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let (x1, eye) = (s.x1, self.camera.eye);
        if !(s.weight > 0.0 && self.in_water(x1)) {
            return;
        }
        let Some(p) = self.camera.project(x1) else {
            return;
        };
        let (a, b) = (x1 - x0, eye - x1);
        let (d1, d2) = (a.length(), b.length());
        let cos0 = if floor { a.z / d1 } else { 1.0 };
        if !(cos0 > 0.0) || !self.clear(x0, x1, stats) || !self.clear(x1, eye, stats) {
            return;
        }
        let value = value
            * self.water.sigma_s
            * self.water.transmittance(d1 + d2)
            * (cos0 * p.importance * s.weight);
        self.splat(term, p, value, out, stats);
    }

    /// Pushes a splat of `value` for `term` through `projection`.
    #[inline]
    fn splat(
        &self,
        term: UnderwaterTerm,
        p: Projection,
        value: Vec3,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        if value.is_finite() && value.max_element() > 0.0 {
            stats.splats[term as usize] += 1;
            out.push(Splat {
                pixel: p.pixel as u32,
                term,
                value,
            });
        }
    }
}

/// The render loop's view of the scene: one item is a chunk of
/// [`CHUNK`] light paths, their splats added in chunk order.
impl Integrator for UnderwaterWorld<'_> {
    type Stats = UnderwaterStats;
    type Item = Vec<Splat>;
    type Scratch = ();

    fn size(&self) -> (u32, u32) {
        (self.camera.width, self.camera.height)
    }

    fn terms(&self) -> &[Term] {
        &self.layers
    }

    fn items(&self) -> u64 {
        self.paths_per_pass().div_ceil(CHUNK)
    }

    fn per_pass(&self) -> f64 {
        self.paths_per_pass() as f64
    }

    fn item(
        &self,
        seed: u64,
        pass: u32,
        chunk: u64,
        stats: &mut UnderwaterStats,
        (): &mut (),
    ) -> Vec<Splat> {
        self.trace_chunk(seed, pass, chunk, stats)
    }

    fn add(&self, splats: &Vec<Splat>, sums: &mut Sums) {
        for s in splats {
            if let Some(layer) = s.term.term().index_in(&self.layers) {
                sums.add_at(s.pixel, layer, s.value);
            }
        }
    }
}

/// Three uniform numbers from `rng`.
#[inline]
fn uniform3(rng: &mut Rng) -> [f32; 3] {
    [rng.uniform(), rng.uniform(), rng.uniform()]
}
