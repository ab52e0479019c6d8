//! The point-to-point test problem of docs/math.md §5 and its quadrature reference.
//!
//! A unit-intensity point light at `x0`, a point receiver at `x2` (optionally
//! with a one-sided cosine about a normal), an infinite homogeneous medium and
//! the integrand restricted to θ < θmax:
//!
//! `I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1`.
//!
//! In the coordinates of [`crate::circumcircle`], with `dx1 = (d1² d2² / s) dθ dβ dφ`
//! and `β = rθ`:
//!
//! `I = (σs/s) ∫₀^θmax p(θ) θ ∫₀¹ e^{−σt s (r sinc β + (1−r) sinc α)/sinc θ} Φ(β) dr dθ`,
//!
//! where `Φ = 2π` without a receiver cosine and, with the normal at angle γ
//! from `x0 − x2`, `Φ(β) = ∫₀^{2π} max(0, cos β cos γ + sin β sin γ cos φ) dφ`
//! in closed form. The double integral is done by adaptive Gauss–Kronrod in
//! f64 with geometric panels towards θ = 0 (the forward peak).

use crate::circumcircle::Axis;
use crate::error::Error;
use crate::medium::Homogeneous;
use crate::phase::{Deflection, PhaseFunction};
use crate::quadrature::{Budget, Towards};
use crate::real::{Real, Vector, cast, cast_vec, sinc};
use crate::sampling::{Connection, Sample, unit_normal};

/// The point-to-point problem: end points, θmax, medium and receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointToPoint<F: Real> {
    /// End points and θmax.
    pub connection: Connection<F>,
    /// The infinite homogeneous medium.
    pub medium: Homogeneous<F>,
    /// Unit normal at `x2` for a one-sided receiver cosine
    /// `cos θ2 = max(0, n · (x1 − x2)/d2)`; `None` for a point receiver.
    pub receiver_normal: Option<F::Vec3>,
}

impl<F: Real> PointToPoint<F> {
    /// The integrand evaluations [`Self::try_integral`] may spend: six
    /// times the most that 300 random receiver normals with θmax up to π
    /// and σt s up to 30 took (1.6·10⁶, 0.16 s), about two seconds of one
    /// core at most; typical problems take 10⁴–10⁶ (milliseconds).
    pub const BUDGET: u64 = 10_000_000;

    /// The problem for `connection` in `medium`; `receiver_normal` is
    /// normalised here ([`unit_normal`]: any finite, non-zero length; a NaN
    /// or infinite component is `NotFinite`, the zero vector `Degenerate`,
    /// field `"receiver_normal"`).
    pub fn new(
        connection: Connection<F>,
        medium: Homogeneous<F>,
        receiver_normal: Option<F::Vec3>,
    ) -> Result<Self, Error> {
        let receiver_normal = match receiver_normal {
            None => None,
            Some(n) => Some(unit_normal::<F>(n, "receiver_normal")?),
        };
        Ok(Self {
            connection,
            medium,
            receiver_normal,
        })
    }

    /// The factors no technique samples:
    /// `f_c(x1) = σs e^{−σt (d1 + d2)} [max(0, n·(x1 − x2)/d2)]`,
    /// with `d1`, `d2` in the connection's unit `L` and `σt L` per unit
    /// (the same optical depth), so that neither the distances nor their
    /// squares leave the range at any scale (docs/math.md §15).
    #[inline]
    pub fn f_c(&self, x1: F::Vec3) -> F {
        let axis = &self.connection.axis;
        let (a, b) = (axis.from_x0_unit(x1), axis.from_x2_unit(x1));
        let (d1, d2) = (a.length(), b.length());
        let cosine = match self.receiver_normal {
            None => F::ONE,
            Some(n) if d2 > F::ZERO => (n.dot(b) / d2).max(F::ZERO),
            Some(_) => F::ZERO,
        };
        let sigma_t = self.medium.sigma_t();
        // Without extinction T = 1 at any distance (exp(−0 · ∞) would be NaN).
        let transmittance = if sigma_t > F::ZERO {
            (-(sigma_t * axis.unit.length) * (d1 + d2)).exp()
        } else {
            F::ONE
        };
        self.medium.sigma_s() * transmittance * cosine
    }

    /// The one-sample estimate `f_c(x1) · k(x1)/pdf(x1)` of [`Self::integral`].
    #[inline]
    pub fn estimate(&self, sample: &Sample<F>) -> F {
        if sample.weight > F::ZERO {
            self.f_c(sample.x1) * sample.weight
        } else {
            F::ZERO
        }
    }

    /// The reference value of `I` by quadrature in f64 (relative accuracy
    /// about 1e-9 for smooth phase functions), or `NaN` if the quadrature
    /// did not converge within [`Self::BUDGET`] evaluations: see
    /// [`Self::try_integral`], which says so as an error.
    pub fn integral<P: PhaseFunction<f64>>(&self, phase: &P) -> f64 {
        self.try_integral(phase).unwrap_or(f64::NAN)
    }

    /// [`Self::integral`] with its outcome: the value, or
    /// `Error::NotConverged` (field `"reference"`) when the quadrature spent
    /// [`Self::BUDGET`] evaluations before meeting its tolerance. It never
    /// takes longer than the budget (a few seconds).
    ///
    /// The quadrature runs in the connection's unit `L = 2ᵏ` (docs/math.md
    /// §15), so it is the same at every scale: scaling the problem by a
    /// power of two λ (end points `λ x`, coefficients `σ/λ`) divides the
    /// value by λ² exactly, wherever both values are normal numbers. A value
    /// beyond f64's range is `+∞` (the C API's `OMNEE_ERROR_NOT_FINITE`), one
    /// below it 0.
    pub fn try_integral<P: PhaseFunction<f64>>(&self, phase: &P) -> Result<f64, Error> {
        let budget = Budget::new(Self::BUDGET);
        let scale = self.scale();
        let value = self.quadrature(&scale, phase, &budget);
        scale.finish(&budget, value)
    }

    /// The quadrature of [`Self::integral`] against `budget` (`+∞` where
    /// `I` is beyond f64's range): for a point
    /// receiver [`Self::point_integral_within`], with a receiver normal the
    /// integral of the clipped cosine split at its kinks (below).
    ///
    /// With a receiver normal at the angle γ from `x0 − x2`, `Φ(β)` has a
    /// kink wherever the cosine starts or stops clipping over φ:
    /// `β + γ = π/2` (it starts clipping) and `|β − γ| = π/2` (it is
    /// clipped everywhere) (docs/math.md §5.3). The r integral is split at
    /// `r = β_k/θ` and the θ integral at `θ = β_k` (where `inner(θ)` has a
    /// kink of its own), so that every piece is smooth: a kink inside a
    /// panel costs the adaptive rule its whole depth at every outer node,
    /// which near θ = π ran for hours.
    pub fn integral_within<P: PhaseFunction<f64>>(&self, phase: &P, budget: &Budget) -> f64 {
        let scale = self.scale();
        scale.apply(self.quadrature(&scale, phase, budget))
    }

    /// [`Self::integral_within`] but for the power of two of `scale`
    /// ([`Scale`]).
    fn quadrature<P: PhaseFunction<f64>>(&self, scale: &Scale, phase: &P, budget: &Budget) -> f64 {
        match self.receiver_normal {
            None => self.point_quadrature(scale, phase, budget),
            Some(n) => self.cosine_quadrature(n, scale, phase, budget),
        }
    }

    /// [`Self::integral_within`] for a point receiver, `Φ = 2π` (whatever
    /// `receiver_normal` holds; it is not read): the r integral in one
    /// piece, or in a thick medium two with geometric panels towards both
    /// ends, and the θ integral with geometric panels towards the forward
    /// peak. A caller that never has a normal (the browser demo) links
    /// only this, not the cosine's kinks and azimuthal integral.
    pub fn point_integral_within<P: PhaseFunction<f64>>(&self, phase: &P, budget: &Budget) -> f64 {
        let scale = self.scale();
        scale.apply(self.point_quadrature(&scale, phase, budget))
    }

    /// [`Self::point_integral_within`] but for the power of two of `scale`.
    fn point_quadrature<P: PhaseFunction<f64>>(
        &self,
        scale: &Scale,
        phase: &P,
        budget: &Budget,
    ) -> f64 {
        let (tau, theta_max) = (scale.tau, scale.theta_max);
        let tol = 1e-11;
        let inner = |theta: f64| {
            let tan_half = libm::tan(0.5 * theta);
            let over_r = |r: f64| {
                let (sin_x, cos_x) = libm::sincos(theta * r.min(1.0 - r));
                transmittance(tau, cos_x + tan_half * sin_x) * core::f64::consts::TAU
            };
            let levels = layer_levels(tau / sinc(theta));
            let pieces: &[(f64, f64, Towards)] = if levels > 0 {
                &[(0.0, 0.5, Towards::Start), (0.5, 1.0, Towards::End)]
            } else {
                &[(0.0, 1.0, Towards::Neither)]
            };
            budget.integrate_pieces(over_r, pieces, levels, tol)
        };
        let outer = |theta: f64| {
            if theta <= 0.0 {
                return 0.0;
            }
            phase.eval(Deflection::from_theta(theta)) * theta * inner(theta)
        };
        let pieces = [(0.0, theta_max, Towards::Start)];
        scale.factor * budget.integrate_pieces(outer, &pieces, 40, tol)
    }

    /// The problem's numbers as the quadrature takes them ([`Scale`]).
    pub(crate) fn scale(&self) -> Scale {
        Scale::new(
            &self.connection.axis,
            cast(self.medium.sigma_t()),
            cast(self.medium.sigma_s()),
            cast(self.connection.theta_max),
        )
    }

    /// [`Self::quadrature`] with the receiver cosine about the unit normal
    /// `n`, split at its kinks.
    fn cosine_quadrature<P: PhaseFunction<f64>>(
        &self,
        n: F::Vec3,
        scale: &Scale,
        phase: &P,
        budget: &Budget,
    ) -> f64 {
        let (tau, theta_max) = (scale.tau, scale.theta_max);
        let gamma = {
            let n = cast_vec::<F, f64>(n);
            let to_light = -cast_vec::<F, f64>(self.connection.axis.e);
            n.cross(to_light).length().atan2(n.dot(to_light))
        };
        let kinks = clipping_kinks(gamma);
        let tol = 1e-11;
        let (sin_gamma, cos_gamma) = libm::sincos(gamma);
        let inner = |theta: f64| {
            // d1 + d2 = s (sin β + sin α)/sin θ = s (cos x + tan(θ/2) sin x)
            // with x the smaller of β = rθ and α = (1 − r)θ: smooth in r to
            // the last bits even next to θ = π, where sin β/sin θ of the
            // rounded angles is noise of relative size ε/(π − θ), which the
            // adaptive rule would chase.
            let tan_half = libm::tan(0.5 * theta);
            let supplement = core::f64::consts::PI - theta;
            let kink_r = kinks.map(|beta| beta / theta);
            let over_r = |r: f64| {
                let x = theta * r.min(1.0 - r);
                let (sin_x, cos_x) = libm::sincos(x);
                let transmittance = transmittance(tau, cos_x + tan_half * sin_x);
                // (sin β, cos β), for r > ½ from π − β = (π − θ) + α.
                let (sin_beta, cos_beta) = if r <= 0.5 {
                    (sin_x, cos_x)
                } else {
                    let (sin_y, cos_y) = libm::sincos(supplement + x);
                    (sin_y, -cos_y)
                };
                // A ± B as sines of the offsets from the nearer kink, with
                // r − r_k exact next to it.
                let offset = |k: usize| theta * (r - kink_r[k]);
                let near = |k: usize| {
                    let d = offset(k);
                    if d.abs() <= core::f64::consts::FRAC_PI_2 {
                        libm::sin(d)
                    } else {
                        -libm::sin(offset(k + 1))
                    }
                };
                let (plus, minus) = (near(0), near(2));
                transmittance
                    * azimuthal_cosine((plus, minus), (sin_beta * sin_gamma, cos_beta * cos_gamma))
            };
            let levels = layer_levels(tau / sinc(theta));
            // Pieces between the kinks r = β_k/θ inside (0, 1) and, in a
            // thick medium, ½ between the two boundary layers, which the
            // pieces at the ends resolve with geometric panels.
            let [k0, k1, k2, k3] = kink_r;
            let (half, ends) = if levels > 0 {
                (0.5, (Towards::Start, Towards::End))
            } else {
                (f64::NAN, (Towards::Neither, Towards::Neither))
            };
            let (pieces, n) = pieces_between(0.0, 1.0, [k0, k1, k2, k3, half], ends);
            budget.integrate_pieces(over_r, pieces.get(..n).unwrap_or(&[]), levels, tol)
        };
        let outer = |theta: f64| {
            if theta <= 0.0 {
                return 0.0;
            }
            phase.eval(Deflection::from_theta(theta)) * theta * inner(theta)
        };
        // θ from 0 with geometric panels towards the forward peak, split at
        // the kinks θ = β_k inside (0, θmax).
        let [k0, k1, k2, k3] = kinks;
        let ends = (Towards::Start, Towards::Neither);
        let (pieces, n) = pieces_between(0.0, theta_max, [k0, k1, k2, k3, f64::NAN], ends);
        scale.factor * budget.integrate_pieces(outer, pieces.get(..n).unwrap_or(&[]), 40, tol)
    }
}

/// A reference problem's numbers as its quadrature takes them, in the
/// connection's unit `L = 2ᵏ`, `s = s_unit L` (docs/math.md §15), for
/// [`PointToPoint`] and [`crate::lobe::LobeToPoint`]. The integrals take
/// path lengths in units of `s` and the optical thickness `τ = σt s`, and
///
/// `I = (σs/s) J = (m/s_unit) J 2^(e − k)`,  `σs = m 2ᵉ`, `m ∈ [1, 2)`,
///
/// with the integral `J` and `m/s_unit` of order one at any scale: the
/// power of two is applied once, to the finished value
/// ([`Scale::finish`]). Formed in metres, `σs/s` overflowed for a subnormal
/// `s` while `I` itself was representable. Scaling the problem by a power
/// of two λ (`x → λ x`, `σ → σ/λ`) leaves `τ`, `m`, `s_unit` and `J` as
/// they are and moves the exponent by `−2 log₂ λ`: `I → I/λ²` exactly.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scale {
    /// The optical thickness of the connection `τ = σt s = (σt s_unit) 2ᵏ`.
    pub tau: f64,
    /// `m/s_unit`, the factor of `J` in `I` but for the power of two.
    pub factor: f64,
    /// θmax in f64, at most the true π: the f32 θmax = π rounds up
    /// (3.14159274 > π), and the quadrature stops where the triangle
    /// closes.
    pub theta_max: f64,
    /// `e − k`.
    exponent: i32,
}

impl Scale {
    /// The numbers of a problem on `axis` with σt, σs ≥ 0 (per metre) and
    /// θmax.
    pub fn new<F: Real>(axis: &Axis<F>, sigma_t: f64, sigma_s: f64, theta_max: f64) -> Self {
        let (s_unit, k) = (cast::<F, f64>(axis.s_unit), axis.unit.exponent);
        // σs = m 2ᵉ (σs = 0 keeps m = 0: I = 0).
        let e = if sigma_s > 0.0 { sigma_s.exponent() } else { 0 };
        Self {
            tau: (sigma_t * s_unit).scale_pow2(k),
            factor: sigma_s.scale_pow2(-e) / s_unit,
            theta_max: theta_max.min(core::f64::consts::PI),
            exponent: e - k,
        }
    }

    /// [`Self::apply`]`(value)` (`+∞` above f64's range, 0 below it) for a
    /// quadrature `value = (m/s_unit) J` that met its tolerance within
    /// `budget`, else `Error::NotConverged` (field `"reference"`).
    pub fn finish(&self, budget: &Budget, value: f64) -> Result<f64, Error> {
        budget.finish("reference", value).map(|v| self.apply(v))
    }

    /// `I = value 2^(e − k)`, rounded once.
    #[inline]
    pub fn apply(&self, value: f64) -> f64 {
        value.scale_pow2(self.exponent)
    }
}

/// The transmittance `e^{−τ ℓ}` along the path length `ℓ = (d1 + d2)/s` in
/// units of `s`, `τ = σt s`; 1 without extinction (at any length:
/// `e^{−0 · ∞}` would be NaN).
pub(crate) fn transmittance(tau: f64, path: f64) -> f64 {
    if tau > 0.0 {
        libm::exp(-tau * path)
    } else {
        1.0
    }
}

/// The levels of geometric panels for the r integral at the deflection θ,
/// from the optical thickness `σt s / sinc θ`: near θ = π the path length
/// is long except close to r = 0 and r = 1, layers of width
/// `≈ sinc θ / (σt s)` at both ends, resolved by geometric panels towards
/// each end; 0 (one plain piece) up to a thickness of 4. (∞ for σt s
/// beyond f64: `log2` saturates, so do the levels.)
fn layer_levels(thickness: f64) -> u32 {
    if thickness > 4.0 {
        (libm::log2(thickness) as u32).saturating_add(4).min(60)
    } else {
        0
    }
}

/// The deflections `β_k` at `x2` where the receiver cosine about a normal
/// at the angle γ from `x0 − x2` stops clipping (`A + B = cos(β − γ) = 0`:
/// `β = γ − π/2`, `γ + π/2`) or starts to (`B − A = −cos(β + γ) = 0`:
/// `β = π/2 − γ`, `3π/2 − γ`), in that order, pairs a half turn apart:
/// `A + B = sin(β − β₀) = −sin(β − β₁)`, `B − A = sin(β − β₂) =
/// −sin(β − β₃)`. Two of the four lie in (0, π) for every γ ≠ π/2.
fn clipping_kinks(gamma: f64) -> [f64; 4] {
    let (half_pi, pi) = (core::f64::consts::FRAC_PI_2, core::f64::consts::PI);
    [
        gamma - half_pi,
        gamma + half_pi,
        half_pi - gamma,
        pi + half_pi - gamma,
    ]
}

/// The pieces of `[lo, hi]` between the `cuts` strictly inside it (in any
/// order; NaN and cuts outside ignored), in order, and how many there are:
/// the piece from `lo` refined towards `ends.0`, the one to `hi` towards
/// `ends.1` (a single piece takes `ends.0`), the others `Neither`.
///
/// Plain loops over fixed arrays: the library's sort and slice indexing
/// would add kilobytes to the browser demo's module.
fn pieces_between(
    lo: f64,
    hi: f64,
    cuts: [f64; 5],
    ends: (Towards, Towards),
) -> ([(f64, f64, Towards); 6], usize) {
    // Cuts inside, then `hi` for the unused places; insertion sort.
    let mut points = cuts.map(|c| if c > lo && c < hi { c } else { hi });
    for i in 1..points.len() {
        let mut j = i;
        while j > 0 && points[j - 1] > points[j] {
            points.swap(j - 1, j);
            j -= 1;
        }
    }
    let mut pieces = [(lo, hi, Towards::Neither); 6];
    let (mut n, mut start) = (0, lo);
    for end in points.into_iter().chain([hi]) {
        if end > start {
            let towards = if start == lo {
                ends.0
            } else if end == hi {
                ends.1
            } else {
                Towards::Neither
            };
            if let Some(piece) = pieces.get_mut(n) {
                *piece = (start, end, towards);
                n += 1;
            }
            start = end;
        }
    }
    (pieces, n)
}

/// `Φ(β) = ∫₀^{2π} max(0, A + B cos φ) dφ` with `A = cos β cos γ`,
/// `B = sin β sin γ ≥ 0`: `2πA` if `A ≥ B`, 0 if `A ≤ −B`, else
/// `2(A φ₀ + B sin φ₀) = 2B (sin φ₀ − φ₀ cos φ₀)` with `cos φ₀ = −A/B`
/// (docs/math.md §5.3), from `A + B`, `B − A` and `(B, A)`.
///
/// Evaluated without cancellation next to both kinks: the caller forms
/// `A + B` and `B − A` as sines of the distance to the nearest kink
/// ([`clipping_kinks`]), small and accurate where the cosine starts or
/// stops clipping, `φ₀ = 2 atan2(√(A + B), √(B − A))`, and
/// `sin φ₀ − φ₀ cos φ₀` by its series for small φ₀, where it is `φ₀³/3`
/// and the two terms cancel. Formed from `A` and `B` instead, the
/// integrand next to a kink is rounding noise of relative size ε/φ₀²,
/// which an adaptive rule chases without end.
fn azimuthal_cosine((plus, minus): (f64, f64), (b, a): (f64, f64)) -> f64 {
    if minus <= 0.0 {
        return core::f64::consts::TAU * a;
    }
    if plus <= 0.0 {
        return 0.0;
    }
    let phi0 = 2.0 * libm::atan2(libm::sqrt(plus), libm::sqrt(minus));
    2.0 * b * sin_minus_x_cos(phi0)
}

/// `sin x − x cos x` for `x ∈ [0, π]`: its series
/// `x³/3 − x⁵/30 + x⁷/840 − x⁹/45360 + x¹¹/3991680` below 0.25 (next term
/// below 1e-16 relative), the difference above (cancelling at most six bits).
fn sin_minus_x_cos(x: f64) -> f64 {
    if x < 0.25 {
        let z = x * x;
        x * z
            * (1.0 / 3.0
                - z * (1.0 / 30.0 - z * (1.0 / 840.0 - z * (1.0 / 45360.0 - z / 3991680.0))))
    } else {
        let (sin, cos) = libm::sincos(x);
        sin - x * cos
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::{HenyeyGreenstein, Isotropic};
    use crate::quadrature::integrate_geometric;
    use glam::DVec3;

    fn problem(sigma_t: f64, theta_max: f64, normal: Option<DVec3>) -> PointToPoint<f64> {
        let c = Connection::new(DVec3::ZERO, DVec3::new(0.0, 0.0, 1.0), theta_max).unwrap();
        PointToPoint::new(c, Homogeneous::new(0.2, sigma_t - 0.2).unwrap(), normal).unwrap()
    }

    #[test]
    fn unattenuated_isotropic_integral_is_the_closed_form() {
        // Isotropic, σt → 0: I = (2π σs / s) ∫₀^θmax θ/(4π) dθ = σs θmax² / (4 s).
        // σs = 1e-300 makes the attenuation vanish; divide it out again.
        let c = Connection::new(
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, 2.0),
            core::f64::consts::FRAC_PI_2,
        )
        .unwrap();
        let p = PointToPoint::new(c, Homogeneous::new(1e-300, 0.0).unwrap(), None).unwrap();
        let got = p.integral(&Isotropic) / 1e-300;
        let want = core::f64::consts::FRAC_PI_2.powi(2) / (4.0 * 2.0);
        assert!((got - want).abs() < 1e-10 * want, "{got} vs {want}");
    }

    #[test]
    fn unattenuated_hg_matches_the_one_dimensional_form() {
        // σt → 0: I = (2π σs / s) ∫ p θ dθ (docs/math.md §5), by a separate 1-D quadrature.
        let hg = HenyeyGreenstein::new(0.9).unwrap();
        let c = Connection::new(
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, 1.0),
            core::f64::consts::PI,
        )
        .unwrap();
        let p = PointToPoint::new(c, Homogeneous::new(1e-200, 0.0).unwrap(), None).unwrap();
        let got = p.integral(&hg) / 1e-200;
        let want = core::f64::consts::TAU
            * integrate_geometric(
                |t| hg.eval(Deflection::from_theta(t)) * t,
                0.0,
                core::f64::consts::PI,
                30,
                1e-12,
            );
        assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    }

    #[test]
    fn receiver_facing_the_light_with_no_spread_gets_the_full_cosine() {
        // Normal pointing at x0, tiny θmax: cos θ2 → 1, so I matches the point receiver.
        let n = Some(DVec3::new(0.0, 0.0, -1.0));
        let (a, b) = (
            problem(0.5, 1e-3, n).integral(&Isotropic),
            problem(0.5, 1e-3, None).integral(&Isotropic),
        );
        assert!((a / b - 1.0).abs() < 1e-6, "{a} vs {b}");
        // Facing away from the light: nothing reaches the receiver in the forward ball.
        let away = problem(
            0.5,
            core::f64::consts::FRAC_PI_2,
            Some(DVec3::new(0.0, 0.0, 1.0)),
        );
        assert!(away.integral(&Isotropic) == 0.0);
    }

    #[test]
    fn azimuthal_cosine_matches_numeric_integration() {
        for &(beta, gamma) in &[(0.3, 0.2), (1.0, 1.2), (2.0, 0.5), (0.5, 2.9), (1.5, 1.5)] {
            // Midpoint rule: the kink of max(0, ·) costs it O(h²) ≈ 1e-10 here.
            let n = 200_000;
            let h = core::f64::consts::TAU / n as f64;
            let num: f64 = (0..n)
                .map(|i| {
                    let phi = (i as f64 + 0.5) * h;
                    (libm::cos(beta) * libm::cos(gamma)
                        + libm::sin(beta) * libm::sin(gamma) * libm::cos(phi))
                    .max(0.0)
                })
                .sum::<f64>()
                * h;
            let plus = libm::cos(beta - gamma);
            let minus = -libm::cos(beta + gamma);
            let (b, a) = (
                libm::sin(beta) * libm::sin(gamma),
                libm::cos(beta) * libm::cos(gamma),
            );
            assert!(
                (azimuthal_cosine((plus, minus), (b, a)) - num).abs() < 1e-9,
                "beta {beta} gamma {gamma}"
            );
        }
    }

    #[test]
    fn an_f32_problem_with_theta_max_pi_integrates_up_to_the_true_pi() {
        // f32's π is 3.14159274 > π; past π the triangle does not close and
        // a thin medium gave a non-finite reference.
        let c =
            Connection::<f32>::new(glam::Vec3::ZERO, glam::Vec3::Z, core::f32::consts::PI).unwrap();
        let p32 = PointToPoint::new(c, Homogeneous::new(1e-6f32, 0.0).unwrap(), None).unwrap();
        let got = p32.integral(&Isotropic);
        let c64 = Connection::new(DVec3::ZERO, DVec3::Z, core::f64::consts::PI).unwrap();
        let p64 =
            PointToPoint::new(c64, Homogeneous::new(1e-6f32 as f64, 0.0).unwrap(), None).unwrap();
        let want = p64.integral(&Isotropic);
        assert!(
            got.is_finite() && (got / want - 1.0).abs() < 1e-9,
            "{got} vs {want}"
        );
    }

    #[test]
    fn f_c_without_extinction_is_finite_at_any_distance() {
        // σt = 0 and d1 + d2 = ∞ in f32: T = 1, not exp(−0 · ∞) = NaN.
        let c = Connection::<f32>::new(glam::Vec3::ZERO, glam::Vec3::Z, 1.0).unwrap();
        let p = PointToPoint::new(c, Homogeneous::new(0.0f32, 0.0).unwrap(), None).unwrap();
        assert_eq!(p.f_c(glam::Vec3::splat(3e38)), 0.0);
        let p = PointToPoint::new(c, Homogeneous::new(0.5f32, 0.0).unwrap(), None).unwrap();
        assert_eq!(p.f_c(glam::Vec3::splat(3e38)), 0.0);
    }

    #[test]
    fn full_range_is_continuous_in_theta_max_and_fast() {
        // The boundary layers near θ = π must neither be missed (a jump between
        // θmax = π − 1e-6 and π) nor chased for seconds.
        let hg = HenyeyGreenstein::new(0.9).unwrap();
        let at = |theta_max: f64| {
            let c = Connection::new(
                DVec3::new(-0.5, 0.1, 0.0),
                DVec3::new(0.5, -0.05, 0.0),
                theta_max,
            )
            .unwrap();
            PointToPoint::new(c, Homogeneous::new(0.2, 0.05).unwrap(), None)
                .unwrap()
                .integral(&hg)
        };
        let start = std::time::Instant::now();
        let (near, full) = (at(core::f64::consts::PI - 1e-6), at(core::f64::consts::PI));
        assert!((full - near).abs() < 1e-6 * full, "{near} vs {full}");
        assert!(full > near);
        std::println!("two full-range integrals: {:?}", start.elapsed());
    }
}
