//! Draine's phase function (Draine 2003, doi:10.1086/379118): Henyey–Greenstein
//! times `(1 + α cos²θ)`, the second lobe of the approximate Mie fit.

use super::invert::invert_cdf;
use super::{Deflection, HenyeyGreenstein, PhaseFunction};
use crate::error::{Error, check_closed, check_open};
use crate::real::{Real, cbrt_start};

/// Largest accepted α. The Mie fit uses up to 250; beyond about 10³ the
/// function is `∝ cos²θ` to within 0.1 % and the closed-form sampler loses its
/// last digits (the Newton polish still converges).
pub const DRAINE_ALPHA_MAX: f64 = 1000.0;

/// Draine (2003):
///
/// `p(θ) = (1 − g²)(1 + α cos²θ) / (4π N (1 + g² − 2g cos θ)^{3/2})`,
/// `N = 1 + α(1 + 2g²)/3`,
///
/// with `g ∈ (−1, 1)`, `α ∈ [0, 1000]`. α = 0 is Henyey–Greenstein, g = 0 with
/// α = 1 Rayleigh, α = 1 Cornette–Shanks. Mean cosine
/// `g (1 + α(3 + 2g²)/5) / N`.
///
/// `cdf` is an exact closed form (see [`PhaseFunction::cdf`] below), evaluated
/// in f64. `sample` evaluates the Jendersie–d'Eon closed-form inverse in f64
/// (in f32 it yields NaN and |cos θ| > 1 for α ≈ 250) and polishes it with a
/// safeguarded Newton iteration on the f64 cdf, so `cdf(sample(u)) = u` to
/// f64 rounding in either precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Draine<F> {
    g: F,
    alpha: F,
    hg: HenyeyGreenstein<F>,
    /// The same g in f64, and its mirror −g (for `P(Θ > θ)`).
    hg64: HenyeyGreenstein<f64>,
    hg64_mirror: HenyeyGreenstein<f64>,
    /// `(1 − g²)/(4π N)`.
    scale: F,
}

impl<F: Real> Draine<F> {
    /// Draine(g, α) with `g ∈ (−1, 1)` (field `"g"`) and `α ∈ [0, 1000]`
    /// (field `"alpha"`).
    pub fn new(g: F, alpha: F) -> Result<Self, Error> {
        check_open("g", g.to_f64(), -1.0, 1.0, "(-1, 1)")?;
        check_closed("alpha", alpha.to_f64(), 0.0, DRAINE_ALPHA_MAX, "[0, 1000]")?;
        let (g64, a64) = (g.to_f64(), alpha.to_f64());
        let n = 1.0 + a64 * (1.0 + 2.0 * g64 * g64) / 3.0;
        Ok(Self {
            g,
            alpha,
            hg: HenyeyGreenstein::new(g)?,
            hg64: HenyeyGreenstein::new(g64)?,
            hg64_mirror: HenyeyGreenstein::new(-g64)?,
            scale: F::from_f64((1.0 - g64) * (1.0 + g64) * 0.25 * core::f64::consts::FRAC_1_PI / n),
        })
    }

    /// The HG asymmetry parameter g (not the mean cosine unless α = 0).
    #[inline]
    pub fn g(&self) -> F {
        self.g
    }

    /// The weight α of the `cos²θ` term.
    #[inline]
    pub fn alpha(&self) -> F {
        self.alpha
    }

    /// `N = 1 + α(1 + 2g²)/3` in f64.
    #[inline]
    fn norm64(&self) -> f64 {
        let g = self.g.to_f64();
        1.0 + self.alpha.to_f64() * (1.0 + 2.0 * g * g) / 3.0
    }

    /// `P(Θ ≤ θ)` in f64 at `x = 1 − cos θ`, `y = 1 + cos θ` (see `cdf`).
    fn cdf64(&self, x: f64, y: f64) -> f64 {
        mass(
            self.g.to_f64(),
            self.alpha.to_f64(),
            self.norm64(),
            &self.hg64,
            x,
            y,
        )
    }

    /// `P(Θ > θ)` in f64: the cdf of Draine(−g, α) at π − θ.
    fn ccdf64(&self, x: f64, y: f64) -> f64 {
        mass(
            -self.g.to_f64(),
            self.alpha.to_f64(),
            self.norm64(),
            &self.hg64_mirror,
            y,
            x,
        )
    }

    /// `2π p(θ)` in f64.
    fn dens64(&self, x: f64, y: f64) -> f64 {
        let g = self.g.to_f64();
        let d = versines(x, y);
        let den = self.hg64.denominator(d);
        let mu = d.cos();
        (1.0 - g) * (1.0 + g) * (1.0 + self.alpha.to_f64() * mu * mu)
            / (2.0 * self.norm64() * den * libm::sqrt(den))
    }

    /// The Jendersie–d'Eon closed-form inverse, `cos θ` for `P(Θ ≤ θ) = u`,
    /// evaluated in f64 (the starting point of [`sample`](PhaseFunction::sample)).
    pub fn closed_form_cos(&self, u: F) -> f64 {
        closed_form(self.g.to_f64(), self.alpha.to_f64(), 1.0 - u.to_f64())
    }
}

/// A deflection from its versines (θ is not needed by the f64 helpers).
#[inline]
fn versines(x: f64, y: f64) -> Deflection<f64> {
    Deflection {
        theta: 0.0,
        one_minus_cos: x,
        one_plus_cos: y,
    }
}

/// `P(Θ ≤ θ)` of Draine(g, α), `N` its normalisation, `hg` the HG(g) lobe.
///
/// With `μ = cos θ`, `a = √(1 + g² − 2gμ)`, `b = 1 − g`, `c = 1 + g²`:
///
/// `P = (1 + g)(1 − μ) / (a (a + b)) · (1 + α M / (3(c + ab))) / N`,
/// `M = (1 + μ)(3c + ab)(c + μ b²)/(c + ab) − μ(3c − ab)`,
///
/// from `∫_μ^1 x² D^{−3/2} dx = 2(1 − μ) M / (3ab(a + b)(c + ab))` (derived
/// from the elementary antiderivative `(3c² + 6cD − D²)/(12 g³ √D)` by
/// factoring `a − b = 2g(1 − μ)/(a + b)` and `c − ab` out of the difference,
/// which removes every power of `1/g`; g = 0 gives `(1 − μ³)/3`). The first
/// factor is the HG cdf, `c + μb² = 2g + (1 + μ) b²`.
fn mass(g: f64, alpha: f64, n: f64, hg: &HenyeyGreenstein<f64>, x: f64, y: f64) -> f64 {
    let d = versines(x, y);
    let a = libm::sqrt(hg.denominator(d));
    let b = 1.0 - g;
    let c = 1.0 + g * g;
    let ab = a * b;
    let mu = d.cos();
    let m = y * (3.0 * c + ab) * (2.0 * g + y * b * b) / (c + ab) - mu * (3.0 * c - ab);
    let hg_part = (1.0 + g) * x / (a * (a + b));
    (hg_part * (1.0 + alpha * m / (3.0 * (c + ab))) / n).min(1.0)
}

/// Jendersie & d'Eon's closed-form inverse of Draine's cdf in `μ`, generic so
/// the tests can show its failure in f32. `xi = P(cos Θ ≤ μ)`.
///
/// For `|g| < 10⁻²` the g = 0 solution of `∝ 1 + αμ²`:
/// `b = (3 + α)/α · (½ − ξ)`, `v = −(b + √(b² + α⁻³))^{−1/3}`, `μ = 1/v − v/α`;
/// for α = 0 Henyey–Greenstein's inverse; otherwise the quartic's root (terms
/// `T1a … T10` as in their HLSL code and Cycles' `phase_draine_sample`).
pub(crate) fn closed_form<F: Real>(g: F, alpha: F, xi: F) -> F {
    let one = F::ONE;
    let c = |x: f64| F::from_f64(x);
    if alpha == F::ZERO {
        if g.abs() < c(1e-3) {
            return one - F::TWO * (one - xi);
        }
        let k = (one - g * g) / (one - g + F::TWO * g * xi);
        return (one + g * g - k * k) / (F::TWO * g);
    }
    if g.abs() < c(1e-2) {
        let b = (c(3.0) + alpha) / alpha * (F::HALF - xi);
        let v = -one / cbrt_start(b + (b * b + one / (alpha * alpha * alpha)).sqrt());
        return (one / v - v / alpha).clamp_to(-one, one);
    }
    let g2 = g * g;
    let g3 = g * g2;
    let g4 = g2 * g2;
    let g6 = g2 * g4;
    let s = F::TWO * xi - one;
    let t1a = alpha * (g4 - one);
    let t2 = c(-1296.0)
        * (g2 - one)
        * (alpha - alpha * g2)
        * t1a
        * (c(4.0) * g2 + alpha * (one + g2).sqr());
    let t9 = F::TWO + g2 + g3 * (one + F::TWO * g2) * s;
    let t3 = c(3.0) * g2 * (one + g * s) + alpha * t9;
    let t4a = c(432.0) * t1a * t1a * t1a + t2 + c(432.0) * alpha * (one - g2) * t3 * t3;
    let t10 = alpha * (F::TWO * g4 - g2 - g6);
    let t4b = c(144.0) * t10;
    let t4 = t4a + (t4a * t4a - c(4.0) * t4b * t4b * t4b).sqrt();
    let cb2 = c(core::f64::consts::LN_2 / 3.0).exp();
    let t4c = cbrt_start(t4);
    let t6 =
        (F::TWO * t1a + c(48.0) * cb2 * t10 / t4c + t4c / (c(3.0) * cb2)) / (alpha * (one - g2));
    let t5 = c(6.0) * (one + g2) + t6;
    let t7 = c(6.0) * (one + g2) - c(8.0) * t3 / (alpha * (g2 - one) * t5.sqrt()) - t6;
    (one + g2 - c(0.25) * (t7.sqrt() - t5.sqrt()).sqr()) / (F::TWO * g)
}

impl<F: Real> PhaseFunction<F> for Draine<F> {
    /// `p = (1 − g²)(1 + α cos²θ) / (4π N D^{3/2})`, with HG's
    /// cancellation-free `D = 1 + g² − 2g cos θ`.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        let den = self.hg.denominator(d);
        let mu = d.cos();
        self.scale * (F::ONE + self.alpha * mu * mu) / (den * den.sqrt())
    }

    /// Closed-form start (in f64) polished by safeguarded Newton on the f64
    /// cdf in `1 − cos θ` (or `1 + cos θ` past π/2): exact inverse of `cdf`.
    fn sample(&self, u: F) -> Deflection<F> {
        let u64 = u.to_f64();
        let mu0 = self.closed_form_cos(u);
        // A NaN start (never seen in f64) just means "no guess".
        let guess = if mu0.is_finite() { 1.0 - mu0 } else { -1.0 };
        let (x, y) = invert_cdf(
            u64,
            guess,
            |x, y| self.cdf64(x, y),
            |x, y| self.ccdf64(x, y),
            |x, y| self.dens64(x, y),
        );
        Deflection::from_versines(F::from_f64(x), F::from_f64(y))
    }

    /// The closed form of `mass` below, evaluated in f64:
    /// `P(Θ ≤ θ) = (1 + g)(1 − μ)/(a(a + b)) · (1 + α M/(3(c + ab))) / N`.
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        F::from_f64(self.cdf64(d.one_minus_cos.to_f64(), d.one_plus_cos.to_f64()))
    }

    /// `⟨cos θ⟩ = g (1 + α(3 + 2g²)/5) / (1 + α(1 + 2g²)/3)`.
    #[inline]
    fn mean_cosine(&self) -> F {
        let g = self.g.to_f64();
        let a = self.alpha.to_f64();
        F::from_f64(g * (1.0 + a * (3.0 + 2.0 * g * g) / 5.0) / self.norm64())
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::*;
    use super::*;

    const CASES: [(f64, f64); 10] = [
        (0.0, 0.0),
        (0.0, 1.0),
        (0.005, 250.0),
        (0.5, 0.0),
        (0.5, 1.0),
        (0.5557, 22.0),
        (0.3, 250.0),
        (-0.6, 10.0),
        (0.95, 3.0),
        (-0.9, 1000.0),
    ];

    #[test]
    fn normalised_with_exact_cdf_and_mean() {
        let mut worst = [0.0f64; 3];
        for (g, a) in CASES {
            let p = Draine::<f64>::new(g, a).unwrap();
            let e = [normalisation_error(&p), cdf_error(&p), mean_error(&p)];
            for k in 0..3 {
                worst[k] = worst[k].max(e[k]);
            }
            assert!(e.iter().all(|&v| v < 1e-9), "g = {g}, α = {a}: {e:?}");
        }
        report("draine normalisation", worst[0]);
        report("draine cdf vs quadrature", worst[1]);
        report("draine mean vs quadrature", worst[2]);
    }

    #[test]
    fn special_cases_match_hg_and_rayleigh() {
        let hg = HenyeyGreenstein::<f64>::new(0.7).unwrap();
        let dr = Draine::<f64>::new(0.7, 0.0).unwrap();
        let ra = Draine::<f64>::new(0.0, 1.0).unwrap();
        for t in [0.0, 1e-4, 0.3, 1.5, 3.0, core::f64::consts::PI] {
            let d = Deflection::from_theta(t);
            assert!((dr.eval(d) / hg.eval(d) - 1.0).abs() < 1e-14);
            assert!((dr.cdf(d) - hg.cdf(d)).abs() < 1e-15);
            let r: f64 = super::super::Rayleigh.cdf(d);
            assert!((ra.cdf(d) - r).abs() < 1e-15);
        }
        // Small-angle relative accuracy of the cdf: P ≈ 2π p(0) (1 − cos θ).
        let p = Draine::<f64>::new(0.3, 250.0).unwrap();
        let d = Deflection::from_theta(1e-7);
        let expected =
            core::f64::consts::TAU * p.eval(Deflection::from_theta(0.0)) * d.one_minus_cos;
        assert!((p.cdf(d) / expected - 1.0).abs() < 1e-9);
    }

    #[test]
    fn sample_inverts_cdf_in_f64() {
        let mut worst = 0.0f64;
        for (g, a) in CASES {
            let p = Draine::<f64>::new(g, a).unwrap();
            let e = inversion_error::<f64, _>(&p);
            assert!(e < 1e-13, "g = {g}, α = {a}: {e}");
            worst = worst.max(e);
        }
        report("draine |cdf(sample(u)) - u| f64", worst);
    }

    #[test]
    fn f32_sampling_at_alpha_250_is_sound() {
        let mut worst_cdf = 0.0f64;
        let mut worst_theta = 0.0f64;
        for g in [0.02, 0.05, 0.3, 0.6] {
            let p32 = Draine::<f32>::new(g as f32, 250.0).unwrap();
            let p64 = Draine::<f64>::new(g as f32 as f64, 250.0).unwrap();
            // No NaN, |cos| ≤ 1, monotone, and cdf(sample(u)) = u.
            let e = inversion_error::<f32, _>(&p32);
            assert!(e < 1e-5, "g = {g}: {e}");
            worst_cdf = worst_cdf.max(e);
            for u in u_grid::<f32>() {
                let d32 = p32.sample(u);
                let d64 = p64.sample(u as f64);
                let rel = (d32.theta as f64 - d64.theta).abs() / d64.theta.max(1e-30);
                assert!(rel < 1e-6, "g = {g}, u = {u}: {d32:?} vs {d64:?}");
                worst_theta = worst_theta.max(rel);
            }
            assert!(f32_eval_error(&p32, &p64) < 1e-4);
            assert_eval_finite::<f32, _>(&p32);
        }
        report("draine f32 α=250 max |cdf(sample(u)) - u|", worst_cdf);
        report("draine f32 α=250 max rel θ difference to f64", worst_theta);
    }

    #[test]
    fn closed_form_alone_in_f32_and_f64() {
        // Measured, not asserted for f32: the reason the sampler runs in f64.
        for g in [0.02f64, 0.05, 0.3, 0.6] {
            let p = Draine::<f64>::new(g, 250.0).unwrap();
            let (mut bad32, mut err64) = (0usize, 0.0f64);
            for i in 0..1000 {
                let u = (i as f64 + 0.5) / 1000.0;
                let mu32 = closed_form(g as f32, 250.0f32, 1.0 - u as f32);
                if mu32.is_nan() || mu32.abs() > 1.0 {
                    bad32 += 1;
                }
                let mu = closed_form(g, 250.0, 1.0 - u);
                err64 = err64.max((p.cdf(Deflection::from_cos(mu)) - u).abs());
            }
            report(
                "draine closed form f32 invalid samples of 1000",
                bad32 as f64,
            );
            report("draine closed form f64 max |cdf - u|", err64);
            assert!(err64 < 1e-6, "g = {g}: {err64}");
        }
    }

    #[test]
    fn constructor_rejects_bad_parameters() {
        assert_eq!(Draine::<f64>::new(f64::NAN, 1.0).unwrap_err().field(), "g");
        assert_eq!(Draine::<f64>::new(-1.0, 1.0).unwrap_err().field(), "g");
        assert_eq!(Draine::<f64>::new(0.5, -0.5).unwrap_err().field(), "alpha");
        assert_eq!(
            Draine::<f64>::new(0.5, f64::NAN).unwrap_err().field(),
            "alpha"
        );
        assert_eq!(Draine::<f32>::new(0.5, 1e4).unwrap_err().field(), "alpha");
        assert!(Draine::<f32>::new(0.5, 1000.0).is_ok());
    }
}
