//! Bad input, file safety (atomic replace, modes), choosing scenes, `--help`.

use crate::common::*;
use std::path::Path;
use std::process::Command;

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
            // An emission the f32 image could not hold is refused up front.
            vec![],
            Box::new(|t| replace_line(&t, "radiance =", "radiance = 1e39")),
            vec!["light.radiance = 1e39", "[0, 1e20]"],
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

#[cfg(unix)]
#[test]
fn outputs_get_the_mode_the_umask_asks_for() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    // Run under `sh` with the umask set, as a user's shell would.
    let with_umask = |umask: &str, args: &[&str]| {
        let o = Command::new("sh")
            .current_dir(dir.path())
            .arg("-c")
            .arg(format!("umask {umask} && exec \"$0\" \"$@\""))
            .arg(env!("CARGO_BIN_EXE_omnee"))
            .args(args)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    };
    let mode = |name: &str| {
        std::fs::metadata(dir.path().join(name))
            .unwrap()
            .permissions()
            .mode()
            & 0o777
    };
    for (umask, want) in [("022", 0o644), ("077", 0o600), ("002", 0o664)] {
        let base = format!("u{umask}");
        with_umask(
            umask,
            &[
                "render",
                "--resolution",
                "4x3",
                "--spp",
                "1",
                "--png-layers",
                "--progress",
                "never",
                "-o",
                &base,
            ],
        );
        for ext in ["exr", "png", "direct.png", "once-more.png", "view.png"] {
            assert_eq!(mode(&format!("{base}.{ext}")), want, "{base}.{ext}");
        }
        let merged = format!("m{umask}");
        with_umask(umask, &["merge", &format!("{base}.exr"), "-o", &merged]);
        for ext in ["exr", "png"] {
            assert_eq!(mode(&format!("{merged}.{ext}")), want, "{merged}.{ext}");
        }
    }
}

#[test]
fn scenes_are_chosen_by_builtin_name_or_file() {
    let dir = tempfile::tempdir().unwrap();
    let by_default = stdout(&run_in(dir.path(), &["default-scene"]));
    let by_name = run_in(dir.path(), &["default-scene", "default"]);
    assert_eq!(stdout(&by_name), by_default);
    let o = run_in(dir.path(), &["default-scene", "moon"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("\"moon\" is not a scene; allowed: default"),
        "{}",
        stderr(&o)
    );
    // `--scene default` is the built-in scene, `--scene ./default` a file.
    std::fs::write(dir.path().join("default"), &by_default).unwrap();
    let args = |scene: &'static str| {
        [
            "probe",
            "--scene",
            scene,
            "--point",
            "0.1,0,0",
            "--samples",
            "5000",
            "--json",
        ]
    };
    let builtin = json(&run_in(dir.path(), &args("default")));
    let file = json(&run_in(dir.path(), &args("./default")));
    assert_eq!(builtin["mean"], file["mean"]);
    std::fs::write(dir.path().join("default"), "not a scene").unwrap();
    let o = run_in(dir.path(), &args("./default"));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("./default"), "{}", stderr(&o));
}

#[test]
fn a_medium_too_thick_for_f32_is_bad_input_not_a_silent_zero() {
    let dir = tempfile::tempdir().unwrap();
    scene_with(dir.path(), "thick.toml", |t| {
        replace_line(&t, "sigma_s =", "sigma_s = 1e39")
    });
    for technique in ["distance", "omnee"] {
        let o = run_in(
            dir.path(),
            &[
                "render",
                "--scene",
                "thick.toml",
                "--technique",
                technique,
                "--resolution",
                "4x3",
                "--spp",
                "1",
            ],
        );
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("medium.sigma_s + medium.sigma_a")
                && stderr(&o).contains("sigma_t"),
            "{}",
            stderr(&o)
        );
        assert_eq!(files_in(dir.path()), ["thick.toml"]);
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
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../omnee-render/scenes/default.toml")
        )
        .unwrap()
    );
}
