//! `omnee estimate` against the quadrature reference, `omnee samples`, tabulated phase functions.

use crate::common::*;
use std::collections::HashMap;

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
    // docs/math.md §6: at g = 0.98 OMNEE's variance is orders of magnitude lower.
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
fn bridges_estimate_the_isotropic_closed_form_for_several_vertex_counts() {
    // 10 estimates against the closed form of docs/math.md §14.6, each
    // within 4.5 σ (two-sided normal tail 6.8e-6 each; the bridges' relative
    // variance is at most 20 here, docs/math.md §14, so 10⁵ draws are
    // near-normal), in f32 and f64, fixed K and the drawn K.
    let geometry = ["--x0", "0,0,0", "--x2", "0.3,-0.2,0.9", "--phase", "iso"];
    for (vertices, sigma_s, sigma_t, precision) in [
        ("2", "0.5", "1", "f32"),
        ("2", "1.5", "2", "f64"),
        ("3", "0.5", "1", "f64"),
        ("4", "2", "2.5", "f32"),
        ("5", "0.5", "1", "f32"),
        ("8", "3", "3", "f64"),
        ("auto", "0.5", "1", "f32"),
        ("auto", "2", "2.2", "f64"),
    ] {
        let v = estimate(
            &[
                &geometry[..],
                &[
                    "--vertices",
                    vertices,
                    "--sigma-s",
                    sigma_s,
                    "--sigma-t",
                    sigma_t,
                    "--precision",
                    precision,
                    "--samples",
                    "100000",
                ],
            ]
            .concat(),
        );
        let (mean, se, want) = (
            v["mean"].as_f64().unwrap(),
            v["stderr"].as_f64().unwrap(),
            v["reference"].as_f64().unwrap(),
        );
        let case = format!("--vertices {vertices} σs {sigma_s} σt {sigma_t} {precision}");
        assert!(
            (mean - want).abs() < 4.5 * se,
            "{case}: {mean} ± {se} vs {want}"
        );
        assert!(se < 0.05 * want, "{case}: {se}");
        assert_eq!(v["technique"], "bridge", "{case}");
        assert_eq!(v["vertices"], vertices, "{case}");
        // The orders add up to the whole, mean and reference.
        let orders = v["orders"].as_array().unwrap();
        let sum = |key: &str| -> f64 { orders.iter().map(|o| o[key].as_f64().unwrap()).sum() };
        assert!((sum("mean") - mean).abs() <= 1e-9 * mean, "{case}");
        assert!((sum("reference") - want).abs() <= 1e-12 * want, "{case}");
        if vertices == "auto" {
            assert_eq!(orders.len(), 8, "{case}: K_max is 8");
            assert!((sum("probability") - 1.0).abs() < 1e-6, "{case}");
        }
    }
    // --max-vertices changes K_max; the first order is the once-more
    // integral, whose closed form is the quadrature's.
    let v = estimate(
        &[
            &geometry[..],
            &[
                "--vertices",
                "auto",
                "--max-vertices",
                "3",
                "--sigma-s",
                "1",
                "--sigma-t",
                "1.5",
                "--precision",
                "f64",
            ],
        ]
        .concat(),
    );
    assert_eq!(v["orders"].as_array().unwrap().len(), 3);
    assert_eq!(v["max_vertices"], 3);
    let once = estimate(&[&geometry[..], &["--sigma-s", "1", "--sigma-t", "1.5"]].concat());
    let (a, b) = (
        v["orders"][0]["reference"].as_f64().unwrap(),
        once["reference"].as_f64().unwrap(),
    );
    assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
}

#[test]
fn one_vertex_is_the_estimate_as_before_and_bad_vertex_counts_are_named() {
    // --vertices 1 is the default and draws exactly as without it.
    let args = [
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.2",
        "--sigma-t",
        "0.5",
        "--phase",
        "hg:0.9",
        "--samples",
        "5000",
    ];
    let plain = estimate_only(&args);
    let one = estimate_only(&[&args[..], &["--vertices", "1"]].concat());
    assert_eq!(plain["mean"], one["mean"]);
    assert_eq!(plain["stderr"], one["stderr"]);
    assert_eq!(one["technique"], "omnee");
    let base = [
        "estimate",
        "--x0",
        "0,0,0",
        "--x2",
        "0,0,1",
        "--sigma-s",
        "0.2",
    ];
    for (extra, needle) in [
        (
            vec!["--sigma-t", "0.5", "--vertices", "0"],
            "--vertices = 0",
        ),
        (
            vec!["--sigma-t", "0.5", "--vertices", "33"],
            "--vertices = 33",
        ),
        (vec!["--sigma-t", "0.5", "--vertices", "many"], "--vertices"),
        (vec!["--sigma-t", "0.5", "--vertices", "-2"], "--vertices"),
        (
            vec![
                "--sigma-t",
                "0.5",
                "--vertices",
                "auto",
                "--max-vertices",
                "40",
            ],
            "--max-vertices = 40",
        ),
        (
            vec!["--sigma-t", "0.5", "--vertices", "2", "--max-vertices", "4"],
            "--max-vertices = 4 applies to --vertices auto only",
        ),
        (
            vec![
                "--sigma-t",
                "0.5",
                "--vertices",
                "2",
                "--technique",
                "omnee",
            ],
            "--technique = omnee applies to --vertices = 1 only",
        ),
        (
            vec!["--sigma-t", "0.5", "--vertices", "3", "--theta-max", "1"],
            "--theta-max = 1",
        ),
        (
            vec![
                "--sigma-t",
                "0.5",
                "--vertices",
                "3",
                "--receiver-normal",
                "0,0,1",
            ],
            "--receiver-normal",
        ),
        (
            vec![
                "--sigma-t",
                "0.5",
                "--vertices",
                "3",
                "--phase",
                "hg:0.5",
                "--reference",
            ],
            "--phase = hg:0.5 has no reference with --vertices = 3",
        ),
    ] {
        let o = omnee().args(base).args(&extra).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(stderr(&o).contains(needle), "{extra:?}: {}", stderr(&o));
    }
    // Without --reference any phase function is fine.
    let v = estimate_only(&[&args[..], &["--vertices", "3"]].concat());
    assert!(v["mean"].as_f64().unwrap() > 0.0 && v["reference"].is_null());
}

#[test]
fn samples_lists_every_vertex_of_a_bridge() {
    let o = omnee()
        .args([
            "samples",
            "--x0",
            "0,0,0",
            "--x2",
            "0,0,1",
            "--sigma-s",
            "0.5",
            "--sigma-t",
            "1",
            "--vertices",
            "3",
            "--count",
            "50",
            "--format",
            "json",
            "--precision",
            "f64",
        ])
        .output()
        .unwrap();
    let v = json(&o);
    assert_eq!(
        (v["technique"].as_str(), v["vertices"].as_str()),
        (Some("bridge"), Some("3"))
    );
    let list = v["samples"].as_array().unwrap();
    assert_eq!(list.len() % 3, 0);
    for draw in list.chunks(3) {
        let vertex: Vec<u64> = draw.iter().map(|s| s["vertex"].as_u64().unwrap()).collect();
        assert_eq!(vertex, [0, 1, 2]);
        assert!(
            draw.iter()
                .all(|s| s["draw"] == draw[0]["draw"] && s["pdf"] == draw[0]["pdf"])
        );
        assert!(draw[0]["estimate"].as_f64().unwrap() > 0.0);
    }
}
