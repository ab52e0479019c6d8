//! Phase functions chosen by the core's specification strings (`iso`, `hg:G`,
//! `tthg:G1,G2,W`, `ff:B,N`, `draine:G,ALPHA`, `mie:D`, `rayleigh`).
//!
//! The syntax, the field names and the error messages are those of
//! [`omnee_core::phase::Spec::parse`] (a native test checks that both agree
//! on valid and invalid strings). The demo parses them itself for the size of
//! the module: the core reads its numbers with `f64::from_str`, whose tables
//! and big-number fallback are some 18 KiB of wasm; here the syntax is checked
//! in Rust and the correctly rounded conversion is JavaScript's `Number` (in
//! the browser) or `f64::from_str` (natively), the same value either way. A
//! string is parsed once and built in either precision, as an [`Analytic`]
//! phase function.

use omnee_core::Error;
use omnee_core::lobe::Restricted;
use omnee_core::phase::{
    Deflection, Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, Phase,
    PhaseFunction, Rayleigh, TwoTermHg,
};
use omnee_core::real::Real;

/// The names accepted, for the error message (the core's wording).
const NAMES: &str =
    "unknown phase function; expected iso, hg, tthg, ff, draine, mie, rayleigh or table";

/// Which phase function a [`Spec`] names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Isotropic,
    HenyeyGreenstein,
    TwoTermHg,
    FournierForand,
    Draine,
    Mie,
    Rayleigh,
}

/// Name, kind, parameter names and the usage message of a wrong count.
type Syntax = (&'static str, Kind, &'static [&'static str], &'static str);

/// Every analytic phase function of the core's spec syntax.
const SYNTAX: [Syntax; 7] = [
    ("iso", Kind::Isotropic, &[], ""),
    ("hg", Kind::HenyeyGreenstein, &["g"], "expected hg:G"),
    (
        "tthg",
        Kind::TwoTermHg,
        &["g1", "g2", "w"],
        "expected tthg:G1,G2,W",
    ),
    (
        "ff",
        Kind::FournierForand,
        &["backscatter", "n"],
        "expected ff:B,N",
    ),
    (
        "draine",
        Kind::Draine,
        &["g", "alpha"],
        "expected draine:G,ALPHA",
    ),
    (
        "mie",
        Kind::Mie,
        &["diameter_um"],
        "expected mie:DIAMETER_UM",
    ),
    ("rayleigh", Kind::Rayleigh, &[], ""),
];

/// A parsed specification: the phase function and its parameters (f64, as
/// written), not yet checked against their ranges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spec {
    kind: Kind,
    params: [f64; 3],
}

fn syntax(field: &'static str, reason: &'static str) -> Error {
    Error::Syntax { field, reason }
}

impl Spec {
    /// Parses the core's syntax (names lower case, parameters comma-separated
    /// decimal numbers, surrounding whitespace ignored). `table:FILE.csv` is
    /// refused: the page reads no files.
    pub fn parse(spec: &str) -> Result<Self, Error> {
        let spec = spec.trim();
        let (name, args) = match split_once(spec, b':') {
            Some((n, a)) => (n.trim(), Some(a)),
            None => (spec, None),
        };
        if name == "table" {
            return Err(if args.map(str::trim).unwrap_or("").is_empty() {
                syntax("table", "expected table:FILE.csv")
            } else {
                syntax("table", "tables cannot be loaded in the browser demo")
            });
        }
        let &(name, kind, fields, usage) = SYNTAX
            .iter()
            .find(|s| s.0 == name)
            .ok_or(syntax("phase", NAMES))?;
        let params = match args {
            None if fields.is_empty() => [0.0; 3],
            Some(_) if fields.is_empty() => return Err(syntax(name, "takes no parameters")),
            None => return Err(syntax(name, usage)),
            Some(args) => numbers(args, fields, syntax(name, usage))?,
        };
        Ok(Self { kind, params })
    }

    /// The phase function in precision `F` (parameters rounded to `F` and
    /// checked by the core's constructors, as `Spec::<F>::parse` does).
    pub fn build<F: Real>(&self) -> Result<Analytic<F>, Error> {
        let [a, b, c] = self.params.map(F::from_f64);
        Ok(match self.kind {
            Kind::Isotropic => Analytic::Isotropic(Isotropic),
            Kind::HenyeyGreenstein => Analytic::HenyeyGreenstein(HenyeyGreenstein::new(a)?),
            Kind::TwoTermHg => Analytic::TwoTermHg(Mixture::two_term(a, b, c)?),
            Kind::FournierForand => Analytic::FournierForand(FournierForand::new(a, b)?),
            Kind::Draine => Analytic::Draine(Draine::new(a, b)?),
            Kind::Mie => Analytic::Mie(Mie::new(a)?),
            Kind::Rayleigh => Analytic::Rayleigh(Rayleigh),
        })
    }
}

/// The analytic phase functions of the core's [`Phase`], i.e. all but its
/// caller-owned table, which the page cannot load. The demo dispatches on
/// this enum rather than on `Phase` so that the table's sampler, CDF and
/// lookup are not in the module (2.1 KiB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Analytic<F> {
    /// `p = 1/(4π)`.
    Isotropic(Isotropic),
    /// Henyey–Greenstein.
    HenyeyGreenstein(HenyeyGreenstein<F>),
    /// Two-term Henyey–Greenstein.
    TwoTermHg(TwoTermHg<F>),
    /// Fournier–Forand.
    FournierForand(FournierForand<F>),
    /// Draine.
    Draine(Draine<F>),
    /// The approximate Mie fit by droplet diameter.
    Mie(Mie<F>),
    /// Rayleigh.
    Rayleigh(Rayleigh),
}

impl<F> From<Analytic<F>> for Phase<'static, F> {
    /// The same phase function as the core's enum.
    fn from(p: Analytic<F>) -> Self {
        match p {
            Analytic::Isotropic(p) => Phase::Isotropic(p),
            Analytic::HenyeyGreenstein(p) => Phase::HenyeyGreenstein(p),
            Analytic::TwoTermHg(p) => Phase::TwoTermHg(p),
            Analytic::FournierForand(p) => Phase::FournierForand(p),
            Analytic::Draine(p) => Phase::Draine(p),
            Analytic::Mie(p) => Phase::Mie(p),
            Analytic::Rayleigh(p) => Phase::Rayleigh(p),
        }
    }
}

/// Calls `$call` on whichever phase function `$self` holds.
macro_rules! dispatch {
    ($self:expr, $p:ident => $call:expr) => {
        match $self {
            Analytic::Isotropic($p) => $call,
            Analytic::HenyeyGreenstein($p) => $call,
            Analytic::TwoTermHg($p) => $call,
            Analytic::FournierForand($p) => $call,
            Analytic::Draine($p) => $call,
            Analytic::Mie($p) => $call,
            Analytic::Rayleigh($p) => $call,
        }
    };
}

/// Every method is the variant's own, as for the core's [`Phase`].
impl<F: Real> PhaseFunction<F> for Analytic<F> {
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.eval(d))
    }
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        dispatch!(self, p => p.sample(u))
    }
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.cdf(d))
    }
    #[inline]
    fn mean_cosine(&self) -> F {
        dispatch!(self, p => PhaseFunction::<F>::mean_cosine(p))
    }
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.pdf(d))
    }
    #[inline]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        dispatch!(self, p => p.sample_pdf(u))
    }
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        dispatch!(self, p => p.invert(d))
    }
    #[inline]
    fn backscatter_fraction(&self) -> F {
        dispatch!(self, p => PhaseFunction::<F>::backscatter_fraction(p))
    }
}

/// Restricted to an interval of deflections as the variant is (the lobe
/// technique's deflection at `x1`).
impl<F: Real> Restricted<F> for Analytic<F> {
    #[inline]
    fn mass_between(&self, lo: Deflection<F>, hi: Deflection<F>) -> F {
        dispatch!(self, p => p.mass_between(lo, hi))
    }
    #[inline]
    fn sample_between(
        &self,
        lo: Deflection<F>,
        hi: Deflection<F>,
        u: F,
    ) -> Option<(Deflection<F>, F)> {
        dispatch!(self, p => p.sample_between(lo, hi, u))
    }
    #[inline]
    fn invert_between(&self, lo: Deflection<F>, hi: Deflection<F>, d: Deflection<F>) -> Option<F> {
        dispatch!(self, p => p.invert_between(lo, hi, d))
    }
}

/// Exactly `fields.len()` comma-separated numbers of `args`; `usage` for a
/// wrong count.
fn numbers(args: &str, fields: &[&'static str], usage: Error) -> Result<[f64; 3], Error> {
    let mut out = [0.0; 3];
    let mut rest = Some(args);
    for (slot, &field) in out.iter_mut().zip(fields) {
        let s = rest.ok_or(usage)?;
        let (part, tail) = match split_once(s, b',') {
            Some((part, tail)) => (part, Some(tail)),
            None => (s, None),
        };
        rest = tail;
        *slot = number(part.trim()).ok_or(syntax(field, "not a number"))?;
    }
    match rest {
        Some(_) => Err(usage),
        None => Ok(out),
    }
}

/// `s` split at the first `separator`, an ASCII byte (so both sides are
/// valid UTF-8): `str::split_once` with a `char`.
fn split_once(s: &str, separator: u8) -> Option<(&str, &str)> {
    let i = s.bytes().position(|b| b == separator)?;
    Some((s.get(..i)?, s.get(i + 1..)?))
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
