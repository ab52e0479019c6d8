//! Multiple importance sampling (Veach 1997) over any set of [`Technique`]s.
//!
//! Every technique's density is in the volume measure, so weights combine
//! them directly. Weights are computed as
//! `w_i = 1 / (1 + Σ_{j≠i} (n_j p_j / n_i p_i)^β)`, which stays finite when a
//! density saturates near an end point.

use crate::phase::{Deflection, PhaseFunction};
use crate::real::Real;
use crate::sampling::{Omnee, Sample, Technique, saturate};

/// The MIS heuristic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Heuristic {
    /// Balance heuristic, `w_i = n_i p_i / Σ_j n_j p_j` (β = 1).
    #[default]
    Balance,
    /// Power heuristic with β = 2, `w_i = (n_i p_i)² / Σ_j (n_j p_j)²`.
    Power,
}

impl Heuristic {
    /// `(ratio)^β` for this heuristic.
    #[inline]
    fn power<F: Real>(self, ratio: F) -> F {
        match self {
            Heuristic::Balance => ratio,
            Heuristic::Power => ratio * ratio,
        }
    }

    /// The weight of a sample from technique `i` with `n_i p_i = own`, given
    /// the other techniques' `n_j p_j` at the same point:
    /// `w_i = 1 / (1 + Σ_{j≠i} (others_j / own)^β)`; 0 if `own` is 0.
    #[inline]
    pub fn weight<F: Real>(self, own: F, others: impl IntoIterator<Item = F>) -> F {
        if !(own > F::ZERO) {
            return F::ZERO;
        }
        let mut sum = F::ONE;
        for other in others {
            sum += self.power(other / own);
        }
        saturate(F::ONE / sum)
    }
}

/// The balance heuristic for two techniques, `n_f p_f / (n_f p_f + n_g p_g)`.
#[inline]
pub fn balance_heuristic<F: Real>(nf: F, f_pdf: F, ng: F, g_pdf: F) -> F {
    Heuristic::Balance.weight(nf * f_pdf, [ng * g_pdf])
}

/// The power heuristic (β = 2) for two techniques,
/// `(n_f p_f)² / ((n_f p_f)² + (n_g p_g)²)`.
#[inline]
pub fn power_heuristic<F: Real>(nf: F, f_pdf: F, ng: F, g_pdf: F) -> F {
    Heuristic::Power.weight(nf * f_pdf, [ng * g_pdf])
}

/// The MIS weight of technique `i` at `x1` in a multi-sample estimator
/// `Σ_i (1/n_i) Σ_k w_i(x_ik) k(x_ik)/p_i(x_ik)`, where technique `i` takes
/// `counts[i]` samples. `own_pdf` is `p_i(x1)` as returned with the sample.
pub fn multi_sample_weight<F: Real>(
    techniques: &[&dyn Technique<F>],
    counts: &[F],
    i: usize,
    x1: F::Vec3,
    own_pdf: F,
    heuristic: Heuristic,
) -> F {
    let others = techniques
        .iter()
        .zip(counts)
        .enumerate()
        .filter(|&(j, _)| j != i)
        .map(|(_, (t, &n))| n * t.pdf(x1));
    heuristic.weight(counts[i] * own_pdf, others)
}

/// One-sample MIS: technique `i` is chosen with probability `c_i`, its sample
/// weighted by `w_i / c_i`. With the balance heuristic this is sampling the
/// mixture `Σ c_j p_j` (Veach 1997, §9.2.4).
///
/// It is itself a [`Technique`]: `pdf` is the mixture density `Σ_j c_j p_j`
/// (the density of the returned points), and `weight = w_i · weight_i / c_i`.
/// The choice reuses `u0` (rescaled into the chosen technique's share), so the
/// combination still takes three numbers. Not invertible.
#[derive(Clone, Copy)]
pub struct OneSample<'a, F: Real, const N: usize> {
    techniques: [&'a dyn Technique<F>; N],
    probabilities: [F; N],
    heuristic: Heuristic,
}

impl<'a, F: Real, const N: usize> OneSample<'a, F, N> {
    /// Combines `techniques`, choosing technique `i` with probability
    /// `probabilities[i]` (normalised here; each finite and ≥ 0, not all 0).
    pub fn new(
        techniques: [&'a dyn Technique<F>; N],
        probabilities: [F; N],
        heuristic: Heuristic,
    ) -> Result<Self, crate::Error> {
        let mut total = F::ZERO;
        for &c in &probabilities {
            crate::error::check_closed("probabilities", c.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
            total += c;
        }
        if !(total > F::ZERO) {
            return Err(crate::Error::Degenerate {
                field: "probabilities",
                reason: "all zero",
            });
        }
        let probabilities = probabilities.map(|c| c / total);
        Ok(Self {
            techniques,
            probabilities,
            heuristic,
        })
    }

    /// The normalised selection probabilities.
    pub fn probabilities(&self) -> [F; N] {
        self.probabilities
    }
}

impl<F: Real, const N: usize> Technique<F> for OneSample<'_, F, N> {
    /// Chooses `i` by `u0`, rescales `u0` into `[0, 1)` and samples technique `i`.
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        let mut lo = F::ZERO;
        let mut chosen = N - 1;
        for (i, &c) in self.probabilities.iter().enumerate() {
            if u[0] < lo + c || i == N - 1 {
                chosen = i;
                break;
            }
            lo += c;
        }
        let c = self.probabilities[chosen];
        if !(c > F::ZERO) {
            return None;
        }
        let u0 = ((u[0] - lo) / c).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON);
        let s = self.techniques[chosen].sample([u0, u[1], u[2]])?;
        // Every other technique's c_j p_j(x1), evaluated once for both the
        // weight and the mixture density (the own density is the sample's).
        let mut others = [F::ZERO; N];
        for (j, other) in others.iter_mut().enumerate() {
            if j != chosen && self.probabilities[j] > F::ZERO {
                *other = self.probabilities[j] * self.techniques[j].pdf(s.x1);
            }
        }
        others[chosen] = F::ZERO;
        let own = c * s.pdf;
        let w = self.heuristic.weight(own, others);
        let mut mixture = own;
        for other in others {
            mixture += other;
        }
        Some(Sample {
            x1: s.x1,
            pdf: saturate(mixture),
            weight: saturate(w * s.weight / c),
        })
    }

    /// The mixture density `Σ_j c_j p_j(x1)`.
    fn pdf(&self, x1: F::Vec3) -> F {
        let mut total = F::ZERO;
        for (t, &c) in self.techniques.iter().zip(&self.probabilities) {
            if c > F::ZERO {
                total += c * t.pdf(x1);
            }
        }
        saturate(total)
    }

    /// Not invertible: several techniques may produce the same point.
    fn invert(&self, _x1: F::Vec3) -> Option<[F; 3]> {
        None
    }
}

/// One-sample MIS of OMNEE over the integrand's whole range θ < θmax and a
/// companion technique (equiangular, say) in the backward cone θ ≥ θmin,
/// the companion chosen with probability `c`. The weights are the balance
/// heuristic behind the cone and all OMNEE in front of it,
///
/// `w_OMNEE = 1` for θ(x1) < θmin, else `w_i = c_i p_i / ((1 − c) p_OMNEE + c p_companion)`,
///
/// a partition of unity, so the estimate stays unbiased. In front of the
/// cone OMNEE's weight θ/(s sin θ) is small (below 3.4/s for θmin = 3π/4) and
/// no second density is evaluated: the common sample costs OMNEE alone.
/// Behind it, where OMNEE's weight grows like 1/(π − θ), the companion takes
/// over. Companion samples in front of the cone are discarded.
///
/// As a [`Technique`]: `pdf = (1 − c) p_OMNEE + c p_companion` behind the cone
/// and `(1 − c) p_OMNEE` in front of it (the density of the returned points),
/// and every returned weight is `k/pdf`. Not invertible.
#[derive(Clone, Copy)]
pub struct OmneeMis<'a, F: Real, P> {
    omnee: Omnee<F, P>,
    companion: &'a dyn Technique<F>,
    share: F,
    /// `1 − cos θmin`.
    one_minus_cos_min: F,
}

impl<'a, F: Real, P: PhaseFunction<F>> OmneeMis<'a, F, P> {
    /// The companion's share used by [`Self::recommended`]: small, since it
    /// only insures the cone (on the slab scene of `omnee-cli` at g = 0 and
    /// 0.5, 0.05 was more efficient than 0.1 and 0.2).
    pub const SHARE: f64 = 0.05;

    /// The cone's edge used by [`Self::recommended`], θmin = 3π/4: in front
    /// of it OMNEE's weight θ/(s sin θ) is at most 3π/(4 sin(3π/4)) / s ≈ 3.3/s.
    pub const THETA_MIN: f64 = 0.75 * core::f64::consts::PI;

    /// [`Self::new`] with [`Self::SHARE`] and [`Self::THETA_MIN`], whose
    /// `1 − cos θmin = 1 + 1/√2` needs no trigonometry per connection.
    pub fn recommended(omnee: Omnee<F, P>, companion: &'a dyn Technique<F>) -> Self {
        let one_minus_cos_min = F::ONE + F::from_f64(core::f64::consts::FRAC_1_SQRT_2);
        Self {
            omnee,
            companion,
            share: F::from_f64(Self::SHARE),
            one_minus_cos_min,
        }
    }

    /// OMNEE with `companion` behind the cone θ ≥ `theta_min`, chosen with
    /// probability `share` ∈ [0, 1) (0: OMNEE alone).
    pub fn new(
        omnee: Omnee<F, P>,
        companion: &'a dyn Technique<F>,
        share: F,
        theta_min: Deflection<F>,
    ) -> Result<Self, crate::Error> {
        crate::error::check_closed("share", share.to_f64(), 0.0, 1.0, "[0, 1)")?;
        if share == F::ONE {
            return Err(crate::Error::OutOfRange {
                field: "share",
                value: 1.0,
                allowed: "[0, 1)",
            });
        }
        Ok(Self {
            omnee,
            companion,
            share,
            one_minus_cos_min: theta_min.one_minus_cos,
        })
    }

    /// Whether `x1` lies in the backward cone θ ≥ θmin.
    #[inline]
    fn behind(&self, x1: F::Vec3) -> bool {
        self.omnee
            .connection
            .deflection(x1)
            .is_some_and(|(d, _, _)| d.one_minus_cos >= self.one_minus_cos_min)
    }
}

impl<F: Real, P: PhaseFunction<F>> Technique<F> for OmneeMis<'_, F, P> {
    /// OMNEE for `u0 < 1 − c` (`u0` rescaled), else the companion.
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        let c_omnee = F::ONE - self.share;
        if u[0] < c_omnee {
            let u0 = (u[0] / c_omnee).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON);
            let (s, d) = self.omnee.sample_deflection([u0, u[1], u[2]])?;
            let own = c_omnee * s.pdf;
            let other = if d.one_minus_cos >= self.one_minus_cos_min && self.share > F::ZERO {
                self.share * self.companion.pdf(s.x1)
            } else {
                F::ZERO
            };
            Some(Sample {
                x1: s.x1,
                pdf: saturate(own + other),
                weight: saturate(Heuristic::Balance.weight(own, [other]) * s.weight / c_omnee),
            })
        } else {
            let u0 = ((u[0] - c_omnee) / self.share).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON);
            let s = self.companion.sample([u0, u[1], u[2]])?;
            if !self.behind(s.x1) {
                return None;
            }
            let own = self.share * s.pdf;
            let other = c_omnee * self.omnee.pdf(s.x1);
            Some(Sample {
                x1: s.x1,
                pdf: saturate(own + other),
                weight: saturate(Heuristic::Balance.weight(own, [other]) * s.weight / self.share),
            })
        }
    }

    /// `(1 − c) p_OMNEE(x1) + c p_companion(x1)` behind the cone, the first
    /// term alone in front of it.
    fn pdf(&self, x1: F::Vec3) -> F {
        let omnee = (F::ONE - self.share) * self.omnee.pdf(x1);
        if self.share > F::ZERO && self.behind(x1) {
            saturate(omnee + self.share * self.companion.pdf(x1))
        } else {
            omnee
        }
    }

    /// Not invertible: both techniques reach the points behind the cone.
    fn invert(&self, _x1: F::Vec3) -> Option<[F; 3]> {
        None
    }
}
