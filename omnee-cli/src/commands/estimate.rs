//! `omnee estimate`: the point-to-point once-more integral in an infinite
//! homogeneous medium, as mean and standard error, optionally against the
//! core's quadrature reference.
//!
//! [`estimate`] computes (and is the library's entry point: the Python
//! bindings call it), [`run`] prints.

use super::args::{check_count, parse_vec3, unit_normal};
use super::problem::{Names, Precision, Problem, ProblemArgs, Sampler, with_sampler};
use super::summary::{choice_json, print_result};
use crate::error::{CliError, Result, core_error};
use crate::moments::Moments;
use crate::parallel::{chunked, with_threads};
use crate::phase::{PhaseSpec, TableStorage};
use crate::rng::Rng;
use crate::technique::{Choice, Technique as TechniqueName};
use clap::Args;
use omnee_core::lobe::{LobeMis, LobeToPoint, PhaseLobe, WithLobe};
use omnee_core::medium::Homogeneous;
use omnee_core::phase::Phase;
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Omnee, Sample, Technique};
use omnee_core::{Real, Vector};
use serde_json::json;
use std::time::Instant;

/// The random streams of `estimate` and `samples`: `(seed, chunk, STREAM)`.
pub const STREAM: u64 = 0x6573_7469;

/// The options of `omnee estimate`.
#[derive(Args, Debug)]
pub struct EstimateArgs {
    /// The problem.
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// A lobe at x0.
    #[command(flatten)]
    pub lobe: LobeArgs,
    /// Number of samples.
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Also compute the quadrature reference (f64, docs/math.md §5).
    #[arg(long)]
    pub reference: bool,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// What [`estimate`] computed: the Monte Carlo estimate of the once-more
/// integral `I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1` over
/// θ < θmax (docs/math.md §1; with a lobe at `x0` its value `p0` towards
/// `x1` joins the integrand, §12), how it was drawn, and the quadrature
/// reference if asked for. `omnee estimate --json` prints these fields with
/// the problem's options.
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
    /// The technique without a lobe at `x0`: what was asked for, the
    /// method used and, for `auto`, why (with a lobe see
    /// [`Estimate::lobe_probability`]).
    pub choice: Choice,
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
    pub lobe: Option<Lobe>,
    /// With a lobe: the probability `c` with which a draw took the lobe
    /// technique (0 for OMNEE with the lobe in its weight).
    pub lobe_probability: Option<f64>,
}

/// The estimate of `a.problem` (with `a.lobe` at `x0`, if given) from
/// `a.samples` draws on `a.threads` threads (`a.json` is [`run`]'s only),
/// naming a bad field by `names`.
///
/// Draws come in chunks of [`crate::parallel::CHUNK`], chunk `k` from the
/// stream `(seed, k, STREAM)`, and the chunks' sums are added in chunk
/// order: the result depends on the seed and the sample count, never on the
/// thread count.
pub fn estimate(a: &EstimateArgs, names: Names) -> Result<Estimate> {
    let samples = check_count(&names.of("samples"), a.samples)?;
    let p = Problem::named(&a.problem, names)?;
    let lobe = a.lobe.named(names)?;
    let start = Instant::now();
    let (moments, accepted, reference, lobe_probability) = match (&lobe, a.problem.precision) {
        (None, Precision::F32) => with_none(sums::<f32>(a, &p, samples)?),
        (None, Precision::F64) => with_none(sums::<f64>(a, &p, samples)?),
        (Some(l), Precision::F32) => sums_lobe::<f32>(a, &p, l, samples)?,
        (Some(l), Precision::F64) => sums_lobe::<f64>(a, &p, l, samples)?,
    };
    let seconds = start.elapsed().as_secs_f64();
    let (mean, stderr) = moments.mean_stderr(samples);
    Ok(Estimate {
        mean,
        stderr,
        samples,
        accepted,
        reference,
        seconds,
        choice: p.choice,
        phase: p.phase,
        mean_cosine: p.g,
        tau: p.tau,
        receiver_normal: p.normal,
        precision: a.problem.precision,
        lobe,
        lobe_probability,
    })
}

/// `omnee estimate`: [`estimate`], printed.
pub fn run(a: EstimateArgs) -> Result<()> {
    let e = estimate(&a, Names::Options)?;
    let (mut tech, requested, mut reason) = choice_json(&e.choice);
    if let Some(c) = e.lobe_probability {
        (tech, reason) = lobe_technique_json(a.problem.technique, c);
    }
    let pa = &a.problem;
    let (mean, stderr) = (e.mean, e.stderr);
    let v = json!({
        "mean": mean, "stderr": stderr, "samples": e.samples, "seconds": e.seconds,
        "technique": tech, "technique_requested": requested, "auto_reason": reason,
        "terms": {"once-more": {"mean": mean, "stderr": stderr}},
        "accepted": e.accepted, "reference": e.reference,
        "x0": pa.x0, "x2": pa.x2, "phase": e.phase.to_string(), "mean_cosine": e.mean_cosine,
        "sigma_s": pa.sigma_s, "sigma_t": pa.sigma_t, "tau": e.tau, "theta_max": pa.theta_max,
        "receiver_normal": e.receiver_normal, "seed": pa.seed,
        "precision": e.precision.to_string(),
        "x0_phase": e.lobe.as_ref().map(|l| l.phase.to_string()),
        "x0_incoming": e.lobe.as_ref().map(|l| l.incoming),
        "lobe_probability": e.lobe_probability,
    });
    print_result(&v, a.json);
    Ok(())
}

/// A result without a lobe: no selection probability.
fn with_none(r: (Moments, u64, Option<f64>)) -> (Moments, u64, Option<f64>, Option<f64>) {
    (r.0, r.1, r.2, None)
}

/// The `technique` and `auto_reason` fields with a lobe at `x0`.
pub fn lobe_technique_json(t: TechniqueName, c: f64) -> (serde_json::Value, serde_json::Value) {
    match t {
        TechniqueName::Omnee => (json!("omnee"), json!(null)),
        _ => (
            json!("lobe-mis"),
            json!(format!(
                "a lobe at x0: OMNEE and the lobe technique, one-sample balance MIS choosing the \
                 lobe technique with c = {c} (LobeMis::recommended, docs/math.md §12.4)"
            )),
        ),
    }
}

/// The estimator's sums over `samples` draws in precision `F`, the number
/// of draws whose own vertex exists, and the quadrature if asked for.
fn sums<F: Real>(
    a: &EstimateArgs,
    p: &Problem,
    samples: u64,
) -> Result<(Moments, u64, Option<f64>)> {
    let seed = a.problem.seed;
    with_sampler::<F, _>(&a.problem, p, |sampler: &Sampler<'_, F>| {
        let chunks = with_threads(a.threads, || {
            chunked(samples, |k, count| {
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
        })?;
        let mut m = Moments::default();
        let mut accepted = 0;
        for (c, n) in &chunks {
            m.add(c);
            accepted += n;
        }
        let reference = if a.reference {
            let mut st = TableStorage::<f64>::default();
            let phase = p.phase.instantiate::<f64>(&mut st)?;
            Some(sampler.problem.integral(&phase))
        } else {
            None
        };
        Ok((m, accepted, reference))
    })?
}

/// The lobe at `x0` (issue 15, docs/math.md §12): `--x0-phase` and
/// `--x0-incoming`, both or neither. With them `--technique omnee` is OMNEE
/// with the lobe in its weight, and `mis`/`auto` the core's recommended
/// combination of OMNEE and the lobe technique (`LobeMis::recommended`).
#[derive(Args, Debug, Default)]
pub struct LobeArgs {
    /// Phase function at x0 (a scattering vertex): light arriving along --x0-incoming leaves x0 with this lobe [spec as --phase]
    #[arg(long)]
    pub x0_phase: Option<String>,
    /// Propagation direction X,Y,Z of the light arriving at x0 (normalised here)
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x0_incoming: Option<[f64; 3]>,
}

/// The checked lobe at `x0`.
#[derive(Clone, Debug)]
pub struct Lobe {
    /// The phase function at `x0`.
    pub phase: PhaseSpec,
    /// The unit propagation direction of the arriving light.
    pub incoming: [f64; 3],
}

impl LobeArgs {
    /// The lobe, `None` without the options; an error naming the option
    /// that is missing or bad as the command line does ([`Names::Options`]).
    pub fn check(&self) -> Result<Option<Lobe>> {
        self.named(Names::Options)
    }

    /// [`LobeArgs::check`], naming the fields by `names`.
    pub fn named(&self, names: Names) -> Result<Option<Lobe>> {
        let (phase, incoming) = (names.of("x0_phase"), names.of("x0_incoming"));
        match (&self.x0_phase, self.x0_incoming) {
            (None, None) => Ok(None),
            (Some(_), None) => Err(CliError::Input(format!(
                "{phase} needs {incoming} X,Y,Z (the propagation direction of the light \
                 arriving at x0)"
            ))),
            (None, Some(_)) => Err(CliError::Input(format!(
                "{incoming} needs {phase} SPEC (the phase function at x0)"
            ))),
            (Some(spec), Some(w)) => Ok(Some(Lobe {
                phase: PhaseSpec::parse(spec).map_err(|e| e.context(&phase))?,
                incoming: unit_normal(&incoming, w)?,
            })),
        }
    }
}

/// A phase function's lobe at `x0`, borrowing the phase function.
type PhaseAt<'p, F> = PhaseLobe<F, &'p Phase<'p, F>>;

/// The technique with a lobe at `x0`.
#[derive(Clone, Copy)]
pub enum LobeTechnique<'p, F: Real> {
    /// OMNEE, the lobe in its weight.
    Omnee(WithLobe<F, Omnee<F, &'p Phase<'p, F>>, PhaseAt<'p, F>>),
    /// The recommended combination.
    Mis(LobeMis<F, PhaseAt<'p, F>, &'p Phase<'p, F>>),
}

impl<F: Real> LobeTechnique<'_, F> {
    /// A vertex from three uniform numbers.
    pub fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        match self {
            LobeTechnique::Omnee(t) => t.sample(u),
            LobeTechnique::Mis(t) => t.sample(u),
        }
    }

    /// The probability of the lobe technique (0 for OMNEE).
    pub fn probability(&self) -> f64 {
        match self {
            LobeTechnique::Omnee(_) => 0.0,
            LobeTechnique::Mis(t) => t.probability().to_f64(),
        }
    }
}

fn vec3<F: Real>(a: [f64; 3]) -> F::Vec3 {
    F::Vec3::new(F::from_f64(a[0]), F::from_f64(a[1]), F::from_f64(a[2]))
}

/// Runs `f` with the technique and the problem with a lobe at `x0`, in
/// precision `F`.
pub fn with_lobe<F: Real, T>(
    a: &ProblemArgs,
    p: &Problem,
    lobe: &Lobe,
    f: impl FnOnce(&LobeTechnique<'_, F>, &LobeToPoint<F, PhaseLobe<F, &Phase<'_, F>>>) -> Result<T>,
) -> Result<T> {
    let connection =
        Connection::<F>::new(vec3::<F>(a.x0), vec3::<F>(a.x2), F::from_f64(a.theta_max))
            .map_err(|e| core_error(&p.names.list(&["x0", "x2", "theta_max"]), e))?;
    let medium = Homogeneous::new(F::from_f64(a.sigma_s), F::from_f64(a.sigma_t - a.sigma_s))
        .map_err(|e| core_error(&p.names.list(&["sigma_s", "sigma_t"]), e))?;
    let point = PointToPoint::new(connection, medium, p.normal.map(vec3::<F>))
        .map_err(|e| core_error(&p.names.of("receiver_normal"), e))?;
    let (mut s1, mut s0) = (TableStorage::<F>::default(), TableStorage::<F>::default());
    let p1 = p.phase.instantiate::<F>(&mut s1)?;
    let p0 = lobe.phase.instantiate::<F>(&mut s0)?;
    let l = PhaseLobe::new(&p0, vec3::<F>(lobe.incoming))
        .map_err(|e| core_error(&p.names.of("x0_incoming"), e))?;
    let problem = LobeToPoint::new(point, Some(l))
        .map_err(|e| core_error(&p.names.of("receiver_normal"), e))?;
    let technique = match a.technique {
        TechniqueName::Omnee => LobeTechnique::Omnee(WithLobe::new(
            Omnee::new(connection, &p1),
            l,
            connection.axis.x0,
        )),
        TechniqueName::Mis | TechniqueName::Auto => {
            LobeTechnique::Mis(LobeMis::recommended(connection, l, &p1))
        }
        other => {
            return Err(CliError::range(
                &p.names.of("technique"),
                other,
                "omnee, mis or auto with --x0-phase",
            ));
        }
    };
    f(&technique, &problem)
}

/// [`sums`] with a lobe at `x0`: the sums, the accepted draws, the
/// reference if asked for (f64, docs/math.md §12.5) and the lobe
/// technique's probability.
fn sums_lobe<F: Real>(
    a: &EstimateArgs,
    p: &Problem,
    lobe: &Lobe,
    samples: u64,
) -> Result<(Moments, u64, Option<f64>, Option<f64>)> {
    let seed = a.problem.seed;
    let (m, accepted, c) = with_lobe::<F, _>(&a.problem, p, lobe, |t, problem| {
        let chunks = with_threads(a.threads, || {
            chunked(samples, |k, count| {
                let mut rng = Rng::stream(seed, k, STREAM);
                let mut m = Moments::default();
                let mut accepted = 0u64;
                for _ in 0..count {
                    let u = [rng.uniform(), rng.uniform(), rng.uniform()];
                    let s = t.sample(u);
                    accepted += u64::from(s.is_some());
                    m.push(s.map_or(0.0, |s| problem.estimate(&s).to_f64()));
                }
                (m, accepted)
            })
        })?;
        let mut m = Moments::default();
        let mut accepted = 0;
        for (c, n) in &chunks {
            m.add(c);
            accepted += n;
        }
        Ok((m, accepted, t.probability()))
    })?;
    let reference = if a.reference {
        let mut st = TableStorage::<f64>::default();
        let phase = p.phase.instantiate::<f64>(&mut st)?;
        Some(with_lobe::<f64, _>(&a.problem, p, lobe, |_, problem| {
            Ok(problem.integral(&phase))
        })?)
    } else {
        None
    };
    Ok((m, accepted, reference, Some(c)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use omnee_core::method::Method;

    fn args(
        technique: TechniqueName,
        x0_phase: Option<&str>,
        incoming: Option<[f64; 3]>,
    ) -> EstimateArgs {
        EstimateArgs {
            problem: ProblemArgs {
                x0: [0.0, 0.0, 0.0],
                x2: [0.0, 0.0, 1.0],
                phase: "hg:0.9".into(),
                sigma_s: 0.5,
                sigma_t: 0.55,
                theta_max: std::f64::consts::PI,
                receiver_normal: None,
                technique,
                seed: 7,
                precision: Precision::F32,
            },
            lobe: LobeArgs {
                x0_phase: x0_phase.map(String::from),
                x0_incoming: incoming,
            },
            samples: 100_000,
            reference: true,
            threads: 1,
            json: true,
        }
    }

    #[test]
    fn the_lobe_options_come_together_and_name_what_is_wrong() {
        let e = |a: EstimateArgs| {
            a.lobe
                .check()
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        assert!(
            args(TechniqueName::Auto, None, None)
                .lobe
                .check()
                .unwrap()
                .is_none()
        );
        assert!(e(args(TechniqueName::Auto, Some("hg:0.9"), None)).contains("--x0-incoming"));
        assert!(e(args(TechniqueName::Auto, None, Some([0.0, 0.0, 1.0]))).contains("--x0-phase"));
        assert!(
            e(args(
                TechniqueName::Auto,
                Some("hg:2"),
                Some([0.0, 0.0, 1.0])
            ))
            .contains("--x0-phase")
        );
        assert!(
            e(args(TechniqueName::Auto, Some("hg:0.5"), Some([0.0; 3]))).contains("--x0-incoming")
        );
    }

    #[test]
    fn a_lobe_estimate_agrees_with_its_reference() {
        // Light 0.5 rad off the axis, HG 0.9 at both vertices: c = 1/2.
        let incoming = Some([0.5f64.sin(), 0.0, 0.5f64.cos()]);
        for t in [TechniqueName::Auto, TechniqueName::Omnee] {
            let a = args(t, Some("hg:0.9"), incoming);
            let p = Problem::new(&a.problem).unwrap();
            let lobe = a.lobe.check().unwrap().unwrap();
            let (m, accepted, reference, c) = sums_lobe::<f32>(&a, &p, &lobe, a.samples).unwrap();
            let (mean, se) = m.mean_stderr(a.samples);
            let want = reference.unwrap();
            // OMNEE's relative variance here is 8 per sample: 5 σ of
            // 100 000 samples is 5 √(8/1e5) = 4.5 % (heavy-tailed: a loose bound).
            assert!(
                (mean - want).abs() < 5.0 * se.max(0.01 * want),
                "{t}: {mean} ± {se} vs {want}"
            );
            assert!(accepted > 99_000, "{accepted}");
            assert_eq!(c.unwrap() > 0.4, t == TechniqueName::Auto);
        }
        let bad = args(TechniqueName::Distance, Some("hg:0.9"), incoming);
        let p = Problem::new(&bad.problem).unwrap();
        let lobe = bad.lobe.check().unwrap().unwrap();
        assert!(sums_lobe::<f32>(&bad, &p, &lobe, 10).is_err());
    }

    /// `args` without a lobe, with 10⁴ draws in f64 on one thread, a
    /// padded spec and a receiver cosine; no reference (the integration
    /// tests compare with it).
    fn plain() -> EstimateArgs {
        let mut a = args(TechniqueName::Auto, None, None);
        a.problem.phase = " hg:0.9 ".into();
        a.problem.receiver_normal = Some([0.0, 0.0, -2.0]);
        a.problem.precision = Precision::F64;
        EstimateArgs {
            samples: 10_000,
            reference: false,
            json: false,
            ..a
        }
    }

    #[test]
    fn the_estimate_is_independent_of_threads_and_reports_its_problem() {
        let one = estimate(&plain(), Names::Fields).unwrap();
        let mut a = plain();
        a.threads = 2;
        let two = estimate(&a, Names::Fields).unwrap();
        assert_eq!(
            (one.mean, one.stderr, one.accepted),
            (two.mean, two.stderr, two.accepted)
        );
        assert_eq!(
            (one.choice.method, one.choice.requested),
            (Method::Omnee, TechniqueName::Auto)
        );
        assert!(one.choice.reason.is_some());
        assert_eq!(one.phase.to_string(), "hg:0.9");
        assert_eq!((one.mean_cosine, one.tau), (0.9, 0.55));
        assert_eq!(one.receiver_normal, Some([0.0, 0.0, -1.0]));
        assert_eq!((one.samples, one.precision), (10_000, Precision::F64));
        assert_eq!((one.reference, one.lobe_probability), (None, None));
        assert!(one.lobe.is_none());
        assert!(one.mean > 0.0 && one.stderr < 0.01 * one.mean, "{one:?}");
    }

    /// A change to [`plain`] that makes it invalid.
    type Spoil = fn(&mut EstimateArgs);

    #[test]
    fn bad_fields_are_named_as_the_caller_spells_them() {
        let message = |change: Spoil, names| {
            let mut a = plain();
            change(&mut a);
            estimate(&a, names).unwrap_err().to_string()
        };
        let cases: [(Spoil, &str, &str); 7] = [
            (|a| a.samples = 0, "samples = 0", "--samples = 0"),
            (
                |a| a.problem.sigma_s = -1.0,
                "sigma_s = -1",
                "--sigma-s = -1",
            ),
            (
                |a| a.problem.theta_max = 0.0,
                "theta_max = 0",
                "--theta-max = 0",
            ),
            (
                |a| a.problem.x2 = a.problem.x0,
                "x2 = 0,0,0 equals x0",
                "--x2 = 0,0,0 equals --x0",
            ),
            (
                |a| a.problem.x0[1] = f64::NAN,
                "x0 = 0,NaN,0 is not a point",
                "--x0 = 0,NaN,0",
            ),
            (
                |a| a.problem.receiver_normal = Some([0.0; 3]),
                "receiver_normal = 0,0,0 has zero length",
                "--receiver-normal = 0,0,0",
            ),
            (
                |a| a.lobe.x0_phase = Some("iso".into()),
                "x0_phase needs x0_incoming",
                "--x0-phase needs --x0-incoming",
            ),
        ];
        for (change, field, option) in cases {
            assert!(message(change, Names::Fields).starts_with(field), "{field}");
            assert!(
                message(change, Names::Options).starts_with(option),
                "{option}"
            );
        }
    }
}
