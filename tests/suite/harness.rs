//! Shared machinery: a seeded generator, the phase functions under test, an
//! independent circumcircle frame, Gauss–Legendre cells, the regularized
//! incomplete gamma function and the χ² statistic of Mitsuba 3's harness
//! (REFERENCE.md §3.1).

use glam::DVec3;
use omnee::Real;
use omnee::phase::{
    Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, PhaseFunction, Rayleigh,
    Tabulated,
};

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny seeded generator. Every test
/// seeds its own stream, so results do not depend on test order or threads.
pub struct Rng(u64);

impl Rng {
    /// A stream from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` with the precision's full mantissa (24 or 53 bits).
    pub fn uniform<F: Real>(&mut self) -> F {
        let bits = if F::EPSILON.to_f64() < 1e-10 { 53 } else { 24 };
        let x = (self.next_u64() >> (64 - bits)) as f64;
        F::from_f64(x * (-(bits as f64)).exp2())
    }

    /// Three uniform numbers.
    pub fn u3<F: Real>(&mut self) -> [F; 3] {
        [self.uniform(), self.uniform(), self.uniform()]
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform::<f64>()
    }

    /// A uniformly distributed unit vector.
    pub fn unit(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, core::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// The phase functions of the suite, as data, so one list instantiates in
/// either precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseSpec {
    /// `1/(4π)`.
    Isotropic,
    /// Rayleigh, `3/(16π)(1 + cos²θ)`.
    Rayleigh,
    /// Henyey–Greenstein with g.
    Hg(f64),
    /// `w·HG(g1) + (1 − w)·HG(g2)`.
    TwoTerm(f64, f64, f64),
    /// Draine with (g, α).
    Draine(f64, f64),
    /// Fournier–Forand with (backscatter fraction B, refractive index n).
    Ff(f64, f64),
    /// Approximate Mie for a droplet diameter in µm.
    Mie(f64),
    /// A measured-style table: the random bins of [`table`] for this seed.
    Tabulated(u64),
}

impl PhaseSpec {
    /// The phase function in precision `F` (panics on invalid parameters:
    /// every spec in the suite is valid).
    pub fn build<F: Real>(self) -> Box<dyn PhaseFunction<F>> {
        let f = F::from_f64;
        match self {
            PhaseSpec::Isotropic => Box::new(Isotropic),
            PhaseSpec::Rayleigh => Box::new(Rayleigh),
            PhaseSpec::Hg(g) => Box::new(HenyeyGreenstein::new(f(g)).unwrap()),
            PhaseSpec::TwoTerm(g1, g2, w) => {
                Box::new(Mixture::two_term(f(g1), f(g2), f(w)).unwrap())
            }
            PhaseSpec::Draine(g, a) => Box::new(Draine::new(f(g), f(a)).unwrap()),
            PhaseSpec::Ff(b, n) => Box::new(FournierForand::new(f(b), f(n)).unwrap()),
            PhaseSpec::Mie(d) => Box::new(Mie::new(f(d)).unwrap()),
            PhaseSpec::Tabulated(seed) => {
                // The table borrows its arrays: leak them (a few hundred bytes
                // per call, in a test binary).
                let (edges, values) = table(seed);
                let mut theta: Vec<F> = edges.iter().map(|&t| f(t)).collect();
                *theta.last_mut().unwrap() = F::PI;
                let values: Vec<F> = values.iter().map(|&v| f(v)).collect();
                let cdf = vec![F::ZERO; theta.len()];
                Box::new(
                    Tabulated::new(
                        Box::leak(theta.into_boxed_slice()),
                        Box::leak(values.into_boxed_slice()),
                        Box::leak(cdf.into_boxed_slice()),
                    )
                    .unwrap(),
                )
            }
        }
    }

    /// The same spec with every parameter rounded to f32, so an f64 instance
    /// has exactly the parameters of the f32 one (1 − g for g = 0.9999 moves
    /// by 6e-4 relative in the rounding alone).
    pub fn rounded_to_f32(self) -> Self {
        let r = |x: f64| x as f32 as f64;
        match self {
            PhaseSpec::Hg(g) => PhaseSpec::Hg(r(g)),
            PhaseSpec::TwoTerm(a, b, w) => PhaseSpec::TwoTerm(r(a), r(b), r(w)),
            PhaseSpec::Draine(g, a) => PhaseSpec::Draine(r(g), r(a)),
            PhaseSpec::Ff(b, n) => PhaseSpec::Ff(r(b), r(n)),
            PhaseSpec::Mie(d) => PhaseSpec::Mie(r(d)),
            other => other,
        }
    }

    /// Where the density jumps inside (0, π): the interior bin edges of a
    /// table. Quadrature must split there: a jump between two nodes of a
    /// Gauss–Kronrod panel can go unnoticed by its error estimate (measured:
    /// a cdf off by 8e-4 without the split).
    pub fn breakpoints(self) -> Vec<f64> {
        match self {
            PhaseSpec::Tabulated(seed) => {
                let (edges, _) = table(seed);
                edges[1..edges.len() - 1].to_vec()
            }
            _ => Vec::new(),
        }
    }

    /// Whether `sample` is the inverse of `cdf` (false for mixtures, which
    /// spend part of `u` on the lobe choice).
    pub fn inverse_cdf(self) -> bool {
        !matches!(self, PhaseSpec::TwoTerm(..) | PhaseSpec::Mie(..))
    }
}

/// The bins of [`PhaseSpec::Tabulated`]: 1 to 12 bins whose edges crowd
/// towards θ = 0 (a forward peak) or spread evenly, with values spanning four
/// orders of magnitude and about one bin in five empty (never all). Edges
/// are at least 1e-4 apart, so they stay distinct in f32.
pub fn table(seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed ^ 0x7ab1_e5ee_d000_0000);
    let bins = 1 + (rng.next_u64() % 12) as usize;
    let crowd = rng.uniform::<f64>() < 0.5;
    let mut interior: Vec<f64> = (1..bins)
        .map(|_| {
            let w = rng.range(0.0, 1.0);
            core::f64::consts::PI * if crowd { w * w * w } else { w }
        })
        .collect();
    interior.sort_by(f64::total_cmp);
    let mut edges = vec![0.0];
    for t in interior {
        if t - edges.last().unwrap() > 1e-4 && core::f64::consts::PI - t > 1e-4 {
            edges.push(t);
        }
    }
    edges.push(core::f64::consts::PI);
    let mut values: Vec<f64> = (1..edges.len())
        .map(|_| {
            if rng.uniform::<f64>() < 0.2 {
                0.0
            } else {
                10f64.powf(rng.range(-2.0, 2.0))
            }
        })
        .collect();
    if values.iter().all(|&v| v == 0.0) {
        values[0] = 1.0;
    }
    (edges, values)
}

/// An orthonormal frame about the axis `x0 → x2`, built here independently of
/// `omnee::circumcircle` so the χ² tests do not check the core against itself.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub x0: DVec3,
    pub s: f64,
    pub e: DVec3,
    pub u: DVec3,
    pub v: DVec3,
}

impl Frame {
    /// The frame of `x0 → x2` (Gram–Schmidt against a coordinate axis).
    pub fn new(x0: DVec3, x2: DVec3) -> Self {
        let d = x2 - x0;
        let s = d.length();
        let e = d / s;
        let helper = if e.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
        let u = (helper - e * e.dot(helper)).normalize();
        let v = e.cross(u);
        Self { x0, s, e, u, v }
    }

    /// `(θ, β/θ, φ)` of `x1`: `α = ∠(e, x1 − x0)`, `β = ∠(−e, x1 − x2)`, θ = α + β.
    pub fn angles(&self, x1: DVec3) -> (f64, f64, f64) {
        let a = x1 - self.x0;
        let h = self.e.cross(a).length();
        let p1 = self.e.dot(a);
        let p2 = self.s - p1;
        let (alpha, beta) = (h.atan2(p1), h.atan2(p2));
        let theta = alpha + beta;
        let ratio = if theta > 0.0 {
            beta / theta
        } else {
            (p1 / self.s).clamp(0.0, 1.0)
        };
        let mut phi = a.dot(self.v).atan2(a.dot(self.u));
        if phi < 0.0 {
            phi += core::f64::consts::TAU;
        }
        (theta, ratio, phi)
    }

    /// `x1` and the volume Jacobian `|dx1 / d(θ, r, φ)| = d1² d2² θ / s` at
    /// `θ ∈ (0, π)`, `r = β/θ ∈ (0, 1)` (MATH.md §2 with `dβ = θ dr`).
    pub fn point(&self, theta: f64, r: f64, phi: f64) -> (DVec3, f64) {
        let beta = r * theta;
        let alpha = theta - beta;
        let d1 = self.s * beta.sin() / theta.sin();
        let d2 = self.s * alpha.sin() / theta.sin();
        let radial = self.u * phi.cos() + self.v * phi.sin();
        let x1 = self.x0 + (self.e * alpha.cos() + radial * alpha.sin()) * d1;
        (x1, d1 * d1 * d2 * d2 * theta / self.s)
    }
}

/// 4-point Gauss–Legendre nodes and weights on `[0, 1]`.
pub const GL4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// The 4³-point Gauss–Legendre rule over the box `[lo, hi]`, and whether
/// its nodes disagree on `f` vanishing (a slab face, a cosine horizon, θmax).
fn gauss_box(f: &mut dyn FnMut([f64; 3]) -> f64, lo: [f64; 3], hi: [f64; 3]) -> (f64, bool) {
    let h = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    let (mut sum, mut zeros, mut nonzeros) = (0.0, 0, 0);
    for &(a, wa) in &GL4 {
        for &(b, wb) in &GL4 {
            for &(c, wc) in &GL4 {
                let v = f([lo[0] + a * h[0], lo[1] + b * h[1], lo[2] + c * h[2]]);
                if v == 0.0 {
                    zeros += 1;
                } else {
                    nonzeros += 1;
                }
                sum += wa * wb * wc * v;
            }
        }
    }
    (sum * h[0] * h[1] * h[2], zeros > 0 && nonzeros > 0)
}

/// The eight half-size boxes of `[lo, hi]`.
fn octants(lo: [f64; 3], hi: [f64; 3]) -> [([f64; 3], [f64; 3]); 8] {
    core::array::from_fn(|k| {
        let (mut l, mut u) = (lo, hi);
        for axis in 0..3 {
            let mid = 0.5 * (lo[axis] + hi[axis]);
            if k >> axis & 1 == 0 {
                u[axis] = mid;
            } else {
                l[axis] = mid;
            }
        }
        (l, u)
    })
}

fn adapt_box(
    f: &mut dyn FnMut([f64; 3]) -> f64,
    lo: [f64; 3],
    hi: [f64; 3],
    whole: (f64, bool),
    tol: f64,
    depth: u32,
) -> f64 {
    let children = octants(lo, hi).map(|(l, u)| (l, u, gauss_box(f, l, u)));
    let sum: f64 = children.iter().map(|c| c.2.0).sum();
    let (estimate, mixed) = whole;
    if depth == 0 || (sum - estimate).abs() <= tol {
        return sum;
    }
    if mixed {
        // Follow the discontinuity only: the parts that lie on one side of
        // it are as smooth as any cell.
        return children
            .into_iter()
            .map(|(l, u, w)| {
                if w.1 {
                    adapt_box(f, l, u, w, tol / 8.0, depth - 1)
                } else {
                    w.0
                }
            })
            .sum();
    }
    children
        .into_iter()
        .map(|(l, u, w)| adapt_box(f, l, u, w, tol / 8.0, depth - 1))
        .sum()
}

/// `∫` of `f` over the box `[lo, hi]`: 4³-point Gauss–Legendre, split in
/// eight while the split changes the value by more than the tolerance, at
/// most `depth` levels. Where the nodes disagree on whether `f` vanishes (a
/// slab face, a cosine horizon) only the parts that still straddle the edge
/// are split further. `f` is a probability density and the result an
/// expected count over `n` samples divided by `n`: the tolerance is 2 % of
/// the cell's Poisson standard deviation, `0.02 √(p n) / n`, shared out
/// among the parts, so the quadrature adds at most 0.0004 per cell to the
/// χ² statistic. `force` levels are split unconditionally first (for a thin
/// sliver of support that no node of the box hits).
pub fn integrate_box(
    f: &mut dyn FnMut([f64; 3]) -> f64,
    lo: [f64; 3],
    hi: [f64; 3],
    n: f64,
    depth: u32,
    force: u32,
) -> f64 {
    if force > 0 {
        return octants(lo, hi)
            .into_iter()
            .map(|(l, u)| integrate_box(f, l, u, n, depth.saturating_sub(1), force - 1))
            .sum();
    }
    let whole = gauss_box(f, lo, hi);
    let tol = 0.02 * (whole.0.abs() * n).sqrt() / n + 1e-12;
    adapt_box(f, lo, hi, whole, tol, depth)
}

/// `∫_a^b f` by [`omnee::quadrature::integrate`] on each piece between the
/// `breaks` that fall inside (a, b) (sorted), with the given tolerances per
/// piece.
pub fn integrate_pieces(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    breaks: &[f64],
    rel_tol: f64,
    abs_tol: f64,
) -> f64 {
    let mut sum = 0.0;
    let mut lo = a;
    for &x in breaks.iter().filter(|&&x| x > a && x < b) {
        sum += omnee::quadrature::integrate(&mut f, lo, x, rel_tol, abs_tol);
        lo = x;
    }
    sum + omnee::quadrature::integrate(&mut f, lo, b, rel_tol, abs_tol)
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
pub fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = core::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let mut a = C[0];
    for (i, &c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * core::f64::consts::TAU.ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularized upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)`:
/// the series for `P = 1 − Q` below `x = a + 1`, Lentz's continued fraction
/// above (Numerical Recipes §6.2, as Cephes' `igamc` that both reference
/// harnesses port).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut ap, mut term) = (a, 1.0 / a);
        let mut sum = term;
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-17 {
                break;
            }
        }
        1.0 - sum * prefactor
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

/// `P(X > x)` for X ~ χ² with `dof` degrees of freedom.
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    gamma_q(0.5 * dof as f64, 0.5 * x)
}

/// The two-sided normal tail `P(|Z| > z) = Q(1/2, z²/2)`.
pub fn normal_two_sided_tail(z: f64) -> f64 {
    gamma_q(0.5, 0.5 * z * z)
}

/// The z with `P(|Z| > z) = p` (bisection; p in (1e-300, 1)).
pub fn normal_two_sided_quantile(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if normal_two_sided_tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Šidák's per-test level for a family of `tests` tests at family level `alpha`:
/// `1 − (1 − α)^{1/tests}`.
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    -((1.0 - alpha).ln() / tests as f64).exp_m1()
}

/// The result of [`chi2`].
#[derive(Clone, Debug)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The five unpooled cells with the largest contributions, as
    /// `(cell, observed, expected)`, for the failure message.
    pub worst: Vec<(usize, f64, f64)>,
}

/// Pearson's χ² over cells with observed and expected counts, pooled as in
/// Mitsuba 3 / pbrt-v4: cells sorted by expected count, those below 5 merged
/// into pools of at least 5; dof = pooled cells − 1. Rejects outright (Err) a
/// negative expected count beyond `tolerance` (the quadrature error of a
/// count computed as `N − Σ expected`: a density that integrates to more
/// than 1) and observations in a cell whose expected count is not
/// positive (samples where the pdf says none can be).
pub fn chi2(observed: &[f64], expected: &[f64], tolerance: f64) -> Result<Chi2, String> {
    let mut cells: Vec<(usize, f64, f64)> = Vec::with_capacity(observed.len());
    for (i, (&o, &e)) in observed.iter().zip(expected).enumerate() {
        if !e.is_finite() || e < -tolerance {
            return Err(format!("cell {i}: expected count {e} (observed {o})"));
        }
        if e <= 0.0 && o == 0.0 {
            continue; // e.g. "no sample" for a sampler that always returns one
        }
        if e <= 0.0 {
            return Err(format!(
                "cell {i}: {o} samples where the pdf integrates to {e}"
            ));
        }
        cells.push((i, o, e));
    }
    let mut worst: Vec<(usize, f64, f64)> = cells.iter().copied().filter(|c| c.2 >= 5.0).collect();
    worst.sort_by(|a, b| ((b.1 - b.2).powi(2) / b.2).total_cmp(&((a.1 - a.2).powi(2) / a.2)));
    worst.truncate(5);
    cells.sort_by(|a, b| a.2.total_cmp(&b.2));
    let (mut statistic, mut n) = (0.0, 0usize);
    let (mut po, mut pe) = (0.0, 0.0);
    for (_, o, e) in cells {
        po += o;
        pe += e;
        if pe >= 5.0 {
            statistic += (po - pe) * (po - pe) / pe;
            n += 1;
            po = 0.0;
            pe = 0.0;
        }
    }
    if pe > 0.0 {
        statistic += (po - pe) * (po - pe) / pe;
        n += 1;
    }
    if n < 2 {
        return Err(format!("only {n} cells after pooling"));
    }
    let dof = n - 1;
    Ok(Chi2 {
        statistic,
        dof,
        p_value: chi2_sf(statistic, dof),
        worst,
    })
}

#[test]
fn incomplete_gamma_matches_tabulated_chi2_quantiles() {
    // Quantiles from standard tables (Abramowitz & Stegun 26.4, and the
    // closed forms for dof 1 and 2).
    let cases = [
        (3.841_458_820_694_124, 1, 0.05),
        (1.0, 1, 0.317_310_507_862_914_15), // erfc(1/√2)
        (6.634_896_601_021_214, 1, 0.01),
        (18.307_038_053_275_146, 10, 0.05),
        (23.209_251_158_954_356, 10, 0.01),
        (0.114_831_801_899_117_9, 3, 0.99),
    ];
    for (x, dof, p) in cases {
        let got = chi2_sf(x, dof);
        assert!(
            (got - p).abs() < 1e-9 * p.max(1e-3) + 1e-12,
            "χ²({dof}) sf({x}) = {got}, want {p}"
        );
    }
    for &x in &[0.1, 1.0, 5.0, 40.0] {
        assert!((chi2_sf(x, 2) - (-0.5 * x).exp()).abs() < 1e-14);
    }
    let z = normal_two_sided_quantile(0.05);
    assert!((z - 1.959_963_984_540_054).abs() < 1e-9, "{z}");
}

#[test]
fn chi2_rejects_impossible_cells_and_accepts_exact_counts() {
    assert!(chi2(&[3.0, 10.0, 10.0], &[0.0, 11.5, 11.5], 1e-9).is_err());
    assert!(chi2(&[10.0, 10.0], &[-5.0, 25.0], 1e-9).is_err());
    let r = chi2(&[100.0, 200.0, 50.0], &[100.0, 200.0, 50.0], 1e-9).unwrap();
    assert!(r.statistic == 0.0 && r.dof == 2 && r.p_value == 1.0);
    let r = chi2(&[150.0, 150.0, 50.0], &[100.0, 200.0, 50.0], 1e-9).unwrap();
    assert!(r.p_value < 1e-6, "{r:?}");
}

/// The output of [`BatchOmnee::batch`]: per lane `x1 = (x, y, z)`, pdf and
/// weight (zeros where no sample), and the number of samples returned.
pub struct Lanes {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
    pub pdf: Vec<f32>,
    pub weight: Vec<f32>,
    pub count: usize,
}

/// The batch entry point `Omnee::sample_batch` (f32, Henyey–Greenstein) seen
/// as a scalar [`Technique<f64>`]: each `sample` runs a batch of one lane
/// (with `u` rounded to f32), `pdf` is the f64 OMNEE density of the same
/// connection and g, so a χ² test compares the batch's points with the
/// density they should have.
pub struct BatchOmnee {
    pub f32: omnee::sampling::Omnee<f32, HenyeyGreenstein<f32>>,
    pub f64: omnee::sampling::Omnee<f64, HenyeyGreenstein<f64>>,
}

impl BatchOmnee {
    /// For the end points and θmax rounded to f32 and g rounded to f32, in
    /// both precisions (one geometry, one phase function).
    pub fn new(x0: DVec3, x2: DVec3, theta_max: f64, g: f64) -> Self {
        use omnee::sampling::{Connection, Omnee};
        let c32 = Connection::new(x0.as_vec3(), x2.as_vec3(), theta_max as f32).unwrap();
        let c64 = Connection::new(
            c32.axis.x0.as_dvec3(),
            c32.axis.x2.as_dvec3(),
            f64::from(c32.theta_max),
        )
        .unwrap();
        let g32 = g as f32;
        Self {
            f32: Omnee::new(c32, HenyeyGreenstein::new(g32).unwrap()),
            f64: Omnee::new(c64, HenyeyGreenstein::new(f64::from(g32)).unwrap()),
        }
    }

    /// One `sample_batch` call in f32 over the uniforms `u0`, `u1`, `u2`
    /// (equal lengths), its output in owned structure-of-arrays form.
    pub fn batch(&self, u0: &[f32], u1: &[f32], u2: &[f32]) -> Lanes {
        use omnee::sampling::{Uniforms, Vertices};
        let m = u0.len();
        let mut out = Lanes {
            x: vec![0.0; m],
            y: vec![0.0; m],
            z: vec![0.0; m],
            pdf: vec![0.0; m],
            weight: vec![0.0; m],
            count: 0,
        };
        out.count = self
            .f32
            .sample_batch(
                Uniforms { u0, u1, u2 },
                Vertices {
                    x: &mut out.x,
                    y: &mut out.y,
                    z: &mut out.z,
                    pdf: &mut out.pdf,
                    weight: &mut out.weight,
                },
            )
            .unwrap();
        out
    }

    /// One lane of the batch: `(x1, pdf, weight)`, or `None` where the batch
    /// reports no sample (pdf = weight = 0).
    pub fn lane(&self, u: [f32; 3]) -> Option<(glam::Vec3, f32, f32)> {
        let l = self.batch(&[u[0]], &[u[1]], &[u[2]]);
        if l.count == 0 {
            assert!(
                l.pdf[0] == 0.0 && l.weight[0] == 0.0,
                "no sample but pdf {} weight {}",
                l.pdf[0],
                l.weight[0]
            );
            return None;
        }
        Some((
            glam::Vec3::new(l.x[0], l.y[0], l.z[0]),
            l.pdf[0],
            l.weight[0],
        ))
    }
}

impl omnee::sampling::Technique<f64> for BatchOmnee {
    fn sample(&self, u: [f64; 3]) -> Option<omnee::sampling::Sample<f64>> {
        let (x1, pdf, weight) = self.lane(u.map(|x| x as f32))?;
        Some(omnee::sampling::Sample {
            x1: x1.as_dvec3(),
            pdf: f64::from(pdf),
            weight: f64::from(weight),
        })
    }
    fn pdf(&self, x1: DVec3) -> f64 {
        self.f64.pdf(x1)
    }
    fn invert(&self, _x1: DVec3) -> Option<[f64; 3]> {
        None
    }
}
