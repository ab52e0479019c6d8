//! Properties over random valid inputs (proptest, shrinking on, fixed seed).
//!
//! Tolerances (f64): quantities recomputed from a sampled point carry the
//! rounding of the point, about ε(|x0| + s) absolute in each coordinate, i.e.
//! a relative error of ε(|x0| + s)/min(d1, d2) in the distances and angles at
//! the end points. Inputs here keep |x0| + s ≤ 20 and the strategies keep
//! the uniform numbers 1e-6 away from the edges, so min(d1, d2) ≳ 1e-6 s and
//! the worst relative error is ~1e-9; a density whose log-derivative in θ is
//! at most 1/(1 − |g|) ≤ 200 turns that into ≤ 2e-7. The checks use 1e-6
//! (relative) or that bound scaled by the local conditioning where stated.
//! A wrong formula misses by O(1), far outside.

use crate::harness::PhaseSpec;
use glam::DVec3;
use omnee::medium::Region;
use omnee::mis::{Heuristic, OneSample, multi_sample_weight};
use omnee::phase::{Deflection, PhaseFunction};
use omnee::quadrature::integrate_geometric;
use omnee::sampling::{Connection, Directions, Distance, Equiangular, Omnee, Technique};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x6f6d_6e65_6506),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Every phase function family with parameters from its whole valid range
/// (|g| ≤ 0.995; the stability tests go to 0.9999).
fn phase_spec() -> impl Strategy<Value = PhaseSpec> {
    let g = -0.995..0.995f64;
    prop_oneof![
        Just(PhaseSpec::Isotropic),
        Just(PhaseSpec::Rayleigh),
        g.clone().prop_map(PhaseSpec::Hg),
        (g.clone(), g.clone(), 0.0..=1.0f64).prop_map(|(a, b, w)| PhaseSpec::TwoTerm(a, b, w)),
        (g, 0.0..=1000.0f64).prop_map(|(g, a)| PhaseSpec::Draine(g, a)),
        (0.001..0.499f64, 1.001..1.5f64).prop_map(|(b, n)| PhaseSpec::Ff(b, n)),
        (0.1..50.0f64).prop_map(PhaseSpec::Mie),
    ]
}

fn point() -> impl Strategy<Value = DVec3> {
    (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// End points at least 0.05 apart.
fn ends() -> impl Strategy<Value = (DVec3, DVec3)> {
    (point(), point()).prop_filter("x0 and x2 apart", |(a, b)| (*a - *b).length() > 0.05)
}

/// A uniform number away from the edges where the map degenerates (θ = 0 is
/// covered by the stability tests).
fn unit() -> impl Strategy<Value = f64> {
    1e-6..(1.0 - 1e-6)
}

fn u3() -> impl Strategy<Value = [f64; 3]> {
    (unit(), unit(), unit()).prop_map(|(a, b, c)| [a, b, c])
}

/// How rays leave `x2`, and the medium region.
#[derive(Clone, Copy, Debug)]
struct Ray {
    cosine: Option<DVec3>,
    slab: Option<(f64, f64)>,
    sigma: f64,
}

fn ray() -> impl Strategy<Value = Ray> {
    (
        prop::option::of(point().prop_filter("non-zero", |n| n.length() > 1e-3)),
        prop::option::of((-3.0..3.0f64, 0.05..4.0f64).prop_map(|(lo, w)| (lo, lo + w))),
        0.05..5.0f64,
    )
        .prop_map(|(cosine, slab, sigma)| Ray {
            cosine,
            slab,
            sigma,
        })
}

impl Ray {
    fn directions(&self) -> Directions<f64> {
        self.cosine
            .map_or(Directions::Sphere, |n| Directions::cosine(n).unwrap())
    }
    fn region(&self) -> Region<f64> {
        self.slab
            .map_or(Region::Everywhere, |(lo, hi)| Region::slab(lo, hi).unwrap())
    }
}

/// `|a − b| ≤ tol · max(|a|, |b|)`.
fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs())
}

/// The relative spread of `p` over the deflections `θ ± 10 Δθ`: how much a
/// rounding `Δθ` in the recomputed angle may move a density. Bounded by
/// 20 Δθ/(1 − |g|) for HG, but unbounded for Fournier–Forand, whose forward
/// peak is singular.
fn spread<P: PhaseFunction<f64>>(p: &P, theta: f64, dtheta: f64) -> f64 {
    let at = |t: f64| p.eval(Deflection::from_theta(t.clamp(0.0, PI)));
    let mid = at(theta);
    let (lo, hi) = (at(theta - 10.0 * dtheta), at(theta + 10.0 * dtheta));
    ((lo - mid).abs().max((hi - mid).abs())) / mid
}

/// The checks every technique's sample must pass: finite, ≥ 0, `pdf(x1)`
/// equals the returned pdf, and (for the non-MIS techniques and balance MIS)
/// the weight equals `kernel(x1) / pdf(x1)`. Both sides recompute θ from
/// the rounded point `x1`, to `Δθ ≈ 1e-15 (|x0| + |x2| + s)(1/d1 + 1/d2)`:
/// the tolerance is 1e-6 plus the phase function's spread over that.
fn check_sample<P: PhaseFunction<f64>>(
    name: &str,
    t: &dyn Technique<f64>,
    connection: &Connection<f64>,
    phase: &P,
    u: [f64; 3],
    weight_is_kernel_over_pdf: bool,
) -> Result<(), TestCaseError> {
    let Some(s) = t.sample(u) else { return Ok(()) };
    prop_assert!(
        s.x1.is_finite() && s.pdf.is_finite() && s.pdf > 0.0,
        "{name}: {s:?}"
    );
    prop_assert!(s.weight.is_finite() && s.weight >= 0.0, "{name}: {s:?}");
    if s.pdf == f64::MAX {
        return Ok(()); // saturated: the true density overflowed
    }
    let axis = &connection.axis;
    let (d, d1, d2) = connection.deflection(s.x1).unwrap();
    let scale = axis.x0.length() + axis.x2.length() + axis.s;
    let dtheta = 1e-15 * scale * (1.0 / d1 + 1.0 / d2);
    let tol = 1e-6 + spread(phase, d.theta, dtheta);
    let again = t.pdf(s.x1);
    prop_assert!(
        close(again, s.pdf, tol),
        "{name}: pdf(x1) = {again:e}, sample.pdf = {:e} (tol {tol:e})",
        s.pdf
    );
    if weight_is_kernel_over_pdf {
        let want = connection.kernel(phase, s.x1) / s.pdf;
        prop_assert!(
            close(s.weight, want, tol),
            "{name}: weight {:e}, kernel/pdf {want:e} (tol {tol:e})",
            s.weight
        );
    }
    Ok(())
}

/// `|a − b|` on the circle of circumference 1 (φ/2π wraps).
fn circular(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

proptest! {
    #![proptest_config(config(400))]

    #[test]
    fn omnee_sample_pdf_weight_and_inverse_agree(
        (x0, x2) in ends(), theta_max in 0.05..=PI, spec in phase_spec(), u in u3()
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let t = Omnee::new(c, &*phase);
        check_sample("omnee", &t, &c, &&*phase, u, true)?;
        let Some(s) = t.sample(u) else { return Ok(()) };
        // The closed-form weight is θ / (s sin θ), bounded for θ < π.
        let theta = phase.sample(u[0]).theta;
        let s_len = (x2 - x0).length();
        prop_assert!(close(s.weight, theta / (s_len * theta.sin()), 1e-9), "{s:?}");
        if spec.inverse_cdf() {
            let back = t.invert(s.x1);
            prop_assert!(back.is_some(), "invert(sample({u:?})) = None");
            let back = back.unwrap();
            // The angles recomputed from the rounded x1 are off by about
            // Δθ = 1e-15 (|x0| + |x2| + s)(1/d1 + 1/d2) (the point's rounding
            // over the arms of the triangle).
            let (d1, d2) = ((s.x1 - x0).length(), (s.x1 - x2).length());
            let dtheta = 1e-15 * (x0.length() + x2.length() + s_len) * (1.0 / d1 + 1.0 / d2);
            // u0 = cdf(θ): off by at most the cdf's mass within θ ± 10 Δθ
            // (tiny except at a singular forward peak, Fournier–Forand).
            let mass = phase.cdf(Deflection::from_theta(theta + 10.0 * dtheta))
                - phase.cdf(Deflection::from_theta((theta - 10.0 * dtheta).max(0.0)));
            prop_assert!((back[0] - u[0]).abs() < 1e-9 + mass, "{u:?} -> {back:?}");
            // β/θ: Δθ relative to θ (the arc's angular width).
            prop_assert!((back[1] - u[1]).abs() < 1e-9 + 10.0 * dtheta / theta, "{u:?} -> {back:?}");
            // φ is undefined on the axis: its error is the point's rounding
            // over its distance from the axis, h = d1 sin α.
            let h = d1 * ((1.0 - u[1]) * theta).sin();
            let scale = x0.length() + x2.length() + s_len;
            prop_assert!(circular(back[2], u[2]) < 1e-9 + 1e-14 * scale / h, "{u:?} -> {back:?}");
        }
    }

    #[test]
    fn ray_techniques_sample_pdf_weight_and_inverse_agree(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), u in u3(), theta_max in 0.05..=PI
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let eq = Equiangular::new(c, &*phase, ray.directions(), ray.region());
        let di = Distance::new(c, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        for (name, t) in [("equiangular", &eq as &dyn Technique<f64>), ("distance", &di)] {
            check_sample(name, t, &c, &&*phase, u, true)?;
            let Some(s) = t.sample(u) else { continue };
            let Some(back) = t.invert(s.x1) else {
                return Err(TestCaseError::fail(format!("{name}: invert(sample({u:?})) = None")));
            };
            // Directions: u0 from z or the radial part, u1 from the azimuth,
            // which is undefined where the radial part vanishes (u0 → 0, 1).
            let d2 = (s.x1 - x2).length();
            let noise = 1e-13 * (x2.length() + d2) / d2;
            prop_assert!((back[0] - u[0]).abs() < 1e-7 + noise, "{name}: {u:?} -> {back:?}");
            let radial = (u[0] * (1.0 - u[0])).sqrt();
            prop_assert!(circular(back[1], u[1]) < 1e-7 + noise / radial, "{name}: {u:?} -> {back:?}");
            // Along the ray: the distance's rounding relative to the segment.
            prop_assert!((back[2] - u[2]).abs() < 1e-6 + noise, "{name}: {u:?} -> {back:?}");
        }
    }

    #[test]
    fn pdfs_are_finite_and_non_negative_everywhere(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), x1 in point(), theta_max in 0.05..=PI
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let om = Omnee::new(c, &*phase);
        let eq = Equiangular::new(c, &*phase, ray.directions(), ray.region());
        let di = Distance::new(c, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        for (name, t) in [("omnee", &om as &dyn Technique<f64>), ("equiangular", &eq), ("distance", &di)] {
            let p = t.pdf(x1);
            prop_assert!(p.is_finite() && p >= 0.0, "{name}: pdf({x1}) = {p}");
        }
        let k = c.kernel(&&*phase, x1);
        prop_assert!(k.is_finite() && k >= 0.0, "kernel {k}");
    }

    #[test]
    fn mis_weights_sum_to_one(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), x1 in point(),
        counts in (0.1..10.0f64, 0.1..10.0f64, 0.1..10.0f64), power in any::<bool>()
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, FRAC_PI_2).unwrap();
        let full = Connection::new(x0, x2, PI).unwrap();
        let om = Omnee::new(c, &*phase);
        let eq = Equiangular::new(full, &*phase, ray.directions(), ray.region());
        let di = Distance::new(full, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        let techniques: [&dyn Technique<f64>; 3] = [&om, &eq, &di];
        let counts = [counts.0, counts.1, counts.2];
        let heuristic = if power { Heuristic::Power } else { Heuristic::Balance };
        let pdfs = techniques.map(|t| t.pdf(x1));
        let sum: f64 = (0..3)
            .map(|i| multi_sample_weight(&techniques, &counts, i, x1, pdfs[i], heuristic))
            .sum();
        if pdfs.iter().any(|&p| p > 0.0) {
            prop_assert!((sum - 1.0).abs() < 1e-12, "Σ w = {sum}, pdfs {pdfs:?}");
        } else {
            prop_assert!(sum == 0.0, "Σ w = {sum} where no technique samples");
        }
        // The two-technique helpers are complementary too.
        let (a, b) = (pdfs[0] * counts[0], pdfs[1] * counts[1]);
        if a > 0.0 || b > 0.0 {
            let bal = omnee::mis::balance_heuristic(counts[0], pdfs[0], counts[1], pdfs[1])
                + omnee::mis::balance_heuristic(counts[1], pdfs[1], counts[0], pdfs[0]);
            let pow = omnee::mis::power_heuristic(counts[0], pdfs[0], counts[1], pdfs[1])
                + omnee::mis::power_heuristic(counts[1], pdfs[1], counts[0], pdfs[0]);
            prop_assert!((bal - 1.0).abs() < 1e-12 && (pow - 1.0).abs() < 1e-12, "{bal} {pow}");
        }
    }

    #[test]
    fn one_sample_balance_weight_is_kernel_over_mixture_pdf(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), u in u3(),
        c in (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64)
    ) {
        let phase = spec.build::<f64>();
        let full = Connection::new(x0, x2, PI).unwrap();
        let om = Omnee::new(Connection::new(x0, x2, FRAC_PI_2).unwrap(), &*phase);
        let eq = Equiangular::new(full, &*phase, ray.directions(), ray.region());
        let di = Distance::new(full, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        let mis = OneSample::new([&om as &dyn Technique<f64>, &eq, &di], [c.0, c.1, c.2], Heuristic::Balance).unwrap();
        // Balance one-sample MIS samples the mixture Σ c_j p_j, and its weight
        // w_i k / (c_i p_i) = k / Σ c_j p_j (Veach §9.2.4).
        check_sample("one-sample balance", &mis, &full, &&*phase, u, true)?;
        let power = OneSample::new([&om as &dyn Technique<f64>, &eq, &di], [c.0, c.1, c.2], Heuristic::Power).unwrap();
        check_sample("one-sample power", &power, &full, &&*phase, u, false)?;
    }
}

/// `2π ∫ g(θ) p(θ) sin θ dθ` over [0, π], split at π/2 with geometric panels
/// towards both poles (forward and backward peaks).
fn moment<P: PhaseFunction<f64> + ?Sized>(p: &P, g: impl Fn(f64) -> f64) -> f64 {
    let forward = integrate_geometric(
        |t| {
            let d = Deflection::from_theta(t);
            p.eval(d) * d.sin() * g(d.cos())
        },
        0.0,
        FRAC_PI_2,
        40,
        1e-11,
    );
    // θ = π − t with both versines from t, exact near the back pole.
    let backward = integrate_geometric(
        |t| {
            let (s, c) = (0.5 * t).sin_cos();
            let d = Deflection {
                theta: PI - t,
                one_minus_cos: 2.0 * c * c,
                one_plus_cos: 2.0 * s * s,
            };
            p.eval(d) * d.sin() * g(d.cos())
        },
        0.0,
        FRAC_PI_2,
        40,
        1e-11,
    );
    TAU * (forward + backward)
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn phase_functions_normalise_sample_their_cdf_and_have_their_mean_cosine(
        spec in phase_spec(), u in 0.0..1.0f64, theta in 0.0..PI
    ) {
        let p = spec.build::<f64>();
        // The bound: ∫ p dω = 1 to 1e-4 (the quadrature itself is
        // good to ~1e-10 on these smooth integrands).
        let mass = moment(&*p, |_| 1.0);
        prop_assert!((mass - 1.0).abs() < 1e-4, "{spec:?}: ∫ p dω = {mass}");
        let mean = moment(&*p, |c| c);
        prop_assert!((mean - p.mean_cosine()).abs() < 1e-4, "{spec:?}: ⟨cos θ⟩ = {mean}, claimed {}", p.mean_cosine());
        // The cdf is the integral of eval (to the quadrature's accuracy).
        let d = Deflection::from_theta(theta);
        let partial = TAU * integrate_geometric(
            |t| {
                let e = Deflection::from_theta(t);
                p.eval(e) * e.sin()
            },
            0.0,
            theta,
            40,
            1e-11,
        );
        prop_assert!((p.cdf(d) - partial).abs() < 1e-6, "{spec:?}: cdf({theta}) = {}, ∫ = {partial}", p.cdf(d));
        // Sampling: the deflection is valid, pdf = eval, and for inverse-CDF
        // samplers cdf(sample(u)) = u and invert(sample(u)) = u.
        let s = p.sample(u);
        prop_assert!(s.is_finite() && (0.0..=PI).contains(&s.theta), "{spec:?}: sample({u}) = {s:?}");
        prop_assert!((s.one_minus_cos + s.one_plus_cos - 2.0).abs() < 1e-12, "{s:?}");
        prop_assert!(p.pdf(s) == p.eval(s), "{spec:?}");
        if spec.inverse_cdf() {
            prop_assert!((p.cdf(s) - u).abs() < 1e-9, "{spec:?}: cdf(sample({u})) = {}", p.cdf(s));
            let back = p.invert(s);
            prop_assert!(back.is_some_and(|b| (b - u).abs() < 1e-9), "{spec:?}: invert = {back:?}");
        }
    }
}
