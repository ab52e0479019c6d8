//! Phase functions chosen by the core's specification strings (`iso`, `hg:G`,
//! `tthg:G1,G2,W`, `ff:B,N`, `draine:G,ALPHA`, `mie:D`, `rayleigh`), parsed
//! by [`omnee_core::phase::Spec::parse`].

use omnee_core::Error;
use omnee_core::phase::{Phase, Spec};
use omnee_core::real::Real;

/// The analytic phase function named by `spec`. `table:FILE.csv` is refused:
/// the page reads no files.
pub fn parse<F: Real>(spec: &str) -> Result<Phase<'static, F>, Error> {
    match Spec::<F>::parse(spec)? {
        Spec::Analytic(phase) => Ok(phase),
        Spec::Table { .. } => Err(Error::Syntax {
            field: "table",
            reason: "tables cannot be loaded in the browser demo",
        }),
    }
}
