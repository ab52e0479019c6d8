//! `omnee probe` against closed forms and quadratures.

use crate::common::*;
use std::path::Path;

/// Probe a scene file made from the default scene.
fn probe(dir: &Path, scene: &str, args: &[&str]) -> serde_json::Value {
    let mut a = vec!["probe", "--scene", scene, "--json"];
    a.extend(args);
    json(&run_in(dir, &a))
}

#[test]
fn probe_of_a_point_light_is_the_inverse_square_law_with_attenuation() {
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "point.toml", |t| {
        let t = replace_line(&t, "radius =", "radius = 0.0");
        let t = replace_line(&t, "radiance =", "intensity = 2.0");
        let cut = t.find("[occluder]").unwrap();
        let end = t.find("[camera]").unwrap();
        format!("{}{}", &t[..cut], &t[end..])
    });
    let v = probe(
        dir.path(),
        "point.toml",
        &[
            "--point",
            "0.3,0.4,0",
            "--terms",
            "direct",
            "--samples",
            "1000",
        ],
    );
    // E = I cos / d² · exp(−σt d), all of d inside the slab; zero variance.
    let d = (0.3f64 * 0.3 + 0.4 * 0.4 + 0.95 * 0.95).sqrt();
    let want = 2.0 * (0.95 / d) / (d * d) * (-0.55 * d).exp();
    let got = v["terms"]["direct"]["mean"].as_f64().unwrap();
    assert!((got / want - 1.0).abs() < 1e-5, "{got} vs {want}");
    assert_eq!(v["samples"], 1000);
    assert!(v["terms"]["once-more"].is_null());
}

#[test]
fn probe_of_a_sphere_light_in_vacuum_matches_the_point_light_of_equal_intensity() {
    // An unoccluded sphere of radiance L and radius r gives, at a point that
    // sees all of its visible cap, the irradiance of a point light of
    // intensity L π r² at its centre, times the cosine: exact, not approximate.
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "vac.toml", |t| {
        let t = replace_line(&t, "sigma_s =", "sigma_s = 0.0");
        let t = replace_line(&t, "sigma_a =", "sigma_a = 0.0");
        let t = replace_line(&t, "radius =", "radius = 0.2");
        let cut = t.find("[occluder]").unwrap();
        let end = t.find("[camera]").unwrap();
        format!("{}{}", &t[..cut], &t[end..])
    });
    let v = probe(
        dir.path(),
        "vac.toml",
        &["--point", "0,0,0", "--samples", "200000", "--seed", "3"],
    );
    let want = 10000.0 * std::f64::consts::PI * 0.04 / (0.95 * 0.95);
    let (m, se) = (v["mean"].as_f64().unwrap(), v["stderr"].as_f64().unwrap());
    // Straight below the centre the cosine varies over the cap; the mean of
    // the estimator is exact. |z| < 5: normal tail 5.7e-7 per test.
    assert!(((m - want) / se).abs() < 5.0, "{m} ± {se} vs {want}");
    assert!(se < 1e-2 * want);
    assert_eq!(
        v["terms"]["once-more"],
        serde_json::Value::Null,
        "no scattering term in vacuum"
    );
}

#[test]
fn probe_once_more_matches_the_point_to_point_quadrature_in_a_deep_slab() {
    // A slab 2 km thick with σt = 1 is an infinite medium for a point light 1 m
    // away. The probe's once-more irradiance at a receiver with normal n is
    // I times the point-to-point integral with the receiver cosine.
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "deep.toml", |t| {
        let t = replace_line(&t, "sigma_s =", "sigma_s = 0.6");
        let t = replace_line(&t, "sigma_a =", "sigma_a = 0.4");
        let t = replace_line(&t, "phase =", "phase = \"hg:0.8\"");
        let t = replace_line(&t, "z_min =", "z_min = -1000.0");
        let t = replace_line(&t, "z_max =", "z_max = 1000.0");
        let t = replace_line(&t, "z = 0.0", "z = -999.0");
        let t = replace_line(&t, "radius =", "radius = 0.0");
        let t = replace_line(&t, "radiance =", "intensity = 1.0");
        let cut = t.find("[occluder]").unwrap();
        let end = t.find("[camera]").unwrap();
        format!("{}{}", &t[..cut], &t[end..])
    });
    let v = probe(
        dir.path(),
        "deep.toml",
        &[
            "--point",
            "0.3,0,0",
            "--normal",
            "0,0.2,1",
            "--terms",
            "once-more",
            "--samples",
            "400000",
            "--technique",
            "omnee",
        ],
    );
    let e = json(&run_in(
        dir.path(),
        &[
            "estimate",
            "--x0",
            "0,0,0.95",
            "--x2",
            "0.3,0,0",
            "--receiver-normal",
            "0,0.2,1",
            "--phase",
            "hg:0.8",
            "--sigma-s",
            "0.6",
            "--sigma-t",
            "1.0",
            "--samples",
            "1000",
            "--reference",
            "--json",
        ],
    ));
    let want = e["reference"].as_f64().unwrap();
    let t = &v["terms"]["once-more"];
    let (m, se) = (t["mean"].as_f64().unwrap(), t["stderr"].as_f64().unwrap());
    // |z| < 5: normal tail 5.7e-7 (the estimator's variance is finite: OMNEE's
    // weight is bounded by θ/sin θ times attenuation).
    assert!(((m - want) / se).abs() < 5.0, "{m} ± {se} vs {want}");
    assert!(se < 0.01 * want);
}

#[test]
fn probe_once_more_of_a_small_sphere_matches_the_point_light_quadrature() {
    // A sphere of radius 1 cm and intensity 1 W/sr in an (effectively)
    // infinite medium with σt = 0.61 /m: its once-more irradiance differs from
    // the point light's at the centre by O(σt r) < 1 % (path lengths from the
    // surface instead of the centre), while a wrong area density of the
    // light point x0 (the cone/uniform mixture) would be off by a factor.
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "sphere.toml", |t| {
        let t = replace_line(&t, "sigma_s =", "sigma_s = 0.6");
        let t = replace_line(&t, "sigma_a =", "sigma_a = 0.01");
        let t = replace_line(&t, "phase =", "phase = \"hg:0.7\"");
        let t = replace_line(&t, "z_min =", "z_min = -1000.0");
        let t = replace_line(&t, "z_max =", "z_max = 1000.0");
        let t = replace_line(&t, "z = 0.0", "z = -999.0");
        let t = replace_line(&t, "radius =", "radius = 0.01");
        let t = replace_line(
            &t,
            "radiance =",
            &format!("radiance = {}", 1.0 / (std::f64::consts::PI * 1e-4)),
        );
        let cut = t.find("[occluder]").unwrap();
        let end = t.find("[camera]").unwrap();
        format!("{}{}", &t[..cut], &t[end..])
    });
    let v = probe(
        dir.path(),
        "sphere.toml",
        &[
            "--point",
            "0.4,0,0",
            "--terms",
            "once-more",
            "--samples",
            "400000",
            "--technique",
            "omnee",
        ],
    );
    let e = json(&run_in(
        dir.path(),
        &[
            "estimate",
            "--x0",
            "0,0,0.95",
            "--x2",
            "0.4,0,0",
            "--receiver-normal",
            "0,0,1",
            "--phase",
            "hg:0.7",
            "--sigma-s",
            "0.6",
            "--sigma-t",
            "0.61",
            "--samples",
            "1000",
            "--reference",
            "--json",
        ],
    ));
    let want = e["reference"].as_f64().unwrap();
    let t = &v["terms"]["once-more"];
    let (m, se) = (t["mean"].as_f64().unwrap(), t["stderr"].as_f64().unwrap());
    // 1 % for the sphere's size plus 5 standard errors (normal tail 5.7e-7).
    assert!(
        (m - want).abs() < 0.01 * want + 5.0 * se,
        "{m} ± {se} vs {want}"
    );
}

#[test]
fn probe_rejects_bad_points_and_terms() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (vec!["--point", "0,0,0.95"], "outside the light"),
        (vec!["--point", "0,0,-1"], "floor.z"),
        (vec!["--point", "0,0"], "X,Y,Z"),
        (vec!["--point", "0,0,0", "--normal", "0,0,0"], "--normal"),
        (
            vec!["--point", "0,0,0", "--terms", "view"],
            "not a probe term",
        ),
        (vec!["--point", "0,0,0", "--samples", "0"], "--samples = 0"),
    ] {
        let mut a = vec!["probe"];
        a.extend(args.iter());
        let o = run_in(dir.path(), &a);
        assert_eq!(o.status.code(), Some(2), "{a:?}");
        assert!(stderr(&o).contains(needle), "{a:?}: {}", stderr(&o));
    }
}

/// The deep slab of the quadrature test above (an infinite medium for a
/// point light 0.95 m above the receiver) with phase function `phase`.
fn deep_slab(dir: &Path, name: &str, phase: &str) {
    scene_with(dir, name, |t| {
        let t = replace_line(&t, "sigma_s =", "sigma_s = 0.6");
        let t = replace_line(&t, "sigma_a =", "sigma_a = 0.4");
        let t = replace_line(&t, "phase =", &format!("phase = \"{phase}\""));
        let t = replace_line(&t, "z_min =", "z_min = -1000.0");
        let t = replace_line(&t, "z_max =", "z_max = 1000.0");
        let t = replace_line(&t, "z = 0.0", "z = -999.0");
        let t = replace_line(&t, "radius =", "radius = 0.0");
        let t = replace_line(&t, "radiance =", "intensity = 1.0");
        let cut = t.find("[occluder]").unwrap();
        let end = t.find("[camera]").unwrap();
        format!("{}{}", &t[..cut], &t[end..])
    });
}

#[test]
fn probe_with_tabulated_phase_sampling_agrees_with_exact_sampling_and_the_quadrature() {
    // The tabulated inverse CDF draws θ from q ≠ p and carries p/q in the
    // weight (docs/math.md §11): the once-more mean must not move. Per phase
    // function and technique (mis: the companion's OMNEE density is the
    // table's), table and exact sampling each against the quadrature, and
    // against each other (independent seeds). |z| < 5 for each of the 15
    // comparisons: normal tail 5.7e-7 each, 9e-6 for the test.
    // The measured table steps down 100× at 7.5°, which the inverse CDF's
    // cubics smooth inside one bin. q keeps every bin's mass at 1/128
    // exactly, so even there p/q only moves mass within a bin: dropping it
    // moves these means by less than their noise (checked by hand); the core's
    // tests check the ratio itself.
    let dir = tempfile::tempdir().unwrap();
    let steps = dir.path().join("steps.csv");
    std::fs::write(&steps, "0,100\n5,100\n10,1\n90,1\n180,2\n").unwrap();
    let measured = format!("table:{}", steps.display());
    let cases = [
        ("ff:0.0183,1.1", "omnee"),
        ("ff:0.0183,1.1", "mis"),
        ("mie:10", "omnee"),
        ("rayleigh", "mis"),
        (measured.as_str(), "omnee"),
    ];
    for (i, (phase, technique)) in cases.into_iter().enumerate() {
        let name = format!("deep{i}.toml");
        deep_slab(dir.path(), &name, phase);
        let run = |sampling: &str, seed: &str| {
            let v = probe(
                dir.path(),
                &name,
                &[
                    "--point",
                    "0.3,0,0",
                    "--terms",
                    "once-more",
                    "--samples",
                    "200000",
                    "--technique",
                    technique,
                    "--phase-sampling",
                    sampling,
                    "--seed",
                    seed,
                ],
            );
            assert_eq!(v["phase_sampling"], sampling, "{phase}");
            let t = &v["terms"]["once-more"];
            (t["mean"].as_f64().unwrap(), t["stderr"].as_f64().unwrap())
        };
        let (mt, st) = run("table", "11");
        let (me, se) = run("exact", "12");
        let e = json(&run_in(
            dir.path(),
            &[
                "estimate",
                "--x0",
                "0,0,0.95",
                "--x2",
                "0.3,0,0",
                "--receiver-normal",
                "0,0,1",
                "--phase",
                phase,
                "--sigma-s",
                "0.6",
                "--sigma-t",
                "1.0",
                "--samples",
                "1000",
                "--reference",
                "--json",
            ],
        ));
        let want = e["reference"].as_f64().unwrap();
        let what =
            format!("{phase} {technique}: table {mt} ± {st}, exact {me} ± {se}, quadrature {want}");
        assert!(((mt - want) / st).abs() < 5.0, "{what}");
        assert!(((me - want) / se).abs() < 5.0, "{what}");
        assert!(((mt - me) / st.hypot(se)).abs() < 5.0, "{what}");
        assert!(st < 0.02 * want && se < 0.02 * want, "{what}");
    }
}

#[test]
fn hg_is_sampled_exactly_whatever_the_phase_sampling() {
    // HG's analytic inverse is as fast as a table: `table` leaves it exact,
    // so both give the same numbers bit for bit.
    let dir = tempfile::tempdir().unwrap();
    deep_slab(dir.path(), "hg.toml", "hg:0.8");
    let run = |sampling: &str| {
        probe(
            dir.path(),
            "hg.toml",
            &[
                "--point",
                "0.3,0,0",
                "--samples",
                "2000",
                "--phase-sampling",
                sampling,
            ],
        )
    };
    let (t, e) = (run("table"), run("exact"));
    assert_eq!(t["phase_sampling"], "exact");
    assert_eq!(t["terms"], e["terms"]);
}
