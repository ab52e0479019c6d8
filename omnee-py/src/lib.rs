//! omnee-py: the Python module `omnee` (its native part, `omnee._omnee`).
//!
//! numpy arrays in, numpy arrays out, in the idiom of Mitsuba 3's warp
//! functions (`square_to_X`, `square_to_X_pdf`, `X_to_square` over arrays):
//!
//! - `Phase` (module `phase`): a phase function from its spec string, with `eval`,
//!   `sample`, `pdf`, `cdf`, `invert` over arrays and `mean_cosine`;
//! - `Technique` (module `technique`) and its subclasses `Omnee`, `Equiangular`,
//!   `Distance`, `Mis`: `sample(u)`, `pdf(x1)`, `invert(x1)` over arrays of
//!   uniform tuples or points;
//! - `EquiangularSegment` (module `segment`): the equiangular distance along
//!   rays the caller traced, `sample(u)`, `pdf(t)`, `invert(t)`;
//! - `estimate` (module `estimate`): the point-to-point integral of `omnee estimate`,
//!   the same numbers for the same seed; with `vertices=K` (or `"auto"`) the
//!   transfer of K scattering vertices by bridges;
//! - `Bridge` (module `bridge`): bridges of k vertices, `sample(u)` and
//!   `pdf(vertices)` over arrays, and `isotropic_transfer`, the exact `I_k`
//!   for isotropic scattering;
//! - `NotConvergedError` (module `error`): a reference that spent its budget.
//!
//! A float32 array is computed in f32 and answered in float32, anything
//! else accepted in f64 (module `array`). The GIL is released while the core
//! samples; bad input raises `ValueError` or `TypeError` naming the argument
//! and what is allowed (module `error`). The binding holds no `unsafe` code: the
//! foreign boundary is PyO3's and rust-numpy's.

mod array;
mod batch;
mod bridge;
mod chunks;
mod config;
mod error;
mod estimate;
mod kernel;
mod phase;
mod segment;
mod technique;

use pyo3::prelude::*;

/// The native module; `omnee/__init__.py` re-exports it with the result
/// types (`Samples`, `Inversion`, `Estimate`).
#[pymodule]
fn _omnee(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<phase::Phase>()?;
    m.add_class::<technique::Technique>()?;
    m.add_class::<technique::Omnee>()?;
    m.add_class::<technique::Equiangular>()?;
    m.add_class::<technique::Distance>()?;
    m.add_class::<technique::Mis>()?;
    m.add_class::<segment::EquiangularSegment>()?;
    m.add_class::<bridge::Bridge>()?;
    m.add_class::<bridge::VertexCount>()?;
    m.add_function(wrap_pyfunction!(estimate::estimate, m)?)?;
    m.add_function(wrap_pyfunction!(bridge::isotropic_transfer_py, m)?)?;
    m.add(
        "NotConvergedError",
        m.py().get_type::<error::NotConvergedError>(),
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
