//! Quadrature for expected counts and reference values: adaptive
//! Gauss–Legendre cells over boxes, and the core's Gauss–Kronrod rule split
//! at a density's jumps.

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
