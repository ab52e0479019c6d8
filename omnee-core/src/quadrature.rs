//! Adaptive Gauss–Kronrod quadrature in f64, for references and tests.
//!
//! `no_std` and allocation-free: bisection recurses on the stack to a fixed
//! depth. Integrands with a known narrow feature (a forward peak at θ = 0)
//! should be split there by the caller, e.g. with [`integrate_geometric`].
//!
//! The public functions are generic over the integrand, but the work is done
//! by private functions that call it through `&mut dyn FnMut(f64) -> f64`:
//! one copy of the adaptive bisection in a binary instead of one per
//! integrand (the browser demo's module had six), for the price of an
//! indirect call per evaluation.

/// Nodes of the 15-point Kronrod rule on [−1, 1] (non-negative half).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights for [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728_8,
];
/// Weights of the embedded 7-point Gauss rule (at XGK[1], XGK[3], XGK[5], XGK[7]).
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// An integrand as the private functions take it.
type Integrand<'a> = &'a mut dyn FnMut(f64) -> f64;

/// One G7–K15 panel: `(Kronrod estimate, |Kronrod − Gauss|)` of `∫_a^b f`.
fn gauss_kronrod(f: Integrand<'_>, a: f64, b: f64) -> (f64, f64) {
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    let fc = f(c);
    let (mut kronrod, mut gauss) = (WGK[7] * fc, WG[3] * fc);
    for i in 0..7 {
        let pair = f(c - h * XGK[i]) + f(c + h * XGK[i]);
        kronrod += WGK[i] * pair;
        if i % 2 == 1 {
            gauss += WG[i / 2] * pair;
        }
    }
    (kronrod * h, ((kronrod - gauss) * h).abs())
}

fn adapt(f: Integrand<'_>, a: f64, b: f64, whole: (f64, f64), tol: f64, depth: u32) -> f64 {
    let (estimate, error) = whole;
    // Below ~100 ulp of the panel's value the error estimate is round-off, and
    // halving the tolerance further would only bisect noise.
    let floor = 128.0 * f64::EPSILON * estimate.abs();
    if error <= tol.max(floor) || depth == 0 || !error.is_finite() {
        return estimate;
    }
    let m = 0.5 * (a + b);
    let left = gauss_kronrod(f, a, m);
    let right = gauss_kronrod(f, m, b);
    adapt(f, a, m, left, 0.5 * tol, depth - 1) + adapt(f, m, b, right, 0.5 * tol, depth - 1)
}

/// `∫_a^b f(x) dx` by adaptive G7–K15 bisection to an absolute error of about
/// `max(abs_tol, rel_tol · |∫ f|)` (depth at most 40).
pub fn integrate<G: FnMut(f64) -> f64>(
    mut f: G,
    a: f64,
    b: f64,
    rel_tol: f64,
    abs_tol: f64,
) -> f64 {
    integrate_dyn(&mut f, a, b, rel_tol, abs_tol)
}

/// [`integrate`] through a `dyn` integrand.
fn integrate_dyn(f: Integrand<'_>, a: f64, b: f64, rel_tol: f64, abs_tol: f64) -> f64 {
    if a == b {
        return 0.0;
    }
    let whole = gauss_kronrod(f, a, b);
    let tol = abs_tol.max(rel_tol * whole.0.abs());
    adapt(f, a, b, whole, tol, 40)
}

/// `∫_a^b f(x) dx` with panels split geometrically towards `a`:
/// `[a, a + w], [a + w, a + 2w], [a + 2w, a + 4w], …` with `w = (b − a)·2^{−levels}`,
/// each integrated by [`integrate`]. For integrands with a narrow feature at `a`
/// (a forward-peaked phase function at θ = 0), whose width can be 10⁻⁴ of the range.
///
/// The tolerance is relative to the whole integral: a first pass estimates it
/// panel by panel, and every panel then gets the absolute tolerance
/// `rel_tol · |total| / panels`, so panels whose values are negligible (or
/// subnormal) are not refined for their own sake.
pub fn integrate_geometric<G: FnMut(f64) -> f64>(
    mut f: G,
    a: f64,
    b: f64,
    levels: u32,
    rel_tol: f64,
) -> f64 {
    geometric_dyn(&mut f, a, b, levels, rel_tol)
}

/// [`integrate_geometric`] through a `dyn` integrand.
fn geometric_dyn(f: Integrand<'_>, a: f64, b: f64, levels: u32, rel_tol: f64) -> f64 {
    let mut panels = [(0.0, 0.0); 64];
    let mut count = 0;
    let mut width = (b - a) / (1u64 << levels.min(62)) as f64;
    let mut lo = a;
    while lo < b && count < panels.len() {
        let hi = if count + 1 == panels.len() {
            b
        } else {
            (lo + width).min(b)
        };
        panels[count] = (lo, hi);
        count += 1;
        lo = hi;
        if count > 1 {
            width *= 2.0;
        }
    }
    let coarse: f64 = panels[..count]
        .iter()
        .map(|&(lo, hi)| gauss_kronrod(f, lo, hi).0.abs())
        .sum();
    let abs_tol = rel_tol * coarse / count as f64;
    panels[..count]
        .iter()
        .map(|&(lo, hi)| integrate_dyn(f, lo, hi, rel_tol, abs_tol))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly_and_smooth_functions_tightly() {
        // G7 is exact to degree 13, K15 to degree 22.
        let poly = integrate(|x| 3.0 * x * x - 2.0 * x + 1.0, -1.0, 2.0, 1e-14, 0.0);
        assert!((poly - 9.0).abs() < 1e-13);
        let s = integrate(libm::sin, 0.0, core::f64::consts::PI, 1e-12, 0.0);
        assert!((s - 2.0).abs() < 1e-12);
    }

    #[test]
    fn resolves_a_narrow_peak_with_geometric_panels() {
        // ∫_0^π w/(w² + x²) dx = atan(π/w) with w = 1e-5.
        let w = 1e-5;
        let exact = libm::atan(core::f64::consts::PI / w);
        let got = integrate_geometric(
            |x| w / (w * w + x * x),
            0.0,
            core::f64::consts::PI,
            24,
            1e-11,
        );
        assert!((got - exact).abs() < 1e-9 * exact, "{got} vs {exact}");
    }
}
