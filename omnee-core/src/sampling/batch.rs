//! A structure-of-arrays entry point: OMNEE with a Henyey–Greenstein phase
//! function for a whole batch of uniform triples at once, in f32.
//!
//! The loop body is the scalar [`Omnee::sample`](super::Technique::sample)
//! written without branches and without conversions between floats and
//! integers (x86-64's baseline, SSE2, converts one lane at a time), with the
//! scalar path's polynomials evaluated in f32 ([`real::SIN_ACUTE`],
//! [`real::ATAN_SQRT`]: the same fits, a few ulps from rounding in f32) and
//! a Newton reciprocal square root instead of calls into `libm` (whose
//! `sqrtf` is an opaque instruction, and stable `no_std` Rust has no other),
//! so that the compiler turns it into SIMD code: four lanes with the x86-64
//! baseline (SSE2), eight with AVX2. What the scalar sampler takes two square
//! roots and several divisions for, a lane gets from one `1/√(ab)` (θ,
//! sin θ, 1/sin θ) and three divisions (`1/k²`, the atan's `min/max` and
//! the pdf's `1/(d1 d2)²`);
//! minima, maxima and clamps are written as comparisons, which SSE2 does in
//! one instruction (`f32::min`'s NaN rule takes five). Results agree with
//! the scalar sampler to a few ulps (tested below); a lane that has no sample
//! (θ ≥ θmax, `x1` on an end point, NaN for `u1` or `u2`) gets
//! `pdf = weight = 0` and `x1 = x0`. As in the scalar sampler, `u0` is
//! clamped to `[0, 1]` with NaN taken as 0.
//!
//! [`real::SIN_ACUTE`]: crate::real
//! [`real::ATAN_SQRT`]: crate::real

use super::Omnee;
use crate::error::Error;
use crate::phase::HenyeyGreenstein;
use crate::real::{ATAN_SQRT, SIN_ACUTE};
use core::f32::consts::{FRAC_1_PI, FRAC_PI_2, TAU};

/// The uniform numbers of a batch, one slice per coordinate (f32 for
/// [`Omnee::sample_batch`], either precision for
/// [`Connections`](super::Connections)).
#[derive(Clone, Copy, Debug)]
pub struct Uniforms<'a, F = f32> {
    /// `u0`, which draws θ.
    pub u0: &'a [F],
    /// `u1 = β/θ`.
    pub u1: &'a [F],
    /// `u2 = φ/2π`.
    pub u2: &'a [F],
}

/// The vertices of a batch: `x1` by coordinate, its density and weight.
#[derive(Debug)]
pub struct Vertices<'a> {
    /// x coordinates of `x1`.
    pub x: &'a mut [f32],
    /// y coordinates of `x1`.
    pub y: &'a mut [f32],
    /// z coordinates of `x1`.
    pub z: &'a mut [f32],
    /// Volume densities (0 where there is no sample).
    pub pdf: &'a mut [f32],
    /// Weights `k/pdf = θ/(s sin θ)` (0 where there is no sample).
    pub weight: &'a mut [f32],
}

impl Omnee<f32, HenyeyGreenstein<f32>> {
    /// [`Technique::sample`](super::Technique::sample) for every `i` of the batch: `x1_i`, its pdf and
    /// weight from `(u0_i, u1_i, u2_i)`, by the same formulas (HG's inverse
    /// CDF in versine form with `θ = 2 atan2(√a, √b)`, the law of sines with
    /// the smaller of α, β through its sine and cosine, φ = 2π u2),
    /// branch-free. Returns the number of lanes that have a sample. Fails
    /// with [`Error::Arrays`] (field `"batch"`) if a slice's length differs
    /// from that of `u.u0` (the C ABI documents that error for it).
    pub fn sample_batch(&self, u: Uniforms<'_>, out: Vertices<'_>) -> Result<usize, Error> {
        let n = u.u0.len();
        let lengths = [
            u.u1.len(),
            u.u2.len(),
            out.x.len(),
            out.y.len(),
            out.z.len(),
            out.pdf.len(),
            out.weight.len(),
        ];
        if lengths.iter().any(|&len| len != n) {
            return Err(Error::Arrays {
                field: "batch",
                reason: "uniform and output slices differ in length",
            });
        }
        // One block for all but the largest batches, without the loop
        // (measured: it costs a batch of one vertex 15-20 ns, a fifth).
        if n <= BLOCK {
            return Ok(self.sample_block(u, out) as usize);
        }
        let mut count = 0;
        for start in (0..n).step_by(BLOCK) {
            let lanes = start..n.min(start + BLOCK);
            let block = self.sample_block(
                Uniforms {
                    u0: &u.u0[lanes.clone()],
                    u1: &u.u1[lanes.clone()],
                    u2: &u.u2[lanes.clone()],
                },
                Vertices {
                    x: &mut out.x[lanes.clone()],
                    y: &mut out.y[lanes.clone()],
                    z: &mut out.z[lanes.clone()],
                    pdf: &mut out.pdf[lanes.clone()],
                    weight: &mut out.weight[lanes],
                },
            );
            count += block as usize;
        }
        Ok(count)
    }

    /// [`sample_batch`](Self::sample_batch) for at most [`BLOCK`] lanes
    /// (slices of equal length), returning the number of lanes with a
    /// sample.
    #[inline]
    fn sample_block(&self, u: Uniforms<'_>, out: Vertices<'_>) -> u32 {
        let n = u.u0.len();
        let axis = &self.connection.axis;
        // The triangle in the connection's unit L = 2ᵏ (s/L of order one),
        // as the scalar sampler solves it: the sides scaled to metres by L,
        // the density per L³ by L⁻³ (three exact products by 1/L while
        // normal: the value leaves the range at most once, monotonely), the
        // weight per 1/L by 1/L. At ordinary scales L = 1.
        let (x0, e, b1, b2, s) = (axis.x0, axis.e, axis.b1, axis.b2, axis.s_unit);
        let (length, inverse) = (axis.unit.length, axis.unit.inverse);
        let theta_max = self.connection.theta_max;
        let g = self.phase.g();
        let (one_minus_g, one_plus_g) = (1.0 - g, 1.0 + g);
        let (omg2, opg2) = (one_minus_g * one_minus_g, one_plus_g * one_plus_g);
        let one_minus_g2 = one_minus_g * one_plus_g;
        let pdf_scale = 0.25 * FRAC_1_PI / (one_minus_g2 * one_minus_g2);
        // k = 1 + g − 2gu from non-negative terms, (1 − g) + 2g (1 − u) for
        // g ≥ 0 and (1 + g) + 2|g| u for g < 0, as k0 + k1 v with
        // v = v0 + v1 u = 1 − u or u (exact: the same roundings as the scalar
        // sampler's, and no select in the loop).
        let k0 = 1.0 - g.abs();
        let (k1, v0, v1) = if g >= 0.0 {
            (2.0 * g, 1.0, -1.0)
        } else {
            (-2.0 * g, 0.0, 1.0)
        };
        // Every slice cut to n, so that the loop has no bounds checks left
        // to stop the vectoriser.
        let (u0, u1, u2) = (&u.u0[..n], &u.u1[..n], &u.u2[..n]);
        let (xs, ys, zs) = (&mut out.x[..n], &mut out.y[..n], &mut out.z[..n]);
        let (pdfs, weights) = (&mut out.pdf[..n], &mut out.weight[..n]);
        let inv_s = 1.0 / s;
        let mut count = 0u32;
        for i in 0..n {
            let uu = clamp_unit(u0[i]);
            // 1 − cos θ = a/k², 1 + cos θ = b/k² (so a + b = 2k² and
            // sin θ = √(ab)/k²), θ = 2 atan2(√a, √b).
            let k = k0 + k1 * (v0 + v1 * uu);
            let a = omg2 * uu * (one_plus_g + k);
            let b = opg2 * (1.0 - uu) * (one_minus_g + k);
            let (k2, ab) = (k * k, a * b);
            let inv_k2 = 1.0 / k2;
            // One reciprocal square root serves θ, sin θ and 1/sin θ.
            let q = rsqrt(ab);
            let theta = 2.0 * atan2_sqrt(a, b, q);
            let sin_theta = ab * q * inv_k2;
            let (omc, opc) = (a * inv_k2, b * inv_k2);
            let cos_theta = if omc <= 1.0 { 1.0 - omc } else { opc - 1.0 };
            let ratio = clamp_unit(u1[i]);
            let beta_is_smaller = ratio <= 1.0 - ratio;
            let small = if beta_is_smaller { ratio } else { 1.0 - ratio };
            let (sin_small, cos_small) = sin_cos_acute(theta * small);
            let sin_large = sin_theta * cos_small - cos_theta * sin_small;
            let cos_large = cos_theta * cos_small + sin_theta * sin_small;
            let (sin_alpha, cos_alpha, sin_beta) = if beta_is_smaller {
                (sin_large, cos_large, sin_small)
            } else {
                (sin_small, cos_small, sin_large)
            };
            // The law of sines d1 = s sin β/sin θ, d2 = s sin α/sin θ, and
            // sinc θ = sin θ/θ; at θ = 0 (a = 0) their limits: the ratios
            // β/θ = r and α/θ = 1 − r, sinc 0 = 1 (x1 on the segment).
            let flat = theta == 0.0;
            let (theta_, sin_theta_, inv_sin_theta) = if flat {
                (1.0, 1.0, 1.0)
            } else {
                (theta, sin_theta, k2 * q)
            };
            let (sin_alpha_, sin_beta_) = if flat {
                (1.0 - ratio, ratio)
            } else {
                (sin_alpha, sin_beta)
            };
            let d1 = s * sin_beta_ * inv_sin_theta;
            let d2 = s * sin_alpha_ * inv_sin_theta;
            let (sin_phi, cos_phi) = sin_cos_turn(clamp_unit(u2[i]));
            // x1 = x0 + (e d1 cos α + ρ d1 sin α) with d1 in metres, in the
            // scalar sampler's order (d1 L overflowing as its does).
            let d1_metres = d1 * length;
            let (p1, h) = (d1_metres * cos_alpha, d1_metres * sin_alpha);
            // p = p(θ) sinc θ · s/(d1 d2)², k/p = θ/(s sin θ), per L³ and
            // per 1/L.
            let d12 = d1 * d2;
            let phase_pdf = pdf_scale * (k2 * k);
            let pdf_unit = phase_pdf * sin_theta_ * s / (theta_ * (d12 * d12));
            let pdf = pdf_unit * inverse * inverse * inverse;
            let weight = theta_ * inv_sin_theta * inv_s * inverse;
            let x = x0.x + (e.x * p1 + (b1.x * cos_phi + b2.x * sin_phi) * h);
            let y = x0.y + (e.y * p1 + (b1.y * cos_phi + b2.y * sin_phi) * h);
            let z = x0.z + (e.z * p1 + (b1.z * cos_phi + b2.z * sin_phi) * h);
            // `&`, not `&&`: no branches in the loop body. `|x| < ∞` is
            // `is_finite` (NaN fails): a vertex beyond the largest number
            // is no sample, as in the scalar sampler.
            let ok = (theta < theta_max)
                & (d1 > 0.0)
                & (d2 > 0.0)
                & (pdf_unit > 0.0)
                & !pdf.is_nan()
                & !weight.is_nan()
                & (x.abs() < f32::INFINITY)
                & (y.abs() < f32::INFINITY)
                & (z.abs() < f32::INFINITY)
                & !u1[i].is_nan()
                & !u2[i].is_nan();
            // Saturated at the largest number, as the scalar sampler's, before
            // the selects: a select inside a select's arm becomes a branch,
            // and stores on both sides of a branch keep LLVM from
            // vectorising the loop.
            let (pdf, weight) = (below_max(pdf), below_max(weight));
            xs[i] = if ok { x } else { x0.x };
            ys[i] = if ok { y } else { x0.y };
            zs[i] = if ok { z } else { x0.z };
            pdfs[i] = if ok { pdf } else { 0.0 };
            weights[i] = if ok { weight } else { 0.0 };
            count += u32::from(ok);
        }
        count
    }
}

/// Lanes per block of [`Omnee::sample_batch`]: a block counts its samples in
/// a `u32`, four lanes to an SSE2 register. A `usize` count in the loop
/// takes two registers per four lanes and doubled the time per sample
/// (`batch/f32/omnee/hg0.9` in `benches/samplers.rs`: 21 ns against 10).
/// The unit tests take blocks of 1000 lanes, so that their batches of
/// 4103 run through the loop over blocks.
const BLOCK: usize = if cfg!(test) { 1000 } else { u32::MAX as usize };

/// `u` clamped to `[0, 1]`, NaN to 0: [`Real::clamp_to`](crate::Real::clamp_to)
/// in the comparison form that SSE2 does in one `maxps` and one `minps`
/// (`f32::clamp` would keep NaN, `f32::max` costs five instructions).
#[inline(always)]
pub(super) fn clamp_unit(u: f32) -> f32 {
    let u = if u >= 0.0 { u } else { 0.0 };
    if u <= 1.0 { u } else { 1.0 }
}

/// `x` saturated at `f32::MAX` (∞ to the largest number) for `x` not NaN,
/// in the comparison form that SSE2 does in one `minps`.
#[inline(always)]
fn below_max(x: f32) -> f32 {
    if x < f32::MAX { x } else { f32::MAX }
}

/// `1/√p` for `p ≥ 0`: the bit-level first guess `0x5f375a86 − bits(p)/2`
/// (Lomont 2003, relative error below 3.5 %) and three Newton steps
/// `y ← y (3/2 − (p/2) y²)` (error squared each time); 0 for `p = 0` (and
/// for the subnormals, below 1.2e-38, where the first guess fails), NaN for
/// NaN. Then `√p = p · rsqrt(p)`.
#[inline(always)]
fn rsqrt(p: f32) -> f32 {
    let h = 0.5 * p;
    let mut y = f32::from_bits(0x5f37_5a86_u32.wrapping_sub(p.to_bits() >> 1));
    for _ in 0..3 {
        y *= 1.5 - h * y * y;
    }
    if p < f32::MIN_POSITIVE { 0.0 } else { y }
}

/// `(sin x, cos x)` for `|x| ≤ π/2` in f32: `x S(x²)` and `y S(y²)` with
/// `y = π/2 − |x|` (π/2 in two parts, so `y` keeps its digits next to π/2),
/// [`SIN_ACUTE`] in Estrin's scheme: the scalar path's kernel
/// ([`crate::real::sin_cos_acute_f32`]) evaluated in f32.
#[inline(always)]
fn sin_cos_acute(x: f32) -> (f32, f32) {
    const C: [f32; 6] = [
        SIN_ACUTE[0] as f32,
        SIN_ACUTE[1] as f32,
        SIN_ACUTE[2] as f32,
        SIN_ACUTE[3] as f32,
        SIN_ACUTE[4] as f32,
        SIN_ACUTE[5] as f32,
    ];
    // π/2 = PIO2_HI + PIO2_LO, PIO2_HI the f32 nearest (above) π/2.
    const PIO2_HI: f32 = FRAC_PI_2;
    const PIO2_LO: f32 = -4.371_139e-8;
    // Estrin's pairs, z⁴ nested as z²(… + z² …) so that no power below z²
    // is formed: z⁴ of a small z would be subnormal, and SSE2 takes a slow
    // path on every subnormal result.
    let poly = |z: f32| {
        let z2 = z * z;
        (C[0] + C[1] * z) + z2 * ((C[2] + C[3] * z) + z2 * (C[4] + C[5] * z))
    };
    let y = (PIO2_HI - x.abs()) + PIO2_LO;
    (x * poly(x * x), y * poly(y * y))
}

/// `(sin 2πt, cos 2πt)` for `t ∈ [0, 1]` without an integer: the nearest half
/// turn `j ∈ {0, 1, 2}` by the round-to-integer constant, `r = t − j/2`
/// (exact), [`sin_cos_acute`] at `2πr`, and the sign `(−1)ʲ = 1 − 2j(2 − j)`.
#[inline(always)]
fn sin_cos_turn(t: f32) -> (f32, f32) {
    const TO_INT: f32 = 1.5 / f32::EPSILON;
    let j = (2.0 * t + TO_INT) - TO_INT;
    let (s, c) = sin_cos_acute(TAU * (t - 0.5 * j));
    let sign = 1.0 - 2.0 * j * (2.0 - j);
    (sign * s, sign * c)
}

/// `atan2(√a, √b)` for `a, b ≥ 0` in f32, given `q = 1/√(ab)` ([`rsqrt`]):
/// `w = min/max(a, b) ∈ [0, 1]`, `t = min(a, b) q = √w`,
/// `atan t = t Q(w)` ([`ATAN_SQRT`] in f32), `π/2 −` it if `a > b`: the
/// scalar path's kernel ([`crate::real::atan2_sqrt_f32`]) evaluated in f32.
/// `w` by a division rather than as `t²`, so that `Q(w)` does not wait for
/// the square root (8 % less time per sample). 0 where `q = 0` and `a ≤ b`
/// (`a = 0`, or `ab` below the normal range).
#[inline(always)]
fn atan2_sqrt(a: f32, b: f32, q: f32) -> f32 {
    const C: [f32; 11] = [
        ATAN_SQRT[0] as f32,
        ATAN_SQRT[1] as f32,
        ATAN_SQRT[2] as f32,
        ATAN_SQRT[3] as f32,
        ATAN_SQRT[4] as f32,
        ATAN_SQRT[5] as f32,
        ATAN_SQRT[6] as f32,
        ATAN_SQRT[7] as f32,
        ATAN_SQRT[8] as f32,
        ATAN_SQRT[9] as f32,
        ATAN_SQRT[10] as f32,
    ];
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let t = lo * q;
    let w = lo
        / if hi > f32::MIN_POSITIVE {
            hi
        } else {
            f32::MIN_POSITIVE
        };
    // Estrin's scheme with w⁸ nested as w⁴(… + w⁴ …): no power below w⁴ is
    // formed (w⁸ is subnormal for t < 0.004, θ < 0.009, and SSE2 takes a
    // slow path on every subnormal result).
    let (w2, w4) = (w * w, w * w * w * w);
    let poly = ((C[0] + C[1] * w) + w2 * (C[2] + C[3] * w))
        + w4 * (((C[4] + C[5] * w) + w2 * (C[6] + C[7] * w))
            + w4 * ((C[8] + C[9] * w) + w2 * C[10]));
    let t = t * poly;
    if a > b { FRAC_PI_2 - t } else { t }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::Vector;
    use crate::sampling::{Connection, Technique};
    use glam::{DVec3, Vec3};

    fn ulps(a: f32, b: f64) -> f64 {
        (a as f64 - b).abs() / (f32::EPSILON as f64 * b.abs().max(f32::MIN_POSITIVE as f64))
    }

    #[test]
    fn lane_kernels_are_within_a_few_ulps() {
        let (mut sin_err, mut cos_err, mut turn_err, mut atan_err) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let n = 1_000_000;
        for i in 0..=n {
            let t = i as f32 / n as f32;
            let x = t * FRAC_PI_2;
            let (s, c) = sin_cos_acute(x);
            let (s64, c64) = (x as f64).sin_cos();
            sin_err = sin_err.max(ulps(s, s64));
            cos_err = cos_err.max(ulps(c, c64));
            // The azimuth: absolute error in units of ε (it only turns x1).
            let (s, c) = sin_cos_turn(t);
            let (s64, c64) = (core::f64::consts::TAU * t as f64).sin_cos();
            let abs = (s as f64 - s64).abs().max((c as f64 - c64).abs());
            turn_err = turn_err.max(abs / f32::EPSILON as f64);
            // atan2(√a, √b) over versine pairs a + b = 2.
            let (a, b) = (2.0 * t, 2.0 - 2.0 * t);
            let exact = (a as f64).sqrt().atan2((b as f64).sqrt());
            atan_err = atan_err.max(ulps(atan2_sqrt(a, b, rsqrt(a * b)), exact));
        }
        let mut sqrt_err = 0.0f64;
        let mut a = f32::MIN_POSITIVE;
        while a < 16.0 {
            sqrt_err = sqrt_err.max(ulps(rsqrt(a), 1.0 / (a as f64).sqrt()));
            a = f32::from_bits(a.to_bits() + 997);
        }
        assert_eq!(rsqrt(0.0), 0.0);
        std::println!(
            "sin {sin_err:.2} ulp, cos {cos_err:.2} ulp, turn {turn_err:.2} ε, atan2_sqrt {atan_err:.2} ulp, rsqrt {sqrt_err:.2} ulp"
        );
        assert!(
            sin_err < 4.0 && cos_err < 4.0 && turn_err < 2.0 && atan_err < 4.0 && sqrt_err < 2.0
        );
    }

    #[test]
    fn the_batch_matches_the_scalar_sampler() {
        // At ordinary scales and far outside them (2^±100: 1e±30), where
        // the triangle is solved in the connection's unit, up to the ends
        // of the range: at 2^127 part of the vertices lie beyond the
        // largest number, below 2^-126 the end points are subnormal.
        for scale in [0, -40, 40, -100, 100, -126, 126, 127, -135, -148] {
            batch_matches_scalar_at(scale);
        }
    }

    fn batch_matches_scalar_at(scale: i32) {
        let (x0, x2) = (Vec3::new(0.3, -0.2, 1.1), Vec3::new(-0.1, 0.4, 0.2));
        let c = Connection::new(x0.scale_pow2(scale), x2.scale_pow2(scale), 2.8).unwrap();
        let n = 4096;
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut us: std::vec::Vec<[f32; 3]> = (0..n).map(|_| [next(), next(), next()]).collect();
        // Edges: u at 0 and 1 − ulp, θ at 0, tiny θ, NaN (u0 taken as 0,
        // no sample for u1 or u2).
        let edge = 1.0 - f32::EPSILON / 2.0;
        us.extend([
            [0.0, 0.5, 0.5],
            [edge, 0.5, 0.5],
            [1e-7, 0.3, 0.1],
            [0.5, 0.0, edge],
            [f32::NAN, 0.5, 0.5],
            [0.5, f32::NAN, 0.5],
            [0.5, 0.5, f32::NAN],
        ]);
        let soa = |k: usize| us.iter().map(|u| u[k]).collect::<std::vec::Vec<f32>>();
        let (u0, u1, u2) = (soa(0), soa(1), soa(2));
        for g in [-0.7f32, 0.0, 0.9, 0.999] {
            let omnee = Omnee::new(c, HenyeyGreenstein::new(g).unwrap());
            let m = us.len();
            let (mut x, mut y, mut z) = (std::vec![0.0; m], std::vec![0.0; m], std::vec![0.0; m]);
            let (mut pdf, mut weight) = (std::vec![0.0; m], std::vec![0.0; m]);
            let count = omnee
                .sample_batch(
                    Uniforms {
                        u0: &u0,
                        u1: &u1,
                        u2: &u2,
                    },
                    Vertices {
                        x: &mut x,
                        y: &mut y,
                        z: &mut z,
                        pdf: &mut pdf,
                        weight: &mut weight,
                    },
                )
                .unwrap();
            let mut expected = 0;
            let (mut dx, mut dp, mut dw) = (0.0f64, 0.0f64, 0.0f64);
            for (i, u) in us.iter().enumerate() {
                match omnee.sample(*u) {
                    Some(s) => {
                        expected += 1;
                        // Relative to the size (in f64: at 2^127 it
                        // overflows f32), less a few of the subnormal
                        // coordinates' ulps (2⁻¹⁴⁹ each).
                        let (x0, x1) = (c.axis.x0.as_dvec3(), s.x1.as_dvec3());
                        let size = (x1 - x0).length() + x0.length() + f64::from(c.axis.s);
                        let ulps = 4.0 * f64::from(f32::from_bits(1));
                        let d = (DVec3::new(x[i].into(), y[i].into(), z[i].into()) - x1).length();
                        dx = dx.max((d - ulps).max(0.0) / size);
                        // Saturated densities (f32 at 1e-30: about 1e90)
                        // saturate alike.
                        if s.pdf == f32::MAX {
                            assert_eq!(pdf[i], f32::MAX, "g {g}, 2^{scale}: {u:?}");
                        } else if s.pdf < f32::MIN_POSITIVE {
                            // Subnormal (2^40: s⁻³ ≈ 1e-36 times a small
                            // density): a few of their ulps, 2⁻¹⁴⁹ each.
                            let ulp = f32::from_bits(1);
                            assert!((pdf[i] - s.pdf).abs() <= 16.0 * ulp, "2^{scale}: {u:?}");
                        } else {
                            dp = dp.max((pdf[i] as f64 / s.pdf as f64 - 1.0).abs());
                        }
                        dw = dw.max((weight[i] as f64 / s.weight as f64 - 1.0).abs());
                    }
                    None => assert!(pdf[i] == 0.0 && weight[i] == 0.0, "g {g}: {u:?}"),
                }
            }
            std::println!(
                "2^{scale}, g {g}: {count} of {m} lanes, x1 {dx:.1e}, pdf {dp:.1e}, weight {dw:.1e}"
            );
            assert_eq!(count, expected, "g {g}, 2^{scale}");
            // Measured ≤ 2.8e-7, 2.1e-6 and 5.4e-7.
            assert!(
                dx < 1e-6 && dp < 5e-6 && dw < 1e-6,
                "g {g}: {dx:e} {dp:e} {dw:e}"
            );
        }
    }

    #[test]
    fn mismatched_lengths_are_refused() {
        let c = Connection::new(Vec3::ZERO, Vec3::Z, 1.0).unwrap();
        let omnee = Omnee::new(c, HenyeyGreenstein::new(0.5).unwrap());
        let (a, b) = ([0.5f32; 3], [0.5f32; 2]);
        let (mut x, mut y, mut z, mut p, mut w) =
            ([0.0f32; 3], [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        let r = omnee.sample_batch(
            Uniforms {
                u0: &a,
                u1: &b,
                u2: &a,
            },
            Vertices {
                x: &mut x,
                y: &mut y,
                z: &mut z,
                pdf: &mut p,
                weight: &mut w,
            },
        );
        match r {
            Err(Error::Arrays { field, .. }) => assert_eq!(field, "batch"),
            other => panic!("{other:?}"),
        }
    }
}
