//! Tabulated inverse CDFs: any phase function sampled at the cost of a
//! table lookup and a cubic, with the table's own density carried into the
//! estimate so that nothing is biased (docs/math.md §11).
//!
//! [`InverseCdf`] tabulates `u ↦ θ` on [`INVERSE_CDF_BINS`] equal-probability
//! bins: a power law in the first bin (where a forward peak like
//! Fournier–Forand's is singular) and a monotone cubic Hermite polynomial in
//! `1 ∓ cos θ` in every other. The table defines its own distribution `q`,
//! whose density it knows exactly at every point it returns; [`TableSampled`]
//! draws θ from `q` and reports `q` as its `pdf` and `p/q` as the ratio an
//! estimator multiplies in ([`PhaseFunction::sample_ratio`]), so an estimate
//! stays unbiased however far `q` is from `p` (it only has to be positive
//! where `p` is). Built once per medium in fixed-size storage, no allocation.

use super::invert::invert_cdf;
use super::{Deflection, PhaseFunction};
use crate::error::Error;
use crate::real::{Real, exp_for, ln_for};

/// The number of equal-probability bins of an [`InverseCdf`]. 128 bins keep
/// the table's cubics within 2 KiB in f32 and the table's density within 1e-4 of the
/// phase function's for every phase function of this crate but the first
/// bin of singular peaks (docs/math.md §11 has the measured deviations).
pub const INVERSE_CDF_BINS: usize = 128;

const N: usize = INVERSE_CDF_BINS;

/// Smallest exponent of the first bin's power law `x ∝ u^{1/a}` (a steeper
/// peak is sampled with this one; the ratio `p/q` absorbs the difference).
const HEAD_A_MIN: f64 = 0.01;

/// The inverse CDF `u ↦ θ` of a phase function on [`INVERSE_CDF_BINS`] bins
/// of equal probability `1/N`, `u ∈ [k/N, (k + 1)/N)`, `t = N u − k ∈ [0, 1)`:
///
/// - bin 0: `1 − cos θ = x₁ t^{1/a}`, a power law through the first node
///   `x₁ = 1 − cos θ(1/N)` whose exponent matches the phase function's
///   density there, `a = 2π p(θ₁) x₁ N` clamped to `[0.01, 1]` (a = 1 for a
///   finite density at θ = 0; Fournier–Forand's `p ∝ x^{a − 1}` peak is
///   followed exactly);
/// - bin k ≥ 1: `v(t) = c0 + c1 t + c2 t² + c3 t³`, the cubic Hermite
///   interpolant of the nodes `v(k/N)`, `v((k+1)/N)` and their slopes
///   `dv/du = ±1/(2π p)`, made monotone (slopes blended towards the secant
///   where they would let `v'` vanish), with `v = 1 − cos θ` for the bins
///   before θ = π/2 and `v = 1 + cos θ` from there on and in the last bin,
///   so that each versine is accurate where it is small.
///
/// The table's density is known exactly wherever it samples:
/// `q = 1 / (2π |dv/du|) = 1 / (2π N |v'(t)|)` per steradian
/// (`dω = 2π d(1 − cos θ)`), and in bin 0
/// `q = 1 / (2π N x₁ t^{1/a − 1} / a)`. It is positive on all of (0, π), so
/// `p/q` importance-weights any integrand of `p` without bias.
///
/// The ratio `p/q` that an estimate multiplies in is, in every bin where
/// that is as exact as evaluating it, a polynomial `r_k(t)` of degree 6
/// fitted when the table is built (`RatioFit`), so that a draw from the
/// table costs no evaluation of `p` there (docs/math.md §11.4).
///
/// Size: `11 N + 2` values of `F`, an index, two 128-bit masks (fitted,
/// split) and a 64-bit fingerprint of `p`: 5696 bytes in f32, 11344 in f64
/// (`core::mem::size_of::<InverseCdf<f32>>()`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InverseCdf<F> {
    /// `(c0, c1, c2, c3)` of each bin's cubic; bin 0's is unused.
    cubic: [[F; 4]; N],
    /// `p/q` in each bin as a polynomial in `t`, where fitted.
    ratio: RatioFit<F>,
    /// The first bin written in `1 + cos θ`; the bins before it are in
    /// `1 − cos θ`. At most `N − 1` (the last bin is always backward).
    backward: usize,
    /// `x₁`, the end of the first bin.
    head_x: F,
    /// `1/a`, the first bin's exponent.
    head_exponent: F,
}

impl<F: Real> InverseCdf<F> {
    /// The table of `phase`, built from its `cdf` (inverted by safeguarded
    /// Newton iteration in f64 at the nodes `u = k/N`) and its `eval` (the
    /// slopes). Fails (field `"phase"`) if the phase function's cdf or density
    /// is not finite and positive where the table needs it.
    pub fn new<P: PhaseFunction<F> + ?Sized>(phase: &P) -> Result<Self, Error> {
        let bad = |reason| Error::Degenerate {
            field: "phase",
            reason,
        };
        let at = |x: f64, y: f64| Deflection::from_versines(F::from_f64(x), F::from_f64(y));
        let cdf = |x: f64, y: f64| phase.cdf(at(x, y)).to_f64();
        let tau = core::f64::consts::TAU;
        let density = |x: f64, y: f64| tau * phase.eval(at(x, y)).to_f64();
        // Nodes: the versines (x, y) at u = k/N, and 2π p there.
        let mut x = [0.0f64; N + 1];
        let mut y = [0.0f64; N + 1];
        let mut dens = [0.0f64; N + 1];
        (x[0], y[0]) = (0.0, 2.0);
        (x[N], y[N]) = (2.0, 0.0);
        for k in 1..N {
            let u = k as f64 / N as f64;
            (x[k], y[k]) = invert_cdf(u, -1.0, cdf, |x, y| 1.0 - cdf(x, y), density);
            // Equal nodes (below the precision's resolution) make an empty
            // bin, which the ratio p/q = 0 there keeps unbiased.
            if !(x[k] >= x[k - 1]) {
                return Err(bad("its cdf is not a distribution function"));
            }
        }
        for k in 1..=N {
            dens[k] = density(x[k], y[k]);
            if !(dens[k] > 0.0 && dens[k].is_finite()) {
                return Err(bad("its density is not finite and positive"));
            }
        }
        // Bins from `backward` on are written in y = 1 + cos θ.
        let backward = (1..N - 1).find(|&k| x[k] >= 1.0).unwrap_or(N - 1);
        let mut cubic = [[F::ZERO; 4]; N];
        for (k, c) in cubic.iter_mut().enumerate().skip(1) {
            // v and dv/dt at both ends (dv/du = ±1/(2π p), dt = N du).
            let (v0, v1, sign) = if k < backward {
                (x[k], x[k + 1], 1.0)
            } else {
                (y[k], y[k + 1], -1.0)
            };
            let m0 = sign / (N as f64 * dens[k]);
            let m1 = sign / (N as f64 * dens[k + 1]);
            *c = hermite(v0, v1, m0, m1).map(F::from_f64);
        }
        let head_x = x[1];
        let a = (dens[1] * head_x * N as f64).clamp_to(HEAD_A_MIN, 1.0);
        let mut table = Self {
            cubic,
            ratio: RatioFit::NONE,
            backward,
            head_x: F::from_f64(head_x),
            head_exponent: F::from_f64(1.0 / a),
        };
        table.ratio = RatioFit::new(&table, phase);
        Ok(table)
    }

    /// FNV-1a over the bits of `p(θ)` at the check points of every bin
    /// (`t = i/32`, see `RatioFit`): equal for the phase function a
    /// table's ratio fits were made from.
    fn fingerprint<P: PhaseFunction<F> + ?Sized>(&self, p: &P) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        for k in 0..N {
            for i in 0..=RATIO_CHECKS {
                let (d, _) = self.at(k, check_point(i));
                for byte in p.eval(d).to_f64().to_bits().to_le_bytes() {
                    hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
                }
            }
        }
        hash
    }

    /// The number of bins whose ratio `p/q` is a fitted polynomial (see
    /// [`InverseCdf`]; docs/math.md §11.4 has the counts): at most `N − 1`
    /// (bin 0 evaluates `p`).
    pub fn fitted_bins(&self) -> usize {
        self.ratio.fitted.count_ones() as usize
    }

    /// A deflection from the table's distribution `q`, and `1/q` there
    /// (`2π N |v'(t)|`, see [`InverseCdf`]); `u` is clamped to `[0, 1]`.
    #[inline]
    pub fn sample_inverse_pdf(&self, u: F) -> (Deflection<F>, F) {
        let (k, t) = bin_of(u);
        self.at(k, t)
    }

    /// [`sample_inverse_pdf`](Self::sample_inverse_pdf) and the ratio
    /// `p/q` at the deflection: bin `k`'s fitted polynomial `r_k(t)` where
    /// `fitted` (the caller has checked that the fits are `p`'s, see
    /// [`TableSampled::new`]) and the bin has one, else `p(θ) · (1/q)` with
    /// `p` evaluated by `eval`.
    #[inline]
    fn sample_ratio(
        &self,
        u: F,
        fitted: bool,
        eval: impl FnOnce(Deflection<F>) -> F,
    ) -> (Deflection<F>, F, F) {
        let (k, t) = bin_of(u);
        let (d, inverse_pdf) = self.at(k, t);
        let ratio = if fitted && self.ratio.has(k) {
            self.ratio.eval(k, t)
        } else {
            eval(d) * inverse_pdf
        };
        (d, inverse_pdf, ratio)
    }

    /// The deflection at `t ∈ [0, 1]` in bin `k` and `1/q` there. Always
    /// inlined: as a call it made the sampler spill its live registers.
    #[inline(always)]
    fn at(&self, k: usize, t: F) -> (Deflection<F>, F) {
        let two_pi_n = F::TAU * F::from_f64(N as f64);
        if k == 0 {
            // x = x₁ t^e: dx/du = N x₁ e t^{e − 1} (e ≥ 1), the power as
            // e^{(e − 1) ln t} by the precision's inline kernels (a call to
            // powf would make the whole sampler spill its registers).
            let e = self.head_exponent;
            let r = if t > F::ZERO {
                let ln_t = ln_for::<F>(t.to_f64());
                F::from_f64(exp_for::<F>((e - F::ONE).to_f64() * ln_t))
            } else if e > F::ONE {
                F::ZERO
            } else {
                F::ONE
            };
            let x = self.head_x * t * r;
            let inverse_pdf = two_pi_n * self.head_x * e * r;
            return (Deflection::from_one_minus_cos(x), inverse_pdf);
        }
        let [c0, c1, c2, c3] = self.cubic[k];
        // Estrin's scheme: (c0 + c1 t) + t² (c2 + c3 t).
        let t2 = t * t;
        let v = (c0 + c1 * t) + t2 * (c2 + c3 * t);
        let slope = (c1 + F::TWO * c2 * t) + F::from_f64(3.0) * c3 * t2;
        // (v, 2 − v) before θ = π/2, (2 − v, v) after, blended with exact
        // 0/1 weights: a branch here is mispredicted for symmetric functions.
        let w = if k < self.backward { F::ZERO } else { F::ONE };
        let (omc, opc) = (
            v * (F::ONE - w) + (F::TWO - v) * w,
            (F::TWO - v) * (F::ONE - w) + v * w,
        );
        (Deflection::from_versines(omc, opc), two_pi_n * slope.abs())
    }

    /// A deflection from the table's distribution (the inverse CDF).
    #[inline]
    pub fn sample(&self, u: F) -> Deflection<F> {
        self.sample_inverse_pdf(u).0
    }

    /// The bin and `t` of the table's `u` at `d` (the inverse of `sample`):
    /// the bin by binary search over its nodes, `t` by safeguarded Newton
    /// iteration on the bin's cubic in f64.
    fn locate(&self, d: Deflection<F>) -> (usize, f64) {
        let (omc, opc) = (d.one_minus_cos.to_f64(), d.one_plus_cos.to_f64());
        let node = |k: usize| self.cubic[k][0].to_f64();
        let b = self.backward;
        if opc > node(b) {
            // Before the first backward bin: x = 1 − cos θ increases.
            let head_x = self.head_x.to_f64();
            if omc < head_x || b == 1 {
                let a = 1.0 / self.head_exponent.to_f64();
                return (0, libm::pow((omc / head_x).max(0.0), a));
            }
            // The last k in [1, b) with x_k ≤ omc.
            let k = 1 + self.cubic[1..b].partition_point(|c| c[0].to_f64() <= omc) - 1;
            let end = if k + 1 < b {
                node(k + 1)
            } else {
                2.0 - node(b)
            };
            (k, self.solve(k, omc, end))
        } else {
            // y = 1 + cos θ decreases; the last k in [b, N) with y_k ≥ opc.
            let k = b + self.cubic[b..].partition_point(|c| c[0].to_f64() >= opc) - 1;
            let k = k.max(b);
            let end = if k + 1 < N { node(k + 1) } else { 0.0 };
            (k, self.solve(k, opc, end))
        }
    }

    /// The `t ∈ [0, 1]` with `v_k(t) = target` on bin `k`'s monotone cubic
    /// from `v_k(0)` to `end`.
    fn solve(&self, k: usize, target: f64, end: f64) -> f64 {
        let [c0, c1, c2, c3] = self.cubic[k].map(|c| c.to_f64());
        let increasing = end > c0;
        let f = |t: f64| c0 + t * (c1 + t * (c2 + t * c3)) - target;
        let df = |t: f64| c1 + t * (2.0 * c2 + 3.0 * t * c3);
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let mut t = ((target - c0) / (end - c0)).clamp_to(0.0, 1.0);
        for _ in 0..60 {
            let r = f(t);
            if r == 0.0 {
                return t;
            }
            if (r < 0.0) == increasing {
                lo = t;
            } else {
                hi = t;
            }
            let mut next = t - r / df(t);
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - t).abs() <= 4.0 * f64::EPSILON {
                return next;
            }
            t = next;
        }
        t
    }

    /// The table's density `q(θ)` per steradian at `d`: `1/(2π N |v'(t)|)`
    /// at the `t` that [`sample`](Self::sample) maps to `d` (see
    /// [`InverseCdf`]).
    pub fn pdf(&self, d: Deflection<F>) -> F {
        let (k, t) = self.locate(d);
        let two_pi_n = core::f64::consts::TAU * N as f64;
        let inverse = if k == 0 {
            let e = self.head_exponent.to_f64();
            two_pi_n * self.head_x.to_f64() * e * libm::pow(t, e - 1.0)
        } else {
            let [_, c1, c2, c3] = self.cubic[k].map(|c| c.to_f64());
            two_pi_n * (c1 + t * (2.0 * c2 + 3.0 * t * c3)).abs()
        };
        F::from_f64(1.0 / inverse).min(F::MAX)
    }

    /// The table's CDF at `d`, the `u` with `sample(u) = d`: `(k + t)/N`.
    pub fn invert(&self, d: Deflection<F>) -> F {
        let (k, t) = self.locate(d);
        F::from_f64((k as f64 + t) / N as f64).min(F::ONE)
    }
}

/// The bin `k = ⌊N u⌋` and `t = N u − k ∈ [0, 1]` of `u` (clamped to
/// `[0, 1]`; `u = 1` is `t = 1` in the last bin).
#[inline]
fn bin_of<F: Real>(u: F) -> (usize, F) {
    let n = F::from_f64(N as f64);
    let s = u.clamp_to(F::ZERO, F::ONE) * n;
    // The bin k = ⌊s⌋ for the load (i32: x86-64 has no unsigned
    // conversion), and t = s − ⌊s⌋ in floating point beside it, with ⌊s⌋
    // by the round-to-integer constant (s < 2²²): the conversions are
    // off the way from u to θ.
    let k = (s.to_f64() as i32).min(N as i32 - 1) as usize;
    let to_int = F::from_f64(1.5) / F::EPSILON;
    let nearest = (s + to_int) - to_int;
    let floor = if nearest > s {
        nearest - F::ONE
    } else {
        nearest
    };
    (k, (s - floor.min(n - F::ONE)).min(F::ONE))
}

/// Coefficients of each bin's polynomial of the ratio `p/q`: degree 6.
const RATIO_TERMS: usize = 7;

/// Points per bin at which a fit is checked, `t = i/RATIO_CHECKS` for
/// `i = 0, …, RATIO_CHECKS`.
const RATIO_CHECKS: usize = 32;

/// A fit is accepted where it is within this many `ε` of the precision
/// (relative) of the ratio as evaluated.
const RATIO_TOLERANCE: f64 = 4.0;

/// The ratio `r = p/q = p(θ(t)) · 2πN |v'(t)|` of a table's phase function
/// to the table's density, as a polynomial in each bin's `t` where that is
/// as exact as evaluating it (docs/math.md §11.4):
///
/// `r_k(t) = Σ_{m=0}^{6} a_m t^m` (evaluated in Estrin's scheme), the
/// polynomial through `r` at the Chebyshev points
/// `t_j = (1 − cos((2j + 1)π/14))/2`, `j = 0, …, 6`, kept for bin `k` if
/// at every check point `t = i/32`, `i = 0, …, 32`, it differs from
/// `p(θ) · (1/q)` (computed in `F`, as the fallback computes it) by at
/// most `4 ε r`. A bin where that fails and `p` jumps once (a measured
/// table's bin edge) gets two quadratics instead, `r` being
/// `p_j · 2πN|v'(t)|` with `v'` quadratic on each side of the jump: the
/// jump is bisected, on `F`'s grid of `t`, between the two check points
/// that differ most to `t_s`, the first `t` of its upper side, and each
/// side is interpolated at its three Chebyshev points; the same check, at
/// the check points and at both sides of `t_s`, decides. Bin 0 (the power
/// law) never has a fit. In f32 the smooth phase functions pass in all but
/// a few bins next to a singular peak or at the backward end (FF 125 of
/// 128, Mie 119, Rayleigh 127; a measured table of 64 bins 123); in f64 the
/// 4 ε of f64 is reached only where `r` is nearly a polynomial (Rayleigh,
/// part of Draine, measured tables), and every other bin evaluates `p`.
///
/// `fingerprint` hashes `p`'s values (their bits) at all check points of
/// all bins: [`TableSampled::new`] uses the fits only for a phase function
/// that reproduces every one of them.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RatioFit<F> {
    /// `(a₀, …, a₆)` or `(l₀, l₁, l₂, h₀, h₁, h₂, t_s)` per bin; unused
    /// where the bin's bit is clear.
    coefficients: [[F; RATIO_TERMS]; N],
    /// Bit `k`: bin `k` has a fit.
    fitted: u128,
    /// Bit `k`: bin `k`'s fit is two quadratics about a jump.
    split: u128,
    /// FNV-1a of `p` at the check points ([`InverseCdf::fingerprint`]).
    fingerprint: u64,
}

const _: () = assert!(N <= 128, "RatioFit's mask has 128 bits");

impl<F: Real> RatioFit<F> {
    /// No bin fitted.
    const NONE: Self = Self {
        coefficients: [[F::ZERO; RATIO_TERMS]; N],
        fitted: 0,
        split: 0,
        fingerprint: 0,
    };

    /// Whether bin `k` has a fit.
    #[inline]
    fn has(&self, k: usize) -> bool {
        (self.fitted >> k) & 1 == 1
    }

    /// `r_k(t)`, bin `k`'s fit at `t`.
    #[inline]
    fn eval(&self, k: usize, t: F) -> F {
        eval_fit(&self.coefficients[k], (self.split >> k) & 1 == 1, t)
    }

    /// The fits of `p/q` for `table` (whose `ratio` is ignored): each bin's
    /// polynomial, or its two quadratics about a jump, kept where its check
    /// passes.
    fn new<P: PhaseFunction<F> + ?Sized>(table: &InverseCdf<F>, p: &P) -> Self {
        let mut fit = Self::NONE;
        let tolerance = RATIO_TOLERANCE * F::EPSILON.to_f64();
        let nodes = chebyshev::<F, RATIO_TERMS>(0.0, 1.0);
        for k in 1..N {
            let r = |t: F| {
                let (d, inverse_pdf) = table.at(k, t);
                (p.eval(d) * inverse_pdf).to_f64()
            };
            let checks: [f64; RATIO_CHECKS + 1] = core::array::from_fn(|i| r(check_point(i)));
            if checks.iter().any(|r| !r.is_finite()) {
                continue;
            }
            // Whether `c` reproduces r at the check points and at `extra`.
            let passes = |c: &[F; RATIO_TERMS], split: bool, extra: &[F]| {
                let close = |t: F, want: f64| {
                    let got = eval_fit(c, split, t).to_f64();
                    (got - want).abs() <= tolerance * want.abs()
                };
                (0..=RATIO_CHECKS).all(|i| close(check_point(i), checks[i]))
                    && extra.iter().all(|&t| close(t, r(t)))
            };
            let smooth = interpolate(nodes, nodes.map(|t| r(F::from_f64(t)))).map(F::from_f64);
            if passes(&smooth, false, &[]) {
                fit.coefficients[k] = smooth;
                fit.fitted |= 1 << k;
                continue;
            }
            let (lo, hi) = jump(&r, &checks);
            let below = chebyshev::<F, 3>(0.0, lo.to_f64());
            let above = chebyshev::<F, 3>(hi.to_f64(), 1.0);
            let [l0, l1, l2] = interpolate(below, below.map(|t| r(F::from_f64(t))));
            let [h0, h1, h2] = interpolate(above, above.map(|t| r(F::from_f64(t))));
            let split = [l0, l1, l2, h0, h1, h2, hi.to_f64()].map(F::from_f64);
            if passes(&split, true, &[lo, hi]) {
                fit.coefficients[k] = split;
                fit.fitted |= 1 << k;
                fit.split |= 1 << k;
            }
        }
        if fit.fitted != 0 {
            fit.fingerprint = table.fingerprint(p);
        }
        fit
    }
}

/// The check point `t = i/RATIO_CHECKS` of a bin, in `F`.
#[inline]
fn check_point<F: Real>(i: usize) -> F {
    F::from_f64(i as f64 / RATIO_CHECKS as f64)
}

/// Where a bin's ratio `r` jumps, on `F`'s grid of `t`: between the two
/// check points whose values `checks` differ most, bisected (each step
/// keeps the side whose end value `r` is closer to) down to adjacent grid
/// points `(lo, hi)`, the last `t` below the jump and the first above.
fn jump<F: Real>(r: &impl Fn(F) -> f64, checks: &[f64; RATIO_CHECKS + 1]) -> (F, F) {
    let step = |i: usize| (checks[i + 1] - checks[i]).abs();
    let i = (0..RATIO_CHECKS)
        .max_by(|&a, &b| step(a).total_cmp(&step(b)))
        .unwrap_or(0);
    let (mut lo, mut hi) = (check_point::<F>(i), check_point::<F>(i + 1));
    let (r_lo, r_hi) = (checks[i], checks[i + 1]);
    loop {
        let mid = F::from_f64(0.5 * (lo.to_f64() + hi.to_f64()));
        if mid == lo || mid == hi {
            return (lo, hi);
        }
        let r_mid = r(mid);
        if (r_mid - r_lo).abs() <= (r_mid - r_hi).abs() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

/// A bin's fit at `t`: `Σ_{m=0}^{6} a_m t^m` in Estrin's scheme, or, for a
/// `split` bin with coefficients `(l₀, l₁, l₂, h₀, h₁, h₂, t_s)`,
/// `l₀ + l₁t + l₂t²` below `t_s` and `h₀ + h₁t + h₂t²` from it on.
#[inline]
fn eval_fit<F: Real>(c: &[F; RATIO_TERMS], split: bool, t: F) -> F {
    let [a0, a1, a2, a3, a4, a5, a6] = *c;
    if split {
        let (b0, b1, b2) = if t < a6 { (a0, a1, a2) } else { (a3, a4, a5) };
        return b0 + t * (b1 + t * b2);
    }
    let t2 = t * t;
    (a0 + a1 * t) + t2 * (a2 + a3 * t) + (t2 * t2) * ((a4 + a5 * t) + t2 * a6)
}

/// The `M` Chebyshev points of `[a, b]`,
/// `a + (b − a)(1 − cos((2j + 1)π/2M))/2`, rounded to `F`.
fn chebyshev<F: Real, const M: usize>(a: f64, b: f64) -> [f64; M] {
    core::array::from_fn(|j| {
        let angle = (2 * j + 1) as f64 * core::f64::consts::PI / (2 * M) as f64;
        F::from_f64(a + (b - a) * 0.5 * (1.0 - libm::cos(angle))).to_f64()
    })
}

/// The monomial coefficients `(a₀, …, a_{M−1})` of the polynomial through
/// `(t_j, r_j)`: Newton's divided differences, then the Newton form
/// `a₀' + (t − t₀)(a₁' + (t − t₁)(…))` expanded from the inside out.
fn interpolate<const M: usize>(t: [f64; M], r: [f64; M]) -> [f64; M] {
    let mut d = r;
    for level in 1..M {
        for j in (level..M).rev() {
            d[j] = (d[j] - d[j - 1]) / (t[j] - t[j - level]);
        }
    }
    let mut a = [0.0; M];
    a[0] = d[M - 1];
    for j in (0..M - 1).rev() {
        // a ← a · (t − t_j) + d_j.
        for m in (1..M).rev() {
            a[m] = a[m - 1] - t[j] * a[m];
        }
        a[0] = d[j] - t[j] * a[0];
    }
    a
}

/// `(c0, c1, c2, c3)` of the cubic `v(t)` on `[0, 1]` with `v(0) = v0`,
/// `v(1) = v1`, `v'(0) = m0`, `v'(1) = m1` (Hermite), after making the slopes
/// monotone: with `Δ = v1 − v0`, `α = m0/Δ`, `β = m1/Δ`,
/// `v'(t)/Δ = 6t(1 − t) + α(1 − 4t + 3t²) + β(3t² − 2t)`; the slopes are
/// blended towards the secant `(α, β) = (1, 1)` (where `v' = Δ`) until that
/// quadratic stays above 1/10 on `[0, 1]`, so `v` is strictly monotone and
/// the table's density `∝ 1/|v'|` finite.
fn hermite(v0: f64, v1: f64, m0: f64, m1: f64) -> [f64; 4] {
    let delta = v1 - v0;
    let (mut a, mut b) = (m0 / delta, m1 / delta);
    if !(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0) {
        (a, b) = (1.0, 1.0);
    }
    let min_slope = |a: f64, b: f64| {
        let at = |t: f64| {
            6.0 * t * (1.0 - t) + a * (1.0 - 4.0 * t + 3.0 * t * t) + b * t * (3.0 * t - 2.0)
        };
        // The quadratic's vertex, where its derivative vanishes.
        let den = 12.0 - 6.0 * a - 6.0 * b;
        let vertex = (6.0 - 4.0 * a - 2.0 * b) / den;
        let inner = if den != 0.0 && vertex > 0.0 && vertex < 1.0 {
            at(vertex)
        } else {
            f64::INFINITY
        };
        a.min(b).min(inner)
    };
    let (a0, b0) = (a, b);
    for step in 1..=8 {
        if min_slope(a, b) >= 0.1 {
            break;
        }
        let lambda = step as f64 / 8.0;
        a = (1.0 - lambda) * a0 + lambda;
        b = (1.0 - lambda) * b0 + lambda;
    }
    let (m0, m1) = (a * delta, b * delta);
    [v0, m0, 3.0 * delta - 2.0 * m0 - m1, m0 + m1 - 2.0 * delta]
}

/// A phase function `p` drawn from its [`InverseCdf`] `q`: `eval`, `cdf`,
/// the mean cosine and the backscatter fraction are `p`'s own; `sample`,
/// `pdf` and `invert` are the table's, and
/// [`sample_ratio`](PhaseFunction::sample_ratio) returns the factor
/// `p(θ)/q(θ)` that makes every estimate with it unbiased (OMNEE's weight
/// becomes `(p/q) θ/(s sin θ)`): the table's fitted polynomial in the bins
/// where it has one for this `p` ([`InverseCdf`], docs/math.md §11.4),
/// `p` evaluated elsewhere. Borrows the table, so it is `Copy` and as small
/// as `p` plus a reference and a flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableSampled<'t, F, P> {
    phase: P,
    table: &'t InverseCdf<F>,
    /// Whether the table's ratio fits were made for `phase`.
    fitted: bool,
}

impl<'t, F: Real, P: PhaseFunction<F>> TableSampled<'t, F, P> {
    /// `phase` sampled through `table` (which should be
    /// `InverseCdf::new(&phase)`; any table gives unbiased estimates, a
    /// table of another function only a worse variance).
    ///
    /// The table's fits of `p/q` are used only if `phase` reproduces, bit
    /// for bit, the values they were made from at every check point (the
    /// table's fingerprint, `33 N` evaluations of `p` here, once); for any
    /// other phase function the ratio is `p · (1/q)` with `p` evaluated.
    pub fn new(phase: P, table: &'t InverseCdf<F>) -> Self {
        let fitted =
            table.ratio.fitted != 0 && table.fingerprint(&phase) == table.ratio.fingerprint;
        Self {
            phase,
            table,
            fitted,
        }
    }

    /// The phase function `p`.
    #[inline]
    pub fn phase(&self) -> &P {
        &self.phase
    }

    /// Its table `q`.
    #[inline]
    pub fn table(&self) -> &'t InverseCdf<F> {
        self.table
    }

    /// Whether the ratio `p/q` comes from the table's fits where it has
    /// them (the table was built from this `p`; see [`new`](Self::new)).
    #[inline]
    pub fn uses_fits(&self) -> bool {
        self.fitted
    }
}

impl<F: Real, P: PhaseFunction<F>> PhaseFunction<F> for TableSampled<'_, F, P> {
    /// `p(θ)`, the phase function's own value.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        self.phase.eval(d)
    }

    /// θ from the table's distribution `q`.
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        self.table.sample(u)
    }

    /// `P(Θ ≤ θ)` of the phase function itself (not of the table).
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        self.phase.cdf(d)
    }

    /// The phase function's mean cosine.
    #[inline]
    fn mean_cosine(&self) -> F {
        self.phase.mean_cosine()
    }

    /// `q(θ)`, the table's density: what `sample` draws with.
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        self.table.pdf(d)
    }

    /// `(d, q(d))` from the table.
    #[inline]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        let (d, inverse_pdf) = self.table.sample_inverse_pdf(u);
        (d, (F::ONE / inverse_pdf).min(F::MAX))
    }

    /// `(d, q(d), p(d)/q(d))`: the ratio from the table's fit of it, or
    /// as `p · (1/q)` without a division.
    #[inline]
    fn sample_ratio(&self, u: F) -> (Deflection<F>, F, F) {
        let (d, inverse_pdf, ratio) = self
            .table
            .sample_ratio(u, self.fitted, |d| self.phase.eval(d));
        (d, (F::ONE / inverse_pdf).min(F::MAX), ratio.min(F::MAX))
    }

    /// `false`: the table's `q` is not `p`.
    #[inline]
    fn samples_exactly(&self) -> bool {
        false
    }

    /// The table's CDF at `d` (the inverse of `sample`).
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        Some(self.table.invert(d))
    }

    /// The phase function's backscatter fraction.
    #[inline]
    fn backscatter_fraction(&self) -> F {
        self.phase.backscatter_fraction()
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::super::testing::report;
    use super::super::{
        Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Rayleigh, TwoTermHg,
    };
    use super::*;

    /// Per table: (max |q/p − 1| outside bin 0, relative variance of p/q,
    /// mean of p/q over stratified u minus 1).
    fn quality<F: Real, P: PhaseFunction<F>>(p: &P, table: &InverseCdf<F>) -> (f64, f64, f64) {
        let m = 1 << 17;
        let (mut dev, mut sum, mut sum2) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..m {
            let u = F::from_f64((i as f64 + 0.5) / m as f64);
            let (d, inverse_pdf) = table.sample_inverse_pdf(u);
            let ratio = p.eval(d).to_f64() * inverse_pdf.to_f64();
            sum += ratio;
            sum2 += ratio * ratio;
            if u.to_f64() >= 1.0 / N as f64 {
                dev = dev.max((1.0 / ratio - 1.0).abs());
            }
        }
        let mean = sum / m as f64;
        (dev, sum2 / m as f64 / (mean * mean) - 1.0, mean - 1.0)
    }

    fn check<F: Real, P: PhaseFunction<F>>(name: &str, p: &P) {
        let table = InverseCdf::new(p).unwrap();
        let (dev, var, bias) = quality(p, &table);
        std::println!(
            "{name} ({}): max |q/p - 1| {dev:.1e}, var(p/q) {var:.1e}, mean(p/q) - 1 {bias:.1e}",
            core::any::type_name::<F>()
        );
        // Round trip and the density at the returned point.
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..2000 {
            let u = F::from_f64((i as f64 + 0.37) / 2000.0);
            let (d, inverse_pdf) = table.sample_inverse_pdf(u);
            let back = table.invert(d).to_f64();
            worst.0 = worst.0.max((back - u.to_f64()).abs());
            let q = table.pdf(d).to_f64();
            worst.1 = worst.1.max((q * inverse_pdf.to_f64() - 1.0).abs());
        }
        std::println!("  invert error {:.1e}, pdf error {:.1e}", worst.0, worst.1);
    }

    #[test]
    fn tables_of_the_phase_functions() {
        check::<f64, _>("hg 0.9", &HenyeyGreenstein::new(0.9).unwrap());
        check::<f64, _>("ff", &FournierForand::new(0.0183, 1.10).unwrap());
        check::<f32, _>("ff", &FournierForand::new(0.0183f32, 1.10).unwrap());
        check::<f64, _>("draine", &Draine::new(0.6, 1.0).unwrap());
        check::<f64, _>("draine 22", &Draine::new(0.5557, 22.0).unwrap());
        check::<f64, _>("mie 10", &Mie::new(10.0).unwrap());
        check::<f32, _>("mie 10", &Mie::new(10.0f32).unwrap());
        check::<f64, _>("rayleigh", &Rayleigh);
        check::<f64, _>("iso", &Isotropic);
        check::<f64, _>("tthg", &TwoTermHg::two_term(0.99, -0.44, 0.96).unwrap());
        // A measured table: FF averaged over 64 bins (log-spaced to 10°).
        let ff = FournierForand::<f64>::new(0.0183, 1.10).unwrap();
        let mut edges = std::vec![0.0f64];
        edges.extend((0..33).map(|i| (0.1f64 * libm::pow(100.0, i as f64 / 32.0)).to_radians()));
        edges.extend((1..=31).map(|i| (10.0 + 170.0 * i as f64 / 31.0).to_radians()));
        *edges.last_mut().unwrap() = core::f64::consts::PI;
        let values: std::vec::Vec<f64> = edges
            .windows(2)
            .map(|w| {
                let (a, b) = (Deflection::from_theta(w[0]), Deflection::from_theta(w[1]));
                (ff.cdf(b) - ff.cdf(a)) / (b.one_minus_cos - a.one_minus_cos)
            })
            .collect();
        let mut cdf = std::vec![0.0; edges.len()];
        let measured = super::super::Tabulated::new(&edges, &values, &mut cdf).unwrap();
        check::<f64, _>("measured", &measured);
        report(
            "size of InverseCdf<f32>",
            core::mem::size_of::<InverseCdf<f32>>() as f64,
        );
    }
}
