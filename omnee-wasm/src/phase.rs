//! Phase functions chosen by the core's specification strings (`iso`, `hg:G`,
//! `tthg:G1,G2,W`, `ff:B,N`, `draine:G,ALPHA`, `mie:D`, `rayleigh`).
//!
//! The grammar and the dispatch are the core's: [`ParsedSpec::parse_with`]
//! reads the string, and the demo's phase functions are the core's
//! [`AnyPhase`] without its table variant ([`NoTable`]: the page reads no
//! files, and the table's code stays out of the module). Only the numbers
//! are read here, for the size of the module: the core's default reads them
//! with `f64::from_str`, whose tables and big-number fallback are some
//! 18 KiB of wasm; here the syntax is checked in Rust and the correctly
//! rounded conversion is JavaScript's `Number` (in the browser) or
//! `f64::from_str` (natively), the same value either way.

use omnee_core::Error;
use omnee_core::phase::{AnyPhase, NoTable, ParsedSpec};
use omnee_core::real::Real;

/// The demo's phase functions: the core's, without tables.
pub type DemoPhase<F> = AnyPhase<F, NoTable>;

/// The phase function `spec` names, in precision `F`: the core's grammar,
/// numbers read by [`number`]; a table is refused (the page reads no
/// files).
#[inline]
pub fn build<F: Real>(spec: &str) -> Result<DemoPhase<F>, Error> {
    match ParsedSpec::parse_with(spec, number)? {
        ParsedSpec::Table { .. } => Err(Error::Syntax {
            field: "table",
            reason: "tables cannot be loaded in the browser demo",
        }),
        parsed => parsed.build(),
    }
}

/// `s` as an f64 if it has the syntax of Rust's `f64::from_str`: an optional
/// sign, then `inf`, `infinity` or `nan` in any case, or decimal digits with
/// an optional point and an optional exponent (`1`, `-0.44`, `.5`, `2.`,
/// `1e-3`), correctly rounded.
pub fn number(s: &str) -> Option<f64> {
    let (negative, unsigned) = match s.as_bytes().first() {
        Some(b'-') => (true, s.get(1..)?),
        Some(b'+') => (false, s.get(1..)?),
        _ => (false, s),
    };
    let special =
        if unsigned.eq_ignore_ascii_case("inf") || unsigned.eq_ignore_ascii_case("infinity") {
            Some(f64::INFINITY)
        } else if unsigned.eq_ignore_ascii_case("nan") {
            Some(f64::NAN)
        } else {
            None
        };
    match special {
        Some(x) if negative => Some(-x),
        Some(x) => Some(x),
        None => is_decimal(unsigned).then(|| decimal(s)),
    }
}

/// Whether `s` is `digits [. digits] [(e|E) [+|-] digits]` with at least one
/// digit before the exponent.
fn is_decimal(s: &str) -> bool {
    let mut rest = s.as_bytes();
    let mut mantissa = skip_digits(&mut rest);
    if let [b'.', tail @ ..] = rest {
        rest = tail;
        mantissa += skip_digits(&mut rest);
    }
    if mantissa == 0 {
        return false;
    }
    if let [b'e' | b'E', tail @ ..] = rest {
        rest = tail;
        if let [b'+' | b'-', tail @ ..] = rest {
            rest = tail;
        }
        if skip_digits(&mut rest) == 0 {
            return false;
        }
    }
    rest.is_empty()
}

/// Advances `s` past its leading ASCII digits and returns how many there were.
fn skip_digits(s: &mut &[u8]) -> usize {
    let n = s.iter().take_while(|c| c.is_ascii_digit()).count();
    *s = s.get(n..).unwrap_or_default();
    n
}

/// The correctly rounded value of a string that [`is_decimal`] accepted
/// (with its sign).
#[cfg(target_arch = "wasm32")]
fn decimal(s: &str) -> f64 {
    js_number(s)
}

/// The correctly rounded value of a string that [`is_decimal`] accepted
/// (with its sign).
#[cfg(not(target_arch = "wasm32"))]
fn decimal(s: &str) -> f64 {
    s.parse().unwrap_or(f64::NAN)
}

#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen]
extern "C" {
    /// JavaScript's `Number(s)`, correctly rounded for decimal strings.
    #[wasm_bindgen(js_name = Number)]
    fn js_number(s: &str) -> f64;
}
