//! The bindings in headless Chromium (wasm-bindgen-test): the same numbers as
//! the native build for the fixed seeds of `common`, to 1e-6 relative, and
//! bad input rejected with an error instead of a trap, and phase-spec
//! numbers read as Rust reads them.
#![cfg(target_arch = "wasm32")]

mod common;

use common::*;
use omnee_wasm::{Demo, Technique, arc, histogram, mean_cosine, quantile, waterlevel};
use wasm_bindgen::prelude::wasm_bindgen;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

fn demo(spec: &str, x0: [f64; 2], x2: [f64; 2], m: (f64, f64, f64)) -> Demo {
    tilted(spec, x0, x2, m, None)
}

/// [`demo`] with the lobe at `x0` tilted by `tilt`, if given.
fn tilted(spec: &str, x0: [f64; 2], x2: [f64; 2], m: (f64, f64, f64), tilt: Option<f64>) -> Demo {
    let d = Demo::new(
        spec,
        x0[0],
        x0[1],
        x2[0],
        x2[1],
        m.0,
        m.1,
        m.2,
        SEED.into(),
        tilt,
    );
    d.unwrap_or_else(|_| panic!("Demo::new({spec}) failed"))
}

/// The demo's techniques, in the order of its statistics
/// (`demo::TECHNIQUES`); without a lobe at `x0` the first three.
const TECHNIQUES: [Technique; 5] = [
    Technique::Omnee,
    Technique::Equiangular,
    Technique::Mis,
    Technique::Lobe,
    Technique::LobeMis,
];

fn estimates(d: &Demo, techniques: &[Technique]) -> Vec<f64> {
    techniques
        .iter()
        .copied()
        .flat_map(|t| {
            let e = d.estimate(t).expect("estimate");
            [get(&e, "count"), get(&e, "mean"), get(&e, "stdError")]
        })
        .collect()
}

#[wasm_bindgen_test]
fn browser_numbers_match_the_native_fixture() {
    let mut a = demo(A_SPEC, A_X0, A_X2, A_MEDIUM);
    a.run(RUN.into()).expect("run a");
    let mut b = demo(B_SPEC, B_X0, B_X2, B_MEDIUM);
    b.run(RUN.into()).expect("run b");
    let mut c = tilted(C_SPEC, C_X0, C_X2, C_MEDIUM, Some(C_TILT));
    c.run(RUN.into()).expect("run c");
    let cloud = |t| numbers(&a.cloud(t, CLOUD.into(), 9.0).expect("cloud"));
    let (spec, n, bins, hi) = HIST;
    let (x0, x2, theta, xi) = WATER;
    let w = waterlevel(x0[0], x0[1], x2[0], x2[1], theta, xi).expect("waterlevel");
    let got = [
        vec![a.reference()],
        estimates(&a, &TECHNIQUES[..3]),
        vec![b.reference()],
        estimates(&b, &TECHNIQUES[..3]),
        estimates(&c, &TECHNIQUES),
        vec![c.lobe_probability()],
        cloud(Technique::Omnee),
        cloud(Technique::Equiangular),
        cloud(Technique::Mis),
        numbers(&histogram(spec, n.into(), bins.into(), hi, 11.0).expect("histogram")),
        [
            "x1x", "x1y", "theta", "alpha", "beta", "xi", "t", "s", "d1", "d2", "radius", "cx",
            "cy",
        ]
        .map(|k| get(&w, k))
        .to_vec(),
        vec![quantile(B_SPEC, 0.9).expect("quantile")],
    ];
    for ((name, g), want) in NAMES.iter().zip(&got).zip(fixture::ALL) {
        assert_close(name, g, want);
    }
    // The fixture is not empty (a blessed fixture, not the placeholder).
    assert!(fixture::ALL.iter().all(|f| !f.is_empty()));
}

#[wasm_bindgen_test]
fn estimates_report_the_relative_error() {
    let mut d = demo("hg:0.9", [-0.5, 0.0], [0.5, 0.0], (0.2, 0.05, PI));
    d.run(50_000.0).expect("run");
    let r = d.reference();
    for t in &TECHNIQUES[..3] {
        let e = d.estimate(*t).expect("estimate");
        assert_eq!(get(&e, "count"), 50_000.0);
        let (mean, rel) = (get(&e, "mean"), get(&e, "relativeError"));
        assert!((rel - (mean - r).abs() / r).abs() < 1e-15);
    }
    d.reset();
    assert_eq!(
        get(&d.estimate(Technique::Mis).expect("estimate"), "count"),
        0.0
    );
    // With a lobe at x0 the module has no reference (the page's is
    // precomputed) and reports the combination's probability c.
    assert!(d.lobe_probability().is_nan());
    let mut t =
        Demo::new("hg:0.9", -0.5, 0.0, 0.5, 0.0, 0.2, 0.05, PI, 1.0, Some(0.5)).expect("lobe");
    assert!(t.reference().is_nan() && t.lobe_probability() > 0.45);
    t.run(1000.0).expect("run");
    let e = t.estimate(Technique::LobeMis).expect("estimate");
    assert!(get(&e, "mean") > 0.0 && get(&e, "relativeError").is_nan());
    assert!((mean_cosine("hg:0.9").expect("g") - 0.9).abs() < 1e-15);
    let pts = arc(0.0, 0.0, 1.0, 0.0, 1.0, 16.0).expect("arc");
    assert_eq!(numbers(&pts).len(), 4 * 17);
}

#[wasm_bindgen_test]
fn bad_input_is_an_error_not_a_trap() {
    let bad = |spec: &str, x2: [f64; 2], g: (f64, f64, f64)| {
        Demo::new(spec, 0.0, 0.0, x2[0], x2[1], g.0, g.1, g.2, 1.0, None).is_err()
    };
    assert!(bad("hg:0.5", [0.0, 0.0], (0.1, 0.1, PI)), "x0 == x2");
    assert!(bad("hg:0.5", [f64::NAN, 0.0], (0.1, 0.1, PI)), "NaN");
    assert!(bad("hg:1.5", [1.0, 0.0], (0.1, 0.1, PI)), "g out of range");
    assert!(bad("hg:-1", [1.0, 0.0], (0.1, 0.1, PI)), "g = -1");
    assert!(bad("nope", [1.0, 0.0], (0.1, 0.1, PI)), "unknown spec");
    assert!(bad("iso", [1.0, 0.0], (f64::NAN, 0.1, PI)), "NaN sigma_s");
    assert!(bad("iso", [1.0, 0.0], (0.1, 0.1, 4.0)), "theta_max > pi");
    for tilt in [-0.5, 4.0, f64::NAN] {
        let d = Demo::new("iso", 0.0, 0.0, 1.0, 0.0, 0.1, 0.1, PI, 1.0, Some(tilt));
        assert!(d.is_err(), "tilt {tilt}");
    }
    let mut d = demo("iso", [0.0, 0.0], [1.0, 0.0], (0.1, 0.1, PI));
    assert!(d.run(0.0).is_err() && d.run(u32::MAX.into()).is_err());
    // Not taken modulo 2³²: 2³² + 5, −1, NaN and 1.5 are refused.
    for n in [4294967301.0, -1.0, f64::NAN, 1.5] {
        assert!(
            d.run(n).is_err() && d.cloud(Technique::Omnee, 10.0, n).is_err(),
            "{n}"
        );
    }
    assert!(d.cloud(Technique::Omnee, u32::MAX.into(), 1.0).is_err());
    assert!(histogram("hg:2", 10.0, 8.0, 1.0, 1.0).is_err());
    assert!(histogram("iso", 10.0, 8.0, f64::NAN, 1.0).is_err());
    assert!(quantile("iso", f64::NAN).is_err());
    assert!(waterlevel(0.0, 0.0, 0.0, 0.0, 1.0, 0.5).is_err());
    assert!(waterlevel(0.0, 0.0, 1.0, 0.0, f64::NAN, 0.5).is_err());
    assert!(arc(f64::INFINITY, 0.0, 1.0, 0.0, 1.0, 8.0).is_err());
    // The demo object is still usable after the errors.
    assert!(d.run(10.0).is_ok());
}

#[wasm_bindgen_test]
fn numbers_are_read_as_f64_from_str_reads_them() {
    // In the browser the rounding is JavaScript's Number: check it against
    // Rust's own reading, compiled into this test.
    for s in NUMBERS {
        let (got, want) = (omnee_wasm::phase::number(s), s.parse::<f64>().ok());
        assert!(same_number(got, want), "{s:?}: {got:?} vs {want:?}");
    }
}

#[wasm_bindgen(inline_js = "
export function message(e) { return e instanceof Error ? e.message : ''; }
export function get(o, key) { return typeof o[key] === 'number' ? o[key] : NaN; }
export function refused(demo, name) {
  try { demo.estimate(name); } catch (e) { return e instanceof Error ? e.message : 'not an Error'; }
  try { demo.cloud(name, 10, 1); } catch (e) { return e instanceof Error ? e.message : 'not an Error'; }
  return '';
}
export function numbers(a) {
  if (!(a instanceof Float32Array || a instanceof Float64Array)) throw new Error('not a typed array');
  return Float64Array.from(a);
}")]
extern "C" {
    /// The message of a thrown JavaScript `Error` (empty for anything else).
    fn message(e: &wasm_bindgen::JsValue) -> String;

    /// The message of the `Error` that `demo.estimate(name)` and
    /// `demo.cloud(name, …)` throw (empty if neither does).
    fn refused(demo: &wasm_bindgen::JsValue, name: &str) -> String;

    /// The number `o[key]` of a result object (NaN if it is missing or not a
    /// number).
    fn get(o: &wasm_bindgen::JsValue, key: &str) -> f64;

    /// The numbers of a `Float32Array` or `Float64Array` result (throws for
    /// anything else).
    fn numbers(a: &wasm_bindgen::JsValue) -> Vec<f64>;
}

#[wasm_bindgen_test]
fn errors_are_javascript_errors_with_the_cores_message() {
    // (spec, x2, sigma_s): out of range, degenerate, not finite, syntax.
    let cases: [(&str, [f64; 2], f64); 6] = [
        ("hg:1.5", [1.0, 0.0], 0.1),
        ("hg:0.5", [0.0, 0.0], 0.1),
        ("hg:0.5", [f64::NAN, 0.0], 0.1),
        ("bogus", [1.0, 0.0], 0.1),
        ("tthg:0.9,x,0.5", [1.0, 0.0], 0.1),
        ("iso", [1.0, 0.0], -0.25),
    ];
    for (spec, x2, sigma_s) in cases {
        let thrown = Demo::new(spec, 0.0, 0.0, x2[0], x2[1], sigma_s, 0.1, PI, 1.0, None)
            .map(|_| ())
            .unwrap_err();
        let native =
            omnee_wasm::demo::Problem::new(spec, [0.0; 2], x2, sigma_s, 0.1, PI, None, 1.0)
                .map(|_| ())
                .unwrap_err()
                .to_string();
        assert_eq!(message(&thrown), native, "{spec} {x2:?} {sigma_s}");
    }
}

#[wasm_bindgen_test]
fn techniques_are_the_demos_names_and_other_strings_are_refused() {
    for t in TECHNIQUES {
        let name = t.technique().expect("a technique").name();
        assert_eq!(
            wasm_bindgen::JsValue::from(t).as_string().as_deref(),
            Some(name)
        );
    }
    let plain = demo("iso", [0.0, 0.0], [1.0, 0.0], (0.1, 0.1, PI));
    let tilted = Demo::new("iso", 0.0, 0.0, 1.0, 0.0, 0.1, 0.1, PI, 1.0, Some(1.0)).expect("lobe");
    let (plain, tilted) = (
        wasm_bindgen::JsValue::from(plain),
        wasm_bindgen::JsValue::from(tilted),
    );
    for name in ["omnee", "equiangular", "mis", "lobe", "lobe-mis"] {
        assert_eq!(refused(&tilted, name), "", "{name}");
    }
    for name in ["omnee", "equiangular", "mis"] {
        assert_eq!(refused(&plain, name), "", "{name}");
    }
    for name in ["lobe", "lobe-mis"] {
        assert_eq!(
            refused(&plain, name),
            "syntax error in technique: lobe and lobe-mis need a lobe at x0 (a tilt)",
            "{name:?}"
        );
    }
    for name in ["distance", "OMNEE", "", "0", "lobemis"] {
        assert_eq!(
            refused(&tilted, name),
            "syntax error in technique: unknown name; allowed: omnee, equiangular, mis, lobe, lobe-mis",
            "{name:?}"
        );
    }
}

#[wasm_bindgen_test]
fn extreme_scales_give_finite_numbers_or_an_error_naming_the_field() {
    // s = 1e-30 with σ scaled: the transfer 3e59, finite estimates.
    let s = 1e-30;
    let mut d = demo("hg:0.5", [0.0, 0.0], [s, 0.0], (0.5 / s, 0.05 / s, PI));
    d.run(2000.0).unwrap();
    for t in [Technique::Omnee, Technique::Mis] {
        let e = d.estimate(t).unwrap();
        let (mean, err, rel) = (
            get(&e, "mean"),
            get(&e, "stdError"),
            get(&e, "relativeError"),
        );
        assert!(
            mean > 1e59 && err.is_finite() && rel < 0.1,
            "{mean} {err} {rel}"
        );
    }
    // s = 1e-300 with σs = 5e299: the transfer 1e600, an Error naming the
    // reference, no NaN in it.
    let thrown = Demo::new("iso", 0.0, 0.0, 1e-300, 0.0, 5e299, 5e298, PI, 1.0, None)
        .map(|_| ())
        .unwrap_err();
    let m = message(&thrown);
    assert!(m.starts_with("reference: ") && !m.contains("NaN"), "{m}");
    // Points 1.6e308 apart: the transfer underflows to 0, estimates 0.
    let mut d = demo("iso", [-8e307, 0.0], [8e307, 0.0], (0.5, 0.05, PI));
    d.run(100.0).unwrap();
    let e = d.estimate(Technique::Mis).unwrap();
    assert_eq!((get(&e, "mean"), get(&e, "stdError")), (0.0, 0.0));
    // A difference beyond f64: an Error.
    let thrown = Demo::new("iso", -1e308, 0.0, 1e308, 0.0, 0.5, 0.05, PI, 1.0, None)
        .map(|_| ())
        .unwrap_err();
    assert!(
        message(&thrown).starts_with("x2 - x0"),
        "{}",
        message(&thrown)
    );
}
