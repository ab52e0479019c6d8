//! A measured phase function: a caller-owned table of bins, constant per solid
//! angle within each bin.

use super::{Deflection, PhaseFunction};
use crate::error::Error;
use crate::real::Real;
use core::f64::consts::{PI, TAU};

/// A tabulated phase function over `n ≥ 1` bins `[θ_i, θ_{i+1})` with
/// `θ_0 = 0 < θ_1 < … < θ_n = π`, density constant per solid angle in each bin:
///
/// `p(θ) = v_i / (2π Σ_j v_j Δx_j)` for `θ ∈ [θ_i, θ_{i+1})`,
/// `Δx_j = cos θ_j − cos θ_{j+1} = 2 sin((θ_{j+1} − θ_j)/2) sin((θ_{j+1} + θ_j)/2)`.
///
/// The values `v_i` are unnormalised. The table borrows everything from the
/// caller (no allocation); the constructor fills the caller's `cdf` buffer,
/// `cdf[i] = P(Θ < θ_i)`, accumulated in f64.
///
/// `cdf` and `sample` are exact inverses: in bin `k`,
/// `P(Θ ≤ θ) = cdf[k] + (cdf[k+1] − cdf[k]) · (x(θ) − x_k)/Δx_k` with
/// `x = 1 − cos θ`, i.e. uniform in solid angle within the bin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tabulated<'a, F> {
    theta: &'a [F],
    values: &'a [F],
    cdf: &'a [F],
    /// `1/(2π Σ v_j Δx_j)`.
    density_scale: F,
    mean: F,
}

impl<'a, F: Real> Tabulated<'a, F> {
    /// A table from `n + 1` bin edges `theta` (field `"theta"`: finite,
    /// strictly increasing, `θ_0 = 0`, `θ_n = π` up to 4 ulps of the
    /// precision's π), `n ≥ 1` bin values `values` (field `"values"`: finite,
    /// ≥ 0, not all 0, with a finite total mass `Σ v_i Δx_i` in f64) and a
    /// buffer `cdf` of `n + 1` entries (field `"cdf"`) that receives the
    /// cumulative distribution.
    ///
    /// Errors: lengths that disagree, misplaced or unordered edges and
    /// values all 0 are `Table`; a NaN or infinite edge or value is
    /// `NotFinite` ("has a non-finite component"), and so are finite values
    /// whose total mass overflows (f64 values near `f64::MAX`: "have a sum,
    /// weighted by their bins' solid angles, that is not finite"); a
    /// negative value is `OutOfRange` with that value.
    pub fn new(theta: &'a [F], values: &'a [F], cdf: &'a mut [F]) -> Result<Self, Error> {
        let err = |field, reason| Err(Error::Table { field, reason });
        let n = values.len();
        if n == 0 {
            return err("values", "needs at least one bin");
        }
        if theta.len() != n + 1 {
            return err("theta", "needs exactly values.len() + 1 bin edges");
        }
        if cdf.len() != n + 1 {
            return err("cdf", "buffer needs exactly values.len() + 1 entries");
        }
        if theta.iter().any(|t| !t.is_finite()) {
            return Err(Error::not_finite("theta"));
        }
        if theta[0] != F::ZERO {
            return err("theta", "first edge must be 0");
        }
        let last = theta[n].to_f64();
        if (last - PI).abs() > 4.0 * F::EPSILON.to_f64() * PI {
            return err("theta", "last edge must be pi");
        }
        // All edges are finite here, so `>=` is the exact negation of `<`.
        if theta.windows(2).any(|w| w[0] >= w[1]) {
            return err("theta", "edges must be strictly increasing");
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(Error::not_finite("values"));
        }
        if let Some(v) = values.iter().find(|v| **v < F::ZERO) {
            return Err(Error::OutOfRange {
                field: "values",
                value: v.to_f64(),
                allowed: "[0, inf)",
            });
        }
        let mut total = 0.0f64;
        let mut first_moment = 0.0f64;
        for (i, v) in values.iter().enumerate() {
            let mass = v.to_f64() * bin_width(theta, i);
            total += mass;
            // ∫ cos θ d(1 − cos θ) over the bin = Δx (cos θ_i + cos θ_{i+1})/2.
            first_moment += mass * 0.5 * (cos_edge(theta, i) + cos_edge(theta, i + 1));
        }
        if total == 0.0 {
            return err("values", "are all zero");
        }
        if !total.is_finite() {
            return Err(Error::NotFinite {
                field: "values",
                reason: "have a sum, weighted by their bins' solid angles, that is not finite",
            });
        }
        let mut acc = 0.0f64;
        cdf[0] = F::ZERO;
        for (i, v) in values.iter().enumerate() {
            acc += v.to_f64() * bin_width(theta, i);
            cdf[i + 1] = F::from_f64(acc / total);
        }
        cdf[n] = F::ONE;
        let cdf: &'a [F] = cdf;
        Ok(Self {
            theta,
            values,
            cdf,
            density_scale: F::from_f64(1.0 / (TAU * total)),
            mean: F::from_f64(first_moment / total),
        })
    }

    /// The number of bins n.
    #[inline]
    pub fn bins(&self) -> usize {
        self.values.len()
    }

    /// The bin edges θ_0 … θ_n.
    #[inline]
    pub fn theta(&self) -> &'a [F] {
        self.theta
    }

    /// The (unnormalised) bin values.
    #[inline]
    pub fn values(&self) -> &'a [F] {
        self.values
    }

    /// The cumulative distribution at the edges, `cdf[i] = P(Θ < θ_i)`.
    #[inline]
    pub fn cdf_table(&self) -> &'a [F] {
        self.cdf
    }

    /// The bin `k` with `θ_k ≤ θ < θ_{k+1}` (the last bin for θ ≥ θ_{n−1}).
    #[inline]
    fn bin_of(&self, theta: F) -> usize {
        let n = self.values.len();
        self.theta[1..n].partition_point(|&t| t <= theta)
    }
}

/// Edge `i` in f64, the last one exactly π.
#[inline]
fn edge<F: Real>(theta: &[F], i: usize) -> f64 {
    if i + 1 == theta.len() {
        PI
    } else {
        theta[i].to_f64()
    }
}

/// `cos θ_i` (exactly −1 at the last edge).
#[inline]
fn cos_edge<F: Real>(theta: &[F], i: usize) -> f64 {
    libm::cos(edge(theta, i))
}

/// `1 − cos θ` minus `1 − cos θ_i`: `2 sin((θ − θ_i)/2) sin((θ + θ_i)/2)`.
#[inline]
fn versine_step(from: f64, to: f64) -> f64 {
    2.0 * libm::sin(0.5 * (to - from)) * libm::sin(0.5 * (to + from))
}

/// `Δx_i = cos θ_i − cos θ_{i+1}`, without cancellation.
#[inline]
fn bin_width<F: Real>(theta: &[F], i: usize) -> f64 {
    versine_step(edge(theta, i), edge(theta, i + 1))
}

/// `(1 − cos θ_i, 1 + cos θ_i)` in f64.
#[inline]
fn versines_at<F: Real>(theta: &[F], i: usize) -> (f64, f64) {
    let (s, c) = libm::sincos(0.5 * edge(theta, i));
    if i + 1 == theta.len() {
        (2.0, 0.0)
    } else {
        (2.0 * s * s, 2.0 * c * c)
    }
}

impl<F: Real> PhaseFunction<F> for Tabulated<'_, F> {
    /// `v_k / (2π Σ_j v_j Δx_j)` in the bin `k` of θ.
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        self.values[self.bin_of(d.theta)] * self.density_scale
    }

    /// The bin `k` with `cdf[k] ≤ u < cdf[k+1]` by binary search (empty bins
    /// are never chosen), then `t = (u − cdf[k])/(cdf[k+1] − cdf[k])` and
    /// `1 − cos θ = x_k + t Δx_k`, `1 + cos θ = y_{k+1} + (1 − t) Δx_k`, with
    /// `1 − t` computed as `(cdf[k+1] − u)/(cdf[k+1] − cdf[k])`.
    fn sample(&self, u: F) -> Deflection<F> {
        let n = self.values.len();
        let k = self.cdf[1..n].partition_point(|&c| c <= u);
        let (c0, c1) = (self.cdf[k].to_f64(), self.cdf[k + 1].to_f64());
        let u = u.to_f64().clamp_to(c0, c1);
        let width = c1 - c0;
        let (t, s) = if width > 0.0 {
            ((u - c0) / width, (c1 - u) / width)
        } else {
            (0.0, 1.0)
        };
        let dx = bin_width(self.theta, k);
        let (x0, _) = versines_at(self.theta, k);
        let (_, y1) = versines_at(self.theta, k + 1);
        Deflection::from_versines(F::from_f64(x0 + t * dx), F::from_f64(y1 + s * dx))
    }

    /// `cdf[k] + (cdf[k+1] − cdf[k]) · (x(θ) − x_k)/Δx_k`, with
    /// `x(θ) − x_k = 2 sin((θ − θ_k)/2) sin((θ + θ_k)/2)`.
    fn cdf(&self, d: Deflection<F>) -> F {
        let k = self.bin_of(d.theta);
        let (t0, t1) = (edge(self.theta, k), edge(self.theta, k + 1));
        let t = d.theta.to_f64().clamp_to(t0, t1);
        let frac = (versine_step(t0, t) / bin_width(self.theta, k)).clamp_to(0.0, 1.0);
        let (c0, c1) = (self.cdf[k].to_f64(), self.cdf[k + 1].to_f64());
        F::from_f64(c0 + (c1 - c0) * frac)
    }

    /// `Σ_i v_i Δx_i (cos θ_i + cos θ_{i+1})/2 / Σ_i v_i Δx_i`, computed at
    /// construction.
    #[inline]
    fn mean_cosine(&self) -> F {
        self.mean
    }
}

#[cfg(test)]
mod tests {
    use super::super::HenyeyGreenstein;
    use super::super::testing::*;
    use super::*;

    const EDGES: [f64; 8] = [0.0, 0.01, 0.05, 0.3, 1.0, 1.6, 2.9, PI];
    const VALUES: [f64; 7] = [40.0, 0.0, 3.0, 1.0, 0.0, 0.25, 2.0];

    /// `2π ∫ h(θ) p sin θ dθ` bin by bin (p is discontinuous at the edges).
    fn by_bins(p: &Tabulated<'_, f64>, upto: f64, h: impl Fn(f64) -> f64) -> f64 {
        let mut sum = 0.0;
        for w in EDGES.windows(2) {
            let b = w[1].min(upto);
            if b > w[0] {
                sum += TAU
                    * plain(
                        |t| {
                            let d = Deflection::from_theta(t);
                            h(d.cos()) * p.eval(d) * d.sin()
                        },
                        w[0],
                        b,
                    );
            }
        }
        sum
    }

    #[test]
    fn normalised_exact_cdf_and_mean() {
        let mut buf = [0.0f64; 8];
        let p = Tabulated::new(&EDGES, &VALUES, &mut buf).unwrap();
        let norm = (by_bins(&p, PI, |_| 1.0) - 1.0).abs();
        report("tabulated normalisation", norm);
        assert!(norm < 1e-12);
        let mut worst = 0.0f64;
        for t in [
            0.0, 1e-6, 0.005, 0.01, 0.03, 0.2, 0.7, 1.3, 1.6, 2.0, 3.0, 3.1,
        ] {
            let c = p.cdf(Deflection::from_theta(t));
            worst = worst.max((c - by_bins(&p, t, |_| 1.0)).abs());
        }
        report("tabulated cdf vs quadrature", worst);
        assert!(worst < 1e-12);
        assert!((p.mean_cosine() - by_bins(&p, PI, |c| c)).abs() < 1e-12);
        // Empty bins carry no probability: their cdf is flat.
        let (a, b) = (
            p.cdf(Deflection::from_theta(0.011)),
            p.cdf(Deflection::from_theta(0.049)),
        );
        assert_eq!(a, b);
    }

    #[test]
    fn sample_inverts_cdf_and_skips_empty_bins() {
        let mut buf = [0.0f64; 8];
        let p = Tabulated::new(&EDGES, &VALUES, &mut buf).unwrap();
        let e = inversion_error::<f64, _>(&p);
        report("tabulated |cdf(sample(u)) - u| f64", e);
        assert!(e < 1e-14);
        let edges32 = EDGES.map(|t| t as f32);
        let values32 = VALUES.map(|v| v as f32);
        let mut buf32 = [0.0f32; 8];
        let p32 = Tabulated::new(&edges32, &values32, &mut buf32).unwrap();
        let e32 = inversion_error::<f32, _>(&p32);
        report("tabulated |cdf(sample(u)) - u| f32", e32);
        assert!(e32 < 1e-6);
        for u in u_grid::<f64>() {
            let k = p.bin_of(p.sample(u).theta);
            assert!(VALUES[k] > 0.0, "u = {u} sampled empty bin {k}");
        }
        // Tiny u: 1 − cos θ is linear in u in the first bin, to full precision.
        let d = p.sample(1e-15);
        let first = p.cdf_table()[1];
        let expected = 1e-15 / first * (1.0 - libm::cos(0.01));
        assert!((d.one_minus_cos / expected - 1.0).abs() < 1e-12);
        assert_eval_finite::<f32, _>(&p32);
        assert_eval_finite::<f64, _>(&p);
        let mut buf64 = [0.0f64; 8];
        let mut e64r = edges32.map(|t| t as f64);
        e64r[7] = PI; // f32's π is not within 4 f64 ulps of π.
        let v64r = values32.map(|v| v as f64);
        let p64r = Tabulated::new(&e64r, &v64r, &mut buf64).unwrap();
        assert!(f32_eval_error(&p32, &p64r) < 1e-6);
    }

    #[test]
    fn a_fine_table_of_hg_reproduces_hg() {
        const N: usize = 4000;
        let hg = HenyeyGreenstein::<f64>::new(0.8).unwrap();
        let mut edges = [0.0f64; N + 1];
        let mut values = [0.0f64; N];
        for (i, e) in edges.iter_mut().enumerate() {
            // Denser towards the forward peak.
            let s = i as f64 / N as f64;
            *e = PI * s * s;
        }
        edges[N] = PI;
        for i in 0..N {
            values[i] = hg.eval(Deflection::from_theta(0.5 * (edges[i] + edges[i + 1])));
        }
        let mut buf = [0.0f64; N + 1];
        let p = Tabulated::new(&edges, &values, &mut buf).unwrap();
        assert!((p.mean_cosine() - 0.8).abs() < 1e-4, "{}", p.mean_cosine());
        for t in [0.01, 0.1, 0.5, 2.0] {
            let d = Deflection::from_theta(t);
            assert!((p.cdf(d) - hg.cdf(d)).abs() < 1e-4);
        }
    }

    #[test]
    fn constructor_names_what_is_wrong() {
        let mut buf = [0.0f64; 8];
        let field = |r: Result<Tabulated<'_, f64>, Error>| match r.unwrap_err() {
            Error::Table { field, .. } => field,
            e => panic!("{e:?}"),
        };
        assert_eq!(
            field(Tabulated::new(&EDGES, &VALUES[..6], &mut buf)),
            "theta"
        );
        assert_eq!(field(Tabulated::new(&EDGES, &VALUES, &mut buf[..7])), "cdf");
        assert_eq!(
            field(Tabulated::new(&EDGES[..1], &[], &mut buf[..1])),
            "values"
        );
        let mut e = EDGES;
        e[0] = 1e-3;
        assert_eq!(field(Tabulated::new(&e, &VALUES, &mut buf)), "theta");
        let mut e = EDGES;
        e[7] = 3.0;
        assert_eq!(field(Tabulated::new(&e, &VALUES, &mut buf)), "theta");
        let mut e = EDGES;
        e[3] = e[2];
        assert_eq!(field(Tabulated::new(&e, &VALUES, &mut buf)), "theta");
        assert_eq!(field(Tabulated::new(&EDGES, &[0.0; 7], &mut buf)), "values");
        // The f32 π is accepted as the last edge.
        let e32 = EDGES.map(|t| t as f32);
        let mut b32 = [0.0f32; 8];
        assert!(Tabulated::new(&e32, &[1.0f32; 7], &mut b32).is_ok());
    }

    /// Non-finite input is `NotFinite`, not a table of the wrong shape: a NaN
    /// or infinite edge or value, and finite values whose weighted sum
    /// overflows (two bins of `f64::MAX`); a negative value is `OutOfRange`.
    #[test]
    fn non_finite_and_negative_input_is_named_as_such() {
        let not_finite = |r: Result<Tabulated<'_, f64>, Error>| match r.unwrap_err() {
            Error::NotFinite { field, reason } => std::format!("{field} {reason}"),
            e => panic!("{e:?}"),
        };
        let mut buf = [0.0f64; 8];
        for bad in [f64::NAN, f64::INFINITY] {
            let mut e = EDGES;
            e[3] = bad;
            assert_eq!(
                not_finite(Tabulated::new(&e, &VALUES, &mut buf)),
                "theta has a non-finite component"
            );
            let mut v = VALUES;
            v[2] = bad;
            assert_eq!(
                not_finite(Tabulated::new(&EDGES, &v, &mut buf)),
                "values has a non-finite component"
            );
        }
        let huge = [f64::MAX, f64::MAX];
        let (e, mut b) = ([0.0, 1.0, PI], [0.0f64; 3]);
        assert_eq!(
            not_finite(Tabulated::new(&e, &huge, &mut b)),
            "values have a sum, weighted by their bins' solid angles, that is not finite"
        );
        let mut v = VALUES;
        v[2] = -1.0;
        assert_eq!(
            Tabulated::new(&EDGES, &v, &mut buf).unwrap_err(),
            Error::OutOfRange {
                field: "values",
                value: -1.0,
                allowed: "[0, inf)"
            }
        );
        // In f32 the same values are accumulated in f64, where their sum is
        // finite: the table is accepted.
        let (e32, mut b32) = ([0.0f32, 1.0, core::f32::consts::PI], [0.0f32; 3]);
        assert!(Tabulated::new(&e32, &[f32::MAX, f32::MAX], &mut b32).is_ok());
    }
}
