//! Bridges of k scattering vertices (docs/math.md §14): cost per bridge
//! against k, variance against k at equal samples, the one-vertex
//! comparison with OMNEE, the two-vertex comparison with a variant without
//! scaling, the sampled number of vertices, and a stress run (no NaN or
//! infinity at extreme inputs).
//!
//! Criterion benchmarks (CPU time of the thread per iteration of [`BATCH`]
//! bridges, from
//! a pool of [`POOL`] pseudo-random inputs so that no branch learns them):
//!
//! - `bridge/<f32|f64>/k<k>/hg0.9`: `Bridge::sample` and `Bridge::estimate`
//!   for `s = 1`, σs = σt = 1;
//! - `one/f32/<omnee|bridge|mis>/hg0.9`: one vertex by OMNEE (θmax = π), by
//!   the bridge, and by their balance-heuristic one-sample MIS
//!   (`mis::OneSample`, probabilities ½, ½), each with its estimate;
//! - `count/f32`: `VertexCount::sample`; `isotropic/k<k>`: the closed form.
//!
//! Then, unless `BRIDGE_TABLES=0`, the tables of docs/benchmarks.md §8 are
//! printed as Markdown: relative variance `Var/mean²` of one bridge's
//! estimate of `I_k` against k, one and two vertices against the
//! alternatives (with ns per estimate measured in the same loop), the
//! sampled k, and the stress counts.
//!
//! Run: `cargo bench --bench bridge` (about 3 minutes of criterion, then
//! about a minute of tables); `BRIDGE_TABLES=0 cargo bench --bench bridge --
//! 'bridge/'` for the costs alone.

use cpu_time::ThreadTime;
use criterion::{Bencher, BenchmarkId, Criterion, Throughput};
use glam::{DVec3, Vec3};
use omnee::bridge::{Bridge, MAX_VERTICES, REFERENCE_BUDGET, VertexCount, isotropic_transfer};
use omnee::lobe::{LobeMis, PhaseLobe};
use omnee::medium::Homogeneous;
use omnee::mis::{Heuristic, OneSample};
use omnee::phase::{HenyeyGreenstein, PhaseFunction};
use omnee::reference::PointToPoint;
use omnee::rng::SplitMix64;
use omnee::sampling::{Connection, Omnee, Technique, uniform};
use omnee::{Real, Vector};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Times `routine` in CPU time of the benchmark thread
/// (`CLOCK_THREAD_CPUTIME_ID`), as the other benchmarks do: the machine is
/// shared, and wall time would charge a descheduled thread for others' work.
fn cpu<R>(b: &mut Bencher, mut routine: impl FnMut() -> R) {
    b.iter_custom(|iterations| {
        let start = ThreadTime::now();
        for _ in 0..iterations {
            black_box(routine());
        }
        start.elapsed()
    })
}

/// Bridges per criterion iteration.
const BATCH: usize = 256;
/// Pseudo-random inputs per pool (each iteration takes the next batch).
const POOL: usize = 256 * BATCH;

/// A pool of `POOL` rows of `3 · MAX_VERTICES` uniform numbers.
fn pool<F: Real>(seed: u64) -> Vec<[[F; 3]; MAX_VERTICES]> {
    let mut rng = SplitMix64::new(seed);
    (0..POOL)
        .map(|_| [[0; 3]; MAX_VERTICES].map(|r| r.map(|_: i32| uniform(&mut rng))))
        .collect()
}

/// Cycles through a pool batch by batch.
struct Cycle<T> {
    items: Vec<T>,
    at: usize,
}

impl<T> Cycle<T> {
    fn next(&mut self) -> &[T] {
        let start = self.at;
        self.at = (self.at + BATCH) % self.items.len();
        &self.items[start..start + BATCH]
    }
}

fn cost<F: Real>(c: &mut Criterion, name: &str, ks: &[usize]) {
    let x2 = F::Vec3::new(F::ZERO, F::ZERO, F::ONE);
    let hg = HenyeyGreenstein::new(F::from_f64(0.9)).unwrap();
    let origin = F::Vec3::new(F::ZERO, F::ZERO, F::ZERO);
    let bridge = Bridge::new(origin, x2, hg).unwrap();
    let medium = Homogeneous::from_extinction(F::ONE, F::ONE).unwrap();
    let mut group = c.benchmark_group(format!("bridge/{name}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    for &k in ks {
        let mut inputs = Cycle {
            items: pool::<F>(k as u64),
            at: 0,
        };
        group.bench_function(BenchmarkId::new(format!("k{k}"), "hg0.9"), |b| {
            cpu(b, || {
                let mut acc = F::ZERO;
                let mut x = [origin; MAX_VERTICES];
                for u in inputs.next() {
                    if let Some(s) = bridge.sample(black_box(&u[..k]), &mut x) {
                        acc += bridge.estimate(&s, &medium) + x[0].x();
                    }
                }
                acc
            })
        });
    }
    group.finish();
}

fn one_vertex(c: &mut Criterion) {
    let (x0, x2) = (Vec3::ZERO, Vec3::Z);
    let hg = HenyeyGreenstein::new(0.9f32).unwrap();
    let connection = Connection::new(x0, x2, std::f32::consts::PI).unwrap();
    let problem = PointToPoint::new(
        connection,
        Homogeneous::from_extinction(1.0, 1.0).unwrap(),
        None,
    )
    .unwrap();
    let omnee = Omnee::new(connection, hg);
    let bridge = Bridge::new(x0, x2, hg).unwrap();
    let mis = OneSample::new([&omnee, &bridge], [0.5, 0.5], Heuristic::Balance).unwrap();
    let techniques: [(&str, &dyn Technique<f32>); 3] =
        [("omnee", &omnee), ("bridge", &bridge), ("mis", &mis)];
    let mut group = c.benchmark_group("one/f32");
    group.throughput(Throughput::Elements(BATCH as u64));
    for (name, t) in techniques {
        let mut inputs = Cycle {
            items: pool::<f32>(7),
            at: 0,
        };
        group.bench_function(BenchmarkId::new(name, "hg0.9"), |b| {
            cpu(b, || {
                let mut acc = 0.0f32;
                for u in inputs.next() {
                    if let Some(s) = t.sample(black_box(u[0])) {
                        acc += problem.estimate(&s);
                    }
                }
                acc
            })
        });
    }
    group.finish();
    let count = VertexCount::<f32>::new(8, 1.0, 1.0, 1.0, 0.9).unwrap();
    let mut inputs = Cycle {
        items: pool::<f32>(8),
        at: 0,
    };
    let mut group = c.benchmark_group("count");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function("f32", |b| {
        cpu(b, || {
            inputs
                .next()
                .iter()
                .map(|u| count.sample(black_box(u[0][0])).0)
                .sum::<usize>()
        })
    });
    group.finish();
    let mut group = c.benchmark_group("isotropic");
    for k in [1, 8] {
        group.bench_function(format!("k{k}"), |b| {
            cpu(b, || {
                isotropic_transfer(black_box(k), 1.0, 1.0, 1.0, REFERENCE_BUDGET)
            })
        });
    }
    group.finish();
}

/// Mean, relative variance `Var/mean²` and wall ns per draw of `n` draws.
fn stats(n: usize, mut draw: impl FnMut() -> f64) -> (f64, f64, f64) {
    let start = Instant::now();
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let x = draw();
        sum += x;
        sum2 += x * x;
    }
    let ns = start.elapsed().as_nanos() as f64 / n as f64;
    let mean = sum / n as f64;
    (mean, (sum2 / n as f64 - mean * mean) / (mean * mean), ns)
}

/// One f64 bridge estimate of `I_k`.
fn bridge_draw<P: PhaseFunction<f64>>(
    bridge: &Bridge<f64, P>,
    medium: &Homogeneous<f64>,
    k: usize,
    rng: &mut SplitMix64,
) -> f64 {
    let mut u = [[0.0; 3]; MAX_VERTICES];
    for ui in u[..k].iter_mut() {
        *ui = [uniform(rng), uniform(rng), uniform(rng)];
    }
    let mut x = [DVec3::ZERO; MAX_VERTICES];
    bridge
        .sample(&u[..k], &mut x)
        .map_or(0.0, |s| bridge.estimate(&s, medium))
}

const GS: [f64; 4] = [0.0, 0.5, 0.9, 0.98];
const TAUS: [f64; 3] = [0.1, 1.0, 10.0];

fn variance_against_k(n: usize) {
    println!(
        "\n### Relative variance of one bridge's estimate of I_k (N = {n}, s = 1, albedo 1)\n"
    );
    println!("| g | σt·s | k=1 | k=2 | k=3 | k=4 | k=5 | k=6 | k=7 | k=8 |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut rng = SplitMix64::new(1);
    let mut worst_z: f64 = 0.0;
    for g in GS {
        let bridge = Bridge::new(DVec3::ZERO, DVec3::Z, HenyeyGreenstein::new(g).unwrap()).unwrap();
        for tau in TAUS {
            let medium = Homogeneous::from_extinction(tau, tau).unwrap();
            let mut row = format!("| {g} | {tau} |");
            for k in 1..=8 {
                let (mean, relvar, _) = stats(n, || bridge_draw(&bridge, &medium, k, &mut rng));
                row += &format!(" {relvar:.3} |");
                if g == 0.0 {
                    let exact = isotropic_transfer(k, 1.0, tau, tau, REFERENCE_BUDGET).unwrap();
                    let z = (mean - exact) / (mean * (relvar / n as f64).sqrt());
                    worst_z = worst_z.max(z.abs());
                }
            }
            println!("{row}");
        }
    }
    println!("\nIsotropic rows against the closed form: largest |z| = {worst_z:.2} over 24 means.");
}

fn one_and_two_vertices(n: usize) {
    println!("\n### One vertex: OMNEE (θmax = π), the bridge, and their MIS (N = {n}, f64)\n");
    println!(
        "| g | σt·s | OMNEE relvar | bridge relvar | MIS relvar | OMNEE ns | bridge ns | MIS ns |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut rng = SplitMix64::new(2);
    for g in GS {
        let hg = HenyeyGreenstein::new(g).unwrap();
        for tau in TAUS {
            let c = Connection::new(DVec3::ZERO, DVec3::Z, PI).unwrap();
            let problem =
                PointToPoint::new(c, Homogeneous::from_extinction(tau, tau).unwrap(), None)
                    .unwrap();
            let omnee = Omnee::new(c, hg);
            let bridge = Bridge::new(DVec3::ZERO, DVec3::Z, hg).unwrap();
            let mis = OneSample::new([&omnee, &bridge], [0.5, 0.5], Heuristic::Balance).unwrap();
            let mut run = |t: &dyn Technique<f64>| {
                stats(n, || {
                    let u = [uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)];
                    t.sample(u).map_or(0.0, |s| problem.estimate(&s))
                })
            };
            let (o, b, m) = (run(&omnee), run(&bridge), run(&mis));
            println!(
                "| {g} | {tau} | {:.3} | {:.3} | {:.3} | {:.0} | {:.0} | {:.0} |",
                o.1, b.1, m.1, o.2, b.2, m.2
            );
        }
    }
    println!(
        "\n### Two vertices: the bridge against OMNEE + the lobe module (no scaling), N = {n}\n"
    );
    println!("| g | σt·s | bridge relvar | OMNEE+lobe relvar | bridge ns | OMNEE+lobe ns |");
    println!("|---|---|---|---|---|---|");
    for g in GS {
        let hg = HenyeyGreenstein::new(g).unwrap();
        for tau in TAUS {
            let medium = Homogeneous::from_extinction(tau, tau).unwrap();
            let bridge = Bridge::new(DVec3::ZERO, DVec3::Z, hg).unwrap();
            let b = stats(n, || bridge_draw(&bridge, &medium, 2, &mut rng));
            let o = stats(n, || omnee_then_lobe(&hg, &medium, &mut rng));
            println!(
                "| {g} | {tau} | {:.3} | {:.3} | {:.0} | {:.0} |",
                b.1, o.1, b.2, o.2
            );
        }
    }
}

/// `I_2` without scaling: the first vertex by OMNEE between `x0 = 0` and
/// `x2 = z`, the second by the lobe module's MIS with the phase function
/// about the incoming direction (the suite's independent estimator).
fn omnee_then_lobe(
    hg: &HenyeyGreenstein<f64>,
    medium: &Homogeneous<f64>,
    rng: &mut SplitMix64,
) -> f64 {
    let mut u3 = || [uniform(rng), uniform(rng), uniform(rng)];
    let outer = Connection::new(DVec3::ZERO, DVec3::Z, PI).unwrap();
    let Some(a) = Omnee::new(outer, *hg).sample(u3()) else {
        return 0.0;
    };
    let Some((theta, d1, d_a2)) = outer.deflection(a.x1) else {
        return 0.0;
    };
    let Ok(inner) = Connection::new(a.x1, DVec3::Z, PI) else {
        return 0.0;
    };
    let Ok(lobe) = PhaseLobe::new(*hg, a.x1 / d1) else {
        return 0.0;
    };
    let Some(b) = LobeMis::recommended(inner, lobe, *hg).sample(u3()) else {
        return 0.0;
    };
    let length = d1 + (b.x1 - a.x1).length() + (DVec3::Z - b.x1).length();
    medium.sigma_s().powi(2) * (-medium.sigma_t() * length).exp() * a.weight * d_a2 * d_a2
        / hg.eval(theta)
        * b.weight
}

fn sampled_k(n: usize) {
    println!("\n### Σ_(k=1..8) I_k by a sampled k (N = {n}, f64, s = 1, albedo 0.95)\n");
    println!(
        "| g | σt·s | μ | relvar, VertexCount | relvar, uniform k | relvar, 8 bridges (one per k) / 8 |"
    );
    println!("|---|---|---|---|---|---|");
    let mut rng = SplitMix64::new(3);
    for g in GS {
        let bridge = Bridge::new(DVec3::ZERO, DVec3::Z, HenyeyGreenstein::new(g).unwrap()).unwrap();
        for tau in TAUS {
            let medium = Homogeneous::from_extinction(0.95 * tau, tau).unwrap();
            let count = VertexCount::<f64>::new(8, 1.0, 0.95 * tau, tau, g).unwrap();
            let uniform_k = VertexCount::<f64>::with_mean(8, 1.0, 1.0).unwrap();
            let mut run = |c: &VertexCount<f64>| {
                stats(n, || {
                    let (k, p) = c.sample(uniform(&mut rng));
                    bridge_draw(&bridge, &medium, k, &mut rng) / p
                })
            };
            let (a, b) = (run(&count), run(&uniform_k));
            // All eight orders per draw costs 8 bridges: its relvar × 8 is
            // the equal-bridge-count comparison.
            let all = stats(n / 8, || {
                (1..=8)
                    .map(|k| bridge_draw(&bridge, &medium, k, &mut rng))
                    .sum()
            });
            println!(
                "| {g} | {tau} | {:.3} | {:.3} | {:.3} | {:.3} |",
                count.mean(),
                a.1,
                b.1,
                all.1 * 8.0
            );
        }
    }
}

fn stress() {
    println!("\n### Stress (f32): bridges at extreme inputs\n");
    println!("| s | g | k | draws | no path | non-finite outputs | negative outputs |");
    println!("|---|---|---|---|---|---|---|");
    let extremes = [
        0.0f32,
        1e-30,
        1e-7,
        0.5,
        1.0 - 1e-7,
        1.0 - f32::EPSILON / 2.0,
    ];
    let mut rng = SplitMix64::new(4);
    for s in [1e-6f32, 1.0, 1e6] {
        for g in [0.0f32, 0.9999, -0.9999] {
            let bridge = Bridge::new(
                Vec3::ZERO,
                Vec3::new(0.0, 0.6 * s, 0.8 * s),
                HenyeyGreenstein::new(g).unwrap(),
            )
            .unwrap();
            let media = [
                (0.0f32, 0.0f32),
                (1e-6 / s, 1e-6 / s),
                (1.0 / s, 1.0 / s),
                (1e3 / s, 1e3 / s),
            ];
            for k in [1, 8, MAX_VERTICES] {
                let (mut draws, mut none, mut bad, mut negative) = (0, 0, 0, 0);
                for trial in 0..20_000 {
                    let mut u = [[0.0f32; 3]; MAX_VERTICES];
                    for ui in u[..k].iter_mut() {
                        *ui = if trial % 2 == 0 {
                            [0, 1, 2].map(|_| extremes[(rng.next_u64() % 6) as usize])
                        } else {
                            [uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)]
                        };
                    }
                    let mut x = [Vec3::ZERO; MAX_VERTICES];
                    draws += 1;
                    let Some(b) = bridge.sample(&u[..k], &mut x) else {
                        none += 1;
                        continue;
                    };
                    let (sigma_s, sigma_t) = media[trial % 4];
                    let medium = Homogeneous::from_extinction(sigma_s, sigma_t).unwrap();
                    let outputs = [
                        b.pdf,
                        b.weight,
                        b.length,
                        bridge.estimate(&b, &medium),
                        bridge.pdf(&x[..k]),
                        bridge.kernel(&x[..k]),
                    ];
                    if outputs.iter().any(|v| !v.is_finite())
                        || x[..k].iter().any(|v| !v.is_finite())
                    {
                        bad += 1;
                    }
                    if outputs.iter().any(|&v| v < 0.0) {
                        negative += 1;
                    }
                }
                println!("| {s:e} | {g} | {k} | {draws} | {none} | {bad} | {negative} |");
            }
        }
    }
}

fn main() {
    // The command line's settings (a filter, --measurement-time, ...) over
    // these defaults.
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30)
        .configure_from_args();
    cost::<f32>(&mut c, "f32", &[1, 2, 3, 4, 5, 6, 7, 8]);
    cost::<f64>(&mut c, "f64", &[1, 2, 4, 8]);
    one_vertex(&mut c);
    c.final_summary();
    if std::env::var("BRIDGE_TABLES").as_deref() == Ok("0") {
        return;
    }
    variance_against_k(400_000);
    one_and_two_vertices(400_000);
    sampled_k(400_000);
    stress();
}
