//! `omnee_cli`: the slab-medium renderer and the measurements behind the
//! `omnee` command, the front end of omnee, a reference implementation of
//! once-more scattered next event estimation (Hanika, Weidlich, Droske,
//! EGSR 2022). The binary is [`cli::run`]; the library is there so that the
//! benchmarks and other programs can drive the same scene and estimators.
//!
//! Subcommands: `render` (the slab scene, a layer per transport term),
//! `probe` (irradiance at a point of a scene), `estimate` (the point-to-point
//! integral in an infinite medium), `samples` (a technique's `x1` samples),
//! `merge` (sum crops rendered apart) and `default-scene`.

pub mod cli;
pub mod error;
pub mod image;
pub mod measure;
pub mod phase;
pub mod progress;
pub mod render;
pub mod rng;
pub mod scene;
pub mod technique;
pub mod underwater;
pub mod world;
