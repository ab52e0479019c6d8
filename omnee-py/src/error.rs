//! The errors of the core and of the library's validation as Python exceptions:
//! bad input is a `ValueError` whose message names the field, its value and
//! the allowed range (the Rust error's text, unchanged).

use omnee_render::RenderError;
use pyo3::PyErr;
use pyo3::exceptions::{PyOSError, PyValueError};

/// A core constructor's refusal: `ValueError("g = 1.5 is out of range; allowed: (-1, 1)")`.
pub fn core(e: omnee_core::Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The library's validation: bad input is a `ValueError`, a file that
/// cannot be read (a `table:` phase function) an `OSError`, a cancelled
/// computation `KeyboardInterrupt`.
pub fn render(e: RenderError) -> PyErr {
    match e {
        RenderError::Input(m) => PyValueError::new_err(m),
        RenderError::Io(m) => PyOSError::new_err(m),
        RenderError::Cancelled => pyo3::exceptions::PyKeyboardInterrupt::new_err("cancelled"),
    }
}
