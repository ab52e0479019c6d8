//! The command line at its boundaries: extreme but valid scales give the
//! scaled answer, NaN and ∞ in any number and huge or negative counts are
//! named errors (exit 2, the field and its allowed range on stderr, nothing
//! on stdout), and nothing hangs: every run here has a watchdog and fails
//! if it is still going after [`WATCHDOG`] (a hang detector, not a timing:
//! the runs take well under a second each in release and a few in debug).

use crate::common::*;
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

/// How long a run may take before it counts as hung.
const WATCHDOG: Duration = Duration::from_secs(120);

/// Runs `omnee ARGS`, killing it (and failing) after [`WATCHDOG`].
fn run(args: &[&str]) -> Output {
    let mut child = omnee()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("omnee starts");
    let start = Instant::now();
    while child.try_wait().expect("omnee runs").is_none() {
        if start.elapsed() > WATCHDOG {
            child.kill().ok();
            panic!("omnee {args:?} still running after {WATCHDOG:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("omnee's output")
}

/// `run(args)` must be refused: exit 2, stderr `omnee: error: FIELD ...
/// allowed: ...` naming `field`, nothing on stdout, no panic.
fn refused(args: &[&str], field: &str) -> String {
    let o = run(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert!(
        e.starts_with(&format!("omnee: error: {field}")) && e.contains("allowed: "),
        "{args:?} should name {field} and its range: {e}"
    );
    assert!(!e.contains("panicked"), "{args:?}: {e}");
    assert!(o.stdout.is_empty(), "{args:?}: {}", stdout(&o));
    e
}

/// `omnee estimate --json ARGS`, which must succeed with finite numbers.
fn estimate(args: &[&str]) -> serde_json::Value {
    let mut a = vec!["estimate", "--json"];
    a.extend(args);
    let v = json(&run(&a));
    for key in ["mean", "stderr"] {
        assert!(v[key].as_f64().is_some_and(f64::is_finite), "{a:?}: {v}");
    }
    v
}

/// `|mean − reference| < z_max · stderr` (with a floor of 1e-12 of the
/// reference for a zero-variance estimate), the reference finite and
/// positive.
fn agrees(v: &serde_json::Value, z_max: f64, what: &str) {
    let (mean, stderr) = (v["mean"].as_f64().unwrap(), v["stderr"].as_f64().unwrap());
    let reference = v["reference"].as_f64().unwrap_or(f64::NAN);
    assert!(reference.is_finite() && reference > 0.0, "{what}: {v}");
    let z = (mean - reference) / stderr.max(1e-12 * reference);
    assert!(
        z.abs() < z_max,
        "{what}: {mean} +- {stderr} vs {reference} (z = {z})"
    );
}

/// `omnee estimate --json` of the problem scaled to `s`: `x0` at the
/// origin, `x2` as given, σs = 0.5/s and σt = 0.55/s (the optical thickness
/// 0.55 at every scale), in `precision` with 40000 draws and the reference,
/// and the options of `rest`.
fn estimate_scaled(x2: &str, s: f64, precision: &str, rest: &[&str]) -> serde_json::Value {
    let (sigma_s, sigma_t) = (format!("{:e}", 0.5 / s), format!("{:e}", 0.55 / s));
    let mut a = vec![
        "--x0",
        "0,0,0",
        "--x2",
        x2,
        "--sigma-s",
        &sigma_s,
        "--sigma-t",
        &sigma_t,
        "--precision",
        precision,
        "--samples",
        "40000",
        "--reference",
    ];
    a.extend(rest);
    estimate(&a)
}

/// End points `s` apart along a diagonal, σs = 0.5/s and σt = 0.55/s (the
/// optical thickness 0.55 at every scale): the transfer is `λ⁻²` times the
/// unit problem's, which the estimate and its reference must both give.
#[test]
fn extreme_scales_estimate_the_scaled_reference() {
    // 12 comparisons (the unit problem, 5 scales × 2 techniques, a thin
    // medium at 1e-300), each |z| < 5.5: normal
    // two-sided tail 3.8e-8, the family fails less than once in 10⁶ runs;
    // OMNEE and MIS have finite variance here.
    let unit = estimate(&[
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
        "--phase",
        "hg:0.5",
        "--technique",
        "omnee",
        "--samples",
        "40000",
        "--reference",
    ]);
    let unit_reference = unit["reference"].as_f64().unwrap();
    agrees(&unit, 5.5, "unit");
    for (precision, s) in [
        ("f32", 1e-30),
        ("f32", 1e30),
        ("f32", 1e38),
        ("f64", 1e-150),
        ("f64", 1e150),
    ] {
        let c = s / 3f64.sqrt();
        let x2 = format!("{c:e},{c:e},{:e}", -c);
        for technique in ["omnee", "mis"] {
            let what = format!("{precision} s = {s:e} {technique}");
            let v = estimate_scaled(
                &x2,
                s,
                precision,
                &["--phase", "hg:0.5", "--technique", technique],
            );
            agrees(&v, 5.5, &what);
            // The reference of the scaled problem is the unit one's over s².
            let scaled = v["reference"].as_f64().unwrap() * s * s;
            assert!(
                (scaled / unit_reference - 1.0).abs() < 1e-6,
                "{what}: {scaled} vs {unit_reference}"
            );
            assert!((v["tau"].as_f64().unwrap() - 0.55).abs() < 1e-6, "{what}");
        }
    }
    // s = 1e-300 in f64 with σs = 0.5/s would give 1e600 (refused below);
    // in a thin medium the transfer is about σs/s = 1e300. One more
    // comparison, by MIS (OMNEE's variance diverges without attenuation).
    let v = estimate(&[
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1e-300",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
        "--phase",
        "hg:0.5",
        "--technique",
        "mis",
        "--precision",
        "f64",
        "--samples",
        "40000",
        "--reference",
    ]);
    agrees(&v, 5.5, "f64 s = 1e-300, thin");
    assert!(v["reference"].as_f64().unwrap() > 1e299, "{v}");
}

/// Bridges at extreme scales: isotropic scattering between end points `s`
/// apart, σs = 0.5/s and σt = 0.55/s, with `k` fixed or drawn: every order's
/// `I_k` is `λ⁻²` times the unit problem's, and the estimate agrees with the
/// closed form where the f32 estimate itself (about 1e59 at s = 1e-30) is
/// beyond f32's range, and with the same numbers gives the unit problem's
/// estimate scaled.
#[test]
fn bridges_at_extreme_scales_estimate_the_scaled_closed_form() {
    // 12 comparisons (2 vertex numbers × (the unit problem and 5 scales)),
    // each |z| < 5.5: the family fails less than once in 10⁶ runs.
    let run_at = |precision: &str, s: f64, vertices: &str| {
        let x2 = format!("0,0,{s:e}");
        let v = estimate_scaled(
            &x2,
            s,
            precision,
            &["--phase", "iso", "--vertices", vertices],
        );
        agrees(
            &v,
            5.5,
            &format!("{precision} s = {s:e}, --vertices {vertices}"),
        );
        v
    };
    for vertices in ["3", "auto"] {
        for precision in ["f32", "f64"] {
            let unit = run_at(precision, 1.0, vertices);
            let scales: &[f64] = if precision == "f32" {
                &[1e-30, 1e30]
            } else {
                &[1e-150, 1e150, 1e-300]
            };
            for &s in scales {
                if precision == "f64" && s == 1e-300 {
                    // I_k ≈ 1e600: beyond f64, a named error.
                    let x2 = "0,0,1e-300";
                    refused(
                        &[
                            "estimate",
                            "--x0",
                            "0,0,0",
                            "--x2",
                            x2,
                            "--sigma-s",
                            "5e299",
                            "--sigma-t",
                            "5.5e299",
                            "--phase",
                            "iso",
                            "--vertices",
                            vertices,
                            "--precision",
                            "f64",
                        ],
                        "--x0/--x2/--sigma-s",
                    );
                    continue;
                }
                let v = run_at(precision, s, vertices);
                let what = format!("{precision} s = {s:e}, --vertices {vertices}");
                for key in ["mean", "reference"] {
                    let scaled = v[key].as_f64().unwrap() * s * s;
                    let want = unit[key].as_f64().unwrap();
                    // The same numbers: the scaled estimate is the unit one
                    // to the rounding of the precision.
                    let tol = if precision == "f32" { 1e-4 } else { 1e-9 };
                    assert!(
                        (scaled / want - 1.0).abs() < tol,
                        "{what}: {key} {scaled} vs {want}"
                    );
                }
            }
        }
    }
}

/// `samples` at s = 1e-30 in f32: the densities (about 1e90) are beyond
/// f32 and listed saturated, with a note naming the way out; the estimates,
/// formed in f64, are the scaled unit ones; the CSV keeps exponents.
#[test]
fn samples_at_extreme_scales_list_saturated_densities_with_a_note() {
    let rows = |s: f64, precision: &str| {
        let x2 = format!("{s:e},0,0");
        let sigma = format!("{:e}", 0.5 / s);
        let o = run(&[
            "samples",
            "--x0",
            "0,0,0",
            "--x2",
            &x2,
            "--sigma-s",
            &sigma,
            "--sigma-t",
            &sigma,
            "--phase",
            "hg:0.9",
            "--count",
            "50",
            "--precision",
            precision,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = stdout(&o);
        let rows: Vec<Vec<f64>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        (rows, stderr(&o), text)
    };
    let (unit, note, _) = rows(1.0, "f32");
    assert!(note.is_empty(), "{note}");
    let (tiny, note, text) = rows(1e-30, "f32");
    assert!(
        note.starts_with("omnee: note: 50 of 50 rows") && note.contains("--precision f64"),
        "{note}"
    );
    assert!(!text.contains("0000000000"), "{text}");
    for (a, b) in unit.iter().zip(&tiny) {
        assert_eq!(b[8], f64::from(f32::MAX));
        assert!((b[10] * 1e-60 / a[10] - 1.0).abs() < 1e-5, "{a:?} vs {b:?}");
    }
    let (unit, _, _) = rows(1.0, "f64");
    let (wide, note, _) = rows(1e-30, "f64");
    assert!(note.is_empty(), "{note}");
    for (a, b) in unit.iter().zip(&wide) {
        assert!((b[8] * 1e-90 / a[8] - 1.0).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

/// Where the transfer itself leaves f64's range the answer is a named
/// error (above) or f64's rounding, 0 (below); never ∞ or NaN.
#[test]
fn a_transfer_beyond_f64_is_refused_and_one_below_it_is_zero() {
    let e = refused(
        &[
            "estimate",
            "--x0",
            "0,0,0",
            "--x2",
            "0,0,1e-300",
            "--sigma-s",
            "5e299",
            "--sigma-t",
            "5.5e299",
            "--precision",
            "f64",
            "--samples",
            "1000",
            "--reference",
        ],
        "--x0/--x2/--sigma-s",
    );
    assert!(e.contains("beyond f64's range"), "{e}");
    // I ≈ 4e-601: both the estimate and the reference round to 0.
    let v = estimate(&[
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1e300",
        "--sigma-s",
        "5e-301",
        "--sigma-t",
        "5.5e-301",
        "--precision",
        "f64",
        "--samples",
        "1000",
        "--reference",
    ]);
    assert_eq!(
        (v["mean"].as_f64(), v["reference"].as_f64()),
        (Some(0.0), Some(0.0)),
        "{v}"
    );
    assert!((v["tau"].as_f64().unwrap() - 0.55).abs() < 1e-9, "{v}");
    // Points at the ends of f64's range: 1.6e308 apart is a distance.
    let v = estimate(&[
        "--x0",
        "-8e307,0,0",
        "--x2",
        "8e307,0,0",
        "--sigma-s",
        "0",
        "--sigma-t",
        "0",
        "--precision",
        "f64",
        "--samples",
        "1000",
    ]);
    assert_eq!(v["mean"].as_f64(), Some(0.0), "{v}");
    // A difference beyond f64 itself is named.
    refused(
        &[
            "estimate",
            "--x0",
            "-1e308,0,0",
            "--x2",
            "1e308,0,0",
            "--sigma-s",
            "0",
            "--sigma-t",
            "0",
            "--precision",
            "f64",
        ],
        "--x2 - --x0",
    );
}

/// A receiver normal of any finite non-zero length is its direction: the
/// estimate is the unit normal's (the same draws), against the reference.
#[test]
fn receiver_normals_of_any_length_are_their_direction() {
    let base = [
        "--x0",
        "0,0,0",
        "--x2",
        "0.2,0.1,1",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
        "--phase",
        "hg:0.3",
        "--technique",
        "omnee",
        "--samples",
        "20000",
    ];
    let with = |normal: &str, precision: &str, reference: bool| {
        let mut a = base.to_vec();
        a.extend(["--receiver-normal", normal, "--precision", precision]);
        if reference {
            a.push("--reference");
        }
        estimate(&a)
    };
    for precision in ["f32", "f64"] {
        let unit = with("0.3,0,-1", precision, true);
        // One comparison per precision, |z| < 5.5.
        agrees(&unit, 5.5, precision);
        let tiny = if precision == "f32" {
            "3e-31,0,-1e-30"
        } else {
            "3e-301,0,-1e-300"
        };
        let huge = if precision == "f32" {
            "3e37,0,-1e38"
        } else {
            "3e307,0,-1e308"
        };
        for normal in [tiny, huge] {
            let v = with(normal, precision, false);
            let (a, b) = (v["mean"].as_f64().unwrap(), unit["mean"].as_f64().unwrap());
            assert!(
                (a / b - 1.0).abs() < 1e-5,
                "{precision} {normal}: {a} vs {b}"
            );
        }
    }
    // Subnormal and f64::MAX components, all three.
    for normal in ["4.9e-324,4.9e-324,4.9e-324", "1.7e308,1.7e308,1.7e308"] {
        let v = with(normal, "f64", false);
        let n = v["receiver_normal"].as_array().unwrap();
        for c in n {
            assert!(
                (c.as_f64().unwrap() - 1.0 / 3f64.sqrt()).abs() < 1e-12,
                "{normal}: {v}"
            );
        }
    }
    refused(
        &[
            &["estimate"][..],
            &base[..],
            &["--receiver-normal", "0,0,0"],
        ]
        .concat(),
        "--receiver-normal",
    );
}

/// θmax from the smallest positive number of the precision to π, with a
/// receiver normal near π too: an answer (the reference's, within its
/// error), promptly (the watchdog), or for a θmax below the precision's
/// smallest a named error.
#[test]
fn theta_max_over_its_whole_range() {
    let base = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
        "--technique",
        "omnee",
        "--samples",
        "20000",
    ];
    for (theta_max, precision) in [("1.401298464324817e-45", "f32"), ("4.9e-324", "f64")] {
        let mut a = base.to_vec();
        a.extend([
            "--theta-max",
            theta_max,
            "--precision",
            precision,
            "--reference",
        ]);
        let v = estimate(&a);
        // The restricted integral is of order θmax²: 0 in f64.
        assert_eq!(v["mean"].as_f64(), Some(0.0), "{v}");
        assert!(
            v["reference"]
                .as_f64()
                .is_some_and(|r| (0.0..1e-80).contains(&r)),
            "{v}"
        );
    }
    let e = refused(
        &[&["estimate"][..], &base[..], &["--theta-max", "4.9e-324"]].concat(),
        "--theta-max = 5e-324",
    );
    assert!(e.contains("1.401298464324817e-45"), "{e}");
    // Near π with receiver normals in several directions: the reference
    // (split where the cosine clips) returns, and agrees. 4 comparisons,
    // |z| < 5.5.
    for normal in ["0.3,0.2,1", "0.3,0.2,-1", "1,0,-0.2", "-0.1,1,0.5"] {
        for theta_max in ["3.14159", "3.141592653589793"] {
            let mut a = base.to_vec();
            a.extend([
                "--theta-max",
                theta_max,
                "--receiver-normal",
                normal,
                "--reference",
            ]);
            a.extend(["--precision", "f64"]);
            let v = estimate(&a);
            if theta_max == "3.14159" {
                agrees(&v, 5.5, normal);
            } else {
                assert!(v["reference"].as_f64().is_some_and(f64::is_finite), "{v}");
            }
        }
    }
}

/// A reference whose quadrature spends its evaluation budget is a named
/// error on `--reference` (exit 2), not a hang and not NaN; the estimate
/// of the same problem without it works. A normal at right angles to the
/// connection puts the cosine's clipping kinks on top of each other (the
/// core's quadrature does not converge there); should it converge one day,
/// the reference must agree with the estimate instead.
#[test]
fn a_reference_out_of_budget_is_a_named_error() {
    let a = [
        "estimate",
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
        "--receiver-normal",
        "1,0,0",
        "--technique",
        "omnee",
        "--samples",
        "20000",
        "--precision",
        "f64",
    ];
    let with = run(&[&a[..], &["--json", "--reference"]].concat());
    match with.status.code() {
        Some(0) => agrees(&json(&with), 5.5, "normal at right angles"),
        _ => {
            let e = stderr(&with);
            assert_eq!(with.status.code(), Some(2), "{e}");
            assert!(
                e.starts_with("omnee: error: --reference: ")
                    && e.contains("did not converge within its budget")
                    && e.contains("allowed: "),
                "{e}"
            );
            assert!(with.stdout.is_empty());
        }
    }
    estimate(&a[1..]);
}

/// NaN and ∞ in every number of every subcommand: the option named, exit 2.
#[test]
fn nan_and_infinity_in_any_number_are_named() {
    let problem = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
    ];
    for command in ["estimate", "samples"] {
        for (option, bad) in [
            ("--x0", "nan,0,0"),
            ("--x2", "0,inf,0"),
            ("--x2", "0,0,-inf"),
            ("--sigma-s", "nan"),
            ("--sigma-t", "inf"),
            ("--sigma-s", "-inf"),
            ("--theta-max", "nan"),
            ("--theta-max", "inf"),
            ("--receiver-normal", "nan,0,1"),
            ("--x0-incoming", "0,inf,1"),
        ] {
            let mut a = vec![command];
            for pair in problem.chunks(2) {
                if pair[0] != option {
                    a.extend(pair);
                }
            }
            a.extend([option, bad]);
            if option == "--x0-incoming" {
                a.extend(["--x0-phase", "hg:0.5"]);
            }
            refused(&a, option);
        }
    }
    // The precision's range: finite in f64, not in f32.
    refused(
        &[&["estimate"][..], &problem[..6], &["--sigma-t", "1e39"]].concat(),
        "--sigma-s/--sigma-t",
    );
    for (option, bad) in [
        ("--point", "nan,0,0"),
        ("--normal", "0,0,inf"),
        ("--theta-max", "nan"),
    ] {
        let mut a = vec!["probe", "--samples", "10", option, bad];
        if option != "--point" {
            a.extend(["--point", "0,0,0"]);
        }
        refused(&a, option);
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x");
    let out = out.to_str().unwrap();
    for (option, bad) in [
        ("--time", "nan"),
        ("--time", "inf"),
        ("--theta-max", "nan"),
        ("--exposure", "inf"),
        ("--russian-roulette", "nan"),
    ] {
        refused(
            &["render", "--resolution", "4x4", "-o", out, option, bad],
            option,
        );
    }
    assert!(files_in(dir.path()).is_empty());
}

/// Counts beyond what can finish, negative counts and counts that are no
/// whole numbers: refused before any work, naming the documented maximum.
#[test]
fn huge_and_negative_counts_are_refused_up_front() {
    let problem = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.5",
        "--sigma-t",
        "0.55",
    ];
    let cases: [(&str, &str, &str, &str); 14] = [
        ("estimate", "--samples", "18446744073709551615", "[1, 2^40]"),
        ("estimate", "--samples", "1099511627777", "[1, 2^40]"),
        ("estimate", "--samples", "1e30", "[1, 2^40]"),
        ("estimate", "--samples", "-1", "[1, 2^40]"),
        ("estimate", "--samples", "0", "[1, 2^40]"),
        ("estimate", "--samples", "2.5", "[1, 2^40]"),
        ("estimate", "--threads", "18446744073709551615", "[0, 1024]"),
        ("estimate", "--threads", "-1", "[0, 1024]"),
        ("estimate", "--max-vertices", "1e30", "[2, 32]"),
        ("samples", "--count", "16777217", "[1, 2^24]"),
        ("samples", "--count", "-1", "[1, 2^24]"),
        ("probe", "--samples", "18446744073709551615", "[1, 2^40]"),
        ("probe", "--threads", "100000000", "[0, 1024]"),
        ("samples", "--count", "nan", "[1, 2^24]"),
    ];
    for (command, option, bad, allowed) in cases {
        let mut a = vec![command, option, bad];
        if command == "probe" {
            a.extend(["--point", "0,0,0"]);
        } else {
            a.extend(problem);
        }
        if option == "--max-vertices" {
            a.extend(["--vertices", "auto"]);
        }
        let e = refused(&a, &format!("{option} = {bad} "));
        assert!(e.contains(allowed), "{a:?}: {e}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x");
    let out = out.to_str().unwrap();
    let render: [(&[&str], &str, &str); 8] = [
        (&["--spp", "1e30"], "--spp", "[1, 2^24]"),
        (&["--spp", "-1"], "--spp", "[1, 2^24]"),
        (&["--spp", "16777217"], "--spp", "[1, 2^24]"),
        // 2^40 samples: 4096 passes of the largest image.
        (
            &["--spp", "4097", "--resolution", "16384x16384"],
            "--spp",
            "[1, 4096]",
        ),
        (&["--time", "1e300"], "--time", "(0, 604800]"),
        (&["--time", "-1"], "--time", "(0, 604800]"),
        (
            &["--threads", "18446744073709551615"],
            "--threads",
            "[0, 1024]",
        ),
        (&["--resolution", "1e30x4"], "--resolution", "[1, 16384]"),
    ];
    for (args, option, allowed) in render {
        let mut a = vec!["render", "-o", out];
        a.extend(args);
        let e = refused(&a, option);
        assert!(e.contains(allowed), "{a:?}: {e}");
    }
    assert!(files_in(dir.path()).is_empty());
}
