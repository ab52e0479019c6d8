//! Phase functions from short specification strings (command line, config).
//!
//! The syntax is documented on [`Spec`] (this module is private).

use super::{
    AnyPhase, Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, Phase, Rayleigh,
};
#[allow(unused_imports)] // named by the documentation of `Spec`
use super::{Tabulated, TwoTermHg};
use crate::error::Error;
use crate::names::Named;
use crate::real::Real;
use core::fmt;

/// A parsed phase-function specification string.
///
/// Syntax (names lower case, parameters comma-separated decimal numbers,
/// surrounding ASCII whitespace ignored):
///
/// | spec | phase function | parameters (allowed) |
/// |---|---|---|
/// | `iso` | [`Isotropic`] | — |
/// | `hg:G` | [`HenyeyGreenstein`] | `g ∈ (−1, 1)` |
/// | `tthg:G1,G2,W` | [`TwoTermHg`]: `W·HG(G1) + (1 − W)·HG(G2)` | `g1, g2 ∈ (−1, 1)`, `w ∈ [0, 1]` |
/// | `ff:B,N` | [`FournierForand`] | `backscatter ∈ (0, 0.5)`, `n ∈ [1.001, 1.5]` |
/// | `draine:G,ALPHA` | [`Draine`] | `g ∈ (−1, 1)`, `alpha ∈ [0, 1000]` |
/// | `mie:DIAMETER_UM` | [`Mie`] | `diameter_um ∈ (0, 50]` |
/// | `rayleigh` | [`Rayleigh`] | — |
/// | `table:FILE.csv` | [`Tabulated`], loaded by the caller | a path (may contain `:`) |
///
/// Example: `tthg:0.99,-0.44,0.96`. The core does no I/O, so `table:` yields
/// [`Spec::Table`] with the path and the caller builds the [`Tabulated`].
/// Errors are [`Error::Syntax`] (unknown name, wrong parameter count, not a
/// number; `field` is the name or the parameter) or the constructors'
/// [`Error::OutOfRange`] naming the parameter and its range. Parsing does not
/// allocate. [`Display`](core::fmt::Display) writes the same syntax back
/// (shortest round-trip decimals), so `parse(spec.to_string())` gives `spec`.
/// The grammar itself is [`ParsedSpec`]'s; this is its result built in
/// precision `F`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spec<'s, F: 'static> {
    /// A phase function with all its parameters.
    Analytic(Phase<'static, F>),
    /// `table:PATH`: the caller reads the file and builds a [`Tabulated`].
    Table {
        /// The path as written after `table:`.
        path: &'s str,
    },
}

/// The phase functions a spec string names: the first part of the syntax
/// of [`Spec`], with its parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhaseKind {
    /// `iso`: [`Isotropic`].
    Isotropic,
    /// `hg:G`: [`HenyeyGreenstein`].
    HenyeyGreenstein,
    /// `tthg:G1,G2,W`: [`TwoTermHg`].
    TwoTermHg,
    /// `ff:B,N`: [`FournierForand`].
    FournierForand,
    /// `draine:G,ALPHA`: [`Draine`].
    Draine,
    /// `mie:DIAMETER_UM`: [`Mie`].
    Mie,
    /// `rayleigh`: [`Rayleigh`].
    Rayleigh,
    /// `table:FILE.csv`: a measured [`Tabulated`] table.
    Table,
}

impl Named for PhaseKind {
    const ALL: &'static [Self] = &[
        PhaseKind::Isotropic,
        PhaseKind::HenyeyGreenstein,
        PhaseKind::TwoTermHg,
        PhaseKind::FournierForand,
        PhaseKind::Draine,
        PhaseKind::Mie,
        PhaseKind::Rayleigh,
        PhaseKind::Table,
    ];

    fn name(self) -> &'static str {
        match self {
            PhaseKind::Isotropic => "iso",
            PhaseKind::HenyeyGreenstein => "hg",
            PhaseKind::TwoTermHg => "tthg",
            PhaseKind::FournierForand => "ff",
            PhaseKind::Draine => "draine",
            PhaseKind::Mie => "mie",
            PhaseKind::Rayleigh => "rayleigh",
            PhaseKind::Table => "table",
        }
    }

    fn help(self) -> &'static str {
        match self {
            PhaseKind::Isotropic => "isotropic, p = 1/(4 pi)",
            PhaseKind::HenyeyGreenstein => "Henyey-Greenstein, G in (-1, 1) (G > 0: forward)",
            PhaseKind::TwoTermHg => {
                "two-term HG, W*HG(G1) + (1-W)*HG(G2); G1, G2 in (-1, 1), W in [0, 1]"
            }
            PhaseKind::FournierForand => {
                "Fournier-Forand, backscatter fraction B in (0, 0.5), refractive index N in [1.001, 1.5]"
            }
            PhaseKind::Draine => "Draine, G in (-1, 1), ALPHA in [0, 1000]",
            PhaseKind::Mie => {
                "approximate Mie (Jendersie & d'Eon 2023), droplet diameter in (0, 50] micrometres"
            }
            PhaseKind::Rayleigh => "Rayleigh, p = 3/(16 pi) (1 + cos^2)",
            PhaseKind::Table => "measured: lines 'angle_deg,value', angles increasing in [0, 180]",
        }
    }
}

crate::display_by_name!(PhaseKind);

impl PhaseKind {
    /// The parameters' names (the fields of their errors) and the usage
    /// message of a wrong count.
    fn parameters(self) -> (&'static [&'static str], &'static str) {
        match self {
            PhaseKind::Isotropic | PhaseKind::Rayleigh => (&[], "takes no parameters"),
            PhaseKind::HenyeyGreenstein => (&["g"], "expected hg:G"),
            PhaseKind::TwoTermHg => (&["g1", "g2", "w"], "expected tthg:G1,G2,W"),
            PhaseKind::FournierForand => (&["backscatter", "n"], "expected ff:B,N"),
            PhaseKind::Draine => (&["g", "alpha"], "expected draine:G,ALPHA"),
            PhaseKind::Mie => (&["diameter_um"], "expected mie:DIAMETER_UM"),
            PhaseKind::Table => (&[], "expected table:FILE.csv"),
        }
    }

    /// The usage line of the syntax: `hg:G`, `table:FILE.csv`, `iso`.
    pub fn usage(self) -> &'static str {
        match self.parameters().1.strip_prefix("expected ") {
            Some(usage) => usage,
            None => self.name(),
        }
    }
}

/// The names accepted, for the error message.
const NAMES: &str =
    "unknown phase function; expected iso, hg, tthg, ff, draine, mie, rayleigh or table";

/// A spec string split into the phase function's kind and its parameters,
/// not yet checked against their ranges nor built in a precision: the
/// grammar of [`Spec`], in one place. The numbers are read by a function
/// the caller passes ([`ParsedSpec::parse`] uses `f64::from_str`; the
/// browser demo passes JavaScript's `Number` for the size of its module).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParsedSpec<'s> {
    /// An analytic phase function and its parameters as written (unused
    /// ones 0).
    Analytic {
        /// Which phase function.
        kind: PhaseKind,
        /// Its parameters in the order of the syntax.
        params: [f64; 3],
    },
    /// `table:PATH`.
    Table {
        /// The path as written after `table:`, trimmed.
        path: &'s str,
    },
}

/// `s` split at the first `separator`, an ASCII byte (both sides stay
/// valid UTF-8).
fn split_once(s: &str, separator: u8) -> Option<(&str, &str)> {
    let i = s.bytes().position(|b| b == separator)?;
    Some((s.get(..i)?, s.get(i + 1..)?))
}

impl<'s> ParsedSpec<'s> {
    /// Parses the syntax of [`Spec`], numbers by `f64::from_str`.
    pub fn parse(spec: &'s str) -> Result<Self, Error> {
        Self::parse_with(spec, |s| s.parse().ok())
    }

    /// Parses the syntax of [`Spec`], reading each (trimmed) number with
    /// `number` (`None`: not a number).
    pub fn parse_with(spec: &'s str, number: impl Fn(&str) -> Option<f64>) -> Result<Self, Error> {
        let syntax = |field, reason| Error::Syntax { field, reason };
        let spec = spec.trim_ascii();
        let (name, args) = match split_once(spec, b':') {
            Some((n, a)) => (n.trim_ascii(), Some(a)),
            None => (spec, None),
        };
        let kind = PhaseKind::from_name(name).ok_or(syntax("phase", NAMES))?;
        let (fields, usage) = kind.parameters();
        let name = kind.name();
        if kind == PhaseKind::Table {
            return match args.map(str::trim_ascii) {
                Some(path) if !path.is_empty() => Ok(ParsedSpec::Table { path }),
                _ => Err(syntax(name, usage)),
            };
        }
        let mut params = [0.0; 3];
        match args {
            None if fields.is_empty() => {}
            Some(_) if fields.is_empty() => return Err(syntax(name, usage)),
            None => return Err(syntax(name, usage)),
            Some(args) => {
                let mut rest = Some(args);
                for (slot, &field) in params.iter_mut().zip(fields) {
                    let (part, tail) = match rest.map(|r| split_once(r, b',')) {
                        None => return Err(syntax(name, usage)),
                        Some(Some((part, tail))) => (part, Some(tail)),
                        Some(None) => (rest.unwrap_or(""), None),
                    };
                    rest = tail;
                    *slot = number(part.trim_ascii()).ok_or(syntax(field, "not a number"))?;
                }
                if rest.is_some() {
                    return Err(syntax(name, usage));
                }
            }
        }
        Ok(ParsedSpec::Analytic { kind, params })
    }

    /// The phase function in precision `F` with table type `T` (parameters
    /// rounded to `F` and checked by the constructors). A table is the
    /// caller's to load: an [`Error::Syntax`] for field `table`.
    pub fn build<F: Real, T>(&self) -> Result<AnyPhase<F, T>, Error> {
        let (kind, [a, b, c]) = match *self {
            ParsedSpec::Analytic { kind, params } => (kind, params.map(F::from_f64)),
            ParsedSpec::Table { .. } => (PhaseKind::Table, [F::ZERO; 3]),
        };
        Ok(match kind {
            PhaseKind::Isotropic => AnyPhase::Isotropic(Isotropic),
            PhaseKind::HenyeyGreenstein => AnyPhase::HenyeyGreenstein(HenyeyGreenstein::new(a)?),
            PhaseKind::TwoTermHg => AnyPhase::TwoTermHg(Mixture::two_term(a, b, c)?),
            PhaseKind::FournierForand => AnyPhase::FournierForand(FournierForand::new(a, b)?),
            PhaseKind::Draine => AnyPhase::Draine(Draine::new(a, b)?),
            PhaseKind::Mie => AnyPhase::Mie(Mie::new(a)?),
            PhaseKind::Rayleigh => AnyPhase::Rayleigh(Rayleigh),
            PhaseKind::Table => {
                return Err(Error::Syntax {
                    field: "table",
                    reason: "a table is loaded by the caller",
                });
            }
        })
    }
}

impl<'s, F: Real> Spec<'s, F> {
    /// Parses the syntax above ([`ParsedSpec::parse`]) and builds the phase
    /// function in precision `F`.
    pub fn parse(spec: &'s str) -> Result<Self, Error> {
        match ParsedSpec::parse(spec)? {
            ParsedSpec::Table { path } => Ok(Spec::Table { path }),
            analytic => Ok(Spec::Analytic(analytic.build()?)),
        }
    }
}

/// Writes a parameter as the shortest decimal that parses back to it (in f32
/// when `F` is f32).
fn num<F: Real>(f: &mut fmt::Formatter<'_>, x: F) -> fmt::Result {
    if F::EPSILON.to_f64() == f32::EPSILON as f64 {
        write!(f, "{}", x.to_f32())
    } else {
        write!(f, "{}", x.to_f64())
    }
}

impl<F: Real, T> fmt::Display for AnyPhase<F, T> {
    /// The spec syntax of the module documentation; a table prints as `table`
    /// (its file name is not known here).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnyPhase::Isotropic(_) => f.write_str("iso"),
            AnyPhase::Rayleigh(_) => f.write_str("rayleigh"),
            AnyPhase::Tabulated(_) => f.write_str("table"),
            AnyPhase::HenyeyGreenstein(p) => {
                f.write_str("hg:")?;
                num(f, p.g())
            }
            AnyPhase::TwoTermHg(p) => {
                f.write_str("tthg:")?;
                num(f, p.first().g())?;
                f.write_str(",")?;
                num(f, p.second().g())?;
                f.write_str(",")?;
                num(f, F::from_f64(p.weight()))
            }
            AnyPhase::FournierForand(p) => {
                f.write_str("ff:")?;
                num(f, p.backscatter())?;
                f.write_str(",")?;
                num(f, p.n())
            }
            AnyPhase::Draine(p) => {
                f.write_str("draine:")?;
                num(f, p.g())?;
                f.write_str(",")?;
                num(f, p.alpha())
            }
            AnyPhase::Mie(p) => {
                f.write_str("mie:")?;
                num(f, p.diameter_um())
            }
        }
    }
}

impl<F: Real> fmt::Display for Spec<'_, F> {
    /// The spec syntax: the phase function's, or `table:PATH`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Spec::Analytic(p) => fmt::Display::fmt(p, f),
            Spec::Table { path } => write!(f, "table:{path}"),
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    fn round_trip<F: Real>(s: &str) {
        let a = Spec::<F>::parse(s).unwrap();
        let printed = a.to_string();
        let b = Spec::<F>::parse(&printed).unwrap();
        assert_eq!(a, b, "{s} -> {printed}");
    }

    #[test]
    fn parses_and_round_trips_every_kind() {
        for s in [
            "iso",
            "rayleigh",
            "hg:0.9",
            " hg: -0.3 ",
            "tthg:0.99,-0.44,0.96",
            "tthg:0.997, 0.960, 0.5",
            "ff:0.0183,1.10",
            "draine:0.5557,22",
            "draine:0.3,250",
            "mie:10",
            "mie:0.05",
            "table:data/petzold.csv",
            "table:C:\\tables\\x.csv",
        ] {
            round_trip::<f64>(s);
            round_trip::<f32>(s);
        }
        match Spec::<f64>::parse("tthg:0.99,-0.44,0.96").unwrap() {
            Spec::Analytic(Phase::TwoTermHg(m)) => {
                assert_eq!(
                    (m.first().g(), m.second().g(), m.weight()),
                    (0.99, -0.44, 0.96)
                );
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            Spec::<f64>::parse("table: C:\\x.csv ").unwrap(),
            Spec::Table { path: "C:\\x.csv" }
        );
        assert_eq!(Spec::<f32>::parse("hg:0.9").unwrap().to_string(), "hg:0.9");
        assert_eq!(
            Spec::<f64>::parse("ff:0.0183,1.1").unwrap().to_string(),
            "ff:0.0183,1.1"
        );
    }

    #[test]
    fn errors_name_the_field() {
        let field = |s: &str| Spec::<f64>::parse(s).unwrap_err();
        let syntax = |s: &str| match field(s) {
            Error::Syntax { field, .. } => field,
            e => panic!("{s}: {e:?}"),
        };
        let range = |s: &str| match field(s) {
            Error::OutOfRange { field, .. } => field,
            e => panic!("{s}: {e:?}"),
        };
        assert_eq!(syntax(""), "phase");
        assert_eq!(syntax("henyey:0.5"), "phase");
        assert_eq!(syntax("hg"), "hg");
        assert_eq!(syntax("hg:"), "g");
        assert_eq!(syntax("hg:0.5,0.2"), "hg");
        assert_eq!(syntax("hg:abc"), "g");
        assert_eq!(syntax("tthg:0.9,0.1"), "tthg");
        assert_eq!(syntax("tthg:0.9,x,0.5"), "g2");
        assert_eq!(syntax("iso:1"), "iso");
        assert_eq!(syntax("rayleigh:"), "rayleigh");
        assert_eq!(syntax("table:"), "table");
        assert_eq!(syntax("table"), "table");
        assert_eq!(syntax("mie:10um"), "diameter_um");
        assert_eq!(range("hg:1"), "g");
        assert_eq!(range("hg:NaN"), "g");
        assert_eq!(range("tthg:0.9,0.1,2"), "w");
        assert_eq!(range("tthg:-1.5,0.1,0.5"), "g1");
        assert_eq!(range("ff:0.6,1.1"), "backscatter");
        assert_eq!(range("ff:0.01,2"), "n");
        assert_eq!(range("draine:0.5,-1"), "alpha");
        assert_eq!(range("draine:inf,1"), "g");
        assert_eq!(range("mie:0"), "diameter_um");
        assert_eq!(range("mie:60"), "diameter_um");
        // Display of an error names field and allowed range.
        assert_eq!(
            field("ff:0.6,1.1").to_string(),
            "backscatter = 0.6 is out of range; allowed: (0, 0.5)"
        );
    }
}
