use super::*;
use crate::medium::Homogeneous;
use crate::phase::{HenyeyGreenstein, Isotropic};
use crate::reference::PointToPoint;
use crate::sampling::{Connection, Technique};
use glam::{DVec3, Vec3};

#[test]
fn ln_factorial_table_is_the_running_sum_of_logs() {
    let mut sum = 0.0f64;
    for (k, &v) in LN_FACTORIAL.iter().enumerate() {
        if k >= 2 {
            sum += libm::log(k as f64);
        }
        assert!((v - sum).abs() <= 1e-14 * sum.max(1.0), "{k}: {v} vs {sum}");
    }
}

#[test]
fn closed_form_of_one_vertex_is_the_quadrature() {
    for tau in [0.1, 1.0, 10.0] {
        let c = Connection::new(DVec3::ZERO, DVec3::Z * 2.0, core::f64::consts::PI).unwrap();
        let m = Homogeneous::from_extinction(0.35 * tau, tau / 2.0).unwrap();
        let q = PointToPoint::new(c, m, None).unwrap().integral(&Isotropic);
        let i1 = isotropic_transfer(1, 2.0, 0.35 * tau, tau / 2.0, REFERENCE_BUDGET).unwrap();
        assert!((i1 / q - 1.0).abs() < 1e-9, "τ {tau}: {i1:e} vs {q:e}");
    }
}

#[test]
fn closed_form_rejects_bad_input_and_keeps_its_budget() {
    assert_eq!(
        isotropic_transfer(0, 1.0, 1.0, 1.0, 10)
            .unwrap_err()
            .field(),
        "k"
    );
    assert_eq!(
        isotropic_transfer(33, 1.0, 1.0, 1.0, 10)
            .unwrap_err()
            .field(),
        "k"
    );
    assert_eq!(
        isotropic_transfer(2, 0.0, 1.0, 1.0, 10)
            .unwrap_err()
            .field(),
        "s"
    );
    assert_eq!(
        isotropic_transfer(2, 1.0, f64::NAN, 1.0, 10)
            .unwrap_err()
            .field(),
        "sigma_s"
    );
    assert_eq!(
        isotropic_transfer(2, 1.0, 1.0, 0.0, 10)
            .unwrap_err()
            .field(),
        "sigma_t"
    );
    assert!(
        isotropic_transfer(1, 1.0, 1.0, 0.0, REFERENCE_BUDGET)
            .unwrap()
            .is_finite()
    );
    assert!(matches!(
        isotropic_transfer(3, 1.0, 1.0, 1.0, 20),
        Err(Error::NotConverged {
            field: "reference",
            evaluations: 30
        })
    ));
    assert_eq!(isotropic_transfer(3, 1.0, 0.0, 1.0, 20), Ok(0.0));
    // σs = 0.5/s at s = 1e-300: I_1 ≈ 1e600, beyond f64, named; at 1e-150
    // it is λ⁻² times the unit one.
    let e = isotropic_transfer(1, 1e-300, 0.5e300, 0.55e300, REFERENCE_BUDGET).unwrap_err();
    assert_eq!(e.field(), "s");
    let unit = isotropic_transfer(2, 1.0, 0.5, 0.55, REFERENCE_BUDGET).unwrap();
    let tiny = isotropic_transfer(2, 1e-150, 0.5e150, 0.55e150, REFERENCE_BUDGET).unwrap();
    assert!(
        (tiny * 1e-300 / unit - 1.0).abs() < 1e-9,
        "{tiny:e} vs {unit:e}"
    );
}

#[test]
fn sampled_density_is_the_density_at_the_points() {
    let b = Bridge::new(
        DVec3::new(0.1, 0.2, 0.3),
        DVec3::new(1.0, -1.0, 2.0),
        HenyeyGreenstein::new(0.7).unwrap(),
    )
    .unwrap();
    let mut x = [DVec3::ZERO; 4];
    let u = [
        [0.3, 0.6, 0.2],
        [0.8, 0.1, 0.5],
        [0.45, 0.9, 0.7],
        [0.05, 0.33, 0.4],
    ];
    for k in 1..=4 {
        let s = b.sample(&u[..k], &mut x).unwrap();
        assert!((b.pdf(&x[..k]) / s.pdf - 1.0).abs() < 1e-10);
        // weight = kernel / pdf, and the length is the sum of the edges.
        assert!((b.kernel(&x[..k]) / s.pdf / s.weight - 1.0).abs() < 1e-10);
        let mut prev: DVec3 = b.axis.x0;
        let mut length = 0.0f64;
        for &v in x[..k].iter().chain([b.axis.x2].iter()) {
            length += (v - prev).length();
            prev = v;
        }
        assert!(
            (length / s.length - 1.0).abs() < 1e-12,
            "{length} vs {}",
            s.length
        );
    }
}

#[test]
fn bad_slices_give_no_sample() {
    let b = Bridge::<f32, _>::new(Vec3::ZERO, Vec3::Z, Isotropic).unwrap();
    let mut x = [Vec3::ZERO; 2];
    assert!(b.sample(&[], &mut x).is_none());
    assert!(b.sample(&[[0.5; 3]; 3], &mut x).is_none());
    assert!(b.sample(&[[0.5; 3]; 2], &mut x).is_some());
    assert!(b.sample(&[[0.5, 0.5, 0.0]], &mut x).is_none()); // d_1 = 0
    assert_eq!(b.pdf(&[]), 0.0);
    assert_eq!(b.pdf(&[Vec3::ZERO]), 0.0);
    assert!(Bridge::<f32, _>::new(Vec3::ZERO, Vec3::ZERO, Isotropic).is_err());
}

#[test]
fn one_vertex_technique_is_the_bridge_of_one() {
    let b = Bridge::new(
        DVec3::ZERO,
        DVec3::new(0.0, 1.0, 1.0),
        HenyeyGreenstein::new(0.4).unwrap(),
    )
    .unwrap();
    let u = [0.3, 0.7, 0.4];
    let t = Technique::sample(&b, u).unwrap();
    let mut x = [DVec3::ZERO];
    let s = b.sample(&[u], &mut x).unwrap();
    assert_eq!((t.x1, t.pdf, t.weight), (x[0], s.pdf, s.weight));
    assert!((Technique::pdf(&b, t.x1) / t.pdf - 1.0).abs() < 1e-12);
    let back = Technique::invert(&b, t.x1).unwrap();
    for m in 0..3 {
        assert!((back[m] - u[m]).abs() < 1e-12, "{back:?}");
    }
}

#[test]
fn vertex_count_is_a_distribution_and_rejects_bad_input() {
    let c = VertexCount::<f32>::new(8, 2.0, 1.0, 1.5, 0.9).unwrap();
    assert_eq!(c.cdf(8), 1.0);
    let total: f32 = (1..=8).map(|k| c.pmf(k)).sum();
    assert!((total - 1.0).abs() < 1e-6);
    assert!((1..=8).all(|k| c.pmf(k) >= 0.2 / 8.0 * 0.999));
    assert_eq!(c.sample(0.0).0, 1);
    assert_eq!(c.sample(1.0 - f32::EPSILON / 2.0).0, 8);
    let (lo, hi) = c.invert(3).unwrap();
    assert_eq!(c.sample(lo).0, 3);
    assert!(hi > lo && c.invert(9).is_none());
    assert_eq!(
        VertexCount::<f64>::new(0, 1.0, 1.0, 1.0, 0.0)
            .unwrap_err()
            .field(),
        "k_max"
    );
    assert_eq!(
        VertexCount::<f64>::new(4, 1.0, 1.0, 1.0, 1.5)
            .unwrap_err()
            .field(),
        "g"
    );
    assert_eq!(
        VertexCount::<f64>::with_mean(4, 1.0, 2.0)
            .unwrap_err()
            .field(),
        "floor"
    );
    let none = VertexCount::<f64>::with_mean(4, 0.0, 0.0).unwrap();
    assert_eq!(none.pmf(1), 1.0);
    let huge = VertexCount::<f64>::new(8, 1e30, 1e30, 1e30, 0.0).unwrap();
    assert!((1..=8).all(|k| huge.pmf(k).is_finite()));
}

/// The bridges of the same numbers between `0` and `λ (1, 2, −0.5)` for
/// `λ = 2ⁿ`, with σs, σt scaled by `1/λ`: every length scales by `λ`, the
/// weight by `λ^{k−2}` and the estimate by `λ^{−2}` (docs/math.md §14.5).
fn scaled<F: Real>(n: i32, k: usize, u: &[[F; 3]]) -> (BridgeSample<F>, F, f64)
where
    F::Vec3: Copy,
{
    let x2 = F::Vec3::new(F::ONE, F::TWO, F::from_f64(-0.5)).scale_pow2(n);
    let b = Bridge::new(
        x2 * F::ZERO,
        x2,
        HenyeyGreenstein::new(F::from_f64(0.6)).unwrap(),
    )
    .unwrap();
    let medium = Homogeneous::from_extinction(
        F::from_f64(0.4).scale_pow2(-n),
        F::from_f64(0.9).scale_pow2(-n),
    )
    .unwrap();
    let mut x = [b.axis.x0; MAX_VERTICES];
    let s = b.sample(&u[..k], &mut x).unwrap();
    (s, b.estimate(&s, &medium), b.estimate_f64(&s, &medium))
}

#[test]
fn weight_and_estimate_follow_the_scale_law_across_the_exponent_range() {
    let u: [[f32; 3]; 6] = [
        [0.3, 0.6, 0.2],
        [0.8, 0.1, 0.5],
        [0.45, 0.9, 0.7],
        [0.05, 0.33, 0.4],
        [0.6, 0.2, 0.9],
        [0.95, 0.75, 0.1],
    ];
    let wide = u.map(|r| r.map(f64::from));
    for k in 1..=6 {
        let (one, e1, w1) = scaled::<f32>(0, k, &u);
        let (one64, _, w64) = scaled::<f64>(0, k, &wide);
        // f32 against f64 at the unit scale.
        assert!((w1 / w64 - 1.0).abs() < 1e-5, "k {k}: {w1:e} vs {w64:e}");
        assert!((f64::from(one.weight) / one64.weight - 1.0).abs() < 1e-5);
        for n in [-126, -100, -60, 60, 100, 126] {
            let (s, e, w) = scaled::<f32>(n, k, &u);
            let exact = |x: f64, p: i32| x * libm::exp2(f64::from(p * n));
            // In f64 the estimate is right at every scale (λ⁻²), to the
            // rounding of the factors' order.
            let tol = 1e-6 * (k as f64 + 2.0);
            assert!(
                (w / exact(w1, -2) - 1.0).abs() < tol,
                "k {k}, 2^{n}: {w:e} vs {:e}",
                exact(w1, -2)
            );
            // In f32: right wherever the value is a normal f32, saturated
            // above, 0 or subnormal below.
            for (got, want) in [
                (e, exact(f64::from(e1), -2)),
                (s.weight, exact(f64::from(one.weight), k as i32 - 2)),
            ] {
                if want > f64::from(f32::MAX) {
                    assert_eq!(got, f32::MAX, "k {k}, 2^{n}");
                } else if want >= f64::from(f32::MIN_POSITIVE) {
                    assert!(
                        (f64::from(got) / want - 1.0).abs() < tol,
                        "k {k}, 2^{n}: {got:e} vs {want:e}"
                    );
                } else {
                    assert!(
                        f64::from(got) <= f64::from(f32::MIN_POSITIVE),
                        "k {k}, 2^{n}"
                    );
                }
            }
            assert!(
                (f64::from(s.length) / exact(f64::from(one.length), 1) - 1.0).abs() < 1e-6,
                "k {k}, 2^{n}"
            );
        }
    }
}

#[test]
fn product_keeps_its_digits_past_the_range() {
    use super::product::Product;
    let p = Product::of(1e-30f32)
        .times_real(1e-30)
        .over_real(1e-30)
        .over_real(1e-30);
    assert!((p.value() - 1.0).abs() < 1e-6);
    let q = Product::of(3e38f32).times_real(3e38);
    assert_eq!(q.value(), f32::MAX);
    assert!((q.to_f64() / 9e76 - 1.0).abs() < 1e-6);
    assert_eq!(Product::of(f32::NAN).value(), 0.0);
    assert_eq!(Product::<f32>::exp_neg(f32::INFINITY).value(), 0.0);
    // e^{−200} leaves f32 but not f64.
    let tiny = Product::<f32>::exp_neg(200.0).to_f64();
    assert!((tiny / libm::exp(-200.0) - 1.0).abs() < 1e-4, "{tiny:e}");
    assert_eq!(Product::<f64>::exp_neg(0.0).value(), 1.0);
}

/// `I_k` at s = 1, σt = τ, σs = 0.8 τ and the cancellation `∫|f|/∫f` of its
/// integrand, by an independent 50-digit evaluation of the same integral
/// (mpmath's tanh-sinh quadrature, split at 1 + 10⁻⁴⁰ … 100).
#[allow(clippy::excessive_precision)]
const HIGH_PRECISION: [(usize, f64, f64, f64); 27] = [
    (2, 0.1, 0.025058943258097383, 4.93),
    (4, 0.1, 0.0021151594746204533, 135.0),
    (8, 0.1, 0.00017310784931874486, 8.52e+4),
    (9, 0.1, 0.00010966261520863995, 4.96e+5),
    (10, 0.1, 7.1655228793233451e-5, 3.1e+6),
    (11, 0.1, 4.7947105175237304e-5, 2.08e+7),
    (12, 0.1, 3.2692481874225192e-5, 1.5e+8),
    (13, 0.1, 2.2633796111326915e-5, 1.15e+9),
    (14, 0.1, 1.5868775058414495e-5, 9.37e+9),
    (2, 1.1, 0.24203289520578002, 1.33),
    (4, 1.1, 0.098435569763471006, 10.6),
    (8, 1.1, 0.016205979423925687, 3.66e+3),
    (9, 1.1, 0.010786083771229267, 2.03e+4),
    (10, 1.1, 0.0072974526287560848, 1.23e+5),
    (11, 1.1, 0.0050090921294354641, 8.06e+5),
    (12, 1.1, 0.0034819845423618679, 5.69e+6),
    (13, 1.1, 0.0024471615096410667, 4.3e+7),
    (14, 1.1, 0.0017364121125959681, 3.46e+8),
    (2, 10.0, 0.00023093991905818695, 1.0),
    (4, 10.0, 0.00050322680444547174, 1.71),
    (8, 10.0, 0.00096368422880097649, 72.5),
    (9, 10.0, 0.0010157956754100235, 260.0),
    (10, 10.0, 0.0010385657363719426, 1.06e+3),
    (11, 10.0, 0.00103431112895219, 4.8e+3),
    (12, 10.0, 0.0010068185684004332, 2.43e+4),
    (13, 10.0, 0.00096066230032307338, 1.35e+5),
    (14, 10.0, 0.00090063323670088952, 8.27e+5),
];

/// `I_k` at s = 1, σt = τ, σs = 0.8 τ for many vertices, by an independent
/// 40-digit evaluation of the Fourier form (mpmath, Gauss–Legendre on
/// `[0, π]` split towards 0 and then on each half-period until it is below
/// 10⁻²⁵ of the sum), where the Laplace form cancels beyond f64. (mpmath's
/// `quadosc` on the same integral is off by 6·10⁻⁷ at k = 32, τ = 10.) The
/// bridges' estimates agree: 5.7818e-5 ± 4.7e-8 at k = 32, τ = 10 and
/// 5.0119e-5 ± 9.4e-8 at τ = 3 (2·10⁶ draws each).
#[allow(clippy::excessive_precision)]
const HIGH_PRECISION_FOURIER: [(usize, f64, f64); 8] = [
    (20, 0.1, 2.2505877373354618e-6),
    (32, 0.1, 7.1453183383583991e-8),
    (20, 1.1, 0.00025623992488906043),
    (32, 1.1, 8.3589029867817484e-6),
    (20, 3.0, 0.0013040259598146852),
    (32, 3.0, 5.0078695540263686e-5),
    (20, 10.0, 0.00046513072029211783),
    (32, 10.0, 5.7787267010779843e-5),
];

#[test]
fn closed_form_keeps_ten_digits_for_every_order() {
    // Each table value, whichever form the function takes (the Laplace
    // form's cancellation reaches 10⁹ in the first table).
    let laplace = HIGH_PRECISION.map(|(k, tau, want, _)| (k, tau, want));
    for (k, tau, want) in laplace.into_iter().chain(HIGH_PRECISION_FOURIER) {
        let got = isotropic_transfer(k, 1.0, 0.8 * tau, tau, REFERENCE_BUDGET).unwrap();
        assert!(
            (got / want - 1.0).abs() < 1e-10,
            "k {k}, τ {tau}: {got:e} vs {want:e}"
        );
    }
    // Every order in thin to dense media is a positive value, or (dense,
    // both forms cancelling) the named refusal; never a negative number
    // (k = 20 gave −3.39 before the forms were checked).
    for k in 1..=MAX_VERTICES {
        for tau in [0.01, 0.1, 1.1, 3.0, 10.0, 30.0] {
            match isotropic_transfer(k, 1.0, 0.8 * tau, tau, REFERENCE_BUDGET) {
                Ok(v) => assert!(v > 0.0 && v.is_finite(), "k {k}, τ {tau}: {v}"),
                Err(e) => {
                    assert_eq!(e.field(), "k", "k {k}, τ {tau}");
                    assert!(tau > 20.0, "k {k}, τ {tau} refused");
                }
            }
        }
    }
}

/// At every scale the density at the sampled points is the sample's own
/// (both saturated where beyond the range), and the inverse gives back the
/// numbers: every length is taken in the connection's unit.
fn density_and_inverse_hold_at_scale<F: Real>(n: i32, tol: f64) {
    let u = [[0.3, 0.4, 0.5], [0.6, 0.2, 0.7], [0.15, 0.85, 0.35]].map(|r| r.map(F::from_f64));
    let x2 = F::Vec3::new(F::ONE, F::from_f64(-0.25), F::from_f64(0.5)).scale_pow2(n);
    let x0 = F::Vec3::new(F::from_f64(0.5), F::ZERO, F::ZERO).scale_pow2(n);
    let b = Bridge::new(x0, x2, HenyeyGreenstein::new(F::from_f64(0.9)).unwrap()).unwrap();
    for k in 1..=3 {
        let mut x = [x0; 3];
        let s = b.sample(&u[..k], &mut x).unwrap();
        let pdf = b.pdf(&x[..k]);
        if s.pdf == F::MAX || s.pdf.to_f64() < F::MIN_POSITIVE.to_f64() {
            assert_eq!(pdf, s.pdf, "k {k}, 2^{n}");
        } else {
            assert!(
                (pdf / s.pdf - F::ONE).abs().to_f64() < tol,
                "k {k}, 2^{n}: {pdf:?} vs {:?}",
                s.pdf
            );
        }
        let mut back = [[F::ZERO; 3]; 3];
        b.invert(&x[..k], &mut back).unwrap();
        for (got, want) in back[..k].iter().flatten().zip(u[..k].iter().flatten()) {
            assert!(
                (*got - *want).abs().to_f64() < 100.0 * tol,
                "k {k}, 2^{n}: {back:?}"
            );
        }
    }
}

#[test]
fn density_and_inverse_hold_across_the_exponent_range() {
    for n in [-120, -100, -60, -34, -20, 0, 20, 34, 60, 100, 120] {
        density_and_inverse_hold_at_scale::<f32>(n, 1e-5);
    }
    for n in [-1000, -600, -300, 0, 300, 600, 1000] {
        density_and_inverse_hold_at_scale::<f64>(n, 1e-12);
    }
}
