//! Properties over random valid inputs (proptest, shrinking on, fixed seed).
//!
//! Tolerances (f64): quantities recomputed from a sampled point carry the
//! rounding of the point, about ε(|x0| + s) absolute in each coordinate, i.e.
//! a relative error of ε(|x0| + s)/min(d1, d2) in the distances and angles at
//! the end points. Inputs here keep |x0| + s ≤ 20 and the strategies keep
//! the uniform numbers 1e-6 away from the edges, so min(d1, d2) ≳ 1e-6 s and
//! the worst relative error is ~1e-9; a density whose log-derivative in θ is
//! at most 1/(1 − |g|) ≤ 200 turns that into ≤ 2e-7. The checks use 1e-6
//! (relative) or that bound scaled by the local conditioning where stated.
//! A wrong formula misses by O(1), far outside.

use crate::harness::{PhaseSpec, integrate_pieces};
use glam::DVec3;
use omnee::medium::Region;
use omnee::mis::{Heuristic, OmneeMis, OneSample, multi_sample_weight};
use omnee::phase::{Deflection, PhaseFunction};
use omnee::quadrature::{integrate, integrate_geometric};
use omnee::sampling::{Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x6f6d_6e65_6506),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Every phase function family with parameters from its whole valid range
/// (|g| ≤ 0.995; the stability tests go to 0.9999).
fn phase_spec() -> impl Strategy<Value = PhaseSpec> {
    let g = -0.995..0.995f64;
    prop_oneof![
        Just(PhaseSpec::Isotropic),
        Just(PhaseSpec::Rayleigh),
        g.clone().prop_map(PhaseSpec::Hg),
        (g.clone(), g.clone(), 0.0..=1.0f64).prop_map(|(a, b, w)| PhaseSpec::TwoTerm(a, b, w)),
        (g, 0.0..=1000.0f64).prop_map(|(g, a)| PhaseSpec::Draine(g, a)),
        (0.001..0.499f64, 1.001..1.5f64).prop_map(|(b, n)| PhaseSpec::Ff(b, n)),
        (0.1..50.0f64).prop_map(PhaseSpec::Mie),
        any::<u64>().prop_map(PhaseSpec::Tabulated),
    ]
}

fn point() -> impl Strategy<Value = DVec3> {
    (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// End points at least 0.05 apart.
fn ends() -> impl Strategy<Value = (DVec3, DVec3)> {
    (point(), point()).prop_filter("x0 and x2 apart", |(a, b)| (*a - *b).length() > 0.05)
}

/// A uniform number away from the edges where the map degenerates (θ = 0 is
/// covered by the stability tests).
fn unit() -> impl Strategy<Value = f64> {
    1e-6..(1.0 - 1e-6)
}

fn u3() -> impl Strategy<Value = [f64; 3]> {
    (unit(), unit(), unit()).prop_map(|(a, b, c)| [a, b, c])
}

/// How rays leave `x2`, and the medium region.
#[derive(Clone, Copy, Debug)]
struct Ray {
    cosine: Option<DVec3>,
    slab: Option<(f64, f64)>,
    sigma: f64,
}

fn ray() -> impl Strategy<Value = Ray> {
    (
        prop::option::of(point().prop_filter("non-zero", |n| n.length() > 1e-3)),
        prop::option::of((-3.0..3.0f64, 0.05..4.0f64).prop_map(|(lo, w)| (lo, lo + w))),
        0.05..5.0f64,
    )
        .prop_map(|(cosine, slab, sigma)| Ray {
            cosine,
            slab,
            sigma,
        })
}

impl Ray {
    fn directions(&self) -> Directions<f64> {
        self.cosine
            .map_or(Directions::Sphere, |n| Directions::cosine(n).unwrap())
    }
    fn region(&self) -> Region<f64> {
        self.slab
            .map_or(Region::Everywhere, |(lo, hi)| Region::slab(lo, hi).unwrap())
    }
}

/// `|a − b| ≤ tol · max(|a|, |b|)`.
fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs())
}

/// The relative spread of `p` over the deflections `θ ± 10 Δθ`: how much a
/// rounding `Δθ` in the recomputed angle may move a density. Bounded by
/// 20 Δθ/(1 − |g|) for HG, but unbounded for Fournier–Forand, whose forward
/// peak is singular.
fn spread<P: PhaseFunction<f64>>(p: &P, theta: f64, dtheta: f64) -> f64 {
    let at = |t: f64| p.eval(Deflection::from_theta(t.clamp(0.0, PI)));
    let mid = at(theta);
    let (lo, hi) = (at(theta - 10.0 * dtheta), at(theta + 10.0 * dtheta));
    let change = (lo - mid).abs().max((hi - mid).abs());
    if change == 0.0 {
        0.0 // constant there, zero included (an empty bin of a table)
    } else {
        change / mid // ∞ next to an empty bin: the check cannot tell
    }
}

/// The rounding of the deflection recomputed at the rounded point `x1`,
/// `Δθ ≈ 1e-15 (|x0| + |x2| + s)(1/d1 + 1/d2)` (the point's rounding over the
/// arms of the triangle).
fn rounding_dtheta(connection: &Connection<f64>, x1: DVec3) -> f64 {
    let axis = &connection.axis;
    let (d1, d2) = ((x1 - axis.x0).length(), (x1 - axis.x2).length());
    1e-15 * (axis.x0.length() + axis.x2.length() + axis.s) * (1.0 / d1 + 1.0 / d2)
}

/// The relative tolerance of a density or weight recomputed at the rounded
/// point `x1`: 1e-6 plus the phase function's spread over the rounding of
/// the deflection, `Δθ ≈ 1e-15 (|x0| + |x2| + s)(1/d1 + 1/d2)`.
fn recompute_tolerance<P: PhaseFunction<f64>>(
    connection: &Connection<f64>,
    phase: &P,
    x1: DVec3,
) -> f64 {
    let (d, _, _) = connection.deflection(x1).unwrap();
    1e-6 + spread(phase, d.theta, rounding_dtheta(connection, x1))
}

/// The checks every technique's sample must pass: finite, ≥ 0, `pdf(x1)`
/// equals the returned pdf, and (for the non-MIS techniques and balance MIS)
/// the weight equals `kernel(x1) / pdf(x1)`. Both sides recompute θ from
/// the rounded point `x1`, to `Δθ ≈ 1e-15 (|x0| + |x2| + s)(1/d1 + 1/d2)`:
/// the tolerance is 1e-6 plus the phase function's spread over that.
fn check_sample<P: PhaseFunction<f64>>(
    name: &str,
    t: &dyn Technique<f64>,
    connection: &Connection<f64>,
    phase: &P,
    u: [f64; 3],
    weight_is_kernel_over_pdf: bool,
) -> Result<(), TestCaseError> {
    let Some(s) = t.sample(u) else { return Ok(()) };
    check_vertex(
        name,
        &s,
        |x1| t.pdf(x1),
        connection,
        phase,
        weight_is_kernel_over_pdf,
    )
}

/// [`check_sample`]'s checks of one vertex `s` against a density `pdf`.
fn check_vertex<P: PhaseFunction<f64>>(
    name: &str,
    s: &Sample<f64>,
    pdf: impl Fn(DVec3) -> f64,
    connection: &Connection<f64>,
    phase: &P,
    weight_is_kernel_over_pdf: bool,
) -> Result<(), TestCaseError> {
    prop_assert!(
        s.x1.is_finite() && s.pdf.is_finite() && s.pdf > 0.0,
        "{name}: {s:?}"
    );
    prop_assert!(s.weight.is_finite() && s.weight >= 0.0, "{name}: {s:?}");
    if s.pdf == f64::MAX {
        return Ok(()); // saturated: the true density overflowed
    }
    let tol = recompute_tolerance(connection, phase, s.x1);
    let again = pdf(s.x1);
    prop_assert!(
        close(again, s.pdf, tol),
        "{name}: pdf(x1) = {again:e}, sample.pdf = {:e} (tol {tol:e})",
        s.pdf
    );
    if weight_is_kernel_over_pdf {
        let want = connection.kernel(phase, s.x1) / s.pdf;
        prop_assert!(
            close(s.weight, want, tol),
            "{name}: weight {:e}, kernel/pdf {want:e} (tol {tol:e})",
            s.weight
        );
    }
    Ok(())
}

/// Veach's heuristic `x^β / Σ_j y_j^β` for `x` among the `ys` (x one of
/// them), formed relative to the largest so that saturated densities
/// (`f64::MAX`) neither overflow nor give NaN; 0 where every `y` is 0.
fn heuristic_formula(x: f64, ys: &[f64], beta: i32) -> f64 {
    let m = ys.iter().copied().fold(0.0, f64::max);
    if !(m > 0.0) {
        return 0.0;
    }
    (x / m).powi(beta) / ys.iter().map(|y| (y / m).powi(beta)).sum::<f64>()
}

/// `|a − b|` on the circle of circumference 1 (φ/2π wraps).
fn circular(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

proptest! {
    #![proptest_config(config(400))]

    #[test]
    fn omnee_sample_pdf_weight_and_inverse_agree(
        (x0, x2) in ends(), theta_max in 0.05..=PI, spec in phase_spec(), u in u3()
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let t = Omnee::new(c, &*phase);
        check_sample("omnee", &t, &c, &&*phase, u, true)?;
        let Some(s) = t.sample(u) else { return Ok(()) };
        // The closed-form weight is θ / (s sin θ), bounded for θ < π.
        let theta = phase.sample(u[0]).theta;
        let s_len = (x2 - x0).length();
        prop_assert!(close(s.weight, theta / (s_len * theta.sin()), 1e-9), "{s:?}");
        if spec.inverse_cdf() {
            let back = t.invert(s.x1);
            prop_assert!(back.is_some(), "invert(sample({u:?})) = None");
            let back = back.unwrap();
            // The angles recomputed from the rounded x1 are off by about
            // Δθ = 1e-15 (|x0| + |x2| + s)(1/d1 + 1/d2) (the point's rounding
            // over the arms of the triangle).
            let (d1, d2) = ((s.x1 - x0).length(), (s.x1 - x2).length());
            let dtheta = 1e-15 * (x0.length() + x2.length() + s_len) * (1.0 / d1 + 1.0 / d2);
            // u0 = cdf(θ): off by at most the cdf's mass within θ ± 10 Δθ
            // (tiny except at a singular forward peak, Fournier–Forand).
            let mass = phase.cdf(Deflection::from_theta(theta + 10.0 * dtheta))
                - phase.cdf(Deflection::from_theta((theta - 10.0 * dtheta).max(0.0)));
            prop_assert!((back[0] - u[0]).abs() < 1e-9 + mass, "{u:?} -> {back:?}");
            // β/θ: Δθ relative to θ (the arc's angular width).
            prop_assert!((back[1] - u[1]).abs() < 1e-9 + 10.0 * dtheta / theta, "{u:?} -> {back:?}");
            // φ is undefined on the axis: its error is the point's rounding
            // over its distance from the axis, h = d1 sin α.
            let h = d1 * ((1.0 - u[1]) * theta).sin();
            let scale = x0.length() + x2.length() + s_len;
            prop_assert!(circular(back[2], u[2]) < 1e-9 + 1e-14 * scale / h, "{u:?} -> {back:?}");
        }
    }

    #[test]
    fn ray_techniques_sample_pdf_weight_and_inverse_agree(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), u in u3(), theta_max in 0.05..=PI
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let eq = Equiangular::new(c, &*phase, ray.directions(), ray.region());
        let di = Distance::new(c, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        for (name, t) in [("equiangular", &eq as &dyn Technique<f64>), ("distance", &di)] {
            check_sample(name, t, &c, &&*phase, u, true)?;
            let Some(s) = t.sample(u) else { continue };
            let Some(back) = t.invert(s.x1) else {
                return Err(TestCaseError::fail(format!("{name}: invert(sample({u:?})) = None")));
            };
            // Directions: u0 from z or the radial part, u1 from the azimuth,
            // which is undefined where the radial part vanishes (u0 → 0, 1).
            let d2 = (s.x1 - x2).length();
            let noise = 1e-13 * (x2.length() + d2) / d2;
            prop_assert!((back[0] - u[0]).abs() < 1e-7 + noise, "{name}: {u:?} -> {back:?}");
            let radial = (u[0] * (1.0 - u[0])).sqrt();
            prop_assert!(circular(back[1], u[1]) < 1e-7 + noise / radial, "{name}: {u:?} -> {back:?}");
            // Along the ray: the distance's rounding relative to the segment.
            prop_assert!((back[2] - u[2]).abs() < 1e-6 + noise, "{name}: {u:?} -> {back:?}");
        }
    }

    #[test]
    fn pdfs_are_finite_and_non_negative_everywhere(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), x1 in point(), theta_max in 0.05..=PI
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let om = Omnee::new(c, &*phase);
        let eq = Equiangular::new(c, &*phase, ray.directions(), ray.region());
        let di = Distance::new(c, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        for (name, t) in [("omnee", &om as &dyn Technique<f64>), ("equiangular", &eq), ("distance", &di)] {
            let p = t.pdf(x1);
            prop_assert!(p.is_finite() && p >= 0.0, "{name}: pdf({x1}) = {p}");
        }
        let k = c.kernel(&&*phase, x1);
        prop_assert!(k.is_finite() && k >= 0.0, "kernel {k}");
    }

    #[test]
    fn mis_weights_sum_to_one(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), x1 in point(),
        counts in (0.1..10.0f64, 0.1..10.0f64, 0.1..10.0f64), power in any::<bool>()
    ) {
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, FRAC_PI_2).unwrap();
        let full = Connection::new(x0, x2, PI).unwrap();
        let om = Omnee::new(c, &*phase);
        let eq = Equiangular::new(full, &*phase, ray.directions(), ray.region());
        let di = Distance::new(full, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        let techniques: [&dyn Technique<f64>; 3] = [&om, &eq, &di];
        let counts = [counts.0, counts.1, counts.2];
        let heuristic = if power { Heuristic::Power } else { Heuristic::Balance };
        let pdfs = techniques.map(|t| t.pdf(x1));
        let weights: [f64; 3] = core::array::from_fn(|i| {
            multi_sample_weight(&techniques, &counts, i, x1, pdfs[i], heuristic)
        });
        let sum: f64 = weights.iter().sum();
        if pdfs.iter().any(|&p| p > 0.0) {
            prop_assert!((sum - 1.0).abs() < 1e-12, "Σ w = {sum}, pdfs {pdfs:?}");
        } else {
            prop_assert!(sum == 0.0, "Σ w = {sum} where no technique samples");
        }
        // Each weight is Veach's (n_i p_i)^β / Σ_j (n_j p_j)^β (β = 1 balance,
        // 2 power), not just some partition of unity.
        let beta = if power { 2 } else { 1 };
        let np: [f64; 3] = core::array::from_fn(|i| counts[i] * pdfs[i]);
        for (i, &w) in weights.iter().enumerate() {
            let want = heuristic_formula(np[i], &np, beta);
            prop_assert!((w - want).abs() <= 1e-12 * want + 1e-300, "w_{i} = {w}, (n p)^β/Σ = {want}, n p = {np:?}");
        }
        // The two-technique helpers likewise, and they are complementary.
        let (a, b) = (np[0], np[1]);
        if a > 0.0 || b > 0.0 {
            let bal = omnee::mis::balance_heuristic(counts[0], pdfs[0], counts[1], pdfs[1]);
            let pow = omnee::mis::power_heuristic(counts[0], pdfs[0], counts[1], pdfs[1]);
            let (want_bal, want_pow) = (heuristic_formula(a, &[a, b], 1), heuristic_formula(a, &[a, b], 2));
            prop_assert!((bal - want_bal).abs() <= 1e-12 * want_bal + 1e-300, "balance {bal}, n_f p_f/(n_f p_f + n_g p_g) = {want_bal}");
            prop_assert!((pow - want_pow).abs() <= 1e-12 * want_pow + 1e-300, "power {pow}, (n_f p_f)²/Σ = {want_pow}");
            let bal = bal + omnee::mis::balance_heuristic(counts[1], pdfs[1], counts[0], pdfs[0]);
            let pow = pow + omnee::mis::power_heuristic(counts[1], pdfs[1], counts[0], pdfs[0]);
            prop_assert!((bal - 1.0).abs() < 1e-12 && (pow - 1.0).abs() < 1e-12, "{bal} {pow}");
        }
    }

    #[test]
    fn one_sample_balance_weight_is_kernel_over_mixture_pdf(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), u in u3(),
        c in (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64)
    ) {
        let phase = spec.build::<f64>();
        let full = Connection::new(x0, x2, PI).unwrap();
        let om = Omnee::new(Connection::new(x0, x2, FRAC_PI_2).unwrap(), &*phase);
        let eq = Equiangular::new(full, &*phase, ray.directions(), ray.region());
        let di = Distance::new(full, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        let mis = OneSample::new([&om as &dyn Technique<f64>, &eq, &di], [c.0, c.1, c.2], Heuristic::Balance).unwrap();
        // Balance one-sample MIS samples the mixture Σ c_j p_j, and its weight
        // w_i k / (c_i p_i) = k / Σ c_j p_j (Veach §9.2.4).
        check_sample("one-sample balance", &mis, &full, &&*phase, u, true)?;
        let techniques = [&om as &dyn Technique<f64>, &eq, &di];
        let power = OneSample::new(techniques, [c.0, c.1, c.2], Heuristic::Power).unwrap();
        check_sample("one-sample power", &power, &full, &&*phase, u, false)?;
        // The power weight of a sample from technique i (chosen by u0 among
        // the normalised c): w_i k/(c_i p_i) with w_i = (c_i p_i)²/Σ_j (c_j p_j)².
        let Some(s) = power.sample(u) else { return Ok(()) };
        if s.pdf == f64::MAX {
            return Ok(());
        }
        let probs = power.probabilities();
        let mut lo = 0.0;
        let mut chosen = probs.len() - 1;
        for (i, &p) in probs.iter().enumerate() {
            if u[0] < lo + p {
                chosen = i;
                break;
            }
            lo += p;
        }
        let cp: [f64; 3] = core::array::from_fn(|j| probs[j] * techniques[j].pdf(s.x1));
        if !(cp[chosen] > 0.0) {
            return Ok(()); // pdf(x1) = 0 at the sample: check_sample's business
        }
        let k = full.kernel(&&*phase, s.x1);
        let want = if k > 0.0 { k / cp[chosen] * heuristic_formula(cp[chosen], &cp, 2) } else { 0.0 };
        // The technique's own weight (≈ k/p_i) and its density, which enters
        // w_i with a relative sensitivity ≤ 2, each carry one recomputation
        // tolerance: 3 to first order, 4 allowed.
        let tol = 4.0 * recompute_tolerance(&full, &&*phase, s.x1);
        prop_assert!(close(s.weight, want, tol), "one-sample power: weight {:e}, w_i k/(c_i p_i) {want:e} (technique {chosen}, c p {cp:?})", s.weight);
    }
}

/// The smallest versine `1 ∓ cos θ` the phase-function quadratures reach.
/// Below it lies a negligible mass for every phase function the strategies
/// draw, except Fournier–Forand with a small backscatter fraction and a large
/// index: FF(B = 0.001, n = 1.5) has 8 % of its mass below the smallest
/// subnormal `1 − cos θ` (ν = −0.0034, mass ≈ δ^{−ν}), unrepresentable in
/// f64; [`ff_mass_below`] says which parameters to leave out.
const VERSINE_FLOOR: f64 = 1e-300;

/// `∫ h(cos θ) p(θ) dv` over the versine `v ∈ [a, b] ⊂ [0, 1]`, `v = 1 − cos θ`
/// (`forward`) or `v = 1 + cos θ`, in `t = ln v` from [`VERSINE_FLOOR`] in
/// panels of width ≤ 10: a peak of `p` at either pole is a bump of width
/// ~1 in `t` however narrow it is in θ (HG with g = 0.995 at v ≈ 1e-5,
/// Fournier–Forand's near-singular peak spread over hundreds of decades).
fn versine_integral<P: PhaseFunction<f64> + ?Sized>(
    p: &P,
    forward: bool,
    (a, b): (f64, f64),
    h: &impl Fn(f64) -> f64,
) -> f64 {
    let (ta, tb) = (a.max(VERSINE_FLOOR).ln(), b.ln());
    if !(tb > ta) {
        return 0.0;
    }
    let f = |t: f64| {
        let v = t.exp();
        let d = if forward {
            Deflection::from_versines(v, 2.0 - v)
        } else {
            Deflection::from_versines(2.0 - v, v)
        };
        p.eval(d) * h(d.cos()) * v
    };
    let panels = ((tb - ta) / 10.0).ceil() as usize;
    let w = (tb - ta) / panels as f64;
    (0..panels)
        .map(|i| {
            let lo = ta + i as f64 * w;
            let hi = if i + 1 == panels { tb } else { lo + w };
            integrate(f, lo, hi, 1e-12, 1e-17)
        })
        .sum()
}

/// `2π ∫ h(cos θ) p(θ) sin θ dθ` over [0, θ], i.e. `2π ∫ h p dx` with
/// `x = 1 − cos θ`, the forward half in `ln(1 − cos θ)` and the backward
/// half in `ln(1 + cos θ)` ([`versine_integral`]); a table (with `breaks`)
/// piecewise in θ between its edges instead.
fn moment_to<P: PhaseFunction<f64> + ?Sized>(
    p: &P,
    breaks: &[f64],
    theta: f64,
    h: impl Fn(f64) -> f64,
) -> f64 {
    if !breaks.is_empty() {
        // Constant per solid angle in each bin: no peak to resolve.
        let f = |t: f64| {
            let d = Deflection::from_theta(t);
            p.eval(d) * d.sin() * h(d.cos())
        };
        return TAU * integrate_pieces(f, 0.0, theta, breaks, 1e-12, 1e-15);
    }
    let d = Deflection::from_theta(theta);
    TAU * if d.one_minus_cos <= 1.0 {
        versine_integral(p, true, (0.0, d.one_minus_cos), &h)
    } else {
        versine_integral(p, true, (0.0, 1.0), &h)
            + versine_integral(p, false, (d.one_plus_cos, 1.0), &h)
    }
}

/// Fournier–Forand's mass below `1 − cos θ = x`, to leading order in δ:
/// `P(Θ < θ) ≈ δ^{−ν}` with `δ = 2x/(3(n − 1)²)` and `ν` from the
/// backscatter fraction (Mobley, Sundman & Boss 2002; as in
/// `fournier_forand_is_the_published_formula`).
fn ff_mass_below(b: f64, n: f64, x: f64) -> f64 {
    let d90 = 2.0 / (3.0 * (n - 1.0).powi(2));
    let nu = -(2.0 * b * (d90 - 1.0)).ln_1p() / d90.ln();
    (d90 * x).powf(-nu)
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn phase_functions_normalise_sample_their_cdf_and_have_their_mean_cosine(
        spec in phase_spec(), u in 0.0..1.0f64, theta in 0.0..PI
    ) {
        if let PhaseSpec::Ff(b, n) = spec {
            // Mass below the quadrature's floor (and f64's): see VERSINE_FLOOR.
            prop_assume!(ff_mass_below(b, n, VERSINE_FLOOR) < 1e-6);
        }
        let p = spec.build::<f64>();
        // The bound: ∫ p dω = 1 to 1e-4 (the quadrature itself is
        // good to ~1e-10 on these integrands).
        let breaks = spec.breakpoints();
        let mass = moment_to(&*p, &breaks, PI, |_| 1.0);
        prop_assert!((mass - 1.0).abs() < 1e-4, "{spec:?}: ∫ p dω = {mass}");
        let mean = moment_to(&*p, &breaks, PI, |c| c);
        prop_assert!((mean - p.mean_cosine()).abs() < 1e-4, "{spec:?}: ⟨cos θ⟩ = {mean}, claimed {}", p.mean_cosine());
        // The cdf is the integral of eval (to the quadrature's accuracy).
        let d = Deflection::from_theta(theta);
        let partial = moment_to(&*p, &breaks, theta, |_| 1.0);
        prop_assert!((p.cdf(d) - partial).abs() < 1e-6, "{spec:?}: cdf({theta}) = {}, ∫ = {partial}", p.cdf(d));
        // Sampling: the deflection is valid, pdf = eval, and for inverse-CDF
        // samplers cdf(sample(u)) = u and invert(sample(u)) = u.
        let s = p.sample(u);
        prop_assert!(s.is_finite() && (0.0..=PI).contains(&s.theta), "{spec:?}: sample({u}) = {s:?}");
        prop_assert!((s.one_minus_cos + s.one_plus_cos - 2.0).abs() < 1e-12, "{s:?}");
        prop_assert!(p.pdf(s) == p.eval(s), "{spec:?}");
        if spec.inverse_cdf() {
            prop_assert!((p.cdf(s) - u).abs() < 1e-9, "{spec:?}: cdf(sample({u})) = {}", p.cdf(s));
            let back = p.invert(s);
            prop_assert!(back.is_some_and(|b| (b - u).abs() < 1e-9), "{spec:?}: invert = {back:?}");
        }
    }
}

proptest! {
    #![proptest_config(config(400))]

    #[test]
    fn omnee_with_a_companion_returns_its_density_and_the_kernel_over_it(
        (x0, x2) in ends(), spec in phase_spec(), ray in ray(), u in u3(), v in u3(),
        rate in 0.0..=1.0f64, cone in 0.3..3.1f64, use_distance in any::<bool>()
    ) {
        // OMNEE's vertex, and with probability c a ray technique's behind
        // the cone θ ≥ θmin (balance heuristic over the expected counts 1 and
        // c there): each vertex comes with pdf(x1) = p_O + c p_C behind the
        // cone, p_O in front, and the weight k/pdf (mis::OmneeMis's contract).
        let phase = spec.build::<f64>();
        let full = Connection::new(x0, x2, PI).unwrap();
        let omnee = Omnee::new(full, &*phase);
        let eq = Equiangular::new(full, &*phase, ray.directions(), ray.region());
        let di = Distance::new(full, &*phase, ray.directions(), ray.region(), ray.sigma).unwrap();
        let companion: &dyn Technique<f64> = if use_distance { &di } else { &eq };
        let mis = OmneeMis::new(omnee, companion, rate, Deflection::from_theta(cone)).unwrap();
        type Mis<'a, 'b> = OmneeMis<'a, f64, &'b dyn PhaseFunction<f64>>;
        let recommended = OmneeMis::recommended(omnee, companion);
        let spelled_out =
            OmneeMis::new(omnee, companion, Mis::RATE, Deflection::from_theta(Mis::THETA_MIN)).unwrap();
        let draw = [u[0], u[1], u[2], v[0], v[1], v[2]];
        for (k, s) in mis.sample(draw).iter().enumerate() {
            let Some(s) = s else { continue };
            prop_assert!(k == 0 || v[0] < rate, "a companion vertex for u3 = {} ≥ c = {rate}", v[0]);
            // A point within the rounding of its recomputed θ from the cone's
            // edge may be classified either way.
            let Some((d, _, _)) = full.deflection(s.x1) else { continue };
            let noise = 10.0 * rounding_dtheta(&full, s.x1) + 1e-12;
            if (d.theta - cone).abs() < noise {
                continue;
            }
            prop_assert!(k == 0 || d.theta > cone, "a companion vertex in front of the cone: θ = {}", d.theta);
            check_vertex(&format!("omnee with companion, vertex {k}"), s, |x1| mis.pdf(x1), &full, &&*phase, true)?;
            // recommended() is new() with RATE and THETA_MIN.
            if (d.theta - Mis::THETA_MIN).abs() > noise {
                let (a, b) = (recommended.pdf(s.x1), spelled_out.pdf(s.x1));
                prop_assert!(close(a, b, 1e-12), "recommended pdf {a:e}, new(RATE, THETA_MIN) pdf {b:e}");
            }
        }
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn mie_is_the_documented_blend_of_its_fitted_lobes(d in 0.01..=50.0f64, theta in 0.0..=PI) {
        // p = (1 − w)·HG(g_hg) + w·Draine(g_draine, α) with the parameters of
        // mie_fit(d): the blend the docs (and Jendersie & d'Eon) define, in
        // its value and in its mean cosine.
        let fit = omnee::phase::mie_fit(d);
        let mie = omnee::phase::Mie::<f64>::new(d).unwrap();
        let hg = omnee::phase::HenyeyGreenstein::new(fit.g_hg).unwrap();
        let draine = omnee::phase::Draine::new(fit.g_draine, fit.alpha).unwrap();
        let x = Deflection::from_theta(theta);
        let want = (1.0 - fit.w) * hg.eval(x) + fit.w * draine.eval(x);
        prop_assert!(close(mie.eval(x), want, 1e-12), "d = {d}: eval {} vs {want}", mie.eval(x));
        let mean = (1.0 - fit.w) * fit.g_hg + fit.w * draine.mean_cosine();
        prop_assert!((mie.mean_cosine() - mean).abs() < 1e-12, "d = {d}: ⟨cos θ⟩ {} vs {mean}", mie.mean_cosine());
        let cdf = (1.0 - fit.w) * hg.cdf(x) + fit.w * draine.cdf(x);
        prop_assert!((mie.cdf(x) - cdf).abs() < 1e-12, "d = {d}: cdf {} vs {cdf}", mie.cdf(x));
    }

    #[test]
    fn fournier_forand_scatters_its_backscatter_fraction_backwards(
        b in 0.001..0.499f64, n in omnee::phase::FF_N_MIN..=omnee::phase::FF_N_MAX
    ) {
        // The parameter B is the fraction scattered into θ > π/2: by eval's
        // quadrature over the back hemisphere and by the cdf.
        let p = omnee::phase::FournierForand::<f64>::new(b, n).unwrap();
        let back = TAU * integrate_geometric(
            |t| {
                let (s, c) = (0.5 * t).sin_cos();
                let d = Deflection { theta: PI - t, one_minus_cos: 2.0 * c * c, one_plus_cos: 2.0 * s * s };
                p.eval(d) * d.sin()
            },
            0.0,
            FRAC_PI_2,
            40,
            1e-11,
        );
        prop_assert!((back - b).abs() < 1e-6 * b, "B = {b}, n = {n}: ∫ back hemisphere = {back}");
        let by_cdf = p.backscatter_fraction();
        prop_assert!((by_cdf - b).abs() < 1e-6 * b, "B = {b}, n = {n}: 1 − cdf(π/2) = {by_cdf}");
    }

    #[test]
    fn fournier_forand_is_the_published_formula(
        b in 0.001..0.499f64, n in omnee::phase::FF_N_MIN..=omnee::phase::FF_N_MAX, psi in 0.01..PI
    ) {
        // Mobley, Sundman & Boss (2002, Appl. Opt. 41(6), eqs. 3–5), written
        // out independently of the implementation: with
        // δ(ψ) = 4 sin²(ψ/2) / (3 (n − 1)²) and ν from the backscatter
        // fraction B = 1 − (1 − δ90^{ν+1} − ½(1 − δ90^ν)) / ((1 − δ90) δ90^ν)
        // (solved: δ90^ν = 1/(1 + 2B(δ90 − 1))),
        // p = [ν(1 − δ) − (1 − δ^ν) + (δ(1 − δ^ν) − ν(1 − δ)) / sin²(ψ/2)] / (4π (1 − δ)² δ^ν)
        //     + (1 − δ180^ν) (3 cos²ψ − 1) / (16π (δ180 − 1) δ180^ν).
        let p = omnee::phase::FournierForand::<f64>::new(b, n).unwrap();
        let delta = |psi: f64| 4.0 * (0.5 * psi).sin().powi(2) / (3.0 * (n - 1.0).powi(2));
        let d90 = delta(FRAC_PI_2);
        let nu = -(2.0 * b * (d90 - 1.0)).ln_1p() / d90.ln();
        let (d, d180) = (delta(psi), delta(PI));
        // The first term is 0/0 at δ = 1 (a removable singularity).
        prop_assume!((d - 1.0).abs() > 1e-3);
        let s2 = (0.5 * psi).sin().powi(2);
        let dn = d.powf(nu);
        let first = (nu * (1.0 - d) - (1.0 - dn) + (d * (1.0 - dn) - nu * (1.0 - d)) / s2)
            / (4.0 * PI * (1.0 - d).powi(2) * dn);
        let d180n = d180.powf(nu);
        let second = (1.0 - d180n) * (3.0 * psi.cos().powi(2) - 1.0)
            / (16.0 * PI * (d180 - 1.0) * d180n);
        let want = first + second;
        let got = p.eval(Deflection::from_theta(psi));
        // The textbook form cancels near δ = 1 and for small δ: it agrees to
        // 7e-10 relative at worst over a 60 × 40 × 200 grid of (B, n, ψ)
        // (measured); 1e-7 leaves room for that, a wrong constant misses by O(1).
        prop_assert!(close(got, want, 1e-7), "B = {b}, n = {n}, ψ = {psi}: {got:e} vs the paper's {want:e}");
    }

    #[test]
    fn equiangular_pdf_is_continuous_onto_the_line_through_x0(
        z0 in -2.0..2.0f64, z2 in -2.0..2.0f64, slab in (-3.0..0.0f64, 0.0..3.0f64),
        beyond in 0.01..0.99f64, normal in prop::option::of(prop::bool::ANY)
    ) {
        // x0, x2 and x1 on the z axis: the ray x2 → x1 meets the line through
        // x0 exactly (D = 0, the closed-form limit of the density); x1 a
        // hair off the axis has D > 0 and the general formula. The density
        // is continuous there.
        prop_assume!((z0 - z2).abs() > 0.05);
        let (lo, hi) = (slab.0 + z2.min(0.0), slab.1 + z2.max(0.0));
        prop_assume!(hi - lo > 0.05 && z2 > lo && z2 < hi);
        let (x0, x2) = (DVec3::new(0.0, 0.0, z0), DVec3::new(0.0, 0.0, z2));
        let c = Connection::new(x0, x2, PI).unwrap();
        let directions = match normal {
            None => Directions::Sphere,
            Some(up) => Directions::cosine(DVec3::new(0.3, -0.2, if up { 1.0 } else { -1.0 })).unwrap(),
        };
        let eq = Equiangular::new(c, omnee::phase::Isotropic, directions, Region::slab(lo, hi).unwrap());
        // Both directions along the axis from x2, to a point inside the slab
        // (the one towards x0 only where the slab ends before x0).
        for dir in [-1.0, 1.0] {
            let end = if dir > 0.0 { hi } else { lo };
            let towards_x0 = (z0 - z2) * dir > 0.0;
            if towards_x0 && (end - z0) * dir >= 0.0 {
                continue; // the segment passes through x0: no density limit
            }
            let x1 = DVec3::new(0.0, 0.0, z2 + beyond * (end - z2));
            let on = eq.pdf(x1);
            // The offset tilts the ray by ε = δ/t = 1e-9: the cosine pdf moves
            // by O(ε), everything else by O(ε²).
            let delta = 1e-9 * beyond * (end - z2).abs();
            let off = eq.pdf(x1 + DVec3::new(delta, 0.0, 0.0));
            if directions.pdf(DVec3::new(0.0, 0.0, dir)) == 0.0 {
                continue; // below the cosine's horizon
            }
            prop_assert!(on > 0.0 && off > 0.0, "pdf on the line {on}, off {off}");
            prop_assert!(close(on, off, 1e-6), "pdf on the line {on:e}, {delta:e} off it {off:e}");
        }
    }

    #[test]
    fn omnee_pdf_vanishes_exactly_beyond_theta_max(
        (x0, x2) in ends(), theta_max in 0.05..3.0f64, spec in phase_spec(), x1 in point()
    ) {
        // pdf(x1) > 0 iff θ(x1) < θmax (and p(θ) > 0): the density belongs to
        // the samples that are returned, none of which has θ ≥ θmax.
        let phase = spec.build::<f64>();
        let c = Connection::new(x0, x2, theta_max).unwrap();
        let t = Omnee::new(c, &*phase);
        let Some((d, _, _)) = c.deflection(x1) else { return Ok(()) };
        prop_assume!((d.theta - theta_max).abs() > 1e-9);
        let p = t.pdf(x1);
        if d.theta > theta_max {
            prop_assert!(p == 0.0, "θ = {} > θmax = {theta_max}: pdf {p:e}", d.theta);
        } else if phase.eval(d) > 0.0 {
            prop_assert!(p > 0.0, "θ = {} < θmax = {theta_max}: pdf {p:e}", d.theta);
        }
    }
}
