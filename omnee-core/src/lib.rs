//! # omnee-core
//!
//! The `no_std`, allocation-free core of omnee: *once-more scattered next event
//! estimation* (Hanika, Weidlich, Droske, "Once-more scattered next event
//! estimation for volume rendering", EGSR 2022, Computer Graphics Forum 41(4),
//! doi:10.1111/cgf.14583).
//!
//! Between a light-side point `x0` and a receiver-side point `x2` one more
//! scattering vertex `x1` is placed *angle first*: the deflection θ is drawn from
//! the phase function, then `x1` on the circumcircle arc of constant θ through
//! `x0` and `x2`. The estimator of the once-scattered transfer is
//! `f_c · θ / (s sin θ)`.
//!
//! Modules, one per idea:
//! - [`real`]: the two precisions (`f32` for renderers, `f64` for references);
//! - [`circumcircle`]: the map (θ, β, φ) ↔ x1 and the triangle's measures;
//! - [`phase`]: phase functions with cancellation-free angles;
//! - [`sampling`]: OMNEE and its baselines, equiangular and distance sampling;
//! - [`mis`]: multiple importance sampling over any set of techniques;
//! - [`error`]: the error every constructor returns for invalid input.
#![no_std]
#![forbid(unsafe_code)]

pub mod circumcircle;
pub mod error;
pub mod medium;
pub mod mis;
pub mod phase;
pub mod quadrature;
pub mod real;
pub mod reference;
pub mod sampling;

pub use error::Error;
pub use real::{Real, Vector};
