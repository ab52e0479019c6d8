//! The number of inner vertices of a bridge, drawn with a probability that
//! follows the k-times scattered transfer (docs/math.md §14.7).

use super::{LN_FACTORIAL, MAX_VERTICES};
use crate::error::{Error, check_closed};
use crate::real::Real;

/// A distribution over the number of vertices `k ∈ 1 ..= k_max`: a Poisson
/// distribution of mean μ truncated to that range, mixed with the uniform
/// distribution for the share `f` (a defensive floor, docs/math.md §14.7),
///
/// `P(k) = (1 − f) (μ^k / k!) / Σ_{j=1}^{k_max} μ^j / j! + f / k_max`,
///
/// with μ from the connection ([`VertexCount::new`]) or given
/// ([`VertexCount::with_mean`]). Its cumulative table makes
/// [`pmf`](Self::pmf) O(1) and [`sample`](Self::sample) a scan of at most
/// `k_max` entries. `Σ_k I_k` over `1 ..= k_max` is estimated without bias by
/// drawing `k`, a bridge of `k` vertices, and dividing its estimate by `P(k)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexCount<F> {
    k_max: usize,
    mean: F,
    /// `cdf[k − 1] = P(K ≤ k)`; `cdf[k_max − 1] = 1` exactly.
    cdf: [F; MAX_VERTICES],
}

impl<F: Real> VertexCount<F> {
    /// The heuristic of docs/math.md §14.7 for a connection of length `s` in
    /// a medium with σs, σt and a phase function of mean cosine `g`:
    ///
    /// `μ = σs s (1 + (1 − |g|) σt s / 2)`,
    ///
    /// the expected number of scattering events along the straight line,
    /// stretched by the detours that a less forward phase function makes
    /// (fitted to the isotropic closed form, exact in the limit g → 1).
    /// The floor is [`VertexCount::FLOOR`]. Fails for `k_max` outside
    /// `1 ..= MAX_VERTICES`, negative or non-finite `s`, σs, σt, and `|g| > 1`.
    pub fn new(k_max: usize, s: F, sigma_s: F, sigma_t: F, g: F) -> Result<Self, Error> {
        check_closed("s", s.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        check_closed("sigma_s", sigma_s.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        check_closed("sigma_t", sigma_t.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        check_closed("g", g.to_f64(), -1.0, 1.0, "[-1, 1]")?;
        let (s, sigma_s, sigma_t, g) = (s.to_f64(), sigma_s.to_f64(), sigma_t.to_f64(), g.to_f64());
        let mean = sigma_s * s * (1.0 + 0.5 * (1.0 - g.abs()) * sigma_t * s);
        Self::with_mean(
            k_max,
            F::from_f64(mean.min(f64::MAX)),
            F::from_f64(Self::FLOOR),
        )
    }

    /// The uniform share of [`new`](Self::new): the bridges of many vertices
    /// have heavy-tailed weights where the Poisson terms are small
    /// (docs/math.md §14.7), and `P(k) ≥ 0.2/k_max` bounds what they add to
    /// the variance.
    pub const FLOOR: f64 = 0.2;

    /// The truncated Poisson distribution of mean `mean ≥ 0` (finite) on
    /// `1 ..= k_max`, mixed with the uniform one for the share
    /// `floor ∈ [0, 1]`; `mean = 0` puts the Poisson part on `k = 1`.
    pub fn with_mean(k_max: usize, mean: F, floor: F) -> Result<Self, Error> {
        check_closed("k_max", k_max as f64, 1.0, MAX_VERTICES as f64, "1 ..= 32")?;
        check_closed("mean", mean.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        check_closed("floor", floor.to_f64(), 0.0, 1.0, "[0, 1]")?;
        let floor = floor.to_f64();
        // ln(μ^k/k!) relative to the largest term, in f64.
        let ln_mean = libm::log(mean.to_f64());
        let ln_term = |k: usize| {
            if mean.to_f64() > 0.0 {
                k as f64 * ln_mean - LN_FACTORIAL[k]
            } else if k == 1 {
                0.0
            } else {
                f64::NEG_INFINITY
            }
        };
        let top = (1..=k_max).map(ln_term).fold(f64::NEG_INFINITY, f64::max);
        let mut terms = [0.0f64; MAX_VERTICES];
        let mut total = 0.0;
        for k in 1..=k_max {
            terms[k - 1] = libm::exp(ln_term(k) - top);
            total += terms[k - 1];
        }
        let mut cdf = [F::ONE; MAX_VERTICES];
        let mut running = 0.0;
        for k in 1..k_max {
            running += (1.0 - floor) * terms[k - 1] / total + floor / k_max as f64;
            cdf[k - 1] = F::from_f64(running.min(1.0));
        }
        Ok(Self { k_max, mean, cdf })
    }

    /// The largest `k`.
    #[inline]
    pub fn k_max(&self) -> usize {
        self.k_max
    }

    /// The Poisson mean μ before truncation.
    #[inline]
    pub fn mean(&self) -> F {
        self.mean
    }

    /// `P(K ≤ k)`: 0 below 1, 1 from `k_max` on.
    #[inline]
    pub fn cdf(&self, k: usize) -> F {
        match k {
            0 => F::ZERO,
            k if k >= self.k_max => F::ONE,
            k => self.cdf[k - 1],
        }
    }

    /// `P(K = k)`, 0 outside `1 ..= k_max`.
    #[inline]
    pub fn pmf(&self, k: usize) -> F {
        if k == 0 || k > self.k_max {
            return F::ZERO;
        }
        self.cdf(k) - self.cdf(k - 1)
    }

    /// The smallest `k` with `u < P(K ≤ k)` (inversion) and its
    /// probability `P(K = k)`, for `u ∈ [0, 1)`.
    #[inline]
    pub fn sample(&self, u: F) -> (usize, F) {
        let mut k = 1;
        while k < self.k_max && !(u < self.cdf[k - 1]) {
            k += 1;
        }
        (k, self.pmf(k))
    }

    /// The interval `[P(K ≤ k − 1), P(K ≤ k))` of the numbers `u` that
    /// [`sample`](Self::sample) maps to `k`; `None` outside `1 ..= k_max`.
    #[inline]
    pub fn invert(&self, k: usize) -> Option<(F, F)> {
        (k >= 1 && k <= self.k_max).then(|| (self.cdf(k - 1), self.cdf(k)))
    }
}
