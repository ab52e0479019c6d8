//! `omnee render --scene underwater` and `omnee default-scene underwater`:
//! the layers, crops that merge into the image, `--time`, `--json`, skipping,
//! and bad scene input (exit 2, the field named, nothing written).

use crate::common::{channels, files_in, json, run_in, stderr, stdout};

/// A small, fast render: 48x36, 2 passes.
const SMALL: [&str; 6] = ["--resolution", "48x36", "--spp", "2", "--progress", "never"];

fn render(dir: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["render", "--scene", "underwater"];
    args.extend(SMALL);
    args.extend(extra);
    run_in(dir, &args)
}

#[test]
fn the_underwater_scene_renders_each_term_into_its_own_layer() {
    let dir = tempfile::tempdir().unwrap();
    let o = render(dir.path(), &["--json", "-o", "uw"]);
    let v = json(&o);
    assert_eq!(v["scene"], "underwater");
    assert_eq!(v["technique"], "mis");
    assert_eq!(v["spp"], 2);
    let ch = channels(&dir.path().join("uw.exr"));
    for term in ["caustics", "caustics-once-more", "shafts"] {
        let r = &ch[&format!("{term}.R")];
        assert_eq!(r.len(), 48 * 36);
        assert!(r.iter().all(|v| v.is_finite() && *v >= 0.0), "{term}");
        let g = &ch[&format!("{term}.G")];
        assert!(g.iter().any(|v| *v > 0.0), "{term} is black");
    }
    // The sum is the sum of the layers.
    for (i, sum) in ch["G"].iter().enumerate() {
        let parts: f32 = ["caustics", "caustics-once-more", "shafts"]
            .iter()
            .map(|t| ch[&format!("{t}.G")][i])
            .sum();
        assert!((sum - parts).abs() <= 1e-5 * parts.abs().max(1e-20), "{i}");
    }
    assert!(dir.path().join("uw.png").exists());
}

#[test]
fn crops_rendered_apart_merge_into_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    assert!(
        render(p, &["-o", "full", "--format", "exr"])
            .status
            .success()
    );
    assert!(
        render(
            p,
            &[
                "-o",
                "a",
                "--format",
                "exr",
                "--crop",
                "0,0,48,20",
                "--threads",
                "1"
            ]
        )
        .status
        .success()
    );
    assert!(
        render(
            p,
            &[
                "-o",
                "b",
                "--format",
                "exr",
                "--crop",
                "0,20,48,36",
                "--threads",
                "2"
            ]
        )
        .status
        .success()
    );
    let o = run_in(p, &["merge", "a.exr", "b.exr", "-o", "merged"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (full, merged) = (
        channels(&p.join("full.exr")),
        channels(&p.join("merged.exr")),
    );
    for (name, data) in &full {
        assert_eq!(data, &merged[name], "{name}");
    }
}

#[test]
fn terms_technique_time_and_skipping_work_as_for_the_default_scene() {
    let dir = tempfile::tempdir().unwrap();
    let o = render(dir.path(), &["--terms", "caustics", "--json", "-o", "c"]);
    let v = json(&o);
    assert_eq!(v["terms"], serde_json::json!(["caustics"]));
    assert_eq!(v["stats"]["splats"]["shafts"], 0);
    let ch = channels(&dir.path().join("c.exr"));
    assert!(ch.contains_key("caustics.R") && !ch.contains_key("shafts.R"));

    let mut args = vec!["render", "--scene", "underwater", "--resolution", "48x36"];
    args.extend([
        "--time",
        "0.5",
        "--progress",
        "never",
        "--technique",
        "auto",
        "--json",
        "-o",
        "t",
    ]);
    let v = json(&run_in(dir.path(), &args));
    assert!(v["spp"].as_u64().unwrap() >= 1);
    assert_eq!(v["technique"], "omnee");
    assert!(
        v["auto_reason"]
            .as_str()
            .unwrap()
            .contains("forward-peaked")
    );

    // Clear water: the scattering terms are skipped, and the run says so.
    let text = omnee_render::scenes::underwater::UNDERWATER_SCENE.replacen(
        "sigma_s = [0.25, 0.25, 0.25]",
        "sigma_s = 0",
        1,
    );
    std::fs::write(dir.path().join("clear.toml"), text).unwrap();
    let o = run_in(
        dir.path(),
        &[
            "render",
            "--scene",
            "clear.toml",
            "--resolution",
            "48x36",
            "--spp",
            "1",
            "--progress",
            "never",
            "-o",
            "clear",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("skip: water.sigma_s = 0"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn default_scene_underwater_prints_a_scene_that_renders_from_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_in(dir.path(), &["default-scene", "underwater"]);
    assert!(o.status.success());
    assert_eq!(
        stdout(&o),
        omnee_render::scenes::underwater::UNDERWATER_SCENE
    );
    std::fs::write(dir.path().join("uw.toml"), stdout(&o)).unwrap();
    let mut args = vec!["render", "--scene", "uw.toml"];
    args.extend(SMALL);
    args.extend(["--json", "-o", "f"]);
    assert_eq!(json(&run_in(dir.path(), &args))["scene"], "underwater");
}

#[test]
fn bad_underwater_input_exits_2_naming_the_field_and_writes_nothing() {
    use omnee_render::scenes::underwater::UNDERWATER_SCENE;
    let cases: [(&str, &str, &str); 6] = [
        (
            "irradiance = 1000.0",
            "irradiance = -1.0",
            "sun.irradiance = -1",
        ),
        (
            "irradiance = 1000.0",
            "irradiance = 1e39",
            "sun.irradiance = 1e39 is out of range; allowed: [0, 1e20]",
        ),
        ("ior = 1.33", "ior = 0.8", "surface.ior = 0.8"),
        ("kind = \"sine\"", "kind = \"gerstner\"", "fold"),
        (
            "sigma_a = [0.45, 0.07, 0.04]",
            "sigma_a = [0.45, 0.07]",
            "water.sigma_a",
        ),
        (
            "albedo_b = [0.55, 0.48, 0.34]",
            "albedo_b = [0.5]",
            "floor.albedo_b",
        ),
    ];
    for (from, to, want) in cases {
        let dir = tempfile::tempdir().unwrap();
        let mut text = UNDERWATER_SCENE.replacen(from, to, 1);
        if to.contains("gerstner") {
            text = text.replacen("amplitude = 0.04 ", "amplitude = 0.3 ", 1);
        }
        std::fs::write(dir.path().join("bad.toml"), text).unwrap();
        let o = run_in(dir.path(), &["render", "--scene", "bad.toml", "-o", "out"]);
        assert_eq!(o.status.code(), Some(2), "{to}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(want) && stderr(&o).contains("allowed"),
            "{to}: {}",
            stderr(&o)
        );
        assert_eq!(files_in(dir.path()), vec!["bad.toml".to_string()], "{to}");
    }
    // The start density's parameters: importance only, but out of range is
    // still a named error.
    for (from, to, want) in [
        (
            "margin = 1.0",
            "margin = -0.5",
            "render.margin = -0.5 is out of range; allowed: [0, 1000]",
        ),
        (
            "margin = 1.0",
            "margin = 1e5",
            "render.margin = 100000 is out of range; allowed: [0, 1000]",
        ),
        (
            "max_distance = 30.0",
            "max_distance = 0.0",
            "render.max_distance = 0 is out of range; allowed: (0, 10000]",
        ),
        (
            "eye_share = 0.2",
            "eye_share = 0.35",
            "render.eye_share = 0.35 is out of range",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        assert!(UNDERWATER_SCENE.contains(from), "{from}");
        std::fs::write(
            dir.path().join("bad.toml"),
            UNDERWATER_SCENE.replacen(from, to, 1),
        )
        .unwrap();
        let o = run_in(dir.path(), &["render", "--scene", "bad.toml", "-o", "out"]);
        assert_eq!(o.status.code(), Some(2), "{to}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{to}: {}", stderr(&o));
        assert_eq!(files_in(dir.path()), vec!["bad.toml".to_string()], "{to}");
    }
    // Options that do not fit the scene.
    let dir = tempfile::tempdir().unwrap();
    for (args, want) in [
        (&["--technique", "distance"][..], "--technique = distance"),
        (
            &["--terms", "direct"][..],
            "--terms = direct is not a term of the underwater scene",
        ),
        (&["--russian-roulette", "0.1"][..], "--russian-roulette"),
    ] {
        let o = render(dir.path(), args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
    }
    assert!(files_in(dir.path()).is_empty());
    // And the slab scene refuses the underwater terms.
    let o = run_in(dir.path(), &["render", "--terms", "caustics", "-o", "x"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("not a term of the slab scene"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn probe_rejects_the_underwater_terms_naming_the_field_and_the_allowed_ones() {
    let dir = tempfile::tempdir().unwrap();
    for term in ["caustics", "caustics-once-more", "shafts", "direct,shafts"] {
        let o = run_in(
            dir.path(),
            &[
                "probe",
                "--point",
                "0,0,0",
                "--terms",
                term,
                "--samples",
                "10",
            ],
        );
        assert_eq!(o.status.code(), Some(2), "{term}");
        let e = stderr(&o);
        assert!(e.contains("--terms"), "{term}: {e}");
        assert!(e.contains("allowed: direct, once-more"), "{term}: {e}");
        assert!(e.contains("underwater"), "{term}: {e}");
        assert!(stdout(&o).is_empty(), "{term}");
        assert!(files_in(dir.path()).is_empty(), "{term}");
    }
}
