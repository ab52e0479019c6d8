//! Bridges of k scattering vertices (docs/math.md §14): the estimate of
//! `I_k` against the isotropic closed form (k = 1 … 8) and against an
//! independent estimator of `I_2` (any phase function), the density against
//! the Jacobian of the map from the uniform numbers, χ² fits of the
//! density's projections and of the sampled number of vertices, the inverse,
//! f32 against f64, the closed-form weight against the kernel over the
//! density at the points, and finiteness at extreme inputs.
//!
//! Tolerance. Each comparison of two Monte Carlo means (or of one with an
//! exact value) is studentized with the estimated standard errors; the
//! family of `FAMILY` comparisons uses the Šidák bound for a family false
//! failure rate of 1e-4, z ≈ 4.7 (never below 4.5). The bridge's estimate
//! `σs^k e^{−σt D} D^{k+1}/(s³ k!)` is bounded by its maximum over D,
//! `σs^k ((k+1)/(e σt))^{k+1}/(s³ k!)`. The independent estimator of `I_2`
//! (OMNEE for the first vertex, the lobe module's MIS for the second) is
//! bounded but for OMNEE's θ/sin θ near θ = π, a logarithmically divergent
//! second moment still in the normal domain of attraction (as argued in
//! `unbiased.rs`). The configurations keep the relative variance below ~50
//! (σt s ≥ 1 for k ≥ 3, where the bridges of many vertices have their heavy
//! but bounded tails), so that with 2·10⁵ samples the studentized mean is
//! close to normal at z ≈ 4.7.

use crate::harness::{Frame, Rng, chi2, integrate_box, normal_two_sided_quantile, sidak};
use glam::{DVec3, Vec3};
use omnee::bridge::{Bridge, MAX_VERTICES, REFERENCE_BUDGET, VertexCount, isotropic_transfer};
use omnee::lobe::{LobeMis, PhaseLobe};
use omnee::medium::Homogeneous;
use omnee::phase::{Deflection, HenyeyGreenstein, Isotropic, PhaseFunction};
use omnee::reference::PointToPoint;
use omnee::sampling::{Connection, Omnee, Technique};
use std::f64::consts::PI;

/// The comparisons of means in this file: 8 orders × 2 media against the
/// closed form, 4 g × 4 σt·s against the independent estimator, and 3
/// orders of the density's expectation.
const FAMILY: usize = 16 + 16 + 3;

/// The studentized bound for the family.
fn z_bound() -> f64 {
    normal_two_sided_quantile(sidak(1e-4, FAMILY)).max(4.5)
}

/// Mean and standard error of `n` draws of `draw`.
fn mean_and_error(n: usize, mut draw: impl FnMut() -> f64) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let x = draw();
        assert!(x.is_finite() && x >= 0.0, "estimate {x}");
        sum += x;
        sum2 += x * x;
    }
    let mean = sum / n as f64;
    let variance = (sum2 / n as f64 - mean * mean).max(0.0) * n as f64 / (n - 1) as f64;
    (mean, (variance / n as f64).sqrt())
}

/// One bridge estimate of `I_k` from a generator's numbers.
fn bridge_estimate<P: PhaseFunction<f64>>(
    bridge: &Bridge<f64, P>,
    medium: &Homogeneous<f64>,
    k: usize,
    rng: &mut Rng,
) -> f64 {
    let mut u = [[0.0; 3]; MAX_VERTICES];
    let mut x = [DVec3::ZERO; MAX_VERTICES];
    for ui in u[..k].iter_mut() {
        *ui = rng.u3();
    }
    match bridge.sample(&u[..k], &mut x) {
        Some(sample) => bridge.estimate(&sample, medium),
        None => 0.0,
    }
}

#[test]
fn isotropic_closed_form_of_one_vertex_is_the_quadrature_reference() {
    // I_1 through the Fourier transform against the circumcircle quadrature
    // of docs/math.md §5, over optical depths and albedos.
    for &(s, sigma_s, sigma_t) in &[
        (1.0, 0.05, 0.1),
        (2.0, 0.5, 0.5),
        (0.3, 2.0, 3.0),
        (5.0, 1.2, 2.0),
    ] {
        let c = Connection::new(DVec3::ZERO, DVec3::new(0.3, -0.4, s), PI).unwrap();
        let s = c.axis.s;
        let medium = Homogeneous::from_extinction(sigma_s, sigma_t).unwrap();
        let quadrature = PointToPoint::new(c, medium, None)
            .unwrap()
            .integral(&Isotropic);
        let closed = isotropic_transfer(1, s, sigma_s, sigma_t, REFERENCE_BUDGET).unwrap();
        assert!(
            (closed / quadrature - 1.0).abs() < 1e-9,
            "s {s} σs {sigma_s} σt {sigma_t}: {closed:e} vs {quadrature:e}"
        );
    }
}

#[test]
fn isotropic_bridges_match_the_closed_form_for_one_to_eight_vertices() {
    let z_max = z_bound();
    let mut rng = Rng::new(0xb1d6e);
    let x2 = DVec3::new(0.5, 1.0, -1.5);
    let s = x2.length();
    let bridge = Bridge::new(DVec3::ZERO, x2, Isotropic).unwrap();
    for &(tau, albedo) in &[(1.0, 0.8), (4.0, 0.95)] {
        let sigma_t = tau / s;
        let medium = Homogeneous::from_extinction(albedo * sigma_t, sigma_t).unwrap();
        for k in 1..=8 {
            let exact =
                isotropic_transfer(k, s, albedo * sigma_t, sigma_t, REFERENCE_BUDGET).unwrap();
            let (mean, error) =
                mean_and_error(200_000, || bridge_estimate(&bridge, &medium, k, &mut rng));
            let z = (mean - exact) / error;
            println!("τ {tau} k {k}: {mean:.6e} ± {error:.1e} vs {exact:.6e} (z {z:+.2})");
            assert!(z.abs() < z_max, "τ {tau} k {k}: z = {z}");
        }
    }
}

/// An estimate of `I_2` independent of the bridge: the first vertex `xa` by
/// OMNEE between `x0` and `x2` (as if it were the only one; θmax = π,
/// docs/math.md §3), then the second `xb` by the lobe module's recommended
/// technique between `xa` and `x2` with the phase function about the
/// incoming direction as `xa`'s lobe (docs/math.md §12), which samples both
/// phase functions of the inner integral. With OMNEE's weight
/// `w_a = p(θ'_a)/(d1² |x2 − xa|²) / pdf_a` (θ'_a the deflection of
/// `x0 → xa → x2`) and the lobe's `w_b = p(θ_a) p(θ_b)/(d2² d3²) / pdf_b`:
///
/// `σs² e^{−σt D} · w_a |x2 − xa|² / p(θ'_a) · w_b`.
fn independent_twice_scattered(
    phase: &HenyeyGreenstein<f64>,
    medium: &Homogeneous<f64>,
    x0: DVec3,
    x2: DVec3,
    rng: &mut Rng,
) -> f64 {
    let outer = Connection::new(x0, x2, PI).unwrap();
    let Some(a) = Omnee::new(outer, *phase).sample(rng.u3()) else {
        return 0.0;
    };
    let Some((theta_a, d1, d_a2)) = outer.deflection(a.x1) else {
        return 0.0;
    };
    let Ok(inner) = Connection::new(a.x1, x2, PI) else {
        return 0.0;
    };
    let Ok(lobe) = PhaseLobe::new(*phase, (a.x1 - x0) / d1) else {
        return 0.0;
    };
    let Some(b) = LobeMis::recommended(inner, lobe, *phase).sample(rng.u3()) else {
        return 0.0;
    };
    let p_a = phase.eval(theta_a);
    if !(p_a > 0.0 && b.weight > 0.0) {
        return 0.0;
    }
    let length = d1 + (b.x1 - a.x1).length() + (x2 - b.x1).length();
    medium.sigma_s().powi(2) * (-medium.sigma_t() * length).exp() * a.weight * d_a2 * d_a2 / p_a
        * b.weight
}

#[test]
fn twice_scattered_bridges_match_an_independent_estimator() {
    let z_max = z_bound();
    let mut rng = Rng::new(0x2b1d6e);
    let (x0, x2) = (DVec3::new(0.2, -0.1, 0.3), DVec3::new(-0.4, 0.9, 1.5));
    let s = (x2 - x0).length();
    for g in [0.0, 0.5, 0.9, 0.98] {
        let hg = HenyeyGreenstein::new(g).unwrap();
        let bridge = Bridge::new(x0, x2, hg).unwrap();
        for tau in [0.1, 0.7, 3.0, 10.0] {
            let sigma_t = tau / s;
            let medium = Homogeneous::from_extinction(0.9 * sigma_t, sigma_t).unwrap();
            let n = 200_000;
            let (b, be) = mean_and_error(n, || bridge_estimate(&bridge, &medium, 2, &mut rng));
            let (r, re) = mean_and_error(n, || {
                independent_twice_scattered(&hg, &medium, x0, x2, &mut rng)
            });
            let z = (b - r) / (be * be + re * re).sqrt();
            println!(
                "g {g} σt·s {tau}: bridge {b:.5e} ± {be:.1e}, independent {r:.5e} ± {re:.1e} (z {z:+.2})"
            );
            assert!(z.abs() < z_max, "g {g} τ {tau}: z = {z}");
        }
    }
}

#[test]
fn the_density_is_the_inverse_jacobian_of_the_map_from_uniform_numbers() {
    // pdf(X) |det ∂X/∂u| = 1 for the injective map u ∈ [0,1)^{3k} → X ∈ R^{3k}
    // (docs/math.md §14.4): central differences in f64, LU with pivoting.
    let mut rng = Rng::new(0x1ac0b);
    let (x0, x2) = (DVec3::new(1.0, 0.0, -0.5), DVec3::new(-0.2, 0.7, 0.4));
    let mut worst = 0.0f64;
    for (g, k) in [(0.0, 1), (0.6, 1), (0.6, 2), (-0.3, 3), (0.8, 5)] {
        let bridge = Bridge::new(x0, x2, HenyeyGreenstein::new(g).unwrap()).unwrap();
        let mut tested = 0;
        while tested < 20 {
            let mut u = [[0.0; 3]; 8];
            for ui in u[..k].iter_mut() {
                *ui = [
                    rng.range(0.02, 0.98),
                    rng.range(0.02, 0.98),
                    rng.range(0.02, 0.98),
                ];
            }
            let mut x = [DVec3::ZERO; 8];
            let Some(sample) = bridge.sample(&u[..k], &mut x) else {
                continue;
            };
            if sample.length > 20.0 * (x2 - x0).length() {
                continue; // a nearly closed chain: differences too stiff
            }
            let n = 3 * k;
            let mut jacobian = vec![vec![0.0; n]; n];
            let h = 1e-6;
            for col in 0..n {
                let point = |delta: f64| {
                    let mut v = u;
                    v[col / 3][col % 3] += delta;
                    let mut y = [DVec3::ZERO; 8];
                    bridge.sample(&v[..k], &mut y).expect("neighbour");
                    y
                };
                let (plus, minus) = (point(h), point(-h));
                for row in 0..n {
                    let (a, b) = (
                        plus[row / 3].to_array()[row % 3],
                        minus[row / 3].to_array()[row % 3],
                    );
                    jacobian[row][col] = (a - b) / (2.0 * h);
                }
            }
            let det = determinant(jacobian).abs();
            let product = sample.pdf * det;
            worst = worst.max((product - 1.0).abs());
            assert!(
                (product - 1.0).abs() < 1e-5,
                "g {g} k {k}: pdf·|J| = {product}"
            );
            // The density recomputed from the points is the sampled one.
            let again = bridge.pdf(&x[..k]);
            assert!(
                (again / sample.pdf - 1.0).abs() < 1e-9,
                "{again} vs {}",
                sample.pdf
            );
            tested += 1;
        }
    }
    println!("worst |pdf·|det J| − 1| = {worst:.1e}");
}

/// The determinant by Gaussian elimination with partial pivoting.
fn determinant(mut a: Vec<Vec<f64>>) -> f64 {
    let n = a.len();
    let mut det = 1.0;
    for c in 0..n {
        let p = (c..n)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        if p != c {
            a.swap(p, c);
            det = -det;
        }
        det *= a[c][c];
        let (top, rest) = a.split_at_mut(c + 1);
        let pivot = &top[c];
        for row in rest {
            let f = row[c] / pivot[c];
            for (x, &y) in row[c..].iter_mut().zip(&pivot[c..]) {
                *x -= f * y;
            }
        }
    }
    det
}

#[test]
fn the_density_integrates_the_kernel() {
    // E[κ(X)/pdf(X)] with both evaluated from the points (not the sampler's
    // closed-form weight) is ∫ κ: the isotropic I_k without σs (albedo 1).
    let z_max = z_bound();
    let mut rng = Rng::new(0xde9);
    let x2 = DVec3::new(0.0, 0.0, 1.3);
    let bridge = Bridge::new(DVec3::ZERO, x2, Isotropic).unwrap();
    let sigma_t = 1.5;
    for k in 1..=3 {
        let exact = isotropic_transfer(k, 1.3, sigma_t, sigma_t, REFERENCE_BUDGET).unwrap();
        let (mean, error) = mean_and_error(200_000, || {
            let mut u = [[0.0; 3]; 3];
            for ui in u[..k].iter_mut() {
                *ui = rng.u3();
            }
            let mut x = [DVec3::ZERO; 3];
            let Some(sample) = bridge.sample(&u[..k], &mut x) else {
                return 0.0;
            };
            let pdf = bridge.pdf(&x[..k]);
            let kernel = bridge.kernel(&x[..k]);
            sigma_t.powi(k as i32) * (-sigma_t * sample.length).exp() * kernel / pdf
        });
        let z = (mean - exact) / error;
        assert!(z.abs() < z_max, "k {k}: {mean:e} ± {error:e} vs {exact:e}");
    }
}

#[test]
fn one_vertex_density_fits_its_samples_chi2() {
    // The (θ, β/θ) histogram of the one-vertex bridge against its density
    // 2π p(θ) θ sin²θ / (sin α + sin β)² in those coordinates (docs/math.md
    // §14.8), from the suite's own frame, integrated over each cell.
    let (x0, x2) = (DVec3::new(0.1, 0.2, 0.3), DVec3::new(1.1, -0.5, 0.9));
    let frame = Frame::new(x0, x2);
    for (seed, g) in [(1u64, 0.0), (2, 0.7), (3, -0.5)] {
        let hg = HenyeyGreenstein::new(g).unwrap();
        let bridge = Bridge::new(x0, x2, hg).unwrap();
        let (bins_t, bins_r) = (24, 12);
        let n = 400_000;
        let mut rng = Rng::new(seed);
        let mut observed = vec![0.0; bins_t * bins_r];
        for _ in 0..n {
            if let Some(s) = Technique::sample(&bridge, rng.u3()) {
                let (theta, r, _) = frame.angles(s.x1);
                let i = ((theta / PI * bins_t as f64) as usize).min(bins_t - 1);
                let j = ((r * bins_r as f64) as usize).min(bins_r - 1);
                observed[i * bins_r + j] += 1.0;
            }
        }
        let density = |t: f64, r: f64| {
            let (beta, alpha) = (r * t, (1.0 - r) * t);
            let p = hg.eval(Deflection::from_theta(t));
            2.0 * PI * p * t * t.sin().powi(2) / (alpha.sin() + beta.sin()).powi(2)
        };
        let mut expected = vec![0.0; bins_t * bins_r];
        let mut total = 0.0;
        for i in 0..bins_t {
            for j in 0..bins_r {
                let lo = [PI * i as f64 / bins_t as f64, j as f64 / bins_r as f64, 0.0];
                let hi = [
                    PI * (i + 1) as f64 / bins_t as f64,
                    (j + 1) as f64 / bins_r as f64,
                    1.0,
                ];
                let mut f = |x: [f64; 3]| density(x[0], x[1]);
                let e = integrate_box(&mut f, lo, hi, n as f64, 8, 0);
                expected[i * bins_r + j] = e * n as f64;
                total += e;
            }
        }
        assert!(
            (total - 1.0).abs() < 1e-4,
            "g {g}: the density integrates to {total}"
        );
        let result = chi2(&observed, &expected, 1e-6).unwrap();
        assert!(
            result.p_value > sidak(1e-4, 3),
            "g {g}: χ² {} dof {} p {:e}, worst {:?}",
            result.statistic,
            result.dof,
            result.p_value,
            result.worst
        );
    }
}

#[test]
fn deflections_and_proportions_of_a_long_bridge_fit_chi2() {
    // The rotation and scale keep every deflection and the edges'
    // proportions: θ_1 and θ_k follow the phase function, d_1/D and
    // d_{k+1}/D the simplex's marginal Beta(1, k): P(t ≤ x) = 1 − (1 − x)^k.
    let (x0, x2) = (DVec3::new(-1.0, 0.5, 0.0), DVec3::new(0.5, 0.0, 2.0));
    let hg = HenyeyGreenstein::new(0.8).unwrap();
    let bridge = Bridge::new(x0, x2, hg).unwrap();
    let k = 5;
    let bins = 40;
    let n = 200_000;
    let mut rng = Rng::new(77);
    let mut observed = [
        vec![0.0; bins],
        vec![0.0; bins],
        vec![0.0; bins],
        vec![0.0; bins],
    ];
    for _ in 0..n {
        let mut u = [[0.0; 3]; 5];
        for ui in u.iter_mut() {
            *ui = rng.u3();
        }
        let mut x = [DVec3::ZERO; 5];
        let Some(sample) = bridge.sample(&u, &mut x) else {
            continue;
        };
        let path = [x0, x[0], x[1], x[2], x[3], x[4], x2];
        let theta = |i: usize| {
            let (a, b) = (path[i] - path[i - 1], path[i + 1] - path[i]);
            Deflection::between(a.normalize(), b.normalize())
        };
        let cdf_bin = |c: f64| ((c * bins as f64) as usize).min(bins - 1);
        observed[0][cdf_bin(hg.cdf(theta(1)))] += 1.0;
        observed[1][cdf_bin(hg.cdf(theta(k)))] += 1.0;
        let first = (path[1] - path[0]).length() / sample.length;
        let last = (path[k + 1] - path[k]).length() / sample.length;
        let beta = |t: f64| 1.0 - (1.0 - t).powi(k as i32);
        observed[2][cdf_bin(beta(first))] += 1.0;
        observed[3][cdf_bin(beta(last))] += 1.0;
    }
    let expected = vec![n as f64 / bins as f64; bins];
    for (name, o) in ["θ_1", "θ_k", "d_1/D", "d_(k+1)/D"].iter().zip(&observed) {
        let r = chi2(o, &expected, 1e-9).unwrap();
        assert!(
            r.p_value > sidak(1e-4, 4),
            "{name}: χ² {} p {:e}",
            r.statistic,
            r.p_value
        );
    }
}

#[test]
fn the_number_of_vertices_follows_its_probabilities_chi2() {
    let mut rng = Rng::new(4);
    for (s, sigma_s, sigma_t, g, k_max) in [
        (1.0, 0.5, 0.6, 0.9, 8),
        (3.0, 2.0, 2.0, 0.0, 8),
        (0.2, 0.1, 0.1, 0.5, 16),
    ] {
        let count = VertexCount::<f64>::new(k_max, s, sigma_s, sigma_t, g).unwrap();
        let total: f64 = (1..=k_max).map(|k| count.pmf(k)).sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        assert!(count.pmf(0) == 0.0 && count.pmf(k_max + 1) == 0.0);
        let n = 100_000;
        let mut observed = vec![0.0; k_max];
        for _ in 0..n {
            let (k, p) = count.sample(rng.uniform());
            assert_eq!(p, count.pmf(k));
            observed[k - 1] += 1.0;
        }
        let expected: Vec<f64> = (1..=k_max).map(|k| n as f64 * count.pmf(k)).collect();
        let r = chi2(&observed, &expected, 1e-9).unwrap();
        assert!(
            r.p_value > sidak(1e-4, 3),
            "μ {}: χ² {} p {:e}",
            count.mean(),
            r.statistic,
            r.p_value
        );
    }
}

#[test]
fn the_sum_over_sampled_orders_matches_the_closed_forms() {
    // Σ_{k=1}^{8} I_k for an isotropic medium, drawing k from VertexCount:
    // the estimate divided by P(k) is unbiased for the sum.
    let mut rng = Rng::new(0x5a11);
    let x2 = DVec3::new(0.0, 1.0, 1.0);
    let s = x2.length();
    let bridge = Bridge::new(DVec3::ZERO, x2, Isotropic).unwrap();
    let (sigma_s, sigma_t) = (1.2, 1.5);
    let medium = Homogeneous::from_extinction(sigma_s, sigma_t).unwrap();
    let count = VertexCount::<f64>::new(8, s, sigma_s, sigma_t, 0.0).unwrap();
    let exact: f64 = (1..=8)
        .map(|k| isotropic_transfer(k, s, sigma_s, sigma_t, REFERENCE_BUDGET).unwrap())
        .sum();
    let (mean, error) = mean_and_error(200_000, || {
        let (k, p) = count.sample(rng.uniform());
        bridge_estimate(&bridge, &medium, k, &mut rng) / p
    });
    let z = (mean - exact) / error;
    assert!(z.abs() < 4.5, "{mean:e} ± {error:e} vs {exact:e}");
}

#[test]
fn invert_recovers_the_uniform_numbers() {
    let mut rng = Rng::new(9);
    let (x0, x2) = (DVec3::new(0.0, 2.0, 0.0), DVec3::new(1.0, -1.0, 3.0));
    let bridge = Bridge::new(x0, x2, HenyeyGreenstein::new(0.6).unwrap()).unwrap();
    let mut worst = 0.0f64;
    for k in [1, 2, 4, 8] {
        for _ in 0..2000 {
            let mut u = [[0.0; 3]; 8];
            for ui in u[..k].iter_mut() {
                *ui = [
                    rng.range(0.01, 0.99),
                    rng.range(0.01, 0.99),
                    rng.range(0.01, 0.99),
                ];
            }
            let mut x = [DVec3::ZERO; 8];
            let Some(sample) = bridge.sample(&u[..k], &mut x) else {
                continue;
            };
            if sample.length > 100.0 {
                continue; // nearly closed chains keep fewer digits
            }
            let mut back = [[0.0; 3]; 8];
            bridge.invert(&x[..k], &mut back[..k]).expect("invertible");
            for (a, b) in u[..k].iter().zip(&back[..k]) {
                for m in 0..3 {
                    // Turns wrap around at 1.
                    let d = (a[m] - b[m]).abs();
                    worst = worst.max(d.min(1.0 - d));
                }
            }
        }
    }
    assert!(worst < 1e-8, "worst {worst:e}");
}

#[test]
fn the_weight_is_the_kernel_over_the_density_at_the_points() {
    // BridgeSample::weight, (p/q) D^{k+1}/(s³ k!) in closed form, is the
    // kernel Π p/Π d² over the density, both evaluated from the points
    // (Bridge::kernel, Bridge::pdf), and BridgeSample::pdf is that density:
    // a factor lost from the closed form (k!, a power of D or s) shows.
    let mut rng = Rng::new(0x3e19);
    let (x0, x2) = (DVec3::new(0.5, -1.0, 0.25), DVec3::new(-0.25, 1.5, 2.0));
    let bridge = Bridge::new(x0, x2, HenyeyGreenstein::new(0.7).unwrap()).unwrap();
    let mut worst = 0.0f64;
    for k in [1, 2, 3, 5, 8, 13] {
        for _ in 0..500 {
            let mut u = [[0.0; 3]; MAX_VERTICES];
            for ui in u[..k].iter_mut() {
                *ui = [
                    rng.range(0.01, 0.99),
                    rng.range(0.01, 0.99),
                    rng.range(0.01, 0.99),
                ];
            }
            let mut x = [DVec3::ZERO; MAX_VERTICES];
            let Some(sample) = bridge.sample(&u[..k], &mut x) else {
                continue;
            };
            if sample.length > 100.0 {
                continue; // nearly closed chains keep fewer digits
            }
            let (kernel, pdf) = (bridge.kernel(&x[..k]), bridge.pdf(&x[..k]));
            assert!(kernel > 0.0 && pdf > 0.0, "k = {k}");
            worst = worst
                .max((sample.weight * pdf / kernel - 1.0).abs())
                .max((sample.pdf / pdf - 1.0).abs());
        }
    }
    // Measured 7.7e-13 (f64); a dropped k! is off by a factor ≥ 2.
    assert!(worst < 1e-9, "worst relative deviation {worst:e}");
}

#[test]
fn f32_bridges_follow_f64_bridges() {
    // Same uniform numbers: each vertex within 64 k ε32 D of the f64 one
    // (D the path's length: the chain is built in unit-length proportions
    // and scaled by D), weights within 64 k ε32 relative.
    let mut rng = Rng::new(0xf32);
    let (x0, x2) = (DVec3::new(0.25, -0.5, 1.0), DVec3::new(1.5, 0.5, -0.75));
    let mut worst = (0.0f64, 0.0f64);
    for g in [0.0, 0.9, 0.99] {
        let b64 = Bridge::new(x0, x2, HenyeyGreenstein::new(g).unwrap()).unwrap();
        let b32 = Bridge::new(
            x0.as_vec3(),
            x2.as_vec3(),
            HenyeyGreenstein::new(g as f32).unwrap(),
        )
        .unwrap();
        for k in 1..=8 {
            for _ in 0..2000 {
                let mut u32s = [[0.0f32; 3]; 8];
                for ui in u32s[..k].iter_mut() {
                    *ui = rng.u3::<f32>();
                }
                let u64s = u32s.map(|v| v.map(f64::from));
                let (mut x32, mut x64) = ([Vec3::ZERO; 8], [DVec3::ZERO; 8]);
                let (Some(a), Some(b)) = (
                    b32.sample(&u32s[..k], &mut x32),
                    b64.sample(&u64s[..k], &mut x64),
                ) else {
                    continue;
                };
                if b.length > 1e3 {
                    continue; // a chain closing on itself: |y| loses digits
                }
                let eps = f32::EPSILON as f64 * k as f64;
                for i in 0..k {
                    let d = (x32[i].as_dvec3() - x64[i]).length() / (eps * b.length);
                    worst.0 = worst.0.max(d);
                }
                let w = (a.weight as f64 / b.weight - 1.0).abs() / eps;
                worst.1 = worst.1.max(w);
            }
        }
    }
    println!(
        "worst vertex error {:.1} k ε32 D, weight {:.1} k ε32",
        worst.0, worst.1
    );
    assert!(worst.0 < 64.0 && worst.1 < 64.0, "{worst:?}");
}

#[test]
fn extreme_inputs_never_give_nan_or_infinity() {
    let extremes = [
        0.0f32,
        1e-30,
        1e-7,
        0.5,
        1.0 - 1e-7,
        1.0 - f32::EPSILON / 2.0,
    ];
    let mut rng = Rng::new(0x57e55);
    for s in [1e-6f32, 1.0, 1e6] {
        for g in [0.0f32, 0.9999, -0.9999] {
            let bridge = Bridge::new(
                Vec3::ZERO,
                Vec3::new(0.0, s * 0.6, s * 0.8),
                HenyeyGreenstein::new(g).unwrap(),
            )
            .unwrap();
            for (sigma_s, sigma_t) in [
                (0.0f32, 0.0f32),
                (1e-6 / s, 1e-6 / s),
                (1.0, 1.0),
                (1e3 / s, 1e3 / s),
            ] {
                let medium = Homogeneous::from_extinction(sigma_s, sigma_t).unwrap();
                for k in [1, 2, 8, MAX_VERTICES] {
                    for trial in 0..400 {
                        let mut u = [[0.0f32; 3]; MAX_VERTICES];
                        for ui in u[..k].iter_mut() {
                            *ui = if trial % 2 == 0 {
                                [0, 1, 2].map(|_| extremes[(rng.next_u64() % 6) as usize])
                            } else {
                                rng.u3()
                            };
                        }
                        let mut x = [Vec3::ZERO; MAX_VERTICES];
                        if let Some(b) = bridge.sample(&u[..k], &mut x) {
                            let e = bridge.estimate(&b, &medium);
                            assert!(b.pdf.is_finite() && b.pdf >= 0.0, "{b:?}");
                            assert!(b.weight.is_finite() && b.weight >= 0.0, "{b:?}");
                            assert!(
                                b.length.is_finite() && e.is_finite() && e >= 0.0,
                                "{b:?} {e}"
                            );
                            assert!(x[..k].iter().all(|v| v.is_finite()));
                            let p = bridge.pdf(&x[..k]);
                            let kern = bridge.kernel(&x[..k]);
                            assert!(p.is_finite() && p >= 0.0 && kern.is_finite() && kern >= 0.0);
                        }
                    }
                }
            }
        }
    }
}
