//! Helpers shared by the harness-less benchmark binaries (`time_vs_error`,
//! `slab_time_vs_error`, `stress`): a small seeded generator, argument
//! parsing, output paths, and the log-log figures ([`loglog`]).
#![allow(dead_code)] // each bench binary uses a different subset

pub mod loglog;

use std::path::PathBuf;

/// SplitMix64 (Steele, Lea, Flood 2014): a fast, seedable 64-bit generator,
/// plenty for Monte Carlo error measurements (not for the statistics tests).
#[derive(Clone, Debug)]
pub struct SplitMix(pub u64);

impl SplitMix {
    /// A generator whose stream is decorrelated from its neighbours' by
    /// hashing the seed once.
    pub fn new(seed: u64) -> Self {
        let mut g = SplitMix(seed ^ 0x6a09_e667_f3bc_c909);
        g.next_u64();
        g
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform f32 in `[0, 1)` from the top 24 bits.
    #[inline]
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// A uniform f64 in `[0, 1)` from the top 53 bits.
    #[inline]
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Mixes several integers into one seed.
pub fn seed(parts: &[u64]) -> u64 {
    let mut g = SplitMix(0x243f_6a88_85a3_08d3);
    for &p in parts {
        g.0 ^= p;
        g.next_u64();
    }
    g.next_u64()
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
