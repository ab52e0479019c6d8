//! The pinhole camera in f32, for both scenes: a ray through every image
//! point (the slab scene's camera rays, the underwater scene's camera-ray
//! techniques), and the pixel measurement, defined once, with the
//! importance a light-traced contribution carries, derived from it
//! (docs/math.md §13.5).
//!
//! The image plane is at unit distance along the optical axis; it spans
//! `[−w, w] × [−h, h]` with `h = tan(fov/2)` and `w = h · W/H`, so a pixel
//! covers the plane area `A_pix = (2w/W)(2h/H)`. The measurement of pixel
//! `j` is the mean radiance arriving at the eye through its part of the
//! plane,
//!
//! `I_j = (1/A_pix) ∫_{pixel j} L(eye ← ω(s)) dA(s)`,
//!
//! which is what a gathering renderer estimates with camera rays through
//! uniform points of the pixel. A plane point at angle θ from the axis is
//! at distance `1/cos θ` and seen at slant `cos θ`, so `dω = cos³θ dA` and
//!
//! `I_j = ∫ W_j(ω) L(ω) dω`, `W_j(ω) = 1 / (A_pix cos³θ)` inside the pixel.
//!
//! A contribution leaving a point `x` towards the eye at distance `d`, with
//! `dω = cos θx dA(x) / d²` for a surface and `dω = dV / d²` per unit length
//! of a beam for the volume, is splatted to the pixel `ω` falls into with
//! the factor `W_j(ω) / d²` (times the surface's cosine).

use glam::Vec3;

/// A pinhole camera in f32.
#[derive(Clone, Copy, Debug)]
pub struct Pinhole {
    /// The eye.
    pub eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// `tan(fov/2)`: half the plane's height.
    half_height: f32,
    /// Half the plane's width.
    half_width: f32,
    /// Image size in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `A_pix`, a pixel's area on the unit-distance plane.
    pixel_area: f32,
}

/// Where a direction from the eye lands on the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// The pixel's index `y · width + x`.
    pub pixel: usize,
    /// `W_j(ω) = 1 / (A_pix cos³θ)` (1/sr).
    pub importance: f32,
}

impl Pinhole {
    /// A camera at `eye` looking at `look_at` with `up` (not parallel to the
    /// view) and a vertical field of view `fov` (radians, (0, π)).
    pub fn looking_at(
        eye: Vec3,
        look_at: Vec3,
        up: Vec3,
        fov: f32,
        width: u32,
        height: u32,
    ) -> Self {
        Self::with_tan_half(eye, look_at, up, (0.5 * fov).tan(), width, height)
    }

    /// The camera with `tan(fov/2) = tan_half`.
    pub fn with_tan_half(
        eye: Vec3,
        look_at: Vec3,
        up: Vec3,
        tan_half: f32,
        width: u32,
        height: u32,
    ) -> Self {
        let forward = (look_at - eye).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        let half_width = tan_half * (width as f32 / height as f32);
        Self {
            eye,
            forward,
            right,
            up,
            half_height: tan_half,
            half_width,
            width,
            height,
            pixel_area: (2.0 * half_width / width as f32) * (2.0 * tan_half / height as f32),
        }
    }

    /// The vertical field of view (radians).
    pub fn fov(&self) -> f32 {
        2.0 * self.half_height.atan()
    }

    /// `A_pix`.
    pub fn pixel_area(&self) -> f32 {
        self.pixel_area
    }

    /// The plane's area `4 w h`.
    pub fn image_area(&self) -> f32 {
        4.0 * self.half_width * self.half_height
    }

    /// The unit direction through the image point `(x, y)` in pixels
    /// (`(0, 0)` the top-left corner), `forward + sx right + sy up`
    /// normalised, `sx = (2x/W − 1) w`, `sy = (1 − 2y/H) h`.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Vec3 {
        let (width, height) = (self.width as f32, self.height as f32);
        let aspect = width / height;
        let sx = (2.0 * x / width - 1.0) * self.half_height * aspect;
        let sy = (1.0 - 2.0 * y / height) * self.half_height;
        (self.forward + self.right * sx + self.up * sy).normalize()
    }

    /// The solid-angle density of [`Self::ray`] at uniform image points,
    /// `1 / (4 w h cos³θ)`, for the direction `omega` (unit) inside the image.
    #[inline]
    pub fn ray_pdf(&self, omega: Vec3) -> f32 {
        let c = omega.dot(self.forward);
        1.0 / (self.image_area() * c * c * c)
    }

    /// The image point `(x, y)` in pixels of the direction `v` (any length)
    /// from the eye and `cos θ` to the axis, if it is in front of the camera.
    #[inline]
    pub fn image_point(&self, v: Vec3) -> Option<(f32, f32, f32)> {
        let depth = v.dot(self.forward);
        if !(depth > 0.0) {
            return None;
        }
        let (sx, sy) = (v.dot(self.right) / depth, v.dot(self.up) / depth);
        let x = (sx / self.half_width + 1.0) * 0.5 * self.width as f32;
        let y = (1.0 - sy / self.half_height) * 0.5 * self.height as f32;
        Some((x, y, depth / v.length()))
    }

    /// The part `[a, b] ⊆ [t0, t1]` of the segment `o + t d` inside the view
    /// frustum (the four half-spaces `n · (x − eye) ≥ 0` bounded by the
    /// image's edges), or `None` when no part of it is.
    pub fn clip(&self, o: Vec3, d: Vec3, t0: f32, t1: f32) -> Option<(f32, f32)> {
        let v = o - self.eye;
        let (mut a, mut b) = (t0, t1);
        for n in [
            self.forward * self.half_width - self.right,
            self.forward * self.half_width + self.right,
            self.forward * self.half_height - self.up,
            self.forward * self.half_height + self.up,
        ] {
            // n · (v + t d) ≥ 0.
            let (c0, c1) = (n.dot(v), n.dot(d));
            if c1 > 0.0 {
                a = a.max(-c0 / c1);
            } else if c1 < 0.0 {
                b = b.min(-c0 / c1);
            } else if c0 < 0.0 {
                return None;
            }
        }
        (a < b).then_some((a, b))
    }

    /// The pixel the point `p` projects to and the importance `W_j` of the
    /// direction, or `None` outside the image.
    #[inline]
    pub fn project(&self, p: Vec3) -> Option<Projection> {
        let (x, y, cos) = self.image_point(p - self.eye)?;
        if !(x >= 0.0 && y >= 0.0 && x < self.width as f32 && y < self.height as f32) {
            return None;
        }
        let (px, py) = (x as usize, y as usize);
        Some(Projection {
            pixel: py * self.width as usize + px,
            importance: 1.0 / (self.pixel_area * cos * cos * cos),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Pinhole {
        Pinhole::looking_at(
            Vec3::new(0.0, -3.0, -2.0),
            Vec3::new(0.0, 2.0, -4.0),
            Vec3::Z,
            60f32.to_radians(),
            8,
            6,
        )
    }

    #[test]
    fn rays_project_back_to_their_image_points() {
        let c = camera();
        for &(x, y) in &[(0.5f32, 0.5f32), (3.2, 4.9), (7.99, 0.01), (4.0, 3.0)] {
            let d = c.ray(x, y);
            let (px, py, _) = c.image_point(d * 2.7).unwrap();
            assert!(
                (px - x).abs() < 1e-4 && (py - y).abs() < 1e-4,
                "{x},{y}: {px},{py}"
            );
        }
    }

    #[test]
    fn each_pixels_importance_integrates_to_one_over_its_solid_angle() {
        // ∫ W_j dω over pixel j = 1: integrate by a fine midpoint rule in
        // angle (not on the image plane, where it would be trivially A/A):
        // directions on a small grid in (azimuth, elevation) about the pixel.
        let c = camera();
        for pixel in [0usize, 13, 47] {
            let (px, py) = ((pixel % 8) as f32, (pixel / 8) as f32);
            // Bounding box in spherical angles of the pixel's corners.
            let corners = [
                (px, py),
                (px + 1.0, py),
                (px, py + 1.0),
                (px + 1.0, py + 1.0),
            ];
            let ang = |d: Vec3| (d.x.atan2(d.y) as f64, d.z.asin() as f64);
            let (mut a0, mut a1, mut e0, mut e1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            for &(x, y) in &corners {
                let (a, e) = ang(c.ray(x, y));
                a0 = a0.min(a);
                a1 = a1.max(a);
                e0 = e0.min(e);
                e1 = e1.max(e);
            }
            let (a0, a1, e0, e1) = (a0 - 0.01, a1 + 0.01, e0 - 0.01, e1 + 0.01);
            let n = 600;
            let mut total = 0.0f64;
            for i in 0..n {
                for k in 0..n {
                    let a = a0 + (a1 - a0) * (i as f64 + 0.5) / n as f64;
                    let e = e0 + (e1 - e0) * (k as f64 + 0.5) / n as f64;
                    let d = Vec3::new(
                        (e.cos() * a.sin()) as f32,
                        (e.cos() * a.cos()) as f32,
                        e.sin() as f32,
                    );
                    if let Some(p) = c.project(c.eye + d).filter(|p| p.pixel == pixel) {
                        let dw = e.cos() * (a1 - a0) * (e1 - e0) / (n * n) as f64;
                        total += p.importance as f64 * dw;
                    }
                }
            }
            assert!((total - 1.0).abs() < 5e-3, "pixel {pixel}: {total}");
        }
    }

    #[test]
    fn a_clipped_segment_is_the_part_that_projects_into_the_image() {
        let c = camera();
        let segments = [
            (Vec3::new(-4.0, 1.0, -1.0), Vec3::new(1.0, 0.3, -0.4)),
            (Vec3::new(0.5, 6.0, 0.0), Vec3::new(-0.3, -0.4, -0.9)),
            (Vec3::new(0.0, -2.5, -3.0), Vec3::new(0.1, 1.0, 0.05)),
            (Vec3::new(3.0, -5.0, -2.0), Vec3::new(0.0, 0.0, 1.0)),
        ];
        for (o, d) in segments {
            let d = d.normalize();
            let clipped = c.clip(o, d, 0.0, 12.0);
            for i in 0..1200 {
                let t = (i as f32 + 0.5) / 100.0;
                let seen = c.project(o + d * t).is_some();
                let inside = clipped.is_some_and(|(a, b)| a < t && t < b);
                let near_edge =
                    clipped.is_some_and(|(a, b)| (t - a).abs() < 0.02 || (t - b).abs() < 0.02);
                assert!(
                    seen == inside || near_edge,
                    "{o} {d} t {t}: {seen} {clipped:?}"
                );
            }
        }
    }

    #[test]
    fn the_ray_density_integrates_to_one_over_the_image() {
        // ∫ ray_pdf dω = 1 over the image, by the same angular midpoint rule.
        let c = camera();
        let n = 800;
        let (a0, a1, e0, e1) = (-1.2f64, 1.2f64, -1.5f64, 0.5f64);
        let mut total = 0.0;
        for i in 0..n {
            for k in 0..n {
                let a = a0 + (a1 - a0) * (i as f64 + 0.5) / n as f64;
                let e = e0 + (e1 - e0) * (k as f64 + 0.5) / n as f64;
                let d = Vec3::new(
                    (e.cos() * a.sin()) as f32,
                    (e.cos() * a.cos()) as f32,
                    e.sin() as f32,
                );
                if c.project(c.eye + d).is_some() {
                    total += c.ray_pdf(d) as f64 * e.cos() * (a1 - a0) * (e1 - e0) / (n * n) as f64;
                }
            }
        }
        assert!((total - 1.0).abs() < 5e-3, "{total}");
    }
}
