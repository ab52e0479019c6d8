//! The library's error: bad input, a reference that spent its evaluation
//! budget, or a file that could not be read or written. Every input message
//! names the field, its value and the allowed range; front ends print it
//! (the command line exits with 2 for input and a spent budget, 1 for
//! files; Python raises `ValueError`, `omnee.NotConvergedError` or
//! `OSError`).

use std::fmt;

/// Why a command failed.
#[derive(Debug)]
pub enum RenderError {
    /// A bad scene file, option or value: the message names the field, its
    /// value and the allowed range.
    Input(String),
    /// Writing a file failed (reading a scene or a table that is not there
    /// is [`RenderError::Input`]: the name given is wrong).
    Io(String),
    /// A quadrature reference spent its evaluation budget (the core's
    /// `Error::NotConverged`): the input was valid, the reference could not
    /// be computed within its bounded cost. The message names `reference`
    /// and what to do about it.
    NotConverged(String),
    /// The caller cancelled the work (a render, an estimate) before it was
    /// done.
    Cancelled,
}

impl RenderError {
    /// An input error naming `field`, its `value` and the `allowed` range.
    pub fn range(field: &str, value: impl fmt::Display, allowed: impl fmt::Display) -> Self {
        RenderError::Input(format!(
            "{field} = {value} is out of range; allowed: {allowed}"
        ))
    }

    /// Prefixes the message with `context` (e.g. the scene file's name).
    pub fn context(self, context: &str) -> Self {
        match self {
            RenderError::Input(m) => RenderError::Input(format!("{context}: {m}")),
            RenderError::Io(m) => RenderError::Io(format!("{context}: {m}")),
            RenderError::NotConverged(m) => RenderError::NotConverged(format!("{context}: {m}")),
            RenderError::Cancelled => RenderError::Cancelled,
        }
    }
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Input(m) | RenderError::Io(m) | RenderError::NotConverged(m) => {
                f.write_str(m)
            }
            RenderError::Cancelled => f.write_str("cancelled"),
        }
    }
}

/// How messages spell the fields of a request: as the command line's
/// options (`--sigma-s`), or as the fields of the library's structs
/// (`sigma_s`), which the Python bindings also use for their keyword
/// arguments.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Spelling {
    /// `--sigma-s`, `--receiver-normal`: the command line's.
    #[default]
    Options,
    /// `sigma_s`, `receiver_normal`: the fields' own.
    Fields,
}

impl Spelling {
    /// `field` (a struct field or an engine's argument, in snake case) as
    /// messages spell it.
    pub fn of(self, field: &str) -> String {
        match self {
            Spelling::Options => format!("--{}", field.replace('_', "-")),
            Spelling::Fields => field.to_string(),
        }
    }

    /// Several fields spelled by [`Spelling::of`], joined by `/` (the fields
    /// a core constructor's parameters came from).
    pub fn list(self, fields: &[&str]) -> String {
        let names: Vec<String> = fields.iter().map(|f| self.of(f)).collect();
        names.join("/")
    }
}

/// A core constructor's error, prefixed with where its parameter came from
/// (e.g. `medium.phase` for the spec string of the scene's medium).
pub fn core_error(prefix: &str, e: omnee_core::Error) -> RenderError {
    RenderError::Input(format!("{prefix}: {e}"))
}

impl std::error::Error for RenderError {}

/// The result type of the library.
pub type Result<T> = std::result::Result<T, RenderError>;

/// The reference's core error (a spent budget) as
/// [`RenderError::NotConverged`], named by `reference`, with what to do
/// about it.
pub(crate) fn not_converged(spelling: Spelling, e: omnee_core::Error) -> RenderError {
    let reference = spelling.of("reference");
    // The core's message names its field ("reference: the quadrature ...");
    // the field is named here as the front end spells it, once.
    let what = e.to_string();
    let what = what
        .strip_prefix(&format!("{}: ", e.field()))
        .unwrap_or(&what);
    RenderError::NotConverged(format!(
        "{reference}: {what}; allowed: a problem whose reference converges (leave out \
         {reference} to estimate without it)"
    ))
}
