//! An orthonormal frame about the axis `x0 → x2` and the map (θ, β/θ, φ) →
//! `x1` with its Jacobian, written here independently of the core.

use glam::DVec3;

/// An orthonormal frame about the axis `x0 → x2`, built here independently of
/// `omnee::circumcircle` so the χ² tests do not check the core against itself.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub x0: DVec3,
    pub s: f64,
    pub e: DVec3,
    pub u: DVec3,
    pub v: DVec3,
}

impl Frame {
    /// The frame of `x0 → x2` (Gram–Schmidt against a coordinate axis).
    pub fn new(x0: DVec3, x2: DVec3) -> Self {
        let d = x2 - x0;
        let s = d.length();
        let e = d / s;
        let helper = if e.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
        let u = (helper - e * e.dot(helper)).normalize();
        let v = e.cross(u);
        Self { x0, s, e, u, v }
    }

    /// `(θ, β/θ, φ)` of `x1`: `α = ∠(e, x1 − x0)`, `β = ∠(−e, x1 − x2)`, θ = α + β.
    pub fn angles(&self, x1: DVec3) -> (f64, f64, f64) {
        let a = x1 - self.x0;
        let h = self.e.cross(a).length();
        let p1 = self.e.dot(a);
        let p2 = self.s - p1;
        let (alpha, beta) = (h.atan2(p1), h.atan2(p2));
        let theta = alpha + beta;
        let ratio = if theta > 0.0 {
            beta / theta
        } else {
            (p1 / self.s).clamp(0.0, 1.0)
        };
        let mut phi = a.dot(self.v).atan2(a.dot(self.u));
        if phi < 0.0 {
            phi += core::f64::consts::TAU;
        }
        (theta, ratio, phi)
    }

    /// `x1` and the volume Jacobian `|dx1 / d(θ, r, φ)| = d1² d2² θ / s` at
    /// `θ ∈ (0, π)`, `r = β/θ ∈ (0, 1)` (docs/math.md §2 with `dβ = θ dr`).
    pub fn point(&self, theta: f64, r: f64, phi: f64) -> (DVec3, f64) {
        let beta = r * theta;
        let alpha = theta - beta;
        let d1 = self.s * beta.sin() / theta.sin();
        let d2 = self.s * alpha.sin() / theta.sin();
        let radial = self.u * phi.cos() + self.v * phi.sin();
        let x1 = self.x0 + (self.e * alpha.cos() + radial * alpha.sin()) * d1;
        (x1, d1 * d1 * d2 * d2 * theta / self.s)
    }
}
