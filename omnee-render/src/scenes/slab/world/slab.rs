//! The homogeneous slab medium `z_min ≤ z ≤ z_max` in f32: where it is,
//! its closed-form transmittance, and whether a connection can reach it.

use glam::Vec3;
use omnee_core::medium::Region;

/// A homogeneous slab; outside it is vacuum.
#[derive(Clone, Copy, Debug)]
pub struct Slab {
    /// The lower plane.
    pub z_min: f32,
    /// The upper plane.
    pub z_max: f32,
    /// Scattering coefficient σs (1/m).
    pub sigma_s: f32,
    /// Extinction coefficient σt = σs + σa (1/m).
    pub sigma_t: f32,
}

impl Slab {
    /// The slab as the core's techniques see it.
    pub fn region(&self) -> Region<f32> {
        Region::Slab {
            z_min: self.z_min,
            z_max: self.z_max,
        }
    }

    /// Whether the medium scatters at all.
    pub fn scatters(&self) -> bool {
        self.sigma_s > 0.0
    }

    /// Whether `p` is inside the slab.
    pub fn contains(&self, p: Vec3) -> bool {
        p.z >= self.z_min && p.z <= self.z_max
    }

    /// The parameter range `[t0, t1] ⊂ [0, 1]` of `a + t (b − a)` in the slab.
    pub fn range(&self, a: Vec3, b: Vec3) -> Option<(f32, f32)> {
        let dz = b.z - a.z;
        if dz == 0.0 {
            return self.contains(a).then_some((0.0, 1.0));
        }
        let (t1, t2) = ((self.z_min - a.z) / dz, (self.z_max - a.z) / dz);
        let (lo, hi) = (t1.min(t2).max(0.0), t1.max(t2).min(1.0));
        (hi > lo).then_some((lo, hi))
    }

    /// Transmittance between two points, closed form: `exp(−σt · ℓ)` with
    /// `ℓ` the length of the segment inside the slab.
    pub fn transmittance(&self, a: Vec3, b: Vec3) -> f32 {
        if self.sigma_t == 0.0 {
            return 1.0;
        }
        match self.range(a, b) {
            Some((t0, t1)) => (-self.sigma_t * (t1 - t0) * (b - a).length()).exp(),
            None => 1.0,
        }
    }

    /// The length of the segment `a → b` inside the slab, `(t1 − t0)|b − a|`
    /// with [`range`](Self::range)'s parameters (the optical depth over σt).
    pub fn inside_length(&self, a: Vec3, b: Vec3) -> f32 {
        self.range(a, b)
            .map_or(0.0, |(t0, t1)| (t1 - t0) * (b - a).length())
    }

    /// Whether the θ < θmax region of a connection `x0 → x2`, contained in
    /// the ball about the midpoint of radius `(s/2) max(1, tan(θmax/2))`,
    /// can reach the slab.
    pub fn may_reach(&self, x0: Vec3, x2: Vec3, theta_max: f32) -> bool {
        if theta_max >= std::f32::consts::PI * (1.0 - 1e-6) {
            return true;
        }
        let mid = 0.5 * (x0 + x2);
        let rho = 0.5 * (x2 - x0).length() * (0.5 * theta_max).tan().max(1.0);
        mid.z - rho <= self.z_max && mid.z + rho >= self.z_min
    }
}
