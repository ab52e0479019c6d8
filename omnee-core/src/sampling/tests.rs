//! Tests of the sampling trio: densities against numerically differentiated
//! Jacobians, round trips, and estimates against the quadrature reference.

use super::*;
use crate::medium::{Homogeneous, Region};
use crate::mis::{Heuristic, OmneeMis, OneSample};
use crate::phase::{HenyeyGreenstein, Isotropic};
use crate::reference::PointToPoint;
use crate::rng::SplitMix64;
use glam::DVec3;

fn connection(theta_max: f64) -> Connection<f64> {
    Connection::new(
        DVec3::new(0.2, -0.1, 1.3),
        DVec3::new(0.5, 0.3, 0.4),
        theta_max,
    )
    .unwrap()
}

fn uniform3(rng: &mut SplitMix64) -> [f64; 3] {
    [uniform(rng), uniform(rng), uniform(rng)]
}

/// Mean and standard error of `n` estimates.
fn mean_and_stderr(n: usize, mut estimate: impl FnMut() -> f64) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let x = estimate();
        sum += x;
        sum2 += x * x;
    }
    let mean = sum / n as f64;
    let var = (sum2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

#[test]
fn deflection_between_directions_matches_acos() {
    let c = connection(core::f64::consts::PI);
    let mut rng = SplitMix64::new(5);
    for _ in 0..1000 {
        let x1 = DVec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)) * 4.0 - 2.0;
        let (d, d1, d2) = c.deflection(x1).unwrap();
        let (w1, w2) = ((x1 - c.axis.x0) / d1, (c.axis.x2 - x1) / d2);
        let theta = w1.dot(w2).clamp(-1.0, 1.0).acos();
        assert!((d.theta - theta).abs() < 1e-7, "{d:?} vs {theta}");
        assert!(
            (d.one_minus_cos - (1.0 - w1.dot(w2))).abs() < 1e-12,
            "{d:?}"
        );
        assert!((d.one_plus_cos - (1.0 + w1.dot(w2))).abs() < 1e-12, "{d:?}");
    }
}

/// The techniques of the round-trip tests, over `phase`.
fn with_techniques<P: PhaseFunction<f64> + Copy>(
    phase: P,
    check: impl Fn(&str, &dyn Technique<f64>),
) {
    let c = connection(core::f64::consts::PI);
    let forward = Connection {
        theta_max: core::f64::consts::FRAC_PI_2,
        ..c
    };
    let slab = Region::slab(-0.5, 2.0).unwrap();
    let cosine = Directions::cosine(DVec3::new(0.3, 0.2, 1.0)).unwrap();
    check("omnee", &Omnee::new(forward, phase));
    check("omnee full range", &Omnee::new(c, phase));
    check(
        "equiangular",
        &Equiangular::new(c, phase, Directions::Sphere, Region::Everywhere),
    );
    check(
        "equiangular cosine slab",
        &Equiangular::new(c, phase, cosine, slab),
    );
    check(
        "distance",
        &Distance::new(c, phase, Directions::Sphere, Region::Everywhere, 0.7).unwrap(),
    );
    check(
        "distance cosine slab",
        &Distance::new(c, phase, cosine, slab, 1.3).unwrap(),
    );
}

#[test]
fn sample_pdf_and_invert_round_trip() {
    with_techniques(HenyeyGreenstein::new(0.8).unwrap(), |name, t| {
        let mut rng = SplitMix64::new(13);
        let mut sampled = 0;
        for _ in 0..5000 {
            let u = uniform3(&mut rng);
            let Some(s) = t.sample(u) else { continue };
            sampled += 1;
            let pdf = t.pdf(s.x1);
            assert!(
                (s.pdf - pdf).abs() <= 1e-9 * pdf,
                "{name}: sample pdf {} vs pdf(x1) {pdf}",
                s.pdf
            );
            let back = t
                .invert(s.x1)
                .unwrap_or_else(|| panic!("{name}: no inverse at {u:?}"));
            for k in 0..3 {
                // φ-like coordinates wrap around at 1.
                let e = (back[k] - u[k]).abs();
                assert!(
                    e.min(1.0 - e) < 1e-7,
                    "{name}: invert(sample({u:?})) = {back:?}"
                );
            }
            let again = t.sample(back).unwrap();
            assert!(
                (again.x1 - s.x1).length() < 1e-8 * (1.0 + s.x1.length()),
                "{name}: {:?} vs {:?}",
                again.x1,
                s.x1
            );
        }
        assert!(
            sampled > 2000,
            "{name}: only {sampled} of 5000 numbers gave a sample"
        );
    });
}

#[test]
fn pdf_is_zero_exactly_where_a_technique_cannot_sample() {
    let hg = HenyeyGreenstein::new(0.5).unwrap();
    let forward = connection(core::f64::consts::FRAC_PI_2);
    let omnee = Omnee::new(forward, hg);
    // Behind x0 on the axis: θ = π ≥ θmax.
    let behind = forward.axis.x0 - forward.axis.e * 0.3;
    assert_eq!(omnee.pdf(behind), 0.0);
    assert!(omnee.invert(behind).is_none());
    // Outside the slab, equiangular and distance sampling have no density.
    let slab = Region::slab(-0.5, 2.0).unwrap();
    let equi = Equiangular::new(forward, hg, Directions::Sphere, slab);
    let dist = Distance::new(forward, hg, Directions::Sphere, slab, 1.0).unwrap();
    let outside = DVec3::new(0.0, 0.0, 3.0);
    assert_eq!(equi.pdf(outside), 0.0);
    assert_eq!(dist.pdf(outside), 0.0);
    // At the end points the integrand is singular: no density is claimed.
    assert_eq!(omnee.pdf(forward.axis.x0), 0.0);
    assert_eq!(omnee.pdf(forward.axis.x2), 0.0);
}

/// One configuration of the point-to-point integral (docs/math.md §5).
struct Config {
    g: f64,
    /// Optical length σt·s.
    tau: f64,
    theta_max: f64,
}

/// Every technique against the quadrature, within 4 standard errors.
///
/// A standard error only means something for an estimator of finite
/// variance, and for a point light at `x0` the baselines alone have none:
/// distance sampling's weight grows like `1/d1²` near `x0` (tail
/// `P(w > x) ∝ x^{−3/2}`), equiangular's like `1/D` as the ray passes `x0`
/// (variance diverges logarithmically), and so does full-range OMNEE's like
/// `1/(π − θ)` without attenuation (docs/math.md §3). So each technique is tested
/// where its estimator has finite variance, and the baselines also inside
/// one-sample MIS with a technique that covers their singularity; their
/// densities are checked exactly by the Jacobian and round-trip tests.
/// Plain equiangular is added for g ≤ 0.5, where its logarithmic divergence
/// is far outside what 10⁶ samples can see.
///
/// Tolerance: 4 standard errors is a two-sided normal tail of 6.3·10⁻⁵ per
/// comparison. Power: a relative standard error above 5 % is refused, so a
/// factor-of-1.25 bug cannot hide in the noise.
#[test]
fn every_technique_agrees_with_the_quadrature_reference() {
    use core::f64::consts::{FRAC_PI_2 as HALF, PI};
    let configs = [
        Config {
            g: -0.5,
            tau: 1.0,
            theta_max: PI,
        },
        Config {
            g: -0.5,
            tau: 0.25,
            theta_max: HALF,
        },
        Config {
            g: 0.0,
            tau: 0.0,
            theta_max: HALF,
        },
        Config {
            g: 0.0,
            tau: 1.0,
            theta_max: PI,
        },
        Config {
            g: 0.0,
            tau: 3.0,
            theta_max: PI,
        },
        Config {
            g: 0.5,
            tau: 0.25,
            theta_max: HALF,
        },
        Config {
            g: 0.5,
            tau: 3.0,
            theta_max: PI,
        },
        Config {
            g: 0.9,
            tau: 0.0,
            theta_max: HALF,
        },
        Config {
            g: 0.9,
            tau: 1.0,
            theta_max: PI,
        },
        Config {
            g: 0.98,
            tau: 0.25,
            theta_max: HALF,
        },
        Config {
            g: 0.98,
            tau: 1.0,
            theta_max: PI,
        },
        Config {
            g: 0.997,
            tau: 0.25,
            theta_max: HALF,
        },
        Config {
            g: 0.997,
            tau: 3.0,
            theta_max: PI,
        },
    ];
    let mut seed = 100;
    let mut compared = 0;
    for cfg in &configs {
        let hg = HenyeyGreenstein::new(cfg.g).unwrap();
        let c = connection(cfg.theta_max);
        let s = c.axis.s;
        let sigma_t = cfg.tau / s;
        let problem =
            PointToPoint::new(c, Homogeneous::from_extinction(0.3, sigma_t).unwrap(), None)
                .unwrap();
        let want = problem.integral(&hg);
        let forward = Connection {
            theta_max: cfg.theta_max.min(HALF),
            ..c
        };
        let omnee = Omnee::new(c, hg);
        let omnee_forward = Omnee::new(forward, hg);
        let equi = Equiangular::new(c, hg, Directions::Sphere, Region::Everywhere);
        // Without attenuation free flight needs some coefficient: use 1/s.
        let dist = Distance::new(
            c,
            hg,
            Directions::Sphere,
            Region::Everywhere,
            sigma_t.max(1.0 / s),
        )
        .unwrap();
        let balance = Heuristic::Balance;
        let omnee_equi = OneSample::new(
            [&omnee_forward as &dyn Technique<f64>, &equi],
            [0.5, 0.5],
            balance,
        )
        .unwrap();
        let omnee_dist = OneSample::new(
            [&omnee as &dyn Technique<f64>, &dist],
            [0.7, 0.3],
            Heuristic::Power,
        )
        .unwrap();
        let omnee_backward = OmneeMis::new(
            omnee,
            &equi,
            0.1,
            crate::phase::Deflection::from_theta(0.75 * PI),
        )
        .unwrap();
        let omnee_has_finite_variance = cfg.theta_max <= HALF || cfg.tau > 0.0;
        // One estimate per call: a technique's vertex, or OmneeMis's pair.
        type Estimator<'a> = std::boxed::Box<dyn FnMut(&mut SplitMix64) -> f64 + 'a>;
        let mut techniques: std::vec::Vec<(&str, &dyn Technique<f64>, usize)> =
            std::vec![("mis omnee(θ<π/2)+equiangular", &omnee_equi, 400_000)];
        if omnee_has_finite_variance {
            techniques.push(("omnee", &omnee, 200_000));
            techniques.push(("mis omnee+distance", &omnee_dist, 400_000));
        }
        if cfg.g <= 0.5 {
            techniques.push(("equiangular", &equi, 1_000_000));
        }
        let mut estimators: std::vec::Vec<(&str, Estimator<'_>, usize)> = techniques
            .into_iter()
            .map(|(name, t, n)| {
                let e: Estimator<'_> = std::boxed::Box::new(move |rng: &mut SplitMix64| {
                    Draw::single(t, || uniform(rng)).sum(|x| problem.estimate(x))
                });
                (name, e, n)
            })
            .collect();
        if omnee_has_finite_variance {
            let e: Estimator<'_> = std::boxed::Box::new(|rng: &mut SplitMix64| {
                omnee_backward
                    .draw(|| uniform(rng))
                    .sum(|x| problem.estimate(x))
            });
            estimators.push(("mis omnee + equiangular behind 3π/4", e, 400_000));
        }
        for (name, mut estimate, n) in estimators {
            seed += 1;
            compared += 1;
            let mut rng = SplitMix64::new(seed);
            let (mean, se) = mean_and_stderr(n, || estimate(&mut rng));
            std::println!(
                "g {} τ {} θmax {:.3} {name}: {mean:.6e} ± {se:.1e} (quadrature {want:.6e})",
                cfg.g,
                cfg.tau,
                cfg.theta_max
            );
            assert!(
                se < 0.05 * want,
                "{name}, g {}: relative standard error {} too large to test",
                cfg.g,
                se / want
            );
            assert!(
                (mean - want).abs() < 4.0 * se,
                "{name}, g {} τ {} θmax {}: {mean} ± {se} vs {want}",
                cfg.g,
                cfg.tau,
                cfg.theta_max
            );
        }
    }
    assert!(compared >= 47, "only {compared} comparisons");
}

#[test]
fn degenerate_input_gives_errors_or_no_sample_never_nan() {
    let p = DVec3::new(1.0, 2.0, 3.0);
    assert!(Connection::new(p, p, 1.0).is_err(), "x0 == x2");
    assert!(Connection::new(DVec3::new(f64::NAN, 0.0, 0.0), p, 1.0).is_err());
    assert!(Connection::new(p, DVec3::new(0.0, f64::INFINITY, 0.0), 1.0).is_err());
    for bad in [0.0, -1.0, 4.0, f64::NAN] {
        assert_eq!(
            Connection::new(DVec3::ZERO, p, bad).unwrap_err().field(),
            "theta_max"
        );
    }
    assert!(
        Distance::new(
            connection(1.0),
            Isotropic,
            Directions::Sphere,
            Region::Everywhere,
            -1.0
        )
        .is_err()
    );
    assert!(Directions::<f64>::cosine(DVec3::ZERO).is_err());

    // u outside [0, 1) is clamped (NaN to 0). The huge pair is what the
    // fuzzer found: it made the sphere direction (1 + 6e231)·z, and
    // equiangular's x1 infinite.
    let extremes = [
        0.0,
        1e-300,
        0.5,
        f64::ONE_MINUS_EPSILON,
        1.0,
        -3.1e231,
        1.6e185,
        f64::NAN,
        f64::NEG_INFINITY,
    ];
    let cosine = Directions::cosine(DVec3::new(1.0, -2.0, 0.5)).unwrap();
    for directions in [Directions::Sphere, cosine] {
        for &a in &extremes {
            for &b in &extremes {
                let omega = directions.sample([a, b]);
                assert!((omega.length() - 1.0).abs() < 1e-15, "{a} {b}: {omega}");
            }
        }
    }
    with_techniques(HenyeyGreenstein::new(0.99).unwrap(), |name, t| {
        for &a in &extremes {
            for &b in &extremes {
                for &c in &extremes {
                    if let Some(s) = t.sample([a, b, c]) {
                        assert!(
                            s.x1.is_finite() && s.pdf.is_finite() && s.weight.is_finite(),
                            "{name} {s:?}"
                        );
                        assert!(s.pdf >= 0.0 && s.weight >= 0.0, "{name} {s:?}");
                    }
                }
            }
        }
        for x1 in [
            DVec3::NAN,
            DVec3::INFINITY,
            DVec3::new(1e308, 1e308, 0.0),
            DVec3::ZERO,
        ] {
            let pdf = t.pdf(x1);
            assert!(pdf.is_finite() && pdf >= 0.0, "{name}: pdf({x1}) = {pdf}");
            let _ = t.invert(x1);
        }
    });
}

#[test]
fn equiangular_is_stable_when_x0_approaches_the_ray() {
    // x2 at the origin, x0 on the +z axis behind the ray's start when the ray
    // points down (u0 = 1 gives ω = −z exactly). Direction numbers close to 1
    // bring the light arbitrarily close to the ray's line: the density must
    // converge to the D = 0 limit `pdf(t) = a / v²`, not blow up or vanish.
    let c = Connection::new(
        DVec3::new(0.0, 0.0, 2.0),
        DVec3::ZERO,
        core::f64::consts::PI,
    )
    .unwrap();
    let equi = Equiangular::new(c, Isotropic, Directions::Sphere, Region::Everywhere);
    let limit = equi.sample([f64::ONE_MINUS_EPSILON, 0.3, 0.5]).unwrap();
    for k in [1e-4, 1e-8, 1e-12] {
        let s = equi.sample([1.0 - k, 0.3, 0.5]).unwrap();
        assert!(s.pdf.is_finite() && s.weight.is_finite());
        let rel = (s.pdf / limit.pdf - 1.0).abs();
        assert!(
            rel < 10.0 * k.sqrt(),
            "1 − u0 = {k}: pdf {} vs limit {}",
            s.pdf,
            limit.pdf
        );
    }
    // Through the light itself (the ray hits x0): no density to sample.
    let through = Connection::new(
        DVec3::new(0.0, 0.0, -2.0),
        DVec3::ZERO,
        core::f64::consts::PI,
    )
    .unwrap();
    let equi = Equiangular::new(through, Isotropic, Directions::Sphere, Region::Everywhere);
    assert!(
        equi.sample([f64::ONE_MINUS_EPSILON, 0.3, 0.5])
            .is_none_or(|s| s.pdf.is_finite())
    );
    // Same in f32, where D underflows sooner.
    let c32 = Connection::<f32>::new(
        glam::Vec3::new(0.0, 0.0, 2.0),
        glam::Vec3::ZERO,
        core::f32::consts::PI,
    )
    .unwrap();
    let e32 = Equiangular::new(c32, Isotropic, Directions::Sphere, Region::Everywhere);
    for u0 in [0.999f32, 0.99999, f32::ONE_MINUS_EPSILON] {
        let s = e32.sample([u0, 0.3, 0.5]).unwrap();
        assert!(
            s.pdf.is_finite() && s.pdf > 0.0 && s.weight.is_finite(),
            "{s:?}"
        );
    }
}

#[test]
fn f32_agrees_with_f64() {
    use glam::Vec3;
    let (x0, x2) = (Vec3::new(0.2, -0.1, 1.3), Vec3::new(0.5, 0.3, 0.4));
    let c32 = Connection::<f32>::new(x0, x2, core::f32::consts::PI).unwrap();
    let c64 = Connection::<f64>::new(x0.as_dvec3(), x2.as_dvec3(), core::f64::consts::PI).unwrap();
    let (h32, h64) = (
        HenyeyGreenstein::new(0.9f32).unwrap(),
        HenyeyGreenstein::new(0.9f64).unwrap(),
    );
    let pairs: [(&str, &dyn Technique<f32>, &dyn Technique<f64>); 3] = [
        ("omnee", &Omnee::new(c32, h32), &Omnee::new(c64, h64)),
        (
            "equiangular",
            &Equiangular::new(c32, h32, Directions::Sphere, Region::Everywhere),
            &Equiangular::new(c64, h64, Directions::Sphere, Region::Everywhere),
        ),
        (
            "distance",
            &Distance::new(c32, h32, Directions::Sphere, Region::Everywhere, 1.0).unwrap(),
            &Distance::new(c64, h64, Directions::Sphere, Region::Everywhere, 1.0).unwrap(),
        ),
    ];
    let mut rng = SplitMix64::new(17);
    for (name, t32, t64) in pairs {
        let mut worst: f64 = 0.0;
        for _ in 0..20_000 {
            let u: [f32; 3] = [uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)];
            let (Some(a), Some(b)) = (t32.sample(u), t64.sample(u.map(f64::from))) else {
                continue;
            };
            // Relative to the geometry: f32 positions carry ~6e-8 relative error.
            let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-30);
            worst = worst.max(rel(a.weight as f64, b.weight));
            // Far along an unbounded ray t ∝ 1/(1 − u2) amplifies rounding of u2
            // (6e-8 / 1e-3 near u2 = 0.999): compare positions relatively.
            assert!(
                (a.x1.as_dvec3() - b.x1).length() < 1e-3 * (1.0 + b.x1.length()),
                "{name}: {a:?} vs {b:?}"
            );
        }
        std::println!("{name}: worst relative f32 weight error {worst:.2e}");
        assert!(worst < 1e-3, "{name}: {worst}");
    }
}
/// `|det ∂x1/∂u|` of a technique's sample map by central differences.
fn jacobian_determinant(t: &dyn Technique<f64>, u: [f64; 3], h: f64) -> Option<f64> {
    let mut columns = [DVec3::ZERO; 3];
    for (k, column) in columns.iter_mut().enumerate() {
        let (mut lo, mut hi) = (u, u);
        lo[k] -= h;
        hi[k] += h;
        *column = (t.sample(hi)?.x1 - t.sample(lo)?.x1) / (2.0 * h);
    }
    Some(columns[0].dot(columns[1].cross(columns[2])).abs())
}

#[test]
fn pdf_is_the_inverse_jacobian_of_the_sample_map() {
    let hg = HenyeyGreenstein::new(0.6).unwrap();
    let c = connection(core::f64::consts::PI);
    let slab = Region::slab(-0.5, 2.0).unwrap();
    let omnee = Omnee::new(c, hg);
    let equi = Equiangular::new(c, hg, Directions::Sphere, Region::Everywhere);
    let equi_cos = Equiangular::new(
        c,
        hg,
        Directions::cosine(DVec3::new(0.3, 0.2, 1.0)).unwrap(),
        slab,
    );
    let dist = Distance::new(c, hg, Directions::Sphere, Region::Everywhere, 0.7).unwrap();
    let dist_slab = Distance::new(c, hg, Directions::cosine(DVec3::Z).unwrap(), slab, 1.3).unwrap();
    let techniques: [(&str, &dyn Technique<f64>); 5] = [
        ("omnee", &omnee),
        ("equiangular", &equi),
        ("equiangular cosine slab", &equi_cos),
        ("distance", &dist),
        ("distance cosine slab", &dist_slab),
    ];
    let mut rng = SplitMix64::new(11);
    for (name, t) in techniques {
        let mut checked = 0;
        while checked < 200 {
            // Stay away from the unit cube's faces so the differences stay inside.
            let u = [0.0; 3].map(|_: f64| 0.01 + 0.98 * uniform::<f64, _>(&mut rng));
            let (Some(s), Some(det)) = (t.sample(u), jacobian_determinant(t, u, 1e-6)) else {
                continue;
            };
            let want = 1.0 / det;
            assert!(
                (s.pdf - want).abs() < 1e-5 * want,
                "{name} at {u:?}: pdf {} vs 1/|J| {want}",
                s.pdf
            );
            checked += 1;
        }
    }
}

/// The f32 sample's pdf and weight against f64 for the same (f32) input:
/// the worst relative differences over `us`.
fn f32_vs_f64_at(
    t32: &dyn Technique<f32>,
    t64: &dyn Technique<f64>,
    us: &[[f32; 3]],
) -> (f64, f64) {
    let rel = |x: f32, y: f64| (x as f64 - y).abs() / y.abs();
    let mut worst = (0.0f64, 0.0f64);
    for &u in us {
        let (a, b) = (t32.sample(u), t64.sample(u.map(f64::from)));
        assert_eq!(a.is_some(), b.is_some(), "{u:?}");
        if let (Some(a), Some(b)) = (a, b) {
            worst.0 = worst.0.max(rel(a.pdf, b.pdf));
            worst.1 = worst.1.max(rel(a.weight, b.weight));
        }
    }
    worst
}

#[test]
fn f32_keeps_its_digits_at_the_edges_of_the_sample_space() {
    // The inputs where f32 used to lose digits, each by a different cause:
    // θ → π (sin θ and sin β from a rounded θ), u2 → 0 for equiangular
    // (t = Δ + v cancelled next to the receiver), and HG with g → 1.
    use glam::Vec3;
    let pi32 = core::f32::consts::PI;
    let (c32, c64) = (
        Connection::new(Vec3::ZERO, Vec3::Z, pi32).unwrap(),
        Connection::new(DVec3::ZERO, DVec3::Z, core::f64::consts::PI).unwrap(),
    );
    let edge = 1.0 - f32::EPSILON / 2.0;
    let tiny = f32::EPSILON / 2.0;
    let mut us = std::vec::Vec::new();
    for u0 in [tiny, 1e-4, 0.3, 0.9998138, 1.0 - 1e-5, edge] {
        for u1 in [tiny, 0.3, 0.5, 0.9, edge] {
            for u2 in [0.0, tiny, 0.7] {
                us.push([u0, u1, u2]);
            }
        }
    }
    for g in [-0.9999f32, -0.9, 0.0, 0.9, 0.9999] {
        let (h32, h64) = (
            HenyeyGreenstein::new(g).unwrap(),
            HenyeyGreenstein::new(g as f64).unwrap(),
        );
        let (pdf, weight) = f32_vs_f64_at(&Omnee::new(c32, h32), &Omnee::new(c64, h64), &us);
        std::println!("omnee g = {g}: pdf {pdf:.1e}, weight {weight:.1e}");
        assert!(
            pdf < 2e-5 && weight < 2e-6,
            "omnee g = {g}: {pdf:e} {weight:e}"
        );
        let (e32, e64) = (
            Equiangular::new(c32, h32, Directions::Sphere, Region::Everywhere),
            Equiangular::new(c64, h64, Directions::Sphere, Region::Everywhere),
        );
        // u0 = 0 or 1 points the ray through x0 (no sample in either precision);
        // keep the equiangular inputs off those two directions.
        let off_axis: std::vec::Vec<_> = us
            .iter()
            .filter(|u| u[0] > 1e-3 && u[0] < 0.999)
            .copied()
            .collect();
        let (pdf, weight) = f32_vs_f64_at(&e32, &e64, &off_axis);
        std::println!("equiangular g = {g}: pdf {pdf:.1e}, weight {weight:.1e}");
        assert!(
            pdf < 2e-5 && weight < 2e-5,
            "equiangular g = {g}: {pdf:e} {weight:e}"
        );
    }
}

#[test]
fn omnee_mis_returns_its_density_and_the_kernel_over_it() {
    use crate::phase::Deflection;
    let c = connection(core::f64::consts::PI);
    for g in [-0.7, 0.0, 0.9] {
        let hg = HenyeyGreenstein::new(g).unwrap();
        let omnee = Omnee::new(c, hg);
        let equi = Equiangular::new(c, hg, Directions::Sphere, Region::Everywhere);
        let cone = Deflection::from_theta(0.75 * core::f64::consts::PI);
        let mis = OmneeMis::new(omnee, &equi, 0.2, cone).unwrap();
        let alone = OmneeMis::new(omnee, &equi, 0.0, cone).unwrap();
        let mut rng = SplitMix64::new(31);
        let (mut behind, mut companions) = (0, 0);
        for _ in 0..20_000 {
            let draw = mis.draw(|| uniform(&mut rng));
            let (u, pair) = (draw.u, draw.vertices);
            assert_eq!(draw.taken, if u[3] < 0.2 { 6 } else { 4 });
            assert_eq!(pair, mis.sample(u), "g {g}: {u:?}");
            // Rate 0 is OMNEE itself.
            let [a, b, c3] = [u[0], u[1], u[2]];
            assert_eq!(
                alone.sample(u),
                [omnee.sample([a, b, c3]), None],
                "g {g}: {u:?}"
            );
            // The companion comes with probability 0.2 (u[3] < 0.2).
            assert!(pair[1].is_none() || u[3] < 0.2);
            for (k, s) in pair.iter().enumerate() {
                let Some(s) = s else { continue };
                let (d, _, _) = c.deflection(s.x1).unwrap();
                // Off the cone's edge, where the sampled and the recomputed θ
                // may classify a point differently by rounding.
                if (d.one_minus_cos / cone.one_minus_cos - 1.0).abs() < 1e-9 {
                    continue;
                }
                let is_behind = d.one_minus_cos > cone.one_minus_cos;
                behind += usize::from(is_behind);
                companions += k;
                let pdf = mis.pdf(s.x1);
                assert!((pdf / s.pdf - 1.0).abs() < 1e-9, "g {g}: {pdf} vs {s:?}");
                let kernel = c.kernel(&hg, s.x1);
                assert!(
                    (kernel / s.pdf / s.weight - 1.0).abs() < 1e-9,
                    "g {g}: k/pdf {} vs weight {}",
                    kernel / s.pdf,
                    s.weight
                );
                // The companion returns points behind the cone only.
                assert!(k == 0 || is_behind);
            }
        }
        assert!(
            behind > 100 && companions > 100,
            "g {g}: {behind} {companions}"
        );
        // The recommended combination is rate 0.05 behind 3π/4.
        type Mis<'a> = OmneeMis<'a, f64, HenyeyGreenstein<f64>>;
        let recommended = OmneeMis::recommended(omnee, &equi);
        let cone = Deflection::from_theta(Mis::THETA_MIN);
        let spelled_out = OmneeMis::new(omnee, &equi, Mis::RATE, cone).unwrap();
        for _ in 0..2000 {
            let draw = recommended.draw(|| uniform(&mut rng));
            assert_eq!(
                draw.vertices,
                spelled_out.sample(draw.u),
                "g {g}: {:?}",
                draw.u
            );
        }
    }
}

#[test]
fn equiangular_keeps_its_f32_digits_when_the_ray_grazes_the_light() {
    // x0 1e-5 off the +z ray from x2 at s = 100 (1e-7 rad): the sampled
    // vertex lies 1e-5 from x0 where t ≈ 100 carries only 8e-6 absolute
    // precision in f32, so d1 must come from the offset to the foot of x0.
    use glam::Vec3;
    let (x0, x2) = (
        Vec3::new(25.00001, -50.0, 112.5),
        Vec3::new(25.0, -50.0, 12.5),
    );
    let pi = core::f32::consts::PI;
    let c32 = Connection::new(x0, x2, pi).unwrap();
    let c64 = Connection::new(x0.as_dvec3(), x2.as_dvec3(), core::f64::consts::PI).unwrap();
    let e32 = Equiangular::new(c32, Isotropic, Directions::Sphere, Region::Everywhere);
    let e64 = Equiangular::new(c64, Isotropic, Directions::Sphere, Region::Everywhere);
    let mut us = std::vec::Vec::new();
    for i in 0..64 {
        // u0 = 0: the ray along +z, exactly.
        us.push([0.0, (i as f32 + 0.5) / 64.0, (i as f32 + 0.25) / 64.0]);
    }
    let (pdf, weight) = f32_vs_f64_at(&e32, &e64, &us);
    std::println!("grazing ray: pdf {pdf:.1e}, weight {weight:.1e}");
    assert!(pdf < 1e-5 && weight < 1e-5, "{pdf:e} {weight:e}");
}

#[test]
fn densities_at_a_vertex_keep_their_digits_next_to_the_end_points() {
    // x0 far from the origin and the vertices within 1e-4 s of an end point:
    // the f32 point itself holds |x1 − x0| to ~ε|x0|/d1 ≈ 1e-2 relative, the
    // offsets as sampled to ~ε. Each technique's density at the other's
    // vertex, f32 against f64 (same uniforms, same geometry).
    use glam::Vec3;
    let (x0, x2) = (Vec3::new(100.0, -50.0, 30.0), Vec3::new(100.5, -49.6, 30.3));
    let c32 = Connection::<f32>::new(x0, x2, core::f32::consts::PI).unwrap();
    let c64 = Connection::<f64>::new(x0.as_dvec3(), x2.as_dvec3(), core::f64::consts::PI).unwrap();
    let (h32, h64) = (
        HenyeyGreenstein::new(-0.5f32).unwrap(),
        HenyeyGreenstein::new(-0.5).unwrap(),
    );
    let (o32, o64) = (Omnee::new(c32, h32), Omnee::new(c64, h64));
    let e32 = Equiangular::new(c32, h32, Directions::Sphere, Region::Everywhere);
    let e64 = Equiangular::new(c64, h64, Directions::Sphere, Region::Everywhere);
    let rel = |a: f32, b: f64| (a as f64 - b).abs() / b.abs();
    let (mut at_point, mut at_vertex, mut checked) = (0.0f64, 0.0f64, 0);
    for &u1 in &[1e-5f32, 3e-5, 1e-4, 1.0 - 1e-4, 1.0 - 3e-5] {
        for i in 0..64 {
            let u = [(i as f32 + 0.5) / 64.0, u1, 0.37];
            let (Some((_, v32, _)), Some((_, v64, _))) = (
                o32.sample_vertex_deflection(u),
                o64.sample_vertex_deflection(u.map(f64::from)),
            ) else {
                continue;
            };
            // Equiangular's density at OMNEE's vertex (f64 from its own
            // offsets, exact to ~1e-16).
            let want = e64.pdf_vertex(&v64);
            if !(want > 0.0 && want.is_finite()) {
                continue;
            }
            at_point = at_point.max(rel(e32.pdf(v32.x1), want));
            at_vertex = at_vertex.max(rel(e32.pdf_vertex(&v32), want));
            checked += 1;
        }
    }
    std::println!(
        "equiangular's pdf at OMNEE vertices next to an end ({checked}): f32 at the point {at_point:.1e}, at the vertex {at_vertex:.1e}"
    );
    assert!(checked > 100);
    assert!(at_vertex < 1e-4, "{at_vertex:e}");
    assert!(at_point > 10.0 * at_vertex, "{at_point:e} vs {at_vertex:e}");
    // And the other way: OMNEE's density at equiangular's vertices.
    let (mut at_point, mut at_vertex, mut checked) = (0.0f64, 0.0f64, 0);
    for i in 0..4096 {
        let u = [
            (i % 64) as f32 / 64.0 + 0.004,
            (i / 64) as f32 / 64.0 + 0.004,
            1e-5,
        ];
        let (Some((_, v32)), Some((_, v64))) = (
            e32.sample_vertex(u, &c32),
            e64.sample_vertex(u.map(f64::from), &c64),
        ) else {
            continue;
        };
        let want = o64.pdf_vertex(&v64);
        if !(want > 0.0 && want.is_finite()) {
            continue;
        }
        at_point = at_point.max(rel(o32.pdf(v32.x1), want));
        at_vertex = at_vertex.max(rel(o32.pdf_vertex(&v32), want));
        checked += 1;
    }
    std::println!(
        "OMNEE's pdf at equiangular vertices next to x2 ({checked}): f32 at the point {at_point:.1e}, at the vertex {at_vertex:.1e}"
    );
    assert!(checked > 100);
    assert!(at_vertex < 1e-4, "{at_vertex:e}");
}

/// Segments of the ray sampler: `x0` off the ray, next to it, on its line
/// behind and ahead of the segment, an infinite segment, and a segment that
/// starts past the foot of `x0`.
fn segments() -> [(DVec3, DVec3, DVec3, f64, f64); 6] {
    let o = DVec3::new(0.1, -0.2, 0.3);
    [
        (
            DVec3::new(0.0, 1.0, 1.0),
            o,
            DVec3::new(0.0, 0.0, 1.0),
            0.0,
            2.0,
        ),
        (DVec3::new(1e-4, 0.0, 1.0), DVec3::ZERO, DVec3::Z, 0.0, 3.0),
        (DVec3::new(0.0, 0.0, -1.0), DVec3::ZERO, DVec3::Z, 0.0, 3.0),
        (DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Z, 0.5, 3.0),
        (
            DVec3::new(2.0, 1.0, 0.5),
            o,
            DVec3::new(1.0, 1.0, 0.0),
            0.0,
            f64::INFINITY,
        ),
        (
            DVec3::new(0.0, 0.3, 0.0),
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, -2.0),
            1.5,
            4.0,
        ),
    ]
}

#[test]
fn equiangular_segment_pdf_integrates_to_one_and_is_sampled_exactly() {
    use crate::quadrature::integrate;
    for (x0, o, w, ta, tb) in segments() {
        let s = EquiangularSegment::new(x0, o, w, ta, tb).unwrap();
        // ∫ pdf = 1 over the segment (an infinite one mapped by t = ta + x/(1 − x)).
        let total = if tb.is_finite() {
            integrate(|t| s.pdf(t), ta, tb, 1e-12, 0.0)
        } else {
            integrate(
                |x| s.pdf(ta + x / (1.0 - x)) / ((1.0 - x) * (1.0 - x)),
                0.0,
                1.0,
                1e-12,
                0.0,
            )
        };
        assert!(
            (total - 1.0).abs() < 1e-8,
            "{x0} {o} {w} [{ta}, {tb}]: ∫ pdf = {total}"
        );
        assert_eq!(s.pdf(ta - 1e-3), 0.0);
        if tb.is_finite() {
            assert_eq!(s.pdf(tb * (1.0 + 1e-9) + 1e-9), 0.0);
        }
        let mut rng = SplitMix64::new(11);
        for i in 0..2000 {
            let u = if i < 2 {
                i as f64
            } else {
                uniform::<f64, _>(&mut rng)
            };
            let Some(d) = s.sample(u) else {
                assert!(u == 1.0 && tb.is_infinite(), "u = {u}: no sample");
                continue;
            };
            assert!(d.t >= ta && d.t <= tb && d.t.is_finite(), "u = {u}: {d:?}");
            // The density it returns is pdf(t), and dt/du = 1/pdf (the
            // inverse CDF's derivative, by central differences).
            let pdf = s.pdf(d.t);
            assert!(
                (d.pdf - pdf).abs() <= 1e-9 * pdf,
                "u = {u}: {} vs {pdf}",
                d.pdf
            );
            if u > 1e-3 && u < 1.0 - 1e-3 {
                let h = 1e-6;
                let dt = (s.sample(u + h).unwrap().t - s.sample(u - h).unwrap().t) / (2.0 * h);
                assert!(
                    (dt * pdf - 1.0).abs() < 1e-5,
                    "u = {u}: dt/du · pdf = {}",
                    dt * pdf
                );
                let back = s.invert(d.t);
                assert!((back - u).abs() < 1e-9, "u = {u} → t = {} → {back}", d.t);
            }
        }
    }
}

#[test]
fn equiangular_segment_scales_exactly_and_refuses_bad_input() {
    let (x0, o, w) = (
        DVec3::new(0.3, 0.7, 1.1),
        DVec3::new(-0.2, 0.1, 0.0),
        DVec3::X,
    );
    let one = EquiangularSegment::new(x0, o, w, 0.25, 2.0).unwrap();
    for k in [-1000, -300, -40, 40, 300, 1000] {
        let l = 2f64.powi(k);
        let scaled = EquiangularSegment::new(x0 * l, o * l, w, 0.25 * l, 2.0 * l).unwrap();
        for u in [0.0, 0.1, 0.5, 0.9, 1.0] {
            let (a, b) = (one.sample(u).unwrap(), scaled.sample(u).unwrap());
            assert_eq!(b.t, a.t * l, "2^{k}, u = {u}");
            assert_eq!(b.pdf, a.pdf / l, "2^{k}, u = {u}");
            assert_eq!(scaled.invert(b.t), one.invert(a.t), "2^{k}, u = {u}");
        }
    }
    // f32 agrees with f64.
    let f =
        EquiangularSegment::<f32>::new(x0.as_vec3(), o.as_vec3(), w.as_vec3(), 0.25, 2.0).unwrap();
    for u in [0.0f32, 0.3, 0.77, 1.0] {
        let (a, b) = (one.sample(f64::from(u)).unwrap(), f.sample(u).unwrap());
        assert!((f64::from(b.t) - a.t).abs() < 1e-6 * a.t, "{a:?} {b:?}");
        assert!(
            (f64::from(b.pdf) - a.pdf).abs() < 1e-5 * a.pdf,
            "{a:?} {b:?}"
        );
    }
    let nan = DVec3::new(f64::NAN, 0.0, 0.0);
    let err = |r: Result<EquiangularSegment<f64>, crate::Error>| r.unwrap_err().field();
    assert_eq!(err(EquiangularSegment::new(nan, o, w, 0.0, 1.0)), "x0");
    assert_eq!(err(EquiangularSegment::new(x0, nan, w, 0.0, 1.0)), "origin");
    assert_eq!(
        err(EquiangularSegment::new(x0, o, DVec3::ZERO, 0.0, 1.0)),
        "direction"
    );
    assert_eq!(err(EquiangularSegment::new(x0, o, w, -1.0, 1.0)), "t_min");
    assert_eq!(
        err(EquiangularSegment::new(x0, o, w, f64::NAN, 1.0)),
        "t_min"
    );
    assert_eq!(err(EquiangularSegment::new(x0, o, w, 1.0, 1.0)), "t_max");
    assert_eq!(
        err(EquiangularSegment::new(x0, o, w, 0.0, f64::NAN)),
        "t_max"
    );
    // x0 on the segment itself.
    assert_eq!(
        err(EquiangularSegment::new(DVec3::X, DVec3::ZERO, w, 0.0, 2.0)),
        "x0"
    );
    // Any u: clamped, never NaN.
    for u in [f64::NAN, -1.0, 2.0, f64::INFINITY] {
        let d = one.sample(u).unwrap();
        assert!(
            d.t.is_finite() && d.pdf.is_finite() && d.pdf > 0.0,
            "u = {u}: {d:?}"
        );
    }
}
