//! The errors of the core and of the library's validation as Python exceptions:
//! bad input is a `ValueError` whose message names the field, its value and
//! the allowed range (the Rust error's text, unchanged); a quadrature
//! reference that spent its evaluation budget is `omnee.NotConvergedError`.

use omnee_render::RenderError;
use pyo3::PyErr;
use pyo3::exceptions::{PyOSError, PyValueError};

pyo3::create_exception!(
    omnee,
    NotConvergedError,
    pyo3::exceptions::PyRuntimeError,
    "A quadrature reference spent its evaluation budget before meeting its \
     tolerance (the core's `Error::NotConverged`): no value is returned. A \
     `RuntimeError`: the input was valid, the reference could not be computed \
     within its bounded cost."
);

/// A core constructor's refusal: `ValueError("g = 1.5 is out of range; allowed: (-1, 1)")`;
/// a spent quadrature budget: `NotConvergedError("reference: the quadrature
/// did not converge within its budget of N evaluations")`.
pub fn core(e: omnee_core::Error) -> PyErr {
    match e {
        omnee_core::Error::NotConverged { .. } => NotConvergedError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// The library's validation: bad input is a `ValueError`, a reference that
/// spent its budget `NotConvergedError`, a file that cannot be read (a
/// `table:` phase function) an `OSError`, a cancelled computation
/// `KeyboardInterrupt`.
pub fn render(e: RenderError) -> PyErr {
    match e {
        RenderError::Input(m) => PyValueError::new_err(m),
        RenderError::Io(m) => PyOSError::new_err(m),
        RenderError::NotConverged(m) => NotConvergedError::new_err(m),
        RenderError::Cancelled => pyo3::exceptions::PyKeyboardInterrupt::new_err("cancelled"),
    }
}
