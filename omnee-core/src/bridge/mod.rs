//! Bridges: `k` scattering vertices `x_1 … x_k` between the end points `x0`
//! and `x_{k+1} = x2` (docs/math.md §14).
//!
//! The target is the k-times scattered point-to-point transfer
//!
//! `I_k = ∫…∫ Π_i σs p(θ_i) · e^{−σt D} / (d_1² ⋯ d_{k+1}²) dx_1 ⋯ dx_k`,
//!
//! with `d_j = |x_j − x_{j−1}|`, `D = d_1 + … + d_{k+1}` and θ_i the
//! deflection at `x_i` between the propagation directions (docs/math.md §1).
//! [`Bridge`] places the vertices as Schüßler, Hanika and Dachsbacher do
//! ("Bridge sampling for connections via multiple scattering events",
//! EGSR 2024): a chain of `k + 1` edges with deflections drawn from the phase
//! function and edge lengths in proportions uniform on the simplex, then
//! turned and scaled about `x0` until it ends at `x2`. With the scale
//! marginalised, its density in the product of volume measures is
//!
//! `pdf = s³ k! Π_i p(θ_i) / (Π_j d_j² · D^{k+1})`,
//!
//! so the estimator's weight (the kernel `Π p / Π d²` over the density) is
//! `D^{k+1} / (s³ k!)`, a function of the total length alone
//! ([`BridgeSample::weight`]); [`Bridge::estimate`] multiplies in
//! `σs^k e^{−σt D}` without forming either huge factor.
//!
//! - [`Bridge`]: the sampler, its density and its inverse (the trio);
//! - [`VertexCount`]: the number of vertices `k` drawn from `s`, σs, σt and
//!   the phase function's mean cosine, with its probability, for an unbiased
//!   estimate of `Σ_{k=1}^{K} I_k`;
//! - [`isotropic_transfer`]: `I_k` for an isotropic phase function as a 1-D
//!   integral (docs/math.md §14.6), the exact reference.

mod count;
mod isotropic;
mod product;
#[cfg(test)]
mod tests;

pub use count::VertexCount;
pub use isotropic::{MAX_CANCELLATION, REFERENCE_BUDGET, isotropic_transfer};

use crate::circumcircle::Axis;
use crate::error::Error;
use crate::medium::Homogeneous;
use crate::phase::{Deflection, PhaseFunction};
use crate::real::{Real, Vector};
use crate::sampling::saturate;
use product::Product;

/// The largest number of inner vertices a bridge takes. Each vertex takes
/// three uniform numbers.
pub const MAX_VERTICES: usize = 32;

/// `ln k!` for `k = 0 …` [`MAX_VERTICES`] (f64 `lgamma(k + 1)`).
const LN_FACTORIAL: [f64; MAX_VERTICES + 1] = [
    0.0,
    0.0,
    core::f64::consts::LN_2,
    1.7917594692280554,
    3.178053830347945,
    4.787491742782047,
    6.579251212010102,
    8.525161361065415,
    10.604602902745249,
    12.801827480081467,
    15.104412573075514,
    17.502307845873887,
    19.987214495661885,
    22.55216385312342,
    25.191221182738683,
    27.89927138384089,
    30.671860106080672,
    33.50507345013689,
    36.39544520803305,
    39.339884187199495,
    42.335616460753485,
    45.38013889847691,
    48.47118135183522,
    51.60667556776438,
    54.78472939811232,
    58.00360522298052,
    61.26170176100201,
    64.55753862700634,
    67.88974313718153,
    71.257038967168,
    74.65823634883017,
    78.0922235533153,
    81.55795945611503,
];

/// `ln k!` in the precision `F`, for `k ≤` [`MAX_VERTICES`].
#[inline]
fn ln_factorial<F: Real>(k: usize) -> F {
    F::from_f64(LN_FACTORIAL[k])
}

/// One sampled bridge: the number of vertices, the path's total length and
/// the density and weight of the draw. The vertices themselves are in the
/// caller's slice ([`Bridge::sample`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BridgeSample<F> {
    /// The number of inner vertices `k`.
    pub k: usize,
    /// `D = d_1 + … + d_{k+1}` as sampled: the scale `s/|y_{k+1}|` of the
    /// chain (docs/math.md §14.2).
    pub length: F,
    /// The density in the product of volume measures (m⁻³ᵏ),
    /// `s³ k! Π_i q(θ_i) / (Π_j d_j² D^{k+1})` with `q` the phase function's
    /// sampling density (its `pdf`); finite (saturates at `F::MAX`).
    pub pdf: F,
    /// `Π_i p(θ_i)/q(θ_i)`: 1 for phase functions that sample exactly, the
    /// table's ratio for [`TableSampled`](crate::phase::TableSampled).
    pub phase_ratio: F,
    /// The kernel `Π_i p(θ_i) / Π_j d_j²` over `pdf`:
    /// `(p/q) · D^{k+1}/(s³ k!)` (m^{k−2}), finite and ≥ 0 (saturating).
    pub weight: F,
}

/// The bridge sampler between `x0` and `x2` with the phase function `P` at
/// every inner vertex (docs/math.md §14).
///
/// Vertex `i` (1-based) takes three uniform numbers `[u_θ, u_φ, u_t]`:
/// `u_θ` draws the deflection θ_i from the phase function; `u_φ` is the
/// azimuth of the deflection about the incoming direction (for `i ≥ 2`), and
/// for `i = 1` the azimuth of the finished bridge about the axis `x0 → x2`;
/// `u_t` breaks the stick of the edge proportions: `d_i/D` takes the share
/// `1 − (1 − u_t)^{1/(k+1−i)}` of what edges `i … k+1` have left, so that the
/// proportions are uniform on the simplex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bridge<F: Real, P> {
    /// The end points and the frame `(b1, b2, e)` about their axis.
    pub axis: Axis<F>,
    /// The phase function at every inner vertex.
    pub phase: P,
}

/// The unscaled chain of step 1 (docs/math.md §14.2): its end point
/// `y_{k+1}`, `Σ ln q(θ_i)`, `Σ ln t_j` and `Π p/q`.
struct Chain<F: Real> {
    end: F::Vec3,
    ln_q: F,
    ln_t: F,
    ratio: F,
}

impl<F: Real, P: PhaseFunction<F>> Bridge<F, P> {
    /// The bridge sampler from `x0` (light side) to `x2` (receiver side).
    /// Fails on non-finite or coincident end points.
    pub fn new(x0: F::Vec3, x2: F::Vec3, phase: P) -> Result<Self, Error> {
        Ok(Self {
            axis: Axis::new(x0, x2)?,
            phase,
        })
    }

    /// A bridge of `k = u.len()` vertices (1 ≤ k ≤ [`MAX_VERTICES`]) from
    /// three uniform numbers per vertex in `[0, 1)`, written to
    /// `vertices[..k]`; `None` if `k` is out of range, `vertices` is shorter
    /// than `u`, or the numbers map to no contributing path (an edge of
    /// length 0, a chain that closes on itself, a non-finite vertex).
    ///
    /// 1. The chain: `y_0 = 0`, `ω_1 = z`, `y_j = y_{j−1} + t_j ω_j` with
    ///    `ω_{i+1}` deflected from `ω_i` by θ_i (docs/math.md §14.2);
    /// 2. the scale `D = s/|y_{k+1}|` and the rotation `R` taking
    ///    `y_{k+1}/|y_{k+1}|` to `e`, turned by the azimuth `2π u_φ` of
    ///    vertex 1: `x_i = x0 + D R y_i`, so that `x0 + D R y_{k+1} = x2`;
    /// 3. `pdf = k! |y_{k+1}|^{3(k+1)} Π q(θ_i) / (s^{3k} Π t_j²)` (§14.4),
    ///    `weight = (p/q) D^{k+1}/(s³ k!)`, both in closed form.
    pub fn sample(&self, u: &[[F; 3]], vertices: &mut [F::Vec3]) -> Option<BridgeSample<F>> {
        let k = u.len();
        if k == 0 || k > MAX_VERTICES || vertices.len() < k {
            return None;
        }
        let chain = self.chain(u, &mut vertices[..k])?;
        let axis = &self.axis;
        let l = chain.end.length();
        let length = axis.s / l;
        if !(l > F::ZERO && length.is_finite()) {
            return None;
        }
        let rotation = Rotation::<F>::new(self.turned(u[0][1]), chain.end * (F::ONE / l), axis.e);
        for v in vertices[..k].iter_mut() {
            let x = axis.x0 + rotation.apply(*v) * length;
            if !x.is_finite() {
                return None;
            }
            *v = x;
        }
        // In the connection's unit L (s = s_u L): pdf = pdf_u · L^{−3k}.
        let ln_pdf = ln_factorial::<F>(k) + F::from_f64(3.0 * (k + 1) as f64) * l.ln()
            - F::from_f64(3.0 * k as f64) * axis.s_unit.ln()
            + chain.ln_q
            - F::TWO * chain.ln_t;
        Some(BridgeSample {
            k,
            length,
            pdf: self.in_metres(ln_pdf, 3 * k),
            phase_ratio: chain.ratio,
            weight: saturate(chain.ratio * length_weight(k, axis.s, length)),
        })
    }

    /// Step 1 of [`sample`](Self::sample): the chain `y_1 … y_k` in `y`
    /// and what the density needs of it; `None` for an edge of length 0.
    #[inline]
    fn chain(&self, u: &[[F; 3]], y: &mut [F::Vec3]) -> Option<Chain<F>> {
        let k = u.len();
        let mut omega = F::Vec3::new(F::ZERO, F::ZERO, F::ONE);
        let mut point = F::Vec3::new(F::ZERO, F::ZERO, F::ZERO);
        let mut left = F::ONE;
        let (mut ln_q, mut ln_t, mut ratio) = (F::ZERO, F::ZERO, F::ONE);
        for (i, &[u_theta, u_phi, u_t]) in u.iter().enumerate() {
            let (t, rest) = stick_sample(left, u_t, k - i);
            if !(t > F::ZERO) {
                return None;
            }
            left = rest;
            ln_t += t.ln();
            point = point + omega * t;
            y[i] = point;
            let (d, q, r) = self.phase.sample_ratio(u_theta);
            if !(q > F::ZERO) {
                return None;
            }
            ln_q += q.ln();
            ratio *= r;
            // Vertex 1's azimuth turns the whole bridge instead (§14.3).
            omega = deflect(omega, d, if i == 0 { F::ZERO } else { u_phi });
        }
        if !(left > F::ZERO) {
            return None;
        }
        Some(Chain {
            end: point + omega * left,
            ln_q,
            ln_t: ln_t + left.ln(),
            ratio,
        })
    }

    /// `(p1, p2)`: the axis frame's `b1`, `b2` turned by `2π turn` about `e`.
    #[inline]
    fn turned(&self, turn: F) -> (F::Vec3, F::Vec3) {
        let (sin_phi, cos_phi) = turn.sin_cos_turn();
        let (b1, b2) = (self.axis.b1, self.axis.b2);
        (b1 * cos_phi + b2 * sin_phi, b2 * cos_phi - b1 * sin_phi)
    }

    /// The deflections `θ_i` and edge lengths `d_j` of the path
    /// `x0, x_1 … x_k, x2`, in the connection's unit `L` (`d_j/L`: the points
    /// taken relative to `x0` and scaled by `1/L` first, so that neither an
    /// edge nor the deflection's products of lengths leave the range at any
    /// scale), passed to `visit(i, θ_i, d_i/L)` for `i = 1 … k` and
    /// `visit(k + 1, −, d_{k+1}/L)` last; `None` for a zero-length or
    /// non-finite edge.
    #[inline]
    fn walk(
        &self,
        vertices: &[F::Vec3],
        mut visit: impl FnMut(usize, Option<Deflection<F>>, F),
    ) -> Option<()> {
        let axis = &self.axis;
        let mut from = F::Vec3::new(F::ZERO, F::ZERO, F::ZERO);
        let mut edge_in: Option<(F::Vec3, F)> = None;
        for (j, &to) in vertices
            .iter()
            .chain(core::iter::once(&axis.x2))
            .enumerate()
        {
            let to = axis.from_x0_unit(to);
            let edge = to - from;
            let d = edge.length();
            if !(d > F::ZERO && d.is_finite()) {
                return None;
            }
            if let Some((a, la)) = edge_in {
                visit(
                    j,
                    Some(Deflection::between_segments(a, la, edge, d)),
                    F::ZERO,
                );
            }
            edge_in = Some((edge, d));
            visit(j + 1, None, d);
            from = to;
        }
        Some(())
    }

    /// `e^{ln_u} · L^{−n}`: a quantity of dimension `m^{−n}` from the log of
    /// its value in the connection's unit, saturating (0 below the range,
    /// `F::MAX` above it).
    #[inline]
    fn in_metres(&self, ln_u: F, n: usize) -> F {
        Product::exp(ln_u)
            .times(Product::pow2(-(n as i32) * self.axis.unit.exponent))
            .value()
    }

    /// The density of [`sample`](Self::sample) at the path `x0, vertices, x2`:
    /// `s³ k! Π_i q(θ_i) / (Π_j d_j² D^{k+1})` (docs/math.md §14.4), with θ_i
    /// and `d_j` formed from the points; 0 for `k` out of range and at
    /// coincident points. Finite (saturating).
    pub fn pdf(&self, vertices: &[F::Vec3]) -> F {
        let k = vertices.len();
        if k == 0 || k > MAX_VERTICES {
            return F::ZERO;
        }
        let (mut ln_q, mut ln_d, mut length) = (F::ZERO, F::ZERO, F::ZERO);
        let found = self.walk(vertices, |_, theta, d| match theta {
            Some(theta) => ln_q += self.phase.pdf(theta).ln(),
            None => {
                ln_d += d.ln();
                length += d;
            }
        });
        if found.is_none() {
            return F::ZERO;
        }
        // Every length in the connection's unit: pdf = pdf_u · L^{−3k}.
        let ln_pdf = ln_factorial::<F>(k) + F::from_f64(3.0) * self.axis.s_unit.ln() + ln_q
            - F::TWO * ln_d
            - F::from_f64((k + 1) as f64) * length.ln();
        self.in_metres(ln_pdf, 3 * k)
    }

    /// The kernel `Π_i p(θ_i) / Π_j d_j²` at the path `x0, vertices, x2`
    /// (m^{−2(k+1)}), the part of the integrand every bridge samples; 0 at
    /// coincident points. Finite (saturating).
    pub fn kernel(&self, vertices: &[F::Vec3]) -> F {
        // In the connection's unit: kernel = kernel_u · L^{−2(k+1)}.
        let mut value = Product::ONE;
        let found = self.walk(vertices, |_, theta, d| match theta {
            Some(theta) => value = value.times_real(self.phase.eval(theta)),
            None => value = value.over_real(d).over_real(d),
        });
        match found {
            Some(()) if !vertices.is_empty() => {
                let n = 2 * (vertices.len() as i32 + 1);
                value
                    .times(Product::pow2(-n * self.axis.unit.exponent))
                    .value()
            }
            _ => F::ZERO,
        }
    }

    /// The estimate of `I_k` in the infinite homogeneous `medium` from one
    /// bridge: `σs^k e^{−σt D} · weight`, evaluated as
    /// `(p/q) · a · Π_{i=1}^k (σs s a / i) / s²` with
    /// `a = (D/s) e^{−σt D/(k+1)} ≤ (k+1)/(e σt s)`, so that neither
    /// `D^{k+1}` nor `e^{−σt D}` is formed alone (docs/math.md §14.5).
    /// Finite and ≥ 0.
    pub fn estimate(&self, sample: &BridgeSample<F>, medium: &Homogeneous<F>) -> F {
        self.estimate_at_depth(sample, medium.sigma_s(), self.depth(sample, medium))
    }

    /// The estimate from one bridge whose path has the optical depth
    /// `tau ≥ 0` (`σt D` in an infinite medium, less where edges leave a
    /// bounded one) and the scattering coefficient σs at every vertex:
    /// `σs^k e^{−τ} · weight`, evaluated as [`estimate`](Self::estimate)
    /// does with `a = (D/s) e^{−τ/(k+1)}` (docs/math.md §14.5, §14.9).
    /// Finite and ≥ 0 (saturating); 0 for σs ≤ 0.
    pub fn estimate_at_depth(&self, sample: &BridgeSample<F>, sigma_s: F, tau: F) -> F {
        self.estimate_product(sample, sigma_s, tau).value()
    }

    /// [`estimate`](Self::estimate) in f64 whatever `F`: the product formed
    /// in `F` with its power of two kept apart and applied in f64, so that
    /// an estimate beyond `F`'s range (f32 at s = 1e-30: `I_k ∝ 1/s²`,
    /// about 1e60 with σs ∝ 1/s) is still right. Finite and ≥ 0
    /// (saturating at `f64::MAX`).
    pub fn estimate_f64(&self, sample: &BridgeSample<F>, medium: &Homogeneous<F>) -> f64 {
        self.estimate_product(sample, medium.sigma_s(), self.depth(sample, medium))
            .to_f64()
    }

    /// The optical depth `σt D` of the sampled path in the infinite `medium`
    /// (+∞ where the product leaves `F`'s range, a path no light crosses).
    #[inline]
    fn depth(&self, sample: &BridgeSample<F>, medium: &Homogeneous<F>) -> F {
        if medium.sigma_t() > F::ZERO {
            medium.sigma_t() * sample.length
        } else {
            F::ZERO
        }
    }

    /// `σs^k e^{−τ} · weight` as `(p/q) · a · Π_{i=1}^k (σs s a / i) / s²`
    /// with `a = (D/s) e^{−τ/(k+1)}` (docs/math.md §14.5): factor by factor
    /// in `F`, and again as a [`Product`] where a partial product left the
    /// normal range (its last factor would not bring it back exactly).
    #[inline]
    fn estimate_product(&self, sample: &BridgeSample<F>, sigma_s: F, tau: F) -> Product<F> {
        let (k, s) = (sample.k, self.axis.s);
        if k == 0 || !(sigma_s > F::ZERO) {
            return Product::of(F::ZERO);
        }
        let n = F::from_f64((k + 1) as f64);
        let attenuation = if tau > F::ZERO {
            (-tau / n).exp()
        } else {
            F::ONE
        };
        let a = sample.length / s * attenuation;
        let mut value = sample.phase_ratio * a;
        let mut normal = normal_range(value);
        for i in 1..=k {
            value *= sigma_s * s * a / F::from_f64(i as f64);
            normal &= normal_range(value);
        }
        let value = value / s / s;
        if normal && normal_range(value) {
            return Product::of(value);
        }
        let a = Product::of(sample.length)
            .over_real(s)
            .times(Product::exp_neg(tau / n));
        let mut value = Product::of(sample.phase_ratio).times(a);
        for i in 1..=k {
            value = value
                .times_real(sigma_s)
                .times_real(s)
                .times(a)
                .over_real(F::from_f64(i as f64));
        }
        value.over_real(s).over_real(s)
    }

    /// The uniform numbers that [`sample`](Self::sample) maps to the path
    /// `x0, vertices, x2`, written to `u[..k]` (`k = vertices.len()`);
    /// `None` where the map has no inverse: `k` out of range or `u` too
    /// short, coincident points, a first deflection of 0 or π (where the
    /// chain's frame is undefined), or a phase function whose sampler is
    /// not invertible (mixtures).
    pub fn invert(&self, vertices: &[F::Vec3], u: &mut [[F; 3]]) -> Option<()> {
        let k = vertices.len();
        if k == 0 || k > MAX_VERTICES || u.len() < k {
            return None;
        }
        // Edge proportions t_j and the deflections' uniform numbers.
        let mut d = [F::ZERO; MAX_VERTICES + 1];
        let mut length = F::ZERO;
        let mut ok = true;
        self.walk(vertices, |j, theta, dj| match theta {
            Some(theta) => match self.phase.invert(theta) {
                Some(v) => u[j - 1][0] = v,
                None => ok = false,
            },
            None => {
                d[j - 1] = dj;
                length += dj;
            }
        })?;
        if !ok {
            return None;
        }
        let mut left = F::ZERO; // Σ_{l > j} d_l, summed from the far end
        let mut tail = [F::ZERO; MAX_VERTICES + 1];
        for j in (0..=k).rev() {
            tail[j] = left;
            left += d[j];
        }
        for j in 0..k {
            u[j][2] = stick_invert(d[j], tail[j], k - j);
        }
        // The rotation from the chain's frame to the world (§14.3), the
        // edges' directions formed in the connection's unit.
        let world = |j: usize| -> F::Vec3 {
            let unit = |x: F::Vec3| self.axis.from_x0_unit(x);
            let from = if j == 0 {
                F::Vec3::new(F::ZERO, F::ZERO, F::ZERO)
            } else {
                unit(vertices[j - 1])
            };
            let to = unit(if j == k { self.axis.x2 } else { vertices[j] });
            let e = to - from;
            e * (F::ONE / e.length())
        };
        let z = F::Vec3::new(F::ZERO, F::ZERO, F::ONE);
        let (a0, _) = z.orthonormal_pair();
        let m = Rotation::<F>::between((z, a0), (world(0), world(1)))?;
        // Local azimuths at vertices 2 … k.
        for (i, ui) in u[..k].iter_mut().enumerate().skip(1) {
            let (w_in, w_out) = (m.unapply(world(i)), m.unapply(world(i + 1)));
            let (a, b) = w_in.orthonormal_pair();
            ui[1] = turn_of(w_out.dot(b), w_out.dot(a));
        }
        // Vertex 1's: the bridge's turn about e (the chain's end is along e).
        let c = m.unapply(self.axis.e);
        let (a, _) = c.orthonormal_pair();
        let p1 = m.apply(a);
        u[0][1] = turn_of(p1.dot(self.axis.b2), p1.dot(self.axis.b1));
        Some(())
    }
}

/// `atan2(y, x)/2π` in `[0, 1)`.
#[inline]
fn turn_of<F: Real>(y: F, x: F) -> F {
    let t = y.atan2(x) / F::TAU;
    let t = if t < F::ZERO { t + F::ONE } else { t };
    if t >= F::ONE { F::ZERO } else { t }
}

/// `D^{k+1}/(s³ k!)` as `(1/s²) (D/s) Π_{i=1}^k (D/i)/s`, factor by factor
/// (saturating), the kernel over the density (docs/math.md §14.4); again as
/// a [`Product`] where a partial product left the normal range (f32 at
/// s = 1e-30: `1/s²` overflows, the weight `∝ s^{k−2}` need not).
#[inline]
fn length_weight<F: Real>(k: usize, s: F, length: F) -> F {
    let r = length / s;
    let mut value = r / s / s;
    let mut normal = normal_range(value);
    for i in 1..=k {
        value *= r * s / F::from_f64(i as f64);
        normal &= normal_range(value);
    }
    if normal {
        return value;
    }
    let r = Product::of(length).over_real(s);
    let mut value = r.over_real(s).over_real(s);
    for i in 1..=k {
        value = value
            .times(r)
            .times_real(s)
            .over_real(F::from_f64(i as f64));
    }
    value.value()
}

/// Whether `x` is a finite normal number, `F::MIN_POSITIVE ≤ x ≤ F::MAX`
/// (0, subnormals, ∞ and NaN are not): a partial product that stays there
/// lost no digits to the range.
#[inline]
fn normal_range<F: Real>(x: F) -> bool {
    x >= F::MIN_POSITIVE && x.is_finite()
}

/// One break of the stick: of the share `left` that `n + 1` edges still
/// have, the next edge takes `t = left (1 − (1 − u)^{1/n})` and `n` edges
/// keep `left (1 − u)^{1/n}`: the first part of a uniform split of `left`
/// into `n + 1` parts has the density `n (1 − t/left)^{n−1}/left`. Formed
/// with `ln(1 − u)` and `e^x − 1` so that a small share keeps its digits.
#[inline]
fn stick_sample<F: Real>(left: F, u: F, n: usize) -> (F, F) {
    let x = (-u).ln_1p() / F::from_f64(n as f64);
    let m1 = x.exp_m1(); // e^x − 1 ∈ (−1, 0]; e^x = 1 + m1 is exact enough
    (-left * m1, left * (F::ONE + m1))
}

/// The inverse of [`stick_sample`]: `u = 1 − (1 − t/(t + rest))^n` from the
/// edge's length `t` and the lengths `rest` of the edges after it,
/// `u = −(e^{n ln(rest/(t + rest))} − 1)`.
#[inline]
fn stick_invert<F: Real>(t: F, rest: F, n: usize) -> F {
    let x = F::from_f64(n as f64) * (-t / (t + rest)).ln_1p();
    (-x.exp_m1()).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON)
}

/// The direction `ω'` deflected from the unit `ω` by θ with the azimuth
/// `2π turn` in `ω`'s frame `(a, b)`:
/// `ω' = ω (1 − (1 − cos θ)) + (a cos ψ + b sin ψ) sin θ`, renormalised.
#[inline]
fn deflect<F: Real>(omega: F::Vec3, d: Deflection<F>, turn: F) -> F::Vec3 {
    let (a, b) = omega.orthonormal_pair();
    let (sin_psi, cos_psi) = turn.sin_cos_turn();
    let radial = a * cos_psi + b * sin_psi;
    let out = omega - omega * d.one_minus_cos + radial * d.sin();
    out * (F::ONE / out.length())
}

/// A rotation as the pair of orthonormal frames it maps onto each other:
/// `R v = Σ_m (v · from_m) to_m`.
#[derive(Clone, Copy)]
struct Rotation<F: Real> {
    from: [F::Vec3; 3],
    to: [F::Vec3; 3],
}

impl<F: Real> Rotation<F> {
    /// The rotation taking the unit `c` to `e` and `c`'s frame
    /// `orthonormal_pair(c)` to `(p1, p2)` (a right-handed frame with `e`).
    #[inline]
    fn new((p1, p2): (F::Vec3, F::Vec3), c: F::Vec3, e: F::Vec3) -> Self {
        let (a, b) = c.orthonormal_pair();
        Self {
            from: [a, b, c],
            to: [p1, p2, e],
        }
    }

    /// The rotation taking the unit `u0` to `v0` and the plane of
    /// `(u0, u1)` to that of `(v0, v1)` (the half-planes of `u1` and `v1`
    /// included); `None` if either pair is (anti)parallel.
    #[inline]
    fn between((u0, u1): (F::Vec3, F::Vec3), (v0, v1): (F::Vec3, F::Vec3)) -> Option<Self> {
        let frame = |w0: F::Vec3, w1: F::Vec3| -> Option<[F::Vec3; 3]> {
            let n = w1 - w0 * w0.dot(w1);
            let ln = n.length();
            if !(ln > F::ZERO && ln.is_finite()) {
                return None;
            }
            let n = n * (F::ONE / ln);
            Some([w0, n, w0.cross(n)])
        };
        Some(Self {
            from: frame(u0, u1)?,
            to: frame(v0, v1)?,
        })
    }

    /// `R v`.
    #[inline]
    fn apply(&self, v: F::Vec3) -> F::Vec3 {
        self.to[0] * v.dot(self.from[0])
            + self.to[1] * v.dot(self.from[1])
            + self.to[2] * v.dot(self.from[2])
    }

    /// `R⁻¹ v = Rᵀ v`.
    #[inline]
    fn unapply(&self, v: F::Vec3) -> F::Vec3 {
        self.from[0] * v.dot(self.to[0])
            + self.from[1] * v.dot(self.to[1])
            + self.from[2] * v.dot(self.to[2])
    }
}

/// The one-vertex bridge as a [`Technique`](crate::sampling::Technique)
/// for the connection `x0 → x2` with θmax = π, so that
/// [`crate::mis::OneSample`] combines it with OMNEE (docs/math.md §14.8):
/// `pdf = s³ q(θ)/(d1² d2² D²)`, `weight = (p/q) D²/s³`.
impl<F: Real, P: PhaseFunction<F>> crate::sampling::Technique<F> for Bridge<F, P> {
    /// [`Bridge::sample`] with `k = 1` and `u = [u_θ, u_φ, u_t]`.
    #[inline]
    fn sample(&self, u: [F; 3]) -> Option<crate::sampling::Sample<F>> {
        let mut x1 = [self.axis.x0];
        let b = Bridge::sample(self, &[u], &mut x1)?;
        Some(crate::sampling::Sample {
            x1: x1[0],
            pdf: b.pdf,
            weight: b.weight,
        })
    }

    /// [`Bridge::pdf`] of the one-vertex path `x0, x1, x2`.
    #[inline]
    fn pdf(&self, x1: F::Vec3) -> F {
        Bridge::pdf(self, &[x1])
    }

    /// [`Bridge::invert`] of the one-vertex path.
    #[inline]
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        let mut u = [[F::ZERO; 3]];
        Bridge::invert(self, &[x1], &mut u)?;
        Some(u[0])
    }
}
