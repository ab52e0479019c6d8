//! Cost of one sample: nanoseconds per `sample` and per `pdf` for every
//! technique and phase function, in f32 and f64, and the cost of one
//! once-more connection of the slab renderer per technique.
//!
//! What is measured, per criterion benchmark:
//!
//! - `sample/<f32|f64>/<technique>/<phase>`: a batch of [`BATCH`] uniform
//!   triples through `Technique::sample(u)`, which returns `x1` with its
//!   density and weight: what a renderer pays per vertex. Time per
//!   iteration / `BATCH` is the cost of one sample. Each iteration takes the
//!   next batch from a fixed pseudo-random pool of [`POOL`] triples, so that
//!   no branch sees a sequence short enough to be learnt (see [`POOL`]).
//! - `pdf/<f32|f64>/<technique>/<phase>`: `Technique::pdf(x1)` at the same
//!   batch's vertices (precomputed), what MIS pays for the other techniques.
//!
//!   The connection is `x0 = (0, 0, 1)`, `x2 = 0` (s = 1) in an infinite
//!   medium, θmax = π (no early rejection); equiangular and distance draw ray
//!   directions uniformly on the sphere, distance sampling uses σ = 1, and
//!   `mis` is the CLI's (`OmneeMis::recommended`: OMNEE's vertex, and with
//!   probability 0.05 an equiangular one behind 3π/4; its "sample" is that
//!   pair from six numbers, its "pdf" the combined density at OMNEE's
//!   vertices).
//! - `phase/<f32|f64>/<phase>`: the phase function alone, `sample_pdf(u)`.
//! - `connection/f32/omnee-hg0.9`: a fresh connection per sample
//!   (`Connection::new` for a moving `x0`, then an OMNEE sample), the cost a
//!   renderer pays when every camera vertex connects to a new light point.
//! - `batch/f32/omnee/<hg>`: `Omnee::sample_batch`, the structure-of-arrays
//!   entry point, on the batch's triples (compare `sample/f32/omnee/<hg>`).
//! - `batch/f32/omnee-one/hg0.9`, `draw/f32/mis-{lazy,six}/hg0.9`,
//!   `pdf/f32/equiangular-at-{point,vertex}/hg0.9`: a batch of one vertex,
//!   `OmneeMis`'s lazy draw and the density at a vertex with its offsets
//!   (see `one_vertex_and_companion` below).
//! - `connections_<f32|f64>/<technique>/<phase>`: `Connections`, the batch
//!   over connections: the same 256 uniform triples per iteration as
//!   `sample/*`, each lane with a connection of its own (end points from a
//!   pool of 2¹⁶ pairs, θmax = π), one call per iteration; `omnee` through
//!   `sample_omnee`, `mis` through `sample_mis` (the CLI's MIS, the six
//!   numbers of `sample/*/mis`), and `omnee-scalar`, the scalar calls it
//!   replaces (`Connection::new` and `Omnee::sample` per lane). Compare
//!   with `sample/<precision>/omnee/<phase>` (one fixed connection, scalar)
//!   and `batch/f32/omnee/<phase>` (one connection, vectorised).
//! - `slab/<technique>`: one call of `SlabWorld::once_more` on
//!   the default scene (`omnee default-scene`) for 256 floor points: a light
//!   point, the connection, the technique's vertex, closed-form
//!   transmittance on both legs and the occluder tests.
//!
//! Time is the benchmark thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`, the
//! [`CpuTime`] measurement below), not wall time: the machine is shared, and
//! a descheduled thread would otherwise be charged for other processes.
//!
//! Run: `cargo bench --bench samplers` (about 10 minutes; every benchmark has
//! 1 s warm-up, 2 s measurement and 30 samples, set below). A filter narrows
//! it, e.g. `cargo bench --bench samplers -- 'sample/f32/.*/hg'`.
//! `benches/summarize.py` turns criterion's estimates into the ns/sample
//! tables of `docs/benchmarks.md`.

use cpu_time::ThreadTime;
use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use omnee::medium::Region;
use omnee::mis::OmneeMis;
use omnee::phase::{
    Deflection, Draine, FournierForand, HenyeyGreenstein, InverseCdf, Isotropic, Mie,
    PhaseFunction, Rayleigh, TableSampled, Tabulated, TwoTermHg,
};
use omnee::sampling::{Connection, Directions, Distance, Equiangular, Omnee, Technique};
use omnee::{Real, Vector};
use std::hint::black_box;
use std::time::Duration;

/// Criterion measurement: the CPU time of the benchmark thread, in ns.
struct CpuTime;

impl Measurement for CpuTime {
    type Intermediate = ThreadTime;
    type Value = Duration;
    fn start(&self) -> ThreadTime {
        ThreadTime::now()
    }
    fn end(&self, i: ThreadTime) -> Duration {
        i.elapsed()
    }
    fn add(&self, v1: &Duration, v2: &Duration) -> Duration {
        *v1 + *v2
    }
    fn zero(&self) -> Duration {
        Duration::ZERO
    }
    fn to_f64(&self, value: &Duration) -> f64 {
        value.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

/// Formats CPU nanoseconds as ns/µs/ms and throughput as elements per
/// CPU second.
struct CpuFormatter;

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, ns: f64, values: &mut [f64]) -> &'static str {
        let (factor, unit) = if ns < 1e3 {
            (1.0, "ns (CPU)")
        } else if ns < 1e6 {
            (1e-3, "µs (CPU)")
        } else {
            (1e-6, "ms (CPU)")
        };
        values.iter_mut().for_each(|v| *v *= factor);
        unit
    }
    fn scale_throughputs(
        &self,
        typical: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let n = match *throughput {
            Throughput::Elements(n) => n as f64,
            _ => 1.0,
        };
        // Per second of CPU, in millions.
        let _ = typical;
        values.iter_mut().for_each(|v| *v = n * 1e3 / *v);
        "Melem/s (CPU)"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

/// SampleArrays per criterion iteration.
const BATCH: usize = 256;

/// Inputs per pool: each iteration takes the next `BATCH` of them, so an
/// input comes back only every `POOL / BATCH = 256` iterations. With a
/// single batch repeated, the branch predictor learns the 256 outcomes of
/// every branch in a sampler: libm's `sincosf` measured 3.8 ns on 4096
/// repeated angles and 15.4 ns on 2²⁰ distinct ones here, and equiangular
/// sampling 83 ns against 107 ns (a renderer never repeats its numbers).
const POOL: usize = 1 << 16;

/// A pool of inputs walked `BATCH` at a time, wrapping around.
struct Pool<T> {
    items: Vec<T>,
    at: std::cell::Cell<usize>,
}

impl<T> Pool<T> {
    fn new(items: Vec<T>) -> Self {
        assert!(items.len() % BATCH == 0 && !items.is_empty());
        Self {
            items,
            at: std::cell::Cell::new(0),
        }
    }

    /// The next `BATCH` inputs.
    fn next(&self) -> &[T] {
        let i = self.at.get();
        self.at.set((i + BATCH) % self.items.len());
        &self.items[i..i + BATCH]
    }
}

/// `POOL` uniform triples in `[0, 1)` from a fixed SplitMix64 stream.
fn uniforms<F: Real>() -> Vec<[F; 3]> {
    uniforms_n(POOL)
}

/// `n` uniform triples of the same stream.
fn uniforms_n<F: Real>(n: usize) -> Vec<[F; 3]> {
    let mut rng = omnee::rng::SplitMix64::new(omnee::rng::SplitMix64::GAMMA);
    // 24 bits so that the f32 and f64 runs see the same numbers.
    let mut next = || F::from_f64((rng.next_u64() >> 40) as f64 / (1u64 << 24) as f64);
    (0..n).map(|_| [next(), next(), next()]).collect()
}

/// Pushes the batch through `sample`, returning a checksum so nothing is
/// optimised away.
#[inline(never)]
fn run_sample<F: Real, T: Technique<F> + ?Sized>(t: &T, us: &[[F; 3]]) -> F {
    let mut acc = F::ZERO;
    for &u in us {
        if let Some(s) = t.sample(black_box(u)) {
            acc += s.weight + s.pdf + s.x1.x();
        }
    }
    acc
}

/// `pdf` at the given vertices.
#[inline(never)]
fn run_pdf<F: Real, T: Technique<F> + ?Sized>(t: &T, x1s: &[F::Vec3]) -> F {
    let mut acc = F::ZERO;
    for &x1 in x1s {
        acc += t.pdf(black_box(x1));
    }
    acc
}

/// Every technique with one phase function.
fn techniques<F: Real, P: PhaseFunction<F> + Copy>(
    c: &mut Criterion<CpuTime>,
    precision: &str,
    name: &str,
    phase: P,
) {
    let x0 = F::Vec3::new(F::ZERO, F::ZERO, F::ONE);
    let x2 = F::Vec3::new(F::ZERO, F::ZERO, F::ZERO);
    let full = Connection::new(x0, x2, F::PI).unwrap();
    let us = uniforms::<F>();

    let omnee = Omnee::new(full, phase);
    let equiangular = Equiangular::new(full, phase, Directions::Sphere, Region::Everywhere);
    let distance =
        Distance::new(full, phase, Directions::Sphere, Region::Everywhere, F::ONE).unwrap();
    let mis = OmneeMis::recommended(omnee, &equiangular);
    let all: [(&str, &dyn Technique<F>); 3] = [
        ("omnee", &omnee),
        ("equiangular", &equiangular),
        ("distance", &distance),
    ];
    // mis draws six numbers: a triple and the next one.
    let u6 = Pool::new(
        (0..POOL)
            .map(|i| {
                let (a, b) = (us[i], us[(i + 1) % POOL]);
                [a[0], a[1], a[2], b[0], b[1], b[2]]
            })
            .collect(),
    );
    let us = Pool::new(us);

    let mut group = c.benchmark_group(format!("sample/{precision}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    for (tech, t) in all {
        group.bench_function(BenchmarkId::new(tech, name), |b| {
            b.iter(|| run_sample(t, us.next()))
        });
    }
    group.bench_function(BenchmarkId::new("mis", name), |b| {
        b.iter(|| {
            let mut acc = F::ZERO;
            for &u in u6.next() {
                for s in mis.sample(black_box(u)).iter().flatten() {
                    acc += s.weight + s.pdf + s.x1.x();
                }
            }
            acc
        })
    });
    group.finish();

    let mut group = c.benchmark_group(format!("pdf/{precision}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    let vertices = |t: &dyn Technique<F>| -> Pool<F::Vec3> {
        // The first POOL vertices the technique returns (some triples give none).
        let x1s: Vec<F::Vec3> = uniforms_n::<F>(8 * POOL)
            .into_iter()
            .filter_map(|u| t.sample(u))
            .map(|s| s.x1)
            .take(POOL)
            .collect();
        assert_eq!(x1s.len(), POOL, "{name}: too few vertices");
        Pool::new(x1s)
    };
    for (tech, t) in all {
        let x1s = vertices(t);
        group.bench_function(BenchmarkId::new(tech, name), |b| {
            b.iter(|| run_pdf(t, x1s.next()))
        });
    }
    // mis's combined density at OMNEE's vertices.
    let x1s = vertices(&omnee);
    group.bench_function(BenchmarkId::new("mis", name), |b| {
        b.iter(|| {
            let mut acc = F::ZERO;
            for &x1 in x1s.next() {
                acc += mis.pdf(black_box(x1));
            }
            acc
        })
    });
    group.finish();

    let mut group = c.benchmark_group(format!("phase/{precision}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(name, |b| {
        b.iter(|| {
            let mut acc = F::ZERO;
            for u in us.next() {
                let (d, pdf) = phase.sample_pdf(black_box(u[0]));
                acc += d.theta + pdf;
            }
            acc
        })
    });
    group.finish();
}

/// A new connection per sample: `Connection::new` + OMNEE sample.
fn connection<F: Real>(c: &mut Criterion<CpuTime>, precision: &str) {
    let us = Pool::new(uniforms::<F>());
    let hg = HenyeyGreenstein::new(F::from_f64(0.9)).unwrap();
    let x2 = F::Vec3::new(F::ZERO, F::ZERO, F::ZERO);
    let mut group = c.benchmark_group(format!("connection/{precision}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function("omnee-hg0.9", |b| {
        b.iter(|| {
            let mut acc = F::ZERO;
            for u in us.next() {
                let x0 = F::Vec3::new(u[2], u[1], F::ONE);
                let Ok(conn) = Connection::new(black_box(x0), x2, F::FRAC_PI_2) else {
                    continue;
                };
                let t = Omnee::new(conn, hg);
                if let Some(s) = t.sample(*u) {
                    acc += s.weight + s.pdf;
                }
            }
            acc
        })
    });
    group.finish();
}

/// `phase` sampled through its [`InverseCdf`] (the renderer's choice for a
/// phase function without a fast exact sampler) under `name`, and its exact
/// sampler's OMNEE sample under `<name>-exact`.
fn tabled<F: Real, P: PhaseFunction<F> + Copy>(
    c: &mut Criterion<CpuTime>,
    precision: &str,
    name: &str,
    phase: P,
) {
    let table = InverseCdf::new(&phase).unwrap();
    techniques(c, precision, name, TableSampled::new(phase, &table));
    let x0 = F::Vec3::new(F::ZERO, F::ZERO, F::ONE);
    let full = Connection::new(x0, F::Vec3::new(F::ZERO, F::ZERO, F::ZERO), F::PI).unwrap();
    let omnee = Omnee::new(full, phase);
    let us = Pool::new(uniforms::<F>());
    let mut group = c.benchmark_group(format!("sample/{precision}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(BenchmarkId::new("omnee", format!("{name}-exact")), |b| {
        b.iter(|| run_sample(&omnee, us.next()))
    });
    group.finish();
}

/// A measured phase function as an instrument would give it: Fournier–Forand
/// (B = 0.0183, n = 1.10) averaged over 64 bins, 33 log-spaced from 0.1° to
/// 10° and 31 even ones to 180° (a Petzold-like table).
fn measured_table() -> (Vec<f64>, Vec<f64>) {
    let ff = FournierForand::new(0.0183, 1.10).unwrap();
    let mut edges = vec![0.0];
    edges.extend((0..33).map(|i| (0.1f64 * 100f64.powf(i as f64 / 32.0)).to_radians()));
    edges.extend((1..=31).map(|i| (10.0 + 170.0 * i as f64 / 31.0).to_radians()));
    *edges.last_mut().unwrap() = std::f64::consts::PI;
    let values = edges
        .windows(2)
        .map(|w| {
            // The bin's mass over its solid angle: a measured bin average.
            let (a, b) = (Deflection::from_theta(w[0]), Deflection::from_theta(w[1]));
            (ff.cdf(b) - ff.cdf(a)) / (b.one_minus_cos - a.one_minus_cos)
        })
        .collect();
    (edges, values)
}

fn all<F: Real>(c: &mut Criterion<CpuTime>, precision: &str) {
    let f = F::from_f64;
    techniques::<F, _>(c, precision, "iso", Isotropic);
    for g in [0.0, 0.9, 0.98] {
        let name = format!("hg{g}");
        techniques(c, precision, &name, HenyeyGreenstein::new(f(g)).unwrap());
    }
    techniques(
        c,
        precision,
        "tthg",
        TwoTermHg::two_term(f(0.99), f(-0.44), f(0.96)).unwrap(),
    );
    tabled(
        c,
        precision,
        "ff",
        FournierForand::new(f(0.0183), f(1.10)).unwrap(),
    );
    tabled(c, precision, "draine", Draine::new(f(0.6), f(1.0)).unwrap());
    tabled(c, precision, "mie10", Mie::new(f(10.0)).unwrap());
    tabled::<F, _>(c, precision, "rayleigh", Rayleigh);
    let (edges, values) = measured_table();
    let (edges, values): (Vec<F>, Vec<F>) = (
        edges.into_iter().map(f).collect(),
        values.into_iter().map(f).collect(),
    );
    let mut cdf = vec![F::ZERO; edges.len()];
    tabled(
        c,
        precision,
        "measured",
        Tabulated::new(&edges, &values, &mut cdf).unwrap(),
    );
    connection::<F>(c, precision);
}

/// One once-more connection of the slab renderer, per technique: the cost of
/// `SlabWorld::once_more` at 256 floor points of the default scene.
fn slab(c: &mut Criterion<CpuTime>) {
    use omnee::method::Method;
    use omnee_render::rng::Rng;
    use omnee_render::scenes::slab::world::{OnceMore, Roulette};
    use omnee_render::scenes::slab::{SlabScene, SlabStats, SlabWorld};
    let scene = SlabScene::default_scene();
    let mut storage = omnee_render::phase::TableStorage::<f32>::default();
    let phase = scene.medium.phase.instantiate::<f32>(&mut storage).unwrap();
    let world = SlabWorld::new(&scene, phase).unwrap();
    let points: Vec<glam::Vec3> = (0..BATCH)
        .map(|i| {
            glam::Vec3::new(
                (i % 16) as f32 * 0.05 - 0.4,
                (i / 16) as f32 * 0.05 - 0.4,
                0.0,
            )
        })
        .collect();
    let mut group = c.benchmark_group("slab");
    group.throughput(Throughput::Elements(BATCH as u64));
    for method in Method::ALL {
        let how = OnceMore {
            method,
            theta_max: std::f32::consts::PI,
        };
        let mut pass = 0u64;
        group.bench_function(method.name(), |b| {
            b.iter(|| {
                pass += 1;
                let mut stats = SlabStats::default();
                let mut acc = 0.0f32;
                for (i, &p) in points.iter().enumerate() {
                    let mut rng = Rng::stream(7, i as u64, pass);
                    acc +=
                        world.once_more(p, glam::Vec3::Z, how, &mut rng, Roulette::OFF, &mut stats);
                }
                acc
            })
        });
    }
    group.finish();
}

/// The structure-of-arrays entry point against the scalar sampler, same
/// triples: `batch/f32/omnee/<phase>` vs `sample/f32/omnee/<phase>`.
fn batch(c: &mut Criterion<CpuTime>) {
    use omnee::sampling::{Uniforms, Vertices};
    let us = uniforms::<f32>();
    let soa = |k: usize| us.iter().map(|u| u[k]).collect::<Vec<f32>>();
    let (u0, u1, u2) = (soa(0), soa(1), soa(2));
    // The same walk through the pool as the scalar benchmarks.
    let at = std::cell::Cell::new(0usize);
    let window = || {
        let i = at.get();
        at.set((i + BATCH) % POOL);
        i..i + BATCH
    };
    let full = Connection::new(glam::Vec3::Z, glam::Vec3::ZERO, std::f32::consts::PI).unwrap();
    let mut group = c.benchmark_group("batch/f32");
    group.throughput(Throughput::Elements(BATCH as u64));
    for g in [0.0f32, 0.9, 0.98] {
        let omnee = Omnee::new(full, HenyeyGreenstein::new(g).unwrap());
        let (mut x, mut y, mut z) = (vec![0.0; BATCH], vec![0.0; BATCH], vec![0.0; BATCH]);
        let (mut pdf, mut weight) = (vec![0.0; BATCH], vec![0.0; BATCH]);
        group.bench_function(BenchmarkId::new("omnee", format!("hg{g}")), |b| {
            b.iter(|| {
                let w = window();
                let n = omnee
                    .sample_batch(
                        Uniforms {
                            u0: black_box(&u0[w.clone()]),
                            u1: &u1[w.clone()],
                            u2: &u2[w],
                        },
                        Vertices {
                            x: &mut x,
                            y: &mut y,
                            z: &mut z,
                            pdf: &mut pdf,
                            weight: &mut weight,
                        },
                    )
                    .unwrap();
                n as f32 + pdf[n / 2] + weight[n / 3] + x[n / 4]
            })
        });
    }
    group.finish();
}

/// One vertex at a time and MIS's companion, f32, HG 0.9, the connection of
/// `sample/*`:
///
/// - `batch/f32/omnee-one/hg0.9`: `Omnee::sample_batch` called with one
///   vertex at a time, as a renderer that draws one vertex per connection
///   (the CLI's once-more term) would call it; against `sample/f32/omnee`.
/// - `draw/f32/mis-lazy/hg0.9`: `OmneeMis::draw`, the numbers from the
///   core's SplitMix64 and taken only when used (4 + 2c per draw), against
///   `draw/f32/mis-six/hg0.9`, six numbers drawn and `OmneeMis::sample`.
/// - `pdf/f32/equiangular-at-{point,vertex}/hg0.9`: the companion's
///   density at OMNEE's vertices from the point (`pdf(x1)`) and from the
///   vertex with its offsets (`pdf_vertex`), what `OmneeMis` evaluates.
fn one_vertex_and_companion(c: &mut Criterion<CpuTime>) {
    use omnee::rng::SplitMix64;
    use omnee::sampling::{Uniforms, Vertex, Vertices, uniform};
    let full = Connection::new(glam::Vec3::Z, glam::Vec3::ZERO, std::f32::consts::PI).unwrap();
    let hg = HenyeyGreenstein::new(0.9f32).unwrap();
    let omnee = Omnee::new(full, hg);
    let us = Pool::new(uniforms::<f32>());

    let mut group = c.benchmark_group("batch/f32");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(BenchmarkId::new("omnee-one", "hg0.9"), |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for u in us.next() {
                let (mut x, mut y, mut z, mut pdf, mut weight) =
                    ([0.0], [0.0], [0.0], [0.0], [0.0]);
                let n = omnee
                    .sample_batch(
                        Uniforms {
                            u0: black_box(&u[0..1]),
                            u1: &u[1..2],
                            u2: &u[2..3],
                        },
                        Vertices {
                            x: &mut x,
                            y: &mut y,
                            z: &mut z,
                            pdf: &mut pdf,
                            weight: &mut weight,
                        },
                    )
                    .unwrap();
                acc += n as f32 + weight[0] + pdf[0] + x[0];
            }
            acc
        })
    });
    group.finish();

    let equiangular = Equiangular::new(full, hg, Directions::Sphere, Region::Everywhere);
    let mis = OmneeMis::recommended(omnee, &equiangular);
    let mut group = c.benchmark_group("draw/f32");
    group.throughput(Throughput::Elements(BATCH as u64));
    let mut rng = SplitMix64::new(7);
    group.bench_function(BenchmarkId::new("mis-lazy", "hg0.9"), |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for _ in 0..BATCH {
                let draw = mis.draw(|| uniform(&mut rng));
                for s in draw.vertices.iter().flatten() {
                    acc += s.weight + s.pdf + s.x1.x;
                }
            }
            acc
        })
    });
    let mut rng = SplitMix64::new(7);
    group.bench_function(BenchmarkId::new("mis-six", "hg0.9"), |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for _ in 0..BATCH {
                let u: [f32; 6] = core::array::from_fn(|_| uniform(&mut rng));
                for s in mis.sample(black_box(u)).iter().flatten() {
                    acc += s.weight + s.pdf + s.x1.x;
                }
            }
            acc
        })
    });
    group.finish();

    let vertices: Vec<Vertex<f32>> = uniforms_n::<f32>(2 * POOL)
        .into_iter()
        .filter_map(|u| omnee.sample_vertex(u, &full).map(|(_, v)| v))
        .take(POOL)
        .collect();
    let vertices = Pool::new(vertices);
    let mut group = c.benchmark_group("pdf/f32");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(BenchmarkId::new("equiangular-at-point", "hg0.9"), |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for v in vertices.next() {
                acc += equiangular.pdf(black_box(v.x1));
            }
            acc
        })
    });
    group.bench_function(BenchmarkId::new("equiangular-at-vertex", "hg0.9"), |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for v in vertices.next() {
                acc += equiangular.pdf_vertex(black_box(v));
            }
            acc
        })
    });
    group.finish();
}

/// End points for `connections_*`: `POOL` pairs, `x0` in the unit cube
/// about `(0, 0, 1)` and `x2` in the one about the origin (s ≈ 1, as the
/// scalar benchmarks' connection), from a fixed SplitMix64 stream.
fn endpoints<F: Real>() -> [Vec<F>; 6] {
    let mut rng = omnee::rng::SplitMix64::new(0xc0_44ec_7104);
    let mut cols: [Vec<F>; 6] = Default::default();
    for _ in 0..POOL {
        for (k, col) in cols.iter_mut().enumerate() {
            let u: f64 = omnee::sampling::uniform(&mut rng);
            let centre = if k == 2 { 1.0 } else { 0.0 };
            col.push(F::from_f64(centre + u - 0.5));
        }
    }
    cols
}

/// The batch over connections: `connections_<precision>/<technique>/<name>`
/// (see the top of the file), for OMNEE, MIS and the scalar calls it
/// replaces.
fn connections<F: Real, P: omnee::sampling::PhaseBatch<F> + Copy>(
    c: &mut Criterion<CpuTime>,
    precision: &str,
    name: &str,
    phase: P,
    with_mis: bool,
) {
    use omnee::method::Setup;
    use omnee::sampling::{Connections, Points, PointsMut, SampleArrays, Uniforms};
    let [ax, ay, az, bx, by, bz] = endpoints::<F>();
    let us = uniforms::<F>();
    let soa = |k: usize| us.iter().map(|u| u[k]).collect::<Vec<F>>();
    let (u0, u1, u2) = (soa(0), soa(1), soa(2));
    // The MIS companion's three: the next triple, as `sample/*/mis` takes them.
    let next = |k: usize| (0..POOL).map(|i| us[(i + 1) % POOL][k]).collect::<Vec<F>>();
    let (v0, v1, v2) = (next(0), next(1), next(2));
    // The same walk through the pool as the scalar benchmarks.
    let at = std::cell::Cell::new(0usize);
    let window = || {
        let i = at.get();
        at.set((i + BATCH) % POOL);
        i..i + BATCH
    };
    let lanes = |w: std::ops::Range<usize>| {
        Connections::new(
            Points {
                x: &ax[w.clone()],
                y: &ay[w.clone()],
                z: &az[w.clone()],
            },
            Points {
                x: &bx[w.clone()],
                y: &by[w.clone()],
                z: &bz[w],
            },
            F::PI,
        )
        .unwrap()
    };
    let mut out: [Vec<F>; 10] = core::array::from_fn(|_| vec![F::ZERO; BATCH]);
    let mut valid = [vec![false; BATCH], vec![false; BATCH]];
    let mut group = c.benchmark_group(format!("connections_{precision}"));
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(BenchmarkId::new("omnee", name), |b| {
        b.iter(|| {
            let w = window();
            let [x, y, z, pdf, weight, ..] = &mut out;
            let samples = SampleArrays {
                x1: PointsMut { x, y, z },
                pdf,
                weight,
                valid: &mut valid[0],
            };
            let u = Uniforms {
                u0: black_box(&u0[w.clone()]),
                u1: &u1[w.clone()],
                u2: &u2[w.clone()],
            };
            let n = lanes(w).sample_omnee(&phase, u, samples).unwrap();
            F::from_f64(n as f64) + out[3][n / 2] + out[4][n / 3] + out[0][n / 4]
        })
    });
    group.bench_function(BenchmarkId::new("omnee-scalar", name), |b| {
        b.iter(|| {
            let w = window();
            let mut acc = F::ZERO;
            for i in w {
                let x0 = F::Vec3::new(ax[i], ay[i], az[i]);
                let x2 = F::Vec3::new(bx[i], by[i], bz[i]);
                let Ok(conn) = Connection::new(black_box(x0), x2, F::PI) else {
                    continue;
                };
                if let Some(s) = Omnee::new(conn, phase).sample([u0[i], u1[i], u2[i]]) {
                    acc += s.weight + s.pdf + s.x1.x();
                }
            }
            acc
        })
    });
    if with_mis {
        let setup = Setup::new(phase, Directions::Sphere, Region::Everywhere, F::ONE).unwrap();
        group.bench_function(BenchmarkId::new("mis", name), |b| {
            b.iter(|| {
                let w = window();
                let [x, y, z, pdf, weight, cx, cy, cz, cpdf, cweight] = &mut out;
                let [valid, cvalid] = &mut valid;
                let omnee = SampleArrays {
                    x1: PointsMut { x, y, z },
                    pdf,
                    weight,
                    valid,
                };
                let companion = SampleArrays {
                    x1: PointsMut {
                        x: cx,
                        y: cy,
                        z: cz,
                    },
                    pdf: cpdf,
                    weight: cweight,
                    valid: cvalid,
                };
                let u = Uniforms {
                    u0: black_box(&u0[w.clone()]),
                    u1: &u1[w.clone()],
                    u2: &u2[w.clone()],
                };
                let v = Uniforms {
                    u0: &v0[w.clone()],
                    u1: &v1[w.clone()],
                    u2: &v2[w.clone()],
                };
                let n = lanes(w).sample_mis(&setup, u, v, omnee, companion).unwrap();
                F::from_f64(n as f64) + out[3][n / 2] + out[4][n / 3] + out[9][0]
            })
        });
    }
    group.finish();
}

/// `connections_*` for HG 0.9 (f32 and f64) and for Fournier–Forand
/// sampled through its table (f32).
fn all_connections(c: &mut Criterion<CpuTime>) {
    connections(
        c,
        "f32",
        "hg0.9",
        HenyeyGreenstein::new(0.9f32).unwrap(),
        true,
    );
    connections(
        c,
        "f64",
        "hg0.9",
        HenyeyGreenstein::new(0.9f64).unwrap(),
        true,
    );
    let ff = FournierForand::new(0.0183f32, 1.10).unwrap();
    let table = InverseCdf::new(&ff).unwrap();
    connections(c, "f32", "ff", TableSampled::new(ff, &table), true);
}

fn benches(c: &mut Criterion<CpuTime>) {
    all::<f32>(c, "f32");
    all::<f64>(c, "f64");
    batch(c);
    one_vertex_and_companion(c);
    all_connections(c);
    slab(c);
}

criterion_group! {
    name = samplers;
    config = Criterion::default()
        .with_measurement(CpuTime)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30);
    targets = benches
}
criterion_main!(samplers);
