//! The `std` feature's cost: OMNEE and equiangular samples (Henyey–Greenstein
//! g = 0.9, f32 and f64) with the core's math from `libm` (the default) or
//! from the platform (`--features std`). Build and run it both ways:
//!
//! ```sh
//! cargo bench --bench std_math                    # libm
//! cargo bench --bench std_math --features std     # the platform's math
//! ```
//!
//! It prints the thread's CPU nanoseconds per sample (CPU time: the machine
//! may be shared), the best of `--rounds` (default 5) rounds of `--samples`
//! (default 10⁷) samples each; `--only "omnee f32"` runs one case. With
//! `--samples 100000 --rounds 1 --only …` under `valgrind --tool=callgrind`
//! the instruction counts of the two builds compare without any timing
//! noise. The measured numbers are in the root `Cargo.toml` and `README.md`
//! (Feature flags).

mod common;

use common::{arg, phase, seed};
use cpu_time::ThreadTime;
use glam::{DVec3, Vec3};
use omnee::medium::Region;
use omnee::phase::Phase;
use omnee::rng::SplitMix64;
use omnee::sampling::{Connection, Directions, Equiangular, Omnee, Technique, uniform};
use omnee::{Real, Vector};
use std::hint::black_box;

/// CPU nanoseconds per sample of `technique` over `n` samples (the best of
/// `rounds`), and the sum of the weights (so nothing is optimised away).
fn time<F: Real>(technique: &dyn Technique<F>, n: u64, rounds: u32) -> (f64, f64) {
    let mut best = f64::INFINITY;
    let mut sum = 0.0;
    for round in 0..rounds {
        let mut rng = SplitMix64::new(seed(&[round.into()]));
        let start = ThreadTime::now();
        sum = 0.0;
        for _ in 0..n {
            let u = [uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)];
            if let Some(s) = technique.sample(black_box(u)) {
                sum += s.weight.to_f64();
            }
        }
        best = best.min(start.elapsed().as_secs_f64() * 1e9 / n as f64);
    }
    (best, sum)
}

/// OMNEE and equiangular sampling over the whole range θ < π, s = 1.
fn run<F: Real>(x2: F::Vec3, precision: &str, n: u64, rounds: u32, only: &str) {
    let connection = Connection::new(F::Vec3::new(F::ZERO, F::ZERO, F::ZERO), x2, F::PI).unwrap();
    let hg: Phase<'static, F> = phase("hg:0.9");
    let omnee = Omnee::new(connection, &hg);
    let equiangular = Equiangular::new(connection, &hg, Directions::Sphere, Region::Everywhere);
    for (name, technique) in [
        ("omnee", &omnee as &dyn Technique<F>),
        ("equiangular", &equiangular),
    ] {
        if !format!("{name} {precision}").contains(only) {
            continue;
        }
        let (ns, sum) = time(technique, n, rounds);
        println!("{name:>11} {precision} hg:0.9: {ns:6.1} ns/sample (weights {sum:.6e})");
    }
}

fn main() {
    let n: u64 = arg("--samples", 10_000_000);
    let rounds: u32 = arg("--rounds", 5);
    let only: String = arg("--only", String::new());
    let math = if cfg!(feature = "std") { "std" } else { "libm" };
    println!("math from {math}, best of {rounds} rounds of {n} samples, thread CPU time");
    run::<f32>(Vec3::Z, "f32", n, rounds, &only);
    run::<f64>(DVec3::Z, "f64", n, rounds, &only);
}
