//! `omnee.estimate`: the point-to-point once-more integral of
//! `omnee estimate`, with the same random streams, so the same seed gives
//! the same numbers as `omnee estimate --json`.
//!
//! `Problem::run` repeats the loop of the CLI's private estimate driver
//! (chunks of `CHUNK` draws, stream `(seed, k, 0x6573_7469)`, sums added in
//! chunk order), because the CLI does not expose it as a function; the
//! tests compare the two bit for bit. Once the CLI's library has a public
//! `estimate(&EstimateArgs) -> Result<Estimate>`, this module validates the
//! arguments with Python's field names and calls it.

use crate::array::vec3;
use crate::error;
use crate::phase::Phase;
use omnee_cli::cli::Precision;
use omnee_cli::measure::CHUNK;
use omnee_cli::phase::TableStorage;
use omnee_cli::rng::Rng;
use omnee_cli::scene::Range;
use omnee_cli::technique::{Choice, Setup, choose};
use omnee_core::Real;
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Directions};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::time::Instant;

/// The point-to-point problem, validated, with the field names of
/// `omnee.estimate`.
struct Problem {
    x0: [f64; 3],
    x2: [f64; 3],
    phase: Phase,
    sigma_s: f64,
    sigma_t: f64,
    theta_max: f64,
    receiver_normal: Option<[f64; 3]>,
    g: f64,
    tau: f64,
    choice: Choice,
}

/// `Σx`, `Σx²` of the per-sample estimates.
#[derive(Clone, Copy, Default)]
struct Moments {
    sum: f64,
    sum2: f64,
}

impl Moments {
    /// `(mean, standard error of the mean)` over `n` samples:
    /// `x̄ = Σx/n`, `se = √((Σx² − x̄ Σx)/((n − 1) n))`.
    fn mean_stderr(&self, n: u64) -> (f64, f64) {
        let n = n as f64;
        let mean = self.sum / n;
        let var = ((self.sum2 - self.sum * mean) / (n - 1.0).max(1.0)).max(0.0);
        (mean, (var / n).sqrt())
    }
}

/// What a run returns besides the moments.
struct Run {
    moments: Moments,
    accepted: u64,
    reference: Option<f64>,
}

impl Problem {
    /// Chunk `k` of `count` samples from the stream `(seed, k)`, in the
    /// order and with the stream `omnee estimate` uses; the sums of chunks
    /// are added in chunk order, so the result is independent of threads.
    fn run<F: Real>(&self, samples: u64, seed: u64, reference: bool) -> PyResult<Run> {
        let connection = Connection::<F>::new(
            vec3::<F>(self.x0),
            vec3::<F>(self.x2),
            F::from_f64(self.theta_max),
        )
        .map_err(error::core)?;
        let medium = Homogeneous::new(
            F::from_f64(self.sigma_s),
            F::from_f64(self.sigma_t - self.sigma_s),
        )
        .map_err(error::core)?;
        let problem = PointToPoint::new(connection, medium, self.receiver_normal.map(vec3::<F>))
            .map_err(error::core)?;
        let mut storage = TableStorage::<F>::default();
        let phase = self.phase.instantiate::<F>(&mut storage)?;
        let directions = match self.receiver_normal {
            Some(n) => Directions::cosine(vec3::<F>(n)).map_err(error::core)?,
            None => Directions::Sphere,
        };
        let setup = Setup {
            phase: &phase,
            directions,
            region: Region::Everywhere,
            sigma_t: F::from_f64(self.sigma_t),
        };
        let tech = self.choice.tech;
        let chunks: Vec<(Moments, u64)> = (0..samples.div_ceil(CHUNK))
            .into_par_iter()
            .map(|k| {
                let mut rng = Rng::stream(seed, k, 0x6573_7469);
                let (mut m, mut accepted) = (Moments::default(), 0u64);
                for _ in 0..CHUNK.min(samples - k * CHUNK) {
                    let draw = setup.sample(tech, connection, &mut rng);
                    accepted += u64::from(draw.vertices[0].is_some());
                    let x: f64 = draw
                        .vertices
                        .iter()
                        .flatten()
                        .map(|s| problem.estimate(s).to_f64())
                        .sum();
                    m.sum += x;
                    m.sum2 += x * x;
                }
                (m, accepted)
            })
            .collect();
        let mut run = Run {
            moments: Moments::default(),
            accepted: 0,
            reference: None,
        };
        for (m, n) in &chunks {
            run.moments.sum += m.sum;
            run.moments.sum2 += m.sum2;
            run.accepted += n;
        }
        if reference {
            let mut storage = TableStorage::<f64>::default();
            run.reference = Some(problem.integral(&self.phase.instantiate::<f64>(&mut storage)?));
        }
        Ok(run)
    }
}

/// `f` on a rayon pool of `threads` workers (0: one per core).
fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| PyValueError::new_err(format!("threads = {threads}: {e}")))?;
    Ok(pool.install(f))
}

/// The unit vector along `n`, naming `field` if it has no direction.
fn unit(field: &str, n: [f64; 3]) -> PyResult<[f64; 3]> {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !(len > 0.0 && len.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{field} = {n:?} has no direction; allowed: any finite non-zero vector"
        )));
    }
    Ok(n.map(|c| c / len))
}

/// The precision from a numpy dtype (anything `numpy.dtype` accepts).
fn precision(dtype: &Bound<'_, PyAny>) -> PyResult<Precision> {
    let np = dtype.py().import("numpy")?;
    let d = np.getattr("dtype")?.call1((dtype,))?;
    let name: String = d.getattr("name")?.extract()?;
    match name.as_str() {
        "float32" => Ok(Precision::F32),
        "float64" => Ok(Precision::F64),
        _ => Err(PyTypeError::new_err(format!(
            "dtype = {name} is not supported; allowed: float32 (the renderer's precision) or float64"
        ))),
    }
}

/// The once-more scattered transfer from a unit point light at `x0` to a
/// point receiver at `x2` through an infinite homogeneous medium,
///
/// `I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1` over θ < θmax,
///
/// estimated with `samples` draws of `technique` (`omnee`, `equiangular`,
/// `distance`, `mis` or `auto`) from the random streams of `seed`, exactly
/// as `omnee estimate --json` does: the same arguments give the same mean and
/// standard error. `reference=True` adds the f64 quadrature value of `I`
/// (docs/math.md §5). Returns `Estimate(mean, stderr, reference, technique,
/// auto_reason, samples, accepted, mean_cosine, tau, seconds)`.
#[pyfunction]
#[pyo3(signature = (
    *, x0, x2, sigma_s, sigma_t, phase = None, technique = "auto", samples = 100_000, seed = 1,
    theta_max = PI, receiver_normal = None, dtype = None, reference = true, threads = 0
))]
#[allow(clippy::too_many_arguments)]
pub fn estimate<'py>(
    py: Python<'py>,
    x0: &Bound<'py, PyAny>,
    x2: &Bound<'py, PyAny>,
    sigma_s: f64,
    sigma_t: f64,
    phase: Option<&Bound<'py, PyAny>>,
    technique: &str,
    samples: i128,
    seed: i128,
    theta_max: f64,
    receiver_normal: Option<&Bound<'py, PyAny>>,
    dtype: Option<&Bound<'py, PyAny>>,
    reference: bool,
    threads: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let x0 = crate::array::point("x0", x0)?;
    let x2 = crate::array::point("x2", x2)?;
    let phase = match phase {
        Some(p) => crate::technique::phase_arg(p)?,
        None => Phase::parse("iso")?,
    };
    let precision = match dtype {
        Some(d) => precision(d)?,
        None => Precision::F32,
    };
    let range = |r: Range, field, x| r.check(field, x).map_err(error::cli);
    let samples = u64::try_from(samples)
        .ok()
        .filter(|n| (1..=1 << 40).contains(n))
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "samples = {samples} is out of range; allowed: [1, 2^40]"
            ))
        })?;
    let seed = u64::try_from(seed).map_err(|_| {
        PyValueError::new_err(format!("seed = {seed} is out of range; allowed: [0, 2^64)"))
    })?;
    range(Range::NON_NEGATIVE, "sigma_s", sigma_s)?;
    if !(sigma_t.is_finite() && sigma_t >= sigma_s) {
        return Err(PyValueError::new_err(format!(
            "sigma_t = {sigma_t} is out of range; allowed: [sigma_s, inf) = [{sigma_s}, inf)"
        )));
    }
    range(Range::open_closed(0.0, PI), "theta_max", theta_max)?;
    let receiver_normal = receiver_normal
        .map(|n| {
            unit(
                "receiver_normal",
                crate::array::point("receiver_normal", n)?,
            )
        })
        .transpose()?;
    let s = (0..3).map(|i| (x2[i] - x0[i]).powi(2)).sum::<f64>().sqrt();
    if !(s > 0.0) {
        return Err(PyValueError::new_err(format!(
            "x2 = {x2:?} equals x0; allowed: any other point"
        )));
    }
    let g = phase.mean_cosine_f64()?;
    let tau = sigma_t * s;
    let choice = choose("technique", technique, g, tau).map_err(error::cli)?;
    let problem = Problem {
        x0,
        x2,
        phase,
        sigma_s,
        sigma_t,
        theta_max,
        receiver_normal,
        g,
        tau,
        choice,
    };
    let start = Instant::now();
    let run = py.detach(|| {
        with_threads(threads, || match precision {
            Precision::F32 => problem.run::<f32>(samples, seed, reference),
            Precision::F64 => problem.run::<f64>(samples, seed, reference),
        })
    })??;
    let seconds = start.elapsed().as_secs_f64();
    let (mean, stderr) = run.moments.mean_stderr(samples);
    py.import("omnee")?.getattr("Estimate")?.call1((
        mean,
        stderr,
        run.reference,
        problem.choice.tech.name(),
        problem.choice.reason.clone(),
        samples,
        run.accepted,
        problem.g,
        problem.tau,
        seconds,
    ))
}
