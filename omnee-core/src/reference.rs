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

use crate::error::Error;
use crate::medium::Homogeneous;
use crate::phase::{Deflection, PhaseFunction};
use crate::quadrature::{integrate, integrate_geometric};
use crate::real::{Real, Vector, cast, cast_vec, sinc};
use crate::sampling::{Connection, Sample};

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
    /// The problem for `connection` in `medium`; `receiver_normal` is
    /// normalised here and must be finite and non-zero.
    pub fn new(
        connection: Connection<F>,
        medium: Homogeneous<F>,
        receiver_normal: Option<F::Vec3>,
    ) -> Result<Self, Error> {
        let receiver_normal = match receiver_normal {
            None => None,
            Some(n) => {
                let len = n.length();
                if !(len > F::ZERO && len.is_finite()) {
                    return Err(Error::Degenerate {
                        field: "receiver_normal",
                        reason: "must be finite and non-zero",
                    });
                }
                Some(n * (F::ONE / len))
            }
        };
        Ok(Self {
            connection,
            medium,
            receiver_normal,
        })
    }

    /// The factors no technique samples:
    /// `f_c(x1) = σs e^{−σt (d1 + d2)} [max(0, n·(x1 − x2)/d2)]`.
    #[inline]
    pub fn f_c(&self, x1: F::Vec3) -> F {
        let axis = &self.connection.axis;
        let (a, b) = (x1 - axis.x0, x1 - axis.x2);
        let (d1, d2) = (a.length(), b.length());
        let cosine = match self.receiver_normal {
            None => F::ONE,
            Some(n) if d2 > F::ZERO => (n.dot(b) / d2).max(F::ZERO),
            Some(_) => F::ZERO,
        };
        self.medium.sigma_s() * self.medium.transmittance(d1 + d2) * cosine
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
    /// about 1e-9 for smooth phase functions).
    pub fn integral<P: PhaseFunction<f64>>(&self, phase: &P) -> f64 {
        let axis = &self.connection.axis;
        let s: f64 = cast(axis.s);
        let sigma_t: f64 = cast(self.medium.sigma_t());
        let sigma_s: f64 = cast(self.medium.sigma_s());
        // The f32 θmax = π rounds up (3.14159274 > π): the quadrature stops at
        // the true π, where the triangle closes.
        let theta_max: f64 = cast::<F, f64>(self.connection.theta_max).min(core::f64::consts::PI);
        let gamma = self.receiver_normal.map(|n| {
            let n = cast_vec::<F, f64>(n);
            let to_light = -cast_vec::<F, f64>(axis.e);
            n.cross(to_light).length().atan2(n.dot(to_light))
        });
        let tol = 1e-11;
        let inner = |theta: f64| {
            let sinc_theta = sinc(theta);
            let over_r = |r: f64| {
                let (beta, alpha) = (r * theta, (1.0 - r) * theta);
                let path = s * (r * sinc(beta) + (1.0 - r) * sinc(alpha)) / sinc_theta;
                let transmittance = if sigma_t > 0.0 {
                    libm::exp(-sigma_t * path)
                } else {
                    1.0
                };
                transmittance * gamma.map_or(core::f64::consts::TAU, |g| azimuthal_cosine(beta, g))
            };
            // Near θ = π the path length is long except close to r = 0 and
            // r = 1: layers of width ≈ sinc θ / (σt s) at both ends, resolved
            // by geometric panels towards each end.
            let thickness = sigma_t * s / sinc_theta;
            if thickness <= 4.0 {
                return integrate(over_r, 0.0, 1.0, tol, 0.0);
            }
            let levels = (libm::log2(thickness) as u32 + 4).min(60);
            integrate_geometric(&over_r, 0.0, 0.5, levels, tol)
                + integrate_geometric(|r| over_r(1.0 - r), 0.0, 0.5, levels, tol)
        };
        let outer = |theta: f64| {
            if theta <= 0.0 {
                return 0.0;
            }
            phase.eval(Deflection::from_theta(theta)) * theta * inner(theta)
        };
        sigma_s / s * integrate_geometric(outer, 0.0, theta_max, 40, tol)
    }
}

/// `Φ(β) = ∫₀^{2π} max(0, A + B cos φ) dφ` with `A = cos β cos γ`,
/// `B = sin β sin γ ≥ 0`: `2πA` if `A ≥ B`, 0 if `A ≤ −B`, else
/// `2(A φ₀ + B sin φ₀)` with `φ₀ = acos(−A/B)`.
fn azimuthal_cosine(beta: f64, gamma: f64) -> f64 {
    let (a, b) = (
        libm::cos(beta) * libm::cos(gamma),
        libm::sin(beta) * libm::sin(gamma),
    );
    if a >= b {
        core::f64::consts::TAU * a
    } else if a <= -b {
        0.0
    } else {
        let phi0 = libm::acos(-a / b);
        2.0 * (a * phi0 + b * libm::sin(phi0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::{HenyeyGreenstein, Isotropic};
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
            assert!(
                (azimuthal_cosine(beta, gamma) - num).abs() < 1e-9,
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
