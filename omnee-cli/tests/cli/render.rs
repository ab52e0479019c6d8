//! `omnee render` and `omnee merge`: layers, thread independence, crops, budgets and skipping.

use crate::common::*;

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
fn the_multiple_term_renders_by_bridges_and_by_path_tracing() {
    // Off by default; on, a layer of its own by either method, the image
    // independent of the thread count; its settings are named when bad.
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "render",
        "--resolution",
        "16x12",
        "--spp",
        "2",
        "--progress",
        "never",
        "--format",
        "exr",
        "--terms",
        "once-more,multiple",
        "--json",
    ];
    let mut layers = Vec::new();
    for (method, vertices, out) in [
        ("bridge", "auto", "b"),
        ("path-tracing", "auto", "p"),
        ("bridge", "3", "b3"),
        ("path-tracing", "2", "p2"),
    ] {
        let o = run_in(
            dir.path(),
            &[
                &base[..],
                &["--multiple", method, "--vertices", vertices, "-o", out],
            ]
            .concat(),
        );
        let v = json(&o);
        assert_eq!(v["multiple"]["method"], method);
        assert_eq!(v["multiple"]["vertices"], vertices);
        let ch = channels(&dir.path().join(format!("{out}.exr")));
        let m = &ch["multiple.G"];
        assert!(m.iter().all(|x| x.is_finite() && *x >= 0.0));
        assert!(m.iter().any(|x| *x > 0.0), "{method} {vertices}");
        layers.push(m.clone());
    }
    let two = run_in(
        dir.path(),
        &[
            &base[..],
            &["--threads", "2", "--multiple", "bridge", "-o", "b2"],
        ]
        .concat(),
    );
    assert!(two.status.success(), "{}", stderr(&two));
    assert_eq!(
        channels(&dir.path().join("b2.exr"))["multiple.G"],
        layers[0]
    );
    for (extra, needle) in [
        (vec!["--vertices", "1"], "--vertices = 1"),
        (
            vec!["--vertices", "auto", "--max-vertices", "1"],
            "--max-vertices = 1",
        ),
        (
            vec!["--vertices", "2", "--max-vertices", "4"],
            "--max-vertices = 4",
        ),
        (vec!["--multiple", "photons"], "photons"),
    ] {
        let o = run_in(dir.path(), &[&base[..], &extra].concat());
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(stderr(&o).contains(needle), "{extra:?}: {}", stderr(&o));
    }
}
