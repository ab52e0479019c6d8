//! Integration tests of the `omnee` binary: every subcommand, the error
//! paths, the file-safety promise, a render against a stored reference and
//! `estimate` against the quadrature reference.
//!
//! Statistical tests use fixed seeds. Each compares a Monte Carlo mean with
//! a reference through `z = (mean − reference) / stderr` and allows
//! `|z| < Z`, with `Z` chosen so that a correct implementation fails less
//! than once in 10⁴ runs of the whole file (the bound is derived at each
//! test), while a biased estimator fails reliably.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn omnee() -> Command {
    Command::new(env!("CARGO_BIN_EXE_omnee"))
}

fn run_in(dir: &Path, args: &[&str]) -> Output {
    omnee()
        .current_dir(dir)
        .args(args)
        .output()
        .expect("omnee runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "omnee failed: {}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("not JSON ({e}): {}", stdout(o)))
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Every channel of an EXR file by name.
fn channels(path: &Path) -> HashMap<String, Vec<f32>> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .expect("a readable EXR");
    image
        .layer_data
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect()
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Writes the default scene with `edit` applied to its text.
fn scene_with(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let out = omnee().arg("default-scene").output().unwrap();
    let text = edit(String::from_utf8(out.stdout).unwrap());
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn replace_line(text: &str, starts: &str, with: &str) -> String {
    let mut found = false;
    let out = text
        .lines()
        .map(|l| {
            if l.starts_with(starts) && !found {
                found = true;
                with.to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(found, "no line starts with {starts}");
    out
}

#[test]
fn render_writes_a_layer_per_term_and_a_png() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_in(
        dir.path(),
        &[
            "render",
            "--resolution",
            "24x18",
            "--spp",
            "2",
            "--progress",
            "never",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("technique: auto picked omnee"),
        "{}",
        stdout(&o)
    );
    assert_eq!(files_in(dir.path()), ["omnee.exr", "omnee.png"]);
    let ch = channels(&dir.path().join("omnee.exr"));
    for layer in ["", "direct.", "once-more.", "view."] {
        for c in ["R", "G", "B"] {
            let v = &ch[&format!("{layer}{c}")];
            assert_eq!(v.len(), 24 * 18);
            assert!(v.iter().all(|x| x.is_finite() && *x >= 0.0));
        }
    }
    // The main layer is the sum of the terms.
    for (i, &main) in ch["G"].iter().enumerate() {
        let sum = ch["direct.G"][i] + ch["once-more.G"][i] + ch["view.G"][i];
        assert!((main - sum).abs() <= 1e-5 * sum.max(1e-30), "pixel {i}");
    }
    let png = std::fs::read(dir.path().join("omnee.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}

#[test]
fn the_image_does_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "render",
        "--resolution",
        "20x15",
        "--spp",
        "3",
        "--format",
        "exr",
    ];
    for (threads, out) in [("1", "one"), ("2", "two"), ("3", "three")] {
        let mut args = common.to_vec();
        args.extend(["--seed", "9", "--threads", threads, "-o", out]);
        let o = run_in(dir.path(), &args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let one = channels(&dir.path().join("one.exr"));
    assert_eq!(one, channels(&dir.path().join("two.exr")));
    assert_eq!(one, channels(&dir.path().join("three.exr")));
    // A different seed gives a different image (the seed is used).
    let mut args = common.to_vec();
    args.extend(["--seed", "10", "-o", "other"]);
    assert!(run_in(dir.path(), &args).status.success());
    assert_ne!(one, channels(&dir.path().join("other.exr")));
}

#[test]
fn crops_render_the_full_images_pixels_and_merge_back() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "render",
        "--resolution",
        "16x12",
        "--spp",
        "2",
        "--format",
        "exr",
    ];
    let mut jobs = vec![
        (None, "full"),
        (Some("0,0,16,5"), "top"),
        (Some("0,5,16,12"), "bottom"),
    ];
    for (crop, out) in jobs.drain(..) {
        let mut args = common.to_vec();
        args.extend(["-o", out]);
        if let Some(c) = crop {
            args.extend(["--crop", c]);
        }
        let o = run_in(dir.path(), &args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let full = channels(&dir.path().join("full.exr"));
    let top = channels(&dir.path().join("top.exr"));
    // Inside the crop the pixels are the full render's, outside they are 0.
    for (i, (&f, &t)) in full["G"].iter().zip(&top["G"]).enumerate() {
        if i < 16 * 5 {
            assert_eq!(f, t, "pixel {i}");
        } else {
            assert_eq!(t, 0.0, "pixel {i}");
        }
    }
    let o = run_in(
        dir.path(),
        &["merge", "top.exr", "bottom.exr", "-o", "merged"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(channels(&dir.path().join("merged.exr")), full);
    assert!(dir.path().join("merged.png").exists());
}

#[test]
fn a_time_budget_renders_whole_passes() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_in(
        dir.path(),
        &[
            "render",
            "--resolution",
            "16x12",
            "--time",
            "0.3",
            "--json",
            "--format",
            "exr",
        ],
    );
    let v = json(&o);
    assert!(v["spp"].as_u64().unwrap() >= 1);
    // The loop stops before a pass that would not fit, unless the first
    // pass alone exceeds the budget; on a loaded machine allow slack.
    assert!(v["seconds"].as_f64().unwrap() < 30.0);
}

#[test]
fn a_vacuum_evaluates_no_scattering_and_matches_the_direct_render() {
    let dir = tempfile::tempdir().unwrap();
    let vac = scene_with(dir.path(), "vacuum.toml", |t| {
        replace_line(&t, "sigma_s =", "sigma_s = 0.0")
    });
    let args = |out: &'static str, terms: &'static str| {
        let mut a = vec![
            "render",
            "--scene",
            "vacuum.toml",
            "--resolution",
            "16x12",
            "--spp",
            "2",
        ];
        a.extend(["--json", "--format", "exr", "-o", out, "--terms", terms]);
        a
    };
    let all = json(&run_in(dir.path(), &args("all", "direct,once-more,view")));
    assert!(
        all["skipped"][0].as_str().unwrap().contains("sigma_s = 0"),
        "{all}"
    );
    assert_eq!(all["stats"]["connections"], 0);
    let direct = json(&run_in(dir.path(), &args("direct", "direct")));
    let (a, d) = (
        channels(&dir.path().join("all.exr")),
        channels(&dir.path().join("direct.exr")),
    );
    assert_eq!(a["G"], d["G"]);
    assert!(!a.contains_key("once-more.G") && !a.contains_key("view.G"));
    // The same work: the same visibility tests.
    assert_eq!(
        all["stats"]["visibility_tests"],
        direct["stats"]["visibility_tests"]
    );
    drop(vac);
}

#[test]
fn without_an_occluder_there_are_no_visibility_tests() {
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "open.toml", |t| {
        let cut = t.find("[occluder]").unwrap();
        let rest = &t[cut..];
        let end = rest.find("[camera]").unwrap();
        format!("{}{}", &t[..cut], &rest[end..])
    });
    let o = run_in(
        dir.path(),
        &[
            "render",
            "--scene",
            "open.toml",
            "--resolution",
            "16x12",
            "--spp",
            "2",
            "--json",
            "--format",
            "exr",
        ],
    );
    let v = json(&o);
    assert_eq!(v["stats"]["visibility_tests"], 0);
    assert!(v["stats"]["connections"].as_u64().unwrap() > 0);
    assert!(v["skipped"][0].as_str().unwrap().contains("no occluder"));
}

#[test]
fn a_restricted_integrand_skips_connections_that_cannot_reach_the_slab() {
    // A thin slab high above the floor: with theta < 0.5 the region of a
    // connection from the light (below the slab) to the floor stays below it.
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "high.toml", |t| {
        let t = replace_line(&t, "z_min =", "z_min = 2.0");
        replace_line(&t, "z_max =", "z_max = 2.5")
    });
    let o = run_in(
        dir.path(),
        &[
            "render",
            "--scene",
            "high.toml",
            "--resolution",
            "8x6",
            "--spp",
            "2",
            "--json",
            "--format",
            "exr",
            "--theta-max",
            "0.5",
            "--terms",
            "once-more",
        ],
    );
    let v = json(&o);
    let st = &v["stats"];
    assert!(st["connections"].as_u64().unwrap() > 0);
    assert_eq!(st["skipped_unreachable"], st["connections"]);
    assert_eq!(st["visibility_tests"], 0);
}

#[test]
fn bad_input_names_field_value_and_range_exits_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An existing output must survive a failed run untouched.
    std::fs::write(d.join("omnee.png"), b"precious").unwrap();
    type Edit = Box<dyn Fn(String) -> String>;
    let cases: Vec<(Vec<&str>, Edit, Vec<&str>)> = vec![
        (
            vec![],
            Box::new(|t| replace_line(&t, "sigma_s =", "sigma_s = -1")),
            vec!["medium.sigma_s = -1", "[0, inf)"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "sigma_s =", "sigma_s = \"thick\"")),
            vec!["medium.sigma_s", "thick", "not a number"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "phase =", "phase = \"hg:1.5\"")),
            vec!["g = 1.5", "(-1, 1)"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "phase =", "phase = \"cloud\"")),
            vec!["phase \"cloud\"", "allowed"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "sigma_s =", "sigma_s = 0.5\ncolour = 3")),
            vec!["medium.colour", "not a known field"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "fov =", "fov = 200")),
            vec!["camera.fov = 200", "(0, 180)"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "width =", "width = 0")),
            vec!["camera.width = 0", "[1, 16384]"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "opening =", "opening = 1.5")),
            vec!["occluder.opening = 1.5", "(0, 1)"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "pattern =", "pattern = \"stars\"")),
            vec!["occluder.pattern", "stars", "holes"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "albedo_a =", "albedo_a = [0.5, 2.0, 0.5]")),
            vec!["floor.albedo_a", "[0, 1]"],
        ),
        (
            vec![],
            Box::new(|t| {
                replace_line(&t, "center = [0.0, 0.0, 0.95]", "center = [0.0, 0.0, -1.0]")
            }),
            vec!["light.center[2] = -1"],
        ),
        (
            vec![],
            Box::new(|t| replace_line(&t, "technique =", "technique = \"magic\"")),
            vec!["render.technique", "magic", "omnee"],
        ),
        (
            vec![],
            Box::new(|t| format!("{t}\n[extra]\n")),
            vec!["[extra]", "not a known section"],
        ),
        (
            vec![],
            Box::new(|t| t.replace("[camera]", "[camera")),
            vec!["not valid TOML"],
        ),
        (
            vec!["--spp", "0"],
            Box::new(|t| t),
            vec!["--spp = 0", "[1,"],
        ),
        (
            vec!["--technique", "magic"],
            Box::new(|t| t),
            vec!["--technique", "magic", "allowed"],
        ),
        (
            vec!["--theta-max", "4"],
            Box::new(|t| t),
            vec!["--theta-max = 4", "(0, 3.14159"],
        ),
        (
            vec!["--crop", "0,0,999,5"],
            Box::new(|t| t),
            vec!["--crop", "X1 <="],
        ),
        (
            vec!["--terms", "direct,glow"],
            Box::new(|t| t),
            vec!["glow", "direct, once-more, view"],
        ),
        (
            vec!["-o", "no/such/folder/img"],
            Box::new(|t| t),
            vec!["--output", "does not exist"],
        ),
        (
            vec!["--resolution", "10by10"],
            Box::new(|t| t),
            vec!["10by10", "WIDTHxHEIGHT"],
        ),
    ];
    for (extra, edit, needles) in cases {
        scene_with(d, "bad.toml", &*edit);
        let mut args = vec!["render", "--scene", "bad.toml"];
        args.extend(extra.iter());
        let o = run_in(d, &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{args:?}: expected {n:?} in {err}");
        }
        assert_eq!(files_in(d), ["bad.toml", "omnee.png"], "{args:?}");
        assert_eq!(std::fs::read(d.join("omnee.png")).unwrap(), b"precious");
    }
    let o = run_in(d, &["render", "--scene", "missing.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.toml"));
}

#[test]
fn a_successful_render_replaces_an_existing_output_whole() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("omnee.png"), b"old").unwrap();
    let o = run_in(
        dir.path(),
        &[
            "render",
            "--resolution",
            "8x6",
            "--spp",
            "1",
            "--format",
            "png",
        ],
    );
    assert!(o.status.success());
    assert_eq!(
        &std::fs::read(dir.path().join("omnee.png")).unwrap()[..4],
        b"\x89PNG"
    );
    // No temporary file is left behind.
    assert_eq!(files_in(dir.path()), ["omnee.png"]);
}

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

fn estimate(args: &[&str]) -> serde_json::Value {
    let mut a = vec!["estimate", "--json", "--reference"];
    a.extend(args);
    json(&omnee().args(&a).output().unwrap())
}

/// `estimate` without the quadrature reference.
fn estimate_only(args: &[&str]) -> serde_json::Value {
    let mut a = vec!["estimate", "--json"];
    a.extend(args);
    json(&omnee().args(&a).output().unwrap())
}

#[test]
fn every_technique_estimates_the_quadrature_reference() {
    // 22 comparisons below, each |z| < 5.5: normal two-sided tail 3.8e-8,
    // so the family fails less than once in 10⁶ runs for estimators with
    // finite variance (all chosen here have it; equiangular and distance
    // sampling of peaked phase functions do not, and are left out).
    let base = [
        "--x0",
        "0,0,0",
        "--x2",
        "0.2,0.1,1",
        "--sigma-s",
        "0.2",
        "--samples",
        "200000",
    ];
    let mut cases: Vec<(Vec<&str>, &str)> = Vec::new();
    for phase in [
        "iso",
        "hg:0.9",
        "hg:-0.5",
        "tthg:0.99,-0.44,0.96",
        "rayleigh",
        "mie:10",
    ] {
        for tech in ["omnee", "mis"] {
            cases.push((vec!["--phase", phase, "--sigma-t", "0.5"], tech));
        }
    }
    for tech in ["equiangular", "distance", "omnee", "mis"] {
        cases.push((vec!["--phase", "iso", "--sigma-t", "1.0"], tech));
        cases.push((
            vec![
                "--phase",
                "hg:0.3",
                "--sigma-t",
                "1.0",
                "--receiver-normal",
                "0.3,0,-1",
                "--theta-max",
                "2.0",
            ],
            tech,
        ));
    }
    cases.push((
        vec![
            "--phase",
            "hg:0.98",
            "--sigma-t",
            "0.25",
            "--theta-max",
            "1.5707963267948966",
            "--precision",
            "f64",
        ],
        "omnee",
    ));
    cases.push((
        vec![
            "--phase",
            "draine:0.5,1",
            "--sigma-t",
            "0.25",
            "--theta-max",
            "1.0",
        ],
        "omnee",
    ));
    assert_eq!(cases.len(), 22);
    // The quadrature runs once per problem.
    let mut references: HashMap<Vec<&str>, f64> = HashMap::new();
    for (extra, tech) in cases {
        let mut a = base.to_vec();
        a.extend(extra.iter());
        a.extend(["--technique", tech]);
        let cached = references.get(&extra).copied();
        let v = if cached.is_some() {
            estimate_only(&a)
        } else {
            estimate(&a)
        };
        let r = cached.unwrap_or_else(|| v["reference"].as_f64().unwrap());
        references.insert(extra.clone(), r);
        let (m, se) = (v["mean"].as_f64().unwrap(), v["stderr"].as_f64().unwrap());
        assert!(r > 0.0 && se > 0.0, "{a:?}");
        assert!(((m - r) / se).abs() < 5.5, "{a:?}: {m} ± {se} vs {r}");
        assert_eq!(v["technique"], tech);
        assert_eq!(v["terms"]["once-more"]["mean"], v["mean"]);
    }
}

#[test]
fn omnee_beats_equiangular_on_a_peaked_phase_function() {
    // MATH.md §6: at g = 0.98 OMNEE's variance is orders of magnitude lower.
    let base = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.2",
        "--sigma-t",
        "0.25",
        "--phase",
        "hg:0.98",
        "--samples",
        "100000",
    ];
    let se = |t: &str| {
        let mut a = base.to_vec();
        a.extend(["--technique", t]);
        estimate_only(&a)["stderr"].as_f64().unwrap()
    };
    assert!(se("omnee") * 10.0 < se("equiangular"));
}

#[test]
fn estimate_does_not_depend_on_the_thread_count_and_auto_explains_itself() {
    let base = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.08",
        "--sigma-t",
        "0.1",
        "--samples",
        "50000",
    ];
    let with = |extra: &[&str]| {
        let mut a = base.to_vec();
        a.extend(extra);
        estimate_only(&a)
    };
    let one = with(&["--threads", "1", "--phase", "iso"]);
    let two = with(&["--threads", "2", "--phase", "iso"]);
    assert_eq!(one["mean"], two["mean"]);
    assert_eq!(one["stderr"], two["stderr"]);
    assert_eq!(one["technique"], "mis");
    assert!(
        one["auto_reason"]
            .as_str()
            .unwrap()
            .contains("optically thin")
    );
    let peaked = with(&["--phase", "hg:0.9"]);
    assert_eq!(peaked["technique"], "omnee");
    assert!(
        peaked["auto_reason"]
            .as_str()
            .unwrap()
            .contains("forward-peaked")
    );
    let thick = estimate_only(&[
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,3",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "1",
        "--phase",
        "iso",
        "--samples",
        "1000",
    ]);
    assert_eq!(thick["technique"], "omnee");
    let back = with(&["--phase", "hg:-0.6"]);
    assert_eq!(back["technique"], "mis");
}

#[test]
fn estimate_rejects_bad_values() {
    for (args, needle) in [
        (
            vec!["--sigma-s", "0.5", "--sigma-t", "0.2"],
            "--sigma-t = 0.2",
        ),
        (
            vec!["--sigma-s", "-1", "--sigma-t", "0.2"],
            "--sigma-s = -1",
        ),
        (
            vec!["--sigma-s", "0.1", "--sigma-t", "0.2", "--theta-max", "0"],
            "--theta-max = 0",
        ),
        (
            vec!["--sigma-s", "0.1", "--sigma-t", "0.2", "--phase", "hg:2"],
            "g = 2",
        ),
        (
            vec![
                "--sigma-s",
                "0.1",
                "--sigma-t",
                "0.2",
                "--phase",
                "table:nope.csv",
            ],
            "nope.csv",
        ),
        (
            vec![
                "--sigma-s",
                "0.1",
                "--sigma-t",
                "0.2",
                "--receiver-normal",
                "0,0,0",
            ],
            "--receiver-normal",
        ),
        (
            vec![
                "--sigma-s",
                "0.1",
                "--sigma-t",
                "0.2",
                "--technique",
                "best",
            ],
            "best",
        ),
    ] {
        let mut a = vec!["estimate", "--x0", "0,0,0", "--x2", "0,0,1"];
        a.extend(args.iter());
        let o = omnee().args(&a).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{a:?}");
        assert!(stderr(&o).contains(needle), "{a:?}: {}", stderr(&o));
    }
    let o = omnee()
        .args([
            "estimate",
            "--x0",
            "1,2,3",
            "--x2",
            "1,2,3",
            "--sigma-s",
            "0.1",
            "--sigma-t",
            "0.2",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("equals --x0"));
}

#[test]
fn a_tabulated_phase_function_works_end_to_end() {
    // A table of HG(0.5) values at 1° steps: its nearest-neighbour bins are
    // HG(0.5) to within 1 %, so OMNEE and MIS with the table both land on
    // HG's quadrature reference within 2 % (plus 5 standard errors, normal
    // tail 5.7e-7; the bias of the binning is far below 2 %). (The core's
    // adaptive quadrature of a 180-bin table is too slow for a test.)
    let dir = tempfile::tempdir().unwrap();
    let g: f64 = 0.5;
    let mut csv = String::from("angle_deg,value\n");
    for i in 0..=180 {
        let mu = (i as f64).to_radians().cos();
        csv += &format!(
            "{i},{}\n",
            (1.0 - g * g) / (1.0 + g * g - 2.0 * g * mu).powf(1.5)
        );
    }
    let path = dir.path().join("hg05.csv");
    std::fs::write(&path, csv).unwrap();
    let spec = format!("table:{}", path.display());
    let base = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.2",
        "--sigma-t",
        "0.5",
        "--samples",
        "200000",
    ];
    let b = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.2",
        "--sigma-t",
        "0.5",
        "--phase",
        "hg:0.5",
        "--samples",
        "1000",
    ];
    let r_hg = estimate(&b)["reference"].as_f64().unwrap();
    for tech in ["omnee", "mis"] {
        let mut a = base.to_vec();
        a.extend(["--phase", spec.as_str(), "--technique", tech]);
        let t = estimate_only(&a);
        let (m, se) = (t["mean"].as_f64().unwrap(), t["stderr"].as_f64().unwrap());
        assert!(
            (m - r_hg).abs() < 0.02 * r_hg + 5.0 * se,
            "{tech}: {m} ± {se} vs {r_hg}"
        );
    }
}

#[test]
fn samples_lists_x1_with_pdf_and_weight() {
    let base = [
        "samples",
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.2",
        "--sigma-t",
        "0.25",
        "--phase",
        "hg:0.7",
        "--technique",
        "omnee",
        "--count",
        "500",
        "--theta-max",
        "1.5707963267948966",
        "--precision",
        "f64",
    ];
    let o = omnee()
        .args(base)
        .args(["--format", "csv"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let text = stdout(&o);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("draw,vertex,u0,u1,u2,x,y,z,pdf,weight,estimate")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    // θ < π/2 keeps a draw with probability cdf(π/2) = 1 − B(0.7) ≈ 0.95.
    assert!(rows.len() > 400 && rows.len() <= 500, "{}", rows.len());
    for r in &rows {
        // One vertex per draw for a single technique.
        assert_eq!(r[1], 0.0);
        let (x, y, z, pdf, w) = (r[5], r[6], r[7], r[8], r[9]);
        // Forward scattering stays inside the Thales ball over x0x2.
        assert!(x * x + y * y + (z - 0.5) * (z - 0.5) <= 0.25 + 1e-9);
        assert!(pdf > 0.0 && w > 0.0);
        // OMNEE's weight is θ/(s sin θ) ∈ [1, π/2] for s = 1.
        assert!(
            (1.0 - 1e-9..=std::f64::consts::FRAC_PI_2 + 1e-9).contains(&w),
            "{w}"
        );
    }
    let o = omnee()
        .args(base)
        .args(["--format", "json"])
        .output()
        .unwrap();
    let v = json(&o);
    assert_eq!(v["draws"], 500);
    assert_eq!(v["returned"].as_u64().unwrap() as usize, rows.len());
    assert_eq!(v["samples"][0]["pdf"].as_f64().unwrap(), rows[0][8]);
    // mis: every draw has OMNEE's vertex (θmax = π/2 here), and about one in
    // twenty an equiangular one behind 3π/4, which θ < π/2 gives weight 0
    // (binomial(500, 0.05): mean 25, sd 4.9; 100 is 15 sd away).
    let mut mis = base.to_vec();
    let at = mis.iter().position(|&a| a == "omnee").unwrap();
    mis[at] = "mis";
    let o = omnee()
        .args(&mis)
        .args(["--format", "json"])
        .output()
        .unwrap();
    let v = json(&o);
    let list = v["samples"].as_array().unwrap();
    let companions = list.iter().filter(|s| s["vertex"] == 1).count();
    assert!(companions < 100, "{companions}");
    for s in list.iter().filter(|s| s["vertex"] == 1) {
        assert_eq!(s["estimate"], 0.0);
    }
}

#[test]
fn help_documents_the_phase_specs_and_default_scene_round_trips() {
    let o = omnee().arg("--help").output().unwrap();
    let h = stdout(&o);
    for spec in [
        "iso",
        "hg:G",
        "tthg:G1,G2,W",
        "ff:B,N",
        "draine:G,ALPHA",
        "mie:DIAMETER_UM",
        "rayleigh",
        "table:FILE.csv",
    ] {
        assert!(h.contains(spec), "{spec} missing from --help");
    }
    let o = omnee().arg("default-scene").output().unwrap();
    let text = stdout(&o);
    for field in [
        "sigma_s",
        "sigma_a",
        "phase",
        "checker_size",
        "radiance",
        "pattern",
        "opening",
        "fov",
        "theta_max",
    ] {
        assert!(text.contains(field), "{field}");
    }
    assert_eq!(
        text,
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/default.toml"))
            .unwrap()
    );
}

/// Block means of a layer (mean of R, G, B) over the 2 × 2 quadrants.
fn quadrants(ch: &HashMap<String, Vec<f32>>, layer: &str, w: usize, h: usize) -> [f64; 4] {
    let mut out = [0.0; 4];
    for y in 0..h {
        for x in 0..w {
            let q = (y * 2 / h) * 2 + x * 2 / w;
            let i = y * w + x;
            let v: f64 = ["R", "G", "B"]
                .iter()
                .map(|c| ch[&format!("{layer}.{c}")][i] as f64)
                .sum::<f64>()
                / 3.0;
            out[q] += v / (w * h / 4) as f64;
        }
    }
    out
}

const LAYERS: [&str; 3] = ["direct", "once-more", "view"];

/// Mean and standard error of the quadrant means over `seeds` renders of
/// `tests/data/small.toml` with `spp` samples per pixel each.
fn quadrant_stats(
    dir: &Path,
    seeds: std::ops::Range<u64>,
    spp: u32,
) -> HashMap<&'static str, Vec<(f64, f64)>> {
    let mut samples: HashMap<&str, Vec<[f64; 4]>> = HashMap::new();
    let scene = data("small.toml");
    for seed in seeds.clone() {
        let out = dir.join(format!("s{seed}"));
        let o = omnee()
            .args([
                "render",
                "--scene",
                scene.to_str().unwrap(),
                "--format",
                "exr",
                "--progress",
                "never",
            ])
            .args([
                "--spp",
                &spp.to_string(),
                "--seed",
                &seed.to_string(),
                "-o",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let ch = channels(&out.with_extension("exr"));
        for l in LAYERS {
            samples
                .entry(l)
                .or_default()
                .push(quadrants(&ch, l, 32, 24));
        }
    }
    let n = seeds.count() as f64;
    LAYERS
        .iter()
        .map(|&l| {
            let runs = &samples[l];
            let stats = (0..4)
                .map(|q| {
                    let mean = runs.iter().map(|r| r[q]).sum::<f64>() / n;
                    let var = runs.iter().map(|r| (r[q] - mean).powi(2)).sum::<f64>() / (n - 1.0);
                    (mean, (var / n).sqrt())
                })
                .collect();
            (l, stats)
        })
        .collect()
}

#[test]
fn a_small_render_matches_the_stored_reference() {
    // The reference (tests/data/render_reference.json) holds, per layer and
    // image quadrant, the mean and standard error over 64 renders of 256 spp
    // (seeds 1000..1064). Here: 32 renders of 64 spp with other seeds. Each of
    // the 10 comparisons uses z = Δ / √(se² + se_ref²), where se has 31
    // degrees of freedom; |z| < 6.5 bounds a t(31)-distributed z's two-sided
    // tail by 4e-7, 4e-6 for the family, while a 5 % bias in any layer moves
    // z by about 10.
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data("render_reference.json")).unwrap())
            .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let got = quadrant_stats(dir.path(), 1..33, 64);
    for l in LAYERS {
        for (q, &(m, se)) in got[l].iter().enumerate() {
            // The top quadrants of the view layer hold the glow around the
            // light seen through a g = 0.98 medium: a heavy-tailed estimator
            // (relative standard error 15-25 % even in the reference), whose
            // standard error 32 runs cannot estimate reliably. The view
            // estimator is checked against quadrature in world.rs instead.
            if l == "view" && q < 2 {
                continue;
            }
            let r = reference[l][q][0].as_f64().unwrap();
            let se_r = reference[l][q][1].as_f64().unwrap();
            let z = (m - r) / (se * se + se_r * se_r).sqrt();
            assert!(
                z.abs() < 6.5,
                "{l} quadrant {q}: {m} ± {se} vs {r} ± {se_r} (z = {z})"
            );
        }
    }
}

/// Rewrites `tests/data/render_reference.json` (run when the renderer's
/// expected output changes on purpose:
/// `cargo test -p omnee-cli --release -- --ignored regenerate`).
#[test]
#[ignore]
fn regenerate_render_reference() {
    let dir = tempfile::tempdir().unwrap();
    let got = quadrant_stats(dir.path(), 1000..1064, 256);
    let v: serde_json::Map<String, serde_json::Value> = LAYERS
        .iter()
        .map(|&l| {
            (
                l.to_string(),
                serde_json::json!(got[l].iter().map(|&(m, s)| [m, s]).collect::<Vec<_>>()),
            )
        })
        .collect();
    std::fs::write(
        data("render_reference.json"),
        serde_json::to_string_pretty(&v).unwrap() + "\n",
    )
    .unwrap();
}
