//! The point-to-point problem of the derivation (docs/math.md §1, §5): a
//! unit-intensity point light `x0`, a point receiver `x2`, an infinite
//! homogeneous medium, and the once-more integral between them. [`problem`]
//! states and checks it, [`estimate`] computes its Monte Carlo estimate
//! (and the quadrature reference), [`samples`] lists a technique's draws;
//! [`bridge`] draws bridges of several vertices instead of one (docs/math.md
//! §14) for both.

pub mod bridge;
pub mod estimate;
pub mod problem;
pub mod samples;
