//! `omnee_problem_*`: the point-to-point problem, its factor f_c, one
//! estimate, and its quadrature reference.

use crate::args::{finite, object, point, required};
use crate::status::{ErrorOut, Failure, finish, omnee_error, omnee_status};
use crate::types::{
    Object, Precision, omnee_connection_f32, omnee_connection_f64, omnee_phase_f64,
    omnee_problem_f32, omnee_problem_f64, omnee_sample, omnee_vec3,
};
use core::mem::MaybeUninit;
use omnee_core::Error;
use omnee_core::medium::Homogeneous;
use omnee_core::reference::PointToPoint;

/// The point-to-point problem (docs/math.md §1, §5): a unit-intensity point
/// light at x0, a point receiver at x2, an infinite homogeneous medium with
/// σs = `sigma_s` ≥ 0 and σa = `sigma_a` ≥ 0 (1/m), the integrand restricted
/// to θ < θmax of `connection`:
/// I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1.
/// `receiver_normal` (NULL: none) adds the one-sided receiver cosine
/// cos θ2 = max(0, n·(x1 − x2)/d2) about that normal, normalised here: any
/// finite, non-zero length (components from 1e-45 or 4.9e-324 up to the
/// largest number); `OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
/// component, `OMNEE_ERROR_DEGENERATE` for the zero vector.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_init_f32(
    problem: Option<&mut MaybeUninit<omnee_problem_f32>>,
    connection: Option<&omnee_connection_f32>,
    sigma_s: f32,
    sigma_a: f32,
    receiver_normal: Option<&omnee_vec3<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    init(
        problem,
        connection,
        sigma_s,
        sigma_a,
        receiver_normal,
        error,
    )
}

/// `omnee_problem_init_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_init_f64(
    problem: Option<&mut MaybeUninit<omnee_problem_f64>>,
    connection: Option<&omnee_connection_f64>,
    sigma_s: f64,
    sigma_a: f64,
    receiver_normal: Option<&omnee_vec3<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    init(
        problem,
        connection,
        sigma_s,
        sigma_a,
        receiver_normal,
        error,
    )
}

fn init<F: Precision>(
    out: Option<&mut MaybeUninit<F::Problem>>,
    connection: Option<&F::Connection>,
    sigma_s: F,
    sigma_a: F,
    receiver_normal: Option<&omnee_vec3<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let connection = *object(connection)?;
        let medium = Homogeneous::new(sigma_s, sigma_a)?;
        let normal = receiver_normal.map(|n| n.get());
        let problem = PointToPoint::new(connection, medium, normal)?;
        Ok::<_, Failure>(Some(F::Problem::new(problem)))
    })();
    finish(out, "problem", error, result)
}

/// The factors no technique samples:
/// f_c(x1) = σs e^{−σt (d1 + d2)} [max(0, n·(x1 − x2)/d2)].
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_f_c_f32(
    problem: Option<&omnee_problem_f32>,
    x1: omnee_vec3<f32>,
    f_c: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    f_c_of::<f32>(problem, x1, f_c, error)
}

/// `omnee_problem_f_c_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_f_c_f64(
    problem: Option<&omnee_problem_f64>,
    x1: omnee_vec3<f64>,
    f_c: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    f_c_of::<f64>(problem, x1, f_c, error)
}

fn f_c_of<F: Precision>(
    problem: Option<&F::Problem>,
    x1: omnee_vec3<F>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let problem = object(problem)?;
        finite(problem.f_c(point(x1, "x1")?), "f_c").map(Some)
    })();
    finish(out, "f_c", error, result)
}

/// One estimate of the problem's integral from a sample of any technique:
/// f_c(x1) · weight (0 for weight 0), rounded to the precision (0 where the
/// product underflows: see SCALE above).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_estimate_f32(
    problem: Option<&omnee_problem_f32>,
    sample: Option<&omnee_sample<f32>>,
    estimate: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    estimate_of::<f32>(problem, sample, estimate, error)
}

/// `omnee_problem_estimate_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_estimate_f64(
    problem: Option<&omnee_problem_f64>,
    sample: Option<&omnee_sample<f64>>,
    estimate: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    estimate_of::<f64>(problem, sample, estimate, error)
}

fn estimate_of<F: Precision>(
    problem: Option<&F::Problem>,
    sample: Option<&omnee_sample<F>>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let problem = object(problem)?;
        let sample = required(sample, "sample")?;
        if !(sample.x1.is_finite() && sample.pdf.is_finite() && sample.weight.is_finite()) {
            return Err(Error::not_finite("sample").into());
        }
        finite(problem.estimate(&sample.get()), "estimate").map(Some)
    })();
    finish(out, "estimate", error, result)
}

/// The problem's integral I by adaptive Gauss–Kronrod quadrature in double
/// precision (relative accuracy about 1e-9 for smooth phase functions), with
/// the phase function `phase` (double precision, whatever the problem's).
/// Takes milliseconds, at most 0.2 s for a receiver normal and θmax = π: a
/// reference, not a per-sample call. Its cost is bounded: a quadrature that
/// spends its budget of evaluations (about a second; a normal at right
/// angles to x2 − x0, where the receiver's horizon passes through the axis,
/// is the known case) before meeting its tolerance returns
/// `OMNEE_ERROR_NOT_CONVERGED` (field "reference") and `*reference` = 0.
/// The quadrature runs in the connection's unit (see SCALE above): at any
/// distance s, subnormal included, the problem scaled by a power of two λ
/// (σ over λ) has the reference over λ², rounded once; an I beyond
/// double's range (at s = 1e-320, σs = 0.5 and θmax = π it is about
/// 1e320) is `OMNEE_ERROR_NOT_FINITE` (field "reference"), one below it 0.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_reference_f32(
    problem: Option<&omnee_problem_f32>,
    phase: Option<&omnee_phase_f64>,
    reference: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    reference_of::<f32>(problem, phase, reference, error)
}

/// `omnee_problem_reference_f32` for a double-precision problem.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_problem_reference_f64(
    problem: Option<&omnee_problem_f64>,
    phase: Option<&omnee_phase_f64>,
    reference: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    reference_of::<f64>(problem, phase, reference, error)
}

fn reference_of<F: Precision>(
    problem: Option<&F::Problem>,
    phase: Option<&omnee_phase_f64>,
    out: Option<&mut MaybeUninit<f64>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let (problem, phase) = (object(problem)?, object(phase)?);
        finite(problem.try_integral(phase)?, "reference").map(Some)
    })();
    finish(out, "reference", error, result)
}
