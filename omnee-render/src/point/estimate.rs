//! The estimate of the point-to-point once-more integral, as mean and
//! standard error, optionally with the core's quadrature reference:
//! `omnee estimate`, Python's `omnee.estimate`; with bridges of several
//! vertices ([`super::bridge`]) the `k`-times scattered transfer and its
//! isotropic closed form.

use super::bridge::{self, BridgeEstimate};
use super::problem::{Precision, Prepared, Problem, X0Lobe, contribution};
use crate::error::{RenderError, Result, Spelling, not_converged};
use crate::moments::Moments;
use crate::parallel::chunked;
use crate::phase::{PhaseSpec, TableStorage};
use crate::rng::Rng;
use crate::technique::Resolved;
use omnee_core::Real;
use omnee_core::sampling::Technique;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The random streams of the estimate and of [`super::samples`]:
/// `(seed, chunk, STREAM)`.
pub const STREAM: u64 = 0x6573_7469;

/// The largest number of draws of an estimate, `2⁴⁰`.
pub const MAX_SAMPLES: u64 = 1 << 40;

/// What [`estimate`] computed: the Monte Carlo estimate of the once-more
/// integral `I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1` over
/// θ < θmax (docs/math.md §1; with a lobe at `x0` its value `p0` towards
/// `x1` joins the integrand, §12), how it was drawn, and the quadrature
/// reference if asked for.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// The mean `x̄ = Σx/n` of the `n` per-draw estimates `x = Σ_k f_c(x1_k) · weight_k`.
    pub mean: f64,
    /// The standard error of the mean, `√((Σx² − x̄ Σx)/((n − 1) n))`.
    pub stderr: f64,
    /// The number of draws `n`.
    pub samples: u64,
    /// The draws whose own vertex exists (the MIS companion not counted).
    pub accepted: u64,
    /// The f64 quadrature value of `I` (docs/math.md §5, §12.5), if asked for.
    pub reference: Option<f64>,
    /// Wall-clock time of the draws and the quadrature, in seconds.
    pub seconds: f64,
    /// The technique: asked for, used and, for `auto`, why.
    pub technique: Resolved,
    /// The phase function at `x1`, as checked.
    pub phase: PhaseSpec,
    /// Its mean cosine `g = ⟨cos θ⟩`.
    pub mean_cosine: f64,
    /// The optical thickness `τ = σt · |x2 − x0|`.
    pub tau: f64,
    /// The receiver's unit normal, if it has a cosine.
    pub receiver_normal: Option<[f64; 3]>,
    /// The arithmetic precision of the draws.
    pub precision: Precision,
    /// The lobe at `x0`, if there is one.
    pub lobe: Option<X0Lobe>,
    /// With a lobe: the probability `c` with which a draw took the lobe
    /// technique (0 for OMNEE with the lobe in its weight).
    pub lobe_probability: Option<f64>,
    /// With bridges (vertices other than one): the orders drawn, each
    /// order's share of the mean, and their closed forms if asked for.
    /// [`mean`](Self::mean) and [`reference`](Self::reference) are then those
    /// of `I_K` or of `Σ_K I_K`, and [`technique`](Self::technique) is not
    /// what drew.
    pub bridge: Option<BridgeEstimate>,
}

/// Checks that `samples` (spelled `field`) is in `[1, 2⁴⁰]`.
pub fn check_samples(field: &str, samples: u64) -> Result<u64> {
    if (1..=MAX_SAMPLES).contains(&samples) {
        Ok(samples)
    } else {
        Err(RenderError::range(field, samples, "[1, 2^40]"))
    }
}

/// The estimate of `problem` from `samples` draws on the current rayon
/// pool, naming a bad field by `spelling`; [`RenderError::Cancelled`] as
/// soon as `cancel` is set (checked between chunks).
///
/// Draws come in chunks of [`crate::parallel::CHUNK`], chunk `k` from the
/// stream `(seed, k, STREAM)`, and the chunks' sums are added in chunk
/// order: the result depends on the seed and the sample count, never on the
/// thread count.
pub fn estimate(
    problem: &Problem,
    samples: u64,
    reference: bool,
    spelling: Spelling,
    cancel: &AtomicBool,
) -> Result<Estimate> {
    let samples = check_samples(&spelling.of("samples"), samples)?;
    let p = problem.check(spelling)?;
    let start = Instant::now();
    if p.bridges() {
        return bridge_estimate(&p, samples, reference, cancel, start);
    }
    let lobe = p.lobe.is_some();
    let (moments, accepted, lobe_probability) = match (lobe, problem.precision) {
        (false, Precision::F32) => sums::<f32>(&p, samples, cancel)?,
        (false, Precision::F64) => sums::<f64>(&p, samples, cancel)?,
        (true, Precision::F32) => sums_lobe::<f32>(&p, samples, cancel)?,
        (true, Precision::F64) => sums_lobe::<f64>(&p, samples, cancel)?,
    };
    let (mean, stderr) = in_range(&p, moments.mean_stderr(samples))?;
    let reference = reference.then(|| quadrature(&p)).transpose()?;
    let seconds = start.elapsed().as_secs_f64();
    Ok(Estimate {
        mean,
        stderr,
        samples,
        accepted,
        reference,
        seconds,
        technique: p.technique,
        mean_cosine: p.g,
        tau: p.tau,
        receiver_normal: p.normal,
        precision: problem.precision,
        lobe_probability,
        phase: p.phase,
        lobe: p.lobe,
        bridge: None,
    })
}

/// [`estimate`] with bridges: the sums in chunk order as for one vertex,
/// the closed forms if asked for (checked before any draw).
fn bridge_estimate(
    p: &Prepared,
    samples: u64,
    reference: bool,
    cancel: &AtomicBool,
    start: Instant,
) -> Result<Estimate> {
    let references = reference.then(|| bridge::references(p)).transpose()?;
    let seed = p.problem.seed;
    let chunks = match p.problem.precision {
        Precision::F32 => p.with_bridge::<f32, _>(|b| {
            chunked(samples, cancel, |k, count| {
                bridge::chunk_sums(b, &mut Rng::stream(seed, k, STREAM), count)
            })
        })??,
        Precision::F64 => p.with_bridge::<f64, _>(|b| {
            chunked(samples, cancel, |k, count| {
                bridge::chunk_sums(b, &mut Rng::stream(seed, k, STREAM), count)
            })
        })??,
    };
    let (mut moments, mut orders, mut accepted) = bridge::BridgeSums::default();
    orders.resize(omnee_core::bridge::MAX_VERTICES + 1, Moments::default());
    for (m, o, a) in &chunks {
        moments.add(m);
        for (sum, add) in orders.iter_mut().zip(o) {
            sum.add(add);
        }
        accepted += a;
    }
    let report = bridge::report(p, samples, &orders, references.as_deref())?;
    let (mean, stderr) = in_range(p, moments.mean_stderr(samples))?;
    Ok(Estimate {
        mean,
        stderr,
        samples,
        accepted,
        reference: references.map(|r| r.iter().sum()),
        seconds: start.elapsed().as_secs_f64(),
        technique: p.technique,
        mean_cosine: p.g,
        tau: p.tau,
        receiver_normal: None,
        precision: p.problem.precision,
        lobe_probability: None,
        phase: p.phase.clone(),
        lobe: None,
        bridge: Some(report),
    })
}

/// The sums of chunks `(moments, accepted draws)` in chunk order, added.
fn total(chunks: Vec<(Moments, u64)>) -> (Moments, u64) {
    let mut m = Moments::default();
    let mut accepted = 0;
    for (c, n) in &chunks {
        m.add(c);
        accepted += n;
    }
    (m, accepted)
}

/// The estimator's sums over `samples` draws in precision `F` and the
/// number of draws whose own vertex exists.
fn sums<F: Real>(
    p: &Prepared,
    samples: u64,
    cancel: &AtomicBool,
) -> Result<(Moments, u64, Option<f64>)> {
    let seed = p.problem.seed;
    let chunks = p.with_sampler::<F, _>(|sampler| {
        chunked(samples, cancel, |k, count| {
            let mut rng = Rng::stream(seed, k, STREAM);
            let mut m = Moments::default();
            let mut accepted = 0u64;
            for _ in 0..count {
                let draw = sampler.draw(&mut rng);
                accepted += u64::from(draw.vertices[0].is_some());
                m.push(draw.sum(|s| sampler.estimate(s)));
            }
            (m, accepted)
        })
    })??;
    let (m, accepted) = total(chunks);
    Ok((m, accepted, None))
}

/// [`sums`] with a lobe at `x0`, and the lobe technique's probability.
fn sums_lobe<F: Real>(
    p: &Prepared,
    samples: u64,
    cancel: &AtomicBool,
) -> Result<(Moments, u64, Option<f64>)> {
    let seed = p.problem.seed;
    p.with_lobe::<F, _>(|t, problem| {
        let chunks = chunked(samples, cancel, |k, count| {
            let mut rng = Rng::stream(seed, k, STREAM);
            let mut m = Moments::default();
            let mut accepted = 0u64;
            for _ in 0..count {
                let u = [rng.uniform(), rng.uniform(), rng.uniform()];
                let s = t.sample(u);
                accepted += u64::from(s.is_some());
                m.push(s.map_or(0.0, |s| contribution(problem.f_c(s.x1), &s)));
            }
            (m, accepted)
        })?;
        let (m, accepted) = total(chunks);
        Ok((m, accepted, Some(t.lobe_probability().to_f64())))
    })
}

/// `(mean, stderr)` if both are finite, else [`beyond_range`] for the
/// estimate `mean +- stderr`.
fn in_range(p: &Prepared, (mean, stderr): (f64, f64)) -> Result<(f64, f64)> {
    if mean.is_finite() && stderr.is_finite() {
        return Ok((mean, stderr));
    }
    Err(beyond_range(
        p,
        &format!("the estimate ({mean} +- {stderr})"),
    ))
}

/// The error for a `value` (the estimate, the reference) beyond f64's range,
/// naming the fields that set the transfer's size: an extreme but valid
/// problem can exceed it (σs = 1e300 at s = 1e-300 gives `I ≈ 1e600`,
/// σs = 0.5 at s = 1e-320 `I ≈ 1e320`); it is refused, never printed as ∞
/// or NaN.
fn beyond_range(p: &Prepared, value: &str) -> RenderError {
    RenderError::Input(format!(
        "{}: {value} is beyond f64's range; allowed: a problem whose transfer (about \
         sigma_s / |x2 - x0| for a thin medium) and its draws' estimates stay below {:e}",
        p.spelling.list(&["x0", "x2", "sigma_s"]),
        f64::MAX
    ))
}

/// The f64 quadrature value of the problem (docs/math.md §5, §12.5), or
/// the core's `NotConverged` when it spent its evaluation budget
/// ([`omnee_core::reference::PointToPoint::BUDGET`], a few seconds at
/// most), named by `reference`, or [`beyond_range`] where the value exceeds
/// f64 (the core's `+∞`).
fn quadrature(p: &Prepared) -> Result<f64> {
    let mut st = TableStorage::<f64>::default();
    let phase = p.phase.instantiate::<f64>(&mut st)?;
    let value = if p.lobe.is_some() {
        p.with_lobe::<f64, _>(|_, problem| Ok(problem.try_integral(&phase)))?
    } else {
        p.with_sampler::<f64, _>(|sampler| sampler.problem.try_integral(&phase))?
    };
    let value = value.map_err(|e| not_converged(p.spelling, e))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(beyond_range(p, &format!("the reference ({value})")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use omnee_core::method::{Choice, LobeMethod, Method};

    fn problem(technique: Choice, x0_phase: Option<&str>, incoming: Option<[f64; 3]>) -> Problem {
        Problem {
            x0: [0.0, 0.0, 0.0],
            x2: [0.0, 0.0, 1.0],
            phase: "hg:0.9".into(),
            sigma_s: 0.5,
            sigma_t: 0.55,
            technique,
            seed: 7,
            precision: Precision::F32,
            x0_phase: x0_phase.map(String::from),
            x0_incoming: incoming,
            ..Problem::default()
        }
    }

    fn run(p: &Problem, samples: u64, reference: bool) -> Result<Estimate> {
        let go = AtomicBool::new(false);
        estimate(p, samples, reference, Spelling::Fields, &go)
    }

    #[test]
    fn the_lobe_fields_come_together_and_name_what_is_wrong() {
        let e = |p: Problem| {
            p.check(Spelling::Options)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        assert!(
            problem(Choice::Auto, None, None)
                .check(Spelling::Options)
                .unwrap()
                .lobe
                .is_none()
        );
        assert!(e(problem(Choice::Auto, Some("hg:0.9"), None)).contains("--x0-incoming"));
        assert!(e(problem(Choice::Auto, None, Some([0.0, 0.0, 1.0]))).contains("--x0-phase"));
        assert!(
            e(problem(Choice::Auto, Some("hg:2"), Some([0.0, 0.0, 1.0]))).contains("--x0-phase")
        );
        assert!(e(problem(Choice::Auto, Some("hg:0.5"), Some([0.0; 3]))).contains("--x0-incoming"));
    }

    #[test]
    fn a_lobe_estimate_agrees_with_its_reference() {
        // Light 0.5 rad off the axis, HG 0.9 at both vertices: c = 1/2.
        let incoming = Some([0.5f64.sin(), 0.0, 0.5f64.cos()]);
        for t in [Choice::Auto, Choice::Omnee] {
            let e = run(&problem(t, Some("hg:0.9"), incoming), 100_000, true).unwrap();
            let want = e.reference.unwrap();
            // OMNEE's relative variance here is 8 per sample: 5 σ of
            // 100 000 samples is 5 √(8/1e5) = 4.5 % (heavy-tailed: a loose bound).
            assert!(
                (e.mean - want).abs() < 5.0 * e.stderr.max(0.01 * want),
                "{t}: {} ± {} vs {want}",
                e.mean,
                e.stderr
            );
            assert!(e.accepted > 99_000, "{}", e.accepted);
            assert_eq!(e.lobe_probability.unwrap() > 0.4, t == Choice::Auto);
            let used = if t == Choice::Auto {
                LobeMethod::LobeMis
            } else {
                LobeMethod::Omnee
            };
            assert_eq!(e.technique.used, Choice::from(used));
        }
        let bad = problem(Choice::Distance, Some("hg:0.9"), incoming);
        let message = run(&bad, 10, false).unwrap_err().to_string();
        assert!(message.starts_with("technique = distance"), "{message}");
    }

    /// `problem` without a lobe, in f64, a padded spec and a receiver
    /// cosine.
    fn plain() -> Problem {
        Problem {
            phase: " hg:0.9 ".into(),
            receiver_normal: Some([0.0, 0.0, -2.0]),
            precision: Precision::F64,
            ..problem(Choice::Auto, None, None)
        }
    }

    #[test]
    fn the_estimate_is_independent_of_threads_and_reports_its_problem() {
        let one = crate::parallel::with_threads(1, || run(&plain(), 10_000, false))
            .unwrap()
            .unwrap();
        let two = crate::parallel::with_threads(2, || run(&plain(), 10_000, false))
            .unwrap()
            .unwrap();
        assert_eq!(
            (one.mean, one.stderr, one.accepted),
            (two.mean, two.stderr, two.accepted)
        );
        assert_eq!(
            (one.technique.used, one.technique.requested),
            (Choice::from(Method::Omnee), Choice::Auto)
        );
        assert!(one.technique.reason.is_some());
        assert_eq!(one.phase.to_string(), "hg:0.9");
        assert_eq!((one.mean_cosine, one.tau), (0.9, 0.55));
        assert_eq!(one.receiver_normal, Some([0.0, 0.0, -1.0]));
        assert_eq!((one.samples, one.precision), (10_000, Precision::F64));
        assert_eq!((one.reference, one.lobe_probability), (None, None));
        assert!(one.lobe.is_none());
        assert!(one.mean > 0.0 && one.stderr < 0.01 * one.mean, "{one:?}");
    }

    #[test]
    fn extreme_scales_give_the_scaled_reference_or_a_named_error() {
        // f32 at s = 1e-30 with σ ∝ 1/s: per-draw products near 1e59,
        // beyond f32, multiplied in f64. |z| < 5.5 (tail 3.8e-8).
        let s = 1e-30;
        let p = Problem {
            x2: [0.0, 0.0, s],
            sigma_s: 0.5 / s,
            sigma_t: 0.55 / s,
            ..problem(Choice::Omnee, None, None)
        };
        let e = run(&p, 20_000, true).unwrap();
        let want = e.reference.unwrap();
        assert!((e.mean - want).abs() < 5.5 * e.stderr, "{e:?}");
        assert!((e.tau - 0.55).abs() < 1e-9);
        // f64 at s = 1e-300 with σs = 5e299: a transfer of 1e600.
        let p = Problem {
            x2: [0.0, 0.0, 1e-300],
            sigma_s: 5e299,
            sigma_t: 5.5e299,
            precision: Precision::F64,
            ..p
        };
        let m = run(&p, 100, true).unwrap_err().to_string();
        assert!(m.starts_with("x0/x2/sigma_s: the estimate"), "{m}");
        // A normal of subnormal length is its direction.
        let p = Problem {
            receiver_normal: Some([0.0, 0.0, -5e-324]),
            ..plain()
        };
        let e = run(&p, 100, false).unwrap();
        assert_eq!(e.receiver_normal, Some([0.0, 0.0, -1.0]));
        let m = crate::parallel::with_threads(usize::MAX, || ())
            .unwrap_err()
            .to_string();
        assert!(
            m.starts_with("threads = ") && m.contains("[0, 1024]"),
            "{m}"
        );
    }

    #[test]
    fn a_cancelled_estimate_stops_with_an_error() {
        let stop = AtomicBool::new(true);
        let e = estimate(&plain(), 1 << 40, false, Spelling::Fields, &stop);
        assert!(matches!(e, Err(RenderError::Cancelled)));
    }

    /// A change to [`plain`] that makes it invalid.
    type Spoil = fn(&mut Problem);

    #[test]
    fn bad_fields_are_named_as_the_caller_spells_them() {
        let message = |change: Spoil, samples: u64, spelling| {
            let mut p = plain();
            change(&mut p);
            let go = AtomicBool::new(false);
            estimate(&p, samples, false, spelling, &go)
                .unwrap_err()
                .to_string()
        };
        assert!(message(|_| {}, 0, Spelling::Fields).starts_with("samples = 0"));
        assert!(message(|_| {}, 0, Spelling::Options).starts_with("--samples = 0"));
        let cases: [(Spoil, &str, &str); 6] = [
            (|p| p.sigma_s = -1.0, "sigma_s = -1", "--sigma-s = -1"),
            (|p| p.theta_max = 0.0, "theta_max = 0", "--theta-max = 0"),
            (
                |p| p.x2 = p.x0,
                "x2 = 0,0,0 equals x0",
                "--x2 = 0,0,0 equals --x0",
            ),
            (
                |p| p.x0[1] = f64::NAN,
                "x0 = 0,NaN,0 is not a point",
                "--x0 = 0,NaN,0",
            ),
            (
                |p| p.receiver_normal = Some([0.0; 3]),
                "receiver_normal = 0,0,0 has zero length",
                "--receiver-normal = 0,0,0",
            ),
            (
                |p| p.x0_phase = Some("iso".into()),
                "x0_phase needs x0_incoming",
                "--x0-phase needs --x0-incoming",
            ),
        ];
        for (change, field, option) in cases {
            assert!(
                message(change, 10, Spelling::Fields).starts_with(field),
                "{field}"
            );
            assert!(
                message(change, 10, Spelling::Options).starts_with(option),
                "{option}"
            );
        }
    }
}
