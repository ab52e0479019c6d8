//! The workspace-wide verification suite of omnee (issue 6): χ² goodness of
//! fit of every sampler, proptest properties, numerical stability at extreme
//! inputs, and unbiasedness against the quadrature reference.
//!
//! Everything random is seeded; `cargo test -p omnee --test suite` runs it
//! (the test profile is optimised, see the root `Cargo.toml`).

mod chi2;
mod harness;
mod properties;
mod stability;
mod unbiased;
