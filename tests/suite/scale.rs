//! Scale (docs/math.md §15): every finite, non-zero geometry is accepted in
//! f32 and f64 and gives the answer of the same problem at unit scale,
//! scaled.
//!
//! Moving `x0`, `x2` by λ and dividing σs, σa (and a distance sampler's σ)
//! by λ maps every vertex `x1` to `λ x1`, divides the weight `k/pdf` and
//! `f_c` by λ, the volume density by λ³, leaves the uniform numbers of an
//! inverse and every MIS weight alone, and divides the point-to-point
//! transfer `I` by λ². For λ a power of two inside the normal range this
//! holds bit for bit (the core works in the connection's unit `L = 2ᵏ`,
//! and scaling by a power of two is exact); for any λ it holds to the
//! rounding of the scaled end points. The tests:
//!
//! - power-of-two scales over the whole normal range of each precision:
//!   every technique's sample, density, weight, inverse and `f_c` are the
//!   unit problem's, scaled, exactly (proptest);
//! - scales over the whole exponent range, subnormal distances and
//!   distances near `F::MAX` included: the connection is accepted with the
//!   right `s` and frame, and nothing returns NaN, ∞ or a negative number
//!   (proptest);
//! - s = 1e-30, 1e30 (f32), 1e-300, 1e300 (f64), points near `F::MAX`:
//!   every technique's estimate, rescaled factor by factor
//!   (`(f_c λ)(weight λ)`, since the transfer `λ⁻² I` itself leaves the
//!   range), equals the same draws at unit scale and the quadrature
//!   reference of the unit problem;
//! - normals and directions of any finite non-zero length, θmax down to
//!   the smallest subnormal, and the errors for NaN and zero.

use crate::harness::{Rng, normal_two_sided_quantile, sidak};
use glam::{DVec3, Vec3};
use omnee::lobe::{LobeMis, LobeRay, LobeToPoint, PhaseLobe, WithLobe};
use omnee::medium::{Homogeneous, Region};
use omnee::mis::OmneeMis;
use omnee::phase::HenyeyGreenstein;
use omnee::reference::PointToPoint;
use omnee::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique, unit_normal,
};
use omnee::{Error, Real, Vector};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x7363_616c_6522),
        failure_persistence: None,
        ..Config::default()
    }
}

/// The estimators under test, by name; the cosine rays estimate the problem
/// with the receiver's cosine about their normal, the last three the
/// problem with the lobe at `x0`.
const NAMES: [&str; 8] = [
    "omnee",
    "equiangular",
    "equiangular (cosine)",
    "distance",
    "omnee mis",
    "omnee with lobe",
    "lobe ray",
    "lobe mis",
];

/// Which estimators have a finite variance on the extreme-scale problem.
const FINITE_VARIANCE: [bool; 8] = [true, false, false, false, true, true, false, true];

/// Which estimators estimate the problem with the lobe.
fn with_lobe(k: usize) -> bool {
    k >= 5
}

/// One problem in precision `F`: the connection, the medium (σs, σa), the
/// HG phase function at `x1`, a lobe at `x0` tilted off the axis, and a
/// normal for the cosine rays.
#[derive(Clone, Copy)]
struct Setup<F: Real> {
    connection: Connection<F>,
    sigma_s: F,
    sigma_a: F,
    hg: HenyeyGreenstein<F>,
    lobe: PhaseLobe<F, HenyeyGreenstein<F>>,
    normal: F::Vec3,
}

impl<F: Real> Setup<F> {
    /// The problem from `x0`, `x2`, θmax and the medium; the lobe's light
    /// arrives along `incoming` and the cosine rays leave about `normal`
    /// (both of any length).
    fn new(
        x0: F::Vec3,
        x2: F::Vec3,
        theta_max: F,
        (sigma_s, sigma_a): (F, F),
        incoming: F::Vec3,
        normal: F::Vec3,
    ) -> Result<Self, Error> {
        let hg = HenyeyGreenstein::new(F::from_f64(0.5))?;
        Ok(Self {
            connection: Connection::new(x0, x2, theta_max)?,
            sigma_s,
            sigma_a,
            hg,
            lobe: PhaseLobe::new(HenyeyGreenstein::new(F::from_f64(0.8))?, incoming)?,
            normal,
        })
    }

    fn medium(&self) -> Homogeneous<F> {
        Homogeneous::new(self.sigma_s, self.sigma_a).unwrap()
    }

    fn problem(&self) -> PointToPoint<F> {
        PointToPoint::new(self.connection, self.medium(), None).unwrap()
    }

    /// The problem with the receiver's cosine about the cosine rays'
    /// normal: what equiangular sampling over those rays estimates.
    fn cosine_problem(&self) -> PointToPoint<F> {
        PointToPoint::new(self.connection, self.medium(), Some(self.normal)).unwrap()
    }

    fn lobe_problem(&self) -> LobeToPoint<F, PhaseLobe<F, HenyeyGreenstein<F>>> {
        LobeToPoint::new(self.problem(), Some(self.lobe)).unwrap()
    }

    /// The vertices estimator `k` draws from `u` (two for the MIS with a
    /// companion, one otherwise).
    fn draw(&self, k: usize, u: [F; 6]) -> [Option<Sample<F>>; 2] {
        let (c, hg) = (self.connection, self.hg);
        let u3 = [u[0], u[1], u[2]];
        let everywhere = Region::Everywhere;
        let eq = Equiangular::new(c, hg, Directions::Sphere, everywhere);
        let one = |t: &dyn Technique<F>| [t.sample(u3), None];
        match k {
            0 => one(&Omnee::new(c, hg)),
            1 => one(&eq),
            2 => {
                let cosine = Directions::cosine(self.normal).unwrap();
                one(&Equiangular::new(c, hg, cosine, everywhere))
            }
            3 => {
                let sigma_t = self.sigma_s + self.sigma_a;
                one(&Distance::new(c, hg, Directions::Sphere, everywhere, sigma_t).unwrap())
            }
            4 => OmneeMis::recommended(Omnee::new(c, hg), &eq).sample(u),
            5 => one(&WithLobe::new(Omnee::new(c, hg), self.lobe, c.axis.x0)),
            6 => one(&LobeRay::new(c, self.lobe, hg)),
            _ => one(&LobeMis::recommended(c, self.lobe, hg)),
        }
    }

    /// The density estimator `k` gives its vertex `x1` (the MIS: the
    /// density OMNEE's vertices come with).
    fn pdf(&self, k: usize, x1: F::Vec3) -> F {
        let (c, hg) = (self.connection, self.hg);
        let everywhere = Region::Everywhere;
        let eq = Equiangular::new(c, hg, Directions::Sphere, everywhere);
        match k {
            0 | 5 => Omnee::new(c, hg).pdf(x1),
            1 => eq.pdf(x1),
            2 => {
                let cosine = Directions::cosine(self.normal).unwrap();
                Equiangular::new(c, hg, cosine, everywhere).pdf(x1)
            }
            3 => {
                let sigma_t = self.sigma_s + self.sigma_a;
                Distance::new(c, hg, Directions::Sphere, everywhere, sigma_t)
                    .unwrap()
                    .pdf(x1)
            }
            4 => OmneeMis::recommended(Omnee::new(c, hg), &eq).pdf(x1),
            6 => LobeRay::new(c, self.lobe, hg).pdf(x1),
            _ => LobeMis::recommended(c, self.lobe, hg).pdf(x1),
        }
    }

    /// The inverse of estimator `k` at `x1`, where it has one.
    fn invert(&self, k: usize, x1: F::Vec3) -> Option<[F; 3]> {
        let (c, hg) = (self.connection, self.hg);
        match k {
            0 => Omnee::new(c, hg).invert(x1),
            1 => Equiangular::new(c, hg, Directions::Sphere, Region::Everywhere).invert(x1),
            6 => LobeRay::new(c, self.lobe, hg).invert(x1),
            _ => None,
        }
    }

    /// `f_c` of the problem estimator `k` estimates.
    fn f_c(&self, k: usize, x1: F::Vec3) -> F {
        if with_lobe(k) {
            self.lobe_problem().f_c(x1)
        } else if k == 2 {
            self.cosine_problem().f_c(x1)
        } else {
            self.problem().f_c(x1)
        }
    }

    /// This problem scaled by `2ⁿ` (exact where the results are normal):
    /// end points times `2ⁿ`, σs and σa times `2⁻ⁿ`.
    fn scaled_pow2(&self, n: i32) -> Result<Self, Error> {
        let axis = &self.connection.axis;
        Ok(Self {
            connection: Connection::new(
                axis.x0.scale_pow2(n),
                axis.x2.scale_pow2(n),
                self.connection.theta_max,
            )?,
            sigma_s: self.sigma_s.scale_pow2(-n),
            sigma_a: self.sigma_a.scale_pow2(-n),
            ..*self
        })
    }
}

/// A base problem at unit scale from random numbers: `x0` in `[−2, 2]³`,
/// `x2` at a distance `s ∈ [1, 2)` along a random direction, θmax one of
/// π/2, π, or uniform in (0.1, π), σt s ∈ [0.2, 2] with albedo 0.8.
fn base<F: Real>(seed: u64) -> Setup<F> {
    let mut rng = Rng::new(seed);
    let x0 = DVec3::new(
        rng.range(-2.0, 2.0),
        rng.range(-2.0, 2.0),
        rng.range(-2.0, 2.0),
    );
    let x2 = x0 + rng.unit() * rng.range(1.0, 2.0);
    let theta_max = match rng.next_u64() % 3 {
        0 => core::f64::consts::FRAC_PI_2,
        1 => core::f64::consts::PI,
        _ => rng.range(0.1, core::f64::consts::PI),
    };
    let sigma_t = rng.range(0.2, 2.0) / (x2 - x0).length();
    let (incoming, normal) = (rng.unit(), rng.unit());
    let v = |p: DVec3| F::Vec3::new(F::from_f64(p.x), F::from_f64(p.y), F::from_f64(p.z));
    Setup::new(
        v(x0),
        v(x2),
        F::from_f64(theta_max),
        (F::from_f64(0.8 * sigma_t), F::from_f64(0.2 * sigma_t)),
        v(incoming),
        v(normal),
    )
    .unwrap()
}

/// `a` is `b · 2ⁿ` rounded once (the same number for `2ⁿ` inside the
/// normal range, the same saturation at its ends).
fn scaled_exactly<F: Real>(a: F, b: F, n: i32) -> bool {
    a == b.scale_pow2(n) || (a == F::MAX && b.scale_pow2(n) > F::MAX)
}

/// The band of exponents inside which a problem scaled by `2ⁿ` keeps every
/// intermediate of the unit problem's computation a normal number (2⁴⁰
/// from either end of the range).
fn band<F: Real>() -> core::ops::RangeInclusive<i32> {
    (F::MIN_EXPONENT + 40)..=(F::MAX_EXPONENT - 40)
}

/// The unit problem from `seed` against its scaling by `2ⁿ`, for every
/// estimator at the uniform numbers `u`: the same vertices times `2ⁿ`,
/// weights and `f_c` over `2ⁿ`, densities over `2³ⁿ`, the same inverse.
fn check_power_of_two<F: Real>(seed: u64, n: i32, u: [f64; 6]) -> Result<(), TestCaseError> {
    let unit = base::<F>(seed);
    let scaled = unit.scaled_pow2(n).unwrap();
    let u = u.map(F::from_f64);
    for (k, name) in NAMES.iter().enumerate() {
        let (a, b) = (unit.draw(k, u), scaled.draw(k, u));
        for (v, (a, b)) in a.iter().zip(&b).enumerate() {
            let what = format!("{name} vertex {v}, seed {seed}, 2^{n}");
            prop_assert_eq!(a.is_some(), b.is_some(), "{}", what);
            let (Some(a), Some(b)) = (a, b) else { continue };
            for (p, q) in b.x1.to_array().into_iter().zip(a.x1.to_array()) {
                prop_assert!(scaled_exactly(p, q, n), "{what}: x1 {:?} {:?}", b.x1, a.x1);
            }
            // The MIS companion's own density comes from its pdf where that
            // is a normal number and is evaluated again where it is not
            // (`Technique` has no way to return it): a few ulps apart.
            let close = |x: F, y: F, m: i32| {
                let want = y.scale_pow2(m);
                scaled_exactly(x, y, m)
                    || (k == 4
                        && v == 1
                        && (x - want).abs() <= F::from_f64(8.0) * F::EPSILON * want)
            };
            prop_assert!(close(b.weight, a.weight, -n), "{what}: weight {b:?} {a:?}");
            prop_assert!(close(b.pdf, a.pdf, -3 * n), "{what}: pdf {b:?} {a:?}");
            let (fa, fb) = (unit.f_c(k, a.x1), scaled.f_c(k, b.x1));
            prop_assert!(scaled_exactly(fb, fa, -n), "{what}: f_c {fb:?} {fa:?}");
            if v == 0 {
                let (pa, pb) = (unit.pdf(k, a.x1), scaled.pdf(k, b.x1));
                prop_assert!(
                    scaled_exactly(pb, pa, -3 * n),
                    "{what}: pdf(x1) {pb:?} {pa:?}"
                );
                let (ia, ib) = (unit.invert(k, a.x1), scaled.invert(k, b.x1));
                prop_assert_eq!(ia, ib, "{}: invert", what);
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn power_of_two_scales_give_the_unit_problems_numbers_scaled_f32(
        seed in any::<u64>(), n in band::<f32>(), u in prop::array::uniform6(0.0..1.0f64)
    ) {
        check_power_of_two::<f32>(seed, n, u)?;
    }

    #[test]
    fn power_of_two_scales_give_the_unit_problems_numbers_scaled_f64(
        seed in any::<u64>(), n in band::<f64>(), u in prop::array::uniform6(0.0..1.0f64)
    ) {
        check_power_of_two::<f64>(seed, n, u)?;
    }
}

/// The unit problem from `seed` scaled by `λ = m 2ⁿ` (`m ∈ [1, 2)`), for
/// any `n` from the subnormals to the top of the range: the connection is
/// accepted (unless the scaled end points round to one point or their
/// distance exceeds `F::MAX`), `s` and the frame are right, and every
/// estimator returns finite, non-negative numbers.
fn check_any_scale<F: Real>(seed: u64, m: f64, n: i32, u: [f64; 6]) -> Result<(), TestCaseError> {
    let unit = base::<F>(seed);
    let axis = &unit.connection.axis;
    let lambda = |p: F::Vec3| (p * F::from_f64(m)).scale_pow2(n);
    let (x0, x2) = (lambda(axis.x0), lambda(axis.x2));
    // The distance of the end points as given, in f64 on numbers scaled
    // back by 2⁻ⁿ (exact in f64 for every f32; for f64 inputs a classic
    // hypot by the largest component, an independent computation).
    let d = [0, 1, 2].map(|i| x2.to_array()[i].to_f64() - x0.to_array()[i].to_f64());
    let largest = d.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let s_ref = if largest > 0.0 {
        largest * d.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
    } else {
        0.0
    };
    let c = Connection::new(x0, x2, unit.connection.theta_max);
    if s_ref == 0.0 {
        prop_assert!(matches!(c, Err(Error::Degenerate { .. })), "{c:?}");
        return Ok(());
    }
    if !(s_ref <= F::MAX.to_f64()) {
        prop_assert!(matches!(c, Err(Error::NotFinite { .. })), "{c:?}");
        return Ok(());
    }
    let c = c.map_err(|e| TestCaseError::fail(format!("seed {seed} {m}·2^{n}: {e}")))?;
    let a = &c.axis;
    // s rounded once: within an ulp of the exact distance (a subnormal
    // s within one subnormal spacing).
    let ulp = F::EPSILON.to_f64() * s_ref + F::MIN_POSITIVE.to_f64() * F::EPSILON.to_f64();
    prop_assert!(
        (a.s.to_f64() - s_ref).abs() <= 2.0 * ulp,
        "s {:?} vs {s_ref:e}",
        a.s
    );
    let eps = 4.0 * F::EPSILON.to_f64();
    let dot = |p: F::Vec3, q: F::Vec3| p.dot(q).to_f64();
    prop_assert!((dot(a.e, a.e) - 1.0).abs() < eps && (dot(a.b1, a.b1) - 1.0).abs() < eps);
    prop_assert!(dot(a.e, a.b1).abs() < eps && dot(a.e, a.b2).abs() < eps);
    // The direction from d/max|dᵢ| (normal numbers even where d is
    // subnormal).
    let norm = d.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt();
    for (i, di) in d.iter().enumerate() {
        let e_i = a.e.to_array()[i].to_f64();
        prop_assert!(
            (e_i - di / largest / norm).abs() < eps,
            "e {:?} vs {d:?}",
            a.e
        );
    }
    // σ over λ, capped where that leaves the range (the medium then is
    // thick beyond what the precision can attenuate).
    let sigma = |x: F| F::from_f64((x.to_f64() / m).scale_pow2(-n).min(F::MAX.to_f64() / 16.0));
    let scaled = Setup {
        connection: c,
        sigma_s: sigma(unit.sigma_s),
        sigma_a: sigma(unit.sigma_a),
        ..unit
    };
    let u = u.map(F::from_f64);
    let finite = |x: F| x.is_finite() && x >= F::ZERO;
    for (k, name) in NAMES.iter().enumerate() {
        for s in scaled.draw(k, u).into_iter().flatten() {
            prop_assert!(s.x1.is_finite(), "{name}: {s:?}");
            prop_assert!(finite(s.pdf) && finite(s.weight), "{name}: {s:?}");
            prop_assert!(finite(scaled.f_c(k, s.x1)), "{name}: f_c at {s:?}");
            prop_assert!(finite(scaled.pdf(k, s.x1)), "{name}: pdf at {s:?}");
            if let Some(v) = scaled.invert(k, s.x1) {
                prop_assert!(v.iter().all(|&x| x >= F::ZERO && x <= F::ONE), "{v:?}");
            }
        }
    }
    Ok(())
}

/// The exponents of λ from where the end points' coordinates become
/// subnormal to where they overflow: the scaled `|x0| ≤ 4`, `s < 2`.
fn whole_range<F: Real>() -> core::ops::RangeInclusive<i32> {
    (F::MIN_EXPONENT - (-F::EPSILON.to_f64().log2()) as i32 - 4)..=(F::MAX_EXPONENT - 1)
}

proptest! {
    #![proptest_config(config(512))]

    #[test]
    fn every_scale_is_accepted_with_its_frame_and_never_gives_nan_f32(
        seed in any::<u64>(), m in 1.0..2.0f64, n in whole_range::<f32>(),
        u in prop::array::uniform6(0.0..1.0f64)
    ) {
        check_any_scale::<f32>(seed, m, n, u)?;
    }

    #[test]
    fn every_scale_is_accepted_with_its_frame_and_never_gives_nan_f64(
        seed in any::<u64>(), m in 1.0..2.0f64, n in whole_range::<f64>(),
        u in prop::array::uniform6(0.0..1.0f64)
    ) {
        check_any_scale::<f64>(seed, m, n, u)?;
    }
}

/// The extreme scales the C and Python checks use: s = 1e-30, 1e30 (and
/// end points 1e38 and 3e38 apart, θmax = π/2 there) in f32; 1e-300,
/// 1e300, 1.6e308 in f64; and `(0.6 max, 0, 0)` to `(0, 0.6 max, 0)`.
fn extreme_scales<F: Real>() -> Vec<(f64, bool)> {
    let max = F::MAX.to_f64();
    let (tiny, huge) = if F::EPSILON.to_f64() > 1e-10 {
        (1e-30, 1e30)
    } else {
        (1e-300, 1e300)
    };
    // (λ, whether θmax must stay π/2: near F::MAX the vertices behind the
    // Thales ball lie beyond the range).
    vec![
        (tiny, false),
        (huge, false),
        (0.3 * max, true),
        (0.6 * max, true),
    ]
}

/// Every estimator's mean over `n` draws of `(f_c λ)(weight λ)` at scale λ
/// (x0 = (1, 0, 0), x2 = (0, 1, 0), both times λ; σ over λ): equal to the
/// same draws at unit scale up to the rounding of the scaled end points;
/// and, for the estimators of finite variance (OMNEE, its MIS, OMNEE with
/// the lobe, the lobe MIS), to the quadrature reference of the unit
/// problem within its standard error (the ray techniques' weights have
/// infinite variance on this problem, `1/d1²` next to `x0`, so their
/// unbiasedness is the business of the suite's unit-scale tests). Also: no
/// refusal, no NaN, and a vertex for most draws.
fn check_extreme<F: Real>(seed: u64, n: usize) {
    let lobe_axis = F::Vec3::new(F::ZERO, F::ZERO, F::ONE);
    let normal = F::Vec3::new(F::from_f64(0.3), F::from_f64(-0.2), F::ONE);
    let tests = 2 * extreme_scales::<F>().len() * FINITE_VARIANCE.iter().filter(|&&f| f).count();
    let z = normal_two_sided_quantile(sidak(1e-5, tests));
    // The references of the unit problem (f64) for θmax = π and π/2:
    // without and with the lobe.
    let reference = |theta_max: f64| {
        let c64 = Connection::new(DVec3::X, DVec3::Y, theta_max).unwrap();
        let medium = Homogeneous::new(0.4, 0.1).unwrap();
        let point = PointToPoint::new(c64, medium, None).unwrap();
        let hg = HenyeyGreenstein::new(0.5).unwrap();
        let lobe = PhaseLobe::new(HenyeyGreenstein::new(0.8).unwrap(), DVec3::Z).unwrap();
        let normal = DVec3::new(0.3, -0.2, 1.0);
        [
            point.try_integral(&hg).unwrap(),
            LobeToPoint::new(point, Some(lobe))
                .unwrap()
                .try_integral(&hg)
                .unwrap(),
            PointToPoint::new(c64, medium, Some(normal))
                .unwrap()
                .try_integral(&hg)
                .unwrap(),
        ]
    };
    let start = std::time::Instant::now();
    let references_pi = reference(core::f64::consts::PI);
    let references_half = reference(core::f64::consts::FRAC_PI_2);
    println!("references: {:?}", start.elapsed());
    for (lambda, thales) in extreme_scales::<F>() {
        let theta_max = if thales { F::FRAC_PI_2 } else { F::PI };
        let references = if thales {
            references_half
        } else {
            references_pi
        };
        let at = |scale: f64| {
            let v = |x: f64, y: f64| F::Vec3::new(F::from_f64(x), F::from_f64(y), F::ZERO);
            let sigma = F::from_f64(0.5 / scale);
            Setup::new(
                v(scale, 0.0),
                v(0.0, scale),
                theta_max,
                (F::from_f64(0.4 / scale), sigma - F::from_f64(0.4 / scale)),
                lobe_axis,
                normal,
            )
            .unwrap_or_else(|e| panic!("λ = {lambda:e}: {e}"))
        };
        let (unit, scaled) = (at(1.0), at(lambda));
        for k in 0..NAMES.len() {
            let mut rng = Rng::new(seed ^ k as u64);
            let (mut sum, mut sum2, mut unit_sum, mut drawn) = (0.0, 0.0, 0.0, 0usize);
            for _ in 0..n {
                let u: [F; 6] = core::array::from_fn(|_| rng.uniform());
                let estimate = |setup: &Setup<F>, scale: f64| -> f64 {
                    let mut e = 0.0;
                    for s in setup.draw(k, u).into_iter().flatten() {
                        let f_c = setup.f_c(k, s.x1);
                        assert!(
                            s.x1.is_finite() && s.pdf.is_finite() && s.weight.is_finite(),
                            "{} at λ = {lambda:e}: {s:?}",
                            NAMES[k]
                        );
                        assert!(f_c.is_finite() && f_c >= F::ZERO && s.weight >= F::ZERO);
                        e += (f_c.to_f64() * scale) * (s.weight.to_f64() * scale);
                    }
                    e
                };
                let e = estimate(&scaled, lambda);
                drawn += usize::from(scaled.draw(k, u)[0].is_some());
                sum += e;
                sum2 += e * e;
                unit_sum += estimate(&unit, 1.0);
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
            let reference = if k == 2 {
                references[2]
            } else {
                references[usize::from(with_lobe(k))]
            };
            let unit_mean = unit_sum / n as f64;
            // The scaled end points are rounded to the precision: the two
            // problems differ by about ε relative.
            let tol = 64.0 * F::EPSILON.to_f64();
            println!(
                "{:>21} {} λ = {lambda:.1e}: {mean:.6e} ± {se:.1e}, unit {unit_mean:.6e}, reference {reference:.6e}, vertices {drawn}/{n}",
                NAMES[k],
                if tol > 1e-10 { "f32" } else { "f64" },
            );
            assert!(
                (mean / unit_mean - 1.0).abs() < tol,
                "{} λ = {lambda:e}: {mean:e} against unit scale {unit_mean:e}",
                NAMES[k]
            );
            assert!(
                !FINITE_VARIANCE[k] || (mean - reference).abs() < z * se + 1e-4 * reference,
                "{} λ = {lambda:e}: {mean:e} ± {se:e} against the reference {reference:e}",
                NAMES[k]
            );
            assert!(drawn > n / 4, "{}: {drawn} vertices of {n}", NAMES[k]);
        }
    }
}

#[test]
fn extreme_scales_estimate_the_scaled_reference_f32() {
    check_extreme::<f32>(1, 1 << 15);
}

#[test]
fn extreme_scales_estimate_the_scaled_reference_f64() {
    check_extreme::<f64>(2, 1 << 15);
}

/// Normals and directions of any finite, non-zero length give the unit
/// vector of the same direction; NaN or ∞ is `NotFinite`, zero
/// `Degenerate`, in the cosine rays, the receiver normal and the lobe.
fn check_normals<F: Real>() {
    let tiny = F::from_f64(1e-30);
    let sub = F::MIN_POSITIVE.scale_pow2(-(-F::EPSILON.to_f64().log2()) as i32);
    let max = F::MAX;
    let want = unit_normal::<F>(F::Vec3::new(F::ONE, F::ONE, F::ONE), "n").unwrap();
    for n in [
        F::Vec3::new(tiny, tiny, tiny),
        F::Vec3::new(sub, sub, sub),
        F::Vec3::new(max, max, max),
        F::Vec3::new(F::ONE, F::ONE, F::ONE).scale_pow2(F::MAX_EXPONENT),
    ] {
        let got = unit_normal::<F>(n, "n").unwrap();
        let err = Vector::length(got - want).to_f64();
        assert!(
            err <= 2.0 * F::EPSILON.to_f64(),
            "{n:?}: {got:?} vs {want:?}"
        );
        let Directions::Cosine { normal, .. } = Directions::<F>::cosine(n).unwrap() else {
            panic!("not a cosine");
        };
        let err = Vector::length(normal - want).to_f64();
        assert!(err <= 2.0 * F::EPSILON.to_f64(), "{n:?}: {normal:?}");
        let c = Connection::new(
            F::Vec3::new(F::ZERO, F::ZERO, F::ONE),
            F::Vec3::new(F::ZERO, F::ZERO, F::ZERO),
            F::PI,
        )
        .unwrap();
        let medium = Homogeneous::new(F::HALF, F::ZERO).unwrap();
        let p = PointToPoint::new(c, medium, Some(n)).unwrap();
        let q = PointToPoint::new(c, medium, Some(want)).unwrap();
        let x1 = F::Vec3::new(F::HALF, F::ZERO, F::HALF);
        let (a, b) = (p.f_c(x1).to_f64(), q.f_c(x1).to_f64());
        assert!(
            (a / b - 1.0).abs() <= 4.0 * F::EPSILON.to_f64(),
            "{n:?}: {a} {b}"
        );
        assert!(PhaseLobe::new(HenyeyGreenstein::new(F::HALF).unwrap(), n).is_ok());
    }
    let nan = F::Vec3::new(F::ZERO, F::from_f64(f64::NAN), F::ONE);
    let inf = F::Vec3::new(F::INFINITY, F::ZERO, F::ONE);
    let zero = F::Vec3::new(F::ZERO, F::ZERO, F::ZERO);
    for bad in [nan, inf] {
        assert_eq!(
            Directions::<F>::cosine(bad),
            Err(Error::not_finite("normal"))
        );
    }
    assert!(matches!(
        Directions::<F>::cosine(zero),
        Err(Error::Degenerate {
            field: "normal",
            ..
        })
    ));
    let c = Connection::new(zero, F::Vec3::new(F::ONE, F::ZERO, F::ZERO), F::PI).unwrap();
    let medium = Homogeneous::new(F::HALF, F::ZERO).unwrap();
    assert!(matches!(
        PointToPoint::new(c, medium, Some(nan)),
        Err(Error::NotFinite {
            field: "receiver_normal",
            ..
        })
    ));
    assert!(matches!(
        PointToPoint::new(c, medium, Some(zero)),
        Err(Error::Degenerate {
            field: "receiver_normal",
            ..
        })
    ));
}

#[test]
fn normals_of_any_finite_non_zero_length_are_accepted_f32() {
    check_normals::<f32>();
}

#[test]
fn normals_of_any_finite_non_zero_length_are_accepted_f64() {
    check_normals::<f64>();
}

#[test]
fn theta_max_takes_its_whole_range_and_a_subnormal_restriction_samples_straight_on() {
    let smallest32 = f32::from_bits(1);
    let smallest64 = f64::from_bits(1);
    let c32 = Connection::new(Vec3::ZERO, Vec3::X, smallest32).unwrap();
    let c64 = Connection::new(DVec3::ZERO, DVec3::X, smallest64).unwrap();
    assert_eq!((c32.theta_max, c64.theta_max), (smallest32, smallest64));
    for bad in [0.0, -smallest64, f64::NAN, 3.2] {
        assert!(matches!(
            Connection::new(DVec3::ZERO, DVec3::X, bad),
            Err(Error::OutOfRange {
                field: "theta_max",
                ..
            })
        ));
    }
    // Only θ = 0 lies below θmax: the segment from x0 to x2, where the
    // weight is 1/s; the reference is finite.
    let hg = HenyeyGreenstein::new(0.5).unwrap();
    let omnee = Omnee::new(c64, hg);
    if let Some(s) = omnee.sample([0.0, 0.25, 0.5]) {
        assert_eq!(s.weight, 1.0);
        assert!((s.x1 - DVec3::new(0.25, 0.0, 0.0)).length() < 1e-15);
    }
    let p = PointToPoint::new(c64, Homogeneous::new(0.5, 0.0).unwrap(), None).unwrap();
    let r = p.try_integral(&hg).unwrap();
    assert!(r.is_finite() && r >= 0.0, "{r}");
}

#[test]
fn a_distance_beyond_the_largest_number_is_named_not_finite() {
    let max = f32::MAX;
    // Opposite sides near the top: x2 − x0 itself overflows.
    let far = Connection::<f32>::new(
        Vec3::new(0.6 * max, 0.0, 0.0),
        Vec3::new(-0.6 * max, 0.0, 0.0),
        1.0,
    );
    assert_eq!(far.unwrap_err(), Error::not_finite("x2 - x0"));
    // Every component representable, the distance √3 max is not.
    let diagonal = Connection::<f32>::new(Vec3::ZERO, Vec3::splat(max), 1.0);
    assert_eq!(diagonal.unwrap_err(), Error::not_finite("x2 - x0"));
    // (0.6 max, 0, 0) to (0, 0.6 max, 0): 0.85 max, accepted exactly.
    let c = Connection::<f32>::new(
        Vec3::new(0.6 * max, 0.0, 0.0),
        Vec3::new(0.0, 0.6 * max, 0.0),
        1.0,
    )
    .unwrap();
    let want = (0.6 * max as f64) * 2f64.sqrt();
    assert!((c.axis.s as f64 / want - 1.0).abs() < 1e-7, "{}", c.axis.s);
    let e = c.axis.e;
    let want_e: Vec3 = Vec3::new(-1.0, 1.0, 0.0) / 2f32.sqrt();
    assert!((e - want_e).length() < 1e-7, "{e}");
}

/// One case of the reference's scale law: the base problem's end points
/// `(0, 0, 0)` and `(1.25, 0.5, −0.75) 2^base` (exactly representable at
/// every shift below), σs = 0.6 · 2^sigma, σa = 0.3 · 2^sigma, scaled by
/// `2^shift`; σ is chosen per case, `sigma[1]` for θmax = 1e-30 (whose
/// transfer is 2^-193 times smaller), so that the base reference is a
/// normal number and the scaled one is representable or, at 2^500 and
/// 2^1000, below the smallest subnormal by the law.
struct ReferenceScale {
    base: i32,
    shift: i32,
    sigma: [i32; 2],
}

/// The point-to-point reference (HG 0.9) of the base problem of `case`
/// scaled by `2^shift` (0: the base problem), with θmax and the receiver
/// normal given.
fn reference_at<F: Real>(
    case: &ReferenceScale,
    shift: i32,
    theta_max: f64,
    normal: Option<[f64; 3]>,
) -> Result<f64, Error> {
    let v = |x: f64, y: f64, z: f64| {
        F::Vec3::new(F::from_f64(x), F::from_f64(y), F::from_f64(z)).scale_pow2(case.base + shift)
    };
    let c = Connection::new(
        v(0.0, 0.0, 0.0),
        v(1.25, 0.5, -0.75),
        F::from_f64(theta_max),
    )?;
    let exponent = case.sigma[usize::from(theta_max < 1e-20)];
    let sigma = |x: f64| F::from_f64(x).scale_pow2(exponent - shift);
    let medium = Homogeneous::new(sigma(0.6), sigma(0.3))?;
    let normal =
        normal.map(|[x, y, z]| F::Vec3::new(F::from_f64(x), F::from_f64(y), F::from_f64(z)));
    PointToPoint::new(c, medium, normal)?.try_integral(&HenyeyGreenstein::new(0.9).unwrap())
}

/// `I(λ) = I(1)/λ²` for every case, θmax = π, π/2 and 1e-30 (a normal at
/// π/2 too): bit for bit, the scaled reference equals the base one times
/// `2^(−2 shift)`, rounded once (so also where it leaves the normal range).
fn check_reference_scales<F: Real>(cases: &[ReferenceScale]) {
    let pi = core::f64::consts::PI;
    let mut failures = Vec::new();
    for case in cases {
        for (theta_max, normal) in [
            (pi, None),
            (0.5 * pi, None),
            (1e-30, None),
            (0.5 * pi, Some([0.3, -0.2, 1.0])),
        ] {
            let (base, scaled) = (
                reference_at::<F>(case, 0, theta_max, normal),
                reference_at::<F>(case, case.shift, theta_max, normal),
            );
            let line = format!(
                "s = 2^{} scaled by 2^{}, θmax {theta_max:e}, normal {normal:?}: {base:?} → {scaled:?}",
                case.base, case.shift
            );
            println!("{line}");
            match (base, scaled) {
                (Ok(a), Ok(b))
                    if a > 0.0 && a.is_finite() && b == a.scale_pow2(-2 * case.shift) => {}
                _ => failures.push(line),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The quadrature reference obeys the scale law the C header states
/// (docs/math.md §15.3) at normal scales, 2^±500, 2^±1000 (f64: the
/// transfer at 2^1000 is below the smallest subnormal, 0 by the law) and
/// for end points a subnormal distance apart. Formed in metres, σs/s
/// overflowed for a subnormal s: the reference said `NotConverged`.
#[test]
fn the_reference_obeys_the_scale_law_at_every_scale_f64() {
    let case = |base, shift, sigma| ReferenceScale { base, shift, sigma };
    check_reference_scales::<f64>(&[
        case(0, 20, [0, 0]),
        case(0, -20, [0, 0]),
        case(0, 500, [0, 0]),
        case(0, 1000, [0, 0]),
        case(0, -500, [-500, -500]),
        // σ times 2^1000 stays in range: the optical thickness is 2^-1000.
        case(0, -1000, [-1000, -800]),
        // (1.25, 0.5, −0.75) 2^-1070: a subnormal distance.
        case(-1000, -70, [-200, -200]),
    ]);
}

/// [`the_reference_obeys_the_scale_law_at_every_scale_f64`] for
/// single-precision problems: normal scales, 2^±100 and a subnormal f32
/// distance.
#[test]
fn the_reference_obeys_the_scale_law_at_every_scale_f32() {
    let case = |base, shift, sigma| ReferenceScale { base, shift, sigma };
    check_reference_scales::<f32>(&[
        case(0, 20, [0, 0]),
        case(0, -20, [0, 0]),
        case(0, 100, [0, 0]),
        case(0, -100, [0, 0]),
        // (1.25, 0.5, −0.75) 2^-140: a subnormal distance in f32.
        case(-120, -20, [100, 100]),
    ]);
}

/// End points 1e-320 apart, HG 0.9, σs = 0.5, σa = 0.25, no receiver
/// normal: for θmax = 1e-30 the reference is about 2e261, the same problem
/// scaled by 2^64 (a normal distance) times 2^128 bit for bit; for θmax = π
/// and π/2 it is beyond f64's range, +∞ by the same law (the C API's
/// `OMNEE_ERROR_NOT_FINITE`), never `NotConverged`.
#[test]
fn a_subnormal_distance_has_its_reference() {
    let hg = HenyeyGreenstein::new(0.9).unwrap();
    for theta_max in [1e-30, core::f64::consts::FRAC_PI_2, core::f64::consts::PI] {
        let at = |lambda: f64| {
            let x2 = DVec3::new(1e-320 * lambda, 0.0, 0.0);
            let c = Connection::new(DVec3::ZERO, x2, theta_max).unwrap();
            let medium = Homogeneous::new(0.5 / lambda, 0.25 / lambda).unwrap();
            PointToPoint::new(c, medium, None)
                .unwrap()
                .try_integral(&hg)
        };
        let (tiny, normal) = (at(1.0), at(2f64.powi(64)).unwrap());
        assert_eq!(tiny, Ok(normal * 2f64.powi(128)), "θmax {theta_max:e}");
        assert_eq!(
            tiny.unwrap().is_finite(),
            theta_max < 1.0,
            "θmax {theta_max:e}"
        );
    }
}
