//! Multiple importance sampling (Veach 1997) over any set of [`Technique`]s.
//!
//! Every technique's density is in the volume measure, so weights combine
//! them directly. Weights are computed as
//! `w_i = 1 / (1 + Σ_{j≠i} (n_j p_j / n_i p_i)^β)`, which stays finite when a
//! density saturates near an end point.

use crate::phase::{Deflection, PhaseFunction};
use crate::real::Real;
use crate::sampling::{Draw, Omnee, Sample, Technique, Vertex, density_of, saturate};

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

/// OMNEE over the integrand's whole range θ < θmax, always, and with
/// probability `c` (the companion's rate) one more vertex from a companion
/// technique (equiangular, say) restricted to the backward cone θ ≥ θmin:
/// multi-sample MIS with the expected counts 1 and `c` (Veach 1997, §9.2),
/// balance heuristic behind the cone and OMNEE alone in front of it,
///
/// `w_OMNEE = 1`, `w_companion = 0` for θ(x1) < θmin, else
/// `w_OMNEE = p_O / (p_O + c p_C)`, `w_companion = c p_C / (p_O + c p_C)`,
///
/// a partition of unity, so the sum over the returned vertices of
/// `f_c · weight` is unbiased; every weight is `k / pdf` with
/// `pdf = p_O + c p_C` behind the cone and `p_O` in front of it.
///
/// In front of the cone OMNEE's weight θ/(s sin θ) stays small (below 3.3/s
/// for θmin = 3π/4) and no second density is evaluated: the common draw
/// costs OMNEE alone. Behind it, where OMNEE's weight grows like 1/(π − θ),
/// the companion takes over. OMNEE's vertex is never dropped in favour of
/// the companion's: a one-sample mixture that draws the companion instead
/// with probability `c` adds a relative variance of about `c/(1 − c)` to
/// every estimate, which for a forward peak (where OMNEE's own relative
/// variance is 10⁻³) costs more than the companion can win.
#[derive(Clone, Copy)]
pub struct OmneeMis<'a, F: Real, P> {
    omnee: Omnee<F, P>,
    companion: &'a dyn Technique<F>,
    rate: F,
    /// `1 − cos θmin`.
    one_minus_cos_min: F,
}

impl<'a, F: Real, P: PhaseFunction<F>> OmneeMis<'a, F, P> {
    /// The companion's rate used by [`Self::recommended`].
    pub const RATE: f64 = 0.05;

    /// The cone's edge used by [`Self::recommended`], θmin = 3π/4: in front
    /// of it OMNEE's weight θ/(s sin θ) is at most 3π/(4 sin(3π/4)) / s ≈ 3.3/s.
    pub const THETA_MIN: f64 = 0.75 * core::f64::consts::PI;

    /// [`Self::new`] with [`Self::RATE`] and [`Self::THETA_MIN`], whose
    /// `1 − cos θmin = 1 + 1/√2` needs no trigonometry per connection.
    pub fn recommended(omnee: Omnee<F, P>, companion: &'a dyn Technique<F>) -> Self {
        let one_minus_cos_min = F::ONE + F::from_f64(core::f64::consts::FRAC_1_SQRT_2);
        Self {
            omnee,
            companion,
            rate: F::from_f64(Self::RATE),
            one_minus_cos_min,
        }
    }

    /// OMNEE with `companion` behind the cone θ ≥ `theta_min`, drawn with
    /// probability `rate` ∈ [0, 1] (0: OMNEE alone).
    pub fn new(
        omnee: Omnee<F, P>,
        companion: &'a dyn Technique<F>,
        rate: F,
        theta_min: Deflection<F>,
    ) -> Result<Self, crate::Error> {
        crate::error::check_closed("rate", rate.to_f64(), 0.0, 1.0, "[0, 1]")?;
        Ok(Self {
            omnee,
            companion,
            rate,
            one_minus_cos_min: theta_min.one_minus_cos,
        })
    }

    /// The companion's rate `c`.
    pub fn rate(&self) -> F {
        self.rate
    }

    /// Whether the vertex lies in the backward cone θ ≥ θmin (θ from its
    /// offsets, [`Connection::deflection_at`](crate::sampling::Connection::deflection_at)).
    #[inline]
    fn behind(&self, v: &Vertex<F>) -> bool {
        self.omnee
            .connection
            .deflection_at(v)
            .is_some_and(|(d, _, _)| d.one_minus_cos >= self.one_minus_cos_min)
    }

    /// The vertices of one estimate from six uniform numbers: OMNEE's from
    /// `u[0..3]`, and the companion's from `u[3..6]` when `u[3] < c`
    /// (`u[3]/c` then its first number). A companion vertex in front of the
    /// cone is dropped (its weight there is 0).
    ///
    /// Each technique's density at the other's vertex is evaluated at the
    /// vertex as sampled, with its offsets `x1 − x0`, `x1 − x2`
    /// ([`Technique::pdf_vertex`]), not at the rounded point: next to an end
    /// point the point alone has lost the digits of its distance to it.
    pub fn sample(&self, u: [F; 6]) -> [Option<Sample<F>>; 2] {
        let unit = &self.omnee.connection.axis.unit;
        let omnee = self
            .omnee
            .sample_unit([u[0], u[1], u[2]])
            .map(|(s, v, d, own)| {
                if d.one_minus_cos >= self.one_minus_cos_min && self.rate > F::ZERO {
                    let other = self.rate * self.companion.pdf_vertex_unit(&v, unit);
                    self.combine(s, own, other, F::ONE)
                } else {
                    s
                }
            });
        let companion = if u[3] < self.rate {
            let u3 = (u[3] / self.rate).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON);
            self.companion
                .sample_vertex([u3, u[4], u[5]], &self.omnee.connection)
                .filter(|(_, v)| self.behind(v))
                .map(|(s, v)| {
                    let companion = |v: &Vertex<F>| self.companion.pdf_vertex_unit(v, unit);
                    let own = density_of(&s, &v, unit, &companion);
                    self.combine(s, own, self.omnee.pdf_vertex_unit(&v, unit), self.rate)
                })
        } else {
            None
        };
        [omnee, companion]
    }

    /// One estimate's vertices as a [`Draw`], the numbers pulled from `next`:
    /// [`Self::sample`] of OMNEE's three, the one that decides on the
    /// companion (`u[3] < c`, then `u[3]/c` is the companion's first), and
    /// the companion's other two only when it is drawn: `4 + 2c` numbers on
    /// average (4.1 for [`Self::RATE`]) instead of six. The vertices are
    /// those of [`Self::sample`] with the same numbers (the two not taken
    /// are not read there).
    pub fn draw(&self, mut next: impl FnMut() -> F) -> Draw<F> {
        let mut u = [next(), next(), next(), next(), F::ZERO, F::ZERO];
        let taken = if u[3] < self.rate {
            u[4] = next();
            u[5] = next();
            6
        } else {
            4
        };
        Draw {
            u,
            taken,
            vertices: self.sample(u),
        }
    }

    /// A vertex of the technique drawn `count` times on average with its
    /// own density `own` and the other's `count · pdf` at its point, both
    /// per `L³` of the connection's unit (docs/math.md §15): weight
    /// `k/(p_O + c p_C)`, the balance heuristic over the expected counts,
    /// and that sum as its pdf (in m⁻³).
    #[inline]
    fn combine(&self, s: Sample<F>, own: F, other: F, count: F) -> Sample<F> {
        let own = count * own;
        let unit = &self.omnee.connection.axis.unit;
        Sample {
            x1: s.x1,
            pdf: saturate(unit.density_from_unit(own + other)),
            weight: saturate(Heuristic::Balance.weight(own, [other]) * s.weight / count),
        }
    }

    /// The combined density `p_O(x1) + c p_C(x1)` behind the cone, `p_O(x1)`
    /// in front of it: the `pdf` the vertices come with.
    pub fn pdf(&self, x1: F::Vec3) -> F {
        self.pdf_vertex(&Vertex::at(&self.omnee.connection, x1))
    }

    /// [`pdf`](Self::pdf) at a vertex given with its offsets from the end
    /// points ([`Vertex`]), both densities per `L³` and the sum scaled once.
    pub fn pdf_vertex(&self, v: &Vertex<F>) -> F {
        if self.rate > F::ZERO && self.behind(v) {
            let unit = &self.omnee.connection.axis.unit;
            let sum = self.omnee.pdf_vertex_unit(v, unit)
                + self.rate * self.companion.pdf_vertex_unit(v, unit);
            saturate(unit.density_from_unit(sum))
        } else {
            self.omnee.pdf_vertex(v)
        }
    }
}
