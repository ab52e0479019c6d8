//! The exact k-times scattered transfer for an isotropic phase function
//! (docs/math.md §14.6).
//!
//! With `G(r) = e^{−σt r}/(4π r²)`, `I_k = 4π σs^k G^{*(k+1)}(s)`, and `G`'s
//! Fourier transform is `atan(q/σt)/q`, so that
//!
//! `I_k = (2 σs^k / (π s)) ∫₀^∞ sin(q s) atan(q/σt)^{k+1} / q^k dq`.
//!
//! That integral oscillates; turned onto the imaginary axis (q = iσt y) it
//! becomes a Laplace transform in the path's stretch `y = D/s ≥ 1`,
//!
//! `I_k = (2 σt/(π s)) (σs/σt)^k ∫₁^∞ e^{−σt s y} ρ^{k+1} sin((k+1)ψ + (1−k)π/2) y^{−k} dy`,
//!
//! `ρ e^{iψ} = π/2 + i arcoth y`, which is integrated here with `y = 1/(1 − v)`.

use super::MAX_VERTICES;
use crate::error::{Error, check_closed};
use crate::quadrature::Budget;

/// The default evaluation budget of [`isotropic_transfer`]: 10⁶ evaluations of
/// the integrand (tens of milliseconds); the references of the tests need
/// 10³–10⁴.
pub const REFERENCE_BUDGET: usize = 1_000_000;

/// The largest cancellation `∫|f| / ∫f` of the integrand `f` of
/// docs/math.md §14.6 that [`isotropic_transfer`] accepts: f64's rounding
/// of the large terms, about `10⁻¹⁶ ∫|f|`, stays below `10⁻¹⁰` of the value.
pub const MAX_CANCELLATION: f64 = 1e6;

/// `I_k` for an isotropic phase function in an infinite homogeneous medium
/// (unit point light at `x0`, point receiver at `x2`, `s = |x2 − x0|`), by
/// adaptive quadrature of the 1-D integral of docs/math.md §14.6 to a
/// relative accuracy of about 1e-10.
///
/// The integrand changes sign, and its positive and negative parts cancel
/// more with every vertex and in thinner media (`∫|f|/∫f` ≈ 130 at k = 4,
/// 8·10⁴ at k = 8, 1.5·10⁸ at k = 12 for σt s = 0.1; 11, 3.7·10³, 5.7·10⁶
/// at σt s = 1.1): where it exceeds [`MAX_CANCELLATION`] the value would
/// have fewer than 10 digits, and the function fails on the field `"k"`
/// instead (from k = 10 at σt s = 0.1, 12 at 1.1, 15 at 10).
///
/// Fails for `k` outside `1 ..= MAX_VERTICES`, `s ≤ 0`, negative or
/// non-finite coefficients, `σt = 0` with `k ≥ 2` (the unattenuated
/// integral diverges: chains wander off to infinity), and when the
/// quadrature needs more than `budget` evaluations of the integrand
/// (`Error::NotConverged` on the field `"reference"`, with the evaluations
/// spent, as every quadrature's [`Budget`]): it never runs longer. A value
/// beyond f64's range (σs ∝ 1/s at s = 1e-300: about 1e600) fails on the
/// field `"s"`.
pub fn isotropic_transfer(
    k: usize,
    s: f64,
    sigma_s: f64,
    sigma_t: f64,
    budget: usize,
) -> Result<f64, Error> {
    check_closed("k", k as f64, 1.0, MAX_VERTICES as f64, "1 ..= 32")?;
    check_closed("s", s, f64::MIN_POSITIVE, f64::MAX, "(0, inf)")?;
    check_closed("sigma_s", sigma_s, 0.0, f64::MAX, "[0, inf)")?;
    check_closed("sigma_t", sigma_t, 0.0, f64::MAX, "[0, inf)")?;
    if k >= 2 && !(sigma_t > 0.0) {
        return Err(Error::OutOfRange {
            field: "sigma_t",
            value: sigma_t,
            allowed: "(0, inf) for k >= 2 (without extinction the integral diverges)",
        });
    }
    if sigma_s == 0.0 {
        return Ok(0.0);
    }
    let tau = sigma_t * s;
    let spend = Budget::new(budget as u64);
    let integrand = |v: f64| {
        if !(v > 0.0 && v < 1.0) {
            return 0.0;
        }
        stretch_density(k, tau, v)
    };
    let j = spend.integrate_geometric(integrand, 0.0, 1.0, 50, 1e-11);
    let j = spend.finish("reference", j)?;
    if k >= 2 {
        let magnitude = spend.integrate_geometric(|v| integrand(v).abs(), 0.0, 1.0, 50, 1e-3);
        let magnitude = spend.finish("reference", magnitude)?;
        if !(j > 0.0 && magnitude <= MAX_CANCELLATION * j) {
            return Err(Error::OutOfRange {
                field: "k",
                value: k as f64,
                allowed: "the vertices for which the closed form's cancellation leaves 10 digits \
                          (docs/math.md §14.6: k <= 9 at sigma_t s = 0.1, k <= 11 at 1.1, \
                          k <= 14 at 10)",
            });
        }
    }
    // (2 σt/(π s)) (σs/σt)^k e^{−τ} J, with σt^{1−k} as the albedo's power.
    let mut prefactor = 2.0 * sigma_s / (core::f64::consts::PI * s);
    for _ in 1..k {
        prefactor *= sigma_s / sigma_t;
    }
    let value = prefactor * libm::exp(-tau) * j;
    if !value.is_finite() {
        return Err(Error::OutOfRange {
            field: "s",
            value: s,
            allowed: "a transfer I_k below f64's largest number (about sigma_s / s in a thin \
                      medium, (sigma_s s)^k / s^2 in general)",
        });
    }
    Ok(value)
}

/// The integrand over `v ∈ (0, 1)`, `y = 1/(1 − v)`, without `e^{−τ}`:
/// `e^{−τ (y − 1)} ρ^{k+1} sin((k+1)ψ + (1−k)π/2) (1 − v)^{k−2}`
/// with `ρ e^{iψ} = π/2 + i arcoth y` and `arcoth y = ln(1 + 2/(y − 1))/2`.
fn stretch_density(k: usize, tau: f64, v: f64) -> f64 {
    let x = v / (1.0 - v); // y − 1
    let attenuation = if tau > 0.0 { libm::exp(-tau * x) } else { 1.0 };
    if attenuation == 0.0 {
        return 0.0;
    }
    let arcoth = 0.5 * libm::log1p(2.0 / x);
    let half_pi = core::f64::consts::FRAC_PI_2;
    let rho = libm::hypot(half_pi, arcoth);
    let a = (k + 1) as f64 * libm::atan2(arcoth, half_pi);
    // sin(a + (1 − k)π/2) by the quarter turns of (1 − k) mod 4.
    let phase = match (1 + 4 * MAX_VERTICES - k) % 4 {
        0 => libm::sin(a),
        1 => libm::cos(a),
        2 => -libm::sin(a),
        _ => -libm::cos(a),
    };
    let mut value = attenuation * phase;
    for _ in 0..=k {
        value *= rho;
    }
    value * libm::pow(1.0 - v, k as f64 - 2.0)
}
