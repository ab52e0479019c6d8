//! Shared machinery of the suite, one module per concern; the items are
//! re-exported here, so tests name them `crate::harness::Item`.
//!
//! - [`random`]: the seeded generator;
//! - [`phases`]: the phase functions under test, as data;
//! - [`frame`]: an independent circumcircle frame and its Jacobian;
//! - [`quadrature`]: Gauss–Legendre cells and piecewise Gauss–Kronrod;
//! - [`statistics`]: the incomplete gamma function, χ² and normal tails,
//!   Šidák's correction and Pearson's χ² statistic;
//! - [`batch`]: the vectorised OMNEE batch as the tests use it.

pub mod batch;
pub mod frame;
pub mod phases;
pub mod quadrature;
pub mod random;
pub mod statistics;

pub use batch::{BatchOmnee, Lanes};
pub use frame::Frame;
pub use phases::PhaseSpec;
pub use quadrature::{integrate_box, integrate_pieces};
pub use random::Rng;
pub use statistics::{Chi2, chi2, normal_two_sided_quantile, sidak};
