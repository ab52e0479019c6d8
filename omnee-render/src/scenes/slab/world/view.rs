//! The `view` term: light scattered once along a camera ray into the eye.
//! The distance along the ray is sampled per angle θ under which the light
//! sees it (`dt/d1² = dθ/D`): equiangular (Kulla & Fajardo 2012,
//! docs/math.md §8) in one-sample MIS (§10) with phase-function sampling of
//! the same angle (`view_sample`); for a sphere also in MIS with choosing
//! the light point first.

use super::SlabStats;
use super::{Roulette, SlabWorld};
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::phase::{Deflection, PhaseFunction};

/// A view estimate before the roulette: the radiance `L = f/pdf`, the
/// scattering point `x` on the ray and the light point `y` it sees.
type Scattered = (f32, Vec3, Vec3);

impl SlabWorld<'_> {
    /// One-sample estimate of single scattering along the camera ray
    /// `o + t d`, `t ∈ (0, t_end)`, over the ray's part in the slab: a point
    /// light by `view_point`, a sphere by `view_sphere`, then
    /// the roulette and the visibility test of `x → y`.
    pub fn view(
        &self,
        o: Vec3,
        d: Vec3,
        t_end: f32,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let end = if t_end.is_finite() {
            o + d * t_end
        } else {
            o + d * 1e6
        };
        let Some((r0, r1)) = self.slab.range(o, end) else {
            return 0.0;
        };
        let len = (end - o).length();
        let seg = (r0 * len, r1 * len);
        let scattered = if self.light.radius == 0.0 {
            self.view_point(o, d, seg, rng)
        } else {
            self.view_sphere(o, d, seg, rng)
        };
        let Some((l, x, y)) = scattered else {
            return 0.0;
        };
        if !l.is_finite() {
            return 0.0;
        }
        let Some(value) = roulette.play(l, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x, y, stats) {
            return 0.0;
        }
        value
    }

    /// A point light at `c`: `t` by [`view_sample`] about `c`, and
    /// `L = T(o, x) σs p(θ) I/|x − c|² T(x, c) / pdf(t)`.
    fn view_point(&self, o: Vec3, d: Vec3, seg: (f32, f32), rng: &mut Rng) -> Option<Scattered> {
        let phase = self.sampler();
        let c = self.light.center;
        let u = [rng.uniform(), rng.uniform()];
        let t = view_sample(o, d, c, seg, u, phase)?;
        let x = o + d * t;
        let to_x = x - c;
        let dist2 = to_x.length_squared();
        let p = phase.eval(Deflection::between(to_x / dist2.sqrt(), -d));
        let pdf = view_pdf(o, d, c, seg, t, phase);
        let f = self.transmittance(o, x) * self.slab.sigma_s * p * self.light.intensity / dist2
            * self.transmittance(x, c);
        Some(((f as f64 / pdf) as f32, x, c))
    }

    /// A sphere: one-sample MIS (balance heuristic) of two ways to choose
    /// the pair `(t, y)`, both with densities in `t` and area:
    /// A: `t` about the centre, then `y` uniform in solid angle from `x`
    ///    (bounded weights, but the centre's angle is not the true
    ///    deflection close to the sphere);
    /// B: `y` on the sphere first ([`Light::sample_facing`](super::Light::sample_facing)),
    ///    then `t` about `y` (the exact deflection, but a weight ∝ 1/distance
    ///    of `y` from the ray);
    /// and `L = T(o, x) σs p(θ) L_e cos θ_y/|x − y|² T(x, y) / (½ pdf_A + ½ pdf_B)`.
    fn view_sphere(&self, o: Vec3, d: Vec3, seg: (f32, f32), rng: &mut Rng) -> Option<Scattered> {
        let phase = self.sampler();
        let c = self.light.center;
        let u = [rng.uniform(), rng.uniform()];
        let (x, y, n_y) = if rng.uniform::<f32>() < 0.5 {
            let t = view_sample(o, d, c, seg, u, phase)?;
            let x = o + d * t;
            let lp = self.light.sample_from(x, [rng.uniform(), rng.uniform()])?;
            (x, lp.y, (lp.y - c) / self.light.radius)
        } else {
            let (y, n_y) =
                self.light
                    .sample_facing(o, d, seg, [rng.uniform(), rng.uniform(), rng.uniform()]);
            let t = view_sample(o, d, y, seg, u, phase)?;
            (o + d * t, y, n_y)
        };
        let t = (x - o).dot(d);
        let to_x = x - y;
        let dist2 = to_x.length_squared();
        let dir = to_x / dist2.sqrt();
        let cos_y = n_y.dot(dir);
        if !(cos_y > 0.0 && dist2 > 0.0) {
            return None;
        }
        let p = phase.eval(Deflection::between(dir, -d));
        let pdf_a = view_pdf(o, d, c, seg, t, phase) * self.light.cone_area_pdf(x, y) as f64;
        let pdf_b = self.light.facing_pdf(o, d, seg, n_y) as f64 * view_pdf(o, d, y, seg, t, phase);
        let f = self.transmittance(o, x) * self.slab.sigma_s * p * self.light.radiance * cos_y
            / dist2
            * self.transmittance(x, y);
        Some(((f as f64 / (0.5 * pdf_a + 0.5 * pdf_b)) as f32, x, y))
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
/// - phase sampling: θ from the phase function's sampler, density
///   `2π q(θ) sin θ` (`q = p` for an exact sampler, the table's density for
///   a tabulated one; a draw outside the segment gives no sample),
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
    phase: &impl PhaseFunction<f32>,
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
/// `(½/(θb − θa) + ½ · 2π q(θ) sin θ) · sin²θ / D` (f64), `q` the phase
/// sampler's density (`pdf`).
fn view_pdf(
    o: Vec3,
    d: Vec3,
    c: Vec3,
    seg: (f32, f32),
    t: f32,
    phase: &impl PhaseFunction<f32>,
) -> f64 {
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
    let q = phase.pdf(Deflection::from_theta(theta as f32)) as f64;
    let pdf_theta = 0.5 / (th_b - th_a) + 0.5 * std::f64::consts::TAU * q * sin;
    pdf_theta * sin * sin / dist
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::PhaseSpec;
    use crate::scenes::slab::{LightSection, SlabScene};

    #[test]
    fn the_view_distance_density_integrates_to_its_mass_and_matches_an_independent_form() {
        use omnee_core::phase::{HenyeyGreenstein, Phase};
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
    fn view_against_quadrature(light: LightSection) -> (f64, f64, f64) {
        let point = light.radius == 0.0;
        let mut scene = SlabScene::default_scene();
        scene.medium.sigma_s = 0.001;
        scene.medium.sigma_a = 0.0;
        scene.medium.phase = PhaseSpec::parse("iso").unwrap();
        scene.light = light;
        // No occluder: every point of the ray sees the whole visible cap.
        scene.occluder = None;
        let mut storage = crate::phase::TableStorage::default();
        let phase = scene.medium.phase.instantiate::<f32>(&mut storage).unwrap();
        let world = SlabWorld::new(&scene, phase).unwrap();
        let (c, r) = (world.light.center.as_dvec3(), world.light.radius as f64);
        // A ray from above the slab passing 2 cm beside the sphere, ending
        // on the floor.
        let o = Vec3::new(0.07, 0.0, 2.0);
        let d = (Vec3::new(0.07, 0.3, 0.0) - o).normalize();
        let t_end = (0.0 - o.z) / d.z;
        let mut st = SlabStats::default();
        let mut rng = Rng::stream(11, 12, 13);
        let n = 400_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let v = world.view(o, d, t_end, &mut rng, Roulette::OFF, &mut st) as f64;
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
        let center = SlabScene::default_scene().light.center;
        for light in [
            LightSection::sphere(center, 0.05, 10000.0),
            LightSection::point(center, 3.0),
        ] {
            let radius = light.radius;
            let (mean, se, want) = view_against_quadrature(light);
            // Transmittance over ≤ 3 m at σt = 1e-3 lowers the truth by
            // < 0.3 %; allow that plus 5 standard errors (normal tail 5.7e-7).
            assert!(
                mean <= want * 1.0001 + 5.0 * se && mean >= want * 0.997 - 5.0 * se,
                "radius {radius}: {mean} ± {se} vs {want}"
            );
            assert!(se < 0.01 * mean, "radius {radius}");
        }
    }
}

#[cfg(test)]
mod table_tests {
    use super::*;
    use crate::phase::{PhaseSampling, PhaseSpec, TableStorage};
    use crate::scenes::slab::SlabScene;

    #[test]
    fn the_view_density_with_a_table_integrates_to_the_tables_mass() {
        // Phase sampling through the table draws θ from q: the density of
        // `view_sample` is ½ uniform + ½ 2π q sin θ, whose phase half has
        // q's mass in the window, the table's CDF difference.
        let spec = PhaseSpec::parse("ff:0.0183,1.1").unwrap();
        let mut storage = TableStorage::<f32>::default();
        let phase = spec.sampled(PhaseSampling::Table, &mut storage).unwrap();
        assert!(phase.is_tabulated());
        let (o, d, c) = (Vec3::ZERO, Vec3::X, Vec3::new(0.7, 0.2, 0.0));
        let seg = (0.1f32, 2.0f32);
        let th = |t: f64| 0.2f64.atan2(0.7 - t);
        let cdf = |theta: f64| phase.invert(Deflection::from_theta(theta as f32)).unwrap() as f64;
        let want = 0.5 + 0.5 * (cdf(th(2.0)) - cdf(th(0.1)));
        let n = 400_000;
        let h = (seg.1 - seg.0) as f64 / n as f64;
        let total: f64 = (0..n)
            .map(|i| view_pdf(o, d, c, seg, seg.0 + ((i as f64 + 0.5) * h) as f32, &phase) * h)
            .sum();
        assert!((total / want - 1.0).abs() < 2e-3, "{total} vs {want}");
    }

    #[test]
    fn the_view_term_with_a_table_agrees_with_exact_sampling() {
        // One ray beside the default scene's sphere light with
        // Fournier–Forand: the estimator's mean must not move when phase
        // sampling goes through the table. Independent streams;
        // |z| < 5: normal tail 5.7e-7.
        let mut scene = SlabScene::default_scene();
        scene.medium.phase = PhaseSpec::parse("ff:0.0183,1.1").unwrap();
        scene.occluder = None;
        let o = Vec3::new(0.07, 0.0, 2.0);
        let d = (Vec3::new(0.07, 0.3, 0.0) - o).normalize();
        let t_end = (0.0 - o.z) / d.z;
        let run = |sampling, seed| {
            let mut storage = TableStorage::<f32>::default();
            let phase = scene.medium.phase.sampled(sampling, &mut storage).unwrap();
            let world = SlabWorld::new(&scene, phase).unwrap();
            assert_eq!(
                world.sampler().is_tabulated(),
                sampling == PhaseSampling::Table
            );
            let (mut st, mut rng) = (SlabStats::default(), Rng::stream(seed, 1, 2));
            let n = 200_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let v = world.view(o, d, t_end, &mut rng, Roulette::OFF, &mut st) as f64;
                sum += v;
                sum2 += v * v;
            }
            let mean = sum / n as f64;
            (mean, ((sum2 / n as f64 - mean * mean) / n as f64).sqrt())
        };
        let (mt, st) = run(PhaseSampling::Table, 21);
        let (me, se) = run(PhaseSampling::Exact, 22);
        let z = (mt - me) / st.hypot(se);
        assert!(z.abs() < 5.0, "table {mt} ± {st}, exact {me} ± {se}");
        assert!(st < 0.02 * me, "{st} vs {me}");
    }
}
