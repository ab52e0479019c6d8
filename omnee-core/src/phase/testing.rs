//! Shared checks for the phase-function tests (f64 quadrature references).

extern crate std;

use super::{Deflection, PhaseFunction};
use crate::quadrature::{integrate, integrate_geometric};
use crate::real::Real;
use core::f64::consts::{FRAC_PI_2, PI, TAU};

/// A deflection `π − t` built from `t` without losing `t`'s digits.
pub fn from_pi(t: f64) -> Deflection<f64> {
    let (s, c) = libm::sincos(0.5 * t);
    Deflection {
        theta: PI - t,
        one_minus_cos: 2.0 * c * c,
        one_plus_cos: 2.0 * s * s,
    }
}

/// `2π ∫_0^θ p sin θ' dθ'` for θ ≤ π/2, geometric panels towards 0.
pub fn forward_mass<P: PhaseFunction<f64>>(p: &P, theta: f64) -> f64 {
    TAU * integrate_geometric(
        |t| {
            let d = Deflection::from_theta(t);
            p.eval(d) * d.sin()
        },
        0.0,
        theta,
        50,
        1e-12,
    )
}

/// `2π ∫_θ^π p sin θ' dθ'` for θ ≥ π/2, geometric panels towards π.
pub fn backward_mass<P: PhaseFunction<f64>>(p: &P, theta: f64) -> f64 {
    TAU * integrate_geometric(
        |t| {
            let d = from_pi(t);
            p.eval(d) * d.sin()
        },
        0.0,
        PI - theta,
        50,
        1e-12,
    )
}

/// `|2π ∫ p sin θ dθ − 1|`, split at π/2 and refined towards both poles.
pub fn normalisation_error<P: PhaseFunction<f64>>(p: &P) -> f64 {
    (forward_mass(p, FRAC_PI_2) + backward_mass(p, FRAC_PI_2) - 1.0).abs()
}

/// `max |cdf(θ) − quadrature|` over a set of angles (complement near π).
pub fn cdf_error<P: PhaseFunction<f64>>(p: &P) -> f64 {
    let mut worst = 0.0f64;
    for &t in &[
        1e-6,
        1e-3,
        0.01,
        0.1,
        0.5,
        1.0,
        FRAC_PI_2,
        2.0,
        2.5,
        3.0,
        PI - 1e-3,
    ] {
        let d = Deflection::from_theta(t);
        let err = if t <= FRAC_PI_2 {
            (p.cdf(d) - forward_mass(p, t)).abs()
        } else {
            (1.0 - p.cdf(d) - backward_mass(p, t)).abs()
        };
        worst = worst.max(err);
    }
    worst
}

/// `|⟨cos θ⟩ − 2π ∫ cos θ p sin θ dθ|`.
pub fn mean_error<P: PhaseFunction<f64>>(p: &P) -> f64 {
    let fwd = TAU
        * integrate_geometric(
            |t| {
                let d = Deflection::from_theta(t);
                d.cos() * p.eval(d) * d.sin()
            },
            0.0,
            FRAC_PI_2,
            50,
            1e-12,
        );
    let bwd = TAU
        * integrate_geometric(
            |t| {
                let d = from_pi(t);
                d.cos() * p.eval(d) * d.sin()
            },
            0.0,
            FRAC_PI_2,
            50,
            1e-12,
        );
    (p.mean_cosine() - fwd - bwd).abs()
}

/// The u grid of the sampling tests: 0, a few tiny values, a uniform grid,
/// values near 1 and `1 − ulp`.
pub fn u_grid<F: Real>() -> impl Iterator<Item = F> {
    let tiny = [0.0, 1e-12, 1e-9, 1e-6, 1e-4];
    let top = [1.0 - 1e-6, 1.0 - 1e-9];
    tiny.into_iter()
        .chain((1..1000).map(|i| i as f64 / 1000.0))
        .chain(top)
        // 1 − 1e-9 rounds to 1 in f32: keep every u below 1.
        .map(|u| F::from_f64(u).min(F::ONE_MINUS_EPSILON))
        .chain(core::iter::once(F::ONE_MINUS_EPSILON))
}

/// `max |cdf(sample(u)) − u|` over [`u_grid`], asserting that θ is monotone
/// in u, every deflection is finite and its versines sum to 2.
pub fn inversion_error<F: Real, P: PhaseFunction<F>>(p: &P) -> f64 {
    let mut worst = 0.0f64;
    let mut last = -1.0f64;
    for u in u_grid::<F>() {
        let d = p.sample(u);
        assert!(d.is_finite(), "u = {u:?}: {d:?}");
        let sum = (d.one_minus_cos + d.one_plus_cos).to_f64();
        assert!((sum - 2.0).abs() < 8.0 * F::EPSILON.to_f64(), "{d:?}");
        assert!(d.cos().abs() <= F::ONE);
        let theta = d.theta.to_f64();
        assert!(theta >= last, "not monotone at u = {u:?}: {theta} < {last}");
        last = theta;
        worst = worst.max((p.cdf(d).to_f64() - u.to_f64()).abs());
    }
    worst
}

/// Asserts `eval` finite and non-negative at θ = 0, tiny angles, π/2 and π.
pub fn assert_eval_finite<F: Real, P: PhaseFunction<F>>(p: &P) {
    for t in [0.0, 1e-30, 1e-12, 1e-6, 1e-3, 1.0, PI - 1e-5, PI - 1e-10] {
        let d = Deflection::from_theta(F::from_f64(t));
        let v = p.eval(d);
        assert!(v.is_finite() && v >= F::ZERO, "θ = {t}: {v:?}");
    }
    for d in [
        Deflection::from_versines(F::ZERO, F::TWO),
        Deflection::from_versines(F::TWO, F::ZERO),
        Deflection::from_versines(F::ONE, F::ONE),
    ] {
        let v = p.eval(d);
        assert!(v.is_finite() && v >= F::ZERO, "{d:?}: {v:?}");
    }
}

/// `max` relative difference of the f32 and f64 `eval` at the angles f64 samples.
pub fn f32_eval_error<P32: PhaseFunction<f32>, P64: PhaseFunction<f64>>(
    p32: &P32,
    p64: &P64,
) -> f64 {
    let mut worst = 0.0f64;
    for u in u_grid::<f64>() {
        let d = p64.sample(u);
        let d32 = Deflection {
            theta: d.theta as f32,
            one_minus_cos: d.one_minus_cos as f32,
            one_plus_cos: d.one_plus_cos as f32,
        };
        // Compare against f64 at the f32-rounded angle: the rounding of the
        // angle itself is not the function's error.
        let dd = Deflection {
            theta: d32.theta as f64,
            one_minus_cos: d32.one_minus_cos as f64,
            one_plus_cos: d32.one_plus_cos as f64,
        };
        // Below the normal range of f32 the angle is not representable
        // (a singular peak is evaluated at the smallest normal instead).
        if d32.one_minus_cos < f32::MIN_POSITIVE {
            continue;
        }
        let a = p64.eval(dd);
        let b = p32.eval(d32) as f64;
        if a > 1e-30 {
            worst = worst.max(((a - b) / a).abs());
        }
    }
    worst
}

/// Empirical check for samplers that do not invert the cdf (mixtures): over a
/// fine stratified u grid the fraction of samples with Θ ≤ θ matches `cdf(θ)`.
pub fn stratified_cdf_error<F: Real, P: PhaseFunction<F>>(p: &P) -> f64 {
    const N: usize = 20000;
    let probes = [1e-4, 1e-3, 0.01, 0.05, 0.2, 0.5, 1.0, 2.0, 3.0];
    let mut below = [0usize; 9];
    for i in 0..N {
        let u = F::from_f64((i as f64 + 0.5) / N as f64);
        let t = p.sample(u).theta.to_f64();
        for (k, &th) in probes.iter().enumerate() {
            if t <= th {
                below[k] += 1;
            }
        }
    }
    let mut worst = 0.0f64;
    for (k, &th) in probes.iter().enumerate() {
        let c = p.cdf(Deflection::from_theta(F::from_f64(th))).to_f64();
        worst = worst.max((below[k] as f64 / N as f64 - c).abs());
    }
    worst
}

/// Prints a measured number when the tests run with `--nocapture`.
pub fn report(what: &str, value: f64) {
    std::eprintln!("{what}: {value:.6e}");
}

/// Integrates a smooth function of θ over [a, b] (for bins of a table).
pub fn plain(f: impl FnMut(f64) -> f64, a: f64, b: f64) -> f64 {
    integrate(f, a, b, 1e-13, 1e-15)
}
