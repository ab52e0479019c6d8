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
    /// Technique draws whose own vertex was missing (no `x1` from its numbers).
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

    /// The area density at `y` (on the sphere) of [`Self::sample_from`]`(x)`:
    /// `cos θ_y / (dist² · 2π (1 − cos θmax))` on the cap visible from `x`.
    fn cone_area_pdf(&self, x: Vec3, y: Vec3) -> f32 {
        let n = (y - self.center) / self.radius;
        let to_x = x - y;
        let dist2 = to_x.length_squared();
        let cos_y = n.dot(to_x) / dist2.sqrt();
        let dc = (x - self.center).length();
        if !(cos_y > 0.0 && dc > self.radius) {
            return 0.0;
        }
        let sin2_max = (self.radius / dc).powi(2);
        let omc_max = sin2_max / (1.0 + (1.0 - sin2_max).max(0.0).sqrt());
        cos_y / (dist2 * std::f32::consts::TAU * omc_max)
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

/// The probability of the facing hemisphere in [`World::view_origin`].
const VIEW_HEMISPHERE: f32 = 0.75;

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

    /// The normal of the light's hemisphere that faces the segment
    /// `o + t d`, `t ∈ [ta, tb]` (towards its point closest to the centre).
    fn facing(&self, o: Vec3, d: Vec3, (ta, tb): (f32, f32)) -> Vec3 {
        let c = self.light.center;
        let foot = o + d * (c - o).dot(d).clamp(ta, tb);
        (foot - c).try_normalize().unwrap_or(-d)
    }

    /// A point on the sphere light for single scattering along a ray
    /// segment, `(y, normal at y)`: with probability 3/4 uniform on the
    /// hemisphere facing the segment, else uniform on the whole sphere.
    fn view_origin(&self, o: Vec3, d: Vec3, seg: (f32, f32), u: [f32; 3]) -> (Vec3, Vec3) {
        let h = self.facing(o, d, seg);
        let z = 1.0 - 2.0 * u[1];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * u[2];
        let (t1, t2) = h.any_orthonormal_pair();
        let mut n = t1 * (r * phi.cos()) + t2 * (r * phi.sin()) + h * z;
        if u[0] < VIEW_HEMISPHERE && n.dot(h) < 0.0 {
            n -= h * (2.0 * n.dot(h)); // mirrored into the facing hemisphere
        }
        (self.light.center + n * self.light.radius, n)
    }

    /// The area density of [`Self::view_origin`] at the point with normal `n`.
    fn view_origin_pdf(&self, o: Vec3, d: Vec3, seg: (f32, f32), n: Vec3) -> f32 {
        let area = 4.0 * std::f32::consts::PI * self.light.radius * self.light.radius;
        let facing = if n.dot(self.facing(o, d, seg)) >= 0.0 {
            2.0 * VIEW_HEMISPHERE
        } else {
            0.0
        };
        (facing + 1.0 - VIEW_HEMISPHERE) / area
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
        let Ok(connection) = Connection::new(x0, p, how.theta_max) else {
            return 0.0;
        };
        // Ray techniques draw cosine-weighted directions about the normal.
        let directions = if how.tech == Tech::Omnee {
            Directions::Sphere
        } else {
            match Directions::cosine(n) {
                Ok(d) => d,
                Err(_) => return 0.0,
            }
        };
        let setup = Setup {
            phase: &self.phase,
            directions,
            region: self.region,
            sigma_t: self.sigma_t,
        };
        let [first, companion] = setup.sample(how.tech, connection, rng).vertices;
        if first.is_none() {
            stats.no_vertex += 1;
        }
        let light = (x0, n0, emitted);
        [first, companion]
            .into_iter()
            .flatten()
            .map(|s| self.once_more_vertex(light, (p, n), s, rng, rr, stats))
            .sum()
    }

    /// The contribution `f_c · weight` of one vertex `x1` of a once-more
    /// connection from the light point `(x0, normal, L/pdf_A)` to the
    /// receiver `(p, n)`: the cosines, closed-form transmittance on both legs,
    /// σs, then Russian roulette and the visibility tests. 0 for a vertex
    /// outside the slab (or below the opaque floor) or with weight 0.
    fn once_more_vertex(
        &self,
        (x0, n0, emitted): (Vec3, Option<Vec3>, f32),
        (p, n): (Vec3, Vec3),
        sample: omnee_core::sampling::Sample<f32>,
        rng: &mut Rng,
        rr: (f32, f32),
        stats: &mut Stats,
    ) -> f32 {
        let x1 = sample.x1;
        if !(sample.weight > 0.0 && self.in_slab(x1) && x1.z >= self.floor_z) {
            return 0.0;
        }
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
    /// `o + t d`, `t ∈ (0, t_end)`. A point light: the distance by
    /// `view_sample` (equiangular about the light, Kulla & Fajardo 2012, in
    /// MIS with phase-function sampling of the same angle). A sphere: one-sample
    /// MIS of (A) the distance about the centre, then a point of the light
    /// uniform in solid angle, and (B) a point of the light first
    /// (`World::view_origin`), then the distance about it.
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
        let seg = (ta, tb);
        let c = self.light.center;
        let (l, x, y) = if self.light.radius == 0.0 {
            // A point light: the distance for the light's position.
            let u = [rng.uniform(), rng.uniform()];
            let Some(t) = view_sample(o, d, c, seg, u, &self.phase) else {
                return 0.0;
            };
            let x = o + d * t;
            let to_x = x - c;
            let dist2 = to_x.length_squared();
            let p = self
                .phase
                .eval(Deflection::between(to_x / dist2.sqrt(), -d));
            let pdf = view_pdf(o, d, c, seg, t, &self.phase);
            let f = self.transmittance(o, x) * self.sigma_s * p * self.light.intensity / dist2
                * self.transmittance(x, c);
            ((f as f64 / pdf) as f32, x, c)
        } else {
            // A sphere: one-sample MIS (balance heuristic) of two ways to
            // choose the pair (t, y), both with densities in t and area:
            // A: t about the centre, then y uniform in solid angle from x
            //    (bounded weights, but the centre's angle is not the true
            //    deflection close to the sphere);
            // B: y on the sphere first, then t about y (the exact deflection,
            //    but a weight ∝ 1/distance of y from the ray).
            let u = [rng.uniform(), rng.uniform()];
            let (x, y, n_y) = if rng.uniform::<f32>() < 0.5 {
                let Some(t) = view_sample(o, d, c, seg, u, &self.phase) else {
                    return 0.0;
                };
                let x = o + d * t;
                let Some(lp) = self.light.sample_from(x, [rng.uniform(), rng.uniform()]) else {
                    return 0.0;
                };
                (x, lp.y, (lp.y - c) / self.light.radius)
            } else {
                let (y, n_y) =
                    self.view_origin(o, d, seg, [rng.uniform(), rng.uniform(), rng.uniform()]);
                let Some(t) = view_sample(o, d, y, seg, u, &self.phase) else {
                    return 0.0;
                };
                (o + d * t, y, n_y)
            };
            let t = (x - o).dot(d);
            let to_x = x - y;
            let dist2 = to_x.length_squared();
            let dir = to_x / dist2.sqrt();
            let cos_y = n_y.dot(dir);
            if !(cos_y > 0.0 && dist2 > 0.0) {
                return 0.0;
            }
            let p = self.phase.eval(Deflection::between(dir, -d));
            let pdf_a =
                view_pdf(o, d, c, seg, t, &self.phase) * self.light.cone_area_pdf(x, y) as f64;
            let pdf_b = self.view_origin_pdf(o, d, seg, n_y) as f64
                * view_pdf(o, d, y, seg, t, &self.phase);
            let f = self.transmittance(o, x) * self.sigma_s * p * self.light.radiance * cos_y
                / dist2
                * self.transmittance(x, y);
            ((f as f64 / (0.5 * pdf_a + 0.5 * pdf_b)) as f32, x, y)
        };
        if !l.is_finite() {
            return 0.0;
        }
        let Some(value) = roulette(l, threshold, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x, y, stats) {
            return 0.0;
        }
        value
    }
}

/// The angle window of single scattering along the ray `o + t d` (unit `d`)
/// for light from `c`: with `Δ = (c − o)·d`, `D = |(c − o) × d|` and
/// `v = t − Δ`, `θ(t) = atan2(D, −v)` is the deflection at `x = o + t d` of
/// light going from `c` through `x` back along the ray, increasing with t.
/// Returns `(Δ, D, θ(ta), θ(tb))` in f64, or `None` when `c` is on the line.
fn view_window(o: Vec3, d: Vec3, c: Vec3, (ta, tb): (f32, f32)) -> Option<(f64, f64, f64, f64)> {
    let (o, d, c) = (o.as_dvec3(), d.as_dvec3(), c.as_dvec3());
    let (ta, tb) = (ta as f64, tb as f64);
    let delta = (c - o).dot(d);
    let dist = (c - o).cross(d).length();
    let (a, b) = (ta - delta, tb - delta);
    if !(tb > ta) || dist <= 1e-9 * (a.abs() + b.abs()) {
        return None;
    }
    Some((delta, dist, dist.atan2(-a), dist.atan2(-b)))
}

/// A distance `t ∈ [ta, tb]` along the ray `o + t d` for single scattering
/// of light from `c`. Since `dt / d1² = dθ / D` (see [`view_window`]), the
/// integrand in θ is `p(θ)` times slowly varying factors. One-sample MIS
/// (balance heuristic, probability 1/2 each, chosen by `u[0]`) of
/// - equiangular sampling: θ uniform on `[θ(ta), θ(tb)]` (Kulla & Fajardo 2012);
/// - phase sampling: θ from the phase function, density `2π p(θ) sin θ`
///   (a draw outside the segment gives no sample),
///
/// which keeps the forward peak of a strongly forward-scattering medium
/// (the glow around a light seen through it) sampled. [`view_pdf`] is its
/// density. When `c` is on the ray's line, `t` is uniform.
fn view_sample(
    o: Vec3,
    d: Vec3,
    c: Vec3,
    seg: (f32, f32),
    u: [f32; 2],
    phase: &Phase<'_, f32>,
) -> Option<f32> {
    let (ta, tb) = (seg.0 as f64, seg.1 as f64);
    let Some((delta, dist, th_a, th_b)) = view_window(o, d, c, seg) else {
        return (tb > ta).then(|| (ta + u[1] as f64 * (tb - ta)) as f32);
    };
    let theta = if u[0] < 0.5 {
        th_a + u[1] as f64 * (th_b - th_a)
    } else {
        let th = phase.sample(u[1]).theta as f64;
        if !(th >= th_a && th <= th_b) {
            return None;
        }
        th
    };
    let (sin, cos) = theta.sin_cos();
    Some((delta - dist * cos / sin).clamp(ta, tb) as f32)
}

/// The density of [`view_sample`] at `t`:
/// `(½/(θb − θa) + ½ · 2π p(θ) sin θ) · sin²θ / D` (f64).
fn view_pdf(o: Vec3, d: Vec3, c: Vec3, seg: (f32, f32), t: f32, phase: &Phase<'_, f32>) -> f64 {
    let (ta, tb) = (seg.0 as f64, seg.1 as f64);
    let t = t as f64;
    if !(t >= ta && t <= tb) {
        return 0.0;
    }
    let Some((delta, dist, th_a, th_b)) = view_window(o, d, c, seg) else {
        return 1.0 / (tb - ta);
    };
    let theta = dist.atan2(delta - t);
    let sin = theta.sin();
    let p = phase.eval(Deflection::from_theta(theta as f32)) as f64;
    let pdf_theta = 0.5 / (th_b - th_a) + 0.5 * std::f64::consts::TAU * p * sin;
    pdf_theta * sin * sin / dist
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_distance_density_integrates_to_its_mass_and_matches_an_independent_form() {
        use omnee_core::phase::HenyeyGreenstein;
        let phase = Phase::HenyeyGreenstein(HenyeyGreenstein::new(0.9f32).unwrap());
        let (o, d, c) = (Vec3::ZERO, Vec3::X, Vec3::new(0.7, 0.2, 0.0));
        let seg = (0.1f32, 2.0f32);
        // Independent form: θ(t) = atan2(D, Δ − t) with Δ = 0.7, D = 0.2.
        let th = |t: f64| 0.2f64.atan2(0.7 - t);
        let (th_a, th_b) = (th(0.1), th(2.0));
        let hg = |theta: f64| {
            let g = 0.9f64;
            (1.0 - g * g)
                / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * theta.cos()).powf(1.5))
        };
        let n = 200_000;
        // The phase half has the phase function's mass inside the window.
        let h = (th_b - th_a) / n as f64;
        let mass: f64 = (0..n)
            .map(|i| {
                let t = th_a + (i as f64 + 0.5) * h;
                std::f64::consts::TAU * hg(t) * t.sin() * h
            })
            .sum();
        let h = (seg.1 - seg.0) as f64 / n as f64;
        let mut total = 0.0;
        for i in 0..n {
            let t = seg.0 as f64 + (i as f64 + 0.5) * h;
            let pdf = view_pdf(o, d, c, seg, t as f32, &phase);
            total += pdf * h;
            if i % 1000 == 0 {
                let theta = th(t);
                let s = theta.sin();
                let want =
                    (0.5 / (th_b - th_a) + 0.5 * std::f64::consts::TAU * hg(theta) * s) * s * s
                        / 0.2;
                assert!((pdf / want - 1.0).abs() < 1e-3, "{pdf} vs {want}");
            }
        }
        let want = 0.5 + 0.5 * mass;
        assert!((total / want - 1.0).abs() < 1e-3, "{total} vs {want}");
        // Samples land in the segment; the equiangular half is uniform in θ.
        let mut rng = Rng::stream(4, 5, 6);
        let mut below = 0;
        for _ in 0..20_000 {
            let t = view_sample(o, d, c, seg, [0.25, rng.uniform()], &phase).unwrap();
            assert!((seg.0..=seg.1).contains(&t));
            if th(t as f64) < 0.5 * (th_a + th_b) {
                below += 1;
            }
        }
        // Binomial(20000, 1/2): sd 71; 6 sd = 424.
        assert!((below - 10_000i32).abs() < 424, "{below}");
    }

    /// The view estimator's mean and standard error over `n` samples for a
    /// ray from above the slab passing beside the light, and the quadrature
    /// `σs/(4π) ∫ Φ(x(t)) dt` over the slab part of the ray, for isotropic
    /// scattering with negligible attenuation (σt = σs = 1e-3), where `Φ` is
    /// the fluence `L·2π(1 − √(1 − r²/d²))` of a sphere or `I/d²` of a point.
    fn view_against_quadrature(
        radius_line: &str,
        emission_line: &str,
        point: bool,
    ) -> (f64, f64, f64) {
        let text = crate::scene::DEFAULT_SCENE
            .replace("sigma_s = 0.5 ", "sigma_s = 0.001 ")
            .replace("sigma_a = 0.05 ", "sigma_a = 0.0 ")
            .replace("phase = \"hg:0.98\"", "phase = \"iso\"")
            .replace("radius = 0.01 ", radius_line)
            .replace("radiance = 10000.0 ", emission_line);
        // No occluder: every point of the ray sees the whole visible cap.
        let (cut, end) = (
            text.find("[occluder]").unwrap(),
            text.find("[camera]").unwrap(),
        );
        let text = format!("{}{}", &text[..cut], &text[end..]);
        let scene = Scene::parse(&text).unwrap();
        let mut storage = crate::phase::TableStorage::default();
        let world = World::new(
            &scene,
            scene.medium.phase.instantiate::<f32>(&mut storage).unwrap(),
        );
        let (c, r) = (world.light.center.as_dvec3(), world.light.radius as f64);
        // A ray from above the slab passing 2 cm beside the sphere, ending
        // on the floor.
        let o = Vec3::new(0.07, 0.0, 2.0);
        let d = (Vec3::new(0.07, 0.3, 0.0) - o).normalize();
        let t_end = (0.0 - o.z) / d.z;
        let mut st = Stats::default();
        let mut rng = Rng::stream(11, 12, 13);
        let n = 400_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let v = world.view(o, d, t_end, &mut rng, 0.0, &mut st) as f64;
            sum += v;
            sum2 += v * v;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        let (od, dd) = (o.as_dvec3(), d.as_dvec3());
        let (t0, t1) = ((1.0 - od.z) / dd.z, (0.0 - od.z) / dd.z);
        let m = 200_000;
        let h = (t1 - t0) / m as f64;
        let mut q = 0.0;
        for i in 0..m {
            let x = od + dd * (t0 + (i as f64 + 0.5) * h);
            let dist = (x - c).length();
            q += h * if point {
                world.light.intensity as f64 / (dist * dist)
            } else {
                world.light.radiance as f64
                    * std::f64::consts::TAU
                    * (1.0 - (1.0 - (r / dist).powi(2)).max(0.0).sqrt())
            };
        }
        (mean, se, 1e-3 / (4.0 * std::f64::consts::PI) * q)
    }

    #[test]
    fn the_view_estimator_matches_a_quadrature_of_the_in_scattered_fluence() {
        for (radius, emission, point) in [
            ("radius = 0.05 ", "radiance = 10000.0 ", false),
            ("radius = 0.0 ", "intensity = 3.0 ", true),
        ] {
            let (mean, se, want) = view_against_quadrature(radius, emission, point);
            // Transmittance over ≤ 3 m at σt = 1e-3 lowers the truth by
            // < 0.3 %; allow that plus 5 standard errors (normal tail 5.7e-7).
            assert!(
                mean <= want * 1.0001 + 5.0 * se && mean >= want * 0.997 - 5.0 * se,
                "{radius}: {mean} ± {se} vs {want}"
            );
            assert!(se < 0.01 * mean, "{radius}");
        }
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
