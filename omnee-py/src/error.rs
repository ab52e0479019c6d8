//! The errors of the core and of the CLI's validation as Python exceptions:
//! bad input is a `ValueError` whose message names the field, its value and
//! the allowed range (the Rust error's text, unchanged).

use omnee_cli::error::CliError;
use pyo3::PyErr;
use pyo3::exceptions::{PyOSError, PyValueError};

/// A core constructor's refusal: `ValueError("g = 1.5 is out of range; allowed: (-1, 1)")`.
pub fn core(e: omnee_core::Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The CLI's validation: bad input is a `ValueError`, a file that cannot be
/// read (a `table:` phase function) an `OSError`.
pub fn cli(e: CliError) -> PyErr {
    match e {
        CliError::Input(m) => PyValueError::new_err(m),
        CliError::Io(m) => PyOSError::new_err(m),
    }
}
