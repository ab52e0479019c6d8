//! The Fournier–Forand phase function of oceanic particles, parameterised by
//! backscatter fraction and refractive index as in Blender Cycles.

use super::invert::invert_cdf;
use super::{Deflection, PhaseFunction};
use crate::error::{Error, check_closed, check_open};
use crate::quadrature::integrate_geometric;
use crate::real::{Real, exp_for, ln_for};

/// Fournier & Forand (1994), in Fournier & Jonasz's (1999) form, for a Junge
/// (hyperbolic) particle size distribution of slope `μ_J = 3 − 2ν` and relative
/// refractive index `n`. With `x = 1 − cos θ`, `δ = 2x/(3(n − 1)²) = δ₉₀ x`,
/// `s = sin²(θ/2) = x/2`:
///
/// `p(θ) = [ν(1 − δ) − (1 − δ^ν) + (δ(1 − δ^ν) − ν(1 − δ))/s] / (4π (1 − δ)² δ^ν)
///        + K (3 cos²θ − 1)/(16π)`,  `K = (δ₁₈₀^{−ν} − 1)/(δ₁₈₀ − 1)`.
///
/// The parameters are the backscatter fraction `B = P(Θ > π/2)` and `n`; the
/// slope follows from B (Cycles' parameterisation):
/// `ν = −ln(1 + 2B(δ₉₀ − 1)) / ln δ₉₀`, `δ₉₀ = 2/(3(n − 1)²)`.
///
/// Allowed: `B ∈ (0, 0.5)` (B → 0 is a delta peak, B = ½ is ν = −1 where the
/// model ends) and `n ∈ [1.001, 1.5]`: ν is defined only while `δ₉₀ > 1`
/// (`n < 1 + √(2/3) ≈ 1.816`); 1.5 covers every marine particle (1.01–1.25)
/// and keeps `δ₉₀ ≥ 2.67` away from the singular `ln δ₉₀ = 0`; 1.001 is
/// Cycles' lower clamp.
///
/// The forward peak is an integrable singularity, `p ∝ θ^{−2−2ν}`. Everything
/// is evaluated in f64 in the forms derived at [`PhaseFunction::eval`] and
/// [`PhaseFunction::cdf`], which have no `|1 − δ| < ε` Taylor branch and no
/// cancellation at θ → 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FournierForand<F> {
    b: F,
    n: F,
    shape: Shape,
}

/// The f64 parameters and formulas of [`FournierForand`], not generic over
/// the precision of the API: a program using both precisions has one copy.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Shape {
    /// `a = −ν ∈ (0, 1)`.
    a: f64,
    delta90: f64,
    k: f64,
    mean: f64,
}

/// Smallest accepted refractive index (Cycles' clamp).
pub const FF_N_MIN: f64 = 1.001;
/// Largest accepted refractive index (see [`FournierForand`]).
pub const FF_N_MAX: f64 = 1.5;

/// `e₂(z) = eᶻ − 1 − z` for `|z| < 1/4` by its Taylor series
/// `z²/2! + z³/3! + … + z¹²/12!` (the next term is below 1e-17 relative),
/// in Estrin's scheme with the coefficients `1/k!` folded.
fn e2_series(z: f64) -> f64 {
    const C: [f64; 11] = [
        1.0 / 2.0,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5040.0,
        1.0 / 40_320.0,
        1.0 / 362_880.0,
        1.0 / 3_628_800.0,
        1.0 / 39_916_800.0,
        1.0 / 479_001_600.0,
    ];
    let z2 = z * z;
    let z4 = z2 * z2;
    let z8 = z4 * z4;
    let p = ((C[0] + C[1] * z) + z2 * (C[2] + C[3] * z))
        + z4 * ((C[4] + C[5] * z) + z2 * (C[6] + C[7] * z))
        + z8 * ((C[8] + C[9] * z) + z2 * C[10]);
    z2 * p
}

impl<F: Real> FournierForand<F> {
    /// FF with backscatter fraction `B ∈ (0, 0.5)` (field `"backscatter"`) and
    /// particle refractive index `n ∈ [1.001, 1.5]` (field `"n"`).
    ///
    /// The mean cosine has no elementary closed form (the integrals of
    /// `δ^{−ν}/(1 − δ)` are incomplete Beta functions across δ = 1); it is
    /// computed here once, `⟨cos θ⟩ = 1 − ∫₀² P(Θ > θ) d(1 − cos θ)`, by adaptive
    /// Gauss–Kronrod with panels refined geometrically towards θ = 0.
    pub fn new(backscatter: F, n: F) -> Result<Self, Error> {
        Ok(Self {
            b: backscatter,
            n,
            shape: Shape::new(backscatter.to_f64(), n.to_f64())?,
        })
    }

    /// The backscatter fraction B.
    #[inline]
    pub fn backscatter(&self) -> F {
        self.b
    }

    /// The relative refractive index n.
    #[inline]
    pub fn n(&self) -> F {
        self.n
    }

    /// The derived exponent `ν = (3 − μ_J)/2 ∈ (−1, 0)`.
    #[inline]
    pub fn nu(&self) -> f64 {
        -self.shape.a
    }

    /// The Junge slope `μ_J = 3 − 2ν`.
    #[inline]
    pub fn junge_slope(&self) -> f64 {
        3.0 + 2.0 * self.shape.a
    }
}

impl Shape {
    /// The parameters for `B = b`, `n` (see [`FournierForand::new`]), with the
    /// mean cosine by quadrature.
    fn new(b: f64, n: f64) -> Result<Self, Error> {
        check_open("backscatter", b, 0.0, 0.5, "(0, 0.5)")?;
        check_closed("n", n, FF_N_MIN, FF_N_MAX, "[1.001, 1.5]")?;
        let delta90 = 2.0 / (3.0 * (n - 1.0) * (n - 1.0));
        let a = libm::log1p(2.0 * b * (delta90 - 1.0)) / libm::log(delta90);
        let d180 = 2.0 * delta90;
        let k = libm::expm1(a * libm::log(d180)) / (d180 - 1.0);
        let mut shape = Self {
            a,
            delta90,
            k,
            mean: 0.0,
        };
        let tail = integrate_geometric(|x| shape.ccdf64(x, 2.0 - x), 0.0, 2.0, 60, 1e-13);
        shape.mean = 1.0 - tail;
        Ok(shape)
    }

    /// `φ(δ) = (δ^{−ν} − 1)/(1 − δ) = expm1(−ν ln δ)/(1 − δ)` (limit ν at δ = 1);
    /// negative for all δ.
    fn phi(&self, delta: f64) -> f64 {
        if delta == 1.0 {
            -self.a
        } else {
            libm::expm1(self.a * libm::log(delta)) / (1.0 - delta)
        }
    }

    /// `2π p(θ)` in f64 at `x = 1 − cos θ`, `y = 1 + cos θ` (see `eval`):
    /// `−φ(δ)/2 + (y/2) δ₉₀ φ'(δ) + (K/8)(3μ² − 1)`, with
    /// `φ(δ) = expm1(aL)/(1 − δ)` and
    /// `φ'(δ) = [(1 − a) e₂(aL) + a e₂((a − 1)L)] / (1 − δ)²`, `a = −ν`,
    /// `L = ln δ`, `e₂(z) = eᶻ − 1 − z ≥ 0`: a sum of non-negative terms (limit
    /// `a(1 − a)/2` at δ = 1), where the textbook numerator
    /// `δ^{−ν} − 1 − ν δ^{−ν−1}(1 − δ)` cancels to `O((1 − δ)²)`.
    ///
    /// One logarithm and one exponential: `E = e^{aL} = δᵃ`, then
    /// `expm1(aL) = E − 1`, `e₂(aL) = (E − 1) − aL` and
    /// `e₂((a − 1)L) = E/δ − 1 − (a − 1)L` where `|z| ≥ 1/4` (they lose at
    /// most 3 bits there), the Taylor series `e2_series` below. `ln` and
    /// `exp` are as accurate as a result in `F` needs ([`exp_for`]).
    #[cfg_attr(not(target_arch = "wasm32"), inline(always))]
    #[cfg_attr(target_arch = "wasm32", inline)]
    fn density<F: Real>(&self, x: f64, y: f64) -> f64 {
        let a = self.a;
        let delta = self.delta90 * x;
        let mu = if x <= 1.0 { 1.0 - x } else { y - 1.0 };
        let legendre = 0.125 * self.k * (3.0 * mu * mu - 1.0);
        if delta == 1.0 {
            return 0.5 * a + 0.25 * y * self.delta90 * a * (1.0 - a) + legendre;
        }
        // The reciprocals beside the logarithm, off the way to the result.
        let (inv_delta, inv_one_minus_delta) = (1.0 / delta, 1.0 / (1.0 - delta));
        let l = ln_for::<F>(delta);
        let (z1, z2) = (a * l, (a - 1.0) * l);
        let e = exp_for::<F>(z1);
        // Both forms, chosen by exact 0/1 weights: a branch on |z| < 1/4 is
        // mispredicted for deflections around δ = 1.
        let near = |z: f64| f64::from(u8::from(z.abs() < 0.25));
        let (w1, w2) = (near(z1), near(z2));
        let e2_a = w1 * e2_series(z1) + (1.0 - w1) * ((e - 1.0) - z1);
        let expm1 = w1 * (z1 + e2_a) + (1.0 - w1) * (e - 1.0);
        let e2_a1 = w2 * e2_series(z2) + (1.0 - w2) * ((e * inv_delta - 1.0) - z2);
        let phi = expm1 * inv_one_minus_delta;
        let phi_prime = ((1.0 - a) * e2_a + a * e2_a1) * inv_one_minus_delta * inv_one_minus_delta;
        -0.5 * phi + 0.5 * y * self.delta90 * phi_prime + legendre
    }

    /// `P(Θ > θ) = −(y/2) φ(δ) − (K/8) μ x y` in f64.
    fn ccdf64(&self, x: f64, y: f64) -> f64 {
        let mu = if x <= 1.0 { 1.0 - x } else { y - 1.0 };
        (-0.5 * y * self.phi(self.delta90 * x) - 0.125 * self.k * mu * x * y).clamp_to(0.0, 1.0)
    }

    /// `P(Θ ≤ θ)` in f64: `[δ^{−ν}(1 − s) + s − δ]/(1 − δ) + (K/8) μ x y` for
    /// δ < ½ (accurate relative to itself as θ → 0), `1 − P(Θ > θ)` above.
    fn cdf64(&self, x: f64, y: f64) -> f64 {
        let delta = self.delta90 * x;
        if delta < 0.5 {
            let mu = 1.0 - x;
            let s = 0.5 * x;
            let da = libm::exp(self.a * libm::log(delta));
            ((da * (1.0 - s) + s - delta) / (1.0 - delta) + 0.125 * self.k * mu * x * y)
                .clamp_to(0.0, 1.0)
        } else {
            1.0 - self.ccdf64(x, y)
        }
    }
}

impl<F: Real> PhaseFunction<F> for FournierForand<F> {
    /// `p = [−φ(δ)/2 + (1 − s) δ₉₀ φ'(δ)] / (2π) + K (3 cos²θ − 1)/(16π)`, the
    /// derivative `dP/dx / (2π)` of the cdf below, equal to the textbook form
    /// but free of its `(1 − δ)²` cancellation (both bracket terms are ≥ 0).
    ///
    /// θ = 0 is the singularity; `eval` returns the value at the smallest
    /// positive normal `1 − cos θ` of `F`, capped at `F::MAX`, so it is finite.
    #[cfg_attr(not(target_arch = "wasm32"), inline(always))]
    #[cfg_attr(target_arch = "wasm32", inline)]
    fn eval(&self, d: Deflection<F>) -> F {
        let x = d.one_minus_cos.to_f64().max(F::MIN_POSITIVE.to_f64());
        let y = d.one_plus_cos.to_f64();
        let p = self.shape.density::<F>(x, y) * 0.5 * core::f64::consts::FRAC_1_PI;
        F::from_f64(p.max(0.0)).min(F::MAX)
    }

    /// Safeguarded Newton/bisection in f64 on the cdf in `1 − cos θ` (on
    /// `P(Θ > θ)` in `1 + cos θ` past π/2), started at the small-angle
    /// asymptote `δ = u^{1/(−ν)}`; converged to a few f64 ulps of the root.
    fn sample(&self, u: F) -> Deflection<F> {
        let u64 = u.to_f64();
        // `u^{1/a}` as `exp(ln u / a)`: a starting value needs no correctly
        // rounded power (libm's `pow` is 1.9 KiB of the browser demo's module).
        let delta0 = libm::exp(libm::log(u64) / self.shape.a);
        let guess = if delta0 < 0.5 {
            delta0 / self.shape.delta90
        } else {
            -1.0
        };
        let (x, y) = invert_cdf(
            u64,
            guess,
            |x, y| self.shape.cdf64(x, y),
            |x, y| self.shape.ccdf64(x, y),
            |x, y| self.shape.density::<f64>(x, y),
        );
        Deflection::from_versines(F::from_f64(x), F::from_f64(y))
    }

    /// `P(Θ ≤ θ) = 1 + (1 − s) φ(δ) + (K/8) cos θ sin²θ`, the published
    /// `T(μ) = [1 − δ^{ν+1} − (1 − δ^ν)s]/[(1 − δ)δ^ν] + (K/8)μ(1 − μ²)`
    /// rewritten: the bracket form for δ < ½, and `1 − P(Θ > θ)` with
    /// `P(Θ > θ) = −(1 − s) φ(δ) − (K/8) μ(1 − μ)(1 + μ)` otherwise.
    fn cdf(&self, d: Deflection<F>) -> F {
        F::from_f64(
            self.shape
                .cdf64(d.one_minus_cos.to_f64(), d.one_plus_cos.to_f64()),
        )
    }

    /// `⟨cos θ⟩`, integrated at construction (see [`FournierForand::new`]).
    fn mean_cosine(&self) -> F {
        F::from_f64(self.shape.mean)
    }

    /// `B`, from `P(Θ > π/2) = −φ(δ₉₀)/2`, the definition of ν (equal to the
    /// parameter up to rounding).
    fn backscatter_fraction(&self) -> F {
        F::from_f64(self.shape.ccdf64(1.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::*;
    use super::*;
    use core::f64::consts::{FRAC_PI_2, PI, TAU};

    /// (B, n, μ_J, ⟨cos θ⟩), the table of docs/math.md §7.4.
    const CHECKS: [(f64, f64, f64, f64); 4] = [
        (0.0183, 1.10, 3.5833, 0.930),
        (0.01, 1.08, 3.4819, 0.958),
        (0.1, 1.175, 4.0646, 0.720),
        (0.001, 1.04, 3.2006, 0.994),
    ];

    /// `2π ∫_0^θ h(θ') p sin θ' dθ'` with `θ' = θ v^{1/a}`: the substitution
    /// turns the `θ^{−1−2ν}` singularity of `p sin θ` into a smooth integrand.
    fn mass_to(p: &FournierForand<f64>, theta: f64, h: impl Fn(f64) -> f64) -> f64 {
        let k = 1.0 / p.shape.a;
        TAU * integrate_geometric(
            |v| {
                if v == 0.0 {
                    return 0.0;
                }
                let t = theta * libm::pow(v, k);
                let d = Deflection::from_theta(t);
                h(d.cos()) * p.eval(d) * d.sin() * theta * k * libm::pow(v, k - 1.0)
            },
            0.0,
            1.0,
            20,
            1e-12,
        )
    }

    #[test]
    fn reference_values_and_normalisation() {
        let (mut worst_norm, mut worst_cdf) = (0.0f64, 0.0f64);
        for (b, n, mu_j, mean) in CHECKS {
            let p = FournierForand::<f64>::new(b, n).unwrap();
            assert!((p.junge_slope() - mu_j).abs() < 1e-4, "{}", p.junge_slope());
            assert!((p.mean_cosine() - mean).abs() < 1e-3, "{}", p.mean_cosine());
            // Backward half by quadrature equals B.
            let back = backward_mass(&p, FRAC_PI_2);
            assert!((back - b).abs() < 1e-10, "{back}");
            assert!((p.backscatter_fraction() - b).abs() < 1e-14);
            let fwd = mass_to(&p, FRAC_PI_2, |_| 1.0);
            worst_norm = worst_norm.max((fwd + back - 1.0).abs());
            // The cdf against quadrature, forwards and backwards.
            for t in [1e-6, 1e-3, 0.01, 0.1, 0.5, 1.0, FRAC_PI_2] {
                let c = p.cdf(Deflection::from_theta(t));
                worst_cdf = worst_cdf.max((c - mass_to(&p, t, |_| 1.0)).abs());
            }
            for t in [2.0, 2.5, 3.0, 3.1, PI - 1e-6] {
                let c = 1.0 - p.cdf(Deflection::from_theta(t));
                worst_cdf = worst_cdf.max((c - backward_mass(&p, t)).abs());
            }
            // Mean cosine against a direct quadrature of ∫ cos θ p dω.
            let m = mass_to(&p, FRAC_PI_2, |c| c)
                + TAU
                    * integrate_geometric(
                        |t| {
                            let d = from_pi(t);
                            d.cos() * p.eval(d) * d.sin()
                        },
                        0.0,
                        FRAC_PI_2,
                        50,
                        1e-12,
                    );
            assert!(
                (m - p.mean_cosine()).abs() < 1e-8,
                "{m} {}",
                p.mean_cosine()
            );
        }
        report("ff normalisation", worst_norm);
        report("ff cdf vs quadrature", worst_cdf);
        assert!(worst_norm < 1e-8 && worst_cdf < 1e-8);
        let p = FournierForand::<f64>::new(0.0183, 1.10).unwrap();
        report("ff (0.0183, 1.10) nu", p.nu());
        report("ff (0.0183, 1.10) mean cosine", p.mean_cosine());
        assert!((p.nu() + 0.29163).abs() < 1e-5);
    }

    #[test]
    fn matches_the_textbook_formula_and_is_smooth_across_delta_one() {
        let p = FournierForand::<f64>::new(0.0183, 1.10).unwrap();
        let nu = p.nu();
        // The published formula (docs/math.md §7.4), valid away from δ = 1.
        let textbook = |x: f64| {
            let delta = p.shape.delta90 * x;
            let s = 0.5 * x;
            let dn = libm::pow(delta, nu);
            let mu = 1.0 - x;
            ((nu * (1.0 - delta) - (1.0 - dn) + (delta * (1.0 - dn) - nu * (1.0 - delta)) / s)
                / (4.0 * core::f64::consts::PI * (1.0 - delta) * (1.0 - delta) * dn))
                + p.shape.k / (16.0 * core::f64::consts::PI) * (3.0 * mu * mu - 1.0)
        };
        for x in [1e-9, 1e-5, 1e-3, 0.05, 0.3, 1.0, 1.7, 2.0] {
            let ours = p.eval(Deflection::from_one_minus_cos(x));
            assert!((ours / textbook(x) - 1.0).abs() < 1e-10, "x = {x}");
        }
        // Across δ = 1 the value is smooth: compare with the chord midpoint.
        let x1 = 1.0 / p.shape.delta90;
        let at = |x: f64| p.eval(Deflection::from_one_minus_cos(x));
        for h in [1e-12, 1e-9, 1e-6] {
            let mid = 0.5 * (at(x1 * (1.0 - h)) + at(x1 * (1.0 + h)));
            assert!((at(x1) / mid - 1.0).abs() < 1e-9, "h = {h}");
        }
        // And the density is the derivative of the cdf there.
        let (c0, c1) = (
            p.cdf(Deflection::from_one_minus_cos(x1 * (1.0 - 1e-5))),
            p.cdf(Deflection::from_one_minus_cos(x1 * (1.0 + 1e-5))),
        );
        let slope = (c1 - c0) / (2e-5 * x1);
        assert!((slope / (TAU * at(x1)) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn sample_inverts_cdf() {
        let mut worst64 = 0.0f64;
        let mut worst32 = 0.0f64;
        for (b, n, ..) in CHECKS
            .into_iter()
            .chain([(1e-4, 1.021, 0.0, 0.0), (0.45, 1.5, 0.0, 0.0)])
        {
            let p64 = FournierForand::<f64>::new(b, n).unwrap();
            let p32 = FournierForand::<f32>::new(b as f32, n as f32).unwrap();
            let e = inversion_error::<f64, _>(&p64);
            // For B = 1e-4 the cdf at the smallest subnormal 1 − cos θ is
            // already 1.6e-12: smaller u have no representable answer.
            let floor = p64.cdf(Deflection::from_one_minus_cos(f64::from_bits(1)));
            assert!(e < 1e-12_f64.max(2.0 * floor), "B = {b}, n = {n}: {e}");
            worst64 = worst64.max(e);
            let e32 = inversion_error::<f32, _>(&p32);
            // In f32 that floor is 3 % for B = 1e-4 (the peak lies below
            // θ = 1e-22): those samples come out as the smallest 1 − cos θ.
            let floor32 = p32.cdf(Deflection::from_one_minus_cos(f32::from_bits(1))) as f64;
            if floor32 > 1e-6 {
                report("ff f32 cdf at the smallest subnormal 1 - cos", floor32);
            }
            assert!(
                e32 < 1e-5_f64.max(1.01 * floor32),
                "B = {b}, n = {n}: {e32}"
            );
            if floor32 <= 1e-6 {
                worst32 = worst32.max(e32);
            }
            assert_eval_finite::<f32, _>(&p32);
            assert_eval_finite::<f64, _>(&p64);
            let p64r = FournierForand::<f64>::new(b as f32 as f64, n as f32 as f64).unwrap();
            let r = f32_eval_error(&p32, &p64r);
            assert!(r < 1e-4, "{r}");
        }
        report("ff |cdf(sample(u)) - u| f64", worst64);
        report("ff |cdf(sample(u)) - u| f32 (representable cases)", worst32);
    }

    #[test]
    fn constructor_rejects_bad_parameters() {
        let f = |b: f64, n: f64| FournierForand::<f64>::new(b, n).unwrap_err().field();
        assert_eq!(f(f64::NAN, 1.1), "backscatter");
        assert_eq!(f(0.0, 1.1), "backscatter");
        assert_eq!(f(0.5, 1.1), "backscatter");
        assert_eq!(f(0.01, 1.0), "n");
        assert_eq!(f(0.01, 1.9), "n");
        assert_eq!(f(0.01, f64::NAN), "n");
    }
}
