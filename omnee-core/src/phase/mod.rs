//! Phase functions: the angular distribution of scattering at the vertex `x1`.
//!
//! Conventions (docs/math.md §1): θ is the deflection between the *propagation*
//! directions before and after scattering, `cos θ = ω1 · ω2`; θ = 0 is straight
//! on. Every phase function is normalised over the sphere, `∫ p dω = 1`, i.e.
//! `2π ∫₀^π p(θ) sin θ dθ = 1`, so Henyey–Greenstein with g > 0 peaks at θ = 0.
//! (pbrt and Mitsuba pass both directions pointing away from the vertex: their
//! cosine is `−ω1 · ω2`.)
//!
//! Angles travel as a [`Deflection`], which carries `1 − cos θ` and `1 + cos θ`
//! next to θ: for a forward peak like g = 0.997 the typical `1 − cos θ` is
//! 4.5e-6 and `cos θ` in f32 would keep two digits of it (docs/math.md §4).
//!
//! Each phase function implements [`PhaseFunction`]: `eval`, an inverse-CDF
//! `sample`, its `cdf` (so `cdf(sample(u)) = u`), and the mean cosine.

mod draine;
mod fournier_forand;
mod henyey_greenstein;
mod inverse_cdf;
mod invert;
mod isotropic;
mod mie;
mod mixture;
mod rayleigh;
mod spec;
mod tabulated;
#[cfg(test)]
mod testing;

pub use draine::{DRAINE_ALPHA_MAX, Draine};
pub use fournier_forand::{FF_N_MAX, FF_N_MIN, FournierForand};
pub use henyey_greenstein::HenyeyGreenstein;
pub use inverse_cdf::{INVERSE_CDF_BINS, InverseCdf, TableSampled};
pub use isotropic::Isotropic;
pub use mie::{MIE_DIAMETER_MAX_UM, Mie, MieFit, mie_fit};
pub use mixture::{Mixture, TwoTermHg};
pub use rayleigh::Rayleigh;
pub use spec::{ParsedSpec, PhaseKind, Spec};
pub use tabulated::Tabulated;

use crate::real::{Real, Vector};

/// A deflection angle θ ∈ [0, π] in cancellation-free form.
///
/// Invariants (up to rounding): `one_minus_cos = 1 − cos θ = 2 sin²(θ/2)`,
/// `one_plus_cos = 1 + cos θ = 2 cos²(θ/2)`, their sum is 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deflection<F> {
    /// θ in radians, in `[0, π]`.
    pub theta: F,
    /// `1 − cos θ`, accurate to the last bit near θ = 0.
    pub one_minus_cos: F,
    /// `1 + cos θ`, accurate to the last bit near θ = π.
    pub one_plus_cos: F,
}

impl<F: Real> Deflection<F> {
    /// From θ (clamped to `[0, π]`): `1 ∓ cos θ = 2 sin²(θ/2)`, `2 cos²(θ/2)`.
    #[inline]
    pub fn from_theta(theta: F) -> Self {
        let theta = theta.clamp_to(F::ZERO, F::PI);
        let (s, c) = (theta * F::HALF).sin_cos_acute();
        Self {
            theta,
            one_minus_cos: F::TWO * s * s,
            one_plus_cos: F::TWO * c * c,
        }
    }

    /// From both versines, each computed without cancellation by the caller:
    /// `θ = 2 atan2(√(1 − cos θ), √(1 + cos θ))` (stable over all of `[0, π]`).
    #[inline]
    pub fn from_versines(one_minus_cos: F, one_plus_cos: F) -> Self {
        let omc = one_minus_cos.clamp_to(F::ZERO, F::TWO);
        let opc = one_plus_cos.clamp_to(F::ZERO, F::TWO);
        Self {
            theta: F::TWO * omc.atan2_sqrt(opc),
            one_minus_cos: omc,
            one_plus_cos: opc,
        }
    }

    /// From `1 − cos θ` alone (accurate for θ ≤ π/2; `1 + cos θ = 2 − (1 − cos θ)`).
    #[inline]
    pub fn from_one_minus_cos(one_minus_cos: F) -> Self {
        let omc = one_minus_cos.clamp_to(F::ZERO, F::TWO);
        Self::from_versines(omc, F::TWO - omc)
    }

    /// From cos θ (clamped to `[−1, 1]`); loses the digits docs/math.md §4 warns
    /// about near θ = 0 and π, so use it only where cos θ is all there is.
    #[inline]
    pub fn from_cos(cos_theta: F) -> Self {
        let c = cos_theta.clamp_to(-F::ONE, F::ONE);
        Self::from_versines(F::ONE - c, F::ONE + c)
    }

    /// Between two *unit* propagation directions:
    /// `1 − ω1·ω2 = |ω1 − ω2|²/2`, `1 + ω1·ω2 = |ω1 + ω2|²/2`, exact where
    /// `1 − ω1·ω2` is not, and `θ = 2 atan2(|ω1 − ω2|, |ω1 + ω2|)`.
    #[inline]
    pub fn between<V: Vector<F>>(omega1: V, omega2: V) -> Self {
        Self::from_difference_and_sum(omega1 - omega2, omega1 + omega2)
    }

    /// Between the directions of two non-zero vectors `a` (length `la`) and
    /// `b` (length `lb`), without normalising them: [`between`](Self::between)
    /// of `a/la` and `b/lb`, scaled by `la lb`, i.e. with
    /// `m = |lb a − la b|²` and `p = |lb a + la b|²`,
    /// `1 − cos θ = 2m/(m + p)`, `1 + cos θ = 2p/(m + p)`, `θ = 2 atan2(√m, √p)`.
    #[inline]
    pub fn between_segments<V: Vector<F>>(a: V, la: F, b: V, lb: F) -> Self {
        Self::from_difference_and_sum(a * lb - b * la, a * lb + b * la)
    }

    /// From `δ = ω1 − ω2` and `σ = ω1 + ω2` of two directions of equal
    /// length: `θ = 2 atan2(|δ|, |σ|)`, and the versines `2|δ|²/(|δ|² + |σ|²)`,
    /// `2|σ|²/(|δ|² + |σ|²)`, which sum to 2 whatever the common length.
    #[inline]
    fn from_difference_and_sum<V: Vector<F>>(difference: V, sum: V) -> Self {
        let minus = difference.length_squared();
        let plus = sum.length_squared();
        let k = F::TWO / (minus + plus);
        Self {
            theta: F::TWO * minus.atan2_sqrt(plus),
            one_minus_cos: minus * k,
            one_plus_cos: plus * k,
        }
    }

    /// cos θ, from whichever versine is smaller (so it is accurate near ±1 in
    /// the absolute sense).
    #[inline]
    pub fn cos(&self) -> F {
        if self.one_minus_cos <= F::ONE {
            F::ONE - self.one_minus_cos
        } else {
            self.one_plus_cos - F::ONE
        }
    }

    /// sin θ = √((1 − cos θ)(1 + cos θ)), accurate at both ends.
    #[inline]
    pub fn sin(&self) -> F {
        (self.one_minus_cos * self.one_plus_cos).sqrt()
    }

    /// Whether all three fields are finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.theta.is_finite() && self.one_minus_cos.is_finite() && self.one_plus_cos.is_finite()
    }
}

/// A phase function p(θ), normalised over the sphere, with exact sampling.
///
/// Every implementation keeps the trio of the core's sampling routines:
/// `sample` draws Θ with density `2π p(θ) sin θ` from one uniform number,
/// `pdf` is that density per solid angle, and `invert` maps a deflection back to
/// the uniform number. For an inverse-CDF sampler `invert = cdf`.
pub trait PhaseFunction<F: Real> {
    /// p(θ) per steradian, `∫ p dω = 1`.
    fn eval(&self, d: Deflection<F>) -> F;

    /// A deflection with solid-angle density `pdf`, from `u ∈ [0, 1)`.
    fn sample(&self, u: F) -> Deflection<F>;

    /// `P(Θ ≤ θ) = 2π ∫₀^θ p(θ') sin θ' dθ'`.
    fn cdf(&self, d: Deflection<F>) -> F;

    /// ⟨cos θ⟩, the mean cosine (the "g" of the function).
    fn mean_cosine(&self) -> F;

    /// The solid-angle density of [`sample`](Self::sample); equal to `eval` for
    /// every phase function of this crate (they sample exactly).
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        self.eval(d)
    }

    /// `(d, pdf(d))` with `d = sample(u)`, for samplers that know the density
    /// of their draw more cheaply than by evaluating it again.
    #[inline]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        let d = self.sample(u);
        (d, self.pdf(d))
    }

    /// `(d, pdf(d), eval(d) / pdf(d))` with `d = sample(u)`: the deflection,
    /// the density it was drawn with, and the factor `p/q` by which an
    /// estimator that divides by that density must correct for drawing from
    /// `q = pdf` instead of `p = eval`. 1 for every sampler that draws `p`
    /// exactly (the default); [`TableSampled`] returns its table's ratio.
    #[inline]
    fn sample_ratio(&self, u: F) -> (Deflection<F>, F, F) {
        let (d, pdf) = self.sample_pdf(u);
        (d, pdf, F::ONE)
    }

    /// Whether `sample` draws `eval` exactly, i.e. `pdf = eval` and
    /// [`sample_ratio`](Self::sample_ratio)'s ratio is 1 (true but for
    /// [`TableSampled`] and mixtures of it).
    #[inline]
    fn samples_exactly(&self) -> bool {
        true
    }

    /// The `u` with `sample(u) = d`, where `sample` is invertible; `cdf(d)` for
    /// inverse-CDF samplers. Mixtures choose a lobe with `u` and return `None`.
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        Some(self.cdf(d))
    }

    /// The fraction scattered backwards, `B = P(Θ > π/2) = 1 − cdf(π/2)`.
    #[inline]
    fn backscatter_fraction(&self) -> F {
        F::ONE - self.cdf(Deflection::from_versines(F::ONE, F::ONE))
    }
}

impl<F: Real, P: PhaseFunction<F> + ?Sized> PhaseFunction<F> for &P {
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        (**self).eval(d)
    }
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        (**self).sample(u)
    }
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        (**self).cdf(d)
    }
    #[inline]
    fn mean_cosine(&self) -> F {
        (**self).mean_cosine()
    }
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        (**self).pdf(d)
    }
    #[inline]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        (**self).sample_pdf(u)
    }
    #[inline]
    fn sample_ratio(&self, u: F) -> (Deflection<F>, F, F) {
        (**self).sample_ratio(u)
    }
    #[inline]
    fn samples_exactly(&self) -> bool {
        (**self).samples_exactly()
    }
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        (**self).invert(d)
    }
}

/// Any phase function of this module, for run-time selection (e.g. from a
/// [`Spec`] string), its table variant of type `T`. Every method dispatches
/// to the variant's own. [`Phase`] is this enum with the caller-owned
/// [`Tabulated`] tables; a program that never tabulates (the browser demo)
/// uses `AnyPhase<F, NoTable>`, whose table variant cannot be built, so the
/// table's code is not linked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyPhase<F, T> {
    /// `p = 1/(4π)`.
    Isotropic(Isotropic),
    /// `p = (1 − g²)/(4π (1 + g² − 2g cos θ)^{3/2})`.
    HenyeyGreenstein(HenyeyGreenstein<F>),
    /// `w·HG(g1) + (1 − w)·HG(g2)`.
    TwoTermHg(TwoTermHg<F>),
    /// Fournier–Forand with backscatter fraction B and refractive index n.
    FournierForand(FournierForand<F>),
    /// Draine: HG times `(1 + α cos²θ)`, normalised.
    Draine(Draine<F>),
    /// Approximate Mie: `(1 − w)·HG + w·Draine` fitted to droplet diameter.
    Mie(Mie<F>),
    /// `p = 3/(16π) (1 + cos²θ)`.
    Rayleigh(Rayleigh),
    /// A table, constant per solid angle in each bin.
    Tabulated(T),
}

/// Any phase function of this module, tables borrowed for `'a`: the
/// run-time choice every front end uses.
pub type Phase<'a, F> = AnyPhase<F, Tabulated<'a, F>>;

/// The table type of a program without tables: it has no values, so
/// `AnyPhase<F, NoTable>` has no table variant to dispatch to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoTable {}

impl<F: Real> PhaseFunction<F> for NoTable {
    fn eval(&self, _: Deflection<F>) -> F {
        match *self {}
    }
    fn sample(&self, _: F) -> Deflection<F> {
        match *self {}
    }
    fn cdf(&self, _: Deflection<F>) -> F {
        match *self {}
    }
    fn mean_cosine(&self) -> F {
        match *self {}
    }
}

impl<F, T> AnyPhase<F, T> {
    /// The same phase function with the table type `U`, if it is not a
    /// table (`None` for [`AnyPhase::Tabulated`]).
    pub fn analytic<U>(self) -> Option<AnyPhase<F, U>> {
        Some(match self {
            AnyPhase::Isotropic(p) => AnyPhase::Isotropic(p),
            AnyPhase::HenyeyGreenstein(p) => AnyPhase::HenyeyGreenstein(p),
            AnyPhase::TwoTermHg(p) => AnyPhase::TwoTermHg(p),
            AnyPhase::FournierForand(p) => AnyPhase::FournierForand(p),
            AnyPhase::Draine(p) => AnyPhase::Draine(p),
            AnyPhase::Mie(p) => AnyPhase::Mie(p),
            AnyPhase::Rayleigh(p) => AnyPhase::Rayleigh(p),
            AnyPhase::Tabulated(_) => return None,
        })
    }
}

/// Calls `$call` on whichever phase function the [`AnyPhase`] `$self`
/// holds, bound to `$p`: the one dispatch of the enum, for every trait it
/// implements.
macro_rules! dispatch {
    ($self:expr, $p:ident => $call:expr) => {
        match $self {
            $crate::phase::AnyPhase::Isotropic($p) => $call,
            $crate::phase::AnyPhase::HenyeyGreenstein($p) => $call,
            $crate::phase::AnyPhase::TwoTermHg($p) => $call,
            $crate::phase::AnyPhase::FournierForand($p) => $call,
            $crate::phase::AnyPhase::Draine($p) => $call,
            $crate::phase::AnyPhase::Mie($p) => $call,
            $crate::phase::AnyPhase::Rayleigh($p) => $call,
            $crate::phase::AnyPhase::Tabulated($p) => $call,
        }
    };
}
pub(crate) use dispatch;

impl<F: Real, T: PhaseFunction<F>> PhaseFunction<F> for AnyPhase<F, T> {
    /// The variant's `p(θ)`.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.eval(d))
    }
    /// The variant's sampler.
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        dispatch!(self, p => p.sample(u))
    }
    /// The variant's `P(Θ ≤ θ)`.
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.cdf(d))
    }
    /// The variant's mean cosine.
    #[inline]
    fn mean_cosine(&self) -> F {
        dispatch!(self, p => PhaseFunction::<F>::mean_cosine(p))
    }
    /// The variant's pdf (its `eval`).
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.pdf(d))
    }
    /// The variant's sample with its pdf.
    #[inline]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        dispatch!(self, p => p.sample_pdf(u))
    }
    /// The variant's sample with its pdf and ratio (1: every variant samples
    /// exactly).
    #[inline]
    fn sample_ratio(&self, u: F) -> (Deflection<F>, F, F) {
        dispatch!(self, p => p.sample_ratio(u))
    }
    /// The variant's (true for all of them).
    #[inline]
    fn samples_exactly(&self) -> bool {
        dispatch!(self, p => PhaseFunction::<F>::samples_exactly(p))
    }
    /// The variant's inverse (`None` for the mixtures).
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        dispatch!(self, p => p.invert(d))
    }
    /// The variant's backscatter fraction.
    #[inline]
    fn backscatter_fraction(&self) -> F {
        dispatch!(self, p => PhaseFunction::<F>::backscatter_fraction(p))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::testing::*;
    use super::*;
    use std::string::ToString;

    const SPECS: [&str; 11] = [
        "iso",
        "hg:0.9",
        "hg:-0.6",
        "hg:0.997",
        "hg:0",
        "rayleigh",
        "tthg:0.99,-0.44,0.96",
        "ff:0.0183,1.1",
        "draine:0.5557,22",
        "mie:10",
        "mie:0.5",
    ];

    fn phase<F: Real>(s: &str) -> Phase<'static, F> {
        match Spec::<F>::parse(s).unwrap() {
            Spec::Analytic(p) => p,
            Spec::Table { .. } => unreachable!(),
        }
    }

    #[test]
    fn every_analytic_phase_function_passes_the_common_checks() {
        let mut worst = [0.0f64; 4];
        for s in SPECS {
            let p64 = phase::<f64>(s);
            let p32 = phase::<f32>(s);
            let e = [normalisation_error(&p64), cdf_error(&p64), mean_error(&p64)];
            assert!(e.iter().all(|&v| v < 1e-6), "{s}: {e:?}");
            assert_eval_finite::<f64, _>(&p64);
            assert_eval_finite::<f32, _>(&p32);
            let p64r = phase::<f64>(&std_string(&p32));
            let r = f32_eval_error(&p32, &p64r);
            assert!(r < 1e-4, "{s}: f32 eval off by {r}");
            let inv = p64.invert(Deflection::from_theta(0.5)).is_some();
            let i = if inv {
                inversion_error::<f64, _>(&p64)
            } else {
                stratified_cdf_error(&p64)
            };
            assert!(i < if inv { 1e-12 } else { 5e-4 }, "{s}: {i}");
            if inv {
                assert!(inversion_error::<f32, _>(&p32) < 1e-5, "{s}");
            }
            for k in 0..3 {
                worst[k] = worst[k].max(e[k]);
            }
            worst[3] = worst[3].max(r);
        }
        report("all: normalisation", worst[0]);
        report("all: cdf vs quadrature", worst[1]);
        report("all: mean cosine vs quadrature", worst[2]);
        report("all: f32 vs f64 eval (relative)", worst[3]);
    }

    #[test]
    fn sample_pdf_is_the_sample_with_its_density() {
        for s in SPECS {
            let p = phase::<f64>(s);
            let mut worst = 0.0f64;
            for i in 0..1000 {
                let u = (i as f64 + 0.5) / 1000.0;
                let (d, pdf) = p.sample_pdf(u);
                assert_eq!(d, p.sample(u), "{s}: u = {u}");
                worst = worst.max((pdf / p.pdf(d) - 1.0).abs());
            }
            // HG's closed-form density k³/(4π(1 − g²)²) against its eval.
            assert!(worst < 1e-12, "{s}: {worst:e}");
        }
    }

    /// The f32 phase function's spec, re-parsed in f64 (same parameters).
    fn std_string(p: &Phase<'static, f32>) -> std::string::String {
        p.to_string()
    }

    #[test]
    fn dispatch_reaches_the_variant() {
        let hg = HenyeyGreenstein::<f64>::new(0.7).unwrap();
        let p = Phase::HenyeyGreenstein(hg);
        let d = Deflection::from_theta(0.2);
        assert_eq!(p.eval(d), hg.eval(d));
        assert_eq!(p.cdf(d), hg.cdf(d));
        assert_eq!(p.sample(0.3), hg.sample(0.3));
        assert_eq!(p.mean_cosine(), 0.7);
        assert_eq!(p.invert(d), Some(hg.cdf(d)));
        let m = phase::<f64>("mie:10");
        assert_eq!(m.invert(d), None);
        let theta = [0.0, 1.0, core::f64::consts::PI];
        let mut buf = [0.0; 3];
        let t = Phase::Tabulated(Tabulated::new(&theta, &[1.0, 1.0], &mut buf).unwrap());
        assert!((t.cdf(d) - Isotropic.cdf(d)).abs() < 1e-15);
        assert!((t.backscatter_fraction() - 0.5).abs() < 1e-15);
    }
}
