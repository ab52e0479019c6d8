//! Phase functions from short specification strings (command line, config).
//!
//! The syntax is documented on [`Spec`] (this module is private).

use super::{Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, Phase, Rayleigh};
#[allow(unused_imports)] // named by the documentation of `Spec`
use super::{Tabulated, TwoTermHg};
use crate::error::Error;
use crate::real::Real;
use core::fmt;

/// A parsed phase-function specification string.
///
/// Syntax (names lower case, parameters comma-separated decimal numbers,
/// surrounding whitespace ignored):
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

/// The names accepted, for the error message.
const NAMES: &str =
    "unknown phase function; expected iso, hg, tthg, ff, draine, mie, rayleigh or table";

/// Splits `args` into exactly `N` numbers named `fields`; `usage` is the
/// message for a wrong count.
fn numbers<const N: usize>(
    name: &'static str,
    args: Option<&str>,
    fields: [&'static str; N],
    usage: &'static str,
) -> Result<[f64; N], Error> {
    let syntax = |field, reason| Error::Syntax { field, reason };
    let args = args.ok_or(syntax(name, usage))?;
    let mut out = [0.0; N];
    let mut parts = args.split(',');
    for (slot, field) in out.iter_mut().zip(fields) {
        let part = parts.next().ok_or(syntax(name, usage))?.trim();
        *slot = part
            .parse::<f64>()
            .map_err(|_| syntax(field, "not a number"))?;
    }
    if parts.next().is_some() {
        return Err(syntax(name, usage));
    }
    Ok(out)
}

impl<'s, F: Real> Spec<'s, F> {
    /// Parses the syntax above.
    pub fn parse(spec: &'s str) -> Result<Self, Error> {
        let spec = spec.trim();
        let (name, args) = match spec.split_once(':') {
            Some((n, a)) => (n.trim(), Some(a)),
            None => (spec, None),
        };
        let f = F::from_f64;
        let none = |field: &'static str| -> Result<(), Error> {
            match args {
                None => Ok(()),
                Some(_) => Err(Error::Syntax {
                    field,
                    reason: "takes no parameters",
                }),
            }
        };
        let phase = match name {
            "iso" => {
                none("iso")?;
                Phase::Isotropic(Isotropic)
            }
            "rayleigh" => {
                none("rayleigh")?;
                Phase::Rayleigh(Rayleigh)
            }
            "hg" => {
                let [g] = numbers("hg", args, ["g"], "expected hg:G")?;
                Phase::HenyeyGreenstein(HenyeyGreenstein::new(f(g))?)
            }
            "tthg" => {
                let [g1, g2, w] =
                    numbers("tthg", args, ["g1", "g2", "w"], "expected tthg:G1,G2,W")?;
                Phase::TwoTermHg(Mixture::two_term(f(g1), f(g2), f(w))?)
            }
            "ff" => {
                let [b, n] = numbers("ff", args, ["backscatter", "n"], "expected ff:B,N")?;
                Phase::FournierForand(FournierForand::new(f(b), f(n))?)
            }
            "draine" => {
                let [g, a] = numbers("draine", args, ["g", "alpha"], "expected draine:G,ALPHA")?;
                Phase::Draine(Draine::new(f(g), f(a))?)
            }
            "mie" => {
                let [d] = numbers("mie", args, ["diameter_um"], "expected mie:DIAMETER_UM")?;
                Phase::Mie(Mie::new(f(d))?)
            }
            "table" => {
                let path = args.map(str::trim).unwrap_or("");
                if path.is_empty() {
                    return Err(Error::Syntax {
                        field: "table",
                        reason: "expected table:FILE.csv",
                    });
                }
                return Ok(Spec::Table { path });
            }
            _ => {
                return Err(Error::Syntax {
                    field: "phase",
                    reason: NAMES,
                });
            }
        };
        Ok(Spec::Analytic(phase))
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

impl<F: Real> fmt::Display for Phase<'_, F> {
    /// The spec syntax of the module documentation; a table prints as `table`
    /// (its file name is not known here).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Phase::Isotropic(_) => f.write_str("iso"),
            Phase::Rayleigh(_) => f.write_str("rayleigh"),
            Phase::Tabulated(_) => f.write_str("table"),
            Phase::HenyeyGreenstein(p) => {
                f.write_str("hg:")?;
                num(f, p.g())
            }
            Phase::TwoTermHg(p) => {
                f.write_str("tthg:")?;
                num(f, p.first().g())?;
                f.write_str(",")?;
                num(f, p.second().g())?;
                f.write_str(",")?;
                num(f, F::from_f64(p.weight()))
            }
            Phase::FournierForand(p) => {
                f.write_str("ff:")?;
                num(f, p.backscatter())?;
                f.write_str(",")?;
                num(f, p.n())
            }
            Phase::Draine(p) => {
                f.write_str("draine:")?;
                num(f, p.g())?;
                f.write_str(",")?;
                num(f, p.alpha())
            }
            Phase::Mie(p) => {
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
