//! Integration tests of the `omnee` binary: every subcommand, the error
//! paths, the file-safety promise, a render against a stored reference and
//! `estimate` against the quadrature reference.
//!
//! Statistical tests use fixed seeds. Each compares a Monte Carlo mean with
//! a reference through `z = (mean − reference) / stderr` and allows
//! `|z| < Z`, with `Z` chosen so that a correct implementation fails less
//! than once in 10⁴ runs of the whole binary (the bound is derived at each
//! test), while a biased estimator fails reliably.
//!
//! One test binary, a module per area: [`boundary`] (extreme scales, NaN,
//! huge counts, hangs), [`render`] (images, terms, crops,
//! skipping), [`io`] (bad input, file safety, scene choice, help),
//! [`probe`], [`estimate`] (`estimate`, `samples`, tables) and [`reference`]
//! (a render against the stored reference), [`underwater`] (the underwater
//! scene through the command line); [`common`] runs the binary.

mod boundary;
mod common;
mod estimate;
mod io;
mod probe;
mod reference;
mod render;
mod underwater;
