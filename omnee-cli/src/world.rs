//! The scene in the renderer's precision (f32) and its light transport: the
//! `direct`, `once-more` and `view` estimators shared by `render` and `probe`.
//!
//! Units: the light's radiance in W/(m²·sr) (or a point light's intensity in
//! W/sr), lengths in m, coefficients in 1/m; the surface estimators return
//! irradiance (W/m²), the view estimator radiance.

use crate::rng::Rng;
use crate::scene::{Pattern, Scene};
use crate::technique::{Setup, Tech};
use glam::Vec3;
use omnee_core::medium::Region;
use omnee_core::phase::{Deflection, Phase, PhaseFunction};
use omnee_core::sampling::{Connection, Directions};

/// Counters of the work done and skipped, summed over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Once-more connections set up (an `x0` chosen).
    pub connections: u64,
    /// Connections not sampled: the θ < θmax region cannot reach the slab.
    pub skipped_unreachable: u64,
    /// Technique draws that returned no `x1` or one outside the medium.
    pub no_vertex: u64,
    /// Contributions below the Russian roulette threshold that were dropped.
    pub roulette_dropped: u64,
    /// Contributions below the threshold that survived (and were boosted).
    pub roulette_kept: u64,
    /// Occluder (visibility) tests done.
    pub visibility_tests: u64,
}

impl Stats {
    /// Adds another run's counters.
    pub fn add(&mut self, o: &Stats) {
        self.connections += o.connections;
        self.skipped_unreachable += o.skipped_unreachable;
        self.no_vertex += o.no_vertex;
        self.roulette_dropped += o.roulette_dropped;
        self.roulette_kept += o.roulette_kept;
        self.visibility_tests += o.visibility_tests;
    }
}

/// A spherical light (radius > 0) or a point light.
#[derive(Clone, Copy, Debug)]
pub struct Light {
    /// Centre.
    pub center: Vec3,
    /// Radius (0: point light).
    pub radius: f32,
    /// Surface radiance (sphere).
    pub radiance: f32,
    /// Intensity (point light; `radiance·π r²` for a sphere).
    pub intensity: f32,
}

/// A point on the light seen from somewhere, with its solid-angle density.
#[derive(Clone, Copy, Debug)]
struct LightPoint {
    /// The point.
    y: Vec3,
    /// Unit direction from the receiver to `y`.
    dir: Vec3,
    /// `L / pdf_ω` for a sphere, `I / dist²` for a point light: the
    /// unoccluded, unattenuated estimate of the irradiance normal to `dir`.
    value: f32,
}

impl Light {
    /// Samples the part of the light visible from `q` uniformly in solid
    /// angle (a sphere's cone of directions), or returns the point light.
    fn sample_from(&self, q: Vec3, u: [f32; 2]) -> Option<LightPoint> {
        let to_c = self.center - q;
        let dc = to_c.length();
        if self.radius == 0.0 {
            return (dc > 0.0).then(|| LightPoint {
                y: self.center,
                dir: to_c / dc,
                value: self.intensity / (dc * dc),
            });
        }
        if !(dc > self.radius) {
            return None;
        }
        // Cone of half-angle θmax about the centre, written without
        // cancellation: 1 − cos θmax = sin²θmax / (1 + cos θmax).
        let sin2_max = (self.radius / dc).powi(2);
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        let omc_max = sin2_max / (1.0 + cos_max);
        let omc = u[0] * omc_max;
        let cos_t = 1.0 - omc;
        let sin2_t = omc * (2.0 - omc);
        // Angle α at the centre between −wc and the point (pbrt-v4's form).
        let sin_max = sin2_max.sqrt();
        let cos_a = sin2_t / sin_max + cos_t * (1.0 - sin2_t / sin2_max).max(0.0).sqrt();
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * u[1];
        let wc = to_c / dc;
        let (t1, t2) = wc.any_orthonormal_pair();
        let n = (t1 * (sin_a * phi.cos()) + t2 * (sin_a * phi.sin())) - wc * cos_a;
        let y = self.center + n * self.radius;
        let v = y - q;
        let dist = v.length();
        (dist > 0.0).then(|| LightPoint {
            y,
            dir: v / dist,
            value: self.radiance * std::f32::consts::TAU * omc_max,
        })
    }

    /// Whether the segment `a → b` passes through the sphere's interior.
    fn blocks(&self, a: Vec3, b: Vec3) -> bool {
        if self.radius == 0.0 {
            return false;
        }
        let d = b - a;
        let len2 = d.length_squared();
        let t = if len2 > 0.0 {
            ((self.center - a).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a + d * t - self.center).length_squared() < self.radius * self.radius * (1.0 - 1e-5)
    }

    /// The first `t > 0` where the ray `o + t d` hits the sphere.
    fn hit(&self, o: Vec3, d: Vec3) -> Option<f32> {
        if self.radius == 0.0 {
            return None;
        }
        let oc = o - self.center;
        let b = oc.dot(d);
        // c = |oc|² − r², the discriminant as r² − |oc − b d|² (no cancellation).
        let perp = oc - d * b;
        let disc = self.radius * self.radius - perp.length_squared();
        if disc < 0.0 {
            return None;
        }
        let t = -b - disc.sqrt();
        (t > 0.0).then_some(t)
    }
}

/// The occluder plate.
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
    fn blocks(&self, a: Vec3, b: Vec3) -> bool {
        let z = self.center.z;
        if (a.z - z) * (b.z - z) >= 0.0 {
            return false;
        }
        let t = (z - a.z) / (b.z - a.z);
        let p = a + (b - a) * t;
        self.solid_at(p.x, p.y)
    }
}

/// What a camera ray hits first.
#[derive(Clone, Copy, Debug)]
pub enum Hit {
    /// Nothing.
    Miss,
    /// The light's sphere at distance `t`.
    Light {
        /// Ray parameter.
        t: f32,
    },
    /// A diffuse surface.
    Surface {
        /// Ray parameter.
        t: f32,
        /// The point.
        p: Vec3,
        /// Unit normal on the side of the ray origin.
        n: Vec3,
        /// RGB albedo.
        albedo: Vec3,
    },
}

/// How the once-more term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct OnceMore {
    /// The technique for `x1`.
    pub tech: Tech,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
}

/// The scene in f32, ready to trace.
pub struct World<'a> {
    /// Slab bounds.
    pub z_min: f32,
    /// Slab top.
    pub z_max: f32,
    /// σs.
    pub sigma_s: f32,
    /// σt.
    pub sigma_t: f32,
    /// The phase function.
    pub phase: Phase<'a, f32>,
    region: Region<f32>,
    floor_z: f32,
    checker: f32,
    albedo_a: Vec3,
    albedo_b: Vec3,
    /// The light.
    pub light: Light,
    /// The occluder.
    pub plate: Option<Plate>,
}

fn v3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

/// Russian roulette on a contribution `c` (in the units of the output) that
/// still needs visibility tests: below `threshold` it survives with
/// probability `c / threshold` and is then worth `threshold` (unbiased).
/// Returns the value to use, or `None` when dropped.
fn roulette(c: f32, threshold: f32, rng: &mut Rng, stats: &mut Stats) -> Option<f32> {
    if c >= threshold || threshold <= 0.0 {
        return Some(c);
    }
    if rng.uniform::<f32>() * threshold < c {
        stats.roulette_kept += 1;
        Some(threshold)
    } else {
        stats.roulette_dropped += 1;
        None
    }
}

impl<'a> World<'a> {
    /// The scene with its phase function instantiated by the caller.
    pub fn new(scene: &Scene, phase: Phase<'a, f32>) -> Self {
        let m = &scene.medium;
        let l = &scene.light;
        World {
            z_min: m.z_min as f32,
            z_max: m.z_max as f32,
            sigma_s: m.sigma_s as f32,
            sigma_t: m.sigma_t() as f32,
            phase,
            region: Region::Slab {
                z_min: m.z_min as f32,
                z_max: m.z_max as f32,
            },
            floor_z: scene.floor.z as f32,
            checker: scene.floor.checker_size as f32,
            albedo_a: v3(scene.floor.albedo_a),
            albedo_b: v3(scene.floor.albedo_b),
            light: Light {
                center: v3(l.center),
                radius: l.radius as f32,
                radiance: l.radiance as f32,
                intensity: l.intensity as f32,
            },
            plate: scene.occluder.as_ref().map(|o| Plate {
                center: v3(o.center),
                half: [0.5 * o.size[0] as f32, 0.5 * o.size[1] as f32],
                pattern: o.pattern,
                period: o.period as f32,
                opening: o.opening as f32,
                albedo: v3(o.albedo),
            }),
        }
    }

    /// Whether the medium scatters at all.
    pub fn scatters(&self) -> bool {
        self.sigma_s > 0.0
    }

    /// Whether `p` is inside the slab.
    fn in_slab(&self, p: Vec3) -> bool {
        p.z >= self.z_min && p.z <= self.z_max
    }

    /// The parameter range `[t0, t1] ⊂ [0, 1]` of `a + t (b − a)` in the slab.
    fn slab_range(&self, a: Vec3, b: Vec3) -> Option<(f32, f32)> {
        let dz = b.z - a.z;
        if dz == 0.0 {
            return self.in_slab(a).then_some((0.0, 1.0));
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
        match self.slab_range(a, b) {
            Some((t0, t1)) => (-self.sigma_t * (t1 - t0) * (b - a).length()).exp(),
            None => 1.0,
        }
    }

    /// Whether the occluder blocks `a → b` (counts the test; no occluder, no test).
    fn occluded(&self, a: Vec3, b: Vec3, stats: &mut Stats) -> bool {
        match &self.plate {
            None => false,
            Some(plate) => {
                stats.visibility_tests += 1;
                plate.blocks(a, b)
            }
        }
    }

    /// The floor's albedo at `p`.
    fn floor_albedo(&self, p: Vec3) -> Vec3 {
        let (i, j) = ((p.x / self.checker).floor(), (p.y / self.checker).floor());
        if (i + j).rem_euclid(2.0) < 0.5 {
            self.albedo_a
        } else {
            self.albedo_b
        }
    }

    /// The first thing the ray `o + t d` (unit `d`) hits.
    pub fn intersect(&self, o: Vec3, d: Vec3) -> Hit {
        let mut best = Hit::Miss;
        let mut t_best = f32::INFINITY;
        if d.z < 0.0 && o.z > self.floor_z {
            let t = (self.floor_z - o.z) / d.z;
            let mut p = o + d * t;
            p.z = self.floor_z;
            t_best = t;
            best = Hit::Surface {
                t,
                p,
                n: Vec3::Z,
                albedo: self.floor_albedo(p),
            };
        }
        if let Some(plate) = &self.plate {
            let t = (plate.center.z - o.z) / d.z;
            if t > 0.0 && t < t_best {
                let mut p = o + d * t;
                if plate.solid_at(p.x, p.y) {
                    p.z = plate.center.z;
                    t_best = t;
                    best = Hit::Surface {
                        t,
                        p,
                        n: if d.z < 0.0 { Vec3::Z } else { -Vec3::Z },
                        albedo: plate.albedo,
                    };
                }
            }
        }
        if let Some(t) = self.light.hit(o, d).filter(|&t| t < t_best) {
            best = Hit::Light { t };
        }
        best
    }

    /// One-sample estimate of the direct irradiance at `p` (normal `n`):
    /// light sampled in solid angle, attenuated, occluded.
    /// `scale` converts irradiance to the output's units for the roulette.
    pub fn direct(
        &self,
        p: Vec3,
        n: Vec3,
        rng: &mut Rng,
        rr: (f32, f32),
        stats: &mut Stats,
    ) -> f32 {
        let u = [rng.uniform(), rng.uniform()];
        let Some(lp) = self.light.sample_from(p, u) else {
            return 0.0;
        };
        let cos = n.dot(lp.dir);
        if !(cos > 0.0) {
            return 0.0;
        }
        let e = lp.value * cos * self.transmittance(p, lp.y);
        let (scale, threshold) = rr;
        let Some(c) = roulette(e * scale, threshold, rng, stats) else {
            return 0.0;
        };
        if self.occluded(p, lp.y, stats) {
            return 0.0;
        }
        if scale > 0.0 { c / scale } else { e }
    }

    /// A point `x0` on the light for a once-more connection to `p`, and the
    /// factor `L cos θ0 / pdf_A(x0)` without the cosine (which depends on
    /// `x1`): `(x0, normal at x0 or None for a point light, L / pdf_A or I)`.
    ///
    /// Sphere: with probability 0.9 a point of the cap visible from `p`
    /// (uniform in solid angle from `p`), else uniform on the whole sphere,
    /// so every point that can light some `x1` has a positive density.
    fn once_more_origin(&self, p: Vec3, rng: &mut Rng) -> Option<(Vec3, Option<Vec3>, f32)> {
        let l = &self.light;
        if l.radius == 0.0 {
            return Some((l.center, None, l.intensity));
        }
        const CONE: f32 = 0.9;
        let (u0, u1, u2): (f32, f32, f32) = (rng.uniform(), rng.uniform(), rng.uniform());
        let y = if u0 < CONE {
            self.light.sample_from(p, [u1, u2])?.y
        } else {
            let z = 1.0 - 2.0 * u1;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * u2;
            l.center + Vec3::new(r * phi.cos(), r * phi.sin(), z) * l.radius
        };
        let n0 = (y - l.center) / l.radius;
        // The mixture's area density at y.
        let area = 4.0 * std::f32::consts::PI * l.radius * l.radius;
        let to_p = p - y;
        let dist2 = to_p.length_squared();
        let cos_y = n0.dot(to_p) / dist2.sqrt();
        let cone_pdf = if cos_y > 0.0 {
            let dc = (p - l.center).length();
            let sin2_max = (l.radius / dc).powi(2);
            let omc_max = sin2_max / (1.0 + (1.0 - sin2_max).max(0.0).sqrt());
            cos_y / (dist2 * std::f32::consts::TAU * omc_max)
        } else {
            0.0
        };
        let pdf = CONE * cone_pdf + (1.0 - CONE) / area;
        Some((y, Some(n0), l.radiance / pdf))
    }

    /// Whether the θ < θmax region of a connection `x0 → x2`, contained in
    /// the ball about the midpoint of radius `(s/2) max(1, tan(θmax/2))`,
    /// can reach the slab.
    fn reaches_medium(&self, x0: Vec3, x2: Vec3, theta_max: f32) -> bool {
        if theta_max >= std::f32::consts::PI * (1.0 - 1e-6) {
            return true;
        }
        let mid = 0.5 * (x0 + x2);
        let rho = 0.5 * (x2 - x0).length() * (0.5 * theta_max).tan().max(1.0);
        mid.z - rho <= self.z_max && mid.z + rho >= self.z_min
    }

    /// One-sample estimate of the once-more scattered irradiance at `p`
    /// (normal `n`): light → `x1` in the slab → `p`.
    pub fn once_more(
        &self,
        p: Vec3,
        n: Vec3,
        how: OnceMore,
        rng: &mut Rng,
        rr: (f32, f32),
        stats: &mut Stats,
    ) -> f32 {
        let Some((x0, n0, emitted)) = self.once_more_origin(p, rng) else {
            return 0.0;
        };
        stats.connections += 1;
        if !self.reaches_medium(x0, p, how.theta_max) {
            stats.skipped_unreachable += 1;
            return 0.0;
        }
        let u = rng.uniform3::<f32>();
        let Ok(connection) = Connection::new(x0, p, how.theta_max) else {
            return 0.0;
        };
        let Ok(directions) = Directions::cosine(n) else {
            return 0.0;
        };
        let setup = Setup {
            phase: &self.phase,
            directions,
            region: self.region,
            sigma_t: self.sigma_t,
        };
        let sample = match setup.sample(how.tech, connection, u) {
            Some(s) if s.weight > 0.0 && self.in_slab(s.x1) => s,
            _ => {
                stats.no_vertex += 1;
                return 0.0;
            }
        };
        let x1 = sample.x1;
        let (a, b) = (x1 - x0, x1 - p);
        let (d1, d2) = (a.length(), b.length());
        let cos0 = match n0 {
            Some(n0) => n0.dot(a) / d1,
            None => 1.0,
        };
        let cos2 = n.dot(b) / d2;
        if !(cos0 > 0.0 && cos2 > 0.0) {
            return 0.0;
        }
        let e = emitted
            * cos0
            * self.transmittance(x0, x1)
            * self.sigma_s
            * self.transmittance(x1, p)
            * cos2
            * sample.weight;
        if !e.is_finite() {
            return 0.0;
        }
        let (scale, threshold) = rr;
        let Some(c) = roulette(e * scale, threshold, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x0, x1, stats) || self.occluded(x1, p, stats) || self.light.blocks(x1, p) {
            return 0.0;
        }
        if scale > 0.0 { c / scale } else { e }
    }

    /// One-sample estimate of single scattering along the camera ray
    /// `o + t d`, `t ∈ (0, t_end)`: the distance equiangular about the light's
    /// centre (Kulla & Fajardo 2012), then a point on the light.
    pub fn view(
        &self,
        o: Vec3,
        d: Vec3,
        t_end: f32,
        rng: &mut Rng,
        threshold: f32,
        stats: &mut Stats,
    ) -> f32 {
        let end = if t_end.is_finite() {
            o + d * t_end
        } else {
            o + d * 1e6
        };
        let Some((r0, r1)) = self.slab_range(o, end) else {
            return 0.0;
        };
        let len = (end - o).length();
        let (ta, tb) = (r0 * len, r1 * len);
        let Some((t, pdf_t)) = equiangular(o, d, self.light.center, ta, tb, rng.uniform()) else {
            return 0.0;
        };
        let x = o + d * t;
        let Some(lp) = self.light.sample_from(x, [rng.uniform(), rng.uniform()]) else {
            return 0.0;
        };
        // Light propagates from y to x, then from x back to the eye.
        let deflection = Deflection::between(-lp.dir, -d);
        let l = self.transmittance(o, x)
            * self.sigma_s
            * self.phase.eval(deflection)
            * lp.value
            * self.transmittance(x, lp.y)
            / pdf_t;
        if !l.is_finite() {
            return 0.0;
        }
        let Some(c) = roulette(l, threshold, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x, lp.y, stats) {
            return 0.0;
        }
        c
    }
}

/// Equiangular sampling of `t ∈ [ta, tb]` on the ray `o + t d` for a point
/// `c`: density `D / ((θb − θa)(D² + (t − Δ)²))`, `Δ = (c − o)·d`,
/// `D = |(c − o) × d|`, evaluated in f64. Uniform on the segment when `c` is
/// on the ray's line. Returns `(t, pdf)`.
fn equiangular(o: Vec3, d: Vec3, c: Vec3, ta: f32, tb: f32, xi: f32) -> Option<(f32, f32)> {
    let (o, d, c) = (o.as_dvec3(), d.as_dvec3(), c.as_dvec3());
    let (ta, tb, xi) = (ta as f64, tb as f64, xi as f64);
    if !(tb > ta) {
        return None;
    }
    let delta = (c - o).dot(d);
    let dist = (c - o).cross(d).length();
    let (a, b) = (ta - delta, tb - delta);
    if dist <= 1e-9 * (a.abs() + b.abs()) {
        let t = ta + xi * (tb - ta);
        return Some((t as f32, (1.0 / (tb - ta)) as f32));
    }
    let (th_a, th_b) = (a.atan2(dist), b.atan2(dist));
    let v = dist * (th_a + xi * (th_b - th_a)).tan();
    let t = (delta + v).clamp(ta, tb);
    let pdf = dist / ((th_b - th_a) * (dist * dist + v * v));
    (pdf > 0.0 && pdf.is_finite()).then_some((t as f32, pdf as f32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equiangular_density_integrates_to_one() {
        let (o, d, c) = (Vec3::ZERO, Vec3::X, Vec3::new(0.3, 0.2, 0.0));
        // Midpoint rule on the pdf: t from its own inverse, not the sampler.
        let n = 20_000;
        let (ta, tb) = (0.0f32, 2.0f32);
        let mut total = 0.0f64;
        for i in 0..n {
            let t = ta as f64 + (i as f64 + 0.5) * (tb - ta) as f64 / n as f64;
            let v = t - 0.3;
            let th_a = (-0.3f64).atan2(0.2);
            let th_b = (1.7f64).atan2(0.2);
            total += 0.2 / ((th_b - th_a) * (0.04 + v * v)) * (tb - ta) as f64 / n as f64;
        }
        assert!((total - 1.0).abs() < 1e-6);
        // The sampler's pdf matches that closed form at its own sample.
        let (t, pdf) = equiangular(o, d, c, ta, tb, 0.37).unwrap();
        let v = t as f64 - 0.3;
        let want = 0.2 / (((1.7f64).atan2(0.2) - (-0.3f64).atan2(0.2)) * (0.04 + v * v));
        assert!((pdf as f64 / want - 1.0).abs() < 1e-5);
    }

    #[test]
    fn the_sphere_light_cone_sample_lies_on_the_sphere_and_faces_the_receiver() {
        let l = Light {
            center: Vec3::new(0.0, 0.0, 1.0),
            radius: 0.1,
            radiance: 1.0,
            intensity: 0.0,
        };
        let q = Vec3::new(0.2, 0.1, 0.0);
        let mut rng = Rng::stream(1, 2, 3);
        for _ in 0..1000 {
            let lp = l.sample_from(q, [rng.uniform(), rng.uniform()]).unwrap();
            assert!(((lp.y - l.center).length() - 0.1).abs() < 1e-5);
            assert!((lp.y - l.center).dot(q - lp.y) >= -1e-6);
        }
    }
}
