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
