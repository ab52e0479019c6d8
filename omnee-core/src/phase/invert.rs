//! Safeguarded Newton inversion of a CDF in f64, shared by the phase
//! functions without (or with only an approximate) closed-form inverse.

use crate::real::Real;

/// Iteration cap; bisection alone would reach 2⁻²⁰⁰ of the bracket.
const MAX_ITER: usize = 200;

/// Solves `P(Θ ≤ θ) = u` for the versines `(1 − cos θ, 1 + cos θ)`.
///
/// - `cdf(x, y)`: `P(Θ ≤ θ)` at `x = 1 − cos θ`, `y = 1 + cos θ`, accurate
///   relative to itself for small θ;
/// - `ccdf(x, y)`: `P(Θ > θ)`, accurate relative to itself near θ = π;
/// - `dens(x, y)`: `2π p(θ) = d cdf/dx = d ccdf/dy`;
/// - `guess`: a starting `1 − cos θ` (anything outside `(0, 2)` means none).
///
/// If `u ≤ cdf(π/2)` the root is sought in `x ∈ [0, 1]` with `cdf = u`,
/// otherwise in `y ∈ [0, 1]` with `ccdf = 1 − u`, so the small versine is found
/// to full relative precision at both ends. Each step is Newton's when it stays
/// inside the current bracket and a (geometric, for wide brackets) bisection
/// otherwise (geometric and by squaring
/// towards a peak at 0, so roots down to the subnormals are found in a few
/// dozen steps); it stops when a step changes the root by at most a few ulps.
pub(crate) fn invert_cdf(
    u: f64,
    guess: f64,
    cdf: impl Fn(f64, f64) -> f64,
    ccdf: impl Fn(f64, f64) -> f64,
    dens: impl Fn(f64, f64) -> f64,
) -> (f64, f64) {
    if u.is_nan() || u <= 0.0 {
        return (0.0, 2.0);
    }
    if u >= 1.0 {
        return (2.0, 0.0);
    }
    if u <= cdf(1.0, 1.0) {
        let x = solve(|x| cdf(x, 2.0 - x), |x| dens(x, 2.0 - x), u, guess);
        (x, 2.0 - x)
    } else {
        let y = solve(
            |y| ccdf(2.0 - y, y),
            |y| dens(2.0 - y, y),
            1.0 - u,
            2.0 - guess,
        );
        (2.0 - y, y)
    }
}

/// The `t ∈ [0, 1]` with `f(t) = target` for increasing `f`, `f(0) = 0 ≤
/// target ≤ f(1)`, `df = f'`.
fn solve(f: impl Fn(f64) -> f64, df: impl Fn(f64) -> f64, target: f64, guess: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let mut t = if guess > 0.0 && guess < 1.0 {
        guess
    } else {
        0.5
    };
    for _ in 0..MAX_ITER {
        let r = f(t) - target;
        if r == 0.0 {
            return t;
        }
        if r < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let mut next = t - r / df(t);
        // `!(a && b)` also catches NaN from an infinite density.
        if !(next > lo && next < hi) {
            next = if lo == 0.0 {
                // Descend fast towards a power-law peak at 0: by 1/16, then by
                // squaring, at most 60 decades per step, into the subnormals.
                (hi * hi.clamp_to(1e-60, 0.0625)).max(f64::from_bits(1))
            } else if hi > 4.0 * lo {
                libm::sqrt(lo * hi)
            } else {
                0.5 * (lo + hi)
            };
        }
        if (next - t).abs() <= 4.0 * f64::EPSILON * next || !(next > lo && next < hi) {
            return next.clamp_to(lo, hi);
        }
        t = next;
    }
    t
}
