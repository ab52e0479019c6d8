//! `shafts-once-more`: points on the refracted sun ray in the water,
//! connected to the eye once more through `x1`, with the phase function's
//! lobe at those points (docs/math.md §12, §13.6).

use super::{Splat, UnderwaterStats, UnderwaterTerm, UnderwaterWorld, uniform3};
use crate::rng::Rng;
use glam::Vec3;
use omnee_core::lobe::PhaseLobe;
use omnee_core::sampling::{Connection, Technique};

impl UnderwaterWorld<'_> {
    /// `shafts-once-more` for the refracted ray `y + t d_t`, `t ∈ [0, len]`,
    /// carrying `power`: `m` vertices `x0 = y + t d_t` (`m` the once-more
    /// draws per floor point), `t` by free flight (the channel mixture, its
    /// distance stratified), each scattering
    /// `Φ T(t) σs / (m pdf(t))` towards [`Self::shaft_once_more`]. The
    /// whole ray counts: `x1`, not `x0`, must be in view.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn shafts_once_more(
        &self,
        y: Vec3,
        dt: Vec3,
        len: f32,
        power: f32,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let m = self.samples[0];
        for i in 0..m {
            let [u0, u1, _] = uniform3(rng);
            let t = self
                .water
                .free_flight(len, [u0, (i as f32 + u1) / m as f32]);
            let pdf = self.water.free_flight_pdf(len, t);
            if !(pdf > 0.0) {
                continue;
            }
            let flux =
                self.water.transmittance(t) * self.water.sigma_s * (power / (m as f32 * pdf));
            self.shaft_once_more(y + dt * t, dt, flux, rng, out, stats);
        }
    }

    /// `shafts-once-more` from the vertex `x0` in the water, where the sun's
    /// light arrives along `incoming` with `flux` per channel (σs at `x0`
    /// included): for the vertex `x1` of the scene's [`LobeMethod`](omnee_core::method::LobeMethod),
    /// `flux σs T(d1 + d2) W(ω1) · k/pdf` with
    /// `k = p0(ω_in · ω01) p1(θ) / (d1² d2²)` (docs/math.md §12.1, §13.6).
    pub fn shaft_once_more(
        &self,
        x0: Vec3,
        incoming: Vec3,
        flux: Vec3,
        rng: &mut Rng,
        out: &mut Vec<Splat>,
        stats: &mut UnderwaterStats,
    ) {
        let eye = self.camera.eye;
        let Ok(connection) = Connection::new(x0, eye, self.once_more.theta_max) else {
            return;
        };
        let Ok(lobe) = PhaseLobe::new(&self.phase, incoming) else {
            return;
        };
        let sample = self
            .lobe
            .technique(connection, lobe, &self.phase)
            .sample(uniform3(rng));
        let Some(s) = sample else {
            stats.no_vertex += 1;
            return;
        };
        self.splat_once_more(
            UnderwaterTerm::ShaftsOnceMore,
            x0,
            s,
            flux,
            false,
            out,
            stats,
        );
    }
}
