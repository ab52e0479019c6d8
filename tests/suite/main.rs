//! The workspace-wide verification suite of omnee: χ² goodness of
//! fit of every sampler, proptest properties, numerical stability at extreme
//! inputs, and unbiasedness against the quadrature reference.
//!
//! Everything random is seeded; `cargo test -p omnee --test suite` runs it
//! (the test profile is optimised, see the root `Cargo.toml`).
//!
//! That it catches real bugs is measured: `tests/mutants/run.sh` breaks the
//! core's formulas one at a time (a wrong Jacobian factor, α and β swapped,
//! HG's sign convention, constants off, ...) and records which of these
//! tests fail; `tests/mutants/README.md` has the table.

mod bridge;
mod chi2;
mod connections;
mod harness;
mod lobe;
mod properties;
mod references;
mod scale;
mod stability;
mod tables;
mod unbiased;
