//! Numerical stability under stress: every technique over
//! extreme inputs, f32 against f64 through the same generic code.
//!
//! Cases (the full cross product): 15 phase functions (HG with g from −0.9999
//! to 0.9999, two-term HG, Fournier–Forand, Mie, Draine, Rayleigh,
//! isotropic) × 7 distances s = 1e-6 … 1e6 × 3 restrictions θmax ∈ {1e-2,
//! π/2, π} × 3 geometries (`x0 − x2` along a random direction, exactly along
//! +z, and along +z tilted by 1e-7: uniform sphere directions with `u0 → 0`
//! point at +z, so the equiangular ray passes through or next to `x0`) ×
//! 4 techniques (`omnee::method::Method::ALL`: omnee, equiangular, distance
//! with σt = 1/s, the CLI's MIS), each drawn through `omnee::method::Setup`.
//! Each case takes `--per-case` (default 2^15) uniform triples; each
//! coordinate is, with probability ¼ each, one of 0, 2^-24, ½ or
//! 1 − 2^-24 (the largest f32 below 1), or for `u0` the CDF of θmax minus
//! 2^-24 (θ just below θmax), else uniform. Uniforms and end points are f32
//! values, converted exactly to f64, so both precisions solve the same
//! problem.
//!
//! For every triple, in each precision: `sample(u)` and `pdf(x1)` of the
//! returned point (for mis both of its vertices: OMNEE's, and the
//! companion's when the rotated triple `(u1, u2, u0)` draws one). Counted: non-finite or negative `x1`/pdf/weight (target:
//! none), samples returned in one precision only, and pdfs saturated to
//! f32::MAX. Relative errors `|a32 − a64| / |a64|` of the sample's pdf and
//! weight are histogrammed (log bins, 200 per decade) for the maximum and
//! the 99.99th percentile; pairs whose f64 value lies outside the f32 normal
//! range are counted apart, not compared.
//!
//! Conditioning: an f32 algorithm cannot be more accurate than the problem
//! it is handed, and some of these inputs (a ray 1e-7 rad from `x0`, θ a
//! few ulps below θmax) are ill-conditioned at f32 resolution. For every
//! compared sample the f64 pdf is also evaluated with each coordinate of `u`
//! moved by one f32 ulp up and down; if any of those moves the f64 pdf by
//! more than [`COND_LIMIT`] relative, the sample counts as ill-conditioned.
//! The pdf target (relative error below 1e-4 for 99.99 % of samples) is
//! reported over all samples and over the well-conditioned ones.
//!
//! Run: `cargo bench --bench stress` (1.2·10⁸ samples, two threads, a few
//! minutes), optional `-- --per-case N`. Writes `docs/results/stress.md`.

mod common;

use common::{NAMES, arg, docs_path, phase, rounded_to_f32, seed};
use omnee::medium::Region;
use omnee::method::{Method, Setup};
use omnee::phase::{Deflection, Phase, PhaseFunction};
use omnee::rng::SplitMix64;
use omnee::sampling::{Connection, Directions, Sample, uniform};
use omnee::{Real, Vector};
use std::fmt::Write as _;
use std::time::Instant;

const PHASES: [&str; 15] = [
    "hg:-0.9999",
    "hg:-0.99",
    "hg:-0.5",
    "hg:0",
    "hg:0.5",
    "hg:0.9",
    "hg:0.99",
    "hg:0.999",
    "hg:0.9999",
    "tthg:0.99,-0.44,0.96",
    "ff:0.0183,1.10",
    "mie:10",
    "draine:0.6,1",
    "rayleigh",
    "iso",
];
const DISTANCES: [f64; 7] = [1e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6];
const THETA_MAX: [f32; 3] = [1e-2, std::f32::consts::FRAC_PI_2, std::f32::consts::PI];
const GEOMETRIES: [&str; 3] = ["random", "+z", "+z tilted 1e-7"];

/// Log-histogram range of relative errors: 10^LO … 10^HI.
const LO: i32 = -12;
const HI: i32 = 4;
const PER_DECADE: usize = 200;
/// A sample is ill-conditioned at f32 resolution if a one-ulp change of one
/// coordinate of `u` changes the f64 pdf by more than this.
const COND_LIMIT: f64 = 1e-5;
const BINS: usize = (HI - LO) as usize * PER_DECADE;

#[derive(Clone, Debug)]
struct Case {
    phase: usize,
    s_index: usize,
    s: f32,
    theta_max: f32,
    x0: [f32; 3],
    x2: [f32; 3],
    method: Method,
}

impl Case {
    fn describe(&self) -> String {
        format!(
            "{} `{}` s={:e} θmax={:.4} x0={:?} x2={:?}",
            self.method, PHASES[self.phase], self.s, self.theta_max, self.x0, self.x2
        )
    }
}

/// A histogram of relative errors with exact zero count and maximum.
#[derive(Clone, Debug)]
struct Errors {
    bins: Vec<u64>,
    zeros: u64,
    below: u64,
    count: u64,
    max: f64,
    worst: Option<(String, [f32; 3], f64, f64)>,
}

impl Default for Errors {
    fn default() -> Self {
        Self {
            bins: vec![0; BINS + 1],
            zeros: 0,
            below: 0,
            count: 0,
            max: 0.0,
            worst: None,
        }
    }
}

impl Errors {
    fn add(&mut self, e: f64, case: &Case, u: [f32; 3], a32: f64, a64: f64) {
        self.count += 1;
        if e > self.max {
            self.max = e;
            self.worst = Some((case.describe(), u, a32, a64));
        }
        if e == 0.0 {
            self.zeros += 1;
            return;
        }
        let k = ((e.log10() - LO as f64) * PER_DECADE as f64).floor();
        if k < 0.0 {
            self.below += 1;
        } else {
            self.bins[(k as usize).min(BINS)] += 1;
        }
    }

    fn merge(&mut self, o: &Errors) {
        for (a, b) in self.bins.iter_mut().zip(&o.bins) {
            *a += b;
        }
        self.zeros += o.zeros;
        self.below += o.below;
        self.count += o.count;
        if o.max > self.max {
            self.max = o.max;
            self.worst = o.worst.clone();
        }
    }

    /// The upper edge of the bin holding quantile `q` (an upper bound within
    /// 1.2 %).
    fn quantile(&self, q: f64) -> f64 {
        let target = (q * self.count as f64).ceil() as u64;
        let mut seen = self.zeros + self.below;
        if seen >= target {
            return if self.below > 0 { 10f64.powi(LO) } else { 0.0 };
        }
        for (k, &c) in self.bins.iter().enumerate() {
            seen += c;
            if seen >= target {
                return 10f64.powf(LO as f64 + (k + 1) as f64 / PER_DECADE as f64);
            }
        }
        self.max
    }

    /// The fraction of comparisons with relative error below `e`.
    fn fraction_below(&self, e: f64) -> f64 {
        let k = ((e.log10() - LO as f64) * PER_DECADE as f64).floor() as usize;
        let n: u64 = self.zeros + self.below + self.bins[..k.min(BINS)].iter().sum::<u64>();
        n as f64 / self.count.max(1) as f64
    }
}

#[derive(Clone, Debug, Default)]
struct Stats {
    samples: u64,
    returned32: u64,
    returned64: u64,
    one_only: u64,
    non_finite: u64,
    negative: u64,
    saturated32: u64,
    outside_f32_range: u64,
    zero_in_one: u64,
    pdf: Errors,
    pdf_well: Errors,
    ill_conditioned: u64,
    pdf_at_point: Errors,
    weight: Errors,
    bad: Vec<String>,
}

impl Stats {
    fn merge(&mut self, o: &Stats) {
        self.samples += o.samples;
        self.returned32 += o.returned32;
        self.returned64 += o.returned64;
        self.one_only += o.one_only;
        self.non_finite += o.non_finite;
        self.negative += o.negative;
        self.saturated32 += o.saturated32;
        self.outside_f32_range += o.outside_f32_range;
        self.zero_in_one += o.zero_in_one;
        self.pdf.merge(&o.pdf);
        self.pdf_well.merge(&o.pdf_well);
        self.ill_conditioned += o.ill_conditioned;
        self.pdf_at_point.merge(&o.pdf_at_point);
        self.weight.merge(&o.weight);
        for b in &o.bad {
            if self.bad.len() < 10 {
                self.bad.push(b.clone());
            }
        }
    }
}

fn vec3<F: Real>(v: [f32; 3]) -> F::Vec3 {
    F::Vec3::new(F::from_f32(v[0]), F::from_f32(v[1]), F::from_f32(v[2]))
}

/// One precision's setup and connection for a case: the phase function
/// with its parameters rounded to f32 (both precisions evaluate the same
/// function), uniform directions in an infinite medium, σt = 1/s.
struct Problem<F: Real> {
    setup: Setup<F, Phase<'static, F>>,
    full: Connection<F>,
}

impl<F: Real> Problem<F> {
    fn new(case: &Case) -> Self {
        let (x0, x2) = (vec3::<F>(case.x0), vec3::<F>(case.x2));
        let theta_max = F::from_f32(case.theta_max).min(F::PI);
        let phase = phase::<F>(&rounded_to_f32(PHASES[case.phase]));
        let sigma_t = F::ONE / F::from_f32(case.s);
        Self {
            setup: Setup::new(phase, Directions::Sphere, Region::Everywhere, sigma_t)
                .expect("valid sigma_t"),
            full: Connection::new(x0, x2, theta_max).expect("valid connection"),
        }
    }

    /// The method's density at `x1`.
    fn pdf(&self, method: Method, x1: F::Vec3) -> F {
        self.setup.pdf(method, self.full, x1)
    }

    /// The method's vertices for `u` (one; for mis OMNEE's and, when
    /// `u[1] < 0.05`, the companion's from the rotated triple
    /// `(u1, u2, u0)`) with the pdf re-evaluated at each `x1`.
    fn sample(&self, method: Method, u: [F; 3]) -> [Option<(Sample<F>, F)>; 2] {
        let mut numbers = [u[0], u[1], u[2], u[1], u[2], u[0]].into_iter();
        let next = || numbers.next().expect("at most Draw::MAX_NUMBERS numbers");
        self.setup
            .draw(method, self.full, next)
            .vertices
            .map(|v| v.map(|s| (s, self.pdf(method, s.x1))))
    }
}

fn bad_output<F: Real>(s: &Sample<F>, pdf_again: F) -> (bool, bool) {
    let x = s.x1.to_array();
    let finite = x.iter().all(|v| v.is_finite())
        && s.pdf.is_finite()
        && s.weight.is_finite()
        && pdf_again.is_finite();
    let negative = s.pdf < F::ZERO || s.weight < F::ZERO || pdf_again < F::ZERO;
    (!finite, negative)
}

/// Adds `|a − b|/|b|` to `errors`; pairs with `b` outside the f32 normal
/// range and pairs where exactly one value is 0 (a θmax or end-point
/// decision that went the other way) are counted instead.
fn compare(errors: &mut Errors, stats: &mut [u64; 2], case: &Case, u: [f32; 3], a: f32, b: f64) {
    let (a, b64) = (a as f64, b);
    if b64 != 0.0 && (b64.abs() > f32::MAX as f64 || b64.abs() < f32::MIN_POSITIVE as f64) {
        stats[0] += 1;
        return;
    }
    if (a == 0.0) != (b64 == 0.0) {
        stats[1] += 1;
        return;
    }
    let e = if b64 == 0.0 {
        0.0
    } else {
        (a - b64).abs() / b64.abs()
    };
    errors.add(e, case, u, a, b64);
}

/// The largest relative change of the f64 pdf when one coordinate of `u`
/// moves by one f32 ulp (up or down, staying in `[0, 1)`); moves that give
/// no sample (a θmax or end-point decision) are skipped.
fn conditioning(s64: &Problem<f64>, method: Method, vertex: usize, u: [f32; 3], pdf: f64) -> f64 {
    let mut worst = 0.0f64;
    for k in 0..3 {
        let bits = u[k].to_bits();
        let moves = [
            (u[k] > 0.0).then(|| f32::from_bits(bits - 1)),
            (u[k] < 1.0 - f32::EPSILON / 2.0).then(|| f32::from_bits(bits + 1)),
        ];
        for v in moves.into_iter().flatten() {
            let mut w = u;
            w[k] = v;
            if let Some((s, _)) = s64.sample(method, w.map(f64::from))[vertex] {
                worst = worst.max((s.pdf / pdf - 1.0).abs());
            }
        }
    }
    worst
}

/// Runs one case; `stats[0]` gets the triples of uniform random numbers,
/// `stats[1]` those with at least one special coordinate.
fn run_case(case: &Case, n: u64, stats: &mut [Stats; 2]) {
    let s32 = Problem::<f32>::new(case);
    let s64 = Problem::<f64>::new(case);
    // u0 just below the CDF of θmax: θ just below θmax.
    let cdf = phase::<f64>(&rounded_to_f32(PHASES[case.phase]))
        .cdf(Deflection::from_theta(case.theta_max as f64));
    let below_max = ((cdf as f32) - 2f32.powi(-24)).max(0.0);
    let specials = [0.0f32, 2f32.powi(-24), 0.5, 1.0 - 2f32.powi(-24)];
    let mut rng = SplitMix64::new(seed(&[
        case.phase as u64,
        case.s.to_bits() as u64,
        case.theta_max.to_bits() as u64,
        case.x0[0].to_bits() as u64,
        case.x0[2].to_bits() as u64,
        case.method as u64,
    ]));
    for _ in 0..n {
        let mut u = [0.0f32; 3];
        let mut special = false;
        for (k, v) in u.iter_mut().enumerate() {
            let r = rng.next_u64();
            special |= r & 3 == 0;
            *v = if r & 3 == 0 {
                let pick = (r >> 2) % 5;
                if pick == 4 {
                    if k == 0 { below_max } else { 0.5 }
                } else {
                    specials[pick as usize]
                }
            } else {
                ((r >> 40) as f32) * (1.0 / (1u64 << 24) as f32)
            };
        }
        let stats = &mut stats[special as usize];
        let (a2, b2) = (
            s32.sample(case.method, u),
            s64.sample(case.method, u.map(|v| v as f64)),
        );
        for vertex in 0..2 {
            let (a, b) = (a2[vertex], b2[vertex]);
            // The second vertex is mis's companion, drawn now and then.
            if vertex == 1 && a.is_none() && b.is_none() {
                continue;
            }
            stats.samples += 1;
            compare_vertex(stats, case, &s64, vertex, u, a, b);
        }
    }
}

/// Counts and compares one vertex of the f32 and the f64 draw.
fn compare_vertex(
    stats: &mut Stats,
    case: &Case,
    s64: &Problem<f64>,
    vertex: usize,
    u: [f32; 3],
    a: Option<(Sample<f32>, f32)>,
    b: Option<(Sample<f64>, f64)>,
) {
    for (bad, neg) in [
        a.as_ref().map(|(s, p)| bad_output(s, *p)),
        b.as_ref().map(|(s, p)| bad_output(s, *p)),
    ]
    .into_iter()
    .flatten()
    {
        if bad || neg {
            if bad {
                stats.non_finite += 1;
            }
            if neg {
                stats.negative += 1;
            }
            if stats.bad.len() < 10 {
                stats.bad.push(format!("{} u={u:?}", case.describe()));
            }
        }
    }
    match (&a, &b) {
        (Some((sa, pa)), Some((sb, _))) => {
            stats.returned32 += 1;
            stats.returned64 += 1;
            if sa.pdf == f32::MAX {
                stats.saturated32 += 1;
            }
            let mut counts = [0; 2];
            compare(&mut stats.pdf, &mut counts, case, u, sa.pdf, sb.pdf);
            if conditioning(s64, case.method, vertex, u, sb.pdf) <= COND_LIMIT {
                compare(&mut stats.pdf_well, &mut [0; 2], case, u, sa.pdf, sb.pdf);
            } else {
                stats.ill_conditioned += 1;
            }
            compare(
                &mut stats.weight,
                &mut counts,
                case,
                u,
                sa.weight,
                sb.weight,
            );
            let x1 = sa.x1.to_array().map(|v| v as f64);
            let at_point = s64.pdf(case.method, glam::DVec3::from_array(x1));
            compare(&mut stats.pdf_at_point, &mut counts, case, u, *pa, at_point);
            stats.outside_f32_range += counts[0];
            stats.zero_in_one += counts[1];
        }
        (Some(_), None) => {
            stats.returned32 += 1;
            stats.one_only += 1;
        }
        (None, Some(_)) => {
            stats.returned64 += 1;
            stats.one_only += 1;
        }
        (None, None) => {}
    }
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let mut rng = SplitMix64::new(7);
    for phase in 0..PHASES.len() {
        for (s_index, &s) in DISTANCES.iter().enumerate() {
            let s = s as f32;
            for &theta_max in &THETA_MAX {
                for geo in 0..GEOMETRIES.len() {
                    let dir = match geo {
                        0 => {
                            let z = 1.0 - 2.0 * uniform::<f64, _>(&mut rng);
                            let phi = std::f64::consts::TAU * uniform::<f64, _>(&mut rng);
                            let r = (1.0 - z * z).max(0.0).sqrt();
                            [r * phi.cos(), r * phi.sin(), z]
                        }
                        1 => [0.0, 0.0, 1.0],
                        _ => [1e-7, 0.0, 1.0],
                    };
                    let x2 = [0.25 * s, -0.5 * s, 0.125 * s];
                    let x0 = [
                        x2[0] + s * dir[0] as f32,
                        x2[1] + s * dir[1] as f32,
                        x2[2] + s * dir[2] as f32,
                    ];
                    for method in Method::ALL {
                        out.push(Case {
                            phase,
                            s_index,
                            s,
                            theta_max,
                            x0,
                            x2,
                            method,
                        });
                    }
                }
            }
        }
    }
    out
}

fn main() {
    let per_case: u64 = arg("--per-case", 1 << 15);
    let threads: usize = arg("--threads", 2);
    let started = Instant::now();
    let all = cases();
    // One Stats per (technique, phase, distance, input class).
    type Key = (Method, usize, usize, usize);
    let results: Vec<Vec<(Key, Stats)>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let all = &all;
                scope.spawn(move || {
                    let mut out: Vec<(Key, Stats)> = Vec::new();
                    for case in all.iter().skip(t).step_by(threads) {
                        let mut st: [Stats; 2] = Default::default();
                        run_case(case, per_case, &mut st);
                        for (class, st) in st.into_iter().enumerate() {
                            out.push(((case.method, case.phase, case.s_index, class), st));
                        }
                    }
                    out
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let results: Vec<(Key, Stats)> = results.into_iter().flatten().collect();
    let sum = |pred: &dyn Fn(&Key) -> bool| {
        let mut st = Stats::default();
        for (k, s) in &results {
            if pred(k) {
                st.merge(s);
            }
        }
        st
    };
    let mut md = String::new();
    writeln!(
        md,
        "<!-- generated by `cargo bench --bench stress -- --per-case {per_case}`; do not edit -->\n"
    )
    .unwrap();
    let header = "| | samples | returned f32 / f64 | returned in one precision only | non-finite | negative | pdf = f32::MAX (saturated) | f64 value outside f32 normal range | value 0 in one precision only | pdf rel. err. max | pdf rel. err. 99.99 % | pdf share < 1e-4 | ill-conditioned | well-conditioned: pdf rel. err. 99.99 % | share < 1e-4 | weight rel. err. max | weight rel. err. 99.99 % | pdf at the f32 point: rel. err. max | 99.99 % | share < 1e-4 |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|";
    let line = |md: &mut String, name: &str, s: &Stats| {
        writeln!(
            md,
            "| {name} | {} | {} / {} | {} | {} | {} | {} | {} | {} | {:.2e} | {:.2e} | {:.4} % | {} | {:.2e} | {:.4} % | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.4} % |",
            s.samples,
            s.returned32,
            s.returned64,
            s.one_only,
            s.non_finite,
            s.negative,
            s.saturated32,
            s.outside_f32_range,
            s.zero_in_one,
            s.pdf.max,
            s.pdf.quantile(0.9999),
            100.0 * s.pdf.fraction_below(1e-4),
            s.ill_conditioned,
            s.pdf_well.quantile(0.9999),
            100.0 * s.pdf_well.fraction_below(1e-4),
            s.weight.max,
            s.weight.quantile(0.9999),
            s.pdf_at_point.max,
            s.pdf_at_point.quantile(0.9999),
            100.0 * s.pdf_at_point.fraction_below(1e-4),
        )
        .unwrap();
    };
    let classes = ["uniform random u", "u with a special coordinate"];
    writeln!(md, "### By technique and input class\n\n{header}").unwrap();
    for (t, name) in Method::ALL.into_iter().zip(NAMES) {
        for (c, class) in classes.iter().enumerate() {
            line(
                &mut md,
                &format!("{name}, {class}"),
                &sum(&|k| k.0 == t && k.3 == c),
            );
        }
        line(&mut md, &format!("**{name}, all**"), &sum(&|k| k.0 == t));
    }
    for (c, class) in classes.iter().enumerate() {
        line(
            &mut md,
            &format!("all techniques, {class}"),
            &sum(&|k| k.3 == c),
        );
    }
    let total = sum(&|_| true);
    line(&mut md, "**all**", &total);
    writeln!(
        md,
        "\n### By technique and distance s (both input classes)\n\n{header}"
    )
    .unwrap();
    for (t, name) in Method::ALL.into_iter().zip(NAMES) {
        for (i, s) in DISTANCES.iter().enumerate() {
            line(
                &mut md,
                &format!("{name}, s = {s:e}"),
                &sum(&|k| k.0 == t && k.2 == i),
            );
        }
    }
    writeln!(md, "\n### By technique and phase function\n\n{header}").unwrap();
    for (t, name) in Method::ALL.into_iter().zip(NAMES) {
        for (p, spec) in PHASES.iter().enumerate() {
            for (c, class) in ["uniform", "special"].iter().enumerate() {
                line(
                    &mut md,
                    &format!("{name} `{spec}`, {class} u"),
                    &sum(&|k| k.0 == t && k.1 == p && k.3 == c),
                );
            }
        }
    }
    writeln!(md, "\n### Worst cases (max relative error)\n").unwrap();
    for (t, name) in Method::ALL.into_iter().zip(NAMES) {
        for (c, class) in classes.iter().enumerate() {
            let st = sum(&|k| k.0 == t && k.3 == c);
            for (what, e) in [
                ("pdf", &st.pdf),
                ("pdf, well-conditioned", &st.pdf_well),
                ("weight", &st.weight),
                ("pdf at the f32 point", &st.pdf_at_point),
            ] {
                if let Some((case, u, a, b)) = &e.worst {
                    writeln!(
                        md,
                        "- {name} {what} ({class}): rel. err. {:.3e}: {case}, u = {u:?}: f32 {a:e}, f64 {b:e}",
                        e.max
                    )
                    .unwrap();
                }
            }
        }
    }
    if !total.bad.is_empty() {
        writeln!(md, "\n### Non-finite or negative outputs (first 10)\n").unwrap();
        for b in &total.bad {
            writeln!(md, "- {b}").unwrap();
        }
    }
    writeln!(
        md,
        "\n{} cases, {} samples, {:.0} s on {threads} threads.",
        all.len(),
        total.samples,
        started.elapsed().as_secs_f64()
    )
    .unwrap();
    let path = docs_path("results/stress.md");
    std::fs::write(&path, &md).expect("write");
    println!("{md}");
    eprintln!("wrote {}", path.display());
}
