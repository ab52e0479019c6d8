//! `omnee_connection_*`: the end points and θmax every technique shares.

use crate::args::point;
use crate::status::{ErrorOut, Failure, finish, omnee_error, omnee_status};
use crate::types::{Object, Precision, omnee_connection_f32, omnee_connection_f64, omnee_vec3};
use core::mem::MaybeUninit;
use omnee_core::sampling::Connection;

/// Makes the connection from `x0` (light side) to `x2` (receiver side),
/// restricted to deflections θ < `theta_max` ∈ (0, π] (π/2: forward
/// scattering only, the ball with diameter x0x2; the smallest subnormal is
/// allowed). Any finite, distinct end points are accepted whose distance is
/// at most the precision's largest number (see SCALE above): s and the axis
/// are computed in a power-of-two unit, so neither s² nor 1/s overflows.
///
/// Errors: `OMNEE_ERROR_NOT_FINITE` (x0, x2, or a distance above the
/// largest number: "x2 - x0"), `OMNEE_ERROR_DEGENERATE` (x0 == x2),
/// `OMNEE_ERROR_OUT_OF_RANGE` (theta_max), `OMNEE_ERROR_NULL` (connection).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_connection_init_f32(
    connection: Option<&mut MaybeUninit<omnee_connection_f32>>,
    x0: omnee_vec3<f32>,
    x2: omnee_vec3<f32>,
    theta_max: f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    init(connection, x0, x2, theta_max, error)
}

/// `omnee_connection_init_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_connection_init_f64(
    connection: Option<&mut MaybeUninit<omnee_connection_f64>>,
    x0: omnee_vec3<f64>,
    x2: omnee_vec3<f64>,
    theta_max: f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    init(connection, x0, x2, theta_max, error)
}

fn init<F: Precision>(
    out: Option<&mut MaybeUninit<F::Connection>>,
    x0: omnee_vec3<F>,
    x2: omnee_vec3<F>,
    theta_max: F,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        // Non-finite points are the core's NotFinite; `point` names them the same.
        let (x0, x2) = (point(x0, "x0")?, point(x2, "x2")?);
        let connection = Connection::new(x0, x2, theta_max)?;
        Ok::<_, Failure>(Some(F::Connection::new(connection)))
    })();
    finish(out, "connection", error, result)
}
