//! Helpers shared by the harness-less benchmark binaries (`time_vs_error`,
//! `slab_time_vs_error`, `stress`): seeds, argument parsing, output paths,
//! the phase functions and techniques they compare, the measured
//! time-against-error curves ([`curve`]) and their log-log figures
//! ([`loglog`]).
#![allow(dead_code)] // each bench binary uses a different subset

pub mod curve;
pub mod loglog;

use omnee::Real;
use omnee::method::Method;
use omnee::phase::{Phase, Spec};
use omnee::rng::mix;
use plotters::style::RGBColor;
use std::path::PathBuf;

/// The phase functions the benchmarks compare, in the spec syntax: HG from
/// isotropic to strongly forward, a two-term HG with a backward lobe, an
/// ocean Fournier–Forand and a cloud-droplet Mie.
pub const BENCH_PHASES: [&str; 7] = [
    "hg:0",
    "hg:0.5",
    "hg:0.9",
    "hg:0.98",
    "tthg:0.99,-0.44,0.96",
    "ff:0.0183,1.10",
    "mie:10",
];

/// The techniques' names, in the order of [`Method::ALL`] (tables, plots,
/// the renderer's `--technique`).
pub const NAMES: [&str; 4] = [
    Method::ALL[0].name(),
    Method::ALL[1].name(),
    Method::ALL[2].name(),
    Method::ALL[3].name(),
];

/// The plot colour of each technique, in the order of [`Method::ALL`]
/// (Okabe–Ito: blue, vermillion, bluish green, reddish purple).
pub const COLORS: [RGBColor; 4] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
];

/// The single techniques (not MIS), for "best single technique" columns.
pub fn single(method: Method) -> bool {
    method != Method::Mis
}

/// The analytic phase function of `spec` in precision `F` (panics on an
/// invalid spec or a table: the benches' specs are constants).
pub fn phase<F: Real>(spec: &str) -> Phase<'static, F> {
    match Spec::<F>::parse(spec).expect("valid spec") {
        Spec::Analytic(p) => p,
        Spec::Table { .. } => panic!("{spec}: a table, not an analytic phase function"),
    }
}

/// `spec` with every parameter rounded to f32 (`hg:0.9` → `hg:0.8999999761581421`),
/// so that an f64 instance has exactly the parameters of the f32 one.
pub fn rounded_to_f32(spec: &str) -> String {
    match spec.split_once(':') {
        None => spec.to_string(),
        Some((name, args)) => {
            let args: Vec<String> = args
                .split(',')
                .map(|a| ((a.parse::<f64>().expect("number") as f32) as f64).to_string())
                .collect();
            format!("{name}:{}", args.join(","))
        }
    }
}

/// One seed from several integers: each hashed into the running value with
/// the SplitMix64 finaliser [`mix`], so distinct tuples give unrelated
/// seeds (for `SplitMix64::new`).
pub fn seed(parts: &[u64]) -> u64 {
    parts
        .iter()
        .fold(0x243f_6a88_85a3_08d3, |h, &p| mix(h ^ mix(p)))
}

/// The value of `--name VALUE` on the command line (cargo bench passes
/// `--bench` and filters too; everything unknown is ignored).
pub fn arg<T: std::str::FromStr>(name: &str, default: T) -> T {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Whether `--name` is on the command line.
pub fn flag(name: &str) -> bool {
    std::env::args().any(|a| a == name)
}

/// `docs/<rest>` in the workspace, created if missing.
pub fn docs_path(rest: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join(rest);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).expect("create docs directory");
    }
    path
}

/// The median of a non-empty slice (sorted in place; NaN sorts last).
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// A number in three significant digits, scientific outside [1e-3, 1e4).
pub fn fmt3(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&a) {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

/// [`fmt3`] of a value that may not exist: `–` for `None` (a table says why).
pub fn fmt_opt(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), fmt3)
}

/// `a / b` where both exist.
pub fn ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    Some(a? / b?)
}

/// The best efficiency among the single techniques other than `Method::ALL[i]`
/// (`eff` in the order of [`Method::ALL`]; those without one left out).
pub fn best_other_single(eff: &[Option<f64>], i: usize) -> Option<f64> {
    Method::ALL
        .iter()
        .zip(eff)
        .enumerate()
        .filter(|&(j, (&m, _))| j != i && single(m))
        .filter_map(|(_, (_, &e))| e)
        .reduce(f64::max)
}
