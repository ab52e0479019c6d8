//! The occluder plate in f32, with its openings (the floor is both scenes'
//! [`crate::scenes::floor::Floor`]).

use crate::scenes::slab::file::Pattern;
use glam::Vec3;

/// The occluder: an opaque horizontal plate with a pattern of openings.
#[derive(Clone, Copy, Debug)]
pub struct Plate {
    center: Vec3,
    half: [f32; 2],
    pattern: Pattern,
    period: f32,
    opening: f32,
    /// RGB albedo.
    pub albedo: Vec3,
}

impl Plate {
    /// A plate centred at `center` of extent `size`, with `pattern`
    /// repeating every `period` and the open fraction `opening`.
    pub fn new(
        center: Vec3,
        size: [f32; 2],
        pattern: Pattern,
        period: f32,
        opening: f32,
        albedo: Vec3,
    ) -> Self {
        Self {
            center,
            half: [0.5 * size[0], 0.5 * size[1]],
            pattern,
            period,
            opening,
            albedo,
        }
    }

    /// Whether `(x, y)` on the plate's plane is solid plate.
    fn solid_at(&self, x: f32, y: f32) -> bool {
        let (u, v) = (x - self.center.x, y - self.center.y);
        if u.abs() > self.half[0] || v.abs() > self.half[1] {
            return false;
        }
        let (fu, fv) = (u / self.period, v / self.period);
        match self.pattern {
            Pattern::Solid => true,
            Pattern::Bars => (fu - fu.round()).abs() >= 0.5 * self.opening,
            Pattern::Holes => {
                let (du, dv) = (fu - fu.round(), fv - fv.round());
                du * du + dv * dv >= 0.25 * self.opening * self.opening
            }
        }
    }

    /// Whether the segment `a → b` crosses the plate's plane at a solid point
    /// (touching it at an end point does not count).
    pub fn blocks(&self, a: Vec3, b: Vec3) -> bool {
        let z = self.center.z;
        if (a.z - z) * (b.z - z) >= 0.0 {
            return false;
        }
        let t = (z - a.z) / (b.z - a.z);
        let p = a + (b - a) * t;
        self.solid_at(p.x, p.y)
    }

    /// Where the ray `o + t d` meets solid plate: `(t, point, unit normal on
    /// the side of `o`)`.
    pub fn hit(&self, o: Vec3, d: Vec3) -> Option<(f32, Vec3, Vec3)> {
        let t = (self.center.z - o.z) / d.z;
        if !(t > 0.0) {
            return None;
        }
        let mut p = o + d * t;
        if !self.solid_at(p.x, p.y) {
            return None;
        }
        p.z = self.center.z;
        let n = if d.z < 0.0 { Vec3::Z } else { -Vec3::Z };
        Some((t, p, n))
    }
}
