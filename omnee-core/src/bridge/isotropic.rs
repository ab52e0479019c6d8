//! The exact k-times scattered transfer for an isotropic phase function
//! (docs/math.md §14.6).
//!
//! With `G(r) = e^{−σt r}/(4π r²)`, `I_k = 4π σs^k G^{*(k+1)}(s)`, and `G`'s
//! Fourier transform is `atan(q/σt)/q`, so that
//!
//! `I_k = (2 σs^k / (π s)) ∫₀^∞ sin(q s) atan(q/σt)^{k+1} / q^k dq`.
//!
//! Two ways to evaluate it, each exact, each with its own cancellation
//! (docs/math.md §14.6):
//!
//! - the Laplace form: turned onto the imaginary axis (q = iσt y) it becomes
//!   a Laplace transform in the path's stretch `y = D/s ≥ 1`,
//!   `I_k = (2 σt/(π s)) (σs/σt)^k ∫₁^∞ e^{−σt s y} ρ^{k+1} sin((k+1)ψ + (1−k)π/2) y^{−k} dy`,
//!   `ρ e^{iψ} = π/2 + i arcoth y`, integrated with `y = 1/(1 − v)`: its
//!   terms cancel more with every vertex and in thin media;
//! - the Fourier form itself, in `u = qs`:
//!   `I_k = (2/(π s²)) (σs s)^k ∫₀^∞ sin u · atan(u/τ)^{k+1} / u^k du`
//!   (τ = σt s), whose oscillations cancel only in dense media, and less
//!   with more vertices.
//!
//! The Laplace form first; where it cancels too much, the Fourier form.

use super::MAX_VERTICES;
use crate::error::{Error, check_closed};
use crate::quadrature::Budget;

/// The default evaluation budget of [`isotropic_transfer`]: 10⁶ evaluations of
/// the integrand (tens of milliseconds); the references of the tests need
/// 10³–10⁴.
pub const REFERENCE_BUDGET: usize = 1_000_000;

/// The largest cancellation `∫|f| / ∫f` of an integrand `f` of
/// docs/math.md §14.6 that [`isotropic_transfer`] accepts: f64's rounding
/// of the large terms, about `10⁻¹⁶ ∫|f|`, stays below `10⁻¹⁰` of the value.
pub const MAX_CANCELLATION: f64 = 1e6;

/// `I_k` for an isotropic phase function in an infinite homogeneous medium
/// (unit point light at `x0`, point receiver at `x2`, `s = |x2 − x0|`), by
/// adaptive quadrature of a 1-D integral of docs/math.md §14.6 to a
/// relative accuracy of about 1e-10.
///
/// Both integrands change sign. The Laplace form's parts cancel more with
/// every vertex and in thinner media (`∫|f|/∫f` ≈ 130 at k = 4, 8·10⁴ at
/// k = 8, 1.5·10⁸ at k = 12 for σt s = 0.1); where that exceeds
/// [`MAX_CANCELLATION`] the Fourier form is taken instead, whose
/// oscillations cancel little below σt s ≈ 3 (1.0 to 1.2 for k ≥ 10) and
/// less with more vertices (75, 8.4, 2.9 for k = 10, 20, 32 at σt s = 10).
/// Where both exceed it the value would have fewer than 10 digits, and the
/// function fails on the field `"k"` instead: no k up to 32 for σt s up to
/// 20; k = 17 … 28 at 30, 18 … 32 at 50.
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
    let laplace_holds = k == 1 || {
        let magnitude = spend.integrate_geometric(|v| integrand(v).abs(), 0.0, 1.0, 50, 1e-3);
        j > 0.0 && spend.finish("reference", magnitude)? <= MAX_CANCELLATION * j
    };
    let value = if laplace_holds {
        // (2 σt/(π s)) (σs/σt)^k e^{−τ} J, with σt^{1−k} as the albedo's power.
        let mut prefactor = 2.0 * sigma_s / (core::f64::consts::PI * s);
        for _ in 1..k {
            prefactor *= sigma_s / sigma_t;
        }
        prefactor * libm::exp(-tau) * j
    } else {
        let (j, magnitude) = fourier(k, tau, &spend);
        let j = spend.finish("reference", j)?;
        if !(j > 0.0 && magnitude <= MAX_CANCELLATION * j) {
            return Err(Error::OutOfRange {
                field: "k",
                value: k as f64,
                allowed: "the vertices for which one of the closed form's integrals keeps 10 \
                          digits against its cancellation (docs/math.md §14.6: every k up to \
                          32 for sigma_t s up to 20, fewer in denser media)",
            });
        }
        // (2/(π s²)) (σs s)^k J_F.
        let mut prefactor = 2.0 / (core::f64::consts::PI * s * s);
        for _ in 0..k {
            prefactor *= sigma_s * s;
        }
        prefactor * j
    };
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

/// The Fourier form `J_F = ∫₀^∞ sin u · atan(u/τ)^{k+1} / u^k du` (k ≥ 2)
/// and `∫₀^∞ |…| du`: `[0, π]` in panels halving towards 0 (the bulk sits
/// near `u ≈ τ`, down to τ·2⁻⁸), then half-period by half-period
/// `[jπ, (j+1)π]` until the tail, at most `(π/2)^{k+1} / ((k−1) Q^{k−1})`
/// beyond `Q`, is below 10⁻¹³ of `|J_F|` (or the budget is spent).
fn fourier(k: usize, tau: f64, spend: &Budget) -> (f64, f64) {
    let pi = core::f64::consts::PI;
    let f = |u: f64| {
        if !(u > 0.0) {
            return 0.0;
        }
        let a = libm::atan(u / tau);
        let mut value = libm::sin(u) * a;
        for _ in 0..k {
            value *= a / u;
        }
        value
    };
    let levels = (libm::log2(pi / tau).max(0.0) as u32 + 8).min(60);
    // On every half-period the integrand keeps the sign of sin u: its
    // magnitude is the sum of the half-periods' magnitudes.
    let mut j = spend.integrate_geometric(f, 0.0, pi, levels, 1e-13);
    let mut magnitude = j;
    let tail_scale = libm::pow(core::f64::consts::FRAC_PI_2, (k + 1) as f64) / (k - 1) as f64;
    let mut q = pi;
    while !spend.exhausted() && j.is_finite() {
        let tail = tail_scale / libm::pow(q, (k - 1) as f64);
        if tail <= 1e-13 * j.abs() {
            break;
        }
        let period = spend.integrate(f, q, q + pi, 1e-13, 1e-16 * j.abs());
        j += period;
        magnitude += period.abs();
        q += pi;
    }
    (j, magnitude)
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
