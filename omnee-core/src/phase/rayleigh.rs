//! Rayleigh scattering, `p = 3/(16π) (1 + cos²θ)`.

use super::{Deflection, PhaseFunction};
use crate::real::{Real, cbrt_start};

/// Rayleigh scattering by particles much smaller than the wavelength:
/// `p(θ) = 3/(16π) (1 + cos²θ)`, symmetric, mean cosine 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rayleigh;

/// `P(Θ ≤ θ)` as a polynomial in `x = 1 − cos θ`: `x (6 − 3x + x²) / 8`
/// (from `(4 − 3μ − μ³)/8` with `μ = 1 − x`; no cancellation for `x ≤ 1`).
#[inline]
fn mass<F: Real>(x: F) -> F {
    x * (F::from_f64(6.0) - F::from_f64(3.0) * x + x * x) / F::from_f64(8.0)
}

/// Solves `x (6 − 3x + x²) = 8v` for `x ∈ [0, 1]`, `v ∈ [0, 1/2]`.
///
/// Start: the exact root of the depressed cubic `μ³ + 3μ + 2a = 0` with
/// `a = 4v − 2`: `μ = t − 1/t`, `t = ∛(√(1 + a²) − a)`, `x = 1 − μ`. That `x`
/// is accurate only in the absolute sense (`1 − μ` cancels near θ = 0), so two
/// Newton steps on the polynomial follow; its derivative `3((1 − x)² + 1) ≥ 3`
/// makes them converge to full relative precision.
#[inline]
fn solve<F: Real>(v: F) -> F {
    let a = F::from_f64(4.0) * v - F::TWO;
    let t = cbrt_start((F::ONE + a * a).sqrt() - a);
    let mut x = (F::ONE - t + F::ONE / t).clamp_to(F::ZERO, F::ONE);
    for _ in 0..2 {
        let r = x * (F::from_f64(6.0) - F::from_f64(3.0) * x + x * x) - F::from_f64(8.0) * v;
        let dr = F::from_f64(3.0) * ((F::ONE - x).sqr() + F::ONE);
        x = (x - r / dr).clamp_to(F::ZERO, F::ONE);
    }
    x
}

impl<F: Real> PhaseFunction<F> for Rayleigh {
    /// `p = 3/(16π) (1 + cos²θ)`.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        F::from_f64(0.75) * F::FRAC_1_4PI * (F::ONE + d.cos().sqr())
    }

    /// The exact inverse of [`cdf`](Self::cdf): the cubic `x (6 − 3x + x²) = 8u`
    /// for `x = 1 − cos θ` if `u ≤ 1/2`, and by the symmetry `p(θ) = p(π − θ)`
    /// the same cubic for `1 + cos θ` with `1 − u` otherwise.
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        let u = u.clamp_to(F::ZERO, F::ONE);
        if u <= F::HALF {
            let x = solve(u);
            Deflection::from_versines(x, F::TWO - x)
        } else {
            let y = solve(F::ONE - u);
            Deflection::from_versines(F::TWO - y, y)
        }
    }

    /// `P(Θ ≤ θ) = x (6 − 3x + x²)/8` with `x = 1 − cos θ`; for `θ > π/2`
    /// `1 − y (6 − 3y + y²)/8` with `y = 1 + cos θ`.
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        if d.one_minus_cos <= F::ONE {
            mass(d.one_minus_cos)
        } else {
            F::ONE - mass(d.one_plus_cos)
        }
    }

    /// `⟨cos θ⟩ = 0` (the function is symmetric about π/2).
    #[inline]
    fn mean_cosine(&self) -> F {
        F::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::*;
    use super::*;

    #[test]
    fn normalised_and_cdf_matches_quadrature() {
        let e = normalisation_error(&Rayleigh);
        report("rayleigh normalisation", e);
        assert!(e < 1e-10);
        let c = cdf_error(&Rayleigh);
        report("rayleigh cdf vs quadrature", c);
        assert!(c < 1e-10);
        assert!(mean_error(&Rayleigh) < 1e-10);
        // Backscatter of a symmetric function is exactly one half.
        let b: f64 = Rayleigh.backscatter_fraction();
        assert!((b - 0.5).abs() < 1e-15);
    }

    #[test]
    fn sample_inverts_cdf_in_both_precisions() {
        let e64 = inversion_error::<f64, _>(&Rayleigh);
        let e32 = inversion_error::<f32, _>(&Rayleigh);
        report("rayleigh |cdf(sample(u)) - u| f64", e64);
        report("rayleigh |cdf(sample(u)) - u| f32", e32);
        assert!(e64 < 1e-15);
        assert!(e32 < 3e-7);
        // Relative accuracy at tiny u: cdf ≈ 3x/4, so x ≈ 4u/3.
        let d: Deflection<f64> = Rayleigh.sample(1e-12);
        assert!((d.one_minus_cos / (4e-12 / 3.0) - 1.0).abs() < 1e-9);
        let d: Deflection<f32> = Rayleigh.sample(1e-12);
        assert!((d.one_minus_cos as f64 / (4e-12 / 3.0) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn eval_is_finite_and_f32_agrees() {
        assert_eval_finite::<f32, _>(&Rayleigh);
        assert_eval_finite::<f64, _>(&Rayleigh);
        assert!(f32_eval_error(&Rayleigh, &Rayleigh) < 1e-6);
        let p0: f64 = Rayleigh.eval(Deflection::from_theta(0.0));
        assert!((p0 - 3.0 / (8.0 * core::f64::consts::PI)).abs() < 1e-16);
    }
}
