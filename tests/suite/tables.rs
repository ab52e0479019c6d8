//! Tabulated inverse CDFs (`phase::InverseCdf`, `phase::TableSampled`,
//! docs/math.md §11): the table samples its own density q (χ², in θ and, with
//! OMNEE, in the volume), its ratio p/q makes estimates of the phase
//! function itself unbiased (its cdf and mean cosine, and OMNEE's
//! point-to-point integral against the quadrature reference), f32 tables
//! agree with f64 ones, and the sizes are the documented ones.
//!
//! Statistical levels: the χ² tests here form one Šidák family at level
//! 1e-5 and the studentized comparisons another (so the suite's χ² and
//! unbiasedness families, at 1e-4 each, keep their total near 1e-4). The
//! ratio-weighted estimates are bounded (p/q is bounded on each phase
//! function's support: the table's q is positive and continuous on (0, π),
//! and near θ = 0 the first bin's power law follows the peak, measured
//! below), so the CLT argument of `unbiased.rs` applies.

use crate::chi2::{Beyond, volume_chi2};
use crate::harness::{PhaseSpec, Rng, chi2, integrate_pieces, normal_two_sided_quantile, sidak};
use glam::DVec3;
use omnee::Real;
use omnee::medium::Homogeneous;
use omnee::phase::{
    Deflection, INVERSE_CDF_BINS, InverseCdf, Phase, PhaseFunction, TableSampled, Tabulated,
};
use omnee::reference::PointToPoint;
use omnee::sampling::{Connection, Draw, Omnee};
use std::f64::consts::{PI, TAU};

/// The phase functions the renderer samples through a table: the issue's
/// Fournier–Forand, Draine, approximate Mie and Rayleigh, a measured-style
/// table with empty bins, and a steep FF and HG for the first bin's power law.
const SPECS: [PhaseSpec; 8] = [
    PhaseSpec::Ff(0.0183, 1.10),
    PhaseSpec::Ff(0.001, 1.05),
    PhaseSpec::Draine(0.6, 1.0),
    PhaseSpec::Draine(0.5557, 22.0),
    PhaseSpec::Mie(10.0),
    PhaseSpec::Rayleigh,
    PhaseSpec::Tabulated(3),
    PhaseSpec::Hg(0.98),
];

/// χ² tests here: one per spec in θ, two OMNEE volume tests.
const CHI2_TESTS: usize = SPECS.len() + 2;
/// Studentized comparisons here: per spec 9 cdf points and the mean cosine
/// in f64 and in f32 (fitted ratios), one OMNEE estimate per spec, and the
/// foreign table's.
const Z_TESTS: usize = SPECS.len() * 21 + 1;

fn chi2_level() -> f64 {
    sidak(1e-5, CHI2_TESTS)
}

fn z_bound() -> f64 {
    normal_two_sided_quantile(sidak(1e-5, Z_TESTS)).max(4.0)
}

/// The phase function of `spec` and its table, in precision `F`.
fn tabled<F: Real>(spec: PhaseSpec) -> (Box<dyn PhaseFunction<F>>, InverseCdf<F>) {
    let phase = spec.build::<F>();
    let table = InverseCdf::new(&*phase).unwrap();
    (phase, table)
}

/// The table's node angles θ(k/N), where its density has kinks.
fn nodes(table: &InverseCdf<f64>) -> Vec<f64> {
    (0..=INVERSE_CDF_BINS)
        .map(|k| table.sample(k as f64 / INVERSE_CDF_BINS as f64).theta)
        .collect()
}

#[test]
fn tables_sample_their_own_density() {
    const SAMPLES: usize = 1_000_000;
    const CELLS: usize = 100;
    let alpha = chi2_level();
    for (i, spec) in SPECS.into_iter().enumerate() {
        let (phase, table) = tabled::<f64>(spec);
        let sampled = TableSampled::new(&*phase, &table);
        // Cells even in θ², which resolves the forward peaks.
        let edges: Vec<f64> = (0..=CELLS)
            .map(|c| PI * (c as f64 / CELLS as f64).powi(2))
            .collect();
        let mut observed = vec![0.0; CELLS];
        let mut rng = Rng::new(0x7ab1e + i as u64);
        for _ in 0..SAMPLES {
            let theta = sampled.sample(rng.uniform()).theta;
            let c = edges.partition_point(|&e| e <= theta).clamp(1, CELLS) - 1;
            observed[c] += 1.0;
        }
        // Expected counts from the table's own CDF (its `invert`, exact), and
        // the density the weights use checked against it: ∫ 2π q sin θ dθ
        // over every cell but the first (where the first bin's power law can
        // be too singular for the quadrature) is that difference of the CDF.
        let mut breaks = nodes(&table);
        breaks.extend(spec.breakpoints());
        breaks.sort_by(f64::total_cmp);
        let n = SAMPLES as f64;
        let cdf = |t: f64| {
            if t >= PI {
                1.0
            } else {
                sampled.invert(Deflection::from_theta(t)).unwrap()
            }
        };
        let expected: Vec<f64> = edges
            .windows(2)
            .map(|w| n * (cdf(w[1]) - cdf(w[0])))
            .collect();
        let mut worst = 0.0f64;
        for w in edges.windows(2).skip(1) {
            let density = |t: f64| {
                let d = Deflection::from_theta(t);
                TAU * sampled.pdf(d) * d.sin()
            };
            let mass = integrate_pieces(density, w[0], w[1], &breaks, 1e-10, 1e-14);
            worst = worst.max((mass - (cdf(w[1]) - cdf(w[0]))).abs());
        }
        assert!(worst < 1e-8, "{spec:?}: q is not dQ/dω: {worst:e}");
        let r = chi2(&observed, &expected, 1e-8 * n).unwrap();
        println!(
            "χ² table {spec:?}: χ² = {:.1}, dof {}, p = {:.4} (level {alpha:.1e})",
            r.statistic, r.dof, r.p_value
        );
        assert!(r.p_value >= alpha, "{spec:?}: {r:?}");
    }
}

/// Mean and standard error of `f` over `n` draws.
fn mean_and_error(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let x = f();
        s += x;
        s2 += x * x;
    }
    let m = s / n as f64;
    let var = (s2 / n as f64 - m * m).max(0.0) * n as f64 / (n as f64 - 1.0);
    (m, (var / n as f64).sqrt())
}

#[test]
fn the_ratio_makes_the_phase_functions_own_integrals_unbiased() {
    integrals_are_unbiased::<f64>(0x5a7e0);
}

#[test]
fn fitted_ratios_keep_the_phase_functions_own_integrals_unbiased() {
    // f32 tables take p/q from their fitted quartics in most bins.
    integrals_are_unbiased::<f32>(0x777000);
}

/// Estimates of the cdf at 9 points and of the mean cosine with draws of an
/// `F` table weighted by its ratio, against the phase function's own (f64,
/// from the same f32-representable parameters).
fn integrals_are_unbiased<F: Real>(seed: u64) {
    const SAMPLES: usize = 400_000;
    let z = z_bound();
    let mut failures = Vec::new();
    for (i, spec) in SPECS.into_iter().enumerate() {
        let spec = spec.rounded_to_f32();
        if F::EPSILON.to_f64() > 1e-10 && spec == PhaseSpec::Ff(0.001, 1.05).rounded_to_f32() {
            // 1.8e-3 of this peak's mass lies at 1 − cos θ below f32's
            // smallest normal, which an f32 table cannot represent (its
            // stratified mean of p/q is 1 − 1.808e-3, with the fitted
            // ratios and with p evaluated alike; docs/math.md §11.3).
            continue;
        }
        let (phase_f, table) = tabled::<F>(spec);
        let phase = spec.build::<f64>();
        let sampled = TableSampled::new(&*phase_f, &table);
        // Thresholds at the phase function's own quantiles, two inside the
        // table's first bin (u < 1/N), where its power law stands in.
        let quantiles = [0.25, 0.5, 1.0, 2.0, 16.0, 64.0, 100.0, 120.0, 127.0];
        let widen = |d: Deflection<F>| {
            Deflection::from_versines(d.one_minus_cos.to_f64(), d.one_plus_cos.to_f64())
        };
        let thresholds: Vec<Deflection<f64>> = quantiles
            .iter()
            .map(|q| widen(table.sample(F::from_f64(q / INVERSE_CDF_BINS as f64))))
            .collect();
        let mut rng = Rng::new(seed + i as u64);
        let draws: Vec<(Deflection<f64>, f64)> = (0..SAMPLES)
            .map(|_| {
                let (d, _, ratio) = sampled.sample_ratio(F::from_f64(rng.uniform()));
                (widen(d), ratio.to_f64())
            })
            .collect();
        let mut check = |what: String, want: f64, h: &dyn Fn(&Deflection<f64>) -> f64| {
            let mut it = draws.iter();
            let (mean, se) = mean_and_error(SAMPLES, || {
                let (d, ratio) = it.next().unwrap();
                h(d) * ratio
            });
            let dev = (mean - want) / se.max(1e-300);
            println!(
                "{spec:?} {what} ({}): {mean:.6e} ± {se:.1e} vs {want:.6e} ({dev:+.2} σ)",
                core::any::type_name::<F>()
            );
            if !(dev.abs() < z || (mean - want).abs() < 1e-14) {
                failures.push(format!("{spec:?} {what}: {mean:e} ± {se:e} vs {want:e}"));
            }
        };
        // f32 cannot resolve 1 − cos θ below ~1e-30 (the steep FF's first
        // quantiles): the table has empty bins there (docs/math.md §11.3).
        for t in thresholds.iter().filter(|t| t.one_minus_cos > 1e-30) {
            check(format!("P(Θ ≤ {:.3e})", t.theta), phase.cdf(*t), &|d| {
                if d.theta <= t.theta { 1.0 } else { 0.0 }
            });
        }
        check("⟨cos θ⟩".into(), phase.mean_cosine(), &|d| d.cos());
    }
    assert!(
        failures.is_empty(),
        "biased (bound {z:.2} σ):\n{}",
        failures.join("\n")
    );
}

/// OMNEE cases: (spec, θmax, x0, x2).
const OMNEE_CASES: [(PhaseSpec, f64, [f64; 3], [f64; 3]); 2] = [
    (
        PhaseSpec::Ff(0.0183, 1.10),
        PI / 2.0,
        [0.3, -1.0, 2.0],
        [1.1, 0.5, 1.2],
    ),
    (PhaseSpec::Mie(10.0), 3.0, [0.0, 0.0, 0.0], [0.0, 0.0, 1.5]),
];

#[test]
fn omnee_with_a_table_samples_its_pdf() {
    let alpha = chi2_level();
    for (i, (spec, theta_max, x0, x2)) in OMNEE_CASES.into_iter().enumerate() {
        let (phase, table) = tabled::<f64>(spec);
        let (x0, x2) = (DVec3::from_array(x0), DVec3::from_array(x2));
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let omnee = Omnee::new(c, TableSampled::new(&*phase, &table));
        let r = volume_chi2(
            &omnee,
            (x0, x2),
            theta_max,
            Beyond::Impossible,
            300_000,
            0x70a1 + i as u64,
        )
        .unwrap();
        println!(
            "χ² omnee+table {spec:?}: χ² = {:.1}, dof {}, p = {:.4}",
            r.statistic, r.dof, r.p_value
        );
        assert!(r.p_value >= alpha, "{spec:?}: {r:?}");
    }
}

#[test]
fn omnee_with_a_table_estimates_the_reference() {
    const SAMPLES: usize = 200_000;
    let z = z_bound();
    let mut rng = Rng::new(0x7ab1);
    let mut failures = Vec::new();
    for (i, spec) in SPECS.into_iter().enumerate() {
        let x0 = DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let s = rng.range(0.3, 2.0);
        let x2 = x0 + rng.unit() * s;
        let sigma_t = rng.range(0.2, 2.0) / s;
        let medium = Homogeneous::new(0.7 * sigma_t, 0.3 * sigma_t).unwrap();
        // θmax ≤ 3: OMNEE's weight θ/(s sin θ) is bounded, and p/q is.
        let theta_max = rng.range(PI / 2.0, 3.0);
        let (phase, table) = tabled::<f64>(spec);
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let problem = PointToPoint::new(c, medium, None).unwrap();
        let want = problem.integral(&&*phase);
        let omnee = Omnee::new(c, TableSampled::new(&*phase, &table));
        let mut stream = Rng::new(0xe57 + i as u64);
        let (mean, se) = mean_and_error(SAMPLES, || {
            Draw::single(&omnee, || stream.uniform()).sum(|s| problem.estimate(s))
        });
        let dev = (mean - want) / se;
        println!("omnee+table {spec:?}: {mean:.6e} ± {se:.1e} vs {want:.6e} ({dev:+.2} σ)");
        if !(dev.abs() < z) {
            failures.push(format!("{spec:?}: {mean:e} ± {se:e} vs {want:e}"));
        }
    }
    assert!(
        failures.is_empty(),
        "biased (bound {z:.2} σ):\n{}",
        failures.join("\n")
    );
}

#[test]
fn a_table_of_another_function_still_estimates_the_reference() {
    // The ratio p/q is what keeps an estimate unbiased, not the table's
    // likeness: HG g = 0.5 drawn through the table of HG g = 0.9 (q/p from
    // 0.13 at θ = π to 32 at θ = 0) still estimates HG 0.5's integral;
    // without the ratio the estimate is 10 % low here (measured with
    // mutation 74: −423 standard errors).
    const SAMPLES: usize = 200_000;
    let z = z_bound();
    let p = PhaseSpec::Hg(0.5).build::<f64>();
    let other = PhaseSpec::Hg(0.9).build::<f64>();
    let table = InverseCdf::new(&*other).unwrap();
    let (x0, x2) = (DVec3::new(0.2, -0.3, 0.1), DVec3::new(0.9, 0.4, 0.6));
    let c = Connection::new(x0, x2, 2.5).unwrap();
    let problem = PointToPoint::new(c, Homogeneous::new(0.4, 0.1).unwrap(), None).unwrap();
    let want = problem.integral(&&*p);
    let omnee = Omnee::new(c, TableSampled::new(&*p, &table));
    let mut stream = Rng::new(0xf0e);
    let (mean, se) = mean_and_error(SAMPLES, || {
        Draw::single(&omnee, || stream.uniform()).sum(|s| problem.estimate(s))
    });
    let dev = (mean - want) / se;
    println!("HG 0.5 through HG 0.9's table: {mean:.6e} ± {se:.1e} vs {want:.6e} ({dev:+.2} σ)");
    assert!(dev.abs() < z, "{mean:e} ± {se:e} vs {want:e}");
}

#[test]
fn f32_tables_agree_with_f64_tables() {
    // Both tables are built from the same (f32-representable) parameters;
    // they differ by the f32 rounding of the cdf they invert at the nodes
    // (a few 1e-7 of u, i.e. ~N·3e-7 = 4e-5 of a bin's width) and of their
    // coefficients. Measured worst over the specs: θ 4.1e-6 relative, q and
    // p/q 1.5e-4 (HG 0.98); the bounds are 10× those. A wrong table formula
    // moves q by O(1).
    for spec in SPECS {
        let spec32 = spec.rounded_to_f32();
        let (p32, t32) = tabled::<f32>(spec32);
        let (p64, t64) = tabled::<f64>(spec32);
        let (s32, s64) = (
            TableSampled::new(&*p32, &t32),
            TableSampled::new(&*p64, &t64),
        );
        let (mut theta, mut q, mut ratio) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..4096 {
            let u = (i as f32 + 0.5) / 4096.0;
            let (a, qa, ra) = s32.sample_ratio(u);
            let (b, qb, rb) = s64.sample_ratio(u as f64);
            let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-300);
            // θ below f32's normal range is not representable.
            if b.one_minus_cos > 1e-30 {
                theta = theta.max(rel(a.theta as f64, b.theta));
                q = q.max(rel(qa as f64, qb));
                ratio = ratio.max(rel(ra as f64, rb));
            }
        }
        println!("f32 vs f64 table {spec:?}: θ {theta:.1e}, q {q:.1e}, p/q {ratio:.1e}");
        assert!(
            theta < 4e-5 && q < 1.5e-3 && ratio < 1.5e-3,
            "{spec:?}: θ {theta:e}, q {q:e}, p/q {ratio:e}"
        );
    }
}

#[test]
fn fitted_ratios_are_exact_to_the_precision() {
    // A table's ratio p/q comes from a degree-6 polynomial per bin (or two
    // quadratics about a jump) where that is within 4 ε of p · (1/q)
    // evaluated at the bin's 33 check points; here
    // it is checked between them, at 2¹⁷ stratified u against p · (1/q)
    // computed in f64 from the same deflection and 1/q. Measured worst:
    // 6.9 ε (f32, the random measured table); a wrong coefficient or node moves the ratio by far
    // more than 8 ε, and a fit used without its check (FF's bins next to
    // the peak) by ~1e-3.
    let counts32 = fits_are_exact::<f32>();
    let counts64 = fits_are_exact::<f64>();
    // In f32 the smooth phase functions are fitted nearly everywhere (bin 0
    // never is); f64 fits only where a degree-6 polynomial reaches 4 ε.
    for (spec, least) in [
        (PhaseSpec::Ff(0.0183, 1.10), 120),
        (PhaseSpec::Mie(10.0), 110),
        (PhaseSpec::Rayleigh, 126),
        (PhaseSpec::Draine(0.6, 1.0), 120),
        // Its jumps: two quadratics per bin (122 with one polynomial).
        (PhaseSpec::Tabulated(3), 125),
    ] {
        let i = SPECS.iter().position(|&s| s == spec).unwrap();
        assert!(
            counts32[i] >= least,
            "{spec:?}: only {} bins fitted",
            counts32[i]
        );
        assert!(counts64[i] <= counts32[i], "{spec:?}");
    }
    // Another function's table: its fits are not this p's, so p is
    // evaluated (the fingerprint differs).
    let p = PhaseSpec::Hg(0.5).build::<f32>();
    let other = InverseCdf::new(&*PhaseSpec::Hg(0.9).build::<f32>()).unwrap();
    assert!(other.fitted_bins() > 0);
    assert!(!TableSampled::new(&*p, &other).uses_fits());
}

/// The densest check of [`fitted_ratios_are_exact_to_the_precision`] for
/// tables in `F`; returns the number of fitted bins per spec.
fn fits_are_exact<F: Real>() -> Vec<usize> {
    const M: usize = 1 << 17;
    let eps = F::EPSILON.to_f64();
    let mut counts = Vec::new();
    for spec in SPECS {
        let spec = spec.rounded_to_f32();
        let (phase, table) = tabled::<F>(spec);
        let sampled = TableSampled::new(&*phase, &table);
        assert!(
            sampled.uses_fits() == (table.fitted_bins() > 0),
            "{spec:?}: its own fits unused"
        );
        let mut worst = 0.0f64;
        for i in 0..M {
            let u = F::from_f64((i as f64 + 0.5) / M as f64);
            let (d, _, ratio) = sampled.sample_ratio(u);
            let (d_table, inverse_pdf) = table.sample_inverse_pdf(u);
            assert_eq!(d, d_table);
            let want = phase.eval(d).to_f64() * inverse_pdf.to_f64();
            if want > 0.0 && want < F::MAX.to_f64() {
                worst = worst.max((ratio.to_f64() - want).abs() / (want * eps));
            }
        }
        println!(
            "fitted ratio {spec:?} ({}): {} of {} bins fitted, worst {worst:.2} ε",
            core::any::type_name::<F>(),
            table.fitted_bins(),
            INVERSE_CDF_BINS
        );
        assert!(worst <= 8.0, "{spec:?}: fitted ratio off by {worst:.1} ε");
        counts.push(table.fitted_bins());
    }
    counts
}

#[test]
fn table_sizes_are_the_documented_ones() {
    // The sizes InverseCdf's documentation states; HG-only builds do not
    // pay for tables: a `Phase` holds none.
    println!(
        "InverseCdf: {} B in f32, {} B in f64",
        core::mem::size_of::<InverseCdf<f32>>(),
        core::mem::size_of::<InverseCdf<f64>>()
    );
    assert_eq!(core::mem::size_of::<InverseCdf<f32>>(), 5696);
    assert_eq!(core::mem::size_of::<InverseCdf<f64>>(), 11344);
    assert!(
        core::mem::size_of::<TableSampled<'static, f32, Phase<'static, f32>>>()
            <= core::mem::size_of::<Phase<'static, f32>>() + 16
    );
    // A table is built in bounded time and refuses nothing valid: every
    // spec of the suite, and a one-bin table.
    let mut cdf = [0.0f64; 2];
    let flat = Tabulated::new(&[0.0, PI], &[1.0], &mut cdf).unwrap();
    assert!(InverseCdf::new(&flat).is_ok());
}
