//! The techniques that place x1, each as the trio sample / pdf / invert:
//! `omnee_omnee_*` (angle first, then the circumcircle arc),
//! `omnee_equiangular_*`, `omnee_distance_*`, and `omnee_mis_*` (the core's
//! recommended OMNEE MIS with the equiangular companion); and
//! `omnee_omnee_sample_batch_f32`, the core's vectorised structure-of-arrays
//! entry point (OMNEE with Henyey–Greenstein, f32).
//!
//! The file is long by the ABI's shape, not by logic: four techniques × three
//! operations × two precisions are 24 documented `extern "C"` functions
//! (their doc comments become the header's), each a few lines over one
//! generic body per operation.

use crate::args::{finite, object, point, rays, uniforms};
use crate::boundary::{array, array_out, overlap, slice, slice_mut};
use crate::status::{ErrorOut, Failure, finish, omnee_error, omnee_status};
use crate::types::{
    Precision, omnee_connection_f32, omnee_connection_f64, omnee_draw, omnee_phase_f32,
    omnee_phase_f64, omnee_rays, omnee_sample, omnee_uniforms_f32, omnee_vec3, omnee_vertices_f32,
};
use core::mem::MaybeUninit;
use omnee_core::Error;
use omnee_core::mis::OmneeMis;
use omnee_core::phase::Phase;
use omnee_core::real::Real;
use omnee_core::sampling::{Distance, Equiangular, Omnee, Sample, Technique, Uniforms, Vertices};

/// A phase function borrowed from its C object.
type PhaseRef<'a, F> = &'a Phase<'static, F>;

/// A sample that is safe to hand out: every field finite.
fn sample_out<F: Real>(s: Sample<F>) -> Result<omnee_sample<F>, Failure> {
    let s = omnee_sample::from_core(s);
    if s.x1.is_finite() && s.pdf.is_finite() && s.weight.is_finite() {
        Ok(s)
    } else {
        Err(Error::not_finite("sample").into())
    }
}

/// `technique.sample(u)` into `out`.
fn sample<F: Real, T: Technique<F>>(
    technique: Result<T, Failure>,
    u: Option<[F; 3]>,
    out: Option<&mut MaybeUninit<omnee_sample<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let technique = technique?;
        technique.sample(uniforms(u)?).map(sample_out).transpose()
    })();
    finish(out, "sample", error, result)
}

/// `technique.pdf(x1)` into `out`.
fn pdf<F: Real, T: Technique<F>>(
    technique: Result<T, Failure>,
    x1: omnee_vec3<F>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let technique = technique?;
        finite(technique.pdf(point(x1, "x1")?), "pdf").map(Some)
    })();
    finish(out, "pdf", error, result)
}

/// `technique.invert(x1)` into `out`.
fn invert<F: Real, T: Technique<F>>(
    technique: Result<T, Failure>,
    x1: omnee_vec3<F>,
    out: Option<&mut MaybeUninit<[F; 3]>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let technique = technique?;
        let u = technique.invert(point(x1, "x1")?);
        u.map(|[a, b, c]| Ok([finite(a, "u")?, finite(b, "u")?, finite(c, "u")?]))
            .transpose()
    })();
    finish(out, "u", error, result)
}

/// OMNEE for a connection and phase function.
fn omnee<'a, F: Precision>(
    connection: Option<&'a F::Connection>,
    phase: Option<&'a F::Phase>,
) -> Result<Omnee<F, PhaseRef<'a, F>>, Failure> {
    Ok(Omnee::new(*object(connection)?, object(phase)?))
}

/// Equiangular sampling along rays from x2.
fn equiangular<'a, F: Precision>(
    connection: Option<&'a F::Connection>,
    phase: Option<&'a F::Phase>,
    ray: Option<&omnee_rays<F>>,
) -> Result<Equiangular<F, PhaseRef<'a, F>>, Failure> {
    let (connection, phase) = (*object(connection)?, object(phase)?);
    let (directions, region) = rays(ray)?;
    Ok(Equiangular::new(connection, phase, directions, region))
}

/// Distance sampling along rays from x2.
fn distance<'a, F: Precision>(
    connection: Option<&'a F::Connection>,
    phase: Option<&'a F::Phase>,
    ray: Option<&omnee_rays<F>>,
    sigma: F,
) -> Result<Distance<F, PhaseRef<'a, F>>, Failure> {
    let (connection, phase) = (*object(connection)?, object(phase)?);
    let (directions, region) = rays(ray)?;
    Ok(Distance::new(connection, phase, directions, region, sigma)?)
}

/// OMNEE (docs/math.md §3): θ from the phase function by `u[0]` (no sample if θ ≥ θmax),
/// β/θ = `u[1]`, φ = 2π `u[2]`; x1 on the circumcircle arc of constant θ through
/// x0 and x2. weight = θ/(s sin θ) (s = |x2 − x0|), pdf =
/// p(θ) (sin θ/θ) s/(d1² d2²). `u` points to 3 finite numbers (clamped into
/// [0, 1]). `OMNEE_NONE` when they map to no vertex that contributes.
///
/// # Safety
/// `u` is NULL or points to 3 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_sample_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    u: *const f32,
    sample_out: Option<&mut MaybeUninit<omnee_sample<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 floats (this function's contract).
    let u = unsafe { array(u) };
    sample(omnee::<f32>(connection, phase), u, sample_out, error)
}

/// `omnee_omnee_sample_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_sample_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    u: *const f64,
    sample_out: Option<&mut MaybeUninit<omnee_sample<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 doubles (this function's contract).
    let u = unsafe { array(u) };
    sample(omnee::<f64>(connection, phase), u, sample_out, error)
}

/// The volume density (1/m³) with which `omnee_omnee_sample_f32` places x1:
/// p(θ) (sin θ/θ) s/(d1² d2²), 0 for θ ≥ θmax and at the end points.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_omnee_pdf_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    x1: omnee_vec3<f32>,
    pdf_out: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    pdf(omnee::<f32>(connection, phase), x1, pdf_out, error)
}

/// `omnee_omnee_pdf_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_omnee_pdf_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    x1: omnee_vec3<f64>,
    pdf_out: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    pdf(omnee::<f64>(connection, phase), x1, pdf_out, error)
}

/// The 3 uniform numbers that `omnee_omnee_sample_f32` maps to x1:
/// (cdf(θ), β/θ, φ/2π). `OMNEE_NONE` for θ ≥ θmax or a mixture phase
/// function (not invertible).
///
/// # Safety
/// `u` is NULL or points to 3 writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_invert_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    x1: omnee_vec3<f32>,
    u: *mut f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 writable floats (this function's contract).
    let u = unsafe { array_out(u) };
    invert(omnee::<f32>(connection, phase), x1, u, error)
}

/// `omnee_omnee_invert_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3 writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_invert_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    x1: omnee_vec3<f64>,
    u: *mut f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 writable doubles (this function's contract).
    let u = unsafe { array_out(u) };
    invert(omnee::<f64>(connection, phase), x1, u, error)
}

/// Equiangular sampling (Kulla & Fajardo 2012; docs/math.md §8): a ray direction from x2 by
/// `u[0]`, `u[1]` (`rays`), then the distance along it inside the medium with
/// density ∝ 1/d1². weight = p(θ)/(pdf_ω · c) (0 for θ ≥ θmax).
///
/// # Safety
/// `u` is NULL or points to 3 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_equiangular_sample_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    u: *const f32,
    sample_out: Option<&mut MaybeUninit<omnee_sample<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 floats (this function's contract).
    let u = unsafe { array(u) };
    let technique = equiangular::<f32>(connection, phase, rays);
    sample(technique, u, sample_out, error)
}

/// `omnee_equiangular_sample_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_equiangular_sample_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    u: *const f64,
    sample_out: Option<&mut MaybeUninit<omnee_sample<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 doubles (this function's contract).
    let u = unsafe { array(u) };
    let technique = equiangular::<f64>(connection, phase, rays);
    sample(technique, u, sample_out, error)
}

/// The volume density of `omnee_equiangular_sample_f32` at x1:
/// pdf_ω(ω) · c/(d1² d2²) inside the medium segment, else 0.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_equiangular_pdf_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    x1: omnee_vec3<f32>,
    pdf_out: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    pdf(
        equiangular::<f32>(connection, phase, rays),
        x1,
        pdf_out,
        error,
    )
}

/// `omnee_equiangular_pdf_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_equiangular_pdf_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    x1: omnee_vec3<f64>,
    pdf_out: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    pdf(
        equiangular::<f64>(connection, phase, rays),
        x1,
        pdf_out,
        error,
    )
}

/// The 3 uniform numbers that `omnee_equiangular_sample_f32` maps to x1
/// (`OMNEE_NONE` below a cosine's horizon or off the medium).
///
/// # Safety
/// `u` is NULL or points to 3 writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_equiangular_invert_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    x1: omnee_vec3<f32>,
    u: *mut f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 writable floats (this function's contract).
    let u = unsafe { array_out(u) };
    invert(equiangular::<f32>(connection, phase, rays), x1, u, error)
}

/// `omnee_equiangular_invert_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3 writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_equiangular_invert_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    x1: omnee_vec3<f64>,
    u: *mut f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 writable doubles (this function's contract).
    let u = unsafe { array_out(u) };
    invert(equiangular::<f64>(connection, phase, rays), x1, u, error)
}

/// Distance sampling (docs/math.md §9): a ray direction from x2 by `u[0]`, `u[1]`, then the
/// free-flight distance with density ∝ σ e^{−σt} (σ = `sigma` ≥ 0, usually
/// the medium's σt), truncated to the medium segment.
///
/// # Safety
/// `u` is NULL or points to 3 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_distance_sample_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    sigma: f32,
    u: *const f32,
    sample_out: Option<&mut MaybeUninit<omnee_sample<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 floats (this function's contract).
    let u = unsafe { array(u) };
    let technique = distance::<f32>(connection, phase, rays, sigma);
    sample(technique, u, sample_out, error)
}

/// `omnee_distance_sample_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_distance_sample_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    sigma: f64,
    u: *const f64,
    sample_out: Option<&mut MaybeUninit<omnee_sample<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 doubles (this function's contract).
    let u = unsafe { array(u) };
    let technique = distance::<f64>(connection, phase, rays, sigma);
    sample(technique, u, sample_out, error)
}

/// The volume density of `omnee_distance_sample_f32` at x1.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_distance_pdf_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    sigma: f32,
    x1: omnee_vec3<f32>,
    pdf_out: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    pdf(
        distance::<f32>(connection, phase, rays, sigma),
        x1,
        pdf_out,
        error,
    )
}

/// `omnee_distance_pdf_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_distance_pdf_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    sigma: f64,
    x1: omnee_vec3<f64>,
    pdf_out: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    pdf(
        distance::<f64>(connection, phase, rays, sigma),
        x1,
        pdf_out,
        error,
    )
}

/// The 3 uniform numbers that `omnee_distance_sample_f32` maps to x1.
///
/// # Safety
/// `u` is NULL or points to 3 writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_distance_invert_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    sigma: f32,
    x1: omnee_vec3<f32>,
    u: *mut f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 writable floats (this function's contract).
    let u = unsafe { array_out(u) };
    invert(
        distance::<f32>(connection, phase, rays, sigma),
        x1,
        u,
        error,
    )
}

/// `omnee_distance_invert_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 3 writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_distance_invert_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    sigma: f64,
    x1: omnee_vec3<f64>,
    u: *mut f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 3 writable doubles (this function's contract).
    let u = unsafe { array_out(u) };
    invert(
        distance::<f64>(connection, phase, rays, sigma),
        x1,
        u,
        error,
    )
}

/// The recommended MIS of the core (`OmneeMis::recommended`, docs/math.md §10): OMNEE's vertex
/// always (from `u[0..3]`) and, when `u[3]` < c (c = 0.05), the equiangular
/// companion's (from `u[3]/c`, `u[4]`, `u[5]`) if it lies behind the cone
/// θ ≥ 3π/4; balance heuristic behind the cone, OMNEE alone in front of
/// it. `u` points to 6 finite numbers. Sum f_c · weight over the present
/// vertices for one estimate. `OMNEE_NONE` when neither is present.
///
/// # Safety
/// `u` is NULL or points to 6 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_mis_sample_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    u: *const f32,
    draw: Option<&mut MaybeUninit<omnee_draw<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 6 floats (this function's contract).
    let u = unsafe { array(u) };
    mis_sample::<f32>(connection, phase, rays, u, draw, error)
}

/// `omnee_mis_sample_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 6 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_mis_sample_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    u: *const f64,
    draw: Option<&mut MaybeUninit<omnee_draw<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 6 doubles (this function's contract).
    let u = unsafe { array(u) };
    mis_sample::<f64>(connection, phase, rays, u, draw, error)
}

/// The combined density of the MIS vertices at x1: p_OMNEE + c p_companion
/// behind the cone, p_OMNEE in front of it.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_mis_pdf_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    x1: omnee_vec3<f32>,
    pdf_out: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    mis_pdf::<f32>(connection, phase, rays, x1, pdf_out, error)
}

/// `omnee_mis_pdf_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_mis_pdf_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    x1: omnee_vec3<f64>,
    pdf_out: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    mis_pdf::<f64>(connection, phase, rays, x1, pdf_out, error)
}

/// 6 uniform numbers with which `omnee_mis_sample_f32` returns x1 (up to
/// rounding) as `vertices[vertex]`: vertex 0 (OMNEE's) takes OMNEE's inverse
/// and leaves the companion undrawn; vertex 1 (the companion's) takes the
/// equiangular inverse scaled into `u[3]` < c. `OMNEE_NONE` when x1 cannot be
/// that vertex (outside θmax, a mixture phase function, a companion vertex
/// in front of the cone).
///
/// # Safety
/// `u` is NULL or points to 6 writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_mis_invert_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    vertex: u32,
    x1: omnee_vec3<f32>,
    u: *mut f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 6 writable floats (this function's contract).
    let u = unsafe { array_out(u) };
    mis_invert::<f32>(connection, phase, rays, vertex, x1, u, error)
}

/// `omnee_mis_invert_f32` in double precision.
///
/// # Safety
/// `u` is NULL or points to 6 writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_mis_invert_f64(
    connection: Option<&omnee_connection_f64>,
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    vertex: u32,
    x1: omnee_vec3<f64>,
    u: *mut f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: u is NULL or points to 6 writable doubles (this function's contract).
    let u = unsafe { array_out(u) };
    mis_invert::<f64>(connection, phase, rays, vertex, x1, u, error)
}

/// Runs `f` on the core's recommended OMNEE MIS with its equiangular companion.
fn with_mis<F: Precision, R>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    ray: Option<&omnee_rays<F>>,
    f: impl FnOnce(&OmneeMis<'_, F, PhaseRef<'_, F>>, &dyn Technique<F>) -> Result<R, Failure>,
) -> Result<R, Failure> {
    let companion = equiangular::<F>(connection, phase, ray)?;
    let omnee = Omnee::new(companion.connection, companion.phase);
    f(&OmneeMis::recommended(omnee, &companion), &companion)
}

fn mis_sample<F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    ray: Option<&omnee_rays<F>>,
    u: Option<[F; 6]>,
    out: Option<&mut MaybeUninit<omnee_draw<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = with_mis::<F, _>(connection, phase, ray, |mis, _| {
        let mut draw = omnee_draw::default();
        for (k, vertex) in mis.sample(uniforms(u)?).into_iter().enumerate() {
            if let Some(s) = vertex {
                draw.vertices[k] = sample_out(s)?;
                draw.present |= 1 << k;
            }
        }
        Ok((draw.present != 0).then_some(draw))
    });
    finish(out, "draw", error, result)
}

fn mis_pdf<F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    ray: Option<&omnee_rays<F>>,
    x1: omnee_vec3<F>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = with_mis::<F, _>(connection, phase, ray, |mis, _| {
        finite(mis.pdf(point(x1, "x1")?), "pdf").map(Some)
    });
    finish(out, "pdf", error, result)
}

fn mis_invert<F: Precision>(
    connection: Option<&F::Connection>,
    phase: Option<&F::Phase>,
    ray: Option<&omnee_rays<F>>,
    vertex: u32,
    x1: omnee_vec3<F>,
    out: Option<&mut MaybeUninit<[F; 6]>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = with_mis::<F, _>(connection, phase, ray, |mis, companion| {
        let x1 = point(x1, "x1")?;
        let z = F::ZERO;
        let u = match vertex {
            0 => {
                let omnee = Omnee::new(*object(connection)?, object(phase)?);
                omnee
                    .invert(x1)
                    .map(|[a, b, c]| [a, b, c, F::ONE_MINUS_EPSILON, z, z])
            }
            1 => companion
                .invert(x1)
                .map(|[a, b, c]| [z, z, z, a * mis.rate(), b, c]),
            other => {
                return Err(Error::OutOfRange {
                    field: "vertex",
                    value: other as f64,
                    allowed: "0 (OMNEE) or 1 (companion)",
                }
                .into());
            }
        };
        // The core decides what the numbers draw: keep them only if they
        // bring back this vertex.
        let u = u.filter(|u| matches!(mis.sample(*u).get(vertex as usize), Some(Some(_))));
        u.map(|u| {
            for x in u {
                finite(x, "u")?;
            }
            Ok(u)
        })
        .transpose()
    });
    finish(out, "u", error, result)
}

/// OMNEE for every entry i of a batch: x1_i, its pdf and weight from
/// (u0_i, u1_i, u2_i), by the scalar sampler's formulas written
/// branch-free with polynomial sin, cos and atan (results agree with
/// `omnee_omnee_sample_f32` to a few ulps; the library's tests measure it).
/// An entry without a sample gets pdf = weight = 0 and x1 = x0.
/// `count` receives the number of entries with a sample.
///
/// The phase function must be Henyey–Greenstein (else
/// `OMNEE_ERROR_UNSUPPORTED`); `uniforms.len` must equal `vertices.len`
/// (else `OMNEE_ERROR_TABLE`), the uniform numbers must be finite (else
/// `OMNEE_ERROR_NOT_FINITE`, naming the array), no two of the eight arrays
/// may overlap, inputs included (else `OMNEE_ERROR_TABLE`), and `count`
/// must not be NULL (else `OMNEE_ERROR_NULL`). Every check comes before the
/// first write: on an error the vertex arrays are left as they were (and
/// `*count`, if `count` is not NULL, is 0).
///
/// # Safety
/// Each pointer in `uniforms` and `vertices` is NULL (allowed with length
/// 0) or points to as many floats as the struct's `len`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_sample_batch_f32(
    connection: Option<&omnee_connection_f32>,
    phase: Option<&omnee_phase_f32>,
    uniforms: omnee_uniforms_f32,
    vertices: omnee_vertices_f32,
    count: Option<&mut MaybeUninit<usize>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // No output is written before every check has passed, `count` first.
    let Some(count) = count else {
        return crate::status::fail(error, Failure::Null("count"));
    };
    let result = (|| {
        let connection = *object(connection)?;
        let Phase::HenyeyGreenstein(hg) = *object(phase)? else {
            return Err(Failure::Unsupported {
                field: "phase",
                reason: "the batch needs Henyey-Greenstein (hg)",
            });
        };
        let (n, m) = (uniforms.len, vertices.len);
        let inputs = [uniforms.u0, uniforms.u1, uniforms.u2];
        let outputs = [
            vertices.x,
            vertices.y,
            vertices.z,
            vertices.pdf,
            vertices.weight,
        ];
        let arrays = [
            (inputs[0], n),
            (inputs[1], n),
            (inputs[2], n),
            (outputs[0] as *const f32, m),
            (outputs[1], m),
            (outputs[2], m),
            (outputs[3], m),
            (outputs[4], m),
        ];
        // NULL arrays are reported as NULL below, not as overlapping.
        for (i, &(a, a_len)) in arrays.iter().enumerate() {
            let clash = arrays[i + 1..]
                .iter()
                .any(|&(b, b_len)| !a.is_null() && !b.is_null() && overlap(a, a_len, b, b_len));
            if clash {
                return Err(Error::Arrays {
                    field: "batch",
                    reason: "arrays overlap",
                }
                .into());
            }
        }
        // SAFETY: every array is NULL with length 0 or as long as its
        // struct's len (this function's contract); the output arrays overlap
        // neither each other nor the inputs (checked above).
        let input = |p, field| unsafe { slice(p, n) }.ok_or(Failure::Null(field));
        let (u0, u1, u2) = (
            input(inputs[0], "u0")?,
            input(inputs[1], "u1")?,
            input(inputs[2], "u2")?,
        );
        for (u, field) in [(u0, "u0"), (u1, "u1"), (u2, "u2")] {
            if !u.iter().all(|x| x.is_finite()) {
                return Err(Error::not_finite(field).into());
            }
        }
        // SAFETY: as above; each output array is borrowed once.
        let output = |p, field| unsafe { slice_mut(p, m) }.ok_or(Failure::Null(field));
        let out = Vertices {
            x: output(outputs[0], "x")?,
            y: output(outputs[1], "y")?,
            z: output(outputs[2], "z")?,
            pdf: output(outputs[3], "pdf")?,
            weight: output(outputs[4], "weight")?,
        };
        let omnee = Omnee::new(connection, hg);
        Ok(Some(omnee.sample_batch(Uniforms { u0, u1, u2 }, out)?))
    })();
    finish(Some(count), "count", error, result)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::connection::omnee_connection_init_f64;
    use crate::phase::omnee_phase_hg_f64;
    use crate::types::omnee_vec3;

    /// A connection, an HG phase function (g = 0.3, so that the companion's
    /// cone gets vertices) and all-zero rays (sphere, everywhere), in f64.
    fn setup() -> (omnee_connection_f64, omnee_phase_f64, omnee_rays<f64>) {
        let (mut c, mut p) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        let x0 = omnee_vec3 {
            x: 0.3,
            y: -0.2,
            z: 1.1,
        };
        let x2 = omnee_vec3 {
            x: -0.1,
            y: 0.4,
            z: 0.2,
        };
        let status = omnee_connection_init_f64(Some(&mut c), x0, x2, 3.0, None);
        assert_eq!(status, omnee_status::OMNEE_OK);
        assert_eq!(
            omnee_phase_hg_f64(Some(&mut p), 0.3, None),
            omnee_status::OMNEE_OK
        );
        // SAFETY: the constructor returned OMNEE_OK, so it wrote `c`.
        let c = unsafe { c.assume_init() };
        // SAFETY: the constructor returned OMNEE_OK, so it wrote `p`.
        let p = unsafe { p.assume_init() };
        (c, p, omnee_rays::default())
    }

    fn distance(a: omnee_vec3<f64>, b: omnee_vec3<f64>) -> f64 {
        ((a.x - b.x).powi(2) + (a.y - b.y).powi(2) + (a.z - b.z).powi(2)).sqrt()
    }

    #[test]
    fn mis_invert_brings_back_each_vertex() {
        let (c, p, rays) = setup();
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut checked, mut worst) = ([0usize; 2], 0.0f64);
        for _ in 0..20_000 {
            let u: [f64; 6] = core::array::from_fn(|_| next());
            let mut draw = MaybeUninit::uninit();
            // SAFETY: u holds 6 doubles.
            let status = unsafe {
                omnee_mis_sample_f64(
                    Some(&c),
                    Some(&p),
                    Some(&rays),
                    u.as_ptr(),
                    Some(&mut draw),
                    None,
                )
            };
            if status != omnee_status::OMNEE_OK {
                continue;
            }
            // SAFETY: written by the OMNEE_OK call above.
            let draw = unsafe { draw.assume_init() };
            for (k, vertex) in draw.vertices.iter().enumerate() {
                if draw.present & (1 << k) == 0 {
                    continue;
                }
                let x1 = vertex.x1;
                let mut v = [0.0f64; 6];
                // SAFETY: v has room for 6 doubles.
                let status = unsafe {
                    omnee_mis_invert_f64(
                        Some(&c),
                        Some(&p),
                        Some(&rays),
                        k as u32,
                        x1,
                        v.as_mut_ptr(),
                        None,
                    )
                };
                assert_eq!(status, omnee_status::OMNEE_OK, "vertex {k} at {x1:?}");
                let mut again = MaybeUninit::uninit();
                // SAFETY: v holds 6 doubles.
                let status = unsafe {
                    omnee_mis_sample_f64(
                        Some(&c),
                        Some(&p),
                        Some(&rays),
                        v.as_ptr(),
                        Some(&mut again),
                        None,
                    )
                };
                assert_eq!(status, omnee_status::OMNEE_OK);
                // SAFETY: written by the OMNEE_OK call above.
                let again = unsafe { again.assume_init() };
                assert!(again.present & (1 << k) != 0);
                worst =
                    worst.max(distance(again.vertices[k].x1, x1) / (1.0 + distance(x1, c_x0())));
                checked[k] += 1;
            }
        }
        std::println!("vertices checked {checked:?}, worst relative distance {worst:.1e}");
        assert!(checked[0] > 10_000 && checked[1] > 100, "{checked:?}");
        assert!(worst < 1e-9, "{worst:e}");
    }

    fn c_x0() -> omnee_vec3<f64> {
        omnee_vec3 {
            x: 0.3,
            y: -0.2,
            z: 1.1,
        }
    }

    #[test]
    fn a_vertex_in_front_of_the_cone_is_not_the_companions() {
        let (c, p, rays) = setup();
        // The midpoint of x0 x2: θ = 0, in front of the cone.
        let mid = omnee_vec3 {
            x: 0.1,
            y: 0.1,
            z: 0.65,
        };
        let mut v = [1.0f64; 6];
        // SAFETY: v has room for 6 doubles.
        let status = unsafe {
            omnee_mis_invert_f64(
                Some(&c),
                Some(&p),
                Some(&rays),
                1,
                mid,
                v.as_mut_ptr(),
                None,
            )
        };
        assert_eq!(status, omnee_status::OMNEE_NONE);
        assert_eq!(v, [0.0; 6]);
    }
}
