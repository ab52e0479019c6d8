//! χ² goodness-of-fit of every sampler against its own pdf (docs/math.md §5.6,
//! Mitsuba 3's method).
//!
//! - Phase functions: 1-D in θ ∈ [0, π], 100 cells whose edges follow the
//!   smoothstep warp `θ = π (3w² − 2w³)` (fine near both poles, where forward
//!   and backward peaks live); expected counts `N · 2π ∫ p sin θ dθ` per cell
//!   by adaptive Gauss–Kronrod on `eval` (not on `cdf`, so the sampler, the
//!   cdf and eval are three independent witnesses).
//! - Volume samplers (OMNEE, equiangular, distance, one-sample MIS): 3-D in
//!   the triangle coordinates (θ, r = β/θ, φ) of an axis frame built by the
//!   test itself, 16 × 6 × 4 cells, θ warped as above on `[0, θ_hi]`.
//!   Expected counts integrate the *volume* pdf with the Jacobian
//!   `dx1 = (d1² d2² / s) θ dθ dr dφ` (docs/math.md §2, `dβ = θ dr`) by 4³-point
//!   Gauss–Legendre per cell, adaptively split in eight (three levels) to 2 %
//!   of the cell's Poisson noise, following the edges where the pdf switches
//!   on or off inside a cell (slab faces, cosine horizons). Ray techniques
//!   are binned for θ ≤ 2.8; samples above join the "no sample" cell. One more
//!   cell counts the calls that return no sample; its expected count is
//!   `N − Σ expected`, so a pdf that integrates to more or less than the
//!   sampler's acceptance fails too.
//!
//! Cells with expected count below 5 are pooled; the p-value of each test is
//! compared with the Šidák level `1 − (1 − 10⁻⁴)^{1/M}` over all `M` χ² tests
//! of the suite, so a correct implementation fails the whole family with
//! probability 10⁻⁴ for fresh seeds (and, with the fixed seeds,
//! deterministically not at all once it has passed). The wrong formulas of
//! `tests/mutants` give p-values below 1e-33 (most underflow to 0), far
//! below that level (≈ 3e-6 per test).

use crate::harness::{
    BatchOmnee, Chi2, Frame, PhaseSpec, Rng, chi2, integrate_box, integrate_pieces, sidak,
};
use glam::DVec3;
use omnee::medium::Region;
use omnee::mis::{Heuristic, OneSample};
use omnee::phase::Deflection;
use omnee::sampling::{
    Connection, Directions, Distance, Equiangular, EquiangularSegment, Omnee, Technique,
};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The phase functions tested in 1-D.
const PHASES: [PhaseSpec; 13] = [
    PhaseSpec::Isotropic,
    PhaseSpec::Rayleigh,
    PhaseSpec::Hg(0.3),
    PhaseSpec::Hg(-0.7),
    PhaseSpec::Hg(0.99),
    PhaseSpec::Hg(-0.99),
    PhaseSpec::TwoTerm(0.99, -0.44, 0.96),
    PhaseSpec::TwoTerm(0.8, -0.6, 0.5),
    PhaseSpec::Draine(0.5, 250.0),
    PhaseSpec::Draine(-0.3, 250.0),
    PhaseSpec::Draine(0.9, 1.0),
    PhaseSpec::Tabulated(TABLE_EVEN),
    PhaseSpec::Tabulated(TABLE_PEAKED),
];

/// Seeds of two tables ([`crate::harness::phases::table`]): seven bins spread
/// evenly with two empty, and twelve bins crowding towards θ = 0 (the first
/// of them, [0, 0.012), empty).
const TABLE_EVEN: u64 = 1;
const TABLE_PEAKED: u64 = 3;

/// OMNEE: phase function, θmax, end points. Scales from 1e-3 to 50 and both
/// restricted and full-range θ.
const OMNEE_CASES: [(PhaseSpec, f64, [f64; 3], [f64; 3]); 7] = [
    (
        PhaseSpec::Isotropic,
        FRAC_PI_2,
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ),
    (PhaseSpec::Hg(0.99), PI, [0.3, -1.0, 2.0], [1.1, 0.5, 1.2]),
    (
        PhaseSpec::Hg(-0.5),
        2.5,
        [1e-3, 2e-3, 0.0],
        [0.0, 1e-3, 1e-3],
    ),
    (
        PhaseSpec::TwoTerm(0.99, -0.44, 0.96),
        PI,
        [0.0, 0.0, 0.0],
        [30.0, -40.0, 0.0],
    ),
    (
        PhaseSpec::Draine(0.5, 250.0),
        PI,
        [-1.0, 0.0, 0.5],
        [0.0, 1.0, 0.5],
    ),
    (PhaseSpec::Rayleigh, 3.0, [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    (PhaseSpec::Hg(0.9), 0.3, [2.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
];

/// How a ray technique draws its direction.
#[derive(Clone, Copy, Debug)]
enum Dirs {
    Sphere,
    Cosine([f64; 3]),
}

/// Where the medium is.
#[derive(Clone, Copy, Debug)]
enum Reg {
    Everywhere,
    Slab(f64, f64),
}

/// A ray technique's parameters: directions, region, σ (distance only),
/// end points.
type RayCase = (Dirs, Reg, f64, [f64; 3], [f64; 3]);

/// Equiangular: sphere and cosine directions, infinite medium and slabs with
/// `x2` inside, `x2` outside and `x0` outside.
const EQUIANGULAR_CASES: [RayCase; 5] = [
    (
        Dirs::Sphere,
        Reg::Everywhere,
        0.0,
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ),
    (
        Dirs::Cosine([0.3, 1.0, -0.2]),
        Reg::Everywhere,
        0.0,
        [0.5, -0.5, 0.0],
        [0.0, 0.5, 0.3],
    ),
    (
        Dirs::Sphere,
        Reg::Slab(-1.0, 1.0),
        0.0,
        [0.2, 0.0, 0.5],
        [0.0, 0.3, -0.4],
    ),
    (
        Dirs::Cosine([0.0, 0.0, 1.0]),
        Reg::Slab(0.5, 2.0),
        0.0,
        [0.0, 1.0, 1.5],
        [0.0, 0.0, 0.0],
    ),
    (
        Dirs::Sphere,
        Reg::Slab(0.0, 0.3),
        0.0,
        [1.0, 0.0, 1.0],
        [0.0, 0.0, 0.1],
    ),
];

/// Distance sampling: as for equiangular, with σ from 0 (uniform on bounded
/// segments) to 10.
const DISTANCE_CASES: [RayCase; 5] = [
    (
        Dirs::Sphere,
        Reg::Everywhere,
        1.0,
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ),
    (
        Dirs::Cosine([1.0, 0.0, 0.0]),
        Reg::Everywhere,
        3.0,
        [0.5, 0.5, 0.0],
        [0.0, 0.0, 0.0],
    ),
    (
        Dirs::Sphere,
        Reg::Slab(-1.0, 1.0),
        0.0,
        [0.2, 0.0, 0.5],
        [0.0, 0.3, -0.4],
    ),
    (
        Dirs::Cosine([0.0, 0.3, 1.0]),
        Reg::Slab(0.0, 1.5),
        0.5,
        [0.0, 1.0, 1.0],
        [0.0, 0.0, 0.2],
    ),
    (
        Dirs::Sphere,
        Reg::Slab(0.5, 1.0),
        10.0,
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.3],
    ),
];

/// One-sample MIS: end points, OMNEE (phase, θmax) if present, equiangular
/// (directions, region) if present, distance (directions, region, σ) if
/// present, and the selection probabilities of the present ones in that order.
type MisCase = (
    [f64; 3],
    [f64; 3],
    Option<(PhaseSpec, f64)>,
    Option<(Dirs, Reg)>,
    Option<(Dirs, Reg, f64)>,
    &'static [f64],
);

const MIS_CASES: [MisCase; 5] = [
    (
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        Some((PhaseSpec::Hg(0.9), FRAC_PI_2)),
        Some((Dirs::Sphere, Reg::Everywhere)),
        None,
        &[0.5, 0.5],
    ),
    (
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        Some((PhaseSpec::Isotropic, PI)),
        None,
        Some((Dirs::Sphere, Reg::Everywhere, 0.8)),
        &[0.3, 0.7],
    ),
    (
        [0.0, 0.2, 0.0],
        [0.0, 0.0, 0.6],
        Some((PhaseSpec::Hg(0.99), 2.5)),
        Some((Dirs::Cosine([0.0, 1.0, 0.0]), Reg::Everywhere)),
        Some((Dirs::Sphere, Reg::Slab(-0.5, 1.0), 1.0)),
        &[1.0, 1.0, 1.0],
    ),
    (
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        None,
        Some((Dirs::Sphere, Reg::Slab(-0.5, 1.5))),
        Some((Dirs::Sphere, Reg::Slab(-0.5, 1.5), 2.0)),
        &[0.8, 0.2],
    ),
    (
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.5],
        Some((PhaseSpec::Draine(0.5, 250.0), 1.2)),
        Some((Dirs::Sphere, Reg::Everywhere)),
        None,
        &[0.9, 0.1],
    ),
];

/// The f32 batch entry point `Omnee::sample_batch` (Henyey–Greenstein):
/// g, θmax, end points.
const BATCH_CASES: [(f64, f64, [f64; 3], [f64; 3]); 2] = [
    (0.99, 2.5, [0.3, -1.0, 2.0], [1.1, 0.5, 1.2]),
    (-0.6, FRAC_PI_2, [0.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
];

/// A ray's medium segment towards a light point: `x0`, the ray's origin
/// and direction, `t_min`, `t_max`.
pub type SegmentCase = ([f64; 3], [f64; 3], [f64; 3], f64, f64);

/// The equiangular distance along a traced ray (`EquiangularSegment`):
/// `x0` off the ray, grazing it, on its line behind the segment, and an
/// infinite segment.
const SEGMENT_CASES: [SegmentCase; 4] = [
    ([0.0, 1.0, 1.0], [0.1, -0.2, 0.3], [0.0, 0.0, 1.0], 0.0, 2.0),
    ([1e-3, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 0.2, 3.0),
    ([0.0, 0.0, -1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 0.0, 3.0),
    (
        [2.0, 1.0, 0.5],
        [0.1, -0.2, 0.3],
        [1.0, 1.0, 0.0],
        0.5,
        f64::INFINITY,
    ),
];

/// Every χ² test of the suite (the Šidák family).
const TESTS: usize = PHASES.len()
    + SEGMENT_CASES.len()
    + OMNEE_CASES.len()
    + EQUIANGULAR_CASES.len()
    + DISTANCE_CASES.len()
    + MIS_CASES.len()
    + BATCH_CASES.len();

/// The per-test significance level: family level 10⁻⁴.
fn level() -> f64 {
    sidak(1e-4, TESTS)
}

/// The smoothstep warp of θ onto `[0, hi]` and its derivative.
fn warp(w: f64, hi: f64) -> (f64, f64) {
    (hi * w * w * (3.0 - 2.0 * w), 6.0 * hi * w * (1.0 - w))
}

/// The warped cell edges on `[0, hi]`.
fn edges(cells: usize, hi: f64) -> Vec<f64> {
    (0..=cells)
        .map(|i| warp(i as f64 / cells as f64, hi).0)
        .collect()
}

/// The cell of `x` among `edges` (clamped to the outer cells).
fn cell(edges: &[f64], x: f64) -> usize {
    edges.partition_point(|&e| e <= x).clamp(1, edges.len() - 1) - 1
}

fn v(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

fn directions(d: Dirs) -> Directions<f64> {
    match d {
        Dirs::Sphere => Directions::Sphere,
        Dirs::Cosine(n) => Directions::cosine(v(n)).unwrap(),
    }
}

fn region(r: Reg) -> Region<f64> {
    match r {
        Reg::Everywhere => Region::Everywhere,
        Reg::Slab(lo, hi) => Region::slab(lo, hi).unwrap(),
    }
}

/// A 1-D χ² test of a phase function's sampler against its `eval`.
pub fn phase_chi2(spec: PhaseSpec, samples: usize, seed: u64) -> Result<Chi2, String> {
    const CELLS: usize = 100;
    let phase = spec.build::<f64>();
    let edges = edges(CELLS, PI);
    let mut observed = vec![0.0; CELLS];
    let mut rng = Rng::new(seed);
    for _ in 0..samples {
        let d = phase.sample(rng.uniform());
        if !(d.theta >= 0.0 && d.theta <= PI) {
            return Err(format!("{spec:?}: sampled θ = {}", d.theta));
        }
        observed[cell(&edges, d.theta)] += 1.0;
    }
    let n = samples as f64;
    let breaks = spec.breakpoints();
    let expected: Vec<f64> = edges
        .windows(2)
        .map(|w| {
            let density = |t: f64| {
                let d = Deflection::from_theta(t);
                TAU * phase.eval(d) * d.sin()
            };
            n * integrate_pieces(density, w[0], w[1], &breaks, 1e-10, 1e-15)
        })
        .collect();
    // The cells cover [0, π]: the expected counts must add up to N up to the
    // quadrature error (1e-10 relative per cell).
    let total: f64 = expected.iter().sum();
    if (total - n).abs() > 1e-6 * n {
        return Err(format!("{spec:?}: eval integrates to {}", total / n));
    }
    chi2(&observed, &expected, 1e-9 * n)
}

/// How a volume χ² test treats samples with θ above the binned range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Beyond {
    /// None may occur: θ_hi is the sampler's θmax.
    Impossible,
    /// They join the "no sample" cell. Ray techniques reach every θ < π, but
    /// as θ → π the points run off to infinity and, in a slab, onto a sheet
    /// of vanishing thickness in (r, φ) that no fixed quadrature resolves;
    /// the cut keeps every binned cell's integrand bounded and resolvable.
    Lumped,
}

/// θ_hi for the ray techniques (see [`Beyond::Lumped`]).
const RAY_THETA_HI: f64 = 2.8;

/// A 3-D χ² test of a volume sampler against its `pdf` in the triangle
/// coordinates of `x0 → x2`, θ on `[0, theta_hi]`.
pub fn volume_chi2(
    technique: &dyn Technique<f64>,
    (x0, x2): (DVec3, DVec3),
    theta_hi: f64,
    beyond: Beyond,
    samples: usize,
    seed: u64,
) -> Result<Chi2, String> {
    const RES: [usize; 3] = [16, 6, 4];
    let frame = Frame::new(x0, x2);
    let theta_edges = edges(RES[0], theta_hi);
    let cells = RES[0] * RES[1] * RES[2];
    let index = |i: usize, j: usize, k: usize| (i * RES[1] + j) * RES[2] + k;
    // The last entry counts the calls that return no sample (and, if lumped,
    // the samples above θ_hi).
    let n = samples as f64;
    let mut observed = vec![0.0; cells + 1];
    let mut rng = Rng::new(seed);
    for _ in 0..samples {
        let Some(s) = technique.sample(rng.u3()) else {
            observed[cells] += 1.0;
            continue;
        };
        if !(s.x1.is_finite() && s.pdf.is_finite() && s.pdf > 0.0) {
            return Err(format!("sample {s:?}"));
        }
        let (theta, r, phi) = frame.angles(s.x1);
        if theta > theta_hi {
            if beyond == Beyond::Lumped {
                observed[cells] += 1.0;
                continue;
            }
            if theta > theta_hi * (1.0 + 1e-9) + 1e-12 {
                return Err(format!("θ = {theta} beyond θmax = {theta_hi}: {s:?}"));
            }
        }
        let i = cell(&theta_edges, theta);
        let j = ((r * RES[1] as f64) as usize).min(RES[1] - 1);
        let k = ((phi / TAU * RES[2] as f64) as usize).min(RES[2] - 1);
        observed[index(i, j, k)] += 1.0;
    }
    let mut expected = vec![0.0; cells + 1];
    let mut density = |p: [f64; 3]| {
        let (theta, dtheta) = warp(p[0], theta_hi);
        let (x1, jacobian) = frame.point(theta, p[1], p[2] * TAU);
        let value = technique.pdf(x1) * jacobian * dtheta * TAU;
        if value.is_finite() { value } else { f64::NAN }
    };
    for i in 0..RES[0] {
        for j in 0..RES[1] {
            for k in 0..RES[2] {
                let lo = [
                    i as f64 / RES[0] as f64,
                    j as f64 / RES[1] as f64,
                    k as f64 / RES[2] as f64,
                ];
                let hi = [
                    (i + 1) as f64 / RES[0] as f64,
                    (j + 1) as f64 / RES[1] as f64,
                    (k + 1) as f64 / RES[2] as f64,
                ];
                let c = index(i, j, k);
                let mut p = integrate_box(&mut density, lo, hi, n, 3, 0);
                if p == 0.0 && observed[c] > 0.0 {
                    // Samples in a cell where no node saw the support: look
                    // closer before calling it a density of zero.
                    p = integrate_box(&mut density, lo, hi, n, 5, 3);
                }
                expected[c] = n * p;
            }
        }
    }
    let mass: f64 = expected[..cells].iter().sum();
    expected[cells] = n - mass;

    // The quadrature's error is within 2 % of each cell's Poisson noise,
    // measured below 1e-4 N in total; a negative expected count of "no
    // sample" beyond 2e-4 N is a density that integrates to more than 1.
    chi2(&observed, &expected, 2e-4 * n)
}

/// Runs a test and compares its p-value with the Šidák level.
fn check(start: std::time::Instant, name: &str, result: Result<Chi2, String>) {
    let alpha = level();
    let time = start.elapsed().as_secs_f64();
    match result {
        Ok(r) => {
            let p = r.p_value;
            println!(
                "χ² {name}: χ² = {:.1}, dof {}, p = {p:.4} (level {alpha:.2e}), {time:.2} s",
                r.statistic, r.dof
            );
            assert!(
                p >= alpha,
                "χ² {name}: p = {p:e} < {alpha:e}: the samples do not follow the pdf; worst cells (index, observed, expected): {:?}",
                r.worst
            );
        }
        Err(e) => panic!("χ² {name}: rejected: {e}"),
    }
}

const PHASE_SAMPLES: usize = 1_000_000;
const VOLUME_SAMPLES: usize = 300_000;

#[test]
fn phase_functions_sample_their_eval() {
    for (i, spec) in PHASES.into_iter().enumerate() {
        check(
            std::time::Instant::now(),
            &format!("{spec:?}"),
            phase_chi2(spec, PHASE_SAMPLES, 1000 + i as u64),
        );
    }
}

/// A 1-D χ² test of the distance along a traced ray against its `pdf`:
/// 100 cells uniform in `w`, `t = t_a + (t_b − t_a) w` on a finite segment,
/// `t = t_a + w/(1 − w)` on an infinite one; expected counts by
/// adaptive quadrature of `pdf(t)`, split at the foot of `x0`.
pub fn segment_chi2(
    (x0, origin, direction, t_min, t_max): SegmentCase,
    samples: usize,
    seed: u64,
) -> Result<Chi2, String> {
    const CELLS: usize = 100;
    let s = EquiangularSegment::new(v(x0), v(origin), v(direction), t_min, t_max)
        .map_err(|e| e.to_string())?;
    // t(w) and dt/dw on w ∈ [0, 1].
    let to_t = |w: f64| {
        if t_max.is_finite() {
            (t_min + (t_max - t_min) * w, t_max - t_min)
        } else {
            (t_min + w / (1.0 - w), 1.0 / ((1.0 - w) * (1.0 - w)))
        }
    };
    let edges: Vec<f64> = (0..=CELLS)
        .map(|i| to_t(i as f64 / CELLS as f64).0)
        .collect();
    let mut observed = vec![0.0; CELLS + 1];
    let mut rng = Rng::new(seed);
    for _ in 0..samples {
        let Some(d) = s.sample(rng.uniform()) else {
            observed[CELLS] += 1.0;
            continue;
        };
        if !(d.t >= t_min && d.t <= t_max && d.pdf > 0.0 && d.pdf.is_finite()) {
            return Err(format!("sample {d:?}"));
        }
        observed[cell(&edges, d.t)] += 1.0;
    }
    let n = samples as f64;
    // The foot of x0 in w, where the density peaks.
    let foot = (v(x0) - v(origin)).dot(v(direction).normalize());
    let foot_w = if t_max.is_finite() {
        (foot - t_min) / (t_max - t_min)
    } else {
        (foot - t_min) / (foot - t_min + 1.0)
    };
    let density = |w: f64| {
        let (t, dt) = to_t(w);
        if w < 1.0 { s.pdf(t) * dt } else { 0.0 }
    };
    let mut expected: Vec<f64> = (0..CELLS)
        .map(|i| {
            let (a, b) = (i as f64 / CELLS as f64, (i + 1) as f64 / CELLS as f64);
            n * integrate_pieces(density, a, b, &[foot_w], 1e-10, 1e-15)
        })
        .collect();
    let mass: f64 = expected.iter().sum();
    expected.push(n - mass);
    chi2(&observed, &expected, 1e-6 * n)
}

#[test]
fn equiangular_segments_sample_their_pdf() {
    for (i, case) in SEGMENT_CASES.into_iter().enumerate() {
        check(
            std::time::Instant::now(),
            &format!("equiangular segment {case:?}"),
            segment_chi2(case, PHASE_SAMPLES, 1500 + i as u64),
        );
    }
}

#[test]
fn omnee_samples_its_pdf() {
    for (i, (spec, theta_max, x0, x2)) in OMNEE_CASES.into_iter().enumerate() {
        let phase = spec.build::<f64>();
        let c = Connection::new(v(x0), v(x2), theta_max).unwrap();
        let t = Omnee::new(c, &*phase);
        let start = std::time::Instant::now();
        check(
            start,
            &format!("omnee {spec:?} θmax {theta_max}"),
            volume_chi2(
                &t,
                (v(x0), v(x2)),
                theta_max,
                Beyond::Impossible,
                VOLUME_SAMPLES,
                2000 + i as u64,
            ),
        );
    }
}

#[test]
fn equiangular_samples_its_pdf() {
    for (i, (dirs, reg, _, x0, x2)) in EQUIANGULAR_CASES.into_iter().enumerate() {
        let c = Connection::new(v(x0), v(x2), PI).unwrap();
        let t = Equiangular::new(c, omnee::phase::Isotropic, directions(dirs), region(reg));
        let start = std::time::Instant::now();
        check(
            start,
            &format!("equiangular {dirs:?} {reg:?}"),
            volume_chi2(
                &t,
                (v(x0), v(x2)),
                RAY_THETA_HI,
                Beyond::Lumped,
                VOLUME_SAMPLES,
                3000 + i as u64,
            ),
        );
    }
}

#[test]
fn distance_samples_its_pdf() {
    for (i, (dirs, reg, sigma, x0, x2)) in DISTANCE_CASES.into_iter().enumerate() {
        let c = Connection::new(v(x0), v(x2), PI).unwrap();
        let t = Distance::new(
            c,
            omnee::phase::Isotropic,
            directions(dirs),
            region(reg),
            sigma,
        )
        .unwrap();
        let start = std::time::Instant::now();
        check(
            start,
            &format!("distance {dirs:?} {reg:?} σ {sigma}"),
            volume_chi2(
                &t,
                (v(x0), v(x2)),
                RAY_THETA_HI,
                Beyond::Lumped,
                VOLUME_SAMPLES,
                4000 + i as u64,
            ),
        );
    }
}

#[test]
fn one_sample_mis_samples_its_mixture_pdf() {
    for (i, (x0, x2, om, eq, di, probabilities)) in MIS_CASES.into_iter().enumerate() {
        let full = Connection::new(v(x0), v(x2), PI).unwrap();
        let phase = om.map(|(spec, _)| spec.build::<f64>());
        let omnee = om.map(|(_, theta_max)| {
            let c = Connection::new(v(x0), v(x2), theta_max).unwrap();
            Omnee::new(c, &**phase.as_ref().unwrap())
        });
        let equiangular = eq.map(|(d, r)| {
            Equiangular::new(full, omnee::phase::Isotropic, directions(d), region(r))
        });
        let distance = di.map(|(d, r, sigma)| {
            Distance::new(
                full,
                omnee::phase::Isotropic,
                directions(d),
                region(r),
                sigma,
            )
            .unwrap()
        });
        let mut techniques: Vec<&dyn Technique<f64>> = Vec::new();
        if let Some(t) = &omnee {
            techniques.push(t);
        }
        if let Some(t) = &equiangular {
            techniques.push(t);
        }
        if let Some(t) = &distance {
            techniques.push(t);
        }
        let (theta_hi, beyond) = (RAY_THETA_HI, Beyond::Lumped);
        let name = format!("one-sample MIS case {i}");
        let start = std::time::Instant::now();
        let result = match techniques.len() {
            2 => {
                let mis = OneSample::new(
                    [techniques[0], techniques[1]],
                    [probabilities[0], probabilities[1]],
                    Heuristic::Balance,
                )
                .unwrap();
                volume_chi2(
                    &mis,
                    (v(x0), v(x2)),
                    theta_hi,
                    beyond,
                    VOLUME_SAMPLES,
                    5000 + i as u64,
                )
            }
            3 => {
                let mis = OneSample::new(
                    [techniques[0], techniques[1], techniques[2]],
                    [probabilities[0], probabilities[1], probabilities[2]],
                    Heuristic::Power,
                )
                .unwrap();
                volume_chi2(
                    &mis,
                    (v(x0), v(x2)),
                    theta_hi,
                    beyond,
                    VOLUME_SAMPLES,
                    5000 + i as u64,
                )
            }
            n => unreachable!("{n} techniques"),
        };
        check(start, &name, result);
    }
}

#[test]
fn the_f32_batch_samples_omnees_pdf() {
    for (i, (g, theta_max, x0, x2)) in BATCH_CASES.into_iter().enumerate() {
        let t = BatchOmnee::new(v(x0), v(x2), theta_max, g);
        // The f32-rounded geometry, which both precisions share.
        let (a, b) = (t.f64.connection.axis.x0, t.f64.connection.axis.x2);
        let start = std::time::Instant::now();
        // θ of an f32 point recomputed in f64 may exceed θmax by the point's
        // rounding (~1e-7): such a sample joins the no-sample cell, a shift
        // of a fraction of a count.
        check(
            start,
            &format!("f32 batch omnee HG {g} θmax {theta_max}"),
            volume_chi2(
                &t,
                (a, b),
                t.f64.connection.theta_max,
                Beyond::Lumped,
                VOLUME_SAMPLES,
                7000 + i as u64,
            ),
        );
    }
}
