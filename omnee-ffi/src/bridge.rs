//! `omnee_bridge_*` and `omnee_vertex_count_*`: bridges of k scattering
//! vertices between x0 and x2 (docs/math.md §14), the number k drawn per
//! connection, and the isotropic closed form of the k-times scattered
//! transfer, the core's `omnee_core::bridge` one to one.
//!
//! A bridge is drawn for a connection (its end points; θmax must be π) and
//! a phase function; its estimate and the reference take a problem (σs, σt,
//! no receiver cosine), as `omnee_problem_estimate_*` does for one vertex.

use crate::args::{finite, object, required};
use crate::boundary::{overlap, slice, slice_mut};
use crate::status::{ErrorOut, Failure, fail, finish, omnee_error, omnee_status};
use crate::types::{
    Precision, omnee_bridge, omnee_connection_f32, omnee_connection_f64, omnee_phase_f32,
    omnee_phase_f64, omnee_problem_f32, omnee_problem_f64, omnee_vec3, omnee_vertex_count_f32,
    omnee_vertex_count_f64, omnee_vertex_draw,
};
use core::mem::{MaybeUninit, size_of};
use omnee_core::Error;
use omnee_core::bridge::{Bridge, MAX_VERTICES, VertexCount, isotropic_transfer};
use omnee_core::phase::{Isotropic, Phase, PhaseFunction};
use omnee_core::real::Real;
use omnee_core::reference::PointToPoint;

/// The largest number of inner vertices of a bridge (the core's
/// `MAX_VERTICES`); a vertex array of this capacity fits every bridge.
pub const OMNEE_MAX_VERTICES: usize = 32;

/// The default evaluation budget of `omnee_bridge_reference_*` (the core's
/// `REFERENCE_BUDGET`): tens of milliseconds at most.
pub const OMNEE_REFERENCE_BUDGET: usize = 1_000_000;

// The header's constants are the core's (cbindgen writes literals only).
/// cbindgen:ignore
const _: () = {
    assert!(OMNEE_MAX_VERTICES == MAX_VERTICES);
    assert!(OMNEE_REFERENCE_BUDGET == omnee_core::bridge::REFERENCE_BUDGET);
};

/// `k` in `1 ..= MAX_VERTICES`, else `OMNEE_ERROR_OUT_OF_RANGE` naming `field`.
fn order(k: usize, field: &'static str) -> Result<usize, Failure> {
    if (1..=MAX_VERTICES).contains(&k) {
        Ok(k)
    } else {
        Err(Error::OutOfRange {
            field,
            value: k as f64,
            allowed: "[1, 32] (OMNEE_MAX_VERTICES)",
        }
        .into())
    }
}

/// A connection whose θmax is π: bridges take every deflection.
fn whole<F: Real>(theta_max: F) -> Result<(), Failure> {
    if theta_max >= F::PI {
        Ok(())
    } else {
        Err(Error::OutOfRange {
            field: "theta_max",
            value: theta_max.to_f64(),
            allowed: "pi (a bridge takes every deflection)",
        }
        .into())
    }
}

/// The bridge of a connection (θmax = π) and a phase function.
fn bridge<'a, F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&'a F::Phase>,
) -> Result<Bridge<F, &'a Phase<'static, F>>, Failure> {
    let (connection, phase) = (*object(connection)?, object(phase)?);
    whole(connection.theta_max)?;
    Ok(Bridge {
        axis: connection.axis,
        phase,
    })
}

/// A problem that bridges can estimate: θmax = π, no receiver cosine.
fn bridge_problem<F: Precision>(problem: Option<&F::Problem>) -> Result<PointToPoint<F>, Failure> {
    let problem = *object(problem)?;
    whole(problem.connection.theta_max)?;
    if problem.receiver_normal.is_some() {
        return Err(Failure::Unsupported {
            field: "receiver_normal",
            reason: "bridges have no receiver cosine (make the problem with receiver_normal = NULL)",
        });
    }
    Ok(problem)
}

/// Draws a bridge of `k` inner vertices x_1 … x_k from x0 to x2 of
/// `connection` (whose θmax must be π, else `OMNEE_ERROR_OUT_OF_RANGE`,
/// field "theta_max"), with `phase` at every vertex (docs/math.md §14): a
/// chain of k + 1 edges with deflections from the phase function and edge
/// proportions uniform on the simplex, turned and scaled about x0 until it
/// ends at x2. `u` points to 3k numbers in [0, 1], three per vertex
/// (u_θ, u_φ, u_t); `vertices` to `capacity` ≥ k points, of which the first
/// k receive the vertices. `*sample_out` gets k, the length D, the density
/// pdf = s³ k! Π q(θ_i) / (Π d_j² D^{k+1}) in the product of volume
/// measures and the weight (p/q) D^{k+1}/(s³ k!).
///
/// `OMNEE_NONE` when the numbers map to no contributing path (an edge of
/// length 0, or a vertex beyond the largest number, which end points near
/// it can ask for): the sample and `vertices[0..k)` are zero. On an error
/// (k = 0 or > OMNEE_MAX_VERTICES and u or vertices NULL:
/// `OMNEE_ERROR_OUT_OF_RANGE`/`_NULL`; capacity < k: `OMNEE_ERROR_OUT_OF_RANGE`,
/// field "capacity"; a NaN or infinite u: `OMNEE_ERROR_NOT_FINITE`; u outside
/// [0, 1]: `OMNEE_ERROR_OUT_OF_RANGE`; `vertices` overlapping `u`:
/// `OMNEE_ERROR_TABLE`) the sample is zeroed and `vertices` is left as it was.
///
/// # Safety
/// `u` is NULL or points to 3k floats; `vertices` is NULL or points to
/// `capacity` writable points.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn omnee_bridge_sample_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    k: usize,
    u: *const f32,
    vertices: *mut omnee_vec3<f32>,
    capacity: usize,
    sample_out: Option<&mut MaybeUninit<omnee_bridge<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the pointer contract is the caller's (above).
    unsafe {
        sample::<f32>(
            connection, phase, k, u, vertices, capacity, sample_out, error,
        )
    }
}

/// `omnee_bridge_sample_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3k doubles; `vertices` is NULL or points to
/// `capacity` writable points.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn omnee_bridge_sample_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    k: usize,
    u: *const f64,
    vertices: *mut omnee_vec3<f64>,
    capacity: usize,
    sample_out: Option<&mut MaybeUninit<omnee_bridge<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the pointer contract is the caller's (above).
    unsafe {
        sample::<f64>(
            connection, phase, k, u, vertices, capacity, sample_out, error,
        )
    }
}

/// The body of `omnee_bridge_sample_*`.
///
/// # Safety
/// As the exported functions'.
#[allow(clippy::too_many_arguments)]
unsafe fn sample<F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    k: usize,
    u: *const F,
    vertices: *mut omnee_vec3<F>,
    capacity: usize,
    out: Option<&mut MaybeUninit<omnee_bridge<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    // No write anywhere before the sample's own pointer is known good.
    if out.is_none() {
        return finish(out, "sample", error, Ok(None));
    }
    let result = (|| {
        let bridge = bridge::<F>(connection, phase)?;
        let k = order(k, "k")?;
        if capacity < k {
            return Err(Error::OutOfRange {
                field: "capacity",
                value: capacity as f64,
                allowed: "at least k (the vertex array's length)",
            }
            .into());
        }
        // SAFETY: u points to 3k values (the contract).
        let numbers = unsafe { slice(u, 3 * k) }.ok_or(Failure::Null("u"))?;
        if !numbers.iter().all(|x| x.is_finite()) {
            return Err(Error::not_finite("u").into());
        }
        if let Some(&bad) = numbers.iter().find(|&&x| !(F::ZERO..=F::ONE).contains(&x)) {
            return Err(Error::OutOfRange {
                field: "u",
                value: bad.to_f64(),
                allowed: "[0, 1]",
            }
            .into());
        }
        let (bytes_u, bytes_v) = (
            3 * k * size_of::<F>(),
            capacity * size_of::<omnee_vec3<F>>(),
        );
        if overlap(u.cast::<u8>(), bytes_u, vertices.cast::<u8>(), bytes_v) {
            return Err(Error::Arrays {
                field: "vertices",
                reason: "overlaps u",
            }
            .into());
        }
        // SAFETY: vertices points to `capacity` writable points that do not
        // overlap u (checked above) and nothing else accesses (the contract).
        let written = unsafe { slice_mut(vertices, capacity) }.ok_or(Failure::Null("vertices"))?;
        let mut uk = [[F::ZERO; 3]; MAX_VERTICES];
        for (ui, chunk) in uk.iter_mut().zip(numbers.chunks_exact(3)) {
            *ui = [chunk[0], chunk[1], chunk[2]];
        }
        let mut x = [bridge.axis.x0; MAX_VERTICES];
        let drawn = bridge.sample(&uk[..k], &mut x[..k]).filter(|s| {
            s.pdf.is_finite()
                && s.weight.is_finite()
                && s.length.is_finite()
                && x[..k]
                    .iter()
                    .all(|&v| omnee_vec3::<F>::from_core(v).is_finite())
        });
        for (slot, &v) in written[..k].iter_mut().zip(&x[..k]) {
            *slot = match drawn {
                Some(_) => omnee_vec3::from_core(v),
                None => omnee_vec3::default(),
            };
        }
        Ok(drawn.map(omnee_bridge::from_core))
    })();
    finish(out, "sample", error, result)
}

/// The density of `omnee_bridge_sample_*` at the path x0, `vertices[0..k)`,
/// x2 of `connection` (θmax = π) with `phase`:
/// s³ k! Π q(θ_i) / (Π d_j² D^{k+1}) (docs/math.md §14.4), 0 where two
/// consecutive points coincide. k ∈ [1, OMNEE_MAX_VERTICES]; `vertices`
/// points to k finite points (`OMNEE_ERROR_NOT_FINITE`, field "vertices").
///
/// # Safety
/// `vertices` is NULL or points to k points.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_bridge_pdf_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    k: usize,
    vertices: *const omnee_vec3<f32>,
    pdf: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the pointer contract is the caller's (above).
    unsafe { pdf_of::<f32>(connection, phase, k, vertices, pdf, error) }
}

/// `omnee_bridge_pdf_f32` in double precision.
///
/// # Safety
/// `vertices` is NULL or points to k points.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_bridge_pdf_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    k: usize,
    vertices: *const omnee_vec3<f64>,
    pdf: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the pointer contract is the caller's (above).
    unsafe { pdf_of::<f64>(connection, phase, k, vertices, pdf, error) }
}

/// The body of `omnee_bridge_pdf_*`.
///
/// # Safety
/// As the exported functions'.
unsafe fn pdf_of<F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    k: usize,
    vertices: *const omnee_vec3<F>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let bridge = bridge::<F>(connection, phase)?;
        let k = order(k, "k")?;
        // SAFETY: vertices points to k points (the contract).
        let points = unsafe { slice(vertices, k) }.ok_or(Failure::Null("vertices"))?;
        if !points.iter().all(|p| p.is_finite()) {
            return Err(Error::not_finite("vertices").into());
        }
        let mut x = [bridge.axis.x0; MAX_VERTICES];
        for (xi, p) in x.iter_mut().zip(points) {
            *xi = p.get();
        }
        finite(bridge.pdf(&x[..k]), "pdf").map(Some)
    })();
    finish(out, "pdf", error, result)
}

/// The uniform numbers that `omnee_bridge_sample_*` maps to the path x0,
/// `vertices[0..k)`, x2 of `connection` (θmax = π) with `phase`, written to
/// `u[0..3k)` (three per vertex, as `omnee_bridge_sample_*` reads them);
/// `capacity` is u's length, at least 3k. `OMNEE_NONE` (u[0..3k) zero) where
/// the map has no inverse: coincident points, a first deflection of 0 or π,
/// or a phase function whose sampler is not invertible (mixtures). On an
/// error (k out of range, capacity < 3k, NULL, a NaN vertex, u overlapping
/// the vertices) u is left as it was.
///
/// # Safety
/// `vertices` is NULL or points to k points; `u` is NULL or points to
/// `capacity` writable numbers.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_bridge_invert_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    k: usize,
    vertices: *const omnee_vec3<f32>,
    u: *mut f32,
    capacity: usize,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the pointer contract is the caller's (above).
    unsafe { invert::<f32>(connection, phase, k, vertices, u, capacity, error) }
}

/// `omnee_bridge_invert_f32` in double precision.
///
/// # Safety
/// `vertices` is NULL or points to k points; `u` is NULL or points to
/// `capacity` writable numbers.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_bridge_invert_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    k: usize,
    vertices: *const omnee_vec3<f64>,
    u: *mut f64,
    capacity: usize,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the pointer contract is the caller's (above).
    unsafe { invert::<f64>(connection, phase, k, vertices, u, capacity, error) }
}

/// The body of `omnee_bridge_invert_*`.
///
/// # Safety
/// As the exported functions'.
unsafe fn invert<F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    k: usize,
    vertices: *const omnee_vec3<F>,
    u: *mut F,
    capacity: usize,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let bridge = bridge::<F>(connection, phase)?;
        let k = order(k, "k")?;
        if capacity < 3 * k {
            return Err(Error::OutOfRange {
                field: "capacity",
                value: capacity as f64,
                allowed: "at least 3k (the length of u)",
            }
            .into());
        }
        // SAFETY: vertices points to k points (the contract).
        let points = unsafe { slice(vertices, k) }.ok_or(Failure::Null("vertices"))?;
        if !points.iter().all(|p| p.is_finite()) {
            return Err(Error::not_finite("vertices").into());
        }
        let (bytes_v, bytes_u) = (k * size_of::<omnee_vec3<F>>(), capacity * size_of::<F>());
        if overlap(
            vertices.cast::<u8>(),
            bytes_v,
            u.cast::<u8>().cast_const(),
            bytes_u,
        ) {
            return Err(Error::Arrays {
                field: "u",
                reason: "overlaps vertices",
            }
            .into());
        }
        let mut x = [bridge.axis.x0; MAX_VERTICES];
        for (xi, p) in x.iter_mut().zip(points) {
            *xi = p.get();
        }
        let mut numbers = [[F::ZERO; 3]; MAX_VERTICES];
        let found = bridge
            .invert(&x[..k], &mut numbers[..k])
            .filter(|()| numbers[..k].iter().flatten().all(|v| v.is_finite()));
        // SAFETY: u points to `capacity` ≥ 3k writable numbers that do not
        // overlap the vertices (checked above) and nothing else accesses.
        let out = unsafe { slice_mut(u, capacity) }.ok_or(Failure::Null("u"))?;
        for (slot, &v) in out[..3 * k].iter_mut().zip(numbers[..k].iter().flatten()) {
            *slot = if found.is_some() { v } else { F::ZERO };
        }
        Ok(found)
    })();
    match result {
        Ok(Some(())) => omnee_status::OMNEE_OK,
        Ok(None) => omnee_status::OMNEE_NONE,
        Err(failure) => fail(error, failure),
    }
}

/// One estimate of I_k = ∫…∫ Π σs p(θ_i) e^{−σt D} / (d_1² ⋯ d_{k+1}²) dx_1 ⋯ dx_k
/// for the problem's medium (σs, σt; θmax = π and no receiver cosine, else
/// `OMNEE_ERROR_OUT_OF_RANGE` / `OMNEE_ERROR_UNSUPPORTED`) from a bridge of
/// `omnee_bridge_sample_*` drawn for the problem's connection:
/// σs^k e^{−σt D} · weight, evaluated without forming D^{k+1} or e^{−σt D}
/// alone (docs/math.md §14.5); finite and ≥ 0 (0 where it underflows).
/// `sample` must hold k ∈ [0, OMNEE_MAX_VERTICES] and finite, non-negative
/// numbers (`OMNEE_ERROR_OUT_OF_RANGE`, field "sample.k" or "sample"); the
/// zero sample of `OMNEE_NONE` (k = 0) estimates 0.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_bridge_estimate_f32(
    problem: Option<&omnee_problem_f32>,
    sample: Option<&omnee_bridge<f32>>,
    estimate: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    estimate_of::<f32>(problem, sample, estimate, error)
}

/// `omnee_bridge_estimate_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_bridge_estimate_f64(
    problem: Option<&omnee_problem_f64>,
    sample: Option<&omnee_bridge<f64>>,
    estimate: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    estimate_of::<f64>(problem, sample, estimate, error)
}

/// The body of `omnee_bridge_estimate_*`.
fn estimate_of<F: Precision>(
    problem: Option<&F::Problem>,
    sample: Option<&omnee_bridge<F>>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let problem = bridge_problem::<F>(problem)?;
        let sample = required(sample, "sample")?;
        if sample.k > MAX_VERTICES {
            order(sample.k, "sample.k")?;
        }
        let fields = [sample.length, sample.pdf, sample.phase_ratio, sample.weight];
        if !fields.iter().all(|x| x.is_finite() && *x >= F::ZERO) {
            return Err(Error::OutOfRange {
                field: "sample",
                value: f64::NAN,
                allowed: "finite, non-negative length, pdf, phase_ratio and weight",
            }
            .into());
        }
        let bridge = Bridge {
            axis: problem.connection.axis,
            phase: Isotropic,
        };
        let value = bridge.estimate(&sample.get(), &problem.medium);
        finite(value, "estimate").map(Some)
    })();
    finish(out, "estimate", error, result)
}

/// The exact I_k for isotropic scattering in the problem's medium (θmax = π,
/// no receiver cosine) between its end points, s = |x2 − x0|, by adaptive
/// quadrature of the 1-D integral of docs/math.md §14.6 (relative accuracy
/// about 1e-10), in double precision whatever the problem's. k ∈
/// [1, OMNEE_MAX_VERTICES]; σt > 0 for k ≥ 2 (`OMNEE_ERROR_OUT_OF_RANGE`,
/// field "sigma_t": without extinction the integral diverges). Its cost is
/// bounded by `budget` evaluations of the integrand
/// (`OMNEE_REFERENCE_BUDGET` is the default, tens of milliseconds at most):
/// a quadrature that spends it returns `OMNEE_ERROR_NOT_CONVERGED` (field
/// "reference") and `*reference` = 0. Of its two integrals (docs/math.md
/// §14.6) it takes the one whose signs cancel little; where both would leave
/// fewer than ten digits (dense media: none for σt s up to 20, k = 17 … 28
/// at 30) it returns `OMNEE_ERROR_OUT_OF_RANGE` (field "k") and
/// `*reference` = 0, never a wrong value.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_bridge_reference_f32(
    problem: Option<&omnee_problem_f32>,
    k: usize,
    budget: usize,
    reference: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    reference_of::<f32>(problem, k, budget, reference, error)
}

/// `omnee_bridge_reference_f32` for a double-precision problem.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_bridge_reference_f64(
    problem: Option<&omnee_problem_f64>,
    k: usize,
    budget: usize,
    reference: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    reference_of::<f64>(problem, k, budget, reference, error)
}

/// The body of `omnee_bridge_reference_*`.
fn reference_of<F: Precision>(
    problem: Option<&F::Problem>,
    k: usize,
    budget: usize,
    out: Option<&mut MaybeUninit<f64>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let problem = bridge_problem::<F>(problem)?;
        let (s, medium) = (problem.connection.axis.s, problem.medium);
        let value = isotropic_transfer(
            order(k, "k")?,
            s.to_f64(),
            medium.sigma_s().to_f64(),
            medium.sigma_t().to_f64(),
            budget,
        )?;
        finite(value, "reference").map(Some)
    })();
    finish(out, "reference", error, result)
}

/// The distribution of the number of bridge vertices k ∈ [1, `k_max`]
/// (`k_max` ≤ OMNEE_MAX_VERTICES) for the problem's connection and medium and
/// `phase`'s mean cosine g (docs/math.md §14.7): a Poisson distribution of
/// mean μ = σs s (1 + (1 − |g|) σt s / 2) truncated to [1, k_max], mixed with
/// the uniform one for the share 0.2. Drawing k, then a bridge of k
/// vertices, and dividing its estimate by P(k) estimates Σ_{k=1}^{k_max} I_k
/// without bias. The problem's θmax and receiver cosine are not used.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_vertex_count_init_f32(
    count: Option<&mut MaybeUninit<omnee_vertex_count_f32>>,
    problem: Option<&omnee_problem_f32>,
    phase: Option<&omnee_phase_f32>,
    k_max: usize,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    count_init::<f32>(count, problem, phase, k_max, error)
}

/// `omnee_vertex_count_init_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_vertex_count_init_f64(
    count: Option<&mut MaybeUninit<omnee_vertex_count_f64>>,
    problem: Option<&omnee_problem_f64>,
    phase: Option<&omnee_phase_f64>,
    k_max: usize,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    count_init::<f64>(count, problem, phase, k_max, error)
}

/// The body of `omnee_vertex_count_init_*`.
fn count_init<F: Precision>(
    out: Option<&mut MaybeUninit<F::VertexCount>>,
    problem: Option<&F::Problem>,
    phase: Option<&F::Phase>,
    k_max: usize,
    error: ErrorOut<'_>,
) -> omnee_status {
    use crate::types::Object;
    let result = (|| {
        let (problem, phase) = (object(problem)?, object(phase)?);
        let k_max = order(k_max, "k_max")?;
        let m = problem.medium;
        let count = VertexCount::new(
            k_max,
            problem.connection.axis.s,
            m.sigma_s(),
            m.sigma_t(),
            phase.mean_cosine(),
        )?;
        Ok(Some(F::VertexCount::new(count)))
    })();
    finish(out, "count", error, result)
}

/// Draws k by inversion of the distribution's table from `u` ∈ [0, 1)
/// (`u` = 1 gives k_max; NaN: `OMNEE_ERROR_NOT_FINITE`, outside [0, 1]:
/// `OMNEE_ERROR_OUT_OF_RANGE`), with its probability P(k).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_vertex_count_sample_f32(
    count: Option<&omnee_vertex_count_f32>,
    u: f32,
    draw: Option<&mut MaybeUninit<omnee_vertex_draw<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    count_sample::<f32>(count, u, draw, error)
}

/// `omnee_vertex_count_sample_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_vertex_count_sample_f64(
    count: Option<&omnee_vertex_count_f64>,
    u: f64,
    draw: Option<&mut MaybeUninit<omnee_vertex_draw<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    count_sample::<f64>(count, u, draw, error)
}

/// The body of `omnee_vertex_count_sample_*`.
fn count_sample<F: Precision>(
    count: Option<&F::VertexCount>,
    u: F,
    out: Option<&mut MaybeUninit<omnee_vertex_draw<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let count = object(count)?;
        if !u.is_finite() {
            return Err(Error::not_finite("u").into());
        }
        if !(F::ZERO..=F::ONE).contains(&u) {
            return Err(Error::OutOfRange {
                field: "u",
                value: u.to_f64(),
                allowed: "[0, 1]",
            }
            .into());
        }
        let (k, probability) = count.sample(u);
        Ok(Some(omnee_vertex_draw { k, probability }))
    })();
    finish(out, "draw", error, result)
}

/// P(k) of the distribution: 0 for k outside [1, k_max].
#[unsafe(no_mangle)]
pub extern "C" fn omnee_vertex_count_pmf_f32(
    count: Option<&omnee_vertex_count_f32>,
    k: usize,
    probability: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    count_pmf::<f32>(count, k, probability, error)
}

/// `omnee_vertex_count_pmf_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_vertex_count_pmf_f64(
    count: Option<&omnee_vertex_count_f64>,
    k: usize,
    probability: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    count_pmf::<f64>(count, k, probability, error)
}

/// The body of `omnee_vertex_count_pmf_*`.
fn count_pmf<F: Precision>(
    count: Option<&F::VertexCount>,
    k: usize,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = object(count).map(|c| Some(c.pmf(k)));
    finish(out, "probability", error, result)
}
