//! The point-to-point problem with a lobe at `x0`, and its quadrature
//! reference over all three coordinates (docs/math.md §12).

use super::Lobe;
use crate::error::Error;
use crate::phase::{Deflection, PhaseFunction};
use crate::quadrature::Budget;
use crate::real::{Real, sinc};
use crate::reference::{PointToPoint, Scale, transmittance};
use crate::sampling::Sample;

/// Geometric levels of the quadrature panels towards a peak: the first
/// panel is `2⁻²⁰` of its interval, a thousandth of the width 1e-3 of a
/// g = 0.999 lobe.
const LEVELS: u32 = 20;

/// [`PointToPoint`] with an optional lobe at `x0`: a point light of unit
/// intensity whose light arrives at `x0` along `ω_in` and leaves with the
/// lobe `p0(ω_in · ω01)` (`None`: `p0 ≡ 1`, the plain problem):
///
/// `I = ∫ σs p0(ω_in · ω01) p1(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1`
/// over θ < θmax, the receiver's cosine `cos θ2` only without a lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeToPoint<F: Real, L> {
    /// End points, θmax, medium and receiver.
    pub point: PointToPoint<F>,
    /// The lobe at `x0`, if any.
    pub lobe: Option<L>,
}

impl<F: Real, L: Lobe<F>> LobeToPoint<F, L> {
    /// The problem `point` with `lobe` at `x0`. A lobe together with a
    /// receiver normal is refused (field `"receiver_normal"`): the receiver's
    /// cosine couples φ with β, so the reference would nest all three
    /// quadratures (measured: more than 20 minutes at a loose tolerance).
    pub fn new(point: PointToPoint<F>, lobe: Option<L>) -> Result<Self, Error> {
        if lobe.is_some() && point.receiver_normal.is_some() {
            return Err(Error::Degenerate {
                field: "receiver_normal",
                reason: "not supported with a lobe at x0 (a point receiver only)",
            });
        }
        Ok(Self { point, lobe })
    }

    /// `p0(ω01)` at `x1` (1 without a lobe, 0 at `x0` itself).
    #[inline]
    pub fn lobe_at(&self, x1: F::Vec3) -> F {
        match &self.lobe {
            Some(lobe) => super::eval_towards(lobe, self.point.connection.axis.x0, x1),
            None => F::ONE,
        }
    }

    /// The kernel `k(x1) = p0(ω01) p1(θ) / (d1² d2²)` for θ < θmax, else 0:
    /// what every technique of [`crate::lobe`] returns `k/pdf` of.
    #[inline]
    pub fn kernel<P: PhaseFunction<F>>(&self, phase: &P, x1: F::Vec3) -> F {
        self.lobe_at(x1) * self.point.connection.kernel(phase, x1)
    }

    /// The factors no technique samples, `σs e^{−σt (d1 + d2)} [cos θ2]`
    /// ([`PointToPoint::f_c`]); the lobe is in every technique's weight.
    #[inline]
    pub fn f_c(&self, x1: F::Vec3) -> F {
        self.point.f_c(x1)
    }

    /// The one-sample estimate `f_c(x1) · k(x1)/pdf(x1)` of a technique of
    /// [`crate::lobe`] (or, without a lobe, of [`crate::sampling`]).
    #[inline]
    pub fn estimate(&self, sample: &Sample<F>) -> F {
        self.point.estimate(sample)
    }
}

impl<L: Lobe<f64>> LobeToPoint<f64, L> {
    /// The integrand evaluations [`Self::try_integral`] may spend with a
    /// lobe: about three times the 3.5·10⁷ a θmax = π problem takes (a
    /// minute at most on one core); without a lobe
    /// [`PointToPoint::BUDGET`] applies.
    pub const BUDGET: u64 = 100_000_000;

    /// The reference value of `I` ([`Self::try_integral`]), or NaN if the
    /// quadrature did not converge within its budget.
    pub fn integral<P: PhaseFunction<f64>>(&self, phase: &P) -> f64 {
        self.try_integral(phase).unwrap_or(f64::NAN)
    }

    /// The reference value of `I` by quadrature (without a lobe,
    /// [`PointToPoint::try_integral`]), or `Error::NotConverged` (field
    /// `"reference"`) once [`Self::BUDGET`] evaluations are spent. In the angles α (at `x0`), θ and φ of
    /// [`crate::circumcircle`], where `dβ dθ = dα dθ`,
    ///
    /// `I = (σs/s) ∫₀^θmax Φ0(α) ∫_α^θmax p1(θ) e^{−σt (d1 + d2)} dθ dα`,
    /// `Φ0(α) = ∫₀^{2π} p0(ω(α, φ)) dφ`,
    ///
    /// `ω(α, φ) = cos α e + sin α (cos φ b1 + sin φ b2)`,
    /// `d1 + d2 = s (sin β + sin α)/sin θ` with β = θ − α (in sinc form).
    /// Each coordinate by adaptive Gauss–Kronrod with geometric panels towards
    /// its features: θ towards α (p1's peak) and θmax, φ towards the lobe's
    /// azimuth and its opposite, α towards 0 and the lobe's angle γ with the
    /// axis and π − γ. About 3.5e7 evaluations for θmax = π (4–10 s on the
    /// shared 2-core machine), relative accuracy about 1e-9 for smooth lobes.
    pub fn try_integral<P: PhaseFunction<f64>>(&self, phase: &P) -> Result<f64, Error> {
        let Some(lobe) = &self.lobe else {
            return self.point.try_integral(phase);
        };
        let budget = Budget::new(Self::BUDGET);
        let scale = self.point.scale();
        let value = self.lobe_quadrature(lobe, &scale, phase, &budget);
        scale.finish(&budget, value)
    }

    /// The quadrature of [`Self::try_integral`] with a lobe, against
    /// `budget`, with path lengths in units of `s` and the optical
    /// thickness `σt s`, but for the power of two of `scale` ([`Scale`]).
    fn lobe_quadrature<P: PhaseFunction<f64>>(
        &self,
        lobe: &L,
        scale: &Scale,
        phase: &P,
        budget: &Budget,
    ) -> f64 {
        let axis = &self.point.connection.axis;
        let (tau, theta_max) = (scale.tau, scale.theta_max);
        let (e, b1, b2) = (axis.e, axis.b1, axis.b2);
        // Each level's tolerance sits above the rounding noise of the
        // integrals inside it, or the outer adaptive rule would bisect noise.
        let (tol_theta, tol_phi, tol_alpha) = (1e-12, 1e-11, 1e-9);

        // ∫_α^θmax p1(θ) T dθ.
        let over_theta = |alpha: f64| {
            let f = |theta: f64| {
                // Reflected panels may round a hair past θmax (and π).
                let theta = theta.clamp(alpha, theta_max);
                let beta = theta - alpha;
                // (d1 + d2)/s.
                let path = if theta > 0.0 {
                    (beta * sinc(beta) + alpha * sinc(alpha)) / (theta * sinc(theta))
                } else {
                    1.0
                };
                phase.eval(Deflection::from_theta(theta)) * transmittance(tau, path)
            };
            // Panels towards α (p1's peak) and, in the upper half, towards
            // θmax: near θ = π the path is long except in a layer of width
            // about α next to π.
            let mid = 0.5 * (alpha + theta_max);
            budget.integrate_geometric(&f, alpha, mid, LEVELS, tol_theta)
                + budget.integrate_geometric(
                    |t| f(theta_max + alpha - t),
                    alpha,
                    mid,
                    LEVELS,
                    tol_theta,
                )
        };

        // Φ0(α) as ∫₀^π h(φ_in + ψ) + h(φ_in − ψ) dψ, panels towards ψ = 0
        // and ψ = π (the lobe's azimuth φ_in and its opposite).
        let a = lobe.axis();
        let gamma = e.cross(a).length().atan2(e.dot(a));
        let phi_in = a.dot(b2).atan2(a.dot(b1));
        let around = |alpha: f64| {
            let (sin_alpha, cos_alpha) = (libm::sin(alpha), libm::cos(alpha));
            let h = |phi: f64| {
                let radial = b1 * libm::cos(phi) + b2 * libm::sin(phi);
                lobe.eval(e * cos_alpha + radial * sin_alpha)
            };
            let g = |psi: f64| h(phi_in + psi) + h(phi_in - psi);
            let half = core::f64::consts::FRAC_PI_2;
            budget.integrate_geometric(g, 0.0, half, LEVELS, tol_phi)
                + budget.integrate_geometric(
                    |psi| g(core::f64::consts::PI - psi),
                    0.0,
                    half,
                    LEVELS,
                    tol_phi,
                )
        };
        let over_alpha = |alpha: f64| {
            let lobe_mass = around(alpha);
            if lobe_mass > 0.0 {
                lobe_mass * over_theta(alpha)
            } else {
                0.0
            }
        };
        scale.factor * split_integral(&over_alpha, theta_max, gamma, tol_alpha, budget)
    }
}

/// `∫₀^b f(α) dα` split at γ and π − γ (those inside), every piece halved
/// and each half integrated with geometric panels towards its outer end, so
/// that a peak at 0, at b or at a split point is resolved.
fn split_integral(f: &dyn Fn(f64) -> f64, b: f64, gamma: f64, tol: f64, budget: &Budget) -> f64 {
    let pi = core::f64::consts::PI;
    let cuts = [
        0.0,
        gamma.min(pi - gamma).clamp(0.0, b),
        gamma.max(pi - gamma).clamp(0.0, b),
        b,
    ];
    let mut sum = 0.0;
    for w in cuts.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        if !(hi > lo) {
            continue;
        }
        let mid = 0.5 * (lo + hi);
        sum += budget.integrate_geometric(f, lo, mid, LEVELS, tol)
            + budget.integrate_geometric(|x| f(hi - x + lo), lo, mid, LEVELS, tol);
    }
    sum
}
