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
        // A ray within rounding of the eye (`EquiangularLine` has no
        // density about a point on its line) adds nothing: its light, ∝ 1/D
        // at the distance D from the eye, is infinite on the line, and free
        // flight, drawing points next to the eye with the weight 1/d², gave
        // one path 10¹⁰ times the image's mean. Such rays, closer than
        // 10⁻⁶ (1 + |Δ|) m, carry less than 10⁻⁵ of the layer's light
        // (docs/math.md §13.6).
        let Some(line) = EquiangularLine::new(y + dt * ta, dt, tb - ta, self.camera.eye) else {
            return;
        };
        let n = self.samples[1];
        let k = ((n as f32 * line.angle() / self.camera.fov()).ceil() as u32).clamp(1, 16 * n);
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
        let along = |u: f32| ta + line.sample(u);
        let (t, pdf) = match self.shafts {
            ShaftSampling::Equiangular => {
                let t = along(u0);
                (t, line.pdf(t - ta))
            }
            ShaftSampling::Mis => {
                let t = if u0 < 0.5 {
                    along(2.0 * u0)
                } else {
                    flight([2.0 * u0 - 1.0, u1])
                };
                (t, 0.5 * (line.pdf(t - ta) + free(t)))
            }
            ShaftSampling::FreeFlight => {
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
/// counted from `ta`).
#[derive(Clone, Copy, Debug)]
struct Segment {
    y: Vec3,
    dt: Vec3,
    ta: f32,
    tb: f32,
    line: EquiangularLine,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::TableStorage;
    use crate::scenes::underwater::UnderwaterScene;

    /// A refracted sun ray through the eye, the camera looking along it:
    /// its image is one point, where its light, ∝ 1/D at the distance D
    /// from the eye, is infinite. It adds nothing (before, free flight on
    /// the ray drew vertices next to the eye with the weight 1/d², whose
    /// mean is infinite), for each way of sampling the shafts; a ray 1 mm
    /// from the eye adds its light.
    #[test]
    fn a_ray_through_the_eye_adds_nothing() {
        // The sun 38° above the horizon; the beam's direction through a flat
        // surface, to look along it.
        let text = |look_at: Vec3| {
            format!(
                r#"
[sun]
direction = [0.35, 0.45, 0.45]
angular_radius_deg = 0.0
[surface]
kind = "flat"
[water]
sigma_s = [0.10, 0.18, 0.06]
sigma_a = [0.30, 0.06, 0.02]
phase = "hg:0.4"
[floor]
z = -6.0
[camera]
position = [0.0, -1.0, -1.5]
look_at = {:?}
fov = 35.0
width = 16
height = 12
[render]
terms = ["shafts"]
"#,
                look_at.to_array()
            )
        };
        let eye = Vec3::new(0.0, -1.0, -1.5);
        let probe = UnderwaterScene::parse(&text(eye + Vec3::Y)).unwrap();
        let mut storage = TableStorage::<f32>::default();
        let phase = probe.phase.instantiate(&mut storage).unwrap();
        let dt = UnderwaterWorld::new(&probe, phase, 16, 12).region.beam;
        let scene = UnderwaterScene::parse(&text(eye + dt)).unwrap();
        let phase = scene.phase.instantiate(&mut storage).unwrap();
        let mut world = UnderwaterWorld::new(&scene, phase, 16, 12);
        // The surface point whose refracted ray passes through the eye, and
        // one whose ray passes 1 mm beside it.
        let y = eye - dt * (eye.z / dt.z);
        let (side, _) = dt.any_orthonormal_pair();
        for sampling in ShaftSampling::ALL {
            world.shafts = *sampling;
            for (offset, lit) in [(0.0, false), (1e-3, true)] {
                let y = y + side * offset;
                let len = (world.floor.z - y.z) / dt.z;
                let mut rng = Rng::stream(7, 0, 0);
                let (mut out, mut stats) = (Vec::new(), UnderwaterStats::default());
                world.shafts(y, dt, len, 1.0, &mut rng, &mut out, &mut stats);
                assert_eq!(!out.is_empty(), lit, "{sampling:?}, {offset} m: {out:?}");
            }
        }
    }
}
