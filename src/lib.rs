//! `omnee`: once-more scattered next event estimation for volume rendering.
//!
//! This crate re-exports [`omnee_core`], the `no_std` sampling core, and hosts the
//! workspace-wide property-test suite (`tests/`) and benchmarks (`benches/`).
#![no_std]
#![forbid(unsafe_code)]

pub use omnee_core::*;

/// The README's code blocks, compiled and run as doctests so they stay true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// The code blocks of the READMEs that omnee-core and omnee-render are
/// packaged with, compiled and run as doctests too.
#[cfg(doctest)]
#[doc = include_str!("../omnee-core/README.md")]
pub struct CoreReadmeDoctests;

/// See [`CoreReadmeDoctests`].
#[cfg(doctest)]
#[doc = include_str!("../omnee-render/README.md")]
pub struct RenderReadmeDoctests;
