//! The floor of both scenes: a diffuse plane `z = const`, seen from above,
//! with a checker (the slab scene's) or a procedural sand-ripple albedo (the
//! underwater scene's choice).

use glam::{Vec2, Vec3};
use omnee_core::names::Named;

/// The floor's albedo pattern (`floor.pattern`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloorPattern {
    /// Squares of edge `size`: `albedo_a` where `⌊x/size⌋ + ⌊y/size⌋` is
    /// even, `albedo_b` elsewhere.
    Checker,
    /// Ripples of wavelength `size` across x, their crests bent by a slow
    /// second wave: `albedo_a + (albedo_b − albedo_a) · s²` with
    /// `s = ½ (1 + sin(2π (x + 0.3 size · sin(2π y / (3.7 size))) / size))`.
    Sand,
}

impl Named for FloorPattern {
    const ALL: &'static [Self] = &[FloorPattern::Checker, FloorPattern::Sand];
    fn name(self) -> &'static str {
        match self {
            FloorPattern::Checker => "checker",
            FloorPattern::Sand => "sand",
        }
    }
    fn help(self) -> &'static str {
        match self {
            FloorPattern::Checker => "squares of edge size, albedo_a and albedo_b alternating",
            FloorPattern::Sand => {
                "ripples of wavelength size, their crests bent by a slow second wave"
            }
        }
    }
}

omnee_core::display_by_name!(FloorPattern);

/// A diffuse floor.
#[derive(Clone, Copy, Debug)]
pub struct Floor {
    /// Height (m).
    pub z: f32,
    /// The pattern.
    pub pattern: FloorPattern,
    /// The pattern's length scale (m).
    pub size: f32,
    /// RGB albedo a.
    pub albedo_a: Vec3,
    /// RGB albedo b.
    pub albedo_b: Vec3,
}

impl Floor {
    /// The albedo at the floor point `p`.
    #[inline]
    pub fn albedo(&self, p: Vec2) -> Vec3 {
        match self.pattern {
            FloorPattern::Checker => {
                let (i, j) = ((p.x / self.size).floor(), (p.y / self.size).floor());
                if (i + j).rem_euclid(2.0) < 0.5 {
                    self.albedo_a
                } else {
                    self.albedo_b
                }
            }
            FloorPattern::Sand => {
                let tau = std::f32::consts::TAU;
                let bend = 0.3 * self.size * (tau * p.y / (3.7 * self.size)).sin();
                let s = 0.5 * (1.0 + (tau * (p.x + bend) / self.size).sin());
                self.albedo_a + (self.albedo_b - self.albedo_a) * (s * s)
            }
        }
    }

    /// The largest albedo of any channel anywhere.
    pub fn max_albedo(&self) -> f32 {
        self.albedo_a.max_element().max(self.albedo_b.max_element())
    }

    /// Where the ray `o + t d` meets the floor from above: `(t, point)`.
    pub fn hit(&self, o: Vec3, d: Vec3) -> Option<(f32, Vec3)> {
        if !(d.z < 0.0 && o.z > self.z) {
            return None;
        }
        let t = (self.z - o.z) / d.z;
        let mut p = o + d * t;
        p.z = self.z;
        Some((t, p))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_and_sand_stays_between_its_albedos() {
        let f = Floor {
            z: -4.0,
            pattern: FloorPattern::Checker,
            size: 0.5,
            albedo_a: Vec3::splat(0.8),
            albedo_b: Vec3::splat(0.2),
        };
        assert_eq!(f.albedo(Vec2::new(0.1, 0.1)), Vec3::splat(0.8));
        assert_eq!(f.albedo(Vec2::new(0.6, 0.1)), Vec3::splat(0.2));
        assert_eq!(f.albedo(Vec2::new(-0.1, 0.1)), Vec3::splat(0.2));
        assert_eq!(f.albedo(Vec2::new(-0.1, -0.1)), Vec3::splat(0.8));
        let s = Floor {
            pattern: FloorPattern::Sand,
            ..f
        };
        let (mut lo, mut hi) = (1.0f32, 0.0f32);
        for i in 0..1000 {
            let a = s.albedo(Vec2::new(i as f32 * 0.013, i as f32 * 0.007)).x;
            lo = lo.min(a);
            hi = hi.max(a);
        }
        assert!(
            lo >= 0.2 - 1e-6 && hi <= 0.8 + 1e-6 && hi - lo > 0.5,
            "{lo} {hi}"
        );
    }
}
