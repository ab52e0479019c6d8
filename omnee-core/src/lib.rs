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
//! The derivation of every formula here, with the numerical traps and how the
//! code avoids them, is `docs/math.md` in the omnee repository; doc comments
//! cite its sections as `docs/math.md §N`.
//!
//! Modules, one per idea:
//! - [`real`]: the two precisions (`f32` for renderers, `f64` for references);
//! - [`bridge`]: bridges of k scattering vertices between `x0` and `x2`
//!   (rotate-and-scale sampling, the number of vertices, the isotropic
//!   closed form);
//! - [`circumcircle`]: the map (θ, β, φ) ↔ x1 and the triangle's measures;
//! - [`phase`]: phase functions with cancellation-free angles, and tabulated
//!   inverse CDFs that sample any of them at Henyey–Greenstein's cost;
//! - [`sampling`]: OMNEE and its baselines, equiangular and distance sampling,
//!   and a vectorised batch entry point for OMNEE with Henyey–Greenstein;
//! - [`lobe`]: a lobe at `x0`: its technique, its MIS with OMNEE, a 3-D reference;
//! - [`mis`]: multiple importance sampling over any set of techniques, and
//!   [`mis::OmneeMis`], OMNEE with a companion behind a backward cone;
//! - [`method`]: the techniques by name ([`method::Choice`], with `auto`
//!   and the lobe combination), [`method::Method`] and the
//!   [`method::Setup`] that makes one draw (up to two vertices) with any of
//!   them, for front ends;
//! - [`names`]: closed sets of names ([`names::Named`]), which every front
//!   end parses and lists the same way; [`term`]: the light transport terms;
//! - [`medium`]: homogeneous coefficients and the region the medium fills;
//! - [`reference`](mod@reference): the point-to-point test problem and its quadrature value;
//! - [`quadrature`]: the f64 adaptive Gauss–Kronrod rule behind it;
//! - [`error`]: the error every constructor returns for invalid input;
//! - [`rng`]: SplitMix64, a seeded generator for tests, benchmarks and front
//!   ends (the samplers themselves take plain uniform numbers).
//!
//! ## Quick start
//!
//! Estimate the once-scattered transfer from a point light at `x0` to a point
//! `x2` through fog with a Henyey–Greenstein lobe, and compare it with the
//! quadrature reference:
//!
//! ```
//! use omnee_core::medium::Homogeneous;
//! use omnee_core::phase::HenyeyGreenstein;
//! use omnee_core::reference::PointToPoint;
//! use omnee_core::sampling::{Connection, Omnee, Technique};
//! use glam::Vec3;
//!
//! # fn main() -> Result<(), omnee_core::Error> {
//! let (x0, x2) = (Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO);
//! let forward = core::f32::consts::FRAC_PI_2; // θmax: forward scattering
//! let connection = Connection::new(x0, x2, forward)?;
//! let phase = HenyeyGreenstein::new(0.9)?;
//! let fog = Homogeneous::new(0.5, 0.05)?; // σs, σa in 1/m
//! let problem = PointToPoint::new(connection, fog, None)?;
//! let omnee = Omnee::new(connection, phase);
//!
//! // Stratified numbers stand in for a sampler; any [0, 1)³ source works.
//! let n = 256;
//! let mut sum = 0.0;
//! for i in 0..n {
//!     for j in 0..n {
//!         let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32, 0.37];
//!         if let Some(sample) = omnee.sample(u) {
//!             // f_c · θ/(s sin θ): the weight is closed-form, never f/pdf.
//!             sum += problem.estimate(&sample);
//!         }
//!     }
//! }
//! let estimate = sum / (n * n) as f32;
//!
//! // The same problem in f64, integrated by quadrature (docs/math.md §5).
//! let reference = PointToPoint::new(
//!     Connection::new(x0.as_dvec3(), x2.as_dvec3(), core::f64::consts::FRAC_PI_2)?,
//!     Homogeneous::new(0.5, 0.05)?,
//!     None,
//! )?
//! .integral(&HenyeyGreenstein::new(0.9)?);
//! assert!((estimate as f64 / reference - 1.0).abs() < 3e-3, "{estimate} vs {reference}");
//! # Ok(())
//! # }
//! ```
//!
//! ## Precision
//!
//! Everything is generic over [`Real`] (`f32` or `f64`); `f32` is the
//! renderer's API and `f64` serves references and accuracy tests, through the
//! same code. Angles travel as [`phase::Deflection`] (θ with `1 ∓ cos θ`), so
//! forward peaks like g = 0.9999 keep their digits in f32 (docs/math.md §4).
//!
//! ## Features
//!
//! - `std` (off by default): use the platform's math functions instead of
//!   `libm`. Results then depend on the platform's libm; without it they are
//!   bit-identical across targets. It is not faster: on x86-64 with glibc
//!   2.36 the OMNEE sample takes 5 % (f32) and 15 % (f64) more CPU time with
//!   it (the workspace's `benches/std_math.rs`).
#![no_std]
#![forbid(unsafe_code)]

#[cfg(test)]
extern crate std;

pub mod bridge;
pub mod circumcircle;
pub mod error;
pub mod lobe;
pub mod medium;
pub mod method;
pub mod mis;
pub mod names;
pub mod phase;
pub mod quadrature;
pub mod real;
pub mod reference;
pub mod rng;
pub mod sampling;
pub mod term;

pub use error::Error;
pub use real::{Real, Vector};
