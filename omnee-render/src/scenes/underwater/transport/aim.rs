//! Where light paths start: the floor point `x_f` each path aims at, drawn
//! through the image, past the eye, or from the defensive density that
//! covers the whole plane, and its density (docs/math.md §13.4).

use super::UnderwaterWorld;
use super::tail::TailedRect;
use crate::camera::Pinhole;
use crate::scenes::underwater::optics::refract;
use crate::scenes::underwater::sun::Sun;
use glam::{Vec2, Vec3};

/// How light paths choose their floor point `x_f` (13.4 of docs/math.md):
/// with probability `camera` through a uniform point of the image's cells
/// that see the floor ([`FloorCells`]), with
/// probability `eye` on a beam passing the eye at a distance uniform in
/// `[0, eye_radius]`, else from the defensive density ([`TailedRect`]),
/// which is positive on the whole plane. The shares change where paths go,
/// never the mean.
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
/// (by the defensive share alone, about 10³ times less dense than the
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
    /// `sample` at a point of a cell of weight `w_k` is
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

/// Where light paths start: the floor point `x_f` a path aims at, the
/// point a sun ray would reach on the floor through a flat surface. A path
/// starts at `x_s = x_f − offset` on the plane `z_top` above every crest;
/// the offset is the flat-water displacement of the sun's central
/// direction, so `x_s` and `x_f` have the same density. The sun lights the
/// whole plane; the core rectangle `R` (what the camera sees, carried down
/// to the floor, grown by the margin) only shapes the defensive density.
#[derive(Clone, Debug)]
pub struct LightRegion {
    /// The defensive density: uniform on the core `R`, heavy-tailed outside.
    pub tail: TailedRect,
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

impl UnderwaterWorld<'_> {
    /// Where paths start. The core rectangle `R`: the camera's rays on a
    /// 17 × 17 grid of the image, followed to the floor, the crests' plane
    /// or `max_distance`, with points along them carried down to the floor
    /// along the refracted central sun ray; their bounding box grown by
    /// `margin`. The defensive density's tail length `ell`.
    pub fn light_region(&self, margin: f32, ell: f32, aim: Aim) -> LightRegion {
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
                let t_end = self.water_segment(c.eye, d).min(self.max_distance);
                for k in 0..=8 {
                    let q = to_floor(c.eye + d * (t_end * k as f32 / 8.0));
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
            }
        }
        LightRegion {
            tail: TailedRect::new(lo - Vec2::splat(margin), hi + Vec2::splat(margin), ell),
            offset,
            z_top,
            beam: dt,
            aim,
            cells: FloorCells::new(&self.camera),
        }
    }

    /// The density in floor area of the floor point `x_f` a light path aims
    /// at, on the whole plane: `c q_cam(x_f) + e q_eye(x_f) + (1 − c − e) q_R(x_f)`,
    /// with `q_R` the defensive density ([`TailedRect::pdf`]),
    /// `q_cam = w_k cos θ0 / (d² · f 4wh · cos³θ)` the density of the floor
    /// point hit by an image point drawn from the [`FloorCells`] (cell `k`
    /// of weight `w_k`, `f = Σ w / 768`; `dω = cos θ0 dA/d²`,
    /// `dω = cos³θ dA_image`)
    /// and `q_eye = cos θt / (2π ρ D)` for the beam through `x_f` passing the
    /// eye at the distance `D < ρ` (uniform in `D` and in angle about the eye
    /// in the plane across the beam, whose area is `cos θt` times the floor's).
    ///
    /// `D` is computed in f64 from the f32 points, so `q_eye` holds down to
    /// the beams through the eye itself, where it is `+∞` (such a path
    /// carries no power). In f32, `|(e − x_f) × b|` loses everything below
    /// `|e − x_f| ε ≈ 5·10⁻⁷ m`: for a beam that close to the eye it rounded
    /// to 0, the term was dropped, and the path's power, `∝ D` where the
    /// term balances the beam's light `∝ 1/D`, came out 10⁷ times too large
    /// (docs/math.md §13.6).
    pub fn start_pdf(&self, xf: Vec3) -> f32 {
        let r = &self.region;
        let defensive = (1.0 - r.aim.camera - r.aim.eye) * r.tail.pdf(xf.truncate());
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
        let dist = v.as_dvec3().cross(r.beam.as_dvec3()).length();
        let radius = f64::from(r.aim.eye_radius);
        let eye = if r.aim.eye > 0.0 && dist < radius {
            let q_eye = -f64::from(r.beam.z) / (std::f64::consts::TAU * radius * dist);
            (f64::from(r.aim.eye) * q_eye) as f32
        } else {
            0.0
        };
        r.aim.camera * cam + eye + defensive
    }

    /// The floor point `x_f` a light path aims at (see [`Aim`]); `None` for
    /// an image point whose ray looks up (an event of density 0 on the floor).
    pub(super) fn start(&self, u: [f32; 3]) -> Option<Vec3> {
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
            // The rest of `u[0]`'s interval picks the defensive density's piece.
            let rest = 1.0 - r.aim.camera - r.aim.eye;
            let v = ((u[0] - r.aim.camera - r.aim.eye) / rest).clamp(0.0, 1.0);
            r.tail.sample([v, u[1], u[2]]).extend(self.floor.z)
        };
        // A ray grazing the floor meets it beyond f32's range: no start.
        let xf = xf.truncate().extend(self.floor.z);
        xf.is_finite().then_some(xf)
    }
}
