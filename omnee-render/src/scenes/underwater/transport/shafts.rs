//! `shafts`: a point on the refracted sun ray in the water straight to the
//! eye, the god rays (docs/math.md §13.6).

use super::{Splat, UnderwaterStats, UnderwaterTerm, UnderwaterWorld, uniform3};
use crate::rng::Rng;
use crate::scenes::underwater::water::EquiangularLine;
use glam::Vec3;
use omnee_core::names::Named;
use omnee_core::phase::{Deflection, PhaseFunction};

/// How the shafts term places its vertex on the refracted sun ray
/// (`render.shafts`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaftSampling {
    /// Free-flight distance from the channel mixture of σt.
    FreeFlight,
    /// Equiangular distance about the eye.
    Equiangular,
    /// One of the two with probability ½ each, weighted by the mixture
    /// density (one-sample MIS with the balance heuristic).
    Mis,
}

impl Named for ShaftSampling {
    const ALL: &'static [Self] = &[
        ShaftSampling::FreeFlight,
        ShaftSampling::Equiangular,
        ShaftSampling::Mis,
    ];
    fn name(self) -> &'static str {
        match self {
            ShaftSampling::FreeFlight => "free-flight",
            ShaftSampling::Equiangular => "equiangular",
            ShaftSampling::Mis => "mis",
        }
    }
    fn help(self) -> &'static str {
        match self {
            ShaftSampling::FreeFlight => "free-flight distance from the channel mixture of sigma_t",
            ShaftSampling::Equiangular => "equiangular distance about the eye",
            ShaftSampling::Mis => "one of the two with probability 1/2 each, balance heuristic",
        }
    }
}

impl UnderwaterWorld<'_> {
    /// `shafts` for the refracted ray `y + t d_t`, `t ∈ [0, len]`, carrying
    /// `power`: its part `[ta, tb]` in the view frustum (the integrand is 0
    /// elsewhere) gets `k` vertices, stratified in the sampler's uniform
    /// number, `k = ⌈n (θb − θa)/fov⌉ ∈ [1, 16n]` with `θb − θa` the angle
    /// the part subtends at the eye and `n` the scene's `shaft_samples`:
    /// about one vertex per `fov/n` of its image, so a ray passing close to
    /// the eye, whose image crosses the picture with a weight `∝ 1/D`, is
    /// drawn as a line of many small splats rather than a few bright dots.
    /// `k` depends on the ray only, and the strata's mean is unbiased.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn shafts(
        &self,
        y: Vec3,
        dt: Vec3,
        len: f32,
        power: f32,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let Some((ta, tb)) = self.camera.clip(y, dt, 0.0, len) else {
            return;
        };
        let line = EquiangularLine::new(y + dt * ta, dt, tb - ta, self.camera.eye);
        let n = self.samples[1];
        let k = match line {
            Some(l) => {
                let k = (n as f32 * l.angle() / self.camera.fov()).ceil();
                (k as u32).clamp(1, 16 * n)
            }
            None => n,
        };
        let segment = Segment {
            y,
            dt,
            ta,
            tb,
            line,
        };
        for i in 0..k {
            let [u0, u1, _] = uniform3(rng);
            let u0 = (i as f32 + u0) / k as f32;
            self.shaft(&segment, [u0, u1], power / k as f32, out, stats);
        }
    }

    /// One `shafts` vertex `x = y + t d_t` on `segment`:
    /// `Φ T(y, x) σs p(θ) T(x, eye) W(ω) / (d² pdf(t))`, `t` drawn by the
    /// scene's [`ShaftSampling`] on `[ta, tb]`.
    fn shaft(
        &self,
        segment: &Segment,
        u: [f32; 2],
        power: f32,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let eye = self.camera.eye;
        let Segment {
            y,
            dt,
            ta,
            tb,
            line,
        } = *segment;
        let [u0, u1] = u;
        // Free flight from `ta`: the truncated exponential on `[ta, tb]`.
        let free = |t: f32| self.water.free_flight_pdf(tb - ta, t - ta);
        let flight = |u: [f32; 2]| ta + self.water.free_flight(tb - ta, u);
        let along = |l: EquiangularLine, u: f32| ta + l.sample(u);
        let (t, pdf) = match (self.shafts, line) {
            (ShaftSampling::Equiangular, Some(l)) => {
                let t = along(l, u0);
                (t, l.pdf(t - ta))
            }
            (ShaftSampling::Mis, Some(l)) => {
                let t = if u0 < 0.5 {
                    along(l, 2.0 * u0)
                } else {
                    flight([2.0 * u0 - 1.0, u1])
                };
                (t, 0.5 * (l.pdf(t - ta) + free(t)))
            }
            // Free flight, or the eye on the ray's line (no equiangular density).
            _ => {
                let t = flight([u0, u1]);
                (t, free(t))
            }
        };
        let x = y + dt * t;
        let Some(p) = self.camera.project(x) else {
            return;
        };
        let v = eye - x;
        let d2 = v.length_squared();
        let d = d2.sqrt();
        if !(d > 0.0 && pdf > 0.0 && self.clear(x, eye, stats)) {
            return;
        }
        let phase = self.phase.eval(Deflection::between_segments(dt, 1.0, v, d));
        let value = self.water.transmittance(t + d)
            * self.water.sigma_s
            * (power * phase * p.importance / (d2 * pdf));
        self.splat(UnderwaterTerm::Shafts, p, value, out, stats);
    }
}

/// The part of a refracted sun ray `y + t d_t` the camera sees,
/// `t ∈ [ta, tb]`, and the equiangular sampler about the eye on it (`t`
/// counted from `ta`; `None` when the eye is on the ray's line).
#[derive(Clone, Copy, Debug)]
struct Segment {
    y: Vec3,
    dt: Vec3,
    ta: f32,
    tb: f32,
    line: Option<EquiangularLine>,
}
