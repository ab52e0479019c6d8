//! Many connections in one call: OMNEE, and its MIS with the equiangular
//! companion, for a batch of connections in structure-of-arrays form, one
//! connection `x0_i → x2_i` per lane, in f32 or f64, without allocation.
//!
//! The shape is pbrt-v4's wavefront SOA and Mitsuba 3's vectorised
//! variants: every point is three slices (`x`, `y`, `z`), every per-lane
//! scalar one slice, and the result of lane `i` sits at index `i` of each
//! output slice, with a `valid` mask where the scalar call returns `None`.
//! A renderer gathers a tile's connections (each shading point with its
//! light point), samples them in one call, then evaluates.
//!
//! The type's documentation ([`Connections`]) says what each lane is and
//! how the f32 lanes are computed.

use super::batch::clamp_unit;
use super::{Connection, Equiangular, Omnee, Sample, Technique, Uniforms, Unit, saturate};
use crate::error::Error;
use crate::lobe::{LobeMis, PhaseLobe, Restricted};
use crate::method::Setup;
use crate::mis::OmneeMis;
use crate::phase::{
    AnyPhase, Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, NoTable,
    PhaseFunction, Rayleigh, TableSampled, Tabulated, dispatch,
};
use crate::real::{ATAN_SQRT, Real, Vector, sin_cos_acute_f64, sinc_is_series, sinc_series};

/// Lanes per chunk: the stages of one chunk keep their values (eleven
/// numbers a lane) in arrays on the stack, 2.9 KiB in f32.
pub const CHUNK: usize = 64;

/// Points, one slice per coordinate: point `i` is `(x[i], y[i], z[i])`.
#[derive(Clone, Copy, Debug)]
pub struct Points<'a, F> {
    /// x coordinates.
    pub x: &'a [F],
    /// y coordinates.
    pub y: &'a [F],
    /// z coordinates.
    pub z: &'a [F],
}

impl<F: Real> Points<'_, F> {
    /// The number of points, if the three slices agree.
    #[inline]
    fn len(&self) -> Option<usize> {
        let n = self.x.len();
        (self.y.len() == n && self.z.len() == n).then_some(n)
    }

    /// Point `i`.
    #[inline]
    fn at(&self, i: usize) -> F::Vec3 {
        F::Vec3::new(self.x[i], self.y[i], self.z[i])
    }
}

/// Writable points, one slice per coordinate.
#[derive(Debug)]
pub struct PointsMut<'a, F> {
    /// x coordinates.
    pub x: &'a mut [F],
    /// y coordinates.
    pub y: &'a mut [F],
    /// z coordinates.
    pub z: &'a mut [F],
}

/// The samples of a batch, [`Sample`] by lane: `x1`, its density and
/// weight, and `valid[i]`, whether lane `i` has a vertex (the scalar call's
/// `Some`). A lane without one is all zero.
#[derive(Debug)]
pub struct SampleArrays<'a, F> {
    /// The vertices `x1`.
    pub x1: PointsMut<'a, F>,
    /// Their volume densities (m⁻³), finite.
    pub pdf: &'a mut [F],
    /// Their weights `k/pdf` without `f_c` (m⁻¹), finite and ≥ 0.
    pub weight: &'a mut [F],
    /// Whether the lane has a vertex.
    pub valid: &'a mut [bool],
}

impl<F: Real> SampleArrays<'_, F> {
    /// Whether every slice has `n` entries.
    fn has_len(&self, n: usize) -> bool {
        [
            self.x1.x.len(),
            self.x1.y.len(),
            self.x1.z.len(),
            self.pdf.len(),
            self.weight.len(),
            self.valid.len(),
        ]
        .iter()
        .all(|&len| len == n)
    }

    /// Lane `i` from a scalar sample (zeros and `valid = false` for `None`).
    #[inline]
    fn set(&mut self, i: usize, sample: Option<Sample<F>>) {
        let s = sample.unwrap_or(Sample {
            x1: F::Vec3::new(F::ZERO, F::ZERO, F::ZERO),
            pdf: F::ZERO,
            weight: F::ZERO,
        });
        let [x, y, z] = s.x1.to_array();
        (self.x1.x[i], self.x1.y[i], self.x1.z[i]) = (x, y, z);
        (self.pdf[i], self.weight[i], self.valid[i]) = (s.pdf, s.weight, sample.is_some());
    }
}

/// The deflections a phase function draws for a batch, by lane: what
/// [`PhaseFunction::sample_ratio`] returns, `(Deflection, pdf, ratio)`.
#[derive(Debug)]
pub struct Deflections<'a, F> {
    /// θ.
    pub theta: &'a mut [F],
    /// `1 − cos θ`.
    pub one_minus_cos: &'a mut [F],
    /// `1 + cos θ`.
    pub one_plus_cos: &'a mut [F],
    /// The solid-angle density of the draw.
    pub pdf: &'a mut [F],
    /// The ratio `p/q` of the phase function to that density (1 for exact
    /// samplers).
    pub ratio: &'a mut [F],
}

/// A phase function that draws the deflections of a whole batch:
/// [`PhaseFunction::sample_ratio`] lane by lane, bit for bit. The default
/// calls it once per lane; Henyey–Greenstein in f32 (alone or in a
/// [`Phase`](crate::phase::Phase)) overrides it with its inverse CDF vectorised.
///
/// Every phase function of the core implements it; a phase function of
/// your own needs only `impl PhaseBatch<F> for Mine {}`.
pub trait PhaseBatch<F: Real>: PhaseFunction<F> {
    /// `sample_ratio(u0[i])` into lane `i` of `out`, for every `i` below
    /// the shortest of the slices.
    #[inline]
    fn sample_ratio_batch(&self, u0: &[F], out: Deflections<'_, F>) {
        sample_ratio_each(self, u0, out)
    }
}

impl<F: Real> PhaseBatch<F> for Isotropic {}
impl<F: Real> PhaseBatch<F> for Rayleigh {}
impl<F: Real> PhaseBatch<F> for FournierForand<F> {}
impl<F: Real> PhaseBatch<F> for Draine<F> {}
impl<F: Real> PhaseBatch<F> for Mie<F> {}
impl<F: Real> PhaseBatch<F> for Tabulated<'_, F> {}
impl<F: Real, A: PhaseFunction<F>, B: PhaseFunction<F>> PhaseBatch<F> for Mixture<A, B> {}
impl<F: Real, P: PhaseFunction<F>> PhaseBatch<F> for TableSampled<'_, F, P> {}

impl<F: Real, P: PhaseBatch<F> + ?Sized> PhaseBatch<F> for &P {
    #[inline]
    fn sample_ratio_batch(&self, u0: &[F], out: Deflections<'_, F>) {
        (**self).sample_ratio_batch(u0, out)
    }
}

impl<F: Real> PhaseBatch<F> for NoTable {}

impl<F: Real, T: PhaseBatch<F>> PhaseBatch<F> for AnyPhase<F, T> {
    /// The variant's own: Henyey–Greenstein's vectorised draw for that
    /// variant, one call per lane for the others.
    #[inline]
    fn sample_ratio_batch(&self, u0: &[F], out: Deflections<'_, F>) {
        dispatch!(self, p => p.sample_ratio_batch(u0, out))
    }
}

impl<F: Real> PhaseBatch<F> for HenyeyGreenstein<F> {
    /// In f32 the scalar inverse CDF (`HenyeyGreenstein::sample_pdf`) bit
    /// for bit, per [`CHUNK`] lanes: the versine numerators `a`, `b`, the
    /// versines and the density four f32 lanes to a register; then
    /// `θ = 2 atan2(√a, √b)` (`w = min/max(a, b)`, `√w`, the polynomial
    /// `Q(w)`, the octant) two f64 lanes to one (`libm`'s f64 square root
    /// is LLVM's intrinsic, `sqrtpd`). In f64 the default, one call per
    /// lane (its `atan2` is `libm`'s).
    fn sample_ratio_batch(&self, u0: &[F], out: Deflections<'_, F>) {
        if !is_f32::<F>() {
            return sample_ratio_each(self, u0, out);
        }
        let n = u0
            .len()
            .min(out.theta.len())
            .min(out.one_minus_cos.len())
            .min(out.one_plus_cos.len())
            .min(out.pdf.len())
            .min(out.ratio.len());
        let mut start = 0;
        while start < n {
            let end = n.min(start + CHUNK);
            self.sample_chunk_f32(
                &u0[start..end],
                Deflections {
                    theta: &mut out.theta[start..end],
                    one_minus_cos: &mut out.one_minus_cos[start..end],
                    one_plus_cos: &mut out.one_plus_cos[start..end],
                    pdf: &mut out.pdf[start..end],
                    ratio: &mut out.ratio[start..end],
                },
            );
            start = end;
        }
    }
}

impl<F: Real> HenyeyGreenstein<F> {
    /// [`PhaseBatch::sample_ratio_batch`] for at most [`CHUNK`] lanes of an
    /// f32 (`F = f32`: every conversion below is the identity).
    fn sample_chunk_f32(&self, u0: &[F], out: Deflections<'_, F>) {
        let n = u0.len();
        let g = self.g().to_f32();
        let (one_minus_g, one_plus_g) = (1.0 - g, 1.0 + g);
        let (omg2, opg2) = (one_minus_g * one_minus_g, one_plus_g * one_plus_g);
        let one_minus_g2 = one_minus_g * one_plus_g;
        let (pdf_scale, pdf_den) = (f32::FRAC_1_4PI, one_minus_g2 * one_minus_g2);
        // k = (1 − g) + 2g (1 − u) for g ≥ 0, (1 + g) − 2g u for g < 0, as
        // k0 + k1 v with v = v0 + v1 u = 1 − u or u: the same roundings
        // (−(2g) u = −(2g u) exactly), no select in the loop.
        let k0 = 1.0 - g.abs();
        let (k1, v0, v1) = if g >= 0.0 {
            (2.0 * g, 1.0, -1.0)
        } else {
            (-2.0 * g, 0.0, 1.0)
        };
        let (mut a, mut b) = ([0.0f32; CHUNK], [0.0f32; CHUNK]);
        let (a, b) = (&mut a[..n], &mut b[..n]);
        let (omc, opc) = (&mut out.one_minus_cos[..n], &mut out.one_plus_cos[..n]);
        let (pdf, ratio) = (&mut out.pdf[..n], &mut out.ratio[..n]);
        // The f32 part: 1 ∓ cos θ = a/k², b/k², and the density.
        for i in 0..n {
            let u = clamp_unit(u0[i].to_f32());
            let k = k0 + k1 * (v0 + v1 * u);
            a[i] = omg2 * u * (one_plus_g + k);
            b[i] = opg2 * (1.0 - u) * (one_minus_g + k);
            let inv_k = 1.0 / k;
            let inv_k2 = inv_k * inv_k;
            // `min(x, 2)` for the x ≥ 0 here: a comparison (no NaN).
            let (x, y) = (a[i] * inv_k2, b[i] * inv_k2);
            omc[i] = F::from_f32(if x <= 2.0 { x } else { 2.0 });
            opc[i] = F::from_f32(if y <= 2.0 { y } else { 2.0 });
            pdf[i] = F::from_f32(pdf_scale * (k * k * k) / pdf_den);
            ratio[i] = F::ONE;
        }
        // θ = 2 atan2(√a, √b) as atan2_sqrt_f32 computes it in f64:
        // w = min/max(a, b), base ± √w Q(w) with the base 0 or π/2, two f64
        // lanes to a register.
        let theta = &mut out.theta[..n];
        for i in 0..n {
            let (a, b) = (f64::from(a[i]), f64::from(b[i]));
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            let w = lo
                / if hi > f64::MIN_POSITIVE {
                    hi
                } else {
                    f64::MIN_POSITIVE
                };
            // sign(b − a) (+1 for a = b), base = (1 − sign) π/4.
            let sign = if b >= a { 1.0 } else { -1.0 };
            let base = (1.0 - sign) * core::f64::consts::FRAC_PI_4;
            let t = (base + w.sqrt() * (sign * atan_sqrt_ratio(w))) as f32;
            theta[i] = F::from_f32(2.0 * t);
        }
    }
}

/// `atan(√w)/√w = Q(w)` on `w ∈ [0, 1]` ([`ATAN_SQRT`]) in f64, in the
/// order of the f32 kernel `atan2_sqrt_f32` (Estrin's pairs, then `w⁴`,
/// `w⁸`), so that `base ± √w Q(w)` is its value bit for bit.
#[inline(always)]
fn atan_sqrt_ratio(w: f64) -> f64 {
    let w2 = w * w;
    let w4 = w2 * w2;
    let w8 = w4 * w4;
    let c = &ATAN_SQRT;
    ((c[0] + c[1] * w) + w2 * (c[2] + c[3] * w))
        + w4 * ((c[4] + c[5] * w) + w2 * (c[6] + c[7] * w))
        + w8 * ((c[8] + c[9] * w) + w2 * c[10])
}

/// [`PhaseBatch::sample_ratio_batch`]'s default: `sample_ratio(u0[i])`
/// into lane `i`, one call per lane.
#[inline]
fn sample_ratio_each<F: Real, P: PhaseFunction<F> + ?Sized>(
    phase: &P,
    u0: &[F],
    out: Deflections<'_, F>,
) {
    let lanes = u0
        .iter()
        .zip(out.theta)
        .zip(out.one_minus_cos)
        .zip(out.one_plus_cos)
        .zip(out.pdf)
        .zip(out.ratio);
    for (((((&u, theta), omc), opc), pdf), ratio) in lanes {
        let (d, q, r) = phase.sample_ratio(u);
        (*theta, *omc, *opc, *pdf, *ratio) = (d.theta, d.one_minus_cos, d.one_plus_cos, q, r);
    }
}

/// `√x` as [`Real::sqrt`] computes it, bit for bit, through f64's square
/// root: in f32 the correctly rounded f64 root of the (exact) f64 value,
/// rounded to f32, is the correctly rounded f32 root (53 ≥ 2·24 + 2 bits:
/// the second rounding cannot cross a midpoint; Figueroa 1995, "When is
/// double rounding innocuous?"; checked on all 2³² inputs). `libm`'s f32
/// root is an instruction opaque to the compiler, taken lane by lane; its
/// f64 root is LLVM's `sqrt` intrinsic, which LLVM, knowing the same fact,
/// turns into the f32 one and vectorises (`sqrtps`, four lanes at a time).
#[inline(always)]
fn sqrt_via_f64<F: Real>(x: F) -> F {
    F::from_f64(x.to_f64().sqrt())
}

/// Whether `F` is f32 (folded at compile time).
#[inline(always)]
fn is_f32<F: Real>() -> bool {
    F::EPSILON.to_f64() > 1e-10
}

/// A batch of connections `x0_i → x2_i` with one restriction θ < θmax: the
/// structure-of-arrays form of [`Connection`], one connection per lane. The
/// end points are the caller's and are not checked here: a lane whose
/// points the scalar constructor refuses has no vertex
/// ([`Connections::connection`]).
///
/// **Each lane is the scalar call, bit for bit.** Lane `i` of
/// [`Connections::sample_omnee`] is
///
/// `Connection::new(x0_i, x2_i, θmax)` then `Omnee::new(c, phase).sample([u0_i, u1_i, u2_i])`,
///
/// of [`Connections::sample_mis`] the core's recommended [`OmneeMis`] (the
/// equiangular companion of the [`Setup`]'s directions and region) on
/// `[u0_i, u1_i, u2_i, v0_i, v1_i, v2_i]`, and of
/// [`Connections::sample_lobe_mis`] the recommended [`LobeMis`]: the same
/// vertex, density and weight to the last bit, and `valid = false` (with
/// zeros) where the scalar constructor refuses the lane's end points
/// (non-finite, coincident, a distance that overflows) or the sampler
/// returns `None`. One rule is the batch's own: a lane with a NaN or
/// infinite uniform number has no vertex (the scalar samplers clamp `u0`
/// into `[0, 1]`, a NaN to 0, and would draw one; the C API refuses such
/// numbers). A lane never holds NaN.
///
/// **How the f32 lanes get there fast.** The scalar sampler is bound by
/// latency (one sample's chain of square roots, divisions and
/// polynomials); written without branches it vectorises across lanes.
/// Its square roots too: `libm`'s f32 root is an opaque instruction to the
/// compiler (stable `no_std` Rust has no other), its f64 root LLVM's
/// intrinsic, and the f32 root is the f64 root of the same number rounded
/// to f32, bit for bit. So a chunk of [`CHUNK`] lanes goes through stages,
/// each a loop over the chunk:
///
/// 1. the phase function's deflections ([`PhaseBatch`]; Henyey–Greenstein
///    in f32 vectorised, its `atan` in f64 lanes, any other phase function
///    one call per lane);
/// 2. the angles whose sines and cosines the f32 kernels take in f64 (the
///    triangle's smaller angle, the azimuth) and the square roots
///    `s = |x2 − x0|` and `sin θ`, two f64 lanes to a register;
/// 3. the frame, the triangle, `x1`, pdf and weight, branch-free, four f32
///    lanes to a register (SSE2);
/// 4. the rare lane left to the scalar sampler (below).
///
/// Every operation is the scalar path's, in its order, with its kernels
/// ([`Real::sin_cos_acute`], the f64 polynomials of the f32 angle kernels);
/// what a branch chooses in the scalar path a select chooses here, with
/// both sides computed. The one kernel written differently is the
/// azimuth's sign `(−1)ʲ`, from `j² = 1` instead of an integer's parity
/// (SSE2 converts one lane at a time): it agrees for `|u2| ≤ 1`
/// (`j ∈ {−2, …, 2}`), and a lane with a finite `u2` beyond is left to the
/// scalar sampler. In f64 the same stages run with `libm`'s trigonometry
/// (the scalar f64 path's), lane by lane.
///
/// ```
/// use omnee_core::phase::HenyeyGreenstein;
/// use omnee_core::sampling::{
///     Connection, Connections, Omnee, Points, PointsMut, SampleArrays, Technique, Uniforms,
/// };
/// use glam::Vec3;
///
/// # fn main() -> Result<(), omnee_core::Error> {
/// // Three receivers on the floor, each with a light point of its own.
/// let x0 = ([0.0f32, 0.5, -0.3], [0.0, 0.1, 0.2], [1.0, 1.2, 0.8]);
/// let x2 = ([0.1f32, -0.2, 0.3], [0.0, 0.0, 0.1], [0.0; 3]);
/// let connections = Connections::new(
///     Points { x: &x0.0, y: &x0.1, z: &x0.2 },
///     Points { x: &x2.0, y: &x2.1, z: &x2.2 },
///     core::f32::consts::PI,
/// )?;
/// let (u0, u1, u2) = ([0.3f32, 0.6, 0.9], [0.5, 0.25, 0.75], [0.1, 0.4, 0.7]);
/// let (mut x, mut y, mut z) = ([0.0f32; 3], [0.0; 3], [0.0; 3]);
/// let (mut pdf, mut weight, mut valid) = ([0.0f32; 3], [0.0; 3], [false; 3]);
/// let phase = HenyeyGreenstein::new(0.9)?;
/// let n = connections.sample_omnee(
///     &phase,
///     Uniforms { u0: &u0, u1: &u1, u2: &u2 },
///     SampleArrays {
///         x1: PointsMut { x: &mut x, y: &mut y, z: &mut z },
///         pdf: &mut pdf,
///         weight: &mut weight,
///         valid: &mut valid,
///     },
/// )?;
/// assert_eq!(n, 3);
/// // Lane 1 is the scalar sample of its own connection, to the last bit.
/// let c = Connection::new(Vec3::new(0.5, 0.1, 1.2), Vec3::new(-0.2, 0.0, 0.0), core::f32::consts::PI)?;
/// let s = Omnee::new(c, phase).sample([0.6, 0.25, 0.4]).unwrap();
/// assert_eq!((Vec3::new(x[1], y[1], z[1]), pdf[1], weight[1]), (s.x1, s.pdf, s.weight));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Connections<'a, F: Real> {
    x0: Points<'a, F>,
    x2: Points<'a, F>,
    theta_max: F,
    len: usize,
}

impl<'a, F: Real> Connections<'a, F> {
    /// The connections from `x0[i]` (light side) to `x2[i]` (receiver side),
    /// restricted to θ < `theta_max`. Fails with [`Error::Arrays`] (field
    /// `"connections"`) if the six slices differ in length, and for a θmax
    /// that [`Connection::new`] refuses, with its error.
    pub fn new(x0: Points<'a, F>, x2: Points<'a, F>, theta_max: F) -> Result<Self, Error> {
        let len = match (x0.len(), x2.len()) {
            (Some(a), Some(b)) if a == b => a,
            _ => {
                return Err(Error::Arrays {
                    field: "connections",
                    reason: "the coordinates of x0 and x2 differ in length",
                });
            }
        };
        // θmax as the scalar constructor checks and stores it, on a unit
        // connection: the batch accepts exactly the θmax it accepts.
        let (zero, one) = (F::ZERO, F::ONE);
        let unit = Connection::new(
            F::Vec3::new(zero, zero, one),
            F::Vec3::new(zero, zero, zero),
            theta_max,
        )?;
        Ok(Self {
            x0,
            x2,
            theta_max: unit.theta_max,
            len,
        })
    }

    /// The number of connections.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The light-side end points.
    #[inline]
    pub fn x0(&self) -> Points<'a, F> {
        self.x0
    }

    /// The receiver-side end points.
    #[inline]
    pub fn x2(&self) -> Points<'a, F> {
        self.x2
    }

    /// θmax, as [`Connection::new`] stores it (at most π).
    #[inline]
    pub fn theta_max(&self) -> F {
        self.theta_max
    }

    /// Lane `i`'s connection, `Connection::new(x0[i], x2[i], θmax)`; `None`
    /// where that fails (the lane has no vertex) or `i ≥ len`.
    #[inline]
    pub fn connection(&self, i: usize) -> Option<Connection<F>> {
        if i >= self.len {
            return None;
        }
        Connection::new(self.x0.at(i), self.x2.at(i), self.theta_max).ok()
    }

    /// OMNEE for every lane: lane `i` of `out` is
    /// `Omnee::new(connection(i), phase).sample([u0[i], u1[i], u2[i]])`,
    /// bit for bit, and no vertex if one of the three is NaN or infinite
    /// (see [`Connections`] for how). Returns
    /// the number of lanes with a vertex. Fails with [`Error::Arrays`]
    /// (field `"connections"`) if a slice of `u` or `out` differs in length
    /// from the connections, writing nothing.
    pub fn sample_omnee<P: PhaseBatch<F>>(
        &self,
        phase: &P,
        u: Uniforms<'_, F>,
        mut out: SampleArrays<'_, F>,
    ) -> Result<usize, Error> {
        self.check(&[u], [&out])?;
        let mut lanes = Lanes::new();
        let mut count = 0;
        for start in (0..self.len).step_by(CHUNK) {
            count += self.omnee_chunk(phase, &u, start, &mut lanes, &mut out);
        }
        Ok(count)
    }

    /// The core's recommended MIS ([`OmneeMis::recommended`], what
    /// [`Setup::draw`] does for [`crate::method::Method::Mis`]) for every
    /// lane: OMNEE's vertex from `u` into `omnee`, and, when `v.u0[i]` is
    /// below the companion's rate, the equiangular companion's (rays by the
    /// setup's directions and region) from `v` into `companion`. Lane `i`
    /// is `OmneeMis::sample([u0, u1, u2, v0, v1, v2])` of lane `i`'s
    /// connection, bit for bit: OMNEE's vertex with its density and weight
    /// combined with the companion's behind the cone θ ≥ 3π/4, the
    /// companion's vertex where it is drawn and lies behind the cone; no
    /// vertex in either output where one of the six numbers is NaN or
    /// infinite.
    /// Returns the number of vertices (of both outputs). Fails with
    /// [`Error::Arrays`] (field `"connections"`) if any slice differs in
    /// length from the connections, writing nothing.
    ///
    /// OMNEE's vertices come from [`sample_omnee`](Self::sample_omnee)'s
    /// stages; a lane behind the cone or with a companion (about 5 % of
    /// lanes for forward phase functions) is then drawn by the scalar
    /// `OmneeMis`.
    pub fn sample_mis<P: PhaseBatch<F>>(
        &self,
        setup: &Setup<F, P>,
        u: Uniforms<'_, F>,
        v: Uniforms<'_, F>,
        mut omnee: SampleArrays<'_, F>,
        mut companion: SampleArrays<'_, F>,
    ) -> Result<usize, Error> {
        self.check(&[u, v], [&omnee, &companion])?;
        // OmneeMis::recommended's rate and the cone's 1 − cos θmin.
        let rate = F::from_f64(OmneeMis::<F, P>::RATE);
        let one_minus_cos_min = F::ONE + F::from_f64(core::f64::consts::FRAC_1_SQRT_2);
        let mut lanes = Lanes::new();
        let mut count = 0;
        for start in (0..self.len).step_by(CHUNK) {
            count += self.omnee_chunk(setup.phase(), &u, start, &mut lanes, &mut omnee);
            let n = (self.len - start).min(CHUNK);
            for i in start..start + n {
                let behind = omnee.valid[i] && lanes.one_minus_cos[i - start] >= one_minus_cos_min;
                let finite = v.u0[i].is_finite() & v.u1[i].is_finite() & v.u2[i].is_finite();
                if !(behind || v.u0[i] < rate || (omnee.valid[i] && !finite)) {
                    companion.set(i, None);
                    continue;
                }
                let u6 = [u.u0[i], u.u1[i], u.u2[i], v.u0[i], v.u1[i], v.u2[i]];
                let lane = self
                    .connection(i)
                    .filter(|_| u6.iter().all(|x| x.is_finite()));
                let vertices = lane.map_or([None, None], |c| {
                    let phase = setup.phase();
                    let equiangular =
                        Equiangular::new(c, phase, setup.directions(), setup.region());
                    OmneeMis::recommended(Omnee::new(c, phase), &equiangular).sample(u6)
                });
                count -= usize::from(omnee.valid[i]);
                count += vertices.iter().flatten().count();
                omnee.set(i, vertices[0]);
                companion.set(i, vertices[1]);
            }
        }
        Ok(count)
    }

    /// The core's recommended combination for a lobe at `x0`
    /// ([`LobeMis::recommended`]: OMNEE with the lobe in its weight and the
    /// lobe technique, one-sample MIS) for every lane, the lobe
    /// `PhaseLobe::new(lobe_phase, incoming[i])` of light arriving at
    /// `x0[i]` along `incoming[i]` (a propagation direction, normalised by
    /// the lobe), `phase` at `x1`: lane `i` of `out` is
    /// `LobeMis::recommended(connection(i), lobe_i, phase).sample([u0, u1, u2])`,
    /// one scalar call per lane (this technique has no vectorised path), so
    /// bit for bit; no vertex where the lobe refuses `incoming[i]` (zero or
    /// not finite) or a uniform number is NaN or infinite. Returns the number of lanes with a vertex. Fails with
    /// [`Error::Arrays`] (field `"connections"`) if a slice differs in
    /// length from the connections, writing nothing.
    pub fn sample_lobe_mis<L: PhaseFunction<F> + Copy, P: Restricted<F> + Copy>(
        &self,
        lobe_phase: L,
        incoming: Points<'_, F>,
        phase: P,
        u: Uniforms<'_, F>,
        mut out: SampleArrays<'_, F>,
    ) -> Result<usize, Error> {
        self.check(&[u], [&out])?;
        if incoming.len() != Some(self.len) {
            return Err(Error::Arrays {
                field: "connections",
                reason: "the incoming directions differ in length from the end points",
            });
        }
        let mut count = 0;
        for i in 0..self.len {
            let ui = [u.u0[i], u.u1[i], u.u2[i]];
            let lane = self
                .connection(i)
                .filter(|_| ui.iter().all(|x| x.is_finite()));
            let sample = lane.and_then(|c| {
                let lobe = PhaseLobe::new(lobe_phase, incoming.at(i)).ok()?;
                LobeMis::recommended(c, lobe, phase).sample(ui)
            });
            count += usize::from(sample.is_some());
            out.set(i, sample);
        }
        Ok(count)
    }

    /// Checks that every slice of `u` and `out` is as long as the batch.
    fn check<const N: usize>(
        &self,
        u: &[Uniforms<'_, F>],
        out: [&SampleArrays<'_, F>; N],
    ) -> Result<(), Error> {
        let n = self.len;
        let uniforms = u
            .iter()
            .all(|u| u.u0.len() == n && u.u1.len() == n && u.u2.len() == n);
        if uniforms && out.iter().all(|o| o.has_len(n)) {
            Ok(())
        } else {
            Err(Error::Arrays {
                field: "connections",
                reason: "uniform or output slices differ in length from the end points",
            })
        }
    }

    /// OMNEE for the lanes `start..start + CHUNK` (or to the end) into
    /// `out`, leaving each lane's drawn deflection in `lanes`; returns the
    /// number of lanes with a vertex.
    fn omnee_chunk<P: PhaseBatch<F>>(
        &self,
        phase: &P,
        u: &Uniforms<'_, F>,
        start: usize,
        lanes: &mut Lanes<F>,
        out: &mut SampleArrays<'_, F>,
    ) -> usize {
        let n = (self.len - start).min(CHUNK);
        let range = start..start + n;
        // 1. The phase function's deflections.
        phase.sample_ratio_batch(
            &u.u0[range.clone()],
            Deflections {
                theta: &mut lanes.theta[..n],
                one_minus_cos: &mut lanes.one_minus_cos[..n],
                one_plus_cos: &mut lanes.one_plus_cos[..n],
                pdf: &mut lanes.pdf[..n],
                ratio: &mut lanes.ratio[..n],
            },
        );
        // 2. The square roots: s = |x2 − x0| (glam's `length`, the dot
        //    product in its order) and sin θ = √((1 − cos θ)(1 + cos θ))
        //    (`Deflection::sin`), through f64; the sines and cosines of
        //    the triangle's smaller angle and of the azimuth.
        let (x0, x2) = (&self.x0, &self.x2);
        let (ax, ay, az) = (
            &x0.x[range.clone()],
            &x0.y[range.clone()],
            &x0.z[range.clone()],
        );
        let (bx, by, bz) = (
            &x2.x[range.clone()],
            &x2.y[range.clone()],
            &x2.z[range.clone()],
        );
        let (u1, u2) = (&u.u1[range.clone()], &u.u2[range.clone()]);
        let theta = &lanes.theta[..n];
        let (omc, opc) = (&lanes.one_minus_cos[..n], &lanes.one_plus_cos[..n]);
        let (s, sin_theta) = (&mut lanes.s[..n], &mut lanes.sin_theta[..n]);
        let (sin_small, cos_small) = (&mut lanes.sin_small[..n], &mut lanes.cos_small[..n]);
        let (sin_phi, cos_phi) = (&mut lanes.sin_phi[..n], &mut lanes.cos_phi[..n]);
        let scalar = &mut lanes.scalar[..n];
        let band = Unit::<F>::band();
        for i in 0..n {
            let (dx, dy, dz) = (bx[i] - ax[i], by[i] - ay[i], bz[i] - az[i]);
            s[i] = sqrt_via_f64(dx * dx + dy * dy + dz * dz);
            sin_theta[i] = sqrt_via_f64(omc[i] * opc[i]);
            let r = u1[i];
            // θ min(r, 1 − r) (`Triangle::solve_with_beta`; r ∈ [0, 1] or
            // the lane is refused).
            let small = theta[i] * if r <= F::ONE - r { r } else { F::ONE - r };
            (sin_small[i], cos_small[i]) = small.sin_cos_acute();
            let (sin, cos, hard) = sin_cos_turn(u2[i]);
            (sin_phi[i], cos_phi[i]) = (sin, cos);
            // A connection outside the band of unit 1 (docs/math.md
            // §15.2) is drawn by the scalar sampler, which scales by L.
            scalar[i] = hard | !((s[i] >= band.0) & (s[i] < band.1));
        }
        // 3. The rest of the geometry, branch-free.
        let (pdf, ratio) = (&lanes.pdf[..n], &lanes.ratio[..n]);
        let (s, sin_theta) = (&lanes.s[..n], &lanes.sin_theta[..n]);
        let (omc, opc) = (&lanes.one_minus_cos[..n], &lanes.one_plus_cos[..n]);
        let (sin_small, cos_small) = (&lanes.sin_small[..n], &lanes.cos_small[..n]);
        let (sin_phi, cos_phi) = (&lanes.sin_phi[..n], &lanes.cos_phi[..n]);
        let scalar = &lanes.scalar[..n];
        let (xs, ys, zs) = (
            &mut out.x1.x[range.clone()],
            &mut out.x1.y[range.clone()],
            &mut out.x1.z[range.clone()],
        );
        let (pdfs, weights) = (&mut out.pdf[range.clone()], &mut out.weight[range.clone()]);
        let u0 = &u.u0[range.clone()];
        let valid = &mut out.valid[range];
        let theta_max = self.theta_max;
        for i in 0..n {
            let lane = Lane {
                x0: [ax[i], ay[i], az[i]],
                x2: [bx[i], by[i], bz[i]],
                s: s[i],
                theta: theta[i],
                one_minus_cos: omc[i],
                one_plus_cos: opc[i],
                sin_theta: sin_theta[i],
                pdf: pdf[i],
                ratio: ratio[i],
                u1: u1[i],
                sin_small: sin_small[i],
                cos_small: cos_small[i],
                sin_phi: sin_phi[i],
                cos_phi: cos_phi[i],
            };
            let (x1, p, w, drawn) = lane.sample(theta_max);
            // (A non-finite u1 fails the triangle, a non-finite u2 goes to
            // the scalar path below.)
            let ok = drawn & !scalar[i] & u0[i].is_finite();
            let zero = F::ZERO;
            xs[i] = if ok { x1[0] } else { zero };
            ys[i] = if ok { x1[1] } else { zero };
            zs[i] = if ok { x1[2] } else { zero };
            pdfs[i] = if ok { p } else { zero };
            weights[i] = if ok { w } else { zero };
            valid[i] = ok;
        }
        // (Counted apart: a 64-bit sum in the loop halves its SIMD width.)
        let mut count = valid.iter().filter(|&&ok| ok).count();
        // 4. The lanes the branch-free path leaves to the scalar sampler
        //    (rare: a scan for one, then the lanes).
        if !lanes.scalar[..n]
            .iter()
            .fold(false, |any, &hard| any | hard)
        {
            return count;
        }
        for i in 0..n {
            if lanes.scalar[i] {
                let j = start + i;
                let uj = [u.u0[j], u.u1[j], u.u2[j]];
                let sample = self
                    .connection(j)
                    .filter(|_| uj.iter().all(|x| x.is_finite()))
                    .and_then(|c| Omnee::new(c, phase).sample(uj));
                count -= usize::from(out.valid[j]);
                count += usize::from(sample.is_some());
                out.set(j, sample);
            }
        }
        count
    }
}

/// One chunk's intermediate values by lane.
struct Lanes<F> {
    theta: [F; CHUNK],
    one_minus_cos: [F; CHUNK],
    one_plus_cos: [F; CHUNK],
    pdf: [F; CHUNK],
    ratio: [F; CHUNK],
    s: [F; CHUNK],
    sin_theta: [F; CHUNK],
    sin_small: [F; CHUNK],
    cos_small: [F; CHUNK],
    sin_phi: [F; CHUNK],
    cos_phi: [F; CHUNK],
    /// Whether the lane is left to the scalar sampler.
    scalar: [bool; CHUNK],
}

impl<F: Real> Lanes<F> {
    fn new() -> Self {
        let zero = [F::ZERO; CHUNK];
        Self {
            theta: zero,
            one_minus_cos: zero,
            one_plus_cos: zero,
            pdf: zero,
            ratio: zero,
            s: zero,
            sin_theta: zero,
            sin_small: zero,
            cos_small: zero,
            sin_phi: zero,
            cos_phi: zero,
            scalar: [false; CHUNK],
        }
    }
}

/// One lane's inputs to the geometry: its end points, the drawn deflection
/// with its density and ratio, the roots `s` and `sin θ`, `u1 = β/θ`, and
/// the sine and cosine of the triangle's smaller angle and of the azimuth.
#[derive(Clone, Copy)]
struct Lane<F> {
    x0: [F; 3],
    x2: [F; 3],
    s: F,
    theta: F,
    one_minus_cos: F,
    one_plus_cos: F,
    sin_theta: F,
    pdf: F,
    ratio: F,
    u1: F,
    sin_small: F,
    cos_small: F,
    sin_phi: F,
    cos_phi: F,
}

impl<F: Real> Lane<F> {
    /// The scalar path from the deflection on, branch-free:
    /// `Axis::new`'s frame (`e = (x2 − x0)/s`, glam's
    /// `any_orthonormal_pair`), `Triangle::solve_with_beta` (the smaller
    /// angle through `sin_cos_acute`, the larger by the addition theorems,
    /// the law of sines in its `sinc` form below the series threshold),
    /// the azimuth, `x1 = x0 + e d1 cos α + ρ d1 sin α`, and
    /// `pdf = p sinc θ · s/(d1 d2)²`, `weight = (p/q)/(s sinc θ)`
    /// (`Omnee::sample_vertex_deflection`), each check of the scalar path
    /// folded into the mask. Returns `(x1, pdf, weight, has a vertex)`.
    #[inline(always)]
    fn sample(self, theta_max: F) -> ([F; 3], F, F, bool) {
        let [ax, ay, az] = self.x0;
        let [bx, by, bz] = self.x2;
        let (one, zero) = (F::ONE, F::ZERO);
        // Axis::new: both points finite, 0 < s < ∞; a non-finite
        // coordinate makes s = |x2 − x0| ∞ or NaN, so 0 < s < ∞ is all of it.
        let s = self.s;
        let axis = (s > zero) & s.is_finite();
        let inv_s = one / s;
        let (ex, ey, ez) = ((bx - ax) * inv_s, (by - ay) * inv_s, (bz - az) * inv_s);
        // any_orthonormal_pair (Duff et al. 2017) with signum(z) as
        // copysign(1, z) (they differ for NaN only, an invalid lane).
        let sign = one.copysign(ez);
        let a = -one / (sign + ez);
        let b = ex * ey * a;
        let b1 = [one + sign * ex * ex * a, sign * b, -sign * ex];
        let b2 = [b, sign + ey * ey * a, -ey];
        // Omnee::sample_vertex_deflection: θ < θmax.
        let (theta, omc, opc) = (self.theta, self.one_minus_cos, self.one_plus_cos);
        let drawn = theta < theta_max;
        // Triangle::solve_with_beta.
        let ratio = self.u1;
        let closes =
            (theta >= zero) & (theta < F::PI) & (opc > zero) & (zero <= ratio) & (ratio <= one);
        let (beta, alpha) = (ratio * theta, (one - ratio) * theta);
        let sin_theta = self.sin_theta;
        let cos_theta = if omc <= one { one - omc } else { opc - one };
        let beta_is_smaller = ratio <= one - ratio;
        let (sin_small, cos_small) = (self.sin_small, self.cos_small);
        let sin_large = sin_theta * cos_small - cos_theta * sin_small;
        let cos_large = cos_theta * cos_small + sin_theta * sin_small;
        let (sin_alpha, cos_alpha, sin_beta) = if beta_is_smaller {
            (sin_large, cos_large, sin_small)
        } else {
            (sin_small, cos_small, sin_large)
        };
        // Below the series threshold of θ (so of β, α ≤ θ too) the sinc form.
        let series = sinc_is_series(theta);
        let sinc_theta = if series {
            sinc_series(theta)
        } else {
            sin_theta / theta
        };
        let scale = s / if series { sinc_theta } else { sin_theta };
        let (d1, d2) = if series {
            (
                scale * ratio * sinc_series(beta),
                scale * (one - ratio) * sinc_series(alpha),
            )
        } else {
            (scale * sin_beta, scale * sin_alpha)
        };
        let solved = closes & d1.is_finite() & d2.is_finite() & (sinc_theta > zero);
        let apart = (d1 > zero) & (d2 > zero);
        // The azimuth and x1 = x0 + e (d1 cos α) + ρ (d1 sin α).
        let (sin_phi, cos_phi) = (self.sin_phi, self.cos_phi);
        let radial = [
            b1[0] * cos_phi + b2[0] * sin_phi,
            b1[1] * cos_phi + b2[1] * sin_phi,
            b1[2] * cos_phi + b2[2] * sin_phi,
        ];
        let (along, across) = (d1 * cos_alpha, d1 * sin_alpha);
        let x1 = [
            ax + (ex * along + radial[0] * across),
            ay + (ey * along + radial[1] * across),
            az + (ez * along + radial[2] * across),
        ];
        let placed = x1[0].is_finite() & x1[1].is_finite() & x1[2].is_finite();
        // Omnee::density and the weight.
        let r = one / (d1 * d2);
        let pdf = saturate(self.pdf * sinc_theta * s * r * r);
        let weight = saturate(self.ratio / (s * sinc_theta));
        let ok = axis & drawn & solved & apart & placed;
        (x1, pdf, weight, ok)
    }
}

/// `(sin 2πt, cos 2πt)` as [`Real::sin_cos_turn`] computes it, and whether
/// the lane must leave it to the scalar path. In f32 that is
/// `sin_cos_turn_f32`'s computation (the nearest half turn `j`, the f64
/// polynomial at `2π(t − j/2)`, the sign `(−1)ʲ`) with `(−1)ʲ` from
/// `j² = 1` instead of an integer conversion (which SSE2 does one lane at a
/// time): equal for `|t| ≤ 1`, where `j ∈ {−2, …, 2}`; any other `t` (NaN
/// included) is left to the scalar path. In f64 it is the scalar's.
#[inline(always)]
fn sin_cos_turn<F: Real>(t: F) -> (F, F, bool) {
    if !is_f32::<F>() {
        let (s, c) = t.sin_cos_turn();
        return (s, c, false);
    }
    // j = round(2t) and r = t − j/2 in f32 (exact for |t| ≤ 1, as in f64),
    // 2πr and the polynomials in f64, the sign after rounding (which
    // commutes with it).
    let to_int = F::from_f64(1.5) / F::EPSILON;
    let j = (F::TWO * t + to_int) - to_int;
    let r = t - F::HALF * j;
    let (s, c) = sin_cos_acute_f64(core::f64::consts::TAU * r.to_f64());
    let sign = if j * j == F::ONE { -F::ONE } else { F::ONE };
    (
        F::from_f64(s) * sign,
        F::from_f64(c) * sign,
        !(t.abs() <= F::ONE),
    )
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::medium::Region;
    use crate::phase::{InverseCdf, Spec};
    use crate::rng::SplitMix64;
    use crate::sampling::{Directions, uniform};
    use glam::DVec3 as F64Vec;
    use std::vec::Vec;

    /// Owned structure-of-arrays storage for `n` lanes.
    struct Owned<F> {
        x: Vec<F>,
        y: Vec<F>,
        z: Vec<F>,
        pdf: Vec<F>,
        weight: Vec<F>,
        valid: Vec<bool>,
    }

    impl<F: Real> Owned<F> {
        fn new(n: usize) -> Self {
            Self {
                x: std::vec![F::ZERO; n],
                y: std::vec![F::ZERO; n],
                z: std::vec![F::ZERO; n],
                pdf: std::vec![F::ZERO; n],
                weight: std::vec![F::ZERO; n],
                valid: std::vec![false; n],
            }
        }

        fn samples(&mut self) -> SampleArrays<'_, F> {
            SampleArrays {
                x1: PointsMut {
                    x: &mut self.x,
                    y: &mut self.y,
                    z: &mut self.z,
                },
                pdf: &mut self.pdf,
                weight: &mut self.weight,
                valid: &mut self.valid,
            }
        }

        fn lane(&self, i: usize) -> Option<Sample<F>> {
            self.valid[i].then(|| Sample {
                x1: F::Vec3::new(self.x[i], self.y[i], self.z[i]),
                pdf: self.pdf[i],
                weight: self.weight[i],
            })
        }
    }

    fn bits<F: Real>(s: Option<Sample<F>>) -> Option<[u64; 5]> {
        s.map(|s| {
            let [x, y, z] = s.x1.to_array();
            [x, y, z, s.pdf, s.weight].map(|v| v.to_f64().to_bits())
        })
    }

    /// Random lanes: end points in a box of size `scale`, now and then a
    /// degenerate one, uniforms with now and then an edge or NaN.
    fn inputs<F: Real>(n: usize, seed: u64) -> [Vec<F>; 9] {
        let mut rng = SplitMix64::new(seed);
        let mut cols: [Vec<F>; 9] = Default::default();
        for i in 0..n {
            let mut p: [F; 9] = core::array::from_fn(|k| {
                let u: F = uniform(&mut rng);
                if k < 6 { F::TWO * u - F::ONE } else { u }
            });
            match i % 37 {
                3 => (p[3], p[4], p[5]) = (p[0], p[1], p[2]),
                5 => p[1] = F::from_f64(f64::NAN),
                7 => p[6] = F::from_f64(f64::NAN),
                11 => p[7] = F::from_f64(f64::NAN),
                13 => p[8] = F::from_f64(f64::NAN),
                17 => p[6] = F::ZERO,
                19 => p[7] = F::ONE,
                23 => p[8] = F::from_f64(1.5),
                29 => p[6] = F::ONE_MINUS_EPSILON,
                _ => {}
            }
            for (c, v) in cols.iter_mut().zip(p) {
                c.push(v);
            }
        }
        cols
    }

    fn check_omnee<F: Real, P: PhaseBatch<F> + Copy>(phase: P, theta_max: F, n: usize) -> usize {
        let [ax, ay, az, bx, by, bz, u0, u1, u2] = inputs::<F>(n, 0x5eed);
        let c = Connections::new(
            Points {
                x: &ax,
                y: &ay,
                z: &az,
            },
            Points {
                x: &bx,
                y: &by,
                z: &bz,
            },
            theta_max,
        )
        .unwrap();
        let mut out = Owned::new(n);
        let count = c
            .sample_omnee(
                &phase,
                Uniforms {
                    u0: &u0,
                    u1: &u1,
                    u2: &u2,
                },
                out.samples(),
            )
            .unwrap();
        let mut expected = 0;
        for i in 0..n {
            let ui = [u0[i], u1[i], u2[i]];
            let scalar = Connection::new(c.x0.at(i), c.x2.at(i), theta_max)
                .ok()
                .filter(|_| ui.iter().all(|x| x.is_finite()))
                .and_then(|conn| Omnee::new(conn, phase).sample(ui));
            expected += usize::from(scalar.is_some());
            assert_eq!(bits(out.lane(i)), bits(scalar), "lane {i}");
            assert!(out.x[i].is_finite() && out.pdf[i].is_finite() && out.weight[i].is_finite());
        }
        assert_eq!(count, expected);
        count
    }

    #[test]
    fn every_lane_is_the_scalar_sample_bit_for_bit() {
        let n = 1000;
        for theta_max in [0.3, core::f64::consts::FRAC_PI_2, core::f64::consts::PI] {
            for g in [-0.7, 0.0, 0.9, 0.999] {
                let count = check_omnee(
                    HenyeyGreenstein::new(g as f32).unwrap(),
                    theta_max as f32,
                    n,
                );
                assert!(count > n / 50, "{g} {theta_max}: {count}");
                check_omnee(HenyeyGreenstein::new(g).unwrap(), theta_max, n);
            }
            for spec in [
                "iso",
                "rayleigh",
                "tthg:0.99,-0.44,0.96",
                "mie:10",
                "hg:0.6",
            ] {
                let Spec::Analytic(p) = Spec::<f32>::parse(spec).unwrap() else {
                    unreachable!()
                };
                check_omnee(p, theta_max as f32, n);
                let Spec::Analytic(p) = Spec::<f64>::parse(spec).unwrap() else {
                    unreachable!()
                };
                check_omnee(p, theta_max, n);
            }
            let ff = FournierForand::new(0.0183f32, 1.1).unwrap();
            let table = InverseCdf::new(&ff).unwrap();
            check_omnee(TableSampled::new(ff, &table), theta_max as f32, n);
        }
    }

    #[test]
    fn mis_lanes_are_the_scalar_draw_bit_for_bit() {
        let n = 2000;
        let [ax, ay, az, bx, by, bz, u0, u1, u2] = inputs::<f32>(n, 7);
        let [_, _, _, _, _, _, v0, v1, v2] = inputs::<f32>(n, 8);
        let c = Connections::new(
            Points {
                x: &ax,
                y: &ay,
                z: &az,
            },
            Points {
                x: &bx,
                y: &by,
                z: &bz,
            },
            core::f32::consts::PI,
        )
        .unwrap();
        for g in [0.0f32, 0.9] {
            let hg = HenyeyGreenstein::new(g).unwrap();
            let setup = Setup::new(hg, Directions::Sphere, Region::Everywhere, 1.0).unwrap();
            let (mut o, mut k) = (Owned::new(n), Owned::new(n));
            let count = c
                .sample_mis(
                    &setup,
                    Uniforms {
                        u0: &u0,
                        u1: &u1,
                        u2: &u2,
                    },
                    Uniforms {
                        u0: &v0,
                        u1: &v1,
                        u2: &v2,
                    },
                    o.samples(),
                    k.samples(),
                )
                .unwrap();
            let (mut expected, mut companions) = (0, 0);
            for i in 0..n {
                let u6 = [u0[i], u1[i], u2[i], v0[i], v1[i], v2[i]];
                let lane = c.connection(i).filter(|_| u6.iter().all(|x| x.is_finite()));
                let want = lane.map_or([None, None], |conn| {
                    let eq = Equiangular::new(conn, hg, Directions::Sphere, Region::Everywhere);
                    OmneeMis::recommended(Omnee::new(conn, hg), &eq).sample(u6)
                });
                assert_eq!(bits(o.lane(i)), bits(want[0]), "g {g} lane {i}");
                assert_eq!(bits(k.lane(i)), bits(want[1]), "g {g} lane {i}");
                expected += want.iter().flatten().count();
                companions += usize::from(want[1].is_some());
            }
            assert_eq!(count, expected);
            assert!(companions > 5, "{companions}");
        }
    }

    #[test]
    fn lobe_lanes_are_the_scalar_combination_bit_for_bit() {
        let n = 500;
        let [ax, ay, az, bx, by, bz, u0, u1, u2] = inputs::<f64>(n, 11);
        let [ix, iy, iz, ..] = inputs::<f64>(n, 12);
        let c = Connections::new(
            Points {
                x: &ax,
                y: &ay,
                z: &az,
            },
            Points {
                x: &bx,
                y: &by,
                z: &bz,
            },
            core::f64::consts::PI,
        )
        .unwrap();
        let water = HenyeyGreenstein::new(0.9).unwrap();
        let mut out = Owned::new(n);
        let count = c
            .sample_lobe_mis(
                water,
                Points {
                    x: &ix,
                    y: &iy,
                    z: &iz,
                },
                water,
                Uniforms {
                    u0: &u0,
                    u1: &u1,
                    u2: &u2,
                },
                out.samples(),
            )
            .unwrap();
        let mut expected = 0;
        for i in 0..n {
            let ui = [u0[i], u1[i], u2[i]];
            let lane = c.connection(i).filter(|_| ui.iter().all(|x| x.is_finite()));
            let want = lane.and_then(|conn| {
                let lobe = PhaseLobe::new(water, F64Vec::new(ix[i], iy[i], iz[i])).ok()?;
                LobeMis::recommended(conn, lobe, water).sample(ui)
            });
            assert_eq!(bits(out.lane(i)), bits(want), "lane {i}");
            expected += usize::from(want.is_some());
        }
        assert_eq!(count, expected);
        assert!(count > n / 2, "{count}");
    }

    #[test]
    fn square_roots_through_f64_are_the_f32_roots() {
        // Every 997th bit pattern up to +∞ (all 2³² were checked once),
        // the edges, and NaN for what has no root.
        let check = |x: f32| {
            let (exact, via) = (Real::sqrt(x), sqrt_via_f64(x));
            let same = exact.to_bits() == via.to_bits() || (exact.is_nan() && via.is_nan());
            assert!(same, "{x:e}: {exact:e} against {via:e}");
        };
        (0..=f32::INFINITY.to_bits())
            .step_by(997)
            .for_each(|bits| check(f32::from_bits(bits)));
        let edges = [0.0, -0.0, f32::from_bits(1), f32::MIN_POSITIVE, f32::MAX];
        for x in edges.into_iter().chain([f32::INFINITY, -1.0, f32::NAN]) {
            check(x);
        }
        assert_eq!(sqrt_via_f64(2.0f64), Real::sqrt(2.0f64));
    }

    #[test]
    fn lengths_that_differ_are_an_error_and_nothing_is_written() {
        let a = [0.0f32; 3];
        let b = [1.0f32; 3];
        let short = [0.5f32; 2];
        let p = |x| Points { x, y: &a, z: &a };
        let e = Connections::new(p(&short), p(&b), 1.0).unwrap_err();
        assert_eq!(e.field(), "connections");
        let e = Connections::new(p(&a), p(&b), 4.0).unwrap_err();
        assert_eq!(e.field(), "theta_max");
        let c = Connections::new(p(&a), p(&b), 1.0).unwrap();
        let mut out = Owned::<f32>::new(3);
        out.pdf[0] = 7.0;
        let hg = HenyeyGreenstein::new(0.5f32).unwrap();
        let u = Uniforms {
            u0: &b,
            u1: &short,
            u2: &b,
        };
        let e = c.sample_omnee(&hg, u, out.samples()).unwrap_err();
        assert_eq!(e.field(), "connections");
        assert_eq!(out.pdf[0], 7.0);
        let mut short_out = Owned::<f32>::new(2);
        let u = Uniforms {
            u0: &b,
            u1: &b,
            u2: &b,
        };
        assert!(c.sample_omnee(&hg, u, short_out.samples()).is_err());
    }
}
