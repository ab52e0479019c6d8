//! The CLI's error: bad input (exit code 2) or a failure to write (exit code 1).

use std::fmt;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// A bad scene file, option or value: the message names the field, its
    /// value and the allowed range. Exit code 2.
    Input(String),
    /// Reading or writing a file failed. Exit code 1.
    Io(String),
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Input(_) => 2,
            CliError::Io(_) => 1,
        }
    }

    /// An input error naming `field`, its `value` and the `allowed` range.
    pub fn range(field: &str, value: impl fmt::Display, allowed: impl fmt::Display) -> Self {
        CliError::Input(format!(
            "{field} = {value} is out of range; allowed: {allowed}"
        ))
    }

    /// Prefixes the message with `context` (e.g. the scene file's name).
    pub fn context(self, context: &str) -> Self {
        match self {
            CliError::Input(m) => CliError::Input(format!("{context}: {m}")),
            CliError::Io(m) => CliError::Io(format!("{context}: {m}")),
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Io(m) => f.write_str(m),
        }
    }
}

/// A core constructor's error, prefixed with where its parameter came from
/// (e.g. `medium.phase` for the spec string of the scene's medium).
pub fn core_error(prefix: &str, e: omnee_core::Error) -> CliError {
    CliError::Input(format!("{prefix}: {e}"))
}

/// The result type of the CLI.
pub type Result<T> = std::result::Result<T, CliError>;
