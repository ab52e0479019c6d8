//! Phase functions chosen by a specification string (`iso`, `hg:G`,
//! `tthg:G1,G2,W`, `rayleigh`, `draine:G,ALPHA`).
//!
//! Interim: the core's `phase::Spec` is still being written; until it lands
//! this module parses the subset of its syntax whose phase functions exist.

use omnee_core::Error;
use omnee_core::phase::{
    Deflection, Draine, HenyeyGreenstein, Isotropic, PhaseFunction, Rayleigh, TwoTermHg,
};
use omnee_core::real::Real;

/// One of the core's phase functions, selected at run time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DemoPhase<F: Real> {
    /// `iso`.
    Isotropic(Isotropic),
    /// `hg:G`.
    HenyeyGreenstein(HenyeyGreenstein<F>),
    /// `tthg:G1,G2,W`.
    TwoTermHg(TwoTermHg<F>),
    /// `rayleigh`.
    Rayleigh(Rayleigh),
    /// `draine:G,ALPHA`.
    Draine(Draine<F>),
}

macro_rules! dispatch {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            DemoPhase::Isotropic($p) => $e,
            DemoPhase::HenyeyGreenstein($p) => $e,
            DemoPhase::TwoTermHg($p) => $e,
            DemoPhase::Rayleigh($p) => $e,
            DemoPhase::Draine($p) => $e,
        }
    };
}

impl<F: Real> PhaseFunction<F> for DemoPhase<F> {
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
        dispatch!(self, p => p.mean_cosine())
    }
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.pdf(d))
    }
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        dispatch!(self, p => p.invert(d))
    }
}

fn syntax(field: &'static str, reason: &'static str) -> Error {
    Error::Syntax { field, reason }
}

/// Parses `N` comma-separated finite numbers.
fn numbers<const N: usize>(args: &str) -> Result<[f64; N], Error> {
    let mut out = [0.0; N];
    let mut parts = args.split(',');
    for slot in &mut out {
        let part = parts
            .next()
            .ok_or_else(|| syntax("phase", "too few parameters"))?;
        *slot = part
            .trim()
            .parse::<f64>()
            .map_err(|_| syntax("phase", "a parameter is not a number"))?;
    }
    if parts.next().is_some() {
        return Err(syntax("phase", "too many parameters"));
    }
    Ok(out)
}

/// The phase function named by `spec` in precision `F`.
pub fn parse<F: Real>(spec: &str) -> Result<DemoPhase<F>, Error> {
    let spec = spec.trim();
    let (name, args) = match spec.split_once(':') {
        Some((name, args)) => (name.trim(), Some(args)),
        None => (spec, None),
    };
    let f = F::from_f64;
    match (name, args) {
        ("iso", None) => Ok(DemoPhase::Isotropic(Isotropic)),
        ("rayleigh", None) => Ok(DemoPhase::Rayleigh(Rayleigh)),
        ("hg", Some(a)) => {
            let [g] = numbers(a)?;
            Ok(DemoPhase::HenyeyGreenstein(HenyeyGreenstein::new(f(g))?))
        }
        ("tthg", Some(a)) => {
            let [g1, g2, w] = numbers(a)?;
            Ok(DemoPhase::TwoTermHg(TwoTermHg::two_term(
                f(g1),
                f(g2),
                f(w),
            )?))
        }
        ("draine", Some(a)) => {
            let [g, alpha] = numbers(a)?;
            Ok(DemoPhase::Draine(Draine::new(f(g), f(alpha))?))
        }
        ("iso" | "rayleigh", Some(_)) => Err(syntax("phase", "takes no parameters")),
        ("hg" | "tthg" | "draine", None) => Err(syntax("phase", "missing parameters")),
        _ => Err(syntax("phase", "unknown phase function")),
    }
}
