//! `omnee.estimate`: the point-to-point once-more integral of
//! `omnee estimate`, computed by the same function of the library
//! ([`omnee_render::point::estimate::estimate`]), so the same seed gives the
//! same numbers as `omnee estimate --json`. This module only turns Python's
//! arguments into the library's [`Problem`] (whose fields the keyword
//! arguments are named after, and which names a bad one as Python spells
//! it) and the result into `omnee.Estimate`.

use crate::error;
use crate::phase::Phase;
use omnee_core::bridge::MAX_VERTICES;
use omnee_core::method::Choice;
use omnee_core::names::Named;
use omnee_render::error::Spelling;
use omnee_render::parallel::with_threads;
use omnee_render::point::estimate::estimate as run;
use omnee_render::point::problem::{Precision, Problem};
use omnee_render::vertices::{DEFAULT_MAX_VERTICES, VertexNumber};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::f64::consts::PI;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How often a waiting call looks for Ctrl-C (Python's signal handlers run
/// on the main thread, between bytecodes or when asked).
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// `work(cancel)` on a thread of its own, the GIL released, while this
/// thread waits for it and runs Python's signal handlers every
/// [`SIGNAL_POLL`]: a `KeyboardInterrupt` (or any exception a handler
/// raises) sets `cancel`, which the work checks between chunks, and is
/// raised at once; the work then stops at its next check, on its own.
fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send + 'static,
) -> PyResult<T> {
    let cancel = Arc::new(AtomicBool::new(false));
    let waiter = std::thread::current();
    let worker = {
        let cancel = Arc::clone(&cancel);
        std::thread::spawn(move || {
            let result = work(&cancel);
            waiter.unpark();
            result
        })
    };
    py.detach(|| {
        while !worker.is_finished() {
            std::thread::park_timeout(SIGNAL_POLL);
            if worker.is_finished() {
                break;
            }
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                cancel.store(true, Ordering::Relaxed);
                return Err(e);
            }
        }
        Ok(())
    })?;
    worker
        .join()
        .map_err(|panic| std::panic::resume_unwind(panic))
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

/// The technique called `name`, or `auto`.
fn technique(name: &str) -> PyResult<Choice> {
    Choice::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "technique = \"{name}\" is not a technique; allowed: {}",
            Choice::allowed()
        ))
    })
}

/// A Python integer as `u64`; the range message of `field` where it does
/// not fit (the command checks the range itself).
fn unsigned(field: &str, n: i128, allowed: &str) -> PyResult<u64> {
    u64::try_from(n).map_err(|_| {
        PyValueError::new_err(format!("{field} = {n} is out of range; allowed: {allowed}"))
    })
}

/// A Python integer as a count (`threads`), its range message where it is
/// negative or too large.
fn count(field: &str, n: i128, allowed: &str) -> PyResult<usize> {
    usize::try_from(n)
        .ok()
        .filter(|&n| n <= 1024)
        .ok_or_else(|| {
            PyValueError::new_err(format!("{field} = {n} is out of range; allowed: {allowed}"))
        })
}

/// The number of vertices from `vertices` (an integer K in [1, 32], or
/// `"auto"`; `None`: 1) and `max_vertices` (the largest K of `"auto"`, in
/// [1, 32], default 8; refused with a fixed K).
fn vertex_number(
    vertices: Option<&Bound<'_, PyAny>>,
    max_vertices: Option<i128>,
) -> PyResult<VertexNumber> {
    let allowed = format!("an integer K in [1, {MAX_VERTICES}] or \"auto\"");
    let max = match max_vertices {
        None => None,
        Some(m) => Some(
            usize::try_from(m)
                .ok()
                .filter(|m| (1..=MAX_VERTICES).contains(m))
                .ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "max_vertices = {m} is out of range; allowed: [1, {MAX_VERTICES}]"
                    ))
                })?,
        ),
    };
    let number = match vertices {
        None => VertexNumber::Fixed(1),
        Some(v) => {
            if let Ok(text) = v.extract::<String>() {
                VertexNumber::parse(&text, max.unwrap_or(DEFAULT_MAX_VERTICES)).map_err(|_| {
                    PyValueError::new_err(format!("vertices = {text:?}; allowed: {allowed}"))
                })?
            } else if let Ok(k) = v.extract::<i128>() {
                let k = usize::try_from(k)
                    .ok()
                    .filter(|k| (1..=MAX_VERTICES).contains(k))
                    .ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "vertices = {k} is out of range; allowed: [1, {MAX_VERTICES}]"
                        ))
                    })?;
                VertexNumber::Fixed(k)
            } else {
                return Err(PyTypeError::new_err(format!(
                    "vertices: expected {allowed}, got {}",
                    v.get_type().name()?
                )));
            }
        }
    };
    match (number, max) {
        (VertexNumber::Fixed(k), Some(m)) => Err(PyValueError::new_err(format!(
            "max_vertices = {m} applies to vertices=\"auto\" only (vertices = {k}); allowed: None"
        ))),
        (n, _) => Ok(n),
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
/// standard error. `dtype` is the precision of the draws: float64 (the
/// default) or float32 (the renderer's, `omnee estimate`'s default).
/// `reference=True` adds the f64 quadrature value of `I` (docs/math.md §5).
/// A reference that spends its evaluation budget raises
/// `omnee.NotConvergedError` (a `RuntimeError`).
///
/// `vertices=K` (an integer in [1, 32]; default 1, the once-more integral)
/// estimates instead the transfer of K scattering vertices by bridges
/// (docs/math.md §14),
/// `I_K = ∫…∫ Π σs p(θ_i) e^{−σt (d_1 + … + d_{K+1})} / (d_1² ⋯ d_{K+1}²) dx_1 ⋯ dx_K`,
/// and `vertices="auto"` the sum of `I_K` over K = 1 … `max_vertices`
/// (default 8) with K drawn per sample; both take θmax = π, no receiver
/// normal and `technique="auto"`, and their reference is the isotropic
/// closed form (`phase` "iso" or "hg:0"; any other phase function with
/// `reference=True` is a `ValueError`: pass `reference=False`).
/// Ctrl-C raises `KeyboardInterrupt` within milliseconds (the draws stop
/// at their next chunk). Returns `Estimate(mean, stderr, reference, technique,
/// auto_reason, samples, accepted, mean_cosine, tau, seconds)`.
#[pyfunction]
#[pyo3(signature = (
    *, x0, x2, sigma_s, sigma_t, phase = None, technique = "auto", samples = 100_000, seed = 1,
    theta_max = PI, receiver_normal = None, dtype = None, reference = true, threads = 0,
    vertices = None, max_vertices = None
), text_signature = "(*, x0, x2, sigma_s, sigma_t, phase=None, technique='auto', samples=100000, \
    seed=1, theta_max=3.141592653589793, receiver_normal=None, dtype=None, reference=True, \
    threads=0, vertices=1, max_vertices=None)")]
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
    threads: i128,
    vertices: Option<&Bound<'py, PyAny>>,
    max_vertices: Option<i128>,
) -> PyResult<Bound<'py, PyAny>> {
    let phase = match phase {
        Some(p) => crate::technique::phase_arg(p)?,
        None => Phase::parse("iso")?,
    };
    let problem = Problem {
        x0: crate::array::point("x0", x0)?,
        x2: crate::array::point("x2", x2)?,
        phase: phase.spec.to_string(),
        sigma_s,
        sigma_t,
        theta_max,
        receiver_normal: receiver_normal
            .map(|n| crate::array::point("receiver_normal", n))
            .transpose()?,
        technique: self::technique(technique)?,
        seed: unsigned("seed", seed, "[0, 2^64)")?,
        precision: match dtype {
            Some(d) => precision(d)?,
            None => Precision::F64,
        },
        x0_phase: None,
        x0_incoming: None,
        vertices: vertex_number(vertices, max_vertices)?,
    };
    let samples = unsigned("samples", samples, "[1, 2^40]")?;
    let threads = count("threads", threads, "[0, 1024], 0: one per core")?;
    let e = interruptible(py, move |cancel| {
        with_threads(threads, || {
            run(&problem, samples, reference, Spelling::Fields, cancel)
        })
        .and_then(|e| e)
    })?
    .map_err(error::render)?;
    py.import("omnee")?.getattr("Estimate")?.call1((
        e.mean,
        e.stderr,
        e.reference,
        e.technique.used.name(),
        e.technique.reason.map(|r| r.to_string()),
        e.samples,
        e.accepted,
        e.mean_cosine,
        e.tau,
        e.seconds,
    ))
}
