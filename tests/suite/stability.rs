//! Numerical stability: extreme and adversarial inputs never give NaN, an
//! infinity, a negative density or a panic, in f32 and f64; and the f32 path
//! agrees with the f64 path (the same generic code) to a derived tolerance.

use crate::harness::PhaseSpec;
use omnee::medium::Region;
use omnee::mis::{Heuristic, OneSample};
use omnee::phase::{Deflection, Draine, HenyeyGreenstein, PhaseFunction};
use omnee::real::cast;
use omnee::sampling::{Connection, Directions, Distance, Equiangular, Omnee, Technique};
use omnee::{Real, Vector};

/// Phase functions at the ends of their ranges.
const EXTREME_PHASES: [PhaseSpec; 13] = [
    PhaseSpec::Isotropic,
    PhaseSpec::Rayleigh,
    PhaseSpec::Hg(0.9999),
    PhaseSpec::Hg(-0.9999),
    PhaseSpec::Hg(0.99),
    PhaseSpec::TwoTerm(0.9999, -0.9999, 0.5),
    PhaseSpec::Draine(0.5, 250.0),
    PhaseSpec::Draine(0.9999, 1000.0),
    PhaseSpec::Draine(-0.9999, 0.0),
    PhaseSpec::Ff(0.001, 1.001),
    PhaseSpec::Ff(0.499, 1.5),
    PhaseSpec::Mie(0.1),
    PhaseSpec::Mie(50.0),
];

/// Uniform numbers at and next to the edges of [0, 1): 0, the smallest
/// subnormal, tiny, 1e-7, ½, 1 − 1e-7, and 1 − ulp.
fn edge_uniforms<F: Real>() -> [F; 7] {
    let subnormal = F::MIN_POSITIVE * F::from_f64(2f64.powi(-20));
    [
        F::ZERO,
        subnormal,
        F::from_f64(1e-30),
        F::from_f64(1e-7),
        F::HALF,
        F::from_f64(1.0 - 1e-7),
        F::ONE_MINUS_EPSILON,
    ]
}

fn v<F: Real>(x: f64, y: f64, z: f64) -> F::Vec3 {
    F::Vec3::new(F::from_f64(x), F::from_f64(y), F::from_f64(z))
}

fn finite_non_negative<F: Real>(x: F) -> bool {
    x.is_finite() && x >= F::ZERO
}

/// Samples, densities and inverses of `t` at every edge triple and at the
/// special points: all finite, densities and weights ≥ 0, inverses in [0, 1].
fn exercise<F: Real>(name: &str, t: &dyn Technique<F>, points: &[F::Vec3]) {
    let us = edge_uniforms::<F>();
    for &a in &us {
        for &b in &us {
            for &c in &us {
                let u = [a, b, c];
                if let Some(s) = t.sample(u) {
                    assert!(
                        s.x1.is_finite()
                            && finite_non_negative(s.pdf)
                            && finite_non_negative(s.weight),
                        "{name}: sample({u:?}) = {s:?}"
                    );
                    let p = t.pdf(s.x1);
                    assert!(finite_non_negative(p), "{name}: pdf(sample({u:?})) = {p:?}");
                }
            }
        }
    }
    for &x1 in points {
        let p = t.pdf(x1);
        assert!(finite_non_negative(p), "{name}: pdf({x1:?}) = {p:?}");
        if let Some(u) = t.invert(x1) {
            assert!(
                u.iter().all(|&x| x >= F::ZERO && x <= F::ONE),
                "{name}: invert({x1:?}) = {u:?}"
            );
        }
    }
}

/// Points where the geometry degenerates: the end points, on the axis
/// between and beyond them, next to the axis, very far, non-finite.
fn special_points<F: Real>(x0: [f64; 3], x2: [f64; 3], s: f64) -> Vec<F::Vec3> {
    let at = |t: f64, off: f64| {
        v::<F>(
            x0[0] + t * (x2[0] - x0[0]) + off * s,
            x0[1] + t * (x2[1] - x0[1]),
            x0[2] + t * (x2[2] - x0[2]),
        )
    };
    vec![
        at(0.0, 0.0),
        at(1.0, 0.0),
        at(0.5, 0.0),
        at(1e-7, 0.0),
        at(-1.0, 0.0),
        at(2.0, 0.0),
        at(0.5, 1e-30),
        at(0.5, 1e-7),
        at(1e-7, 1e-7),
        at(0.5, 1e30),
        at(1e30, 1.0),
        v::<F>(f64::NAN, 0.0, 0.0),
        v::<F>(f64::INFINITY, 0.0, 0.0),
        v::<F>(0.0, f64::NEG_INFINITY, 1.0),
    ]
}

fn extremes_are_finite<F: Real>() {
    let pi = core::f64::consts::PI;
    for scale in [1e-6, 1e-3, 1.0, 1e3, 1e6] {
        // x0 off the origin, so coordinates carry rounding of their own.
        let x0 = [0.1 * scale, 0.2 * scale, -0.3 * scale];
        let x2 = [
            x0[0] + 0.6 * scale,
            x0[1] - 0.48 * scale,
            x0[2] + 0.64 * scale,
        ];
        let points = special_points::<F>(x0, x2, scale);
        for spec in EXTREME_PHASES {
            let phase = spec.build::<F>();
            for theta_max in [1e-6, core::f64::consts::FRAC_PI_2, pi] {
                let c = Connection::new(
                    v::<F>(x0[0], x0[1], x0[2]),
                    v::<F>(x2[0], x2[1], x2[2]),
                    F::from_f64(theta_max),
                )
                .unwrap();
                let name = format!("s {scale} {spec:?} θmax {theta_max}");
                let omnee = Omnee::new(c, &*phase);
                exercise(&format!("omnee {name}"), &omnee, &points);
                let eq = Equiangular::new(c, &*phase, Directions::Sphere, Region::Everywhere);
                exercise(&format!("equiangular {name}"), &eq, &points);
                let slab = Region::slab(F::from_f64(x0[2]), F::from_f64(x2[2])).unwrap();
                let cos = Directions::cosine(v::<F>(0.0, 0.0, 1.0)).unwrap();
                let di = Distance::new(c, &*phase, cos, slab, F::from_f64(1.0 / scale)).unwrap();
                exercise(&format!("distance {name}"), &di, &points);
                let mis = OneSample::new(
                    [&omnee as &dyn Technique<F>, &eq, &di],
                    [F::ONE; 3],
                    Heuristic::Power,
                )
                .unwrap();
                exercise(&format!("one-sample MIS {name}"), &mis, &points);
                for &x1 in &points {
                    let k = c.kernel(&&*phase, x1);
                    assert!(finite_non_negative(k), "kernel {name} at {x1:?}: {k:?}");
                }
            }
        }
    }
}

#[test]
fn extreme_inputs_give_finite_results_in_f32() {
    extremes_are_finite::<f32>();
}

#[test]
fn extreme_inputs_give_finite_results_in_f64() {
    extremes_are_finite::<f64>();
}

fn non_finite_uniforms_never_panic<F: Real>() {
    let c = Connection::new(v::<F>(0.0, 0.0, 0.0), v::<F>(0.0, 0.0, 1.0), F::PI).unwrap();
    let phase = HenyeyGreenstein::new(F::from_f64(0.9)).unwrap();
    let omnee = Omnee::new(c, phase);
    let eq = Equiangular::new(c, phase, Directions::Sphere, Region::Everywhere);
    let di = Distance::new(c, phase, Directions::Sphere, Region::Everywhere, F::ONE).unwrap();
    let bad = [
        F::from_f64(f64::NAN),
        F::INFINITY,
        -F::INFINITY,
        -F::ONE,
        F::TWO,
        F::ONE,
        F::HALF,
    ];
    for t in [&omnee as &dyn Technique<F>, &eq, &di] {
        for &a in &bad {
            for &b in &bad {
                for &c in &bad {
                    // Outside the contract (u ∈ [0, 1)): a sample may or may
                    // not come back, but never a non-finite one.
                    if let Some(s) = t.sample([a, b, c]) {
                        assert!(
                            s.x1.is_finite()
                                && finite_non_negative(s.pdf)
                                && finite_non_negative(s.weight),
                            "sample({:?}) = {s:?}",
                            [a, b, c]
                        );
                    }
                }
            }
        }
    }
    for u in bad {
        let d = phase.sample(u);
        let _ = phase.eval(d);
    }
}

#[test]
fn non_finite_uniforms_never_give_non_finite_samples() {
    non_finite_uniforms_never_panic::<f32>();
    non_finite_uniforms_never_panic::<f64>();
}

fn phase_extremes<F: Real>() {
    let pi = core::f64::consts::PI;
    let thetas = [0.0, 1e-300, 1e-30, 1e-7, 1.0, pi - 1e-7, pi];
    for spec in EXTREME_PHASES {
        let p = spec.build::<F>();
        for &t in &thetas {
            for d in [
                Deflection::from_theta(F::from_f64(t)),
                Deflection::from_cos(F::from_f64(t.cos())),
            ] {
                let (e, c) = (p.eval(d), p.cdf(d));
                assert!(finite_non_negative(e), "{spec:?} eval({d:?}) = {e:?}");
                assert!(c >= F::ZERO && c <= F::ONE, "{spec:?} cdf({d:?}) = {c:?}");
            }
        }
        for u in edge_uniforms::<F>() {
            let d = p.sample(u);
            assert!(
                d.is_finite() && d.theta >= F::ZERO && d.theta <= F::PI,
                "{spec:?} sample({u:?}) = {d:?}"
            );
            assert!(finite_non_negative(p.pdf(d)), "{spec:?} pdf(sample({u:?}))");
        }
        let m = p.mean_cosine();
        assert!(
            m.is_finite() && m.abs() <= F::ONE,
            "{spec:?} mean cosine {m:?}"
        );
    }
}

#[test]
fn phase_functions_are_finite_at_the_poles_and_at_g_near_one() {
    phase_extremes::<f32>();
    phase_extremes::<f64>();
}

#[test]
fn invalid_parameters_are_refused_not_panicked_on() {
    let o = v::<f32>(0.0, 0.0, 0.0);
    let z = v::<f32>(0.0, 0.0, 1.0);
    let nan = v::<f32>(f64::NAN, 0.0, 0.0);
    assert!(Connection::new(o, o, 1.0f32).is_err());
    assert!(Connection::new(nan, z, 1.0f32).is_err());
    assert!(Connection::new(o, v::<f32>(f64::INFINITY, 0.0, 0.0), 1.0f32).is_err());
    assert!(
        Connection::new(o, v::<f32>(3e38, 3e38, 3e38), 1.0f32).is_err(),
        "s overflows f32"
    );
    for t in [0.0f32, -1.0, 3.2, f32::NAN, f32::INFINITY] {
        assert!(Connection::new(o, z, t).is_err(), "θmax = {t}");
    }
    for g in [1.0f32, -1.0, f32::NAN, 2.0] {
        assert!(HenyeyGreenstein::new(g).is_err(), "g = {g}");
    }
    assert!(Draine::new(0.5f32, 1001.0).is_err() && Draine::new(0.5f32, -1.0).is_err());
    let c = Connection::new(o, z, 1.0f32).unwrap();
    let hg = HenyeyGreenstein::new(0.5f32).unwrap();
    for sigma in [-1.0f32, f32::NAN, f32::INFINITY] {
        assert!(
            Distance::new(c, hg, Directions::Sphere, Region::Everywhere, sigma).is_err(),
            "σ = {sigma}"
        );
    }
    assert!(Directions::<f32>::cosine(o).is_err() && Directions::<f32>::cosine(nan).is_err());
    assert!(Region::slab(1.0f32, 1.0).is_err() && Region::slab(1.0f32, 0.0).is_err());
    assert!(Region::slab(f32::NAN, 1.0).is_err());
}

/// The largest relative difference of f32 results from f64 results for the
/// same inputs (uniforms representable in f32), over configurations away from
/// the edges, per quantity: (weight, pdf, x1 relative to s + d1 + d2).
fn f32_f64_differences(spec: PhaseSpec, theta_max: f64, scale: f64) -> (f64, f64, f64) {
    let x0 = [0.3 * scale, -0.1 * scale, 0.2 * scale];
    let x2 = [
        x0[0] + 0.36 * scale,
        x0[1] + 0.48 * scale,
        x0[2] + 0.8 * scale,
    ];
    let (p32, p64) = (spec.build::<f32>(), spec.rounded_to_f32().build::<f64>());
    let c32 = Connection::new(
        v::<f32>(x0[0], x0[1], x0[2]),
        v::<f32>(x2[0], x2[1], x2[2]),
        theta_max as f32,
    )
    .unwrap();
    let c64 = Connection::new(
        v::<f64>(x0[0], x0[1], x0[2]),
        v::<f64>(x2[0], x2[1], x2[2]),
        theta_max,
    )
    .unwrap();
    // The same points, rounded to f32, in both precisions: both see one geometry.
    let c64 = Connection::new(
        omnee::real::cast_vec::<f32, f64>(c32.axis.x0),
        omnee::real::cast_vec::<f32, f64>(c32.axis.x2),
        c64.theta_max,
    )
    .unwrap();
    let (o32, o64) = (Omnee::new(c32, &*p32), Omnee::new(c64, &*p64));
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    let n = 24;
    for i in 0..n {
        for j in 0..n {
            for k in 0..4 {
                // u away from the edges, where the f32 point itself is exact
                // to a few ulps of s.
                let u32 = [
                    (i as f32 + 0.5) / n as f32,
                    0.02 + 0.96 * (j as f32 + 0.5) / n as f32,
                    (k as f32 + 0.5) / 4.0,
                ];
                let u64 = u32.map(f64::from);
                let (Some(a), Some(b)) = (o32.sample(u32), o64.sample(u64)) else {
                    assert!(
                        o32.sample(u32).is_none() == o64.sample(u64).is_none()
                            || theta_max < core::f64::consts::PI,
                        "f32 and f64 disagree on whether {u32:?} gives a sample"
                    );
                    continue;
                };
                let rel = |x: f64, y: f64| (x - y).abs() / y.abs();
                worst.0 = worst.0.max(rel(cast(a.weight), b.weight));
                worst.1 = worst.1.max(rel(cast(a.pdf), b.pdf));
                let dx = omnee::real::cast_vec::<f32, f64>(a.x1) - b.x1;
                let size = scale + (b.x1 - c64.axis.x0).length() + (b.x1 - c64.axis.x2).length();
                worst.2 = worst.2.max(dx.length() / size);
            }
        }
    }
    worst
}

#[test]
fn f32_agrees_with_f64() {
    // Tolerances, with ε = 2^-23 ≈ 1.2e-7 (f32):
    // - weight = θ/(s sin θ): θ comes from a cancellation-free sampler, a few
    //   ulps (~4ε) relative; the weight's relative sensitivity to θ is
    //   θ|1/θ − cot θ| ≤ 22 for θ ≤ 3, so ≲ 4ε(1 + 22)/… in practice within
    //   6e-7 (measured at θmax = 3): allow 5e-6.
    // - pdf = p(θ) sinc θ s/(d1² d2²): d1, d2 are a few ulps each (×4 in the
    //   product), and p(θ) moves by (d ln p/d ln θ)·(Δθ/θ) with d ln p/d ln θ
    //   ≤ 3 for HG and ≤ 5 for Draine's (1 + α cos²θ) factor: ≲ 40ε: allow 1e-5.
    // - x1 relative to the triangle's size s + d1 + d2: |x0| is within it
    //   and the arc's construction adds a few ulps: allow 1e-6.
    // Measured maxima (printed): weight 6e-7, pdf 2.8e-6, x1 3.2e-7. The
    // tolerances are 2–8× those, so they catch an f32
    // path that loses digits (e.g. 1 − cos θ by subtraction at g = 0.99,
    // which costs ~1e-3 relative in p), not rounding noise.
    let specs = [
        PhaseSpec::Isotropic,
        PhaseSpec::Hg(0.9),
        PhaseSpec::Hg(0.99),
        PhaseSpec::Hg(-0.7),
        PhaseSpec::TwoTerm(0.99, -0.44, 0.96),
        PhaseSpec::Draine(0.5, 250.0),
        PhaseSpec::Rayleigh,
    ];
    for spec in specs {
        for theta_max in [core::f64::consts::FRAC_PI_2, 3.0] {
            for scale in [1e-3, 1.0, 1e3] {
                let (w, p, x) = f32_f64_differences(spec, theta_max, scale);
                println!(
                    "f32 vs f64 {spec:?} θmax {theta_max} s {scale}: weight {w:.1e}, pdf {p:.1e}, x1/s {x:.1e}"
                );
                assert!(
                    w < 5e-6 && p < 1e-5 && x < 1e-6,
                    "{spec:?} θmax {theta_max} s {scale}: {w:e} {p:e} {x:e}"
                );
            }
        }
    }
}

#[test]
fn hg_sampler_keeps_its_f32_digits_near_g_one() {
    // At g = 0.9999 a sampler that forms `(q + 1) − g` (or k = 1 + g − 2gu)
    // loses log10(1/(1 − g)) digits: the f32 pdf of the same u then differs
    // from f64 by 2.2e-4 (measured). Summing non-negative terms,
    // `q + (1 − g)` and k = (1 − g) + 2g(1 − u), keeps it at the ulp level.
    let (_, p, _) = f32_f64_differences(PhaseSpec::Hg(0.9999), core::f64::consts::FRAC_PI_2, 1.0);
    assert!(p < 1e-5, "f32 pdf differs by {p:e}");
}

/// Uniform numbers crowding towards both ends of [0, 1), all exact in f32:
/// `k·2⁻²⁴` and `1 − k·2⁻²⁴` for k = 1, 2, 4, …, 2²³, and a uniform grid
/// between. Near u = 1 an inverse-CDF sampler reaches θ → π (and 1 + cos θ
/// carries the digits); near u = 0 it reaches θ → 0.
fn ends_of_the_unit_interval() -> Vec<f32> {
    let ulp = 2f32.powi(-24);
    let mut us: Vec<f32> = (0..24)
        .flat_map(|i| {
            let k = 2f32.powi(i) * ulp;
            [k, 1.0 - k]
        })
        .collect();
    us.extend((1..64).map(|i| i as f32 / 64.0));
    us
}

/// The largest relative f32-vs-f64 difference of the two versines a phase
/// function's sampler returns for the same u (f32-rounded parameters in both).
fn versine_differences(spec: PhaseSpec) -> (f64, f64) {
    let (p32, p64) = (spec.build::<f32>(), spec.rounded_to_f32().build::<f64>());
    let mut worst = (0.0f64, 0.0f64);
    for u in ends_of_the_unit_interval() {
        let (a, b) = (p32.sample(u), p64.sample(f64::from(u)));
        let rel = |x: f32, y: f64| {
            if y == 0.0 {
                f64::from(x).abs()
            } else {
                (f64::from(x) - y).abs() / y
            }
        };
        worst.0 = worst.0.max(rel(a.one_minus_cos, b.one_minus_cos));
        worst.1 = worst.1.max(rel(a.one_plus_cos, b.one_plus_cos));
    }
    worst
}

#[test]
fn f32_samplers_keep_both_versines_to_relative_precision() {
    // A Deflection promises 1 − cos θ and 1 + cos θ each without
    // cancellation (README, docs/math.md §4), so the f32 sampler must match the
    // f64 one in *relative* terms at both ends of u: near u → 1 a sampler
    // that forms 1 + cos θ, or any term of it, by subtracting numbers near
    // 1 (e.g. k = 1 + g − 2gu for g → 1) loses log10(1/(1 − g)) digits.
    // Bound: the closed forms are a dozen roundings of non-negative terms
    // (≤ 12 ε relative) and an f32 division of u (ε); with ε = 2⁻²⁴ that is
    // 8e-7: allow 2e-6. Rayleigh's cubic is polished by Newton steps whose
    // residual is formed in f32 (a few ε more); Draine and Fournier–Forand
    // invert in f64 and round once.
    let specs = [
        PhaseSpec::Isotropic,
        PhaseSpec::Rayleigh,
        PhaseSpec::Hg(0.0),
        PhaseSpec::Hg(0.5),
        PhaseSpec::Hg(-0.5),
        PhaseSpec::Hg(0.99),
        PhaseSpec::Hg(-0.99),
        PhaseSpec::Hg(0.9999),
        PhaseSpec::Hg(-0.9999),
        PhaseSpec::Draine(0.5, 250.0),
        PhaseSpec::Draine(-0.9, 3.0),
    ];
    for spec in specs {
        let (minus, plus) = versine_differences(spec);
        println!("f32 vs f64 sampler {spec:?}: 1 − cos θ {minus:.1e}, 1 + cos θ {plus:.1e}");
        assert!(
            minus < 2e-6 && plus < 2e-6,
            "{spec:?}: f32 versines off by {minus:e} (1 − cos θ), {plus:e} (1 + cos θ)"
        );
    }
}

#[test]
fn f32_batch_agrees_with_f64() {
    // The vectorised f32 entry point (Omnee::sample_batch, Henyey–Greenstein:
    // polynomial sin/cos and atan, a Newton square root) against the f64
    // scalar sampler for the same u, geometry and g (all f32-rounded), run
    // as one batch per configuration. Tolerances as for the scalar f32 path
    // in `f32_agrees_with_f64` (weight 5e-6, pdf 1e-5, x1 1e-6 of the
    // triangle's size): the polynomials add at most 3 ulps to the functions
    // they replace. u0 runs to both ends of [0, 1) (θ → 0 and the back of
    // the lobe), u1 stays 0.02 away from the end points (see there).
    // Measured maxima: weight 3.8e-7, pdf 1.4e-6, x1 2.7e-7.
    let mut u0s = ends_of_the_unit_interval();
    u0s.extend((0..24).map(|i| (i as f32 + 0.5) / 24.0));
    let mut us = Vec::new();
    for &a in &u0s {
        for j in 0..24 {
            for k in 0..4 {
                us.push([
                    a,
                    0.02 + 0.96 * (j as f32 + 0.5) / 24.0,
                    (k as f32 + 0.5) / 4.0,
                ]);
            }
        }
    }
    let soa = |k: usize| us.iter().map(|u| u[k]).collect::<Vec<f32>>();
    let (u0, u1, u2) = (soa(0), soa(1), soa(2));
    for g in [0.0, 0.9, 0.99, 0.9999, -0.7, -0.9999] {
        for theta_max in [core::f64::consts::FRAC_PI_2, 3.0] {
            for scale in [1e-3, 1.0, 1e3] {
                let x0 = glam::DVec3::new(0.3, -0.1, 0.2) * scale;
                let x2 = x0 + glam::DVec3::new(0.36, 0.48, 0.8) * scale;
                let t = crate::harness::BatchOmnee::new(x0, x2, theta_max, g);
                let super::harness::Lanes {
                    x,
                    y,
                    z,
                    pdf,
                    weight,
                    ..
                } = t.batch(&u0, &u1, &u2);
                let (mut dw, mut dp, mut dx) = (0.0f64, 0.0f64, 0.0f64);
                let c64 = &t.f64.connection;
                for (i, u) in us.iter().enumerate() {
                    let b = t.f64.sample(u.map(f64::from));
                    let lane = (pdf[i] > 0.0).then_some(i);
                    let (Some(b), Some(i)) = (b, lane) else {
                        // Only where θ itself is within the f32 rounding of θmax.
                        let theta = t.f64.phase.sample(f64::from(u[0])).theta;
                        assert!(
                            b.is_none() == lane.is_none()
                                || (theta / c64.theta_max - 1.0).abs() < 1e-5,
                            "g {g} θmax {theta_max} s {scale}: batch and f64 disagree on {u:?}"
                        );
                        continue;
                    };
                    let rel = |x: f32, y: f64| (f64::from(x) - y).abs() / y.abs();
                    dw = dw.max(rel(weight[i], b.weight));
                    dp = dp.max(rel(pdf[i], b.pdf));
                    let x1 = glam::DVec3::new(x[i].into(), y[i].into(), z[i].into());
                    let size =
                        scale + (b.x1 - c64.axis.x0).length() + (b.x1 - c64.axis.x2).length();
                    dx = dx.max((x1 - b.x1).length() / size);
                }
                println!(
                    "f32 batch vs f64 HG {g} θmax {theta_max} s {scale}: weight {dw:.1e}, pdf {dp:.1e}, x1/s {dx:.1e}"
                );
                assert!(
                    dw < 5e-6 && dp < 1e-5 && dx < 1e-6,
                    "HG {g} θmax {theta_max} s {scale}: weight {dw:e}, pdf {dp:e}, x1 {dx:e}"
                );
            }
        }
    }
}
