//! Light tracing under water: sun rays through the surface to the floor, and
//! the three terms that connect them to the camera (docs/math.md §13):
//!
//! - `caustics`: the floor point `x0` straight to the eye;
//! - `caustics-once-more`: `x0 → x1 → eye` with `x1` placed by the once-more
//!   technique, the blur with depth;
//! - `shafts`: a point on the refracted sun ray in the water straight to the
//!   eye, the god rays.
//!
//! Each light path is one sample of the sun's flux through a region of the
//! surface; every term splats its contribution to the pixel its last vertex
//! projects to, with the camera's importance ([`super::camera`]).

use super::camera::{Pinhole, Projection};
use super::floor::Floor;
use super::optics::{fresnel_transmittance, refract};
use super::sun::Sun;
use super::surface::Surface;
use super::water::{EquiangularLine, Water};
use crate::rng::Rng;
pub use crate::term::Term;
use glam::{Vec2, Vec3};
use omnee_core::lobe::{LobeMis, PhaseLobe, WithLobe};
use omnee_core::mis::OmneeMis;
use omnee_core::phase::{Deflection, Phase, PhaseFunction};
use omnee_core::sampling::{Connection, Omnee, Sample, Technique};

/// The scene's terms in the order of their layers.
pub const TERMS: [Term; 4] = crate::term::UNDERWATER;

/// The layer of `term`, one of [`TERMS`].
#[inline]
pub fn layer(term: Term) -> usize {
    term.index_in(&TERMS).expect("an underwater term")
}

/// How the shafts term places its vertex on the refracted sun ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaftSampling {
    /// Free-flight distance from the channel mixture of σt.
    FreeFlight,
    /// Equiangular distance about the eye.
    Equiangular,
    /// One of the two with probability ½ each, weighted by the mixture
    /// density (one-sample MIS with the balance heuristic).
    Mis,
}

impl ShaftSampling {
    /// The names, in the order of the variants.
    pub const NAMES: [&'static str; 3] = ["free-flight", "equiangular", "mis"];

    /// The sampling called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "free-flight" => Some(Self::FreeFlight),
            "equiangular" => Some(Self::Equiangular),
            "mis" => Some(Self::Mis),
            _ => None,
        }
    }
}

/// The techniques for `shafts-once-more`'s vertex `x1`: its `x0` lies on a
/// refracted sun ray in the water, so the light leaving `x0` follows the
/// phase function's lobe about the ray, `p0(ω_in · ω01)`, as well as `p1`
/// at `x1` (docs/math.md §12, §13.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LobeTech {
    /// OMNEE alone, the lobe's value in its weight ([`WithLobe`]).
    Omnee,
    /// The core's recommended combination ([`LobeMis::recommended`]):
    /// OMNEE and the lobe technique (a direction from `p0`, then a
    /// distance along it), one-sample balance heuristic, the lobe technique
    /// drawn where the axis `x0 → eye` lies in the lobe's tail.
    LobeMis,
}

impl LobeTech {
    /// The names, in the order of the variants.
    pub const NAMES: [&'static str; 2] = ["omnee", "lobe-mis"];

    /// The technique's name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The technique called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "omnee" => Some(Self::Omnee),
            "lobe-mis" => Some(Self::LobeMis),
            _ => None,
        }
    }
}

/// One contribution to the image: a pixel, a term and its RGB value
/// (radiance times the number of paths, W/(m²·sr)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Pixel index `y · width + x` in the full image.
    pub pixel: u32,
    /// The term.
    pub term: Term,
    /// The value.
    pub value: Vec3,
}

/// Counters of the work done and skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Light paths started.
    pub paths: u64,
    /// Paths whose start point fell outside the lit region (no work).
    pub outside_region: u64,
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

impl Stats {
    /// Adds another run's counters.
    pub fn add(&mut self, o: &Stats) {
        self.paths += o.paths;
        self.outside_region += o.outside_region;
        self.lost_at_surface += o.lost_at_surface;
        self.floor_hits += o.floor_hits;
        for (a, b) in self.splats.iter_mut().zip(o.splats) {
            *a += b;
        }
        self.no_vertex += o.no_vertex;
        self.surface_tests += o.surface_tests;
    }
}

/// How light paths choose their floor point `x_f` (13.4 of docs/math.md):
/// with probability `camera` through a uniform point of the image's cells
/// that see the floor ([`FloorCells`]), with
/// probability `eye` on a beam passing the eye at a distance uniform in
/// `[0, eye_radius]`, else uniformly on the region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aim {
    /// Share of paths aimed through the image.
    pub camera: f32,
    /// Share of paths aimed past the eye.
    pub eye: f32,
    /// The largest distance from the eye of those beams (m).
    pub eye_radius: f32,
}

/// The cells of a 32 × 24 grid over the image, extended by a margin of
/// [`FloorCells::MARGIN`] cells on every side, through which paths aimed
/// through the image draw their floor point: cell `k` with probability
/// `w_k / Σ w`, then a uniform point in it.
///
/// A cell has weight 0 when its four corner rays look up (the height of a
/// ray direction is linear on the image plane, so such a cell has no ray
/// that looks down, and no path is wasted on the water above the horizon);
/// else 1 inside the image and `1/(1 + k)²` in the margin's `k`-th ring.
/// The margin is what keeps the light paths' weights bounded under waves:
/// a refracted ray lands on the floor up to half a metre from the point
/// `x_f` it was aimed at, so without it a path aimed just outside the image
/// (by the uniform share alone, about 10³ times less dense than the
/// image's share there) lands in it and carries 10³ times the power of its
/// neighbours: the white speckle along the image's edges (docs/math.md §13.4).
#[derive(Clone, Debug)]
pub struct FloorCells {
    /// Per cell of the extended grid, row-major, its weight `w_k`.
    weights: Vec<f32>,
    /// The running sums of the weights.
    cdf: Vec<f32>,
    width: f32,
    height: f32,
}

impl FloorCells {
    const COLUMNS: u32 = 32;
    const ROWS: u32 = 24;
    /// The margin's width in cells.
    pub const MARGIN: u32 = 6;
    const GRID_COLUMNS: u32 = Self::COLUMNS + 2 * Self::MARGIN;
    const GRID_ROWS: u32 = Self::ROWS + 2 * Self::MARGIN;

    /// The cells of `camera`'s extended image that see down.
    pub fn new(camera: &Pinhole) -> Self {
        let (w, h) = (camera.width as f32, camera.height as f32);
        let m = Self::MARGIN as i32;
        // The image point of the grid's corner (i, j), in pixels.
        let point = |i: i32, j: i32| {
            (
                w * (i - m) as f32 / Self::COLUMNS as f32,
                h * (j - m) as f32 / Self::ROWS as f32,
            )
        };
        let down = |i: i32, j: i32| {
            let (x, y) = point(i, j);
            camera.ray(x, y).z < 0.0
        };
        let ring = |k: i32, n: u32| (m - k).max(k - (n as i32 - m - 1)).max(0);
        let mut weights = Vec::new();
        let mut cdf = Vec::new();
        let mut total = 0.0;
        for row in 0..Self::GRID_ROWS as i32 {
            for column in 0..Self::GRID_COLUMNS as i32 {
                let sees = down(column, row)
                    || down(column + 1, row)
                    || down(column, row + 1)
                    || down(column + 1, row + 1);
                let k = ring(column, Self::GRID_COLUMNS).max(ring(row, Self::GRID_ROWS)) as f32;
                let weight = if sees {
                    1.0 / ((1.0 + k) * (1.0 + k))
                } else {
                    0.0
                };
                total += weight;
                weights.push(weight);
                cdf.push(total);
            }
        }
        Self {
            weights,
            cdf,
            width: w,
            height: h,
        }
    }

    /// `Σ w` over the image's cell count: the image-plane density of
    /// [`Self::sample`] at a point of a cell of weight `w_k` is
    /// `w_k / (fraction · A_img)`.
    pub fn fraction(&self) -> f32 {
        self.cdf.last().copied().unwrap_or(0.0) / (Self::COLUMNS * Self::ROWS) as f32
    }

    /// An image point (pixels, possibly outside the image): `u0` picks the
    /// cell by its weight and the column inside it, `u1` the row.
    fn sample(&self, u: [f32; 2]) -> Option<(f32, f32)> {
        let total = *self.cdf.last()?;
        if !(total > 0.0) {
            return None;
        }
        let target = u[0] * total;
        let k = self
            .cdf
            .partition_point(|&c| c <= target)
            .min(self.cdf.len() - 1);
        let below = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        let fx = ((target - below) / self.weights[k]).clamp(0.0, 1.0);
        let m = Self::MARGIN as f32;
        let column = (k as u32 % Self::GRID_COLUMNS) as f32 - m;
        let row = (k as u32 / Self::GRID_COLUMNS) as f32 - m;
        Some((
            (column + fx) / Self::COLUMNS as f32 * self.width,
            (row + u[1]) / Self::ROWS as f32 * self.height,
        ))
    }

    /// The weight of the cell holding the image point `(x, y)` (pixels),
    /// 0 outside the extended grid.
    fn weight(&self, x: f32, y: f32) -> f32 {
        let m = Self::MARGIN as f32;
        let column = (x / self.width * Self::COLUMNS as f32).floor() + m;
        let row = (y / self.height * Self::ROWS as f32).floor() + m;
        let inside = column >= 0.0
            && row >= 0.0
            && column < Self::GRID_COLUMNS as f32
            && row < Self::GRID_ROWS as f32;
        if !inside {
            return 0.0;
        }
        self.weights[row as usize * Self::GRID_COLUMNS as usize + column as usize]
    }
}

/// The region of the floor whose flat-water sun rays light the light paths:
/// `x_f ∈ [lo, hi]`, the point a sun ray would reach on the floor through a
/// flat surface. A path starts at `x_s = x_f − offset` on the plane
/// `z_top` above every crest; the offset is the flat-water displacement of
/// the sun's central direction, so `x_s` and `x_f` have the same density.
#[derive(Clone, Debug)]
pub struct LightRegion {
    /// Lower corner of the rectangle on the floor.
    pub lo: Vec2,
    /// Upper corner.
    pub hi: Vec2,
    /// `x_f − x_s` for the sun's central direction.
    pub offset: Vec2,
    /// The start plane's height.
    pub z_top: f32,
    /// The refracted central sun direction through a flat surface.
    pub beam: Vec3,
    /// How `x_f` is drawn.
    pub aim: Aim,
    /// The image cells that see the floor, for the paths aimed through the image.
    pub cells: FloorCells,
}

impl LightRegion {
    /// The rectangle's area.
    pub fn area(&self) -> f32 {
        let e = self.hi - self.lo;
        e.x * e.y
    }

    /// Whether `p` is inside the rectangle.
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.lo.x && p.y >= self.lo.y && p.x <= self.hi.x && p.y <= self.hi.y
    }
}

/// The techniques for the once-more vertex `x1` of `caustics-once-more`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnceMoreTech {
    /// OMNEE: the deflection from the phase function, then the circumcircle arc.
    Omnee,
    /// Equiangular from a camera ray through a uniform image point.
    Equiangular,
    /// OMNEE's vertex, and with probability `rate` a camera-ray equiangular
    /// vertex kept behind θ ≥ θmin, balance heuristic there ([`OmneeMis`];
    /// the scene's defaults are [`OmneeMis::recommended`]'s 0.05 and 3π/4).
    Mis,
}

impl OnceMoreTech {
    /// The technique's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Omnee => "omnee",
            Self::Equiangular => "equiangular",
            Self::Mis => "mis",
        }
    }
}

/// How the once-more term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct OnceMore {
    /// The technique for `x1`.
    pub tech: OnceMoreTech,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
    /// The mis companion's rate `c ∈ [0, 1]`.
    pub mis_rate: f32,
    /// The mis companion's cone edge θmin.
    pub mis_theta_min: f32,
}

/// The underwater scene in f32, ready to trace.
pub struct World<'a> {
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
    /// Farthest distance from the eye that the camera-ray techniques sample (m).
    pub max_distance: f32,
    /// Which terms to evaluate, in layer order.
    pub terms: [bool; 4],
    /// The once-more technique.
    pub once_more: OnceMore,
    /// The shafts' sampling.
    pub shafts: ShaftSampling,
    /// The technique for `shafts-once-more`'s vertex `x1`.
    pub lobe: LobeTech,
    /// Once-more draws per floor point and shaft vertices per refracted ray:
    /// `[once-more, shafts]`, each contribution divided by its count.
    pub samples: [u32; 2],
}

/// The deflection of the central sun ray after a flat surface, and the
/// flat-water horizontal displacement from `z_top` down to `z_floor`.
pub fn flat_water_offset(
    sun: &Sun,
    ior: f32,
    z_surface: f32,
    z_top: f32,
    z_floor: f32,
) -> (Vec3, Vec2) {
    let d = -sun.direction;
    let (dt, _) = refract(d, Vec3::Z, 1.0 / ior).unwrap_or((Vec3::NEG_Z, 1.0));
    let air = d.truncate() * ((z_top - z_surface) / -d.z);
    let water = dt.truncate() * ((z_surface - z_floor) / -dt.z);
    (dt, air + water)
}

impl World<'_> {
    /// The region of the floor whose flat-water sun rays cross what the
    /// camera sees out to `max_distance`: the camera's rays on a 17 × 17
    /// grid of the image, followed to the floor, the troughs' plane or
    /// `max_distance`, with points along them carried down to the floor along
    /// the refracted central sun ray; their bounding box grown by `margin`.
    pub fn light_region(&self, margin: f32, aim: Aim) -> LightRegion {
        let z_top = self.surface.crest();
        let (dt, offset) =
            flat_water_offset(&self.sun, self.ior, self.surface.z, z_top, self.floor.z);
        let to_floor = |p: Vec3| p.truncate() + dt.truncate() * ((p.z - self.floor.z) / -dt.z);
        let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
        let n = 16;
        for i in 0..=n {
            for j in 0..=n {
                let c = &self.camera;
                let d = c.ray(
                    c.width as f32 * i as f32 / n as f32,
                    c.height as f32 * j as f32 / n as f32,
                );
                let t_end = self.water_segment(c.eye, d);
                for k in 0..=8 {
                    let q = to_floor(c.eye + d * (t_end * k as f32 / 8.0));
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
            }
        }
        LightRegion {
            lo: lo - Vec2::splat(margin),
            hi: hi + Vec2::splat(margin),
            offset,
            z_top,
            beam: dt,
            aim,
            cells: FloorCells::new(&self.camera),
        }
    }

    /// The length of the ray `o + t d` from the eye through the water band
    /// below the crests and above the floor, capped at `max_distance`.
    fn water_segment(&self, o: Vec3, d: Vec3) -> f32 {
        let t = if d.z < 0.0 {
            (self.floor.z - o.z) / d.z
        } else if d.z > 0.0 {
            (self.surface.crest() - o.z) / d.z
        } else {
            f32::INFINITY
        };
        t.min(self.max_distance)
    }

    /// Whether `x` is in the water: above the floor, below the surface.
    fn in_water(&self, x: Vec3) -> bool {
        x.z > self.floor.z
            && (x.z <= self.surface.trough() || x.z < self.surface.height(x.truncate()))
    }

    /// Whether the segment `a → b` between points in the water stays in it
    /// (only segments reaching into the wave band are marched).
    fn clear(&self, a: Vec3, b: Vec3, stats: &mut Stats) -> bool {
        let trough = self.surface.trough();
        if a.z <= trough && b.z <= trough {
            return true;
        }
        stats.surface_tests += 1;
        self.surface.segment_under(a, b)
    }

    /// The density in floor area of the floor point `x_f` a light path aims at: on the
    /// rectangle `R`, `c q_cam(x_f) + e q_eye(x_f) + (1 − c − e)/|R|`, with
    /// `q_cam = w_k cos θ0 / (d² · f 4wh · cos³θ)` the density of the floor
    /// point hit by an image point drawn from the [`FloorCells`] (cell `k`
    /// of weight `w_k`, `f = Σ w / 768`; `dω = cos θ0 dA/d²`,
    /// `dω = cos³θ dA_image`)
    /// and `q_eye = cos θt / (2π ρ D)` for the beam through `x_f` passing the
    /// eye at the distance `D < ρ` (uniform in `D` and in angle about the eye
    /// in the plane across the beam, whose area is `cos θt` times the floor's).
    pub fn start_pdf(&self, xf: Vec3) -> f32 {
        let r = &self.region;
        if !r.contains(xf.truncate()) {
            return 0.0;
        }
        let uniform = (1.0 - r.aim.camera - r.aim.eye) / r.area();
        let c = &self.camera;
        let v = c.eye - xf;
        // The image points that see the floor cover `fraction · 4wh` of the plane.
        let cam = match c.image_point(-v) {
            Some((x, y, cos)) if r.cells.weight(x, y) > 0.0 => {
                let d2 = v.length_squared();
                let cos0 = v.z / d2.sqrt();
                r.cells.weight(x, y) * cos0
                    / (d2 * c.image_area() * r.cells.fraction() * cos * cos * cos)
            }
            _ => 0.0,
        };
        let dist = v.cross(r.beam).length();
        let eye = if dist < r.aim.eye_radius && dist > 0.0 {
            -r.beam.z / (std::f32::consts::TAU * r.aim.eye_radius * dist)
        } else {
            0.0
        };
        r.aim.camera * cam + r.aim.eye * eye + uniform
    }

    /// The floor point `x_f` a light path aims at (see [`Aim`]); `None`
    /// outside the rectangle (or for an image point above the horizon).
    fn start(&self, u: [f32; 3]) -> Option<Vec3> {
        let r = &self.region;
        let c = &self.camera;
        let xf = if u[0] < r.aim.camera {
            let (x, y) = r.cells.sample([u[1], u[2]])?;
            let d = c.ray(x, y);
            if !(d.z < 0.0) {
                return None;
            }
            c.eye + d * ((self.floor.z - c.eye.z) / d.z)
        } else if u[0] < r.aim.camera + r.aim.eye {
            // A point of the disc across the beam about the eye, carried
            // down the beam to the floor.
            let (e1, e2) = r.beam.any_orthonormal_pair();
            let (sin, cos) = (std::f32::consts::TAU * u[2]).sin_cos();
            let q = c.eye + (e1 * cos + e2 * sin) * (u[1] * r.aim.eye_radius);
            q + r.beam * ((self.floor.z - q.z) / r.beam.z)
        } else {
            let e = r.hi - r.lo;
            Vec3::new(r.lo.x + u[1] * e.x, r.lo.y + u[2] * e.y, self.floor.z)
        };
        let xf = xf.truncate().extend(self.floor.z);
        r.contains(xf.truncate()).then_some(xf)
    }

    /// Whether `term` is evaluated.
    #[inline]
    pub fn enabled(&self, term: Term) -> bool {
        self.terms[layer(term)]
    }

    /// Traces one light path and appends its splats.
    pub fn trace(&self, rng: &mut Rng, out: &mut Vec<Splat>, stats: &mut Stats) {
        stats.paths += 1;
        let Some(xf) = self.start(uniform3(rng)) else {
            stats.outside_region += 1;
            return;
        };
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
        if self.enabled(Term::Shafts) {
            self.shafts(y, dt, t_floor, power, rng, out, stats);
        }
        if self.enabled(Term::ShaftsOnceMore) {
            self.shafts_once_more(y, dt, t_floor, power, rng, out, stats);
        }
        // Flux arriving at x0 per channel, times the floor's BRDF: the
        // radiance leaving x0 in any direction, per unit area density.
        let radiance = self.water.transmittance(t_floor)
            * self.floor.albedo(x0.truncate())
            * (power * std::f32::consts::FRAC_1_PI);
        if self.enabled(Term::Caustics) {
            self.caustic(x0, radiance, out, stats);
        }
        if self.enabled(Term::CausticsOnceMore) {
            let k = self.samples[0];
            let share = radiance / k as f32;
            for _ in 0..k {
                self.caustic_once_more(x0, share, rng, out, stats);
            }
        }
    }

    /// Pushes a splat of `value` for `term` through `projection`.
    #[inline]
    fn splat(
        &self,
        term: Term,
        p: Projection,
        value: Vec3,
        out: &mut Vec<Splat>,
        stats: &mut Stats,
    ) {
        if value.is_finite() && value.max_element() > 0.0 {
            stats.splats[layer(term)] += 1;
            out.push(Splat {
                pixel: p.pixel as u32,
                term,
                value,
            });
        }
    }

    /// `caustics`: `L(x0) cos θ0 T(x0, eye) W(ω) / d²`.
    fn caustic(&self, x0: Vec3, radiance: Vec3, out: &mut Vec<Splat>, stats: &mut Stats) {
        let Some(p) = self.camera.project(x0) else {
            return;
        };
        let v = self.camera.eye - x0;
        let d2 = v.length_squared();
        let d = d2.sqrt();
        let cos0 = v.z / d;
        if !(cos0 > 0.0) {
            return;
        }
        let value = radiance * self.water.transmittance(d) * (cos0 * p.importance / d2);
        self.splat(Term::Caustics, p, value, out, stats);
    }

    /// `caustics-once-more` from the floor point `x0` leaving `radiance`
    /// (the same in every direction): for each vertex `x1` of the technique's
    /// draw, `L(x0) cos θ0 σs T(x0, x1) T(x1, eye) W(ω1) · k/pdf`, with
    /// `k/pdf` the technique's weight (`k = p(θ)/(d1² d2²)`).
    pub fn caustic_once_more(
        &self,
        x0: Vec3,
        radiance: Vec3,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut Stats,
    ) {
        let eye = self.camera.eye;
        let Ok(connection) = Connection::new(x0, eye, self.once_more.theta_max) else {
            return;
        };
        let vertices = self.draw(connection, rng);
        if vertices[0].is_none() {
            stats.no_vertex += 1;
        }
        for s in vertices.into_iter().flatten() {
            let x1 = s.x1;
            if !(s.weight > 0.0 && self.in_water(x1)) {
                continue;
            }
            let Some(p) = self.camera.project(x1) else {
                continue;
            };
            let (a, b) = (x1 - x0, eye - x1);
            let (d1, d2) = (a.length(), b.length());
            let cos0 = a.z / d1;
            if !(cos0 > 0.0) || !self.clear(x0, x1, stats) || !self.clear(x1, eye, stats) {
                continue;
            }
            let value = radiance
                * self.water.sigma_s
                * self.water.transmittance(d1 + d2)
                * (cos0 * p.importance * s.weight);
            self.splat(Term::CausticsOnceMore, p, value, out, stats);
        }
    }

    /// The once-more technique's vertices for `connection`.
    fn draw(&self, connection: Connection<f32>, rng: &mut Rng) -> [Option<Sample<f32>>; 2] {
        let omnee = Omnee::new(connection, &self.phase);
        let camera_rays = CameraEquiangular {
            world: self,
            connection,
        };
        match self.once_more.tech {
            OnceMoreTech::Omnee => [omnee.sample(uniform3(rng)), None],
            OnceMoreTech::Equiangular => [camera_rays.sample(uniform3(rng)), None],
            OnceMoreTech::Mis => {
                let [a, b, c] = uniform3(rng);
                let [d, e, f] = uniform3(rng);
                let theta_min = Deflection::from_theta(self.once_more.mis_theta_min);
                match OmneeMis::new(omnee, &camera_rays, self.once_more.mis_rate, theta_min) {
                    Ok(mis) => mis.sample([a, b, c, d, e, f]),
                    // The scene parser keeps the rate in [0, 1].
                    Err(_) => [omnee.sample([a, b, c]), None],
                }
            }
        }
    }

    /// `shafts` for the refracted ray `y + t d_t`, `t ∈ [0, len]`, carrying
    /// `power`: its part `[ta, tb]` in the view frustum (the integrand is 0
    /// elsewhere) gets `k` vertices, stratified in the sampler's uniform
    /// number, `k = ⌈n (θb − θa)/fov⌉ ∈ [1, 16n]` with `θb − θa` the angle
    /// the part subtends at the eye and `n` the scene's `shaft_samples`:
    /// about one vertex per `fov/n` of its image, so a ray passing close to
    /// the eye, whose image crosses the picture with a weight `∝ 1/D`, is
    /// drawn as a line of many small splats rather than a few bright dots.
    /// `k` depends on the ray only, and the strata's mean is unbiased.
    #[allow(clippy::too_many_arguments)]
    fn shafts(
        &self,
        y: Vec3,
        dt: Vec3,
        len: f32,
        power: f32,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut Stats,
    ) {
        let Some((ta, tb)) = self.camera.clip(y, dt, 0.0, len) else {
            return;
        };
        let line = EquiangularLine::new(y + dt * ta, dt, tb - ta, self.camera.eye);
        let n = self.samples[1];
        let k = match line {
            Some(l) => {
                let k = (n as f32 * l.angle() / self.camera.fov()).ceil();
                (k as u32).clamp(1, 16 * n)
            }
            None => n,
        };
        let segment = Segment {
            y,
            dt,
            ta,
            tb,
            line,
        };
        for i in 0..k {
            let [u0, u1, _] = uniform3(rng);
            let u0 = (i as f32 + u0) / k as f32;
            self.shaft(&segment, [u0, u1], power / k as f32, out, stats);
        }
    }

    /// One `shafts` vertex `x = y + t d_t` on `segment`:
    /// `Φ T(y, x) σs p(θ) T(x, eye) W(ω) / (d² pdf(t))`, `t` drawn by the
    /// scene's [`ShaftSampling`] on `[ta, tb]`.
    fn shaft(
        &self,
        segment: &Segment,
        u: [f32; 2],
        power: f32,
        out: &mut Vec<Splat>,
        stats: &mut Stats,
    ) {
        let eye = self.camera.eye;
        let Segment {
            y,
            dt,
            ta,
            tb,
            line,
        } = *segment;
        let [u0, u1] = u;
        // Free flight from `ta`: the truncated exponential on `[ta, tb]`.
        let free = |t: f32| self.water.free_flight_pdf(tb - ta, t - ta);
        let flight = |u: [f32; 2]| ta + self.water.free_flight(tb - ta, u);
        let along = |l: EquiangularLine, u: f32| ta + l.sample(u);
        let (t, pdf) = match (self.shafts, line) {
            (ShaftSampling::Equiangular, Some(l)) => {
                let t = along(l, u0);
                (t, l.pdf(t - ta))
            }
            (ShaftSampling::Mis, Some(l)) => {
                let t = if u0 < 0.5 {
                    along(l, 2.0 * u0)
                } else {
                    flight([2.0 * u0 - 1.0, u1])
                };
                (t, 0.5 * (l.pdf(t - ta) + free(t)))
            }
            // Free flight, or the eye on the ray's line (no equiangular density).
            _ => {
                let t = flight([u0, u1]);
                (t, free(t))
            }
        };
        let x = y + dt * t;
        let Some(p) = self.camera.project(x) else {
            return;
        };
        let v = eye - x;
        let d2 = v.length_squared();
        let d = d2.sqrt();
        if !(d > 0.0 && pdf > 0.0 && self.clear(x, eye, stats)) {
            return;
        }
        let phase = self.phase.eval(Deflection::between_segments(dt, 1.0, v, d));
        let value = self.water.transmittance(t + d)
            * self.water.sigma_s
            * (power * phase * p.importance / (d2 * pdf));
        self.splat(Term::Shafts, p, value, out, stats);
    }

    /// `shafts-once-more` for the refracted ray `y + t d_t`, `t ∈ [0, len]`,
    /// carrying `power`: `m` vertices `x0 = y + t d_t` (`m` the once-more
    /// draws per floor point), `t` by free flight (the channel mixture, its
    /// distance stratified), each scattering
    /// `Φ T(t) σs / (m pdf(t))` towards [`Self::shaft_once_more`]. The
    /// whole ray counts: `x1`, not `x0`, must be in view.
    #[allow(clippy::too_many_arguments)]
    fn shafts_once_more(
        &self,
        y: Vec3,
        dt: Vec3,
        len: f32,
        power: f32,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut Stats,
    ) {
        let m = self.samples[0];
        for i in 0..m {
            let [u0, u1, _] = uniform3(rng);
            let t = self
                .water
                .free_flight(len, [u0, (i as f32 + u1) / m as f32]);
            let pdf = self.water.free_flight_pdf(len, t);
            if !(pdf > 0.0) {
                continue;
            }
            let flux =
                self.water.transmittance(t) * self.water.sigma_s * (power / (m as f32 * pdf));
            self.shaft_once_more(y + dt * t, dt, flux, rng, out, stats);
        }
    }

    /// `shafts-once-more` from the vertex `x0` in the water, where the sun's
    /// light arrives along `incoming` with `flux` per channel (σs at `x0`
    /// included): for the vertex `x1` of the scene's [`LobeTech`],
    /// `flux σs T(d1 + d2) W(ω1) · k/pdf` with
    /// `k = p0(ω_in · ω01) p1(θ) / (d1² d2²)` (docs/math.md §12.1, §13.6).
    pub fn shaft_once_more(
        &self,
        x0: Vec3,
        incoming: Vec3,
        flux: Vec3,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut Stats,
    ) {
        let eye = self.camera.eye;
        let Ok(connection) = Connection::new(x0, eye, self.once_more.theta_max) else {
            return;
        };
        let Ok(lobe) = PhaseLobe::new(&self.phase, incoming) else {
            return;
        };
        let u = uniform3(rng);
        let sample = match self.lobe {
            LobeTech::Omnee => {
                WithLobe::new(Omnee::new(connection, &self.phase), lobe, x0).sample(u)
            }
            LobeTech::LobeMis => LobeMis::recommended(connection, lobe, &self.phase).sample(u),
        };
        let Some(s) = sample else {
            stats.no_vertex += 1;
            return;
        };
        let x1 = s.x1;
        if !(s.weight > 0.0 && self.in_water(x1)) {
            return;
        }
        let Some(p) = self.camera.project(x1) else {
            return;
        };
        if !self.clear(x0, x1, stats) || !self.clear(x1, eye, stats) {
            return;
        }
        let d = (x1 - x0).length() + (eye - x1).length();
        let value =
            flux * self.water.sigma_s * self.water.transmittance(d) * (p.importance * s.weight);
        self.splat(Term::ShaftsOnceMore, p, value, out, stats);
    }
}

/// The part of a refracted sun ray `y + t d_t` the camera sees,
/// `t ∈ [ta, tb]`, and the equiangular sampler about the eye on it (`t`
/// counted from `ta`; `None` when the eye is on the ray's line).
#[derive(Clone, Copy, Debug)]
struct Segment {
    y: Vec3,
    dt: Vec3,
    ta: f32,
    tb: f32,
    line: Option<EquiangularLine>,
}

/// Three uniform numbers from `rng`.
#[inline]
fn uniform3(rng: &mut Rng) -> [f32; 3] {
    [rng.uniform(), rng.uniform(), rng.uniform()]
}

/// Equiangular sampling of `x1` from a camera ray through a uniform point
/// of the image, towards `x0`: the ray direction with density
/// `p_ω = 1/(4wh cos³θ)` ([`Pinhole::ray_pdf`]), the distance equiangular
/// about `x0` on the ray's water segment; in the volume measure
/// `pdf(x1) = p_ω · pdf(t) / t²`, and the weight `k/pdf = p(θ)/(d1² p_ω pdf(t))`.
struct CameraEquiangular<'w, 'a> {
    world: &'w World<'a>,
    connection: Connection<f32>,
}

impl CameraEquiangular<'_, '_> {
    fn line(&self, d: Vec3) -> Option<EquiangularLine> {
        let eye = self.world.camera.eye;
        let len = self.world.water_segment(eye, d);
        EquiangularLine::new(eye, d, len, self.connection.axis.x0)
    }
}

impl Technique<f32> for CameraEquiangular<'_, '_> {
    fn sample(&self, u: [f32; 3]) -> Option<Sample<f32>> {
        let c = &self.world.camera;
        let d = c.ray(u[0] * c.width as f32, u[1] * c.height as f32);
        let line = self.line(d)?;
        let t = line.sample(u[2]);
        if !(t > 0.0) {
            return None;
        }
        let x1 = c.eye + d * t;
        let pdf_w = c.ray_pdf(d);
        let pdf_t = line.pdf(t);
        let (deflection, d1) = self.connection.deflection_along(d, t)?;
        let weight = if deflection.theta < self.connection.theta_max {
            self.world.phase.eval(deflection) / (d1 * d1 * pdf_w * pdf_t)
        } else {
            0.0
        };
        Some(Sample {
            x1,
            pdf: pdf_w * pdf_t / (t * t),
            weight: if weight.is_finite() { weight } else { 0.0 },
        })
    }

    fn pdf(&self, x1: Vec3) -> f32 {
        let c = &self.world.camera;
        let v = x1 - c.eye;
        let t = v.length();
        if c.project(x1).is_none() || !(t > 0.0) {
            return 0.0;
        }
        let d = v / t;
        match self.line(d) {
            Some(line) if t <= self.world.water_segment(c.eye, d) => {
                c.ray_pdf(d) * line.pdf(t) / (t * t)
            }
            _ => 0.0,
        }
    }

    fn invert(&self, x1: Vec3) -> Option<[f32; 3]> {
        let c = &self.world.camera;
        let v = x1 - c.eye;
        let (x, y, _) = c.image_point(v)?;
        let t = v.length();
        let line = self.line(v / t)?;
        Some([x / c.width as f32, y / c.height as f32, line.invert(t)])
    }
}
