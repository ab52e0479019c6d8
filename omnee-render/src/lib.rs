//! # omnee-render
//!
//! The renderer of omnee, the library every front end shares (the `omnee`
//! command line, the Python bindings, the benchmarks and the fuzzers): the
//! scenes, their transport terms, one render loop, and the point-to-point
//! engines, on top of the `no_std` sampling core `omnee-core`. It parses and
//! checks every input (scene files, phase specs, tables) with messages that
//! name the field, its value and the allowed range, and does no terminal
//! I/O: progress and cancellation are callbacks.
//!
//! Where things are (docs/architecture.md draws it):
//! Features: `scenes` (on by default) for the scenes and their TOML files,
//! `files` for OpenEXR and PNG; without either the library is the
//! point-to-point engines, the render loop and the shared pieces (what the
//! Python bindings link).
//!
//! - `scenes`: the scenes as sibling modules behind one enum
//!   (`scenes::Scene`): `scenes::slab` (gathered by camera rays) and
//!   `scenes::underwater` (light traced and splatted), each with its scene
//!   file, its world in f32 and its transport terms;
//! - [`render`]: the one render loop (passes, threads, a progress callback,
//!   cancellation), which does not know what a work item computes;
//! - [`point`]: the point-to-point problem and its estimate and samples
//!   engines, with one vertex or bridges of several; the slab scene's
//!   probe is `scenes::slab::probe`;
//! - [`image`]: layers of linear RGB and tone mapping; `files` (feature
//!   `files`): OpenEXR and PNG, written atomically;
//! - shared pieces: [`camera`] (the pinhole and the pixel measurement),
//!   [`phase`] (phase specs and their tables), `section` (reading a TOML
//!   section field by field), [`range`] (range checks), [`parallel`] (the
//!   pool and the chunks), [`technique`] (a technique as asked for and as
//!   used), [`vertices`] (how many vertices a bridge has), [`moments`],
//!   [`rng`], [`error`].

pub mod camera;
pub mod error;
#[cfg(feature = "files")]
pub mod files;
pub mod image;
pub mod moments;
pub mod parallel;
pub mod phase;
pub mod point;
pub mod range;
pub mod render;
pub mod rng;
#[cfg(feature = "scenes")]
pub mod scenes;
#[cfg(feature = "scenes")]
pub mod section;
pub mod technique;
pub mod vertices;

pub use error::{RenderError, Result};
