//! Two-lobe mixtures `w·A + (1 − w)·B`, and the two-term Henyey–Greenstein
//! function built from them.

use super::{Deflection, HenyeyGreenstein, PhaseFunction};
use crate::error::{Error, check_closed, check_open};
use crate::real::Real;

/// The mixture `p = w·p_A + (1 − w)·p_B` of two phase functions, `w ∈ [0, 1]`
/// the weight of lobe A.
///
/// `eval`, `cdf` and `mean_cosine` are the weighted sums. `sample` chooses the
/// lobe with `u` (A if `u < w`) and reuses the remapped `u` inside the lobe, so
/// the samples have density `p` but `sample` is not the inverse of `cdf`:
/// [`invert`](PhaseFunction::invert) returns `None`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixture<A, B> {
    w: f64,
    a: A,
    b: B,
}

impl<A, B> Mixture<A, B> {
    /// `w·A + (1 − w)·B`; `w` (field `"w"`) must lie in `[0, 1]`.
    pub fn new(w: f64, a: A, b: B) -> Result<Self, Error> {
        check_closed("w", w, 0.0, 1.0, "[0, 1]")?;
        Ok(Self { w, a, b })
    }

    /// The weight `w` of the first lobe.
    #[inline]
    pub fn weight(&self) -> f64 {
        self.w
    }

    /// The first lobe A (weight `w`).
    #[inline]
    pub fn first(&self) -> &A {
        &self.a
    }

    /// The second lobe B (weight `1 − w`).
    #[inline]
    pub fn second(&self) -> &B {
        &self.b
    }
}

/// Two-term Henyey–Greenstein:
/// `p = w·HG(g1) + (1 − w)·HG(g2)`, mean cosine `w·g1 + (1 − w)·g2`.
pub type TwoTermHg<F> = Mixture<HenyeyGreenstein<F>, HenyeyGreenstein<F>>;

impl<F: Real> Mixture<HenyeyGreenstein<F>, HenyeyGreenstein<F>> {
    /// `w·HG(g1) + (1 − w)·HG(g2)` with `g1, g2 ∈ (−1, 1)` of either sign and
    /// `w ∈ [0, 1]` the weight of the `g1` lobe (fields `"g1"`, `"g2"`, `"w"`).
    ///
    /// For example the talk's water fit `(g1, g2) = (0.990, −0.440)` with
    /// `w ≈ 0.96`: a sharp forward lobe and a weak backward one.
    pub fn two_term(g1: F, g2: F, w: F) -> Result<Self, Error> {
        check_open("g1", g1.to_f64(), -1.0, 1.0, "(-1, 1)")?;
        check_open("g2", g2.to_f64(), -1.0, 1.0, "(-1, 1)")?;
        Self::new(
            w.to_f64(),
            HenyeyGreenstein::new(g1)?,
            HenyeyGreenstein::new(g2)?,
        )
    }
}

impl<F: Real, A: PhaseFunction<F>, B: PhaseFunction<F>> PhaseFunction<F> for Mixture<A, B> {
    /// `w·p_A(θ) + (1 − w)·p_B(θ)`.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        let w = F::from_f64(self.w);
        w * self.a.eval(d) + F::from_f64(1.0 - self.w) * self.b.eval(d)
    }

    /// Lobe A with `u/w` if `u < w`, else lobe B with `(u − w)/(1 − w)`; the
    /// remapped number is kept below 1 (`F::ONE_MINUS_EPSILON`) against rounding.
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        let uf = u.to_f64();
        if uf < self.w {
            self.a
                .sample(F::from_f64(uf / self.w).min(F::ONE_MINUS_EPSILON))
        } else {
            let v = (uf - self.w) / (1.0 - self.w);
            self.b
                .sample(F::from_f64(v).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON))
        }
    }

    /// `w·P_A(Θ ≤ θ) + (1 − w)·P_B(Θ ≤ θ)`.
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        let w = F::from_f64(self.w);
        w * self.a.cdf(d) + F::from_f64(1.0 - self.w) * self.b.cdf(d)
    }

    /// `w·q_A(θ) + (1 − w)·q_B(θ)`, the density `sample` draws with (equal to
    /// `eval` for lobes that sample exactly).
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        let w = F::from_f64(self.w);
        w * self.a.pdf(d) + F::from_f64(1.0 - self.w) * self.b.pdf(d)
    }

    /// [`sample_pdf`](PhaseFunction::sample_pdf) with the ratio `eval/pdf`:
    /// 1 if both lobes sample exactly, else evaluated.
    #[inline]
    fn sample_ratio(&self, u: F) -> (Deflection<F>, F, F) {
        let (d, pdf) = self.sample_pdf(u);
        if self.samples_exactly() {
            (d, pdf, F::ONE)
        } else {
            (d, pdf, self.eval(d) / pdf)
        }
    }

    /// Whether both lobes sample exactly.
    #[inline]
    fn samples_exactly(&self) -> bool {
        self.a.samples_exactly() && self.b.samples_exactly()
    }

    /// `w·⟨cos θ⟩_A + (1 − w)·⟨cos θ⟩_B`.
    #[inline]
    fn mean_cosine(&self) -> F {
        let w = F::from_f64(self.w);
        w * self.a.mean_cosine() + F::from_f64(1.0 - self.w) * self.b.mean_cosine()
    }

    /// `None`: the lobe choice consumes part of `u`, so no single `u` maps to `d`.
    #[inline]
    fn invert(&self, _d: Deflection<F>) -> Option<F> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::*;
    use super::super::{Isotropic, Rayleigh};
    use super::*;

    const FITS: [(f64, f64, f64); 4] = [
        (0.997, 0.960, 0.96),
        (0.990, -0.440, 0.96),
        (0.5, -0.5, 0.25),
        (-0.3, 0.0, 1.0),
    ];

    #[test]
    fn two_term_hg_is_normalised_with_exact_cdf_and_mean() {
        for (g1, g2, w) in FITS {
            let p = TwoTermHg::<f64>::two_term(g1, g2, w).unwrap();
            let (n, c, m) = (normalisation_error(&p), cdf_error(&p), mean_error(&p));
            report("tthg normalisation", n);
            report("tthg cdf vs quadrature", c);
            assert!(
                n < 1e-8 && c < 1e-8 && m < 1e-8,
                "{g1} {g2} {w}: {n} {c} {m}"
            );
            let mean: f64 = p.mean_cosine();
            assert!((mean - (w * g1 + (1.0 - w) * g2)).abs() < 1e-15);
        }
    }

    #[test]
    fn samples_follow_the_cdf_and_invert_is_none() {
        for (g1, g2, w) in FITS {
            let p64 = TwoTermHg::<f64>::two_term(g1, g2, w).unwrap();
            let p32 = TwoTermHg::<f32>::two_term(g1 as f32, g2 as f32, w as f32).unwrap();
            // Stratified u with 2·10⁴ points: the empirical cdf is within a
            // few 1/N of the exact one (a wrong remap breaks this by ~w).
            let e = stratified_cdf_error(&p64);
            assert!(e < 5e-4, "{e}");
            assert!(stratified_cdf_error(&p32) < 5e-4);
            assert!(p64.invert(Deflection::from_theta(0.3)).is_none());
            for u in u_grid::<f32>() {
                assert!(p32.sample(u).is_finite());
            }
            assert_eval_finite::<f32, _>(&p32);
            assert_eval_finite::<f64, _>(&p64);
            let r = f32_eval_error(&p32, &p64);
            assert!(r < 1e-4, "{r}");
        }
        // A mixture of other lobes through the generic constructor.
        let m = Mixture::new(0.3, Isotropic, Rayleigh).unwrap();
        let c: f64 = m.cdf(Deflection::from_theta(1.0));
        let expected = 0.3 * Isotropic.cdf(Deflection::from_theta(1.0))
            + 0.7 * PhaseFunction::<f64>::cdf(&Rayleigh, Deflection::from_theta(1.0));
        assert!((c - expected).abs() < 1e-16);
        assert!(stratified_cdf_error::<f64, _>(&m) < 5e-4);
    }

    #[test]
    fn constructors_reject_bad_parameters() {
        let field = |r: Result<TwoTermHg<f64>, Error>| r.unwrap_err().field();
        assert_eq!(field(TwoTermHg::two_term(f64::NAN, 0.5, 0.5)), "g1");
        assert_eq!(field(TwoTermHg::two_term(1.0, 0.5, 0.5)), "g1");
        assert_eq!(field(TwoTermHg::two_term(0.5, -1.0, 0.5)), "g2");
        assert_eq!(field(TwoTermHg::two_term(0.5, 0.5, 1.5)), "w");
        assert_eq!(field(TwoTermHg::two_term(0.5, 0.5, f64::NAN)), "w");
        assert_eq!(
            Mixture::new(-0.1, Isotropic, Rayleigh).unwrap_err().field(),
            "w"
        );
    }
}
