//! Unit tests of the lobe module: the reference against the 2-D one, each
//! technique's weight against its kernel over its pdf, round trips, bad input.

use super::*;
use crate::medium::Homogeneous;
use crate::phase::{HenyeyGreenstein, Isotropic, Mixture, Phase, Spec};
use crate::reference::PointToPoint;
use crate::sampling::{Connection, Omnee};
use glam::DVec3;
use std::vec::Vec;

fn phase(spec: &str) -> Phase<'static, f64> {
    match Spec::<f64>::parse(spec).unwrap() {
        Spec::Analytic(p) => p,
        Spec::Table { .. } => unreachable!(),
    }
}

fn point(x0: DVec3, x2: DVec3, theta_max: f64, sigma_s: f64, sigma_t: f64) -> PointToPoint<f64> {
    let c = Connection::new(x0, x2, theta_max).unwrap();
    PointToPoint::new(
        c,
        Homogeneous::from_extinction(sigma_s, sigma_t).unwrap(),
        None,
    )
    .unwrap()
}

/// A direction tilted by `tilt` from `e` about an arbitrary azimuth.
fn tilted(e: DVec3, tilt: f64) -> DVec3 {
    let (b1, b2) = e.any_orthonormal_pair();
    e * tilt.cos() + (b1 * 0.6 + b2 * 0.8) * tilt.sin()
}

/// A deterministic low-discrepancy sequence of uniform triples.
fn triples(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let i = i as f64 + 0.5;
            [
                (i * 0.754_877_666_246_692_7).fract(),
                (i * 0.569_840_290_998_053_2).fract(),
                (i / n as f64).fract(),
            ]
        })
        .collect()
}

#[test]
fn isotropic_lobe_reference_is_the_two_dimensional_one_over_four_pi() {
    let start = std::time::Instant::now();
    let cases = [
        ("hg:0.9", core::f64::consts::PI, 0.5, 0.55),
        ("hg:0.98", core::f64::consts::FRAC_PI_2, 0.2, 1.0),
        ("tthg:0.99,-0.44,0.954", 2.5, 0.5, 0.55),
        ("hg:-0.5", core::f64::consts::PI, 0.3, 0.0),
    ];
    for (spec, theta_max, sigma_s, sigma_t) in cases {
        let p = point(
            DVec3::new(0.3, -0.2, 0.1),
            DVec3::new(1.1, 0.4, -0.3),
            theta_max,
            sigma_s,
            sigma_t,
        );
        let p1 = phase(spec);
        let lobe = PhaseLobe::new(Isotropic, DVec3::new(0.2, 0.9, -0.1)).unwrap();
        let with = LobeToPoint::new(p, Some(lobe)).unwrap().integral(&p1);
        let plain = p.integral(&p1) / (4.0 * core::f64::consts::PI);
        assert!(
            (with / plain - 1.0).abs() < 1e-8,
            "{spec}: {with:e} vs {plain:e}"
        );
        let without = LobeToPoint::<f64, PhaseLobe<f64, Isotropic>>::new(p, None)
            .unwrap()
            .integral(&p1);
        assert_eq!(without, p.integral(&p1));
    }
    std::println!("four isotropic-lobe references: {:?}", start.elapsed());
}

#[test]
fn lobe_along_the_axis_without_attenuation_is_a_double_integral() {
    // ω_in = e, σt = 0: Φ0(α) = 2π p0(α), so
    // I = (2π σs / s) ∫₀^θmax p0(α) (P1(θmax) − P1(α)) / (2π sin) ... written
    // with the cdf: ∫_α^θmax p1 dθ has no closed form, but for p1 isotropic it
    // is (θmax − α)/(4π): I = (σs / (2 s)) ∫₀^θmax p0(α) (θmax − α) dα.
    let (x0, x2) = (DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0));
    let theta_max = 2.0;
    let p = point(x0, x2, theta_max, 1e-200, 0.0);
    let p0 = HenyeyGreenstein::new(0.9).unwrap();
    let lobe = PhaseLobe::new(p0, DVec3::Z).unwrap();
    let got = LobeToPoint::new(p, Some(lobe))
        .unwrap()
        .integral(&Isotropic)
        / 1e-200;
    let want = 1.0 / (2.0 * 2.0)
        * crate::quadrature::integrate_geometric(
            |a| p0.eval(crate::phase::Deflection::from_theta(a)) * (theta_max - a),
            0.0,
            theta_max,
            30,
            1e-13,
        );
    assert!((got / want - 1.0).abs() < 1e-9, "{got:e} vs {want:e}");
}

/// Every sample's weight is its kernel over its pdf, its pdf the
/// technique's `pdf`, and (where invertible) `invert` returns its numbers.
fn check_trio<T: Technique<f64>>(
    name: &str,
    t: &T,
    problem: &LobeToPoint<f64, PhaseLobe<f64, Phase<'static, f64>>>,
    p1: &Phase<'static, f64>,
    invertible: bool,
) {
    let mut returned = 0;
    for u in triples(4000) {
        let Some(s) = t.sample(u) else { continue };
        returned += 1;
        assert!(
            s.x1.is_finite() && s.pdf > 0.0 && s.weight >= 0.0,
            "{name} {u:?}: {s:?}"
        );
        let pdf = t.pdf(s.x1);
        assert!(
            (pdf / s.pdf - 1.0).abs() < 1e-7,
            "{name} {u:?}: pdf {pdf:e} vs {:e}",
            s.pdf
        );
        let k = problem.kernel(p1, s.x1);
        if s.pdf < 1e12 && k > 0.0 {
            let w = k / s.pdf;
            assert!(
                (s.weight / w - 1.0).abs() < 1e-6,
                "{name} {u:?}: weight {:e} vs {w:e}",
                s.weight
            );
        }
        if invertible {
            let back = t.invert(s.x1).unwrap();
            for k in 0..3 {
                assert!((back[k] - u[k]).abs() < 1e-6, "{name} {u:?} -> {back:?}");
            }
        }
    }
    // θmax = π/2 leaves no interval [α, θmax) to half the directions of an
    // isotropic lobe.
    assert!(returned > 1900, "{name}: {returned} samples of 4000");
}

#[test]
fn every_technique_weighs_its_kernel_by_its_pdf() {
    let (x0, x2) = (DVec3::new(0.1, 0.2, -0.3), DVec3::new(0.9, -0.4, 0.5));
    for (spec0, spec1, tilt, theta_max, invertible) in [
        ("hg:0.9", "hg:0.9", 0.5, core::f64::consts::PI, true),
        ("hg:0.98", "hg:0.5", 0.05, 2.5, true),
        ("hg:-0.7", "rayleigh", 2.0, core::f64::consts::PI, true),
        (
            "tthg:0.99,-0.44,0.954",
            "tthg:0.997,0.96,0.5",
            1.0,
            core::f64::consts::PI,
            false,
        ),
        ("iso", "mie:10", 0.0, core::f64::consts::FRAC_PI_2, false),
    ] {
        let p = point(x0, x2, theta_max, 0.5, 0.55);
        let e = p.connection.axis.e;
        let lobe = PhaseLobe::new(phase(spec0), tilted(e, tilt)).unwrap();
        let p1 = phase(spec1);
        let problem = LobeToPoint::new(p, Some(lobe)).unwrap();
        let ray = LobeRay::new(p.connection, lobe, p1);
        check_trio(
            &std::format!("ray {spec0} {spec1}"),
            &ray,
            &problem,
            &p1,
            invertible,
        );
        let omnee = WithLobe::new(Omnee::new(p.connection, p1), lobe, x0);
        check_trio(
            &std::format!("omnee {spec0} {spec1}"),
            &omnee,
            &problem,
            &p1,
            spec1 != "mie:10" && !spec1.starts_with("tthg"),
        );
        for mis in [
            LobeMis::recommended(p.connection, lobe, p1),
            LobeMis::new(p.connection, lobe, p1, 0.3).unwrap(),
        ] {
            check_trio(
                &std::format!("mis {spec0} {spec1}"),
                &mis,
                &problem,
                &p1,
                false,
            );
        }
    }
}

#[test]
fn restricted_sampling_stays_in_its_interval_with_the_mixture_mass() {
    let lo = crate::phase::Deflection::from_theta(0.7);
    let hi = crate::phase::Deflection::from_theta(2.9);
    for spec in [
        "hg:0.98",
        "tthg:0.99,-0.44,0.954",
        "mie:10",
        "ff:0.0183,1.1",
        "iso",
    ] {
        let p = phase(spec);
        let mass = p.mass_between(lo, hi);
        let want = p.cdf(hi) - p.cdf(lo);
        assert!(
            (mass / want - 1.0).abs() < 1e-12,
            "{spec}: {mass} vs {want}"
        );
        for i in 0..1000 {
            let u = (i as f64 + 0.5) / 1000.0;
            let (d, m) = p.sample_between(lo, hi, u).unwrap();
            assert_eq!(m, mass);
            assert!(
                d.theta >= lo.theta && d.theta <= hi.theta,
                "{spec} u {u}: {d:?}"
            );
        }
    }
    let two = Mixture::two_term(0.9, -0.5, 0.5).unwrap();
    let d = two.sample_between(lo, hi, 0.999_999).unwrap().0;
    assert!(d.theta <= hi.theta);
    // An empty interval has no sample.
    assert!(
        HenyeyGreenstein::new(0.5)
            .unwrap()
            .sample_between(hi, hi, 0.5)
            .is_none()
    );
}

#[test]
fn recommended_probability_is_zero_where_omnee_needs_no_help() {
    let c = Connection::new(DVec3::ZERO, DVec3::Z, core::f64::consts::PI).unwrap();
    let p1 = HenyeyGreenstein::new(0.9).unwrap();
    let iso = PhaseLobe::new(Isotropic, DVec3::X).unwrap();
    assert_eq!(LobeMis::recommended(c, iso, p1).probability(), 0.0);
    let along = PhaseLobe::new(HenyeyGreenstein::new(0.98).unwrap(), DVec3::Z).unwrap();
    assert_eq!(LobeMis::recommended(c, along, p1).probability(), 0.0);
    // A mild lobe tilted by 1 rad: p0(e)/p0_peak = 0.21 > 0.1.
    let mild = PhaseLobe::new(HenyeyGreenstein::new(0.5).unwrap(), tilted(DVec3::Z, 1.0)).unwrap();
    assert_eq!(LobeMis::recommended(c, mild, p1).probability(), 0.0);
    let away = PhaseLobe::new(HenyeyGreenstein::new(0.98).unwrap(), DVec3::X).unwrap();
    let q = LobeMis::recommended(c, away, p1).probability();
    assert!(q > 0.49 && q <= 0.5, "{q}");
    assert!(LobeMis::new(c, away, p1, 1.5).is_err());
    assert!(LobeMis::new(c, away, p1, f64::NAN).is_err());
}

#[test]
fn bad_input_is_refused_or_gives_no_sample() {
    let hg = HenyeyGreenstein::new(0.9).unwrap();
    assert!(PhaseLobe::new(hg, DVec3::ZERO).is_err());
    assert!(PhaseLobe::new(hg, DVec3::new(f64::NAN, 0.0, 1.0)).is_err());
    assert!(PhaseLobe::new(hg, DVec3::new(f64::INFINITY, 0.0, 1.0)).is_err());
    assert!(PhaseLobe::new(hg, DVec3::new(1e300, 1e300, 0.0)).is_ok());
    let lobe: PhaseLobe<f64, _> = PhaseLobe::new(hg, DVec3::new(0.0, 3.0, 4.0)).unwrap();
    assert!((lobe.incoming().length() - 1.0).abs() < 1e-15);
    let c = Connection::new(DVec3::ZERO, DVec3::Z, core::f64::consts::PI).unwrap();
    let mis = LobeMis::recommended(c, lobe, hg);
    let ray = LobeRay::new(c, lobe, hg);
    for u in [
        [f64::NAN; 3],
        [-1.0, 2.0, 0.5],
        [1.0, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        [f64::INFINITY, f64::NEG_INFINITY, 0.3],
    ] {
        for t in [&mis as &dyn Technique<f64>, &ray] {
            if let Some(s) = t.sample(u) {
                assert!(
                    s.x1.is_finite() && s.pdf.is_finite() && s.weight.is_finite(),
                    "{u:?}: {s:?}"
                );
            }
        }
    }
    for x1 in [
        DVec3::ZERO,
        DVec3::Z,
        DVec3::new(0.0, 0.0, 0.5),
        DVec3::splat(f64::NAN),
        DVec3::new(0.0, 0.0, -3.0),
    ] {
        for t in [&mis as &dyn Technique<f64>, &ray] {
            let pdf = t.pdf(x1);
            assert!(pdf.is_finite() && pdf >= 0.0, "{x1}: {pdf}");
        }
    }
}

#[test]
fn a_lobe_with_a_receiver_normal_is_refused() {
    let c = Connection::new(DVec3::ZERO, DVec3::Z, 2.0).unwrap();
    let medium = Homogeneous::from_extinction(0.5, 0.8).unwrap();
    let p = PointToPoint::new(c, medium, Some(DVec3::new(0.2, 0.4, -1.0))).unwrap();
    let lobe = PhaseLobe::new(Isotropic, DVec3::X).unwrap();
    let e = LobeToPoint::new(p, Some(lobe)).unwrap_err();
    assert_eq!(e.field(), "receiver_normal");
    assert!(LobeToPoint::<f64, PhaseLobe<f64, Isotropic>>::new(p, None).is_ok());
}

#[test]
fn a_table_sampled_lobe_reports_the_phase_functions_value_and_the_tables_density() {
    use crate::phase::{InverseCdf, TableSampled};
    let ff = phase("ff:0.0183,1.1");
    let table = InverseCdf::new(&ff).unwrap();
    let incoming = DVec3::new(0.0, 0.6, 0.8);
    let lobe = PhaseLobe::new(TableSampled::new(ff, &table), incoming).unwrap();
    let mut apart = 0;
    for u in triples(2000) {
        let s = lobe.sample([u[0], u[1]]).unwrap();
        let (value, pdf) = (lobe.eval(s.omega), lobe.pdf(s.omega));
        assert!(
            (s.value / value - 1.0).abs() < 1e-9 && (s.pdf / pdf - 1.0).abs() < 1e-7,
            "{u:?}: {s:?} against eval {value:e}, pdf {pdf:e}"
        );
        // The table is close to p0 but not p0: the ratio is not always 1.
        if (s.value / s.pdf - 1.0).abs() > 1e-6 {
            apart += 1;
        }
    }
    assert!(apart > 100, "{apart} of 2000 draws with p0/q ≠ 1");
}
