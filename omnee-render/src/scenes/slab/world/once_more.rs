//! The `once-more` term, OMNEE's: light → `x1` in the slab → surface. A
//! point `x0` on the light, then `x1` by the chosen technique for the
//! connection `x0 → p`, each vertex weighted by its technique (OMNEE's
//! weight `θ/(s sin θ)`, docs/math.md §3; `mis`, §10).

use super::SlabStats;
use super::{Light, Roulette, SlabWorld};
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::method::Method;
use omnee_core::sampling::{
    Connection, Connections, Directions, Omnee, Points, PointsMut, Sample, SampleArrays, Technique,
    Uniforms,
};

/// How the once-more term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct OnceMore {
    /// The method for `x1`.
    pub method: Method,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
}

/// The light end of a once-more connection (and of the `multiple` term's
/// bridges and next event estimates).
#[derive(Clone, Copy, Debug)]
pub(super) struct LightVertex {
    /// The point on the light.
    pub x0: Vec3,
    /// The sphere's normal at `x0` (`None` for a point light).
    pub n0: Option<Vec3>,
    /// `L / pdf_A(x0)` for a sphere, `I` for a point light: the factor
    /// `L cos θ0 / pdf_A` without the cosine, which depends on `x1`.
    pub emitted: f32,
}

/// The probability of choosing `x0` in the cap visible from the receiver.
const CONE: f32 = 0.9;

impl Light {
    /// A point `x0` for a once-more connection to `p`. Sphere: with
    /// probability [`CONE`] a point of the cap visible from `p` (uniform in
    /// solid angle from `p`), else uniform on the whole sphere, so every
    /// point that can light some `x1` has a positive density; its area
    /// density is `CONE · pdf_cone + (1 − CONE)/(4π r²)`.
    pub(super) fn once_more_origin(&self, p: Vec3, rng: &mut Rng) -> Option<LightVertex> {
        if self.radius == 0.0 {
            return Some(LightVertex {
                x0: self.center,
                n0: None,
                emitted: self.intensity,
            });
        }
        let (u0, u1, u2): (f32, f32, f32) = (rng.uniform(), rng.uniform(), rng.uniform());
        let y = if u0 < CONE {
            self.sample_from(p, [u1, u2])?.y
        } else {
            self.sample_area([u1, u2])
        };
        let pdf = self.origin_pdf(p, y);
        Some(LightVertex {
            x0: y,
            n0: Some((y - self.center) / self.radius),
            emitted: self.radiance / pdf,
        })
    }

    /// The area density at `y` on the sphere of
    /// [`once_more_origin`](Self::once_more_origin)`(p)`:
    /// `CONE · pdf_cone(y) + (1 − CONE)/(4π r²)`.
    pub(super) fn origin_pdf(&self, p: Vec3, y: Vec3) -> f32 {
        CONE * self.cone_area_pdf(p, y) + (1.0 - CONE) / self.area()
    }
}

/// A once-more connection whose OMNEE vertex is still to be drawn: the
/// light point, the connection `x0 → p` and the three uniform numbers of
/// its vertex, so that a renderer can draw the vertices of many
/// connections in one call (`omnee_core::sampling::Connections`) and
/// finish each with [`SlabWorld::once_more_finish`].
#[derive(Clone, Copy, Debug)]
pub struct PendingVertex {
    light: LightVertex,
    /// The connection from the light point to the receiver.
    pub connection: Connection<f32>,
    /// The vertex's uniform numbers.
    pub u: [f32; 3],
}

/// Where [`SlabWorld::once_more_start`] left a once-more estimate.
#[derive(Clone, Copy, Debug)]
pub enum OnceMoreStart {
    /// The estimate, complete (no connection, or a technique other than
    /// OMNEE, drawn and evaluated at once).
    Done(f32),
    /// OMNEE's vertex is to be drawn.
    Vertex(PendingVertex),
}

/// OMNEE's vertices for many pending connections, drawn in one call of the
/// core's batch over connections: the connections' end points, numbers and
/// vertices by coordinate, reused from one batch to the next.
#[derive(Clone, Debug, Default)]
pub struct VertexBatch {
    /// `x0`, `x2` and the three uniform numbers, by coordinate.
    inputs: [Vec<f32>; 9],
    /// `x1`, the density and the weight by lane.
    x1: [Vec<f32>; 3],
    pdf: Vec<f32>,
    weight: Vec<f32>,
    valid: Vec<bool>,
}

impl VertexBatch {
    /// Draws OMNEE's vertex of every connection of `pending` (all with θmax
    /// `theta_max`) with `world`'s phase function, each bit for bit the
    /// vertex [`SlabWorld::once_more`] draws,
    /// `Omnee::new(connection, phase).sample(u)`; lane `i` is then
    /// [`VertexBatch::sample`]`(i)`.
    pub fn draw(&mut self, world: &SlabWorld<'_>, pending: &[PendingVertex], theta_max: f32) {
        let n = pending.len();
        for column in self.inputs.iter_mut().chain(&mut self.x1) {
            column.clear();
        }
        for v in pending {
            let (a, b) = (v.connection.axis.x0, v.connection.axis.x2);
            let lane = [a.x, a.y, a.z, b.x, b.y, b.z, v.u[0], v.u[1], v.u[2]];
            for (column, value) in self.inputs.iter_mut().zip(lane) {
                column.push(value);
            }
        }
        for column in &mut self.x1 {
            column.resize(n, 0.0);
        }
        for column in [&mut self.pdf, &mut self.weight] {
            column.clear();
            column.resize(n, 0.0);
        }
        self.valid.clear();
        self.valid.resize(n, false);
        let [x0x, x0y, x0z, x2x, x2y, x2z, u0, u1, u2] = &self.inputs;
        let [x, y, z] = &mut self.x1;
        let drawn = Connections::new(
            Points {
                x: x0x,
                y: x0y,
                z: x0z,
            },
            Points {
                x: x2x,
                y: x2y,
                z: x2z,
            },
            theta_max,
        )
        .and_then(|c| {
            c.sample_omnee(
                world.sampler(),
                Uniforms { u0, u1, u2 },
                SampleArrays {
                    x1: PointsMut { x, y, z },
                    pdf: &mut self.pdf,
                    weight: &mut self.weight,
                    valid: &mut self.valid,
                },
            )
        });
        if drawn.is_err() {
            // The arrays are made to fit and θmax is the connections' own:
            // draw them one by one all the same.
            for (i, v) in pending.iter().enumerate() {
                let s = Omnee::new(v.connection, world.sampler()).sample(v.u);
                self.valid[i] = s.is_some();
                if let Some(s) = s {
                    (self.x1[0][i], self.x1[1][i], self.x1[2][i]) = (s.x1.x, s.x1.y, s.x1.z);
                    (self.pdf[i], self.weight[i]) = (s.pdf, s.weight);
                }
            }
        }
    }

    /// Lane `i`'s vertex, if it has one.
    pub fn sample(&self, i: usize) -> Option<Sample<f32>> {
        self.valid[i].then(|| Sample {
            x1: Vec3::new(self.x1[0][i], self.x1[1][i], self.x1[2][i]),
            pdf: self.pdf[i],
            weight: self.weight[i],
        })
    }
}

impl SlabWorld<'_> {
    /// One-sample estimate of the once-more scattered irradiance at `p`
    /// (normal `n`): light → `x1` in the slab → `p`, the sum of
    /// `once_more_vertex` over the draw's vertices.
    pub fn once_more(
        &self,
        p: Vec3,
        n: Vec3,
        how: OnceMore,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        match self.once_more_start(p, n, how, rng, roulette, stats) {
            OnceMoreStart::Done(e) => e,
            OnceMoreStart::Vertex(v) => {
                let sample = Omnee::new(v.connection, self.sampler()).sample(v.u);
                self.once_more_finish(&v, (p, n), sample, rng, roulette, stats)
            }
        }
    }

    /// [`once_more`](Self::once_more) up to OMNEE's vertex: the light
    /// point, the connection and the vertex's three numbers, drawn from
    /// `rng` in the order `once_more` draws them. Other techniques are
    /// drawn and evaluated here.
    pub fn once_more_start(
        &self,
        p: Vec3,
        n: Vec3,
        how: OnceMore,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> OnceMoreStart {
        let Some(light) = self.light.once_more_origin(p, rng) else {
            return OnceMoreStart::Done(0.0);
        };
        stats.connections += 1;
        if !self.slab.may_reach(light.x0, p, how.theta_max) {
            stats.skipped_unreachable += 1;
            return OnceMoreStart::Done(0.0);
        }
        let Ok(connection) = Connection::new(light.x0, p, how.theta_max) else {
            return OnceMoreStart::Done(0.0);
        };
        if how.method == Method::Omnee {
            let u = [rng.uniform(), rng.uniform(), rng.uniform()];
            return OnceMoreStart::Vertex(PendingVertex {
                light,
                connection,
                u,
            });
        }
        // Ray methods draw cosine-weighted directions about the normal.
        let Ok(directions) = Directions::cosine(n) else {
            return OnceMoreStart::Done(0.0);
        };
        let [first, companion] = self
            .setup
            .with_directions(directions)
            .draw(how.method, connection, || rng.uniform())
            .vertices;
        if first.is_none() {
            stats.no_vertex += 1;
        }
        OnceMoreStart::Done(
            [first, companion]
                .into_iter()
                .flatten()
                .map(|s| self.once_more_vertex(light, (p, n), s, rng, roulette, stats))
                .sum(),
        )
    }

    /// The once-more estimate from OMNEE's `sample` for the pending
    /// connection `v` to the receiver `(p, n)` (its roulette drawing from
    /// `rng`, which continues the one `once_more_start` drew from).
    pub fn once_more_finish(
        &self,
        v: &PendingVertex,
        (p, n): (Vec3, Vec3),
        sample: Option<Sample<f32>>,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        match sample {
            Some(s) => self.once_more_vertex(v.light, (p, n), s, rng, roulette, stats),
            None => {
                stats.no_vertex += 1;
                0.0
            }
        }
    }

    /// The contribution `f_c · weight` of one vertex `x1` of a once-more
    /// connection from the light point to the receiver `(p, n)`:
    /// `emitted · cos θ0 · T(x0, x1) · σs · T(x1, p) · cos θ2 · weight`
    /// (closed-form transmittance on both legs), then the roulette and the
    /// visibility tests. 0 for a vertex outside the slab (or below the
    /// opaque floor) or with weight 0.
    fn once_more_vertex(
        &self,
        light: LightVertex,
        (p, n): (Vec3, Vec3),
        sample: Sample<f32>,
        rng: &mut Rng,
        roulette: Roulette,
        stats: &mut SlabStats,
    ) -> f32 {
        let LightVertex { x0, n0, emitted } = light;
        let x1 = sample.x1;
        if !(sample.weight > 0.0 && self.slab.contains(x1) && x1.z >= self.floor.z) {
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
            * self.slab.sigma_s
            * self.transmittance(x1, p)
            * cos2
            * sample.weight;
        if !e.is_finite() {
            return 0.0;
        }
        let Some(e) = roulette.play(e, rng, stats) else {
            return 0.0;
        };
        if self.occluded(x0, x1, stats) || self.occluded(x1, p, stats) || self.light.blocks(x1, p) {
            return 0.0;
        }
        e
    }
}
