//! The `multiple` term: light → `x_1 … x_k` in the slab → surface point,
//! `k = 2 … K` (or one fixed `k`), the irradiance
//!
//! `E = Σ_k ∫ dA(x0) ∫ dx_1 ⋯ dx_k  L cos θ0 Π_i σs p(θ_i) Π_j T_j / Π_j d_j² · cos θ_p · V`
//!
//! over the light's area (a point light: its intensity), every vertex in
//! the slab, `T_j` the transmittance of edge `j` (closed form, vacuum
//! outside the slab) and `V` the visibility of every edge (docs/math.md
//! §14.9). Two unbiased estimators of it:
//!
//! - [`MultipleMethod::Bridge`]: `x0` on the light as the once-more term
//!   chooses it, `k` fixed or drawn ([`Orders`] from 2), a bridge of `k`
//!   vertices from `x0` to the surface point (the core's [`Bridge`]), whose
//!   weight carries the kernel `Π p/Π d²`; the rest, `σs^k e^{−σt ℓ}` over
//!   the in-slab length ℓ, the cosines and `L/pdf_A`, multiplies it;
//! - [`MultipleMethod::PathTracing`]: from the surface point a
//!   cosine-weighted direction, exponential free flights in the slab,
//!   deflections from the phase function, and at vertex `j` of the orders
//!   asked for next event estimation towards the light; with a sphere light
//!   the phase-sampled rays that hit it count too, both by the balance
//!   heuristic (at the last vertex `K` only next event estimation).

use super::SlabStats;
use super::once_more::LightVertex;
use super::{Hit, Roulette, SlabWorld};
use crate::phase::Sampled;
use crate::rng::Rng;
use crate::vertices::{Orders, VertexNumber};
use glam::Vec3;
use omnee_core::bridge::{Bridge, MAX_VERTICES};
use omnee_core::lobe::{Lobe, PhaseLobe};
use omnee_core::method::MultipleMethod;
use omnee_core::sampling::Directions;

/// How the multiple term is estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Multiple {
    /// Bridges or path tracing.
    pub method: MultipleMethod,
    /// The orders: [`VertexNumber::Fixed`]`(k ≥ 2)`, or `2 ..= max`
    /// ([`VertexNumber::Auto`]).
    pub vertices: VertexNumber,
    /// The phase function's mean cosine (for the drawn number of vertices).
    pub mean_cosine: f32,
}

/// The phase function at a vertex for the direction `d` a path from the
/// receiver arrived along (light leaves the vertex along `−d`).
type VertexLobe<'w, 'a> = PhaseLobe<f32, &'w Sampled<'a, f32>>;

impl SlabWorld<'_> {
    /// One-sample estimate of the multiply scattered irradiance at `p`
    /// with the unit normal `n` (`None`: a point receiver without a
    /// cosine), by `how.method`.
    pub fn multiple(
        &self,
        (p, n): (Vec3, Option<Vec3>),
        how: Multiple,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        match how.method {
            MultipleMethod::Bridge => self.multiple_bridge((p, n), how, rng, roulette, stats),
            MultipleMethod::PathTracing => self.multiple_path((p, n), how, rng, roulette, stats),
        }
    }

    /// A bridge from a light point to `p`: `L/pdf_A · cos θ0 · cos θ_p ·
    /// σs^k e^{−σt ℓ} · weight / P(k)` (the core's
    /// [`Bridge::estimate_at_depth`]), then the roulette and the visibility
    /// of every edge. 0 when a vertex leaves the slab or falls below the
    /// floor.
    fn multiple_bridge(
        &self,
        (p, n): (Vec3, Option<Vec3>),
        how: Multiple,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let Some(light) = self.light.once_more_origin(p, rng) else {
            return 0.0;
        };
        let Ok(bridge) = Bridge::new(light.x0, p, self.sampler()) else {
            return 0.0;
        };
        let slab = &self.slab;
        let orders = Orders::new(
            how.vertices,
            2,
            bridge.axis.s,
            slab.sigma_s,
            slab.sigma_t,
            how.mean_cosine,
        );
        let uk = if orders.is_drawn() {
            rng.uniform()
        } else {
            0.0
        };
        let (k, probability) = orders.draw(uk);
        let mut u = [[0.0f32; 3]; MAX_VERTICES];
        for ui in u[..k].iter_mut() {
            *ui = [rng.uniform(), rng.uniform(), rng.uniform()];
        }
        let mut x = [p; MAX_VERTICES + 2];
        let Some(sample) = bridge.sample(&u[..k], &mut x[1..=k]) else {
            stats.no_vertex += 1;
            return 0.0;
        };
        // The path x0, x_1 … x_k, p.
        x[0] = light.x0;
        x[k + 1] = p;
        let path = &x[..k + 2];
        if !path[1..=k]
            .iter()
            .all(|v| slab.contains(*v) && v.z >= self.floor.z)
        {
            return 0.0;
        }
        let cos0 = light.n0.map_or(1.0, |n0| n0.dot((x[1] - x[0]).normalize()));
        let cos_p = n.map_or(1.0, |n| n.dot((x[k] - p).normalize()));
        if !(cos0 > 0.0 && cos_p > 0.0) {
            return 0.0;
        }
        let inside: f32 = path
            .windows(2)
            .map(|e| slab.inside_length(e[0], e[1]))
            .sum();
        let kernel = bridge.estimate_at_depth(&sample, slab.sigma_s, slab.sigma_t * inside);
        let e = light.emitted * cos0 * cos_p * kernel / probability;
        if !e.is_finite() {
            return 0.0;
        }
        let Some(e) = roulette.play(e, rng, stats) else {
            return 0.0;
        };
        // The first edge leaves the light outwards (cos θ0 > 0).
        let blocked = path.windows(2).enumerate().any(|(j, e)| {
            self.occluded(e[0], e[1], stats) || (j > 0 && self.light.blocks(e[0], e[1]))
        });
        if blocked { 0.0 } else { e }
    }

    /// Path tracing from `p` for the orders `how.vertices` (from 2): the sum
    /// of the next event estimates at vertices `lo ..= hi` and of the light
    /// hits of the phase-sampled rays leaving vertices `lo … hi − 1`.
    fn multiple_path(
        &self,
        (p, n): (Vec3, Option<Vec3>),
        how: Multiple,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let (lo, hi) = how.vertices.range(2);
        let directions = match n.map(Directions::<f32>::cosine) {
            None => Directions::Sphere,
            Some(Ok(d)) => d,
            Some(Err(_)) => return 0.0,
        };
        let mut d = directions.sample([rng.uniform(), rng.uniform()]);
        let (pdf, cos_p) = (directions.pdf(d), n.map_or(1.0, |n| n.dot(d)));
        if !(pdf > 0.0 && cos_p > 0.0) {
            return 0.0;
        }
        // β: the path's value over its density so far, from the receiver
        // to the current vertex (the cosine over its density, σs/σt per
        // free flight, p/q per deflection).
        let mut beta = cos_p / pdf;
        let albedo = self.slab.sigma_s / self.slab.sigma_t;
        let mut o = p;
        let mut total = 0.0;
        // The order of the vertex `o` the ray leaves and the density of the
        // deflection drawn there (for a light hit's MIS weight).
        let mut from: Option<(usize, f32)> = None;
        for j in 1..=hi {
            let hit = self.intersect(o, d);
            let Some(t) = self.free_flight(o, d, hit.t(), rng) else {
                if let (Hit::Light { t }, Some((order, q))) = (hit, from)
                    && order >= lo
                {
                    total += beta * self.light_hit(o, o + d * t, d, q);
                }
                break;
            };
            let x = o + d * t;
            beta *= albedo;
            let Ok(lobe) = PhaseLobe::new(self.sampler(), d) else {
                break;
            };
            if j >= lo {
                let mis = self.light.radius > 0.0 && j < hi;
                total += self.next_event(x, &lobe, beta, mis, rng, roulette, stats);
            }
            if j == hi {
                break;
            }
            let Some(s) = lobe.sample([rng.uniform(), rng.uniform()]) else {
                break;
            };
            beta *= s.value / s.pdf;
            (o, d, from) = (x, s.omega, Some((j, s.pdf)));
        }
        if total.is_finite() { total } else { 0.0 }
    }

    /// The distance to the next vertex along `o + t d`: an exponential free
    /// flight of rate σt through the slab (vacuum elsewhere), `None` when it
    /// reaches `t_end` (what the ray hits) or leaves the slab first.
    fn free_flight(&self, o: Vec3, d: Vec3, t_end: f32, rng: &mut Rng) -> Option<f32> {
        let (ta, tb) = self.slab.region().segment(o, d)?;
        let u: f32 = rng.uniform();
        let t = ta - (-u).ln_1p() / self.slab.sigma_t;
        (t < tb.min(t_end)).then_some(t)
    }

    /// Next event estimation at the vertex `x` (lobe about the arrival
    /// direction): a light point as the once-more term chooses it,
    /// `β p(θ) L cos θ0 T / (d² pdf_A)`, with `mis` times the balance
    /// weight against the phase-sampled ray, `pdf_A/(pdf_A + q cos θ0 T/d²)`;
    /// then the roulette and the visibility test.
    #[allow(clippy::too_many_arguments)]
    fn next_event(
        &self,
        x: Vec3,
        lobe: &VertexLobe<'_, '_>,
        beta: f32,
        mis: bool,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let Some(LightVertex { x0, n0, emitted }) = self.light.once_more_origin(x, rng) else {
            return 0.0;
        };
        let to = x0 - x;
        let dist2 = to.length_squared();
        let w = to / dist2.sqrt();
        let cos0 = n0.map_or(1.0, |n0| -n0.dot(w));
        if !(cos0 > 0.0 && dist2 > 0.0) {
            return 0.0;
        }
        let geometry = cos0 * self.transmittance(x, x0) / dist2;
        let mut e = beta * lobe.eval(w) * emitted * geometry;
        if mis {
            let pdf_light = self.light.origin_pdf(x, x0);
            e *= pdf_light / (pdf_light + lobe.pdf(w) * geometry);
        }
        if !(e.is_finite() && e > 0.0) {
            return 0.0;
        }
        let Some(e) = roulette.play(e, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x, x0, stats) { 0.0 } else { e }
    }

    /// The radiance `L` times the balance weight of a phase-sampled ray from
    /// `x` (deflection density `q`) along `d` that hit the sphere light at
    /// `y` unscattered: `q cos θ_y T/d² / (pdf_A + q cos θ_y T/d²)`.
    fn light_hit(&self, x: Vec3, y: Vec3, d: Vec3, q: f32) -> f32 {
        let n_y = (y - self.light.center) / self.light.radius;
        let cos_y = -n_y.dot(d);
        let dist2 = (y - x).length_squared();
        if !(cos_y > 0.0 && dist2 > 0.0) {
            return 0.0;
        }
        let pdf_phase = q * cos_y * self.transmittance(x, y) / dist2;
        let pdf_light = self.light.origin_pdf(x, y);
        self.light.radiance * pdf_phase / (pdf_light + pdf_phase)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moments::Moments;
    use crate::phase::{PhaseSampling, TableStorage};
    use crate::scenes::slab::SlabScene;
    use omnee_core::bridge::{REFERENCE_BUDGET, isotropic_transfer};
    use omnee_core::phase::PhaseFunction;

    /// A slab 80 m thick about the origin (an infinite medium for paths of
    /// a few metres: e^{−40} beyond it) with σs = 0.5, σt = 1 and `phase`,
    /// a light at the origin of `radius` (0: a point light of intensity 1;
    /// else radiance 1/(π r²), the same intensity), no occluder.
    fn infinite(phase: &str, radius: f64) -> SlabScene {
        let light = if radius > 0.0 {
            format!(
                "radius = {radius}\nradiance = {}",
                1.0 / (std::f64::consts::PI * radius * radius)
            )
        } else {
            "intensity = 1.0".to_string()
        };
        SlabScene::parse(&format!(
            "[medium]\nsigma_s = 0.5\nsigma_a = 0.5\nphase = \"{phase}\"\nz_min = -40.0\nz_max = 40.0\n\
             [floor]\nz = -40.0\n[light]\ncenter = [0.0, 0.0, 0.0]\n{light}\n\
             [camera]\nposition = [0.0, 0.0, 30.0]\n"
        ))
        .unwrap()
    }

    /// Mean and standard error of `n` estimates of the multiple term at
    /// `receiver` in `world`, from the stream `seed`.
    fn estimate(
        world: &SlabWorld<'_>,
        receiver: (Vec3, Option<Vec3>),
        how: Multiple,
        n: u64,
        seed: u64,
    ) -> (f64, f64) {
        let mut rng = Rng::stream(seed, 0, 0x6d75);
        let mut stats = SlabStats::default();
        let mut m = Moments::default();
        for _ in 0..n {
            let e = world.multiple(receiver, how, &mut rng, Roulette::OFF, &mut stats);
            assert!(e.is_finite() && e >= 0.0, "{e}");
            m.push(e as f64);
        }
        m.mean_stderr(n)
    }

    /// The scene's world, its phase function sampled as the renderer does.
    fn world<'a>(scene: &SlabScene, storage: &'a mut TableStorage<f32>) -> SlabWorld<'a> {
        let phase = scene
            .medium
            .phase
            .sampled(PhaseSampling::Table, storage)
            .unwrap();
        SlabWorld::new(scene, phase).unwrap()
    }

    fn how(method: MultipleMethod, vertices: VertexNumber, world: &SlabWorld<'_>) -> Multiple {
        Multiple {
            method,
            vertices,
            mean_cosine: world.phase().mean_cosine(),
        }
    }

    /// `Σ_k I_k` over the orders of `vertices` for s = 1, σs = 0.5, σt = 1.
    fn closed_form(vertices: VertexNumber) -> f64 {
        let (lo, hi) = vertices.range(2);
        (lo..=hi)
            .map(|k| isotropic_transfer(k, 1.0, 0.5, 1.0, REFERENCE_BUDGET).unwrap())
            .sum()
    }

    #[test]
    fn bridges_from_a_point_light_give_the_isotropic_closed_form() {
        // Every order 2 … 4 drawn, and 2 and 5 alone; 4.5 σ each (the
        // bridges' relative variance here is below 1, docs/math.md §14).
        let scene = infinite("iso", 0.0);
        let mut storage = TableStorage::default();
        let world = world(&scene, &mut storage);
        let p = (Vec3::new(0.0, 0.0, -1.0), None);
        for (vertices, seed) in [
            (VertexNumber::Auto { max: 4 }, 1),
            (VertexNumber::Fixed(2), 2),
            (VertexNumber::Fixed(5), 3),
        ] {
            let (mean, se) = estimate(
                &world,
                p,
                how(MultipleMethod::Bridge, vertices, &world),
                200_000,
                seed,
            );
            let want = closed_form(vertices);
            assert!(
                (mean - want).abs() < 4.5 * se,
                "{vertices}: {mean} ± {se} vs {want}"
            );
            assert!(se < 0.01 * want, "{vertices}: {se}");
        }
    }

    /// `|a − b| < 4.5 σ` for two independent estimates `(mean, se)`.
    fn agree(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 4.5 * a.1.hypot(b.1)
    }

    #[test]
    fn path_tracing_agrees_with_bridges_in_an_infinite_medium() {
        // A sphere light (r = 0.05): next event estimation towards a point
        // light has infinite variance (the last edge's 1/d², unbounded next
        // to the light), so path tracing meets the closed form through the
        // bridges, which match it from a point light (above). Path tracing's
        // relative standard errors here are 1–3 %, the bridges' below 1 %.
        for (phase, vertices, seed) in [
            ("iso", VertexNumber::Auto { max: 4 }, 4),
            ("iso", VertexNumber::Fixed(3), 5),
            ("hg:0.5", VertexNumber::Auto { max: 3 }, 6),
        ] {
            let scene = infinite(phase, 0.05);
            let mut storage = TableStorage::default();
            let world = world(&scene, &mut storage);
            let p = (Vec3::new(0.0, 0.0, -1.0), None);
            let (b, t) = bridges_and_path_tracing(&world, p, vertices, seed);
            assert!(
                agree(b, t),
                "{phase} {vertices}: bridges {b:?}, path tracing {t:?}"
            );
            assert!(b.1 < 0.01 * b.0 && t.1 < 0.05 * t.0, "{b:?} {t:?}");
        }
    }

    /// The multiple term at `p` by bridges (2·10⁵ samples) and by path
    /// tracing (4·10⁵), each as (mean, standard error).
    fn bridges_and_path_tracing(
        world: &SlabWorld<'_>,
        p: (Vec3, Option<Vec3>),
        vertices: VertexNumber,
        seed: u64,
    ) -> ((f64, f64), (f64, f64)) {
        let b = estimate(
            world,
            p,
            how(MultipleMethod::Bridge, vertices, world),
            200_000,
            seed,
        );
        let t = estimate(
            world,
            p,
            how(MultipleMethod::PathTracing, vertices, world),
            400_000,
            seed,
        );
        (b, t)
    }

    #[test]
    fn path_tracing_agrees_with_bridges_under_the_plate() {
        // The default scene (slab 0 ≤ z ≤ 1, the perforated plate at 0.5,
        // the floor) with isotropic scattering and a light of radius 0.05:
        // floor points under the plate and beside it, their cosine included.
        let text = crate::scenes::slab::DEFAULT_SCENE
            .replacen("hg:0.98", "iso", 1)
            .replacen("radius = 0.01 ", "radius = 0.05 ", 1);
        let scene = SlabScene::parse(&text).unwrap();
        let mut storage = TableStorage::default();
        let world = world(&scene, &mut storage);
        for (i, (x, vertices)) in [
            (Vec3::new(0.2, 0.1, 0.0), VertexNumber::Fixed(2)),
            (Vec3::new(0.2, 0.1, 0.0), VertexNumber::Auto { max: 4 }),
            (Vec3::new(0.4, 0.3, 0.0), VertexNumber::Auto { max: 3 }),
        ]
        .into_iter()
        .enumerate()
        {
            let p = (x, Some(Vec3::Z));
            let seed = 10 + i as u64;
            let (b, t) = bridges_and_path_tracing(&world, p, vertices, seed);
            assert!(
                agree(b, t),
                "{x} {vertices}: bridges {b:?}, path tracing {t:?}"
            );
            assert!(b.1 < 0.02 * b.0 && t.1 < 0.02 * t.0, "{b:?} {t:?}");
        }
    }
}
