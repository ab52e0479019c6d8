//! Checks that turn the C arguments into the core's values, each failure
//! naming the argument.

use crate::status::Failure;
use crate::types::{
    OMNEE_DIRECTIONS_COSINE, OMNEE_DIRECTIONS_SPHERE, OMNEE_REGION_EVERYWHERE, OMNEE_REGION_SLAB,
    Object, omnee_rays, omnee_vec3,
};
use omnee_core::Error;
use omnee_core::medium::Region;
use omnee_core::real::Real;
use omnee_core::sampling::Directions;

/// The value of an opaque object: `OMNEE_ERROR_NULL` for NULL,
/// `OMNEE_ERROR_UNINITIALISED` without its constructor's tag.
#[inline]
pub(crate) fn object<O: Object>(o: Option<&O>) -> Result<&O::Value, Failure> {
    o.ok_or(Failure::Null(O::NAME))?
        .value()
        .ok_or(Failure::Uninitialised(O::NAME))
}

/// A required plain-old-data input.
#[inline]
pub(crate) fn required<T: Copy>(p: Option<&T>, field: &'static str) -> Result<T, Failure> {
    p.copied().ok_or(Failure::Null(field))
}

/// `N` uniform numbers, present and finite (the core clamps finite numbers
/// into [0, 1]).
#[inline]
pub(crate) fn uniforms<F: Real, const N: usize>(u: Option<[F; N]>) -> Result<[F; N], Failure> {
    let u = u.ok_or(Failure::Null("u"))?;
    if u.iter().all(|x| x.is_finite()) {
        Ok(u)
    } else {
        Err(Error::not_finite("u").into())
    }
}

/// A finite point.
#[inline]
pub(crate) fn point<F: Real>(p: omnee_vec3<F>, field: &'static str) -> Result<F::Vec3, Failure> {
    if p.is_finite() {
        Ok(p.get())
    } else {
        Err(Error::not_finite(field).into())
    }
}

/// An output that must be finite: one beyond the precision's range (a
/// transfer that grows as 1/s² for a short connection) is
/// `OMNEE_ERROR_NOT_FINITE` naming it, and no NaN ever crosses the
/// boundary (the core gives none).
#[inline]
pub(crate) fn finite<F: Real>(x: F, field: &'static str) -> Result<F, Failure> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::NotFinite {
            field,
            reason: "is beyond the precision's range",
        }
        .into())
    }
}

/// The core's ray directions and medium region.
pub(crate) fn rays<F: Real>(
    rays: Option<&omnee_rays<F>>,
) -> Result<(Directions<F>, Region<F>), Failure> {
    let rays = required(rays, "rays")?;
    let directions = match rays.directions {
        OMNEE_DIRECTIONS_SPHERE => Directions::Sphere,
        OMNEE_DIRECTIONS_COSINE => Directions::cosine(rays.normal.get())?,
        other => {
            return Err(Error::OutOfRange {
                field: "directions",
                value: other as f64,
                allowed: "0 (sphere) or 1 (cosine)",
            }
            .into());
        }
    };
    let region = match rays.region {
        OMNEE_REGION_EVERYWHERE => Region::Everywhere,
        OMNEE_REGION_SLAB => Region::slab(rays.z_min, rays.z_max)?,
        other => {
            return Err(Error::OutOfRange {
                field: "region",
                value: other as f64,
                allowed: "0 (everywhere) or 1 (slab)",
            }
            .into());
        }
    };
    Ok((directions, region))
}
